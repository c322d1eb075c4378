"""Second-order coupling: the guideway FMU extrapolates its coupling inputs
over each communication step along the line through their values at the
last two communication points, and so does the quarter car when its
`extrapolate` parameter is 1. Coupled so (fmpy by hand, libcosim), the run
must converge to the built-in sprung-mass vehicle (the independent
reference: one model, no co-simulation) faster than first order.

The errors are e(H) = C H² + a floor that does not depend on H (the
reference's own error: guideway integrates the built-in vehicle with its
own integrator at `solver.step`, the quarter car uses RK4); the test
asserts the measured figures quoted in docs/coupling.md.
"""

import numpy as np
import pytest

from test_coupling import (BUILTIN_COLUMNS, OBSERVED, RUNNERS, STARTS, errors,
                           fmus)  # noqa: F401  (fmus is a fixture)

STEPS = [2.5e-3, 1.25e-3, 6.25e-4]
MASTERS = ["fmpy", "libcosim"]
EXTRAPOLATING = {**STARTS, ("vehicle", "extrapolate"): 1}
# the car body's acceleration besides the displacements
WATCHED = OBSERVED + [("vehicle", "ay")]
COLUMNS = BUILTIN_COLUMNS + ["car.ay"]
BODY_Y, GLIDER_Y, DEFLECTION, BODY_AY = range(4)


@pytest.fixture(scope="module")
def runs(fmus):  # noqa: F811
    paths, _ = fmus
    return {(m, h): RUNNERS[m](paths, h, EXTRAPOLATING, WATCHED)
            for m in MASTERS for h in STEPS}


@pytest.mark.parametrize("master", MASTERS)
def test_extrapolated_coupling_converges_faster_than_first_order(fmus, runs, master):  # noqa: F811
    e = errors(fmus, runs, master, STEPS, COLUMNS)
    for h, row in zip(STEPS, e):
        print(f"{master} H = {h:g} s: " + ", ".join(
            f"{c} {x:.3e}" for c, x in zip(COLUMNS, row)))
    ratios = e[:-1] / e[1:]
    # The car body's acceleration (the ride-comfort quantity): each halving
    # of H divides its error by about three (2.9 to 3.2 measured), a first
    # order coupling by two; below 1 % of its peak at H = 0.625 ms.
    assert np.all(ratios[:, BODY_AY] > 2.7), ratios[:, BODY_AY]
    assert e[-1, BODY_AY] < 0.01, e[:, BODY_AY]
    assert e[0, BODY_AY] < 0.065, e[:, BODY_AY]
    # The glider and the beam: second order down to the floor (the first
    # halving divides their errors by 3.6 to 4.1).
    assert np.all(ratios[0, [GLIDER_Y, DEFLECTION]] > 3.3), ratios[0]
    # Everything within 2e-4 of its swing at the smallest step.
    assert np.all(e[-1, :BODY_AY] < 2e-4), e[-1]


def test_the_masters_agree_on_the_extrapolated_run_to_the_bit(runs):
    # libcosim passes t[k+1] - t[k] (off by ulps of t) where fmpy passes H:
    # both FMUs snap such steps, so nothing depends on it.
    for h in STEPS:
        ref, other = runs[("fmpy", h)], runs[("libcosim", h)]
        assert np.array_equal(other, ref), h

"""The default FMU run alone in three independent masters: fmpy, libcosim
(libcosimpy) and Ecos (ecospy). Each steps it with the same communication
step; their results must agree to 1e-9 at every communication point.

The run goes to the default experiment's stop time, past the exit at
2.27 s (an event, not the end: every step is fmi2OK); the exit shows in
`contact.on_beam` and `wheel.vx` in every master's result.
"""

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

from conftest import WHEEL, fmu_path

H = 0.01
# to the default stop time (3.63 s), past the exit at 2.2749 s
STEPS = int(float(read_model_description(str(fmu_path(WHEEL))).defaultExperiment.stopTime) / H)


def real_outputs(md):
    return [v for v in md.modelVariables if v.causality == "output" and v.type == "Real"]


def run_fmpy(fmu, names):
    result = simulate_fmu(fmu, output_interval=H, stop_time=STEPS * H,
                          output=names + ["contact.on_beam"])
    assert len(result) == STEPS + 1
    np.testing.assert_allclose(result["time"][-1], STEPS * H, rtol=1e-12)
    return np.array([[row[n] for n in names + ["contact.on_beam"]] for row in result[1:]])


def run_libcosim(fmu, vrs, on_beam):
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    execution = CosimExecution.from_step_size(round(H * 1e9))
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    index = execution.add_local_slave(CosimLocalSlave(fmu_path=fmu, instance_name="guideway"))
    rows = []
    for k in range(STEPS):
        assert execution.step(), f"libcosim step {k} failed"
        rows.append(observer.last_real_values(index, vrs)
                    + observer.last_integer_values(index, [on_beam]))
    return np.array(rows)


def run_ecos(fmu, names):
    from ecospy import EcosSimulation
    from ecospy.EcosSimulationStructure import EcosSimulationStructure

    structure = EcosSimulationStructure()
    structure.add_model("guideway", fmu)
    rows = []
    with EcosSimulation(structure=structure, step_size=H) as sim:
        assert sim.init(), "Ecos could not initialize the FMU"
        for _ in range(STEPS):
            sim.step()
            rows.append([sim.get_real(f"guideway::{n}") for n in names]
                        + [sim.get_integer("guideway::contact.on_beam")])
        np.testing.assert_allclose(sim.get_time(), STEPS * H, rtol=1e-12)
        sim.terminate()
    return np.array(rows)


@pytest.fixture(scope="module")
def results():
    fmu = str(fmu_path(WHEEL))
    md = read_model_description(fmu)
    outputs = real_outputs(md)
    names = [v.name for v in outputs]
    on_beam = next(v.valueReference for v in md.modelVariables if v.name == "contact.on_beam")
    return names + ["contact.on_beam"], {
        "fmpy": run_fmpy(fmu, names),
        "libcosim": run_libcosim(fmu, [v.valueReference for v in outputs], on_beam),
        "ecos": run_ecos(fmu, names),
    }


@pytest.mark.parametrize("master", ["fmpy", "libcosim", "ecos"])
def test_each_master_runs_the_default_fmu_past_the_exit_to_its_stop_time(results, master):
    """Every step fmi2OK (libcosim's step() and Ecos' time say so, fmpy
    raises otherwise); the exit state is in the result."""
    names, runs = results
    r = runs[master]
    assert r.shape == (STEPS, len(names)) and np.all(np.isfinite(r))
    x = r[:, names.index("wheel.x")]
    assert np.all(np.diff(x) > 0), "the wheel moves forward every step"
    on = r[:, names.index("contact.on_beam")]
    k = int(np.argmax(on == 0))  # first row off the beam: t = (k + 1) H
    assert on[k] == 0 and np.all(on[:k] == 1) and np.all(on[k:] == 0)
    assert (k + 1) * H == pytest.approx(2.28, abs=1e-9)  # the exit at 2.2749 s
    vx = r[k, names.index("wheel.vx")]
    assert 9.5 < vx < 12.0, vx  # the exit speed of the centre (10 m/s at the start)
    assert x[-1] > 24.0 + 9.0 * (STEPS * H - 2.28)


@pytest.mark.parametrize("master", ["libcosim", "ecos"])
def test_masters_agree_with_fmpy_to_1e_9(results, master):
    names, runs = results
    reference, other = runs["fmpy"], runs[master]
    for j, name in enumerate(names):
        scale = max(np.max(np.abs(reference[:, j])), 1e-300)
        np.testing.assert_allclose(other[:, j], reference[:, j], rtol=1e-9, atol=1e-9 * scale,
                                   err_msg=f"{master}: {name}")

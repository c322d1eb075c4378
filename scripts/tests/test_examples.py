"""The scripted runs in scripts/examples/ work as documented."""

import sys

import numpy as np
import pytest

from conftest import ROOT, WHEEL, fmu_path

sys.path.insert(0, str(ROOT / "scripts" / "examples"))

import run_and_plot  # noqa: E402
import start_values  # noqa: E402
import step_by_hand  # noqa: E402


def test_run_and_plot_writes_a_png_and_runs_past_the_exit(tmp_path):
    png = tmp_path / "run.png"
    result = run_and_plot.main(str(fmu_path(WHEEL)), str(png))
    assert png.read_bytes().startswith(b"\x89PNG")
    # the wheel (speeding up to 11 m/s over the beam) leaves the 24 m beam
    # at 2.275 s (an event), and the run goes on to the default stop time
    off = result["time"][result["contact.on_beam"] == 0]
    assert off[0] == pytest.approx(2.2749, abs=3e-3)
    assert result["time"][-1] > off[0] + 0.5
    # the paper's figure: peak midspan deflection 1.093 x 0.1728 m
    assert result["sensor.midspan.deflection"].min() == pytest.approx(-1.093 * 0.1728, rel=2e-3)


def test_start_values_change_the_run():
    rows = start_values.main(str(fmu_path(WHEEL)))
    peak = {(v, ei): p for v, ei, p, _ in rows}
    exit_time = {(v, ei): t for v, ei, _, t in rows}
    # doubling EI roughly halves the deflection; faster runs leave earlier
    assert 0.4 < peak[(10.0, 2e9)] / peak[(10.0, 1e9)] < 0.6
    assert exit_time[(100.0, 1e9)] < exit_time[(50.0, 1e9)] < exit_time[(10.0, 1e9)]
    assert exit_time[(100.0, 1e9)] == pytest.approx(24 / 100, abs=0.0025 + 0.005)


def test_traction_input_accelerates_the_wheel():
    rows = np.array(step_by_hand.main(str(fmu_path(WHEEL))))
    t, force, x, v = rows.T
    assert force[-1] == pytest.approx(60e3, rel=1e-9)
    # rigid-body estimate: the force over m + J / r^2 = 3000 + 1500 kg,
    # ramped over 1 s: v = 10 + (60 kN / 4500 kg) (t_end - 0.5 s); the
    # beam's dynamics change the nominal speed by a few per cent only
    expected = 10.0 + 60e3 / 4500.0 * (t[-1] - 0.5)
    assert v[-1] == pytest.approx(expected, rel=0.03)
    assert np.all(np.diff(v[t > 0.2]) > 0)
    # without the force the wheel needs about 2.4 s; with it much less
    assert t[-1] < 2.0

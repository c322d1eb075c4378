"""Issue 26 item 4: the FMU of a moving-force scene, FMI 2.0 and 3.0, in fmpy.

One force of 600 kN crosses the paper's 24 m beam (40 elements, 4000 steps
a passage) at alpha = 1.5; its speed is set through the FMU's parameter
(the scene is exported at another speed). The FMU's midspan deflection
equals `guideway run`'s CSV of the same crossing bit for bit, and the
largest deflection after the force has left matches Fryba's modal series,
written here: mode j of the simply supported undamped beam, in units of
v0 = 2 P L^3 / (pi^4 EI), during the passage (0 <= t <= T = L / c)

    q_j(t) = [sin j w t - (alpha / j) sin w_j t] / (j^2 (j^2 - alpha^2)),

w = pi c / L = alpha w_1, w_j = j^2 w_1, and after it each mode vibrates
freely from its state at T. An HSLM train's FMU runs too.
"""

import csv
import math
import subprocess

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu

from conftest import GUIDEWAY, ROOT

LENGTH, MASS, EI, FORCE, ALPHA = 24.0, 1250.0, 1e9, 600e3, 1.5
OMEGA1 = (math.pi / LENGTH) ** 2 * math.sqrt(EI / MASS)
SPEED = ALPHA * OMEGA1 * LENGTH / math.pi
EXIT = LENGTH / SPEED
STEP = EXIT / 4000.0
# 1.5 periods of the first mode after the exit, on the grid of steps
END = round((EXIT + 1.5 * 2.0 * math.pi / OMEGA1) / STEP) * STEP
V0 = 2.0 * FORCE * LENGTH**3 / (math.pi**4 * EI)
DEFLECTION = "sensor.midspan.deflection"


def scene_toml(speed, end_time=None):
    end = f"end_time = {end_time!r}\n" if end_time is not None else ""
    return f"""name = "force24"
gravity = 0.0
[beam]
length = {LENGTH!r}
mass_per_length = {MASS!r}
bending_stiffness = {EI!r}
surface_offset = 0.0
elements = 40
[body]
name = "force"
kind = "moving_force"
mass = 1.0
initial_position = 0.0
initial_speed = {speed!r}
force_y = {-FORCE!r}
[[sensors]]
name = "midspan"
position = 12.0
[[sections]]
name = "midspan"
position = 12.0
[solver]
step = {STEP!r}
{end}"""


def series_midspan(t, modes=200):
    """Midspan deflection over v0 (down positive) at time t."""
    w1, total = OMEGA1, 0.0
    omega = ALPHA * w1
    for j in range(1, modes + 1):
        wj, d = j * j * w1, j * j * (j * j - ALPHA * ALPHA)
        q = lambda s: (math.sin(j * omega * s) - ALPHA / j * math.sin(wj * s)) / d
        dq = lambda s: (j * omega * math.cos(j * omega * s) - ALPHA / j * wj * math.cos(wj * s)) / d
        if t <= EXIT:
            value = q(t)
        else:
            s = t - EXIT
            value = q(EXIT) * math.cos(wj * s) + dq(EXIT) / wj * math.sin(wj * s)
        total += value * math.sin(j * math.pi / 2.0)
    return total


def run(*args):
    r = subprocess.run([str(GUIDEWAY), *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r


@pytest.fixture(scope="module")
def crossing(tmp_path_factory):
    """The FMUs (FMI 2 and 3) of the scene at 10 m/s, and `guideway run`'s
    CSV of the same scene at alpha = 1.5 to END."""
    d = tmp_path_factory.mktemp("mforce")
    exported = d / "force10.toml"
    exported.write_text(scene_toml(10.0))
    fmus = {}
    for version in ["2", "3"]:
        fmus[version] = d / f"force{version}.fmu"
        run("export", exported, "--fmi", version, "-o", fmus[version])
    alpha = d / "alpha.toml"
    alpha.write_text(scene_toml(SPEED, END))
    run("run", alpha, "-q", "--out", d / "run.csv")
    with open(d / "run.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    return fmus, rows


def simulate(fmu):
    return simulate_fmu(str(fmu), stop_time=END, output_interval=STEP,
                        start_values={"force.initial_speed": SPEED},
                        output=["time", DEFLECTION, "section.midspan.moment", "forces.on_beam"])


@pytest.mark.parametrize("version", ["2", "3"])
def test_the_fmu_equals_the_run_bit_for_bit(crossing, version):
    fmus, rows = crossing
    assert validate_fmu(str(fmus[version])) == []
    result = simulate(fmus[version])
    assert len(result) == len(rows), (len(result), len(rows))
    for name in [DEFLECTION, "section.midspan.moment"]:
        csv_values = np.array([float(r[name]) for r in rows])
        assert np.array_equal(result[name], csv_values), name
    times = np.array([float(r["time"]) for r in rows])
    assert np.max(np.abs(result["time"] - times)) < 1e-9 * END
    # the force is on the beam during the passage only
    on = result["forces.on_beam"]
    assert on[1] == 1 and on[-1] == 0


def test_the_free_vibration_after_the_passage_matches_the_series(crossing):
    result = simulate(crossing[0]["2"])
    after = result["time"] > EXIT
    fmu_after = np.max(np.abs(result[DEFLECTION][after])) / V0
    ts = np.linspace(EXIT, END, 20001)
    series_after = max(abs(series_midspan(t)) for t in ts)
    print(f"after the passage: FMU {fmu_after:.5f} v0, series {series_after:.5f} v0")
    assert abs(series_after - 1.18422) < 5e-5
    assert abs(fmu_after / series_after - 1.0) < 5e-3


def test_an_hslm_train_fmu_runs_in_both_versions(tmp_path):
    scene = ROOT / "scenes" / "bridge25_hslm.toml"
    peaks = {}
    for version in ["2", "3"]:
        fmu = tmp_path / f"hslm{version}.fmu"
        run("export", scene, "--fmi", version, "-o", fmu)
        md = read_model_description(str(fmu))
        names = {v.name: v for v in md.modelVariables}
        assert "train.initial_speed" in names and "train.force_y" not in names
        assert not [v for v in md.modelVariables if v.causality == "input"]
        # stepped on the fixed grid of solver.step, which the experiment keeps
        assert md.coSimulation.canHandleVariableCommunicationStepSize is False
        stop = float(md.defaultExperiment.stopTime)
        assert abs(stop / 0.001 - round(stop / 0.001)) < 1e-9
        result = simulate_fmu(str(fmu), stop_time=1.0, output_interval=0.001,
                              start_values={"train.initial_speed": 80.0},
                              output=[DEFLECTION, "sensor.midspan.acceleration", "forces.on_beam"])
        peaks[version] = result
        # the leading axle at x = 0 first, then a power car's four and more
        assert result["forces.on_beam"][0] == 1 and result["forces.on_beam"].max() >= 4
    for name in [DEFLECTION, "sensor.midspan.acceleration"]:
        assert np.array_equal(peaks["2"][name], peaks["3"][name]), name

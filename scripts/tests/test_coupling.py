"""The guideway FMU coupled to a vehicle FMU through its coupling ports, in
three masters (fmpy, libcosim, Ecos): a quarter car (sprung mass on a
spring-damper, `vehicle/quarter_car.py`, built into an FMU with pythonfmu)
hangs on the glider that the guideway scene names in `couplings`.

The same system exists inside guideway as the built-in `sprung_mass`
vehicle (one model, no co-simulation). The coupled run must match it to
within the coupling error of a co-simulation in which the quarter car holds
its inputs over a communication step (first order: halving the step halves
the error; guideway's own extrapolation is in test_coupling_order2.py), and
the three masters, which all exchange values at the communication points
(Jacobi), must agree with one another to 1e-9.
"""

import subprocess

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi2 import FMU2Slave

from conftest import GUIDEWAY, ROOT, extracted, read_csv

M, K, C, G = 5750.0, 1.595e6, 2.0e4, 9.81  # the quarter car (Yang & Yau 1997)
UNSPRUNG = 575.0
D0 = 1.0  # m, the sprung mass starts 1 m above the glider (guideway's SPRUNG_HEIGHT)
STOP = 0.8  # s, before the exit at 0.9 s (a glider cannot pass the support's kink)
STEPS = [4e-3, 2e-3, 1e-3]  # communication steps (s)
MASTERS = ["fmpy", "libcosim", "ecos"]

BEAM = """
[beam]
length = 25.0
mass_per_length = 2303.0
bending_stiffness = 8.5347e10
surface_offset = 0.0
elements = 10
[[sensors]]
name = "midspan"
position = 12.5
[solver]
step = 2.5e-4
integrator = "auto"
end_time = 0.8
"""

COUPLED = f"""
name = "coupled_glider"
gravity = 9.81
couplings = ["car_unsprung"]
[body]
name = "car_unsprung"
kind = "glider"
mass = {UNSPRUNG}
initial_position = 0.0
initial_speed = 27.78
"""

BUILTIN = f"""
name = "builtin_sprung_mass"
gravity = 9.81
[body]
name = "car"
kind = "sprung_mass"
mass = {M}
initial_position = 0.0
initial_speed = 27.78
[body.suspension]
stiffness = {K}
damping = {C}
unsprung_mass = {UNSPRUNG}
"""

# guideway output -> vehicle input, and vehicle output -> guideway input
CONNECTIONS = [
    ("guideway", "car_unsprung.y", "vehicle", "y_w"),
    ("guideway", "car_unsprung.vy", "vehicle", "vy_w"),
    ("vehicle", "force_y", "guideway", "car_unsprung.coupling_force_y"),
]
# start values: the vehicle in equilibrium on the glider at y = 0 (h = 0)
STARTS = {
    ("guideway", "car_unsprung.coupling_force_y"): -M * G,
    ("vehicle", "y0"): D0,
    ("vehicle", "d0"): D0,
    ("vehicle", "y_w"): 0.0,
    ("vehicle", "vy_w"): 0.0,
    ("vehicle", "mass"): M,
    ("vehicle", "stiffness"): K,
    ("vehicle", "damping"): C,
    ("vehicle", "gravity"): G,
}
OBSERVED = [("vehicle", "y"), ("guideway", "car_unsprung.y"),
            ("guideway", "sensor.midspan.deflection")]
# the same quantities in the built-in run's CSV
BUILTIN_COLUMNS = ["car.y", "car_unsprung.y", "sensor.midspan.deflection"]


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    d = tmp_path_factory.mktemp("coupling")
    (d / "coupled.toml").write_text(COUPLED + BEAM)
    (d / "builtin.toml").write_text(BUILTIN + BEAM)
    guideway = d / "coupled_glider.fmu"
    subprocess.run([str(GUIDEWAY), "export", str(d / "coupled.toml"), "-o", str(guideway)],
                   check=True, capture_output=True)
    subprocess.run([str(GUIDEWAY), "run", str(d / "builtin.toml"), "--out",
                    str(d / "builtin.csv"), "--quiet"], check=True)
    subprocess.run([str(ROOT / ".venv" / "bin" / "pythonfmu"), "build", "-f",
                    str(ROOT / "scripts" / "tests" / "vehicle" / "quarter_car.py"), "--dest", str(d)],
                   check=True, capture_output=True)
    names, data = read_csv(d / "builtin.csv")
    return {"guideway": str(guideway), "vehicle": str(d / "quarter_car.fmu")}, (names, data)


def variable_refs(path):
    return {v.name: v.valueReference for v in read_model_description(path).modelVariables}


def run_fmpy(paths, h, starts=STARTS, observed=OBSERVED):
    """Jacobi by hand: read every output at t, set every input, step both."""
    slaves, vrs = {}, {}
    for name, path in paths.items():
        md = read_model_description(path)
        vrs[name] = {v.name: v.valueReference for v in md.modelVariables}
        s = FMU2Slave(guid=md.guid, unzipDirectory=extracted(path),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        s.instantiate()
        s.setupExperiment(startTime=0.0)
        slaves[name] = s
    for (name, var), value in starts.items():
        if isinstance(value, int):
            slaves[name].setInteger([vrs[name][var]], [value])
        else:
            slaves[name].setReal([vrs[name][var]], [value])
    for s in slaves.values():
        s.enterInitializationMode()
        s.exitInitializationMode()

    def get(name, var):
        return slaves[name].getReal([vrs[name][var]])[0]

    rows = []
    n = int(round(STOP / h))
    for k in range(n):
        values = [get(a, x) for a, x, _, _ in CONNECTIONS]
        for (_, _, b, y), value in zip(CONNECTIONS, values):
            slaves[b].setReal([vrs[b][y]], [value])
        for s in slaves.values():
            s.doStep(k * h, h)  # fmpy raises unless fmi2OK
        rows.append([get(a, x) for a, x in observed])
    for s in slaves.values():
        s.terminate()
        s.freeInstance()
    return np.array(rows)


def run_libcosim(paths, h, starts=STARTS, observed=OBSERVED):
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    execution = CosimExecution.from_step_size(round(h * 1e9))
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    index, vrs = {}, {}
    for name, path in paths.items():
        index[name] = execution.add_local_slave(CosimLocalSlave(fmu_path=path, instance_name=name))
        vrs[name] = variable_refs(path)
    for a, x, b, y in CONNECTIONS:
        execution.connect_real_variables(index[a], vrs[a][x], index[b], vrs[b][y])
    for (name, var), value in starts.items():
        if isinstance(value, int):
            execution.integer_initial_value(index[name], vrs[name][var], value)
        else:
            execution.real_initial_value(index[name], vrs[name][var], value)
    rows = []
    for k in range(int(round(STOP / h))):
        assert execution.step(), f"libcosim step {k} failed"
        rows.append([observer.last_real_values(index[a], [vrs[a][x]])[0] for a, x in observed])
    return np.array(rows)


def run_ecos(paths, h, starts=STARTS, observed=OBSERVED):
    from ecospy import EcosSimulation
    from ecospy.EcosSimulationStructure import EcosSimulationStructure

    structure = EcosSimulationStructure()
    for name, path in paths.items():
        structure.add_model(name, path)
    for a, x, b, y in CONNECTIONS:
        structure.make_real_connection(f"{a}::{x}", f"{b}::{y}")
    structure.add_parameter_set("start", {f"{a}::{x}": v for (a, x), v in starts.items()})
    rows = []
    with EcosSimulation(structure=structure, step_size=h) as sim:
        assert sim.init(parameter_set="start"), "Ecos could not initialize"
        for _ in range(int(round(STOP / h))):
            sim.step()
            rows.append([sim.get_real(f"{a}::{x}") for a, x in observed])
        np.testing.assert_allclose(sim.get_time(), STOP, rtol=1e-9)
        sim.terminate()
    return np.array(rows)


RUNNERS = {"fmpy": run_fmpy, "libcosim": run_libcosim, "ecos": run_ecos}


@pytest.fixture(scope="module")
def runs(fmus):
    paths, _ = fmus
    return {(m, h): RUNNERS[m](paths, h) for m in MASTERS for h in STEPS}


def errors(fmus, runs, master, steps=STEPS, columns=BUILTIN_COLUMNS):
    """Per communication step: the largest difference from the built-in
    run of each observed quantity, over its peak change."""
    _, (names, data) = fmus
    out = []
    for h in steps:
        r = runs[(master, h)]
        t = h * np.arange(1, len(r) + 1)
        errs = []
        for j, col in enumerate(columns):
            ref = np.interp(t, data[:, 0], data[:, names.index(col)])
            swing = np.max(np.abs(ref - ref[0]))
            errs.append(np.max(np.abs(r[:, j] - ref)) / swing)
        out.append(errs)
    return np.array(out)


@pytest.mark.parametrize("master", MASTERS)
def test_the_coupled_quarter_car_matches_the_built_in_sprung_mass(fmus, runs, master):
    e = errors(fmus, runs, master)
    for h, row in zip(STEPS, e):
        print(f"{master} H = {h:g} s: " + ", ".join(
            f"{c} {x:.3e}" for c, x in zip(BUILTIN_COLUMNS, row)))
    # first order: each halving of the communication step halves the error
    ratios = e[:-1] / e[1:]
    assert np.all((ratios > 1.8) & (ratios < 2.2)), ratios
    assert np.all(e[-1] < 5e-3), e[-1]


@pytest.mark.parametrize("master", ["libcosim", "ecos"])
def test_the_masters_agree_on_the_coupled_run_to_1e_9(runs, master):
    for h in STEPS:
        ref, other = runs[("fmpy", h)], runs[(master, h)]
        assert other.shape == ref.shape
        scale = np.max(np.abs(ref), axis=0)
        np.testing.assert_allclose(other, ref, rtol=1e-9, atol=0, err_msg=f"{master} H = {h}")
        assert np.all(np.abs(other - ref) <= 1e-9 * scale)

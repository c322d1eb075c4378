"""Where the coupling error of the car body's acceleration comes from.

The quarter car of scripts/tests/test_coupling.py (a pythonfmu FMU) hangs on
guideway's glider FMU; fmpy steps both by hand, exchanging values at the
communication points (Jacobi), both extrapolating their inputs along a line
(as test_coupling_order2.py). The reference is the same system built into
guideway (`kind = "sprung_mass"`), run by `guideway run`.

For each variant and communication step H it prints the largest error over
0.8 s, relative to the reference's peak change, of
- the car body's displacement,
- the car body's acceleration as the vehicle FMU reports it (`vehicle.ay`),
- the same acceleration computed from the states both FMUs report at the
  communication point (the car body's y, vy and the glider's y, vy):
  what the vehicle's output would be if it saw its inputs at t + H.

Variants (each changes the coupled system and its reference alike):
  base       the system of the tests
  no-damper  suspension damping c = 0
  stiff-beam the beam's bending stiffness x 100 (first mode 480 Hz)
  one-mode   the beam in its first mode only (48 Hz; `solver.structure =
             "modal"`), two-modes: its first two (48 and 193 Hz)
  quadratic  the quarter car extrapolates a parabola through its last
             three communication points instead of a line
  consistent the quarter car computes its outputs ay and force_y (which
             depend directly on its inputs) when they are read, from its
             state and its inputs as last set, and the master sets its
             inputs before reading them (guideway's outputs have no direct
             feedthrough, so this order is always possible): every output
             at t + H is consistent with every state at t + H
  exact      the master sends the quarter car the exact derivatives of its
             inputs at the communication point (d y_w/dt = glider vy,
             d vy_w/dt = glider ay, the quarter car's `extrapolate` = 3),
             and guideway its force's derivative from both FMUs' outputs
             (dF/dt = k (vy - vy_w) + c (ay - ay_w))

With --masters it runs the base system in the three masters of
test_coupling.py instead, the vehicle computing its outputs at the step's
end (`consistent` = 0) and when read (1).

Usage: .venv/bin/python scripts/coupling_order.py [VARIANT ...] [--steps H ...] [--masters]
"""

import argparse
import pathlib
import subprocess
import sys
import tempfile

import numpy as np
from fmpy import read_model_description
from fmpy.fmi2 import FMU2Slave

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts" / "tests"))
from test_coupling import BEAM, BUILTIN, COUPLED, CONNECTIONS, STARTS, STOP, C, D0, G, K, M  # noqa: E402
from conftest import GUIDEWAY, extracted, read_csv  # noqa: E402

EI = 8.5347e10
VARIANTS = {
    "base": {},
    "no-damper": {"damping": 0.0},
    "stiff-beam": {"stiffness_factor": 100.0},
    "one-mode": {"modes": 1},
    "two-modes": {"modes": 2},
    "quadratic": {"extrapolate": 2},
    "exact": {"exact": True, "extrapolate": 3},
    "consistent": {"consistent": 1},
    "consistent+exact": {"consistent": 1, "exact": True, "extrapolate": 3},
}


def build(d, damping, stiffness_factor, modes=None):
    """The guideway FMU, the quarter car FMU and the reference run."""
    beam = BEAM.replace("bending_stiffness = 8.5347e10", f"bending_stiffness = {EI * stiffness_factor!r}")
    assert stiffness_factor == 1.0 or beam != BEAM
    if modes is not None:
        beam = beam.replace("[solver]\n", f'[solver]\nstructure = "modal"\nmodes = {modes}\n')
    builtin = BUILTIN.replace(f"damping = {C}", f"damping = {damping}")
    (d / "coupled.toml").write_text(COUPLED + beam)
    (d / "builtin.toml").write_text(builtin + beam)
    run = lambda *a: subprocess.run([str(GUIDEWAY), *a], check=True, capture_output=True)
    run("export", str(d / "coupled.toml"), "-o", str(d / "coupled_glider.fmu"))
    run("run", str(d / "builtin.toml"), "--out", str(d / "builtin.csv"), "--quiet")
    subprocess.run([str(ROOT / ".venv" / "bin" / "pythonfmu"), "build", "-f",
                    str(ROOT / "scripts" / "tests" / "vehicle" / "quarter_car.py"), "--dest", str(d)],
                   check=True, capture_output=True)
    return {"guideway": str(d / "coupled_glider.fmu"), "vehicle": str(d / "quarter_car.fmu")}, \
        read_csv(d / "builtin.csv")


def instantiate(paths, starts):
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
        setter = slaves[name].setInteger if isinstance(value, int) else slaves[name].setReal
        setter([vrs[name][var]], [value])
    for s in slaves.values():
        s.enterInitializationMode()
        s.exitInitializationMode()
    return slaves, vrs


def send_exact_derivatives(slaves, vrs, get, damping):
    """The inputs' exact first derivatives at the communication point: the
    quarter car's through its input `ay_w` (pythonfmu does not forward
    fmi2SetRealInputDerivatives; `extrapolate` = 3 reads d y_w/dt = vy_w,
    d vy_w/dt = ay_w), guideway's through fmi2SetRealInputDerivatives."""
    vy_w, ay_w = get("guideway", "car_unsprung.vy"), get("guideway", "car_unsprung.ay")
    vy, ay = get("vehicle", "vy"), get("vehicle", "ay")
    slaves["vehicle"].setReal([vrs["vehicle"]["ay_w"]], [ay_w])
    force_rate = K * (vy - vy_w) + damping * (ay - ay_w)
    slaves["guideway"].setRealInputDerivatives(
        [vrs["guideway"]["car_unsprung.coupling_force_y"]], [1], [force_rate])


def run(paths, h, damping, options):
    """Per communication point: car y, vy, ay (reported) and glider y, vy."""
    starts = {**STARTS, ("vehicle", "damping"): damping,
              ("vehicle", "extrapolate"): options.get("extrapolate", 1),
              ("vehicle", "consistent"): options.get("consistent", 0)}
    slaves, vrs = instantiate(paths, starts)

    def get(name, var):
        return slaves[name].getReal([vrs[name][var]])[0]

    def transfer(source):
        """Every connection from `source`'s outputs, in the connections'
        order (guideway's first: the vehicle's outputs may depend on them)."""
        for a, x, b, y in CONNECTIONS:
            if a == source:
                slaves[b].setReal([vrs[b][y]], [get(a, x)])

    rows = []
    for k in range(int(round(STOP / h))):
        transfer("guideway")
        transfer("vehicle")
        # (at t = 0 guideway's ay leaves out the coupling loads' start
        # values: the system starts at rest, every derivative is 0)
        if options.get("exact") and k > 0:
            send_exact_derivatives(slaves, vrs, get, damping)
        for s in slaves.values():
            s.doStep(k * h, h)
        transfer("guideway")
        rows.append([get("vehicle", "y"), get("vehicle", "vy"), get("vehicle", "ay"),
                     get("guideway", "car_unsprung.y"), get("guideway", "car_unsprung.vy")])
    for s in slaves.values():
        s.terminate()
        s.freeInstance()
    return np.array(rows)


def errors(rows, reference, h, damping):
    names, data = reference
    t = h * np.arange(1, len(rows) + 1)

    def error(values, column):
        ref = np.interp(t, data[:, 0], data[:, names.index(column)])
        return np.max(np.abs(values - ref)) / np.max(np.abs(ref - ref[0]))

    y, vy, ay, y_w, vy_w = rows.T
    consistent = (-K * (y - y_w - D0) - damping * (vy - vy_w)) / M
    ay_ref = np.interp(t, data[:, 0], data[:, names.index("car.ay")])
    return (error(y, "car.y"), error(ay, "car.ay"), error(consistent, "car.ay"),
            np.max(np.abs(ay_ref - ay_ref[0])))


def masters(steps):
    """The base system in the three masters of test_coupling.py (each reads
    every output after the step, then transfers), the vehicle computing its
    outputs at the step's end and on read."""
    import test_coupling

    watched = test_coupling.OBSERVED + [("vehicle", "ay")]
    columns = test_coupling.BUILTIN_COLUMNS + ["car.ay"]
    print("master     vehicle.consistent  " + "  ".join(f"car ay, H = {h * 1e3:g} ms" for h in steps))
    with tempfile.TemporaryDirectory() as d:
        fmus = build(pathlib.Path(d), C, 1.0)
        for consistent in (0, 1):
            starts = {**STARTS, ("vehicle", "extrapolate"): 1, ("vehicle", "consistent"): consistent}
            for master, runner in test_coupling.RUNNERS.items():
                runs = {(master, h): runner(fmus[0], h, starts, watched) for h in steps}
                e = test_coupling.errors(fmus, runs, master, steps, columns)[:, -1]
                print(f"{master:10s} {consistent:18d}  " + "  ".join(f"{x:19.3e}" for x in e),
                      flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("variants", nargs="*", default=list(VARIANTS))
    parser.add_argument("--steps", nargs="+", type=float, default=[2.5e-3, 1.25e-3])
    parser.add_argument("--masters", action="store_true",
                        help="the base system in fmpy, libcosim and Ecos instead")
    args = parser.parse_args()
    if args.masters:
        return masters(args.steps)
    print("variant            H (ms)  car y      car ay (reported)  car ay (consistent)  "
          "peak ay change (m/s2)  reported ay error (m/s2)")
    for variant in args.variants:
        options = VARIANTS[variant]
        damping = options.get("damping", C)
        with tempfile.TemporaryDirectory() as d:
            paths, reference = build(pathlib.Path(d), damping, options.get("stiffness_factor", 1.0),
                                     options.get("modes"))
            for h in args.steps:
                rows = run(paths, h, damping, options)
                e = errors(rows, reference, h, damping)
                print(f"{variant:18s} {h * 1e3:6.3f}  {e[0]:.3e}  {e[1]:.3e}          {e[2]:.3e}"
                      f"            {e[3]:.3e}              {e[1] * e[3]:.3e}",
                      flush=True)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""guideway side by side with its peers, in one measurement run: a general
multibody code (Exudyn) on the paper's 10 m/s wheel, and a structural
finite-element code (OpenSeesPy) on a moving force and a sprung mass.

    .venv/bin/python scripts/bench_peers.py                       # both peers, 5 rounds
    .venv/bin/python scripts/bench_peers.py --peers opensees --rounds 1   # shorter

What it does:

1. Installs the peers (PyPI `exudyn` and `openseespy`, pinned) and numpy
   into their own venv, `target/peers-venv`, unless present. OpenSeesPy's
   Linux wheel links libblas.so.3 and ships a copy: it runs with that copy
   on LD_LIBRARY_PATH; if it still fails to import, the script says which
   Debian package to install (it never installs system packages). The
   Exudyn model is run from `../shared/peers/exudyn/runExudynWheelBeam.py`
   (beside this repository); the OpenSees models are
   `scripts/peers/opensees_models.py`.
2. Builds `target/release/guideway`.
3. References. Exudyn: each code's exit speed against its own converged
   value (the models differ): guideway's RK4 at two fine steps,
   Richardson-extrapolated; Exudyn's the mean of two fine runs, half their
   difference its uncertainty. OpenSees: both codes' midspan histories
   against the same closed form (`scripts/peers/references.py`): Frýba's
   series for the moving force, a modal superposition for the sprung
   mass; each code writes its history in one untimed run.
4. Timing: every configuration runs once per round, round after round,
   the codes alternating (never all of one code then the other), each as
   its own process and bounded in time. Per round the ratio peer /
   guideway is taken for each pairing, whole process (wall clock around
   the process, start-up included) and solve only (guideway's
   `wall_time_s`, Exudyn's `wallSolve_s`, the time inside OpenSees'
   `analyze` calls); the report gives their median and range.
5. Pairing (`pairings`): for each peer run, the cheapest guideway run (by
   median process time) whose error is at most the peer run's error.
6. The process floor, in the same rounds: `/bin/true` and `guideway
   --version`, spawned as the runs are.
7. Writes `report/peers.md` and `report/peers.png` (error against time,
   one panel per case).
"""

import argparse
import datetime
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

from built import guideway_command
from peers import opensees_bench
from peers.timing import (RUN_TIMEOUT_S, Config, alternate, cheapest_as_accurate, machine,
                          pairings, ratios, run_bounded, spread)

ROOT = Path(__file__).resolve().parent.parent
PEER_DIR = ROOT.parent / "shared" / "peers" / "exudyn"
PEER_SCRIPT = PEER_DIR / "runExudynWheelBeam.py"
VENV = ROOT / "target" / "peers-venv"
EXUDYN_VERSION = "1.13.6"
# The command step 2 builds, or $GUIDEWAY_BIN (scripts/built.py).
GUIDEWAY = guideway_command()
PAPER_STEP = 0.0025


def sh(cmd, **kw):
    return subprocess.run(cmd, check=True, **kw)


def ensure_peers(peers):
    """The peers venv's python, with the packages of `peers` installed
    (each at its pinned version) and numpy."""
    python = VENV / "bin" / "python"
    wanted = {"exudyn": ("exudyn", EXUDYN_VERSION),
              "opensees": ("openseespy", opensees_bench.OPENSEES_VERSION)}
    missing = []
    for peer in peers:
        package, version = wanted[peer]
        probe = [str(python), "-m", "pip", "show", package]
        found = subprocess.run(probe, capture_output=True, text=True) if python.exists() else None
        if found is None or found.returncode != 0 or f"Version: {version}" not in found.stdout:
            missing.append(f"{package}=={version}")
    if missing:
        print(f"installing {', '.join(missing)} and numpy into {VENV}", flush=True)
        if not python.exists():
            sh([sys.executable, "-m", "venv", str(VENV)])
        sh([str(python), "-m", "pip", "install", "-q", *missing, "numpy"])
    if "opensees" in peers:
        check_opensees(python)
    return python


def check_opensees(python):
    """OpenSeesPy imports with the wheel's own BLAS on the library path;
    if not, say which system package would give it one."""
    probe = [str(python), "-c", "import openseespy.opensees"]
    found = subprocess.run(probe, capture_output=True, text=True,
                           env=opensees_bench.opensees_env(python))
    if found.returncode != 0:
        sys.exit("openseespy does not import in target/peers-venv, even with its bundled "
                 "libblas.so.3 on LD_LIBRARY_PATH: install the Debian package libblas3 "
                 f"(and liblapack3), then run again. Its error:\n{found.stderr[-800:]}")


def guideway_scene(elements, step, integrator, damping=0.0, tolerance=1e-7, modes=None):
    text = subprocess.run(
        [str(GUIDEWAY), "scenes", "--show", "lee1994-wheel-10"],
        check=True, capture_output=True, text=True).stdout
    return edit_scene(text, elements, step, integrator, damping, tolerance, modes)


def edit_scene(text, elements, step, integrator, damping=0.0, tolerance=1e-7, modes=None):
    """The built-in scene's text with these solver and mesh settings; with
    `modes`, the beam reduced to its lowest `modes` modes."""
    replace = {
        "elements": str(elements),
        "step": repr(step),
        "integrator": f'"{integrator}"',
        "numerical_damping": repr(damping),
        "velocity_tolerance": repr(tolerance),
        "max_iterations": "200",
    }
    for key, value in replace.items():
        text, count = re.subn(rf"^{key} = [^#\n]*", f"{key} = {value}", text, flags=re.M)
        if count != 1:
            raise ValueError(f"the scene has {count} lines `{key} = ...`, expected 1")
    if modes is not None:
        if re.search(r"^(structure|modes) = ", text, flags=re.M):
            raise ValueError("the scene already sets solver.structure or solver.modes")
        # In [solver], after its integrator line.
        text = re.sub(r"^(integrator = [^\n]*)$",
                      rf'\1\nstructure = "modal"\nmodes = {int(modes)}', text, flags=re.M)
    return text


def parse_result(code, text):
    """(exit speed, solve time) from a run's JSON: guideway's summary or the
    peer model's result file. A run without an exit speed is an error."""
    result = json.loads(text)
    if code == "guideway":
        speed, solve = result.get("exit_nominal_speed"), result.get("wall_time_s")
    else:
        speed, solve = result.get("exitSpeed"), result.get("wallSolve_s")
    if not isinstance(speed, (int, float)) or not isinstance(solve, (int, float)):
        raise ValueError(f"{code}: no exit speed or solve time in its result")
    return float(speed), float(solve)


def make_guideway(tmp, label, elements, step, integrator, damping=0.0, tolerance=1e-7,
                  modes=None):
    scene = tmp / f"{label}.toml"
    scene.write_text(guideway_scene(elements, step, integrator, damping, tolerance, modes))
    summary = tmp / f"{label}.json"
    # The run's step bound is 10 crossing times of steps; the fine reference
    # steps need more than its default of 1e6 (the run stops at the exit).
    max_steps = max(1_000_000, int(30.0 / step))
    cmd = [str(GUIDEWAY), "run", str(scene), "-q", "--summary", str(summary),
           "--max-steps", str(max_steps)]
    family = f"{integrator.upper()}" if modes is None else f"{integrator.upper()}, modal"
    return Config("guideway", label, cmd, summary, elements, step, family,
                  lambda text: parse_result("guideway", text))


def make_floor(label, cmd):
    """A process that does nothing (or as little as guideway can): the
    floor under every whole-process time on this machine."""
    return Config("floor", label, cmd, None, 0, 0.0)


def make_exudyn(python, tmp, label, elements, step):
    out = tmp / f"{label}.json"
    cmd = [str(python), str(PEER_SCRIPT), "--V0", "10", "--nElements", str(elements),
           "--stepSize", repr(step), "--contactStiffness", "1e12", "--quiet",
           "--json", str(out)]
    return Config("exudyn", label, cmd, out, elements, step, "generalized-α",
                  lambda text: parse_result("exudyn", text))


class ExudynBench:
    """The wheel case against Exudyn: references, runs, pairing, report."""

    def __init__(self, python, tmp):
        print("Exudyn references ...", flush=True)
        self.references = {}
        for elements, h in [(2, PAPER_STEP / 64), (32, PAPER_STEP / 256)]:
            coarse = make_guideway(tmp, f"ref{elements}a", elements, h, "rk4", tolerance=1e-11)
            fine = make_guideway(tmp, f"ref{elements}b", elements, h / 2, "rk4", tolerance=1e-11)
            coarse.run()
            fine.run()
            value = fine.exit_speed + (fine.exit_speed - coarse.exit_speed) / 3.0
            self.references[elements] = (value, abs(fine.exit_speed - coarse.exit_speed))
        refs = [make_exudyn(python, tmp, "eref32", 32, 1e-4),
                make_exudyn(python, tmp, "eref64", 64, 2.5e-4)]
        for config in refs:
            config.run()
        self.fine_runs = tuple(c.exit_speed for c in refs)
        a, b = self.fine_runs
        self.reference, self.uncertainty = 0.5 * (a + b), 0.5 * abs(a - b)
        self.guideway = [
            make_guideway(tmp, "g2-rk4-2.5ms", 2, PAPER_STEP, "rk4"),
            make_guideway(tmp, "g32-modal4-rk4-2.5ms", 32, PAPER_STEP, "rk4", modes=4),
            make_guideway(tmp, "g32-modal6-rk4-2.5ms", 32, PAPER_STEP, "rk4", modes=6),
            make_guideway(tmp, "g32-modal8-rk4-2.5ms", 32, PAPER_STEP, "rk4", modes=8),
            make_guideway(tmp, "g32-hht-2.5ms", 32, PAPER_STEP, "hht"),
            make_guideway(tmp, "g32-hht-1.25ms", 32, PAPER_STEP / 2, "hht"),
            make_guideway(tmp, "g32-hht-0.625ms", 32, PAPER_STEP / 4, "hht"),
            make_guideway(tmp, "g32-hht-0.3125ms", 32, PAPER_STEP / 8, "hht"),
        ]
        self.exudyn = [
            make_exudyn(python, tmp, "e32-1ms", 32, 1e-3),
            make_exudyn(python, tmp, "e32-0.5ms", 32, 5e-4),
            make_exudyn(python, tmp, "e32-0.25ms", 32, 2.5e-4),
        ]

    def error(self, config):
        if config.code == "guideway":
            return abs(config.exit_speed - self.references[config.elements][0])
        return abs(config.exit_speed - self.reference)

    def pairs(self):
        cost = Config.median_process
        at_32 = [g for g in self.guideway if g.elements == 32]
        paired = pairings(self.exudyn, at_32, self.error, cost)
        rows = [("paper's setting (2 elements, RK4, 2.5 ms)", self.guideway[0],
                 min(self.exudyn, key=cost))]
        rows += [(f"32 elements, error ≤ Exudyn's at {e.step:g} s", g, e) for e, g in paired if g]
        return paired, rows

    def report(self, floors):
        lines = ["## Against Exudyn (the paper's wheel)", ""]
        lines += self.intro_lines()
        lines += self.run_lines(floors)
        paired, rows = self.pairs()
        lines += self.pairing_lines(paired)
        lines += self.ratio_lines(rows, paired)
        lines += self.ceiling_lines(floors)
        return lines, rows

    def intro_lines(self):
        a, b = self.fine_runs
        lines = [
            f"Exudyn {EXUDYN_VERSION} runs the peer model `../shared/peers/exudyn/runExudynWheelBeam.py` "
            "(ANCF cable, penalty contact with k_c = 1e12 N/m, generalized-α with ρ∞ = 0.8, one "
            "thread); guideway runs `target/release/guideway run <scene> -q --summary`: the paper's "
            "setting, 32 elements reduced to their lowest 4, 6 or 8 modes (`[solver] structure = "
            "\"modal\"`) with RK4 at the paper's step, and the full 32-element mesh with HHT-α at "
            "four steps. *Process*: wall clock around the whole process (start-up, build, solve, "
            "output) as the script spawns it. *Solve*: the time each code reports for its time "
            "stepping alone. *Process CPU time*: user + system time of the process.", "",
            "Each code's exit speed is compared with its own converged value: the models differ "
            "(finite EA, penalty contact and the centre's speed at x_c = L in Exudyn; the paper's "
            "model and the nominal speed V at the contact's exit in guideway). The modal runs are "
            "compared with the full 32-element reference: their error includes the truncation to "
            "k modes. The full mesh's HHT-α runs do not converge monotonically at these steps: the "
            "rigid wheel excites the 32-element beam's highest modes (up to 12.7 kHz, ω = 8.0e4 "
            "rad/s, by `guideway modes SCENE --count 64`), which HHT-α follows in phase only for "
            "ω Δt below about 1, Δt below about 12 µs; the RK4 reference's steps (9.8 and 4.9 µs; "
            "RK4 is stable there only below 35 µs) resolve them, and the modal runs leave them "
            "out.", ""]
        for elements in (2, 32):
            value, diff = self.references[elements]
            lines.append(f"- guideway, {elements} elements: {value:.7f} m/s (RK4 at two fine "
                         f"steps, Richardson; the two runs differ by {diff:.1e} m/s)")
        lines.append(f"- Exudyn: {self.reference:.5f} m/s (mean of 32 elements at 1e-4 s and 64 "
                     f"elements at 2.5e-4 s, {a:.5f} and {b:.5f}; ± {self.uncertainty:.1e} m/s)")
        return lines + [""]

    def run_lines(self, floors):
        lines = ["| code | configuration | exit speed (m/s) | error (m/s) | process (s): median [min, max] | solve (s): median [min, max] |",
                 "|---|---|---:|---:|---|---|"]
        for c in self.guideway + self.exudyn:
            pm, plo, phi = spread(c.process)
            sm, slo, shi = spread(c.solve)
            lines.append(f"| {c.code} | {c.label} | {c.exit_speed:.6f} | {self.error(c):.1e} | "
                         f"{pm:.4g} [{plo:.4g}, {phi:.4g}] | {sm:.4g} [{slo:.4g}, {shi:.4g}] |")
        for c in floors:
            pm, plo, phi = spread(c.process)
            lines.append(f"| floor | `{c.label}` | | | {pm:.4g} [{plo:.4g}, {phi:.4g}] | |")
        return lines + [""]

    def pairing_lines(self, paired):
        u = self.uncertainty
        lines = [
            "For each Exudyn run, the cheapest 32-element guideway run (by median process time) "
            "whose exit-speed error is at most that Exudyn run's error; the paper's setting "
            "(2 elements, its own reference) is paired with Exudyn's cheapest run. Exudyn's "
            f"reference is itself uncertain by ± {u:.1e} m/s (half the difference of its two fine "
            "runs): an Exudyn error below it is not resolved. The last column names the cheapest "
            "guideway run whose error is below Exudyn's error minus the uncertainty (more "
            "accurate beyond doubt), where there is one.", "",
            "| Exudyn run | its error (m/s) | resolved? | paired guideway run | its error (m/s) | beyond doubt |",
            "|---|---:|---|---|---:|---|"]
        at_32 = [g for g in self.guideway if g.elements == 32]
        for e, g in paired:
            resolved = "yes" if self.error(e) > u else f"no (≤ {u:.1e})"
            strict = cheapest_as_accurate(self.error(e) - u, at_32, self.error,
                                          Config.median_process)
            ours = f"{g.label} | {self.error(g):.1e}" if g else "none | "
            lines.append(f"| {e.label} | {self.error(e):.1e} | {resolved} | {ours} | "
                         f"{strict.label if strict else 'none'} |")
        return lines + [""]

    def ratio_lines(self, rows, paired):
        lines = ["### Ratios (Exudyn time / guideway time, per round)", "",
                 "| pairing | guideway | Exudyn | errors (m/s) | process ratio: median [min, max] | solve ratio: median [min, max] | process CPU-time ratio |",
                 "|---|---|---|---|---|---|---|"]
        for name, g, e in rows:
            cells = [spread(ratios(e.process, g.process)), spread(ratios(e.solve, g.solve)),
                     spread(ratios(e.cpu, g.cpu))]
            lines.append(f"| {name} | {g.label} | {e.label} | {self.error(g):.1e} / "
                         f"{self.error(e):.1e} | "
                         + " | ".join(f"{m:.0f}× [{lo:.0f}, {hi:.0f}]" for m, lo, hi in cells)
                         + " |")
        lines.append("")
        lines += [f"No 32-element guideway run reached the error of {e.label}, "
                  f"{self.error(e):.1e} m/s." for e, g in paired if g is None]
        return lines + [""]

    def ceiling_lines(self, floors):
        lines = ["### The ceiling: the process floor", "",
                 "A whole-process ratio cannot exceed the peer's time over the time of a process "
                 "that does nothing, spawned the same way on the same machine. Per round, "
                 "Exudyn's process time over the floor's:", "",
                 "| Exudyn run | / `/bin/true`: median [min, max] | / `guideway --version`: median [min, max] |",
                 "|---|---|---|"]
        for e in sorted(self.exudyn, key=Config.median_process):
            cells = [spread(ratios(e.process, f.process)) for f in floors]
            lines.append(f"| {e.label} | " + " | ".join(
                f"{m:.0f}× [{lo:.0f}, {hi:.0f}]" for m, lo, hi in cells) + " |")
        return lines + [""]

    def plot(self, ax):
        """Exit-speed error against whole-process time, both codes."""
        runs, cost = self.guideway + self.exudyn, Config.median_process
        for code, marker in (("guideway", "o"), ("exudyn", "s")):
            for elements, family in sorted({(c.elements, c.family) for c in runs
                                            if c.code == code}):
                group = [c for c in runs
                         if c.code == code and (c.elements, c.family) == (elements, family)]
                name = "Exudyn" if code == "exudyn" else "guideway"
                ax.plot([cost(c) for c in group], [max(self.error(c), 1e-9) for c in group],
                        marker=marker, linestyle="-", label=f"{name}, {elements} el., {family}")
        ax.axhline(self.uncertainty, color="tab:orange", linestyle=":", linewidth=1,
                   label="uncertainty of Exudyn's reference")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("whole-process wall time (s), median of the rounds")
        ax.set_ylabel("|exit speed − own reference| (m/s)")
        ax.set_title("paper's wheel at 10 m/s: Exudyn", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6)


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rounds", type=int, default=5, help="measurement rounds (default 5)")
    parser.add_argument("--peers", choices=("exudyn", "opensees", "all"), default="all",
                        help="which peers to run (default all)")
    parser.add_argument("--out", default=str(ROOT / "report"), help="report directory")
    args = parser.parse_args()
    args.peers = ("exudyn", "opensees") if args.peers == "all" else (args.peers,)
    if "exudyn" in args.peers and not PEER_SCRIPT.exists():
        sys.exit(f"the peer model is not at {PEER_SCRIPT}")
    if args.rounds < 1 or args.rounds > 50:
        sys.exit("--rounds must be 1 to 50 (each round runs the peers for 10 to 30 s)")
    return args


def measure(order, rounds):
    """Every run of `order` once per round, the order reversed every other
    round."""
    for r in range(rounds):
        for config in order if r % 2 == 0 else reversed(order):
            wall, solve = config.run()
            config.process.append(wall)
            config.solve.append(solve)
        print(f"  round {r + 1}: done", flush=True)


def run_history(config):
    run_bounded(config.history_cmd, RUN_TIMEOUT_S, config.env)


def main():
    args = parse_args()
    python = ensure_peers(args.peers)
    sh(["cargo", "build", "--release", "--quiet", "--bin", "guideway"], cwd=ROOT)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix="bench_peers_"))
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    load_before = os.getloadavg()
    exudyn = ExudynBench(python, tmp) if "exudyn" in args.peers else None
    opensees, refs = [], {}
    if "opensees" in args.peers:
        print("OpenSees references and histories ...", flush=True)
        refs = {name: opensees_bench.Reference(name) for name in opensees_bench.CASES}
        opensees = opensees_bench.configs(GUIDEWAY, python, tmp, list(refs))
        opensees_bench.measure_errors(opensees, refs, run_history)
    floors = [make_floor("/bin/true", ["/bin/true"]),
              make_floor("guideway --version", [str(GUIDEWAY), "--version"])]
    ours = floors + [c for c in opensees if c.code == "guideway"]
    peers = [c for c in opensees if c.code != "guideway"]
    if exudyn:
        ours, peers = ours + exudyn.guideway, exudyn.exudyn + peers
    print(f"{args.rounds} rounds of {len(ours) + len(peers)} runs, alternating ...", flush=True)
    measure(alternate(ours, peers), args.rounds)
    load = (load_before, os.getloadavg())
    write_report(out, args, date, load, exudyn, opensees, refs, floors)


def write_report(out, args, date, load, exudyn, opensees, refs, floors):
    (before, after) = load
    lines = ["# guideway and its peers side by side", "",
             f"Measured {date} with `.venv/bin/python scripts/bench_peers.py --peers "
             f"{'all' if len(args.peers) == 2 else args.peers[0]} --rounds {args.rounds}` on "
             f"{machine()}; load average (1, 5, 15 min) {before[0]:.2f}, {before[1]:.2f}, "
             f"{before[2]:.2f} before and {after[0]:.2f}, {after[1]:.2f}, {after[2]:.2f} after "
             "(other developers' builds share the machine: read the ratios, which pair runs "
             "taken seconds apart, rather than the absolute times). Every configuration ran "
             "once per round, the codes alternating, the order reversed every other round, "
             "together with the process floor (`/bin/true`, `guideway --version`).", ""]
    rows, paired = [], {"solve": {}, "process": {}}
    if exudyn:
        exudyn_lines, rows = exudyn.report(floors)
        lines += exudyn_lines
    if opensees:
        paired = {"solve": opensees_bench.pairs(opensees, refs, Config.median_solve),
                  "process": opensees_bench.pairs(opensees, refs, Config.median_process)}
        lines += opensees_bench.report_lines(opensees, refs, paired, floors)
    lines += ["![error against time](peers.png)", ""]
    (out / "peers.md").write_text("\n".join(lines) + "\n")
    plot(out / "peers.png", date, exudyn, opensees, refs)
    print((out / "peers.md").read_text())
    for name, (slo, shi, plo, phi) in opensees_bench.summary(paired).items():
        print(f"OpenSees, {name}: solve {slo:.0f}-{shi:.0f}x, process {plo:.0f}-{phi:.0f}x")


def plot(path, date, exudyn, opensees, refs):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib missing: no plot", file=sys.stderr)
        return
    panels = (["exudyn"] if exudyn else []) + list(refs)
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.8), squeeze=False)
    for ax, panel in zip(axes[0], panels):
        if panel == "exudyn":
            exudyn.plot(ax)
        else:
            opensees_bench.plot_case(ax, opensees, panel)
    fig.suptitle(f"guideway and its peers: error against time, paired runs ({date})",
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()

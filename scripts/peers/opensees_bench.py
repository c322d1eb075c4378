"""The OpenSeesPy half of the peer bench: its two cases (Frýba's moving
force, Yang & Yau's sprung mass on a massless follower), the guideway
scenes and OpenSees runs of each, their errors against the closed forms
of references.py, the pairing at equal accuracy and the report's rows."""

import csv
import json
import math
import os
from pathlib import Path

import numpy as np

from . import references
from .timing import Config, pairings, ratios, spread

HERE = Path(__file__).resolve().parent
MODELS = HERE / "opensees_models.py"
OPENSEES_VERSION = "3.7.1.2"

_FRYBA_OMEGA1 = (math.pi / 24.0) ** 2 * math.sqrt(1e9 / 1250.0)
# Frýba's case at α = c / c_cr = 0.5 (tests/physics/fryba.rs's beam and force), and
# the sprung mass of tests/physics/sprung_mass.rs over a massless follower
# (Yang & Yau's moving oscillator), with its dashpot.
CASES = {
    "moving_force": dict(case="moving_force", length=24.0, mass_per_length=1250.0,
                         bending_stiffness=1e9, force=600e3,
                         speed=0.5 * _FRYBA_OMEGA1 * 24.0 / math.pi),
    "sprung_mass": dict(case="sprung_mass", length=25.0, mass_per_length=2303.0,
                        bending_stiffness=8.5347e10, sprung_mass=5750.0, stiffness=1.595e6,
                        damping=2.0e4, gravity=9.81, speed=100.0 / 3.6),
}
ELEMENTS = (8, 16, 32, 64)
# Steps per passage (moving force) and step in seconds (sprung mass).
GRIDS = {
    "moving_force": {"opensees": (250, 1000), "guideway": (125, 250, 500, 1000, 2000, 4000)},
    "sprung_mass": {"opensees": (1e-3, 2.5e-4),
                    "guideway": (1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5)},
}
TITLES = {"moving_force": "moving force (Frýba, α = 0.5)",
          "sprung_mass": "sprung mass (Yang & Yau, follower)"}
# The sprung mass's reference: 30 modes, RK4 at this step (and at twice it
# for its own uncertainty).
REFERENCE_STEP = 1.25e-5


def passage(case):
    return case["length"] / case["speed"]


def step_of(name, value):
    """The time step of a grid entry."""
    return passage(CASES[name]) / value if name == "moving_force" else value


def scene_text(name, elements, step):
    """The guideway scene of a case on `elements` at `step`."""
    c = CASES[name]
    beam = (f'[beam]\nlength = {c["length"]!r}\nmass_per_length = {c["mass_per_length"]!r}\n'
            f'bending_stiffness = {c["bending_stiffness"]!r}\nsurface_offset = 0.0\n'
            f"elements = {elements}\n")
    sensor = f'[[sensors]]\nname = "midspan"\nposition = {c["length"] / 2!r}\n'
    if name == "moving_force":
        body = ('[body]\nname = "force"\nkind = "moving_force"\nmass = 1.0\n'
                f'initial_speed = {c["speed"]!r}\nforce_y = {-c["force"]!r}\n')
        return f'name = "fryba"\ngravity = 0.0\n{beam}{body}{sensor}[solver]\nstep = {step!r}\n'
    body = ('[body]\nname = "car"\nkind = "sprung_mass"\n'
            f'mass = {c["sprung_mass"]!r}\ninitial_speed = {c["speed"]!r}\n'
            f'[body.suspension]\nstiffness = {c["stiffness"]!r}\ndamping = {c["damping"]!r}\n'
            "unsprung_mass = 0.0\n")
    return (f'name = "sprung"\ngravity = {c["gravity"]!r}\n{beam}{body}{sensor}'
            f'[solver]\nintegrator = "hht"\nstep = {step!r}\n')


def guideway_solve(text):
    return None, float(json.loads(text)["wall_time_s"])


def opensees_solve(text):
    return None, float(json.loads(text)["wallSolve_s"])


def make_guideway(guideway, tmp, name, elements, step):
    label = f"g-{name}-{elements}-{step:.3g}"
    scene = tmp / f"{label}.toml"
    scene.write_text(scene_text(name, elements, step))
    summary = tmp / f"{label}.json"
    cmd = [str(guideway), "run", str(scene), "-q", "--summary", str(summary)]
    config = Config("guideway", label, cmd, summary, elements, step, f"{elements} el.",
                    guideway_solve)
    config.case, config.history_cmd = name, cmd + ["-o", str(tmp / f"{label}.csv")]
    return config


def opensees_env(python):
    """The environment with the wheel's own BLAS/LAPACK on the library
    path (the wheel links libblas.so.3 but does not find its copy)."""
    site = Path(python).parent.parent / "lib"
    bundled = sorted(site.glob("python3*/site-packages/openseespylinux/lib"))
    env = dict(os.environ)
    if bundled:
        env["LD_LIBRARY_PATH"] = ":".join([str(bundled[0])] + [
            p for p in env.get("LD_LIBRARY_PATH", "").split(":") if p])
    return env


def make_opensees(python, tmp, name, elements, step):
    label = f"o-{name}-{elements}-{step:.3g}"
    case = dict(CASES[name], elements=elements, step=step,
                steps=int(math.ceil(passage(CASES[name]) / step - 1e-9)))
    case_file = tmp / f"{label}.case.json"
    case_file.write_text(json.dumps(case))
    out = tmp / f"{label}.json"
    cmd = [str(python), str(MODELS), str(case_file), str(out), "--no-history"]
    config = Config("opensees", label, cmd, out, elements, step, f"{elements} el.",
                    opensees_solve, env=opensees_env(python))
    config.case, config.history_cmd = name, cmd[:-1]
    return config


def configs(guideway, python, tmp, names):
    """Every guideway and OpenSees run of the cases `names`."""
    made = []
    for name in names:
        for elements in ELEMENTS:
            made += [make_opensees(python, tmp, name, elements, step_of(name, v))
                     for v in GRIDS[name]["opensees"]]
            made += [make_guideway(guideway, tmp, name, elements, step_of(name, v))
                     for v in GRIDS[name]["guideway"]]
    return made


def history(config):
    """(times, midspan) of a config's history run (already run)."""
    if config.code == "opensees":
        result = json.loads(Path(config.history_cmd[3]).read_text())
        return result["time"], result["midspan"]
    with open(config.history_cmd[-1], newline="") as f:
        rows = list(csv.DictReader(f))
    return ([float(r["time"]) for r in rows], [float(r["sensor.midspan.deflection"]) for r in rows])


class Reference:
    """A case's midspan reference as a function of time, and the relative
    error it cannot resolve."""

    def __init__(self, name):
        case = CASES[name]
        self.until = passage(case)
        if name == "moving_force":
            self.at = lambda t: references.fryba_midspan(case, t)
            more = dict(case, terms=1600)
            grid = np.linspace(0.0, self.until, 2001)
            fine = references.fryba_midspan(more, grid)
            self.resolution = float(np.abs(self.at(grid) - fine).max() / np.abs(fine).max())
            return
        count = int(math.ceil(self.until / REFERENCE_STEP)) + 1
        model = references.SprungMass(case)
        fine = model.midspan(REFERENCE_STEP, count)
        coarse = model.midspan(2 * REFERENCE_STEP, (count + 1) // 2)
        grid = np.arange(count + 1) * REFERENCE_STEP
        self.at = lambda t: np.interp(t, grid, fine)
        self.resolution = float(np.abs(fine[::2][:len(coarse)] - coarse[:len(fine[::2])]).max()
                                / np.abs(fine).max())

    def error(self, times, midspan):
        return references.history_error(times, midspan, self.at, self.until)


def measure_errors(runs, refs, run_history):
    """Each run's error against its case's reference, from one history run."""
    for config in runs:
        run_history(config)
        config.error = refs[config.case].error(*history(config))


def pairs(runs, refs, cost):
    """Per case, [(OpenSees run, cheapest guideway run as accurate)]."""
    out = {}
    for name in refs:
        peer = [c for c in runs if c.case == name and c.code == "opensees"]
        ours = [c for c in runs if c.case == name and c.code == "guideway"]
        out[name] = pairings(peer, ours, lambda c: c.error, cost, refs[name].resolution)
    return out


def report_lines(runs, refs, paired, floors):
    """The report's OpenSees section."""
    lines = ["## Against OpenSeesPy", ""]
    w = lines.append
    w(f"OpenSeesPy {OPENSEES_VERSION} runs `scripts/peers/opensees_models.py` (elasticBeamColumn "
      "elements with consistent mass, the axial DOF held, Newmark average acceleration, "
      "`Linear -factorOnce`, BandSPD): the moving force as Path time series of its Hermite "
      "nodal loads; the sprung mass by a Python loop (the beam one step under the last contact "
      "force, updated in place through parameters; then the sprung mass over the step by the "
      "trapezoidal rule: first order in the coupling). guideway runs the same beams "
      "(moving forces: Newmark average acceleration; the sprung mass on its massless follower: "
      "HHT-α with α = 0). *Error*: the largest |midspan deflection − reference| over the "
      "passage, relative to the reference's peak. *Solve*: guideway's `wall_time_s` (its "
      "`advance_to` calls) and the time inside OpenSees' `analyze` calls, both measured in "
      "the process. Both codes write their history in a separate, untimed run.")
    w("")
    for name, ref in refs.items():
        how = ("Frýba's series, 400 terms; the resolution is its change at 1600"
               if name == "moving_force" else
               f"30 sine modes, RK4 at {REFERENCE_STEP:g} s, plus the static part of the modes "
               "left out; the resolution is its change at twice the step")
        w(f"- {TITLES[name]}: passage {ref.until:.4f} s; reference: {how}: "
          f"{ref.resolution:.1e} of the peak. Errors within it of each other count as equal.")
    w("")
    w("| case | code | run | error | process (s): median [min, max] | solve (s): median [min, max] |")
    w("|---|---|---|---:|---|---|")
    for c in runs:
        pm, plo, phi = spread(c.process)
        sm, slo, shi = spread(c.solve)
        w(f"| {c.case} | {c.code} | {c.label} | {c.error:.2e} | {pm:.4g} [{plo:.4g}, {phi:.4g}] "
          f"| {sm:.3g} [{slo:.3g}, {shi:.3g}] |")
    w("")
    lines += ratio_lines(paired, floors)
    return lines


def ratio_lines(paired, floors):
    """`paired`: {"solve": pairs by median solve time, "process": pairs by
    median process time}, each {case: [(OpenSees run, guideway run)]}."""
    lines = ["### Ratios (OpenSees time / guideway time, per round)", "",
             "For each OpenSees run, the cheapest guideway run of the same case whose error is "
             "at most the OpenSees run's (within the reference's resolution): cheapest by "
             "median solve time for the in-process ratio, by median process time for the "
             "whole-process ratios.", "",
             "| case | OpenSees run | its error | guideway run (in process) | its error "
             "| solve ratio: median [min, max] | guideway run (whole process) | its error "
             "| process ratio: median [min, max] | CPU-time ratio | OpenSees / `guideway --version` |",
             "|---|---|---:|---|---:|---|---|---:|---|---|---|"]
    for name in paired["solve"]:
        by_process = dict((o.label, g) for o, g in paired["process"][name])
        for o, g in paired["solve"][name]:
            cells = [f"| {name} | {o.label} | {o.error:.2e} |"]
            cells.append(pair_cells(g, lambda g: [spread(ratios(o.solve, g.solve))], 1))
            cells.append(pair_cells(by_process[o.label], lambda g: [
                spread(ratios(o.process, g.process)), spread(ratios(o.cpu, g.cpu))], 2))
            m, lo, hi = spread(ratios(o.process, floors[1].process))
            lines.append(" ".join(cells) + f" {m:.0f}× [{lo:.0f}, {hi:.0f}] |")
    lines.append("")
    return lines


def pair_cells(g, spreads, width):
    """A guideway run, its error and `width` ratio cells (`spreads(g)`)."""
    if g is None:
        return " none as accurate | |" + " |" * width
    return f" {g.label} | {g.error:.2e} | " + " | ".join(
        f"{m:.0f}× [{lo:.0f}, {hi:.0f}]" for m, lo, hi in spreads(g)) + " |"


def summary(paired):
    """Per case, the range of the median solve and process ratios."""
    out = {}
    for name in paired["solve"]:
        solve = [spread(ratios(o.solve, g.solve))[0] for o, g in paired["solve"][name] if g]
        process = [spread(ratios(o.process, g.process))[0]
                   for o, g in paired["process"][name] if g]
        if solve and process:
            out[name] = (min(solve), max(solve), min(process), max(process))
    return out


def plot_case(ax, runs, name):
    """Error against in-process time, one line per code and mesh."""
    colours = dict(zip(ELEMENTS, ("tab:blue", "tab:orange", "tab:green", "tab:red")))
    for code, marker, style in (("guideway", "o", "-"), ("opensees", "s", "--")):
        for elements in ELEMENTS:
            group = sorted((c for c in runs if c.case == name and c.code == code
                            and c.elements == elements), key=lambda c: c.step, reverse=True)
            if group:
                ax.plot([c.median_solve() for c in group], [max(c.error, 1e-12) for c in group],
                        marker=marker, linestyle=style, color=colours[elements],
                        label=f"{'OpenSees' if code == 'opensees' else 'guideway'}, "
                              f"{elements} elements")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("in-process solve time (s), median of the rounds")
    ax.set_ylabel("midspan error / peak")
    ax.set_title(TITLES[name], fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=2)

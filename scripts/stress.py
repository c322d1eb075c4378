#!/usr/bin/env python3
"""Stiff and extreme cases: run each with `guideway run` and tabulate.

    .venv/bin/python scripts/stress.py [--quick] [--out report/stress.md]

Every case starts from the default scene (the paper's 10 m/s wheel) with one
or two fields changed. Each must either complete (exit reached, energy drift
bounded, iterations converged) or stop early with a diagnostic naming the
limit and the values: never NaN, never inf, never a hang (each run has a
time limit), never a silent wrong answer. The table in report/stress.md
says which, with the figures.
"""

import argparse
import json
import os
import math
import pathlib
import subprocess
import sys
import tempfile
import time
import tomllib

ROOT = pathlib.Path(__file__).resolve().parents[1]
TIME_LIMIT_S = 600


def toml_value(value):
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, float):
        return repr(value)
    return str(value)


def scene_text(base, changes):
    """The base scene with `changes` ({"beam.elements": 8, ...}) applied."""
    scene = json.loads(json.dumps(base))
    for path, value in changes.items():
        table, key = path.split(".")
        scene[table][key] = value
    lines = [f"name = {toml_value(scene['name'])}"]
    for table in ("beam", "body", "solver"):
        lines.append(f"[{table}]")
        for key, value in scene[table].items():
            if isinstance(value, dict):
                continue
            if isinstance(value, list):
                lines.append(f"{key} = [{', '.join(toml_value(v) for v in value)}]")
            else:
                lines.append(f"{key} = {toml_value(value)}")
        if table == "beam":
            supports = scene["beam"].get("supports", {})
            lines.append("[beam.supports]")
            for key, value in supports.items():
                lines.append(f"{key} = {toml_value(value) if not isinstance(value, list) else '[' + ', '.join(map(repr, value)) + ']'}")
    for sensor in scene.get("sensors", []):
        lines.append("[[sensors]]")
        lines.append(f"name = {toml_value(sensor['name'])}")
        lines.append(f"position = {toml_value(sensor['position'])}")
    return "\n".join(lines) + "\n"


def cases(quick):
    rows = []
    meshes = [2, 4, 8, 16, 32, 64, 128, 256] if not quick else [2, 8, 32]
    for n in meshes:
        rows.append((f"{n} elements, RK4 at the paper's step", {"beam.elements": n}))
        rows.append((f"{n} elements, auto at the paper's step", {"beam.elements": n, "solver.integrator": "auto"}))
    for n, step in [(4, 0.00125), (8, 0.0003125), (16, 7.8125e-05)] if not quick else [(8, 0.0003125)]:
        rows.append((f"{n} elements, RK4 at a stable step {step:g} s", {"beam.elements": n, "solver.step": step}))
    rows += [
        ("EI × 1000, auto", {"beam.bending_stiffness": 1e12, "solver.integrator": "auto"}),
        ("EI × 1000, RK4", {"beam.bending_stiffness": 1e12}),
        ("EI / 100, auto", {"beam.bending_stiffness": 1e7, "solver.integrator": "auto"}),
        ("mass per length × 100", {"beam.mass_per_length": 125000.0, "solver.integrator": "auto"}),
        ("mass per length × 0.01", {"beam.mass_per_length": 12.5, "solver.integrator": "auto"}),
        ("wheel mass 1e-3 of the beam's (30 kg, J scaled)", {"body.mass": 30.0, "body.inertia": 1.35}),
    ]
    speeds = [0.1, 1, 50, 117, 150, 200, 300] if not quick else [0.1, 300]
    for v in speeds:
        rows.append((f"speed {v:g} m/s, 2 elements", {"body.initial_speed": float(v)}))
    for v in ([150, 200, 300] if not quick else [300]):
        rows.append((f"speed {v:g} m/s, 8 elements, auto", {"body.initial_speed": float(v), "beam.elements": 8, "solver.integrator": "auto"}))
    rows += [
        ("step 1e-5 s (much smaller)", {"solver.step": 1e-5}),
        ("step 0.02 s (much larger), RK4", {"solver.step": 0.02}),
        ("step 0.02 s (much larger), HHT", {"solver.step": 0.02, "solver.integrator": "hht"}),
        ("tolerances at round-off: 1e-14 m/s, 1e-12 m", {"solver.velocity_tolerance": 1e-14, "solver.gap_tolerance": 1e-12}),
        ("tolerances at round-off, 50 iterations cap → 5", {"solver.velocity_tolerance": 1e-14, "solver.max_iterations": 5}),
    ]
    return rows


def run_case(guideway, base, changes, workdir):
    scene = workdir / "scene.toml"
    summary = workdir / "summary.json"
    summary.unlink(missing_ok=True)
    text = scene_text(base, changes)
    scene.write_text(text)
    start = time.monotonic()
    try:
        proc = subprocess.run([guideway, "run", str(scene), "--quiet", "--summary", str(summary)],
                              capture_output=True, text=True, timeout=TIME_LIMIT_S)
    except subprocess.TimeoutExpired:
        return {"outcome": "HANG", "detail": f"no answer within {TIME_LIMIT_S} s"}
    elapsed = time.monotonic() - start
    result = {"code": proc.returncode, "elapsed": elapsed}
    if proc.returncode < 0:
        result.update(outcome="CRASH", detail=proc.stderr.strip()[-300:])
        return result
    if summary.exists():
        result["summary"] = json.loads(summary.read_text())
    if proc.returncode == 0:
        s = result["summary"]
        finite = all(isinstance(v, (int, float)) and math.isfinite(v)
                     for v in (s["exit_nominal_speed"], s["max_energy_drift"]) if v is not None)
        result["outcome"] = "exit" if s["exit_time"] is not None and finite else ("NON-FINITE" if not finite else "no exit")
        result["detail"] = ""
    else:
        result["outcome"] = "stopped"
        result["detail"] = proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else ""
    return result


def fmt(value, spec):
    return "" if value is None else format(value, spec)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", default=str(ROOT / "report" / "stress.md"))
    parser.add_argument("--guideway", default=str(ROOT / os.environ.get("CARGO_TARGET_DIR", "target") / "release" / "guideway"))
    args = parser.parse_args(argv)
    base_text = subprocess.run([args.guideway, "scenes", "--show", "lee1994-wheel-10"],
                               capture_output=True, text=True, check=True).stdout
    base = tomllib.loads(base_text)
    lines = [
        "# Stiff and extreme cases",
        "",
        "Each row is the default scene (`lee1994-wheel-10`: the paper's beam, two elements, wheel at 10 m/s,"
        " RK4 at 2.5 ms) with the changes named. Produced by `.venv/bin/python scripts/stress.py`.",
        "",
        "| case | outcome | exit V (m/s) | max energy drift | steps | iterations | solve (s) | diagnostic |",
        "|---|---|---:|---:|---:|---:|---:|---|",
    ]
    bad = 0
    with tempfile.TemporaryDirectory() as tmp:
        for label, changes in cases(args.quick):
            r = run_case(args.guideway, base, changes, pathlib.Path(tmp))
            s = r.get("summary") or {}
            if r["outcome"] in ("HANG", "CRASH", "NON-FINITE"):
                bad += 1
            detail = r.get("detail", "").replace("|", "/")
            row = (f"| {label} | {r['outcome']} | {fmt(s.get('exit_nominal_speed'), '.4f')} | "
                   f"{fmt(s.get('max_energy_drift'), '.2e')} | {s.get('steps', '')} | {s.get('iterations', '')} | "
                   f"{fmt(s.get('wall_time_s'), '.3g')} | {detail} |")
            print(row, flush=True)
            lines.append(row)
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    print(f"wrote {out}; {bad} crashes, hangs or non-finite results")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

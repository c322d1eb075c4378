#!/usr/bin/env python3
"""Instructions per step of the full and the modal structure, by callgrind.

    python3 scripts/modal_cost.py [--elements 32 1024 4096] [--modes 8] [--no-full]

For each mesh, the paper's 10 m/s case under `auto` at 2.5 ms, with the
full beam and with `--modes` modes: `guideway run -q` under
`valgrind --tool=callgrind` to two end times, and the difference of the
instruction counts divided by the difference of the steps (the start-up,
the eigensolver included, cancels). Instruction counts do not depend on the
machine's load, unlike times. Prints a markdown table.
"""

import argparse
import json
import os
import pathlib
import re
import subprocess
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[1]
# Two end times (s): 20 and 100 steps of 2.5 ms, the wheel on the first span.
END_TIMES = (0.05, 0.25)


def scene(guideway, elements, extra, end_time):
    text = subprocess.run([guideway, "scenes", "--show", "lee1994-wheel-10"], check=True,
                          capture_output=True, text=True).stdout
    lines = []
    for line in text.splitlines():
        if line.startswith("elements ="):
            line = f"elements = {elements}"
        if line.startswith("integrator ="):
            line = 'integrator = "auto"'
        lines.append(line)
    # [solver] is the scene's last table.
    return "\n".join(lines) + f"\n{extra}end_time = {end_time}\n"


def instructions(guideway, path, summary):
    """Instructions of one run under callgrind, and its steps."""
    run = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null",
                          guideway, "run", str(path), "-q", "--summary", str(summary)],
                         check=True, capture_output=True, text=True)
    collected = re.search(r"Collected\s*:\s*(\d+)", run.stderr)
    if not collected:
        raise SystemExit(f"no instruction count from callgrind:\n{run.stderr}")
    steps = json.loads(summary.read_text())["steps"]
    return int(collected.group(1)), steps


def per_step(guideway, tmp, elements, name, extra):
    counts = []
    for end_time in END_TIMES:
        path = pathlib.Path(tmp) / f"{name}-{elements}-{end_time}.toml"
        path.write_text(scene(guideway, elements, extra, end_time))
        counts.append(instructions(guideway, path, pathlib.Path(tmp) / "summary.json"))
    (i0, s0), (i1, s1) = counts
    return (i1 - i0) / (s1 - s0), i0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, nargs="+", default=[32, 1024, 4096])
    parser.add_argument("--modes", type=int, default=8)
    parser.add_argument("--no-full", action="store_true", help="measure the modal structure only")
    parser.add_argument("--guideway", default=str(ROOT / os.environ.get("CARGO_TARGET_DIR", "target") / "release" / "guideway"))
    args = parser.parse_args(argv)
    variants = [(f"modal-{args.modes}", f'structure = "modal"\nmodes = {args.modes}\n')]
    if not args.no_full:
        variants.insert(0, ("full", ""))
    names = [name for name, _ in variants]
    print("| elements | " + " | ".join(f"{n}: instructions per step" for n in names)
          + " | " + " | ".join(f"{n}: whole run of 20 steps" for n in names) + " |")
    print("|---:|" + "---:|" * (2 * len(names)))
    with tempfile.TemporaryDirectory() as tmp:
        for elements in args.elements:
            cells = [per_step(args.guideway, tmp, elements, name, extra)
                     for name, extra in variants]
            row = [f"{c[0]:,.0f}" for c in cells] + [f"{c[1]:.3g}" for c in cells]
            print(f"| {elements} | " + " | ".join(row) + " |", flush=True)


if __name__ == "__main__":
    main()

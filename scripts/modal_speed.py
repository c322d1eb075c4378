#!/usr/bin/env python3
"""Paired whole-process runs of the full and the modal structure.

    python3 scripts/modal_speed.py [--rounds 10] [--elements 32 1024]

For each mesh, the paper's 10 m/s case under `auto` at 2.5 ms with the full
beam, 8 modes and 16 modes: `guideway run -q` of each in turn, round after
round (A B C A B C ...), and per round the ratio of each to the full run;
prints the median time of the full runs and the median (min-max) ratios.
"""

import argparse
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
VARIANTS = [("full", ""), ("modal-8", 'structure = "modal"\nmodes = 8\n'),
            ("modal-16", 'structure = "modal"\nmodes = 16\n')]


def scene(guideway, elements, extra):
    text = subprocess.run([guideway, "scenes", "--show", "lee1994-wheel-10"], check=True,
                          capture_output=True, text=True).stdout
    lines = []
    for line in text.splitlines():
        if line.startswith("elements ="):
            line = f"elements = {elements}"
        if line.startswith("integrator ="):
            line = 'integrator = "auto"'
        lines.append(line)
    return "\n".join(lines) + "\n" + extra


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=10)
    parser.add_argument("--elements", type=int, nargs="+", default=[32, 1024])
    parser.add_argument("--guideway", default=str(ROOT / os.environ.get("CARGO_TARGET_DIR", "target") / "release" / "guideway"))
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        for elements in args.elements:
            files = []
            for name, extra in VARIANTS:
                path = pathlib.Path(tmp) / f"{name}-{elements}.toml"
                path.write_text(scene(args.guideway, elements, extra))
                files.append(path)
            times = [[] for _ in files]
            for _ in range(args.rounds):
                for i, path in enumerate(files):
                    start = time.perf_counter()
                    subprocess.run([args.guideway, "run", str(path), "-q"], check=True)
                    times[i].append(time.perf_counter() - start)
            full = times[0]
            cells = [f"{statistics.median(full) * 1e3:.0f} ms"]
            for t in times[1:]:
                ratios = [a / b for a, b in zip(t, full)]
                cells.append(f"{statistics.median(ratios):.2f}× ({min(ratios):.2f}–{max(ratios):.2f})")
            print(f"| {elements} elements, {args.rounds} rounds | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Two builds of guideway on one scene, paired: A B A B ... in one
measurement run, so that the machine's load weighs on both alike.

    python3 scripts/bench_versions.py OLD_BINARY NEW_BINARY [--scene S] [--rounds N]

Each round runs `guideway run S --summary ... --quiet` with each binary (the
order alternates between rounds) and records the whole process's wall time, its CPU time (user + system,
from getrusage: less sensitive to other processes on a loaded machine) and
the run's own `wall_time_s` (scene read to exit, from the summary). It
prints the medians and the per-round ratio old / new as median [min, max].
"""

import argparse
import json
import pathlib
import resource
import statistics
import subprocess
import sys
import tempfile
import time


def cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_once(binary, scene, summary):
    cpu = cpu_seconds()
    started = time.perf_counter()
    subprocess.run([binary, "run", scene, "--summary", str(summary), "--quiet"],
                   check=True, stdout=subprocess.DEVNULL)
    process = time.perf_counter() - started
    cpu = cpu_seconds() - cpu
    return process, cpu, json.loads(summary.read_text())["wall_time_s"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--scene", default="lee1994-wheel-10")
    parser.add_argument("--rounds", type=int, default=50)
    args = parser.parse_args()
    if not 1 <= args.rounds <= 100_000:
        sys.exit(f"--rounds = {args.rounds}: must be 1 to 100000")
    times = {"old": [], "new": []}
    with tempfile.TemporaryDirectory() as tmp:
        summary = pathlib.Path(tmp) / "summary.json"
        for round_ in range(args.rounds):
            order = ["old", "new"] if round_ % 2 == 0 else ["new", "old"]
            for which in order:
                times[which].append(run_once(getattr(args, which), args.scene, summary))
    for k, what in enumerate(["whole process", "process CPU", "run (summary wall_time_s)"]):
        old = [t[k] for t in times["old"]]
        new = [t[k] for t in times["new"]]
        ratios = [o / n for o, n in zip(old, new)]
        print(f"{what}: old {statistics.median(old) * 1e3:.3f} ms, "
              f"new {statistics.median(new) * 1e3:.3f} ms, old/new "
              f"{statistics.median(ratios):.3f} [{min(ratios):.3f}, {max(ratios):.3f}] "
              f"over {args.rounds} paired rounds")


if __name__ == "__main__":
    main()

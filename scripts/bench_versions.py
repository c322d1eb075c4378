#!/usr/bin/env python3
"""Two builds of guideway (or two scenes), paired: A B A B ... in one
measurement run, so that the machine's load weighs on both alike.

    python3 scripts/bench_versions.py OLD_BINARY NEW_BINARY [--scene S]
        [--old-scene S_OLD] [--rounds N] [--in-process]

Each round runs `guideway run S --summary ... --quiet` with each binary (the
order alternates between rounds) and records the whole process's wall time,
its CPU time (user + system, from getrusage: less sensitive to other
processes on a loaded machine) and the run's own `wall_time_s` (scene read
to exit, from the summary). It prints the medians and the per-round ratio
old / new as median [min, max], and a 95 % bootstrap interval of that
median (2,000 resamples, seeded: the same rounds give the same interval).

`--old-scene` runs OLD on another scene than NEW (issue 24's ratio: the
rail scene against the followers scene). `--in-process` takes the two
binaries as builds of `examples/advance_cpu` and records the CPU time of
`Simulation::advance_to` alone (no outputs), issue 29's measure.
"""

import argparse
import json
import pathlib
import random
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time

BOOTSTRAP_RESAMPLES = 2000
# Each run's bound: a benchmark run that takes longer is refused, named.
RUN_TIMEOUT_S = 600


def cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def bounded(command, **kwargs):
    """`command` run to its end within `RUN_TIMEOUT_S`, or the script's exit
    naming it."""
    try:
        return subprocess.run(command, timeout=RUN_TIMEOUT_S, **kwargs)
    except subprocess.TimeoutExpired:
        sys.exit(f"{' '.join(map(str, command))}: longer than {RUN_TIMEOUT_S} s, stopped")


def run_once(binary, scene, summary):
    cpu = cpu_seconds()
    started = time.perf_counter()
    bounded([binary, "run", scene, "--summary", str(summary), "--quiet"],
            check=True, stdout=subprocess.DEVNULL)
    process = time.perf_counter() - started
    cpu = cpu_seconds() - cpu
    return process, cpu, json.loads(summary.read_text())["wall_time_s"]


def advance_once(binary, scene, _summary):
    """advance_cpu's one round: its `Simulation::advance_to` CPU time (s)."""
    run = bounded([binary, scene, "1"], capture_output=True, text=True)
    found = re.search(r"least ([0-9.]+) ms", run.stdout)
    if run.returncode != 0 or not found:
        sys.exit(f"{binary} {scene} 1: exit status {run.returncode}, not an advance_cpu "
                 f"run ({(run.stdout + run.stderr).strip()[:200]!r})")
    return (float(found.group(1)) * 1e-3,)


def bootstrap_interval(ratios):
    """The 95 % bootstrap interval of the ratios' median."""
    rng = random.Random(1)
    medians = sorted(statistics.median(rng.choices(ratios, k=len(ratios)))
                     for _ in range(BOOTSTRAP_RESAMPLES))
    return medians[int(0.025 * BOOTSTRAP_RESAMPLES)], medians[int(0.975 * BOOTSTRAP_RESAMPLES) - 1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--scene", default="lee1994-wheel-10")
    parser.add_argument("--old-scene", help="OLD's scene (default: --scene)")
    parser.add_argument("--rounds", type=int, default=50)
    parser.add_argument("--in-process", action="store_true",
                        help="OLD and NEW are examples/advance_cpu builds")
    args = parser.parse_args()
    if not 1 <= args.rounds <= 100_000:
        sys.exit(f"--rounds = {args.rounds}: must be 1 to 100000")
    scenes = {"old": args.old_scene or args.scene, "new": args.scene}
    for which, scene in scenes.items():
        if args.in_process and not pathlib.Path(scene).is_file():
            sys.exit(f"{which}'s scene {scene}: --in-process needs a scene file")
    once = advance_once if args.in_process else run_once
    times = {"old": [], "new": []}
    with tempfile.TemporaryDirectory() as tmp:
        summary = pathlib.Path(tmp) / "summary.json"
        for round_ in range(args.rounds):
            order = ["old", "new"] if round_ % 2 == 0 else ["new", "old"]
            for which in order:
                times[which].append(once(getattr(args, which), scenes[which], summary))
    measures = ["in process (advance_to)"] if args.in_process else [
        "whole process", "process CPU", "run (summary wall_time_s)"]
    for k, what in enumerate(measures):
        old = [t[k] for t in times["old"]]
        new = [t[k] for t in times["new"]]
        ratios = [o / n for o, n in zip(old, new)]
        low, high = bootstrap_interval(ratios)
        print(f"{what}: old {statistics.median(old) * 1e3:.3f} ms, "
              f"new {statistics.median(new) * 1e3:.3f} ms, old/new "
              f"{statistics.median(ratios):.3f} [{min(ratios):.3f}, {max(ratios):.3f}], "
              f"95 % interval of the median [{low:.3f}, {high:.3f}] "
              f"over {args.rounds} paired rounds")


if __name__ == "__main__":
    main()

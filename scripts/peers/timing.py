"""The peer bench's timing and pairing arithmetic: bounded, exactly timed
runs; the cheapest run at least as accurate; rounds that alternate the
codes; per-round ratios."""

import os
import platform
import resource
import statistics
import subprocess
import threading
import time
from pathlib import Path

# Every run is bounded: a process that takes longer is killed and reported.
RUN_TIMEOUT_S = 120


def run_bounded(cmd, timeout_s, env=None):
    """Run `cmd` to its end, killed after `timeout_s`, and time it exactly.

    `subprocess.run(..., timeout=...)` waits by polling with sleeps that
    double from 0.5 ms, so a process of a few milliseconds was timed at
    the next of 7.5, 15.5, 31.5, 63.5 ms; a blocking wait with a watchdog
    thread returns when the process ends."""
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    expired = threading.Event()

    def kill():
        expired.set()
        proc.kill()

    watchdog = threading.Timer(timeout_s, kill)
    watchdog.start()
    try:
        code = proc.wait()
    finally:
        watchdog.cancel()
    if expired.is_set():
        raise subprocess.TimeoutExpired(cmd, timeout_s)
    if code != 0:
        raise subprocess.CalledProcessError(code, cmd)


class Config:
    """One way of running one code: a command, the figure its result file
    gives (`parse(text)` -> (value, solve time)) and its times. `env`: the
    process's environment (None: the bench's)."""

    def __init__(self, code, label, cmd, result_file, elements, step, family="", parse=None,
                 env=None):
        self.code, self.label, self.cmd = code, label, cmd
        self.result_file, self.elements, self.step = result_file, elements, step
        # What the configuration is a point of (for the plot's lines).
        self.family = family
        self.parse, self.env = parse, env
        self.process = []
        self.cpu = []
        self.solve = []
        self.value = None

    @property
    def exit_speed(self):
        return self.value

    def run(self):
        if self.result_file is not None and self.result_file.exists():
            self.result_file.unlink()
        usage = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        run_bounded(self.cmd, RUN_TIMEOUT_S, self.env)
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        self.cpu.append(after.ru_utime + after.ru_stime - usage.ru_utime - usage.ru_stime)
        if self.result_file is None:
            return wall, None
        try:
            self.value, solve = self.parse(self.result_file.read_text())
        except ValueError as e:
            raise RuntimeError(f"{self.label}: {e}") from e
        return wall, solve

    def median_process(self):
        return statistics.median(self.process)

    def median_solve(self):
        return statistics.median(self.solve)


def cheapest_as_accurate(target_error, candidates, error, cost, resolution=0.0):
    """The candidate of least `cost` whose `error` is at most
    `target_error` (+ `resolution`, the error the reference cannot
    resolve), or None."""
    accurate = [c for c in candidates if error(c) <= target_error + resolution]
    return min(accurate, key=cost) if accurate else None


def pairings(peer, guideway, error, cost, resolution=0.0):
    """For each peer run (cheapest first), the cheapest guideway run at
    least as accurate (None where there is none): [(peer, guideway)]."""
    return [(p, cheapest_as_accurate(error(p), guideway, error, cost, resolution))
            for p in sorted(peer, key=cost)]


def alternate(a, b):
    """The runs of a round: every item of `a` and `b` once, those of `b`
    spread evenly among those of `a` (a b a a b ... when `a` is longer)."""
    order, taken = [], 0
    for i, item in enumerate(a):
        order.append(item)
        while taken < len(b) and (taken + 1) * len(a) <= (i + 1) * len(b) + len(a) // 2:
            order.append(b[taken])
            taken += 1
    return order + list(b[taken:])


def ratios(numerators, denominators):
    """Per-round ratios."""
    return [n / max(d, 1e-9) for n, d in zip(numerators, denominators)]


def spread(values):
    return statistics.median(values), min(values), max(values)


def machine():
    cpu = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{os.cpu_count()} cores, {cpu}, {platform.system()} {platform.release()}"

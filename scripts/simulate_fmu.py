#!/usr/bin/env python3
"""Simulate a guideway FMU with fmpy: print a summary, write a plot.

    .venv/bin/python scripts/simulate_fmu.py out/fmu/lee1994_wheel_10.fmu \
        [--plot out/fmu/lee1994_wheel_10.png] [--interval 0.0025] [--set NAME=VALUE ...]

Runs the FMU's default experiment to its stop time. Leaving the beam is an
event, not the end of the run: the exit shows as the first output where
`contact.on_beam` is 0 (the exact time is logged under `logEvents`).
"""

import argparse
import sys

import numpy as np
from fmpy import read_model_description, simulate_fmu


def parse_value(text):
    try:
        return int(text)
    except ValueError:
        return float(text)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("fmu")
    p.add_argument("--plot", help="write a PNG of speed, deflection and contact force")
    p.add_argument("--interval", type=float, help="output interval (default: stepSize)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="start value of a parameter or input")
    args = p.parse_args(argv)

    md = read_model_description(args.fmu)
    exp = md.defaultExperiment
    interval = args.interval or float(exp.stepSize)
    start = {}
    for item in args.set:
        name, _, value = item.partition("=")
        start[name] = parse_value(value)
    result = simulate_fmu(args.fmu, output_interval=interval, start_values=start)
    names = result.dtype.names
    body = next(v.name.split(".")[0] for v in md.modelVariables
                if v.name.endswith(".initial_speed"))
    t = result["time"]
    stop = float(exp.stopTime)
    off = np.flatnonzero(result["contact.on_beam"] == 0) if "contact.on_beam" in names else []
    exited = len(off) > 0

    print(f"model        {md.modelName} (GUID {md.guid})")
    print(f"run          0 .. {t[-1]:.6g} s, {len(t) - 1} communication steps of {interval:g} s")
    if exited:
        k = off[0]
        print(f"exit         contact.on_beam = 0 from t = {t[k]:.9g} s (the first output after "
              f"the exit), speed {result[body + '.vx'][k]:.6g} m/s; run on to {stop:g} s")
    else:
        print(f"exit         none before the stop time {stop:g} s")
    v = result[body + ".nominal_speed"]
    print(f"nominal V    {v[0]:.6g} -> {v[-1]:.6g} m/s at the end, peak {v.max():.6g} m/s")
    print(f"centre vx    {result[body + '.vx'][0]:.6g} -> {result[body + '.vx'][-1]:.6g} m/s")
    for name in names:
        if name.startswith("sensor.") and name.endswith(".deflection"):
            d = result[name]
            k = int(np.argmax(np.abs(d)))
            print(f"{name}  peak {d[k]:.6g} m at t = {t[k]:.6g} s")
    n = result["contact.normal_force"]
    print(f"normal force {n.min():.6g} .. {n.max():.6g} N")
    e = result["energy.balance"]
    drift = np.abs(e - e[0]) / abs(e[0])
    print(f"energy       balance drift {drift.max():.3e} at most (relative to E(0)), {(e[-1] - e[0]) / abs(e[0]):.3e} at the end")
    print(f"iterations   {int(result['solver.iterations'].sum())} contact iterations in total")

    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        panels = [(body + ".nominal_speed", "nominal speed (m/s)")]
        panels += [(n_, n_ + " (m)") for n_ in names if n_.endswith(".deflection")]
        panels += [("contact.normal_force", "normal force (N)")]
        fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(8, 2.4 * len(panels)))
        for ax, (name, label) in zip(np.atleast_1d(axes), panels):
            ax.plot(t, result[name])
            ax.set_ylabel(label)
            ax.grid(True)
        np.atleast_1d(axes)[-1].set_xlabel("time (s)")
        fig.suptitle(f"{md.modelName} (FMU, fmpy)")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=100)
        print(f"plot         {args.plot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

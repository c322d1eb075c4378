#!/usr/bin/env python3
"""Run a guideway FMU with fmpy and plot the midspan deflection and the
wheel's nominal speed.

    .venv/bin/python scripts/examples/run_and_plot.py lee1994_wheel_10.fmu run.png

fmpy runs the FMU's default experiment to its stop time: the wheel crosses
the beam, leaves it (an event: `contact.on_beam` turns 0) and rolls on over
the ground beyond, while the beam vibrates freely.
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from fmpy import read_model_description, simulate_fmu


def main(fmu, png):
    md = read_model_description(fmu)
    body = next(v.name.split(".")[0] for v in md.modelVariables if v.name.endswith(".initial_speed"))
    speed = f"{body}.nominal_speed"
    result = simulate_fmu(fmu, output=["sensor.midspan.deflection", speed, "contact.on_beam"])

    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(8, 5))
    top.plot(result["time"], result["sensor.midspan.deflection"] * 1e3)
    top.set_ylabel("midspan deflection (mm)")
    off = result["time"][result["contact.on_beam"] == 0]
    if len(off):
        for ax in (top, bottom):
            ax.axvline(off[0], color="k", linestyle=":", label="exit")
        top.legend()
    bottom.plot(result["time"], result[speed])
    bottom.set_ylabel("nominal speed (m/s)")
    bottom.set_xlabel("time (s)")
    for ax in (top, bottom):
        ax.grid(True)
    fig.suptitle(md.modelName)
    fig.savefig(png, dpi=100)
    print(f"{md.modelName}: {len(result)} samples up to t = {result['time'][-1]:.4f} s, "
          f"peak deflection {result['sensor.midspan.deflection'].min() * 1e3:.2f} mm -> {png}")
    return result


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])

#!/usr/bin/env python3
"""Change an FMU's parameters with start values: the same wheel FMU at
several speeds and on a stiffer beam, without exporting a new FMU.

    .venv/bin/python scripts/examples/start_values.py lee1994_wheel_10.fmu

Every parameter of the scene is a variable of the FMU (`beam.length`,
`beam.bending_stiffness`, `beam.elements`, `wheel.mass`,
`wheel.initial_speed`, `solver.step`, ...; the FMU's
documentation/index.html lists them). A bad value is refused with a message
naming the variable and the rule.
"""

import sys

from fmpy import simulate_fmu


def peak_deflection(fmu, **start_values):
    """Largest downward midspan deflection (m) while the wheel is on the beam
    and exit time (s, to the output interval) of one run."""
    # keyword arguments cannot contain dots: wheel__mass -> wheel.mass
    start = {k.replace("__", "."): v for k, v in start_values.items()}
    result = simulate_fmu(fmu, start_values=start,
                          output=["sensor.midspan.deflection", "contact.on_beam"])
    # the first output after the contact left the beam (the run goes on)
    on = result["contact.on_beam"] == 1
    exit_time = result["time"][~on][0] if not on.all() else float("nan")
    return -result["sensor.midspan.deflection"][on].min(), exit_time


def main(fmu):
    rows = []
    for speed in [10.0, 50.0, 100.0]:
        for ei in [1e9, 2e9]:
            peak, exit_time = peak_deflection(fmu, wheel__initial_speed=speed, beam__bending_stiffness=ei)
            rows.append((speed, ei, peak, exit_time))
            print(f"V0 = {speed:5.1f} m/s  EI = {ei:.0e} N m2: peak deflection {peak * 1e3:7.2f} mm, "
                  f"exit at {exit_time:.4f} s")
    return rows


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])

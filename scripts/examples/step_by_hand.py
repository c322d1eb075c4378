#!/usr/bin/env python3
"""Step a guideway FMU by hand with fmpy's FMU2Slave and feed it a
time-varying traction force through the input `wheel.force_x`.

    .venv/bin/python scripts/examples/step_by_hand.py lee1994_wheel_10.fmu

The traction force ramps up to 60 kN over the first second and is then held;
between two communication steps the master sets the input, does the step and
reads the outputs. Leaving the beam is an event, not the end of the FMU's
run (it would go on over the ground beyond): this script stops at the first
communication point where `contact.on_beam` is 0.
"""

import shutil
import sys

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave


def traction(t):
    """Traction force (N) on the wheel's centre at time t (s)."""
    return 60e3 * min(t / 1.0, 1.0)


def main(fmu, step=0.01):
    md = read_model_description(fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzipdir = extract(fmu)
    slave = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="by-hand")
    rows = []
    try:
        slave.instantiate()
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        t = 0.0
        on_beam = 1
        while on_beam:
            slave.setReal([vr["wheel.force_x"]], [traction(t)])
            slave.doStep(currentCommunicationPoint=t, communicationStepSize=step)
            t += step
            x, v = slave.getReal([vr["wheel.x"], vr["wheel.nominal_speed"]])
            rows.append((t, traction(t), x, v))
            on_beam = slave.getInteger([vr["contact.on_beam"]])[0]
        slave.terminate()
    finally:
        slave.freeInstance()
        shutil.rmtree(unzipdir, ignore_errors=True)
    t, f, x, v = rows[-1]
    print(f"left the beam by t = {t:.4f} s with V = {v:.3f} m/s "
          f"(traction {f / 1e3:.0f} kN at the end, {len(rows)} communication steps)")
    return rows


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])

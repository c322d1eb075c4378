"""Running an SSP in OMSimulator's command line, for the SSP tests.

OMSimulator is not on any registry this project installs from (PyPI's
`OMSimulator` is a 9 KB source package that downloads its binaries at
install time), so these checks run only where someone built it and set
`OMSIMULATOR` or put it on the PATH (docs/fmu.md, "OMSimulator").
"""

import csv
import os
import shutil
import subprocess


def omsimulator():
    """OMSimulator's command, or None."""
    return os.environ.get("OMSIMULATOR") or shutil.which("OMSimulator")


def omsimulator_run(ssp, cwd, stop):
    """Run `ssp` to `stop` (OMSimulator's command line sets its own stop
    time, default 1 s, over the SSD's) and return, per communication
    point, the vehicle's `glider.vx` and guideway's `wheel.force_x` after
    the transfer (OMSimulator writes a row before and one after it). The
    run must load and finish with no error and without OMSimulator's
    "wrong/deprecated content" warning."""
    r = subprocess.run([omsimulator(), str(ssp), "--resultFile=r.csv", f"--stopTime={stop!r}"],
                       capture_output=True, text=True, cwd=cwd, timeout=600)
    log = r.stdout + r.stderr
    if r.returncode != 0 or "0 errors" not in log or "error:" in log:
        raise RuntimeError(f"OMSimulator exit {r.returncode}: {log}")
    assert "deprecated" not in log, log
    with open(os.path.join(cwd, "r.csv")) as f:
        rows = list(csv.reader(f, skipinitialspace=True))
    vx = next(i for i, n in enumerate(rows[0]) if n.endswith(".vehicle.glider.vx"))
    fx = next(i for i, n in enumerate(rows[0]) if n.endswith(".guideway.wheel.force_x"))
    return {float(row[0]): (float(row[vx]), float(row[fx])) for row in rows[1:]}

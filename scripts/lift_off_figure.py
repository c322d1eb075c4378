"""Figure of a lift-off and landing for docs/lift-off.md ("Lift-off and landing"):
the paper's wheel at 150 m/s on a 16-element beam (Δt = 1e-4 s, `auto`
picks RK4) leaves the beam's surface near its end, flies and lands on the
rigid run-off. Runs `guideway run` and draws the wheel's height, the gap
and the normal force against the wheel's abscissa, flights shaded.

    .venv/bin/python scripts/lift_off_figure.py [target/release/guideway] [docs/lift_off.png]
"""
import subprocess
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

SCENE = """
name = "lift-off"
gravity = 0.0
[beam]
length = 24.0
mass_per_length = 1250.0
bending_stiffness = 1e9
surface_offset = 0.6
elements = 16
[track]
run_off = 30.0
[body]
name = "wheel"
kind = "wheel"
mass = 3000.0
inertia = 135.0
radius = 0.3
initial_speed = 150.0
force_y = -6e5
[solver]
step = 1e-4
integrator = "auto"
end_time = 0.22
"""


def main(binary="target/release/guideway", out="docs/lift_off.png"):
    with tempfile.TemporaryDirectory() as tmp:
        scene, csv = Path(tmp) / "scene.toml", Path(tmp) / "run.csv"
        scene.write_text(SCENE)
        subprocess.run([binary, "run", str(scene), "--out", str(csv), "-q"], check=True)
        data = np.genfromtxt(csv, delimiter=",", names=True)
    x = data["wheelx"]
    height = data["wheely"] - 0.9  # centre above its height on the undeformed track
    closed = data["contactstate"]
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 8))
    series = [(height * 1e3, "wheel centre height (mm)"),
              (data["contactgap"] * 1e3, "gap g (mm)"),
              (data["contactnormal_force"] / 1e3, "normal force (kN)")]
    for ax, (y, label) in zip(axes, series):
        ax.plot(x, y, lw=1.5)
        ax.fill_between(x, 0, 1, where=closed == 0, color="0.85",
                        transform=ax.get_xaxis_transform(), label="open (in flight)")
        ax.axvline(24.0, color="k", lw=0.8, ls=":")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(loc="lower left")
    axes[0].set_title("Paper's wheel at 150 m/s, 16 elements: lift-off, flight, landing")
    axes[-1].set_xlabel("wheel abscissa x (m); beam end at 24 m")
    fig.tight_layout()
    fig.savefig(out, dpi=100)


if __name__ == "__main__":
    main(*sys.argv[1:])

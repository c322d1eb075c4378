"""Figure of the Timoshenko paradox for docs/vehicles.md ("Prescribed speed and the
Timoshenko paradox"): the paper's glider (600 kN on 3000 kg) is held at
30 m/s over the paper's beam and on along a rigid run-off. Runs `guideway
run` and draws, against time, the work of the tractive force that holds
the speed and the beam's energy (kinetic + strain): after the exit the
beam keeps what the horizontal force put in.

    .venv/bin/python scripts/timoshenko_figure.py [target/release/guideway] [docs/timoshenko.png]
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
name = "timoshenko"
gravity = 0.0
[beam]
length = 24.0
mass_per_length = 1250.0
bending_stiffness = 1e9
surface_offset = 0.6
elements = 2
[track]
run_off = 30.0
[body]
name = "glider"
kind = "glider"
mass = 3000.0
initial_speed = 30.0
prescribed_speed = 30.0
force_y = -6e5
[solver]
step = 0.000625
velocity_tolerance = 1e-11
gap_tolerance = 1e-11
end_time = 1.4
"""


def main(binary="target/release/guideway", out="docs/timoshenko.png"):
    with tempfile.TemporaryDirectory() as tmp:
        scene, csv = Path(tmp) / "scene.toml", Path(tmp) / "run.csv"
        scene.write_text(SCENE)
        subprocess.run([binary, "run", str(scene), "--out", str(csv), "-q"], check=True)
        data = np.genfromtxt(csv, delimiter=",", names=True)
    t = data["time"]
    beam = data["energybeam_kinetic"] + data["energybeam_strain"]
    tractive = data["energytractive_work"]
    exit_time = 24.0 / 30.0
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(t, tractive / 1e3, lw=2, label="work of the tractive force")
    ax.plot(t, beam / 1e3, lw=1.2, label="beam energy (kinetic + strain)")
    ax.axvline(exit_time, color="k", lw=0.8, ls=":")
    ax.annotate("exit", (exit_time, 0), xytext=(4, 4), textcoords="offset points")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (kJ)")
    ax.set_title("Glider held at 30 m/s: the energy left in the beam is the tractive work")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", frameon=True)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    after = t > exit_time + 0.05
    print(f"after the exit: tractive work {tractive[after].mean():.1f} J, "
          f"beam energy {beam[after].mean():.1f} J (means over t > {exit_time + 0.05:.2f} s)")


if __name__ == "__main__":
    main(*sys.argv[1:])

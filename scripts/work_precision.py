#!/usr/bin/env python3
"""Error against run time: run `guideway work-precision` and plot it.

    .venv/bin/python scripts/work_precision.py [--quick] [--repeats 5] [--csv FILE] [--modal-only]

Writes report/work_precision.csv (from the CLI, unless --csv names an
existing file to plot) and report/work_precision.png: for each case (rows)
and error measure (columns), error against the median wall time, log-log,
one curve per scheme over the step sweep; the paper's own setting (RK4 at
the built-in step and tolerance) is marked with a star, runs that stopped
(beyond RK4's stability limit, lift-off) are left out. With --modal-only
only the modal structures are measured again, and their rows replace the
`modal-*` rows of the existing CSV.
"""

import argparse
import csv
import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
MEASURES = [
    ("exit_speed_error", "exit speed error (m/s)"),
    ("rms_deflection_error", "RMS midspan deflection error / static"),
    ("max_energy_drift", "max relative energy drift"),
]


def read_points(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def merge_modal(csv_path, modal_path):
    """Replace the `modal-*` rows of `csv_path` by those of `modal_path`."""
    kept = [p for p in read_points(csv_path) if not p["scheme"].startswith("modal-")]
    modal = read_points(modal_path)
    with open(csv_path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(modal[0].keys()), lineterminator="\n")
        writer.writeheader()
        writer.writerows(kept + modal)
    modal_path.unlink()


def plot(points, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cases = list(dict.fromkeys(p["case"] for p in points))
    schemes = list(dict.fromkeys(p["scheme"] for p in points))
    fig, axes = plt.subplots(len(cases), len(MEASURES), figsize=(14, 3.6 * len(cases)), squeeze=False)
    for row, case in enumerate(cases):
        for col, (key, label) in enumerate(MEASURES):
            ax = axes[row][col]
            for scheme in schemes:
                pts = [p for p in points if p["case"] == case and p["scheme"] == scheme
                       and not p["failure"] and float(p[key]) > 0]
                # The step sweep is the curve; tolerance variants are dots.
                paper_tol = min((float(p["velocity_tolerance"]) for p in pts), default=None,
                                key=lambda t: abs(t - 1e-7))
                sweep = sorted((p for p in pts if float(p["velocity_tolerance"]) == paper_tol),
                               key=lambda p: -float(p["step"]))
                others = [p for p in pts if p not in sweep]
                line, = ax.loglog([float(p["wall_time_s"]) for p in sweep],
                                  [float(p[key]) for p in sweep], "o-", label=scheme, markersize=4)
                if others:
                    ax.loglog([float(p["wall_time_s"]) for p in others],
                              [float(p[key]) for p in others], "x", color=line.get_color())
                for p in pts:
                    if p["paper_setting"] == "true":
                        ax.loglog(float(p["wall_time_s"]), float(p[key]), "*", color="k",
                                  markersize=14, label="paper's setting (RK4, Δt 2.5 ms)")
            ax.set_title(f"{case}", fontsize=10)
            ax.set_xlabel("wall time (s, median)")
            ax.set_ylabel(label)
            ax.grid(True, which="both", alpha=0.3)
            if row == 0 and col == 0:
                ax.legend(fontsize=8)
    fig.suptitle("guideway: error against run time (x: tolerance variants at the paper's step)")
    fig.tight_layout()
    fig.savefig(out, dpi=90)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="short sweep, coarse reference")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--csv", help="plot this CSV instead of measuring")
    parser.add_argument("--modal-only", action="store_true",
                        help="measure the modal curves only, replacing them in the existing CSV")
    parser.add_argument("--out-dir", default=str(ROOT / "report"))
    parser.add_argument("--guideway", default=str(ROOT / os.environ.get("CARGO_TARGET_DIR", "target") / "release" / "guideway"))
    args = parser.parse_args(argv)

    out_dir = pathlib.Path(args.out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    csv_path = pathlib.Path(args.csv) if args.csv else out_dir / "work_precision.csv"
    if not args.csv:
        target = csv_path.with_suffix(".modal.csv") if args.modal_only else csv_path
        command = [args.guideway, "work-precision", "-o", str(target), "--repeats", str(args.repeats)]
        if args.quick:
            command.append("--quick")
        if args.modal_only:
            command.append("--modal-only")
        subprocess.run(command, check=True)
        if args.modal_only:
            merge_modal(csv_path, target)
    points = read_points(csv_path)
    png = out_dir / "work_precision.png"
    plot(points, png)
    print(f"wrote {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

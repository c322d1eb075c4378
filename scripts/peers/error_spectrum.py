"""Where the sprung-mass case's error comes from: the error history of
each run (guideway's follower, and OpenSees' loop where its venv exists)
against the modal reference, split by frequency into the bands of the
beam's symmetric modes 1 and 3 (the midspan sees no antisymmetric mode)
and the rest, each band's largest value over the passage.

    .venv/bin/python scripts/peers/error_spectrum.py [--elements 8 64]
        [--steps 1e-3 5e-4 2.5e-4] [--opensees] [--guideway BIN]

A band's part that shrinks fourfold a halving of the step is the time
integrator's (the trapezoidal rule's period error, second order); one
that does not is the mesh's or the model's."""

import argparse
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from peers import opensees_bench as bench  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
CASE = "sprung_mass"


def first_frequency(case):
    """f1 of the simply supported beam (Hz), the closed form."""
    omega = (math.pi / case["length"]) ** 2 * math.sqrt(
        case["bending_stiffness"] / case["mass_per_length"])
    return omega / (2.0 * math.pi)


def band_parts(times, error, f1):
    """Largest |error| over time in each band: [0, 4 f1) (mode 1),
    [4 f1, 16 f1) (mode 3), [16 f1, ∞) (the rest), by FFT on the run's
    own uniform grid."""
    step = times[1] - times[0]
    spectrum = np.fft.rfft(error)
    freqs = np.fft.rfftfreq(len(error), step)
    parts = []
    for low, high in ((0.0, 4.0 * f1), (4.0 * f1, 16.0 * f1), (16.0 * f1, np.inf)):
        kept = np.where((freqs >= low) & (freqs < high), spectrum, 0.0)
        parts.append(float(np.abs(np.fft.irfft(kept, len(error))).max()))
    return parts


def guideway_history(binary, tmp, elements, step):
    label = f"g-{elements}-{step:.3g}"
    scene, out = tmp / f"{label}.toml", tmp / f"{label}.csv"
    scene.write_text(bench.scene_text(CASE, elements, step))
    subprocess.run([str(binary), "run", str(scene), "-q", "-o", str(out)], check=True)
    config = type("Run", (), {"code": "guideway", "history_cmd": [str(out)]})
    return bench.history(config)


def opensees_history(python, tmp, elements, step):
    config = bench.make_opensees(python, tmp, CASE, elements, step)
    subprocess.run(config.history_cmd, check=True, env=config.env,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return bench.history(config)


def rows(reference, f1, histories):
    """(code, elements, step, largest error, band parts), relative to the
    reference's peak over the passage."""
    out = []
    for (code, elements, step), (times, values) in histories:
        times, values = np.asarray(times), np.asarray(values)
        keep = times <= reference.until * (1.0 + 1e-12)
        times, values = times[keep], values[keep]
        reference_values = reference.at(times)
        error = (values - reference_values) / np.abs(reference_values).max()
        out.append((code, elements, step, float(np.abs(error).max()), band_parts(times, error, f1)))
    return out


def table(found, f1):
    lines = [f"f1 = {f1:.2f} Hz (closed form); error relative to the reference's peak", "",
             "| code | elements | step (s) | largest error | mode 1 band | mode 3 band | above |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for code, elements, step, largest, parts in found:
        cells = " | ".join(f"{p:.2e}" for p in parts)
        lines.append(f"| {code} | {elements} | {step:g} | {largest:.2e} | {cells} |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--elements", type=int, nargs="+", default=[8, 64])
    parser.add_argument("--steps", type=float, nargs="+", default=[1e-3, 5e-4, 2.5e-4])
    parser.add_argument("--opensees", action="store_true",
                        help="also OpenSees' loop (needs target/peers-venv, see bench_peers.py)")
    parser.add_argument("--guideway", default=str(ROOT / "target" / "release" / "guideway"))
    args = parser.parse_args(argv)
    case = bench.CASES[CASE]
    reference, f1 = bench.Reference(CASE), first_frequency(case)
    python = ROOT / "target" / "peers-venv" / "bin" / "python"
    if args.opensees and not python.exists():
        parser.error(f"--opensees needs {python}: run scripts/bench_peers.py once")
    histories = []
    with tempfile.TemporaryDirectory() as tmp:
        for elements in args.elements:
            for step in args.steps:
                histories.append((("guideway", elements, step),
                                  guideway_history(args.guideway, Path(tmp), elements, step)))
                if args.opensees:
                    histories.append((("opensees", elements, step),
                                      opensees_history(python, Path(tmp), elements, step)))
        print(table(rows(reference, f1, histories), f1))


if __name__ == "__main__":
    main()

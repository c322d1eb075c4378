#!/usr/bin/env python3
"""The HSLM speed sweep of `guideway sweep` spread over a Dask cluster: one
task per train, each running `guideway sweep SCENE --trains HSLM-Ak
--threads 1` on a worker; the parts are joined into the same envelope CSV
a single machine writes, and plotted.

    .venv/bin/python scripts/hslm_sweep.py scenes/bridge25_hslm.toml \
        [--speeds 100:400:5] [--unit km/h] [--trains hslm | HSLM-A1,HSLM-A7] \
        [--track ballasted|slab] [--workers 2 | --scheduler tcp://HOST:8786] \
        [--guideway target/release/guideway] [--out hslm_sweep.csv] [--plot hslm_sweep.png]

The guideway binary travels to each worker once, in a worker plugin, and
the scene file's text with each task: neither needs to be on the workers'
disks (the workers must run the binary: same OS and architecture). A task
per train, not per speed: a run takes milliseconds, and the speeds of one
train are then the very numbers `guideway sweep` computes from the range.
"""

import argparse
import hashlib
import io
import os
import stat
import subprocess
import sys
import tempfile

import pandas as pd
from distributed.diagnostics.plugin import WorkerPlugin

HSLM = [f"HSLM-A{k}" for k in range(1, 11)]
# EN 1990 A2.4.4.2.1(4): deck acceleration limits (m/s^2).
LIMITS = {"ballasted": 3.5, "slab": 5.0}


class GuidewayBinary(WorkerPlugin):
    """The guideway binary's bytes, written once into each worker's local
    directory and made executable."""

    def __init__(self, path):
        with open(path, "rb") as f:
            self.binary = f.read()
        self.name = "guideway-binary-" + hashlib.sha256(self.binary).hexdigest()[:16]

    def setup(self, worker=None):
        root = worker.local_directory if worker is not None else None
        directory = tempfile.mkdtemp(prefix="guideway-bin-", dir=root)
        self.path = os.path.join(directory, "guideway")
        with open(self.path, "wb") as f:
            f.write(self.binary)
        os.chmod(self.path, os.stat(self.path).st_mode | stat.S_IXUSR)


def run_train(plugin_name, scene_text, train, speeds, unit):
    """On a worker: one train at every speed; the envelope CSV text and the
    binary's path (which shows where it was extracted)."""
    from distributed import get_worker

    binary = get_worker().plugins[plugin_name].path
    with tempfile.TemporaryDirectory(prefix="guideway-sweep-") as work:
        scene = os.path.join(work, "scene.toml")
        out = os.path.join(work, "part.csv")
        with open(scene, "w") as f:
            f.write(scene_text)
        done = subprocess.run(
            [binary, "sweep", scene, "--speeds", speeds, "--unit", unit, "--trains", train,
             "--threads", "1", "--out", out],
            capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"guideway sweep --trains {train}: {done.stderr.strip()}")
        with open(out) as f:
            return f.read(), binary


def sweep(client, binary, scene_file, trains, speeds, unit):
    """Every train at every speed on the cluster: the envelope table (rows
    train by train, speed by speed, as `guideway sweep` orders them) and the
    binary paths the tasks used."""
    plugin = GuidewayBinary(binary)
    client.register_plugin(plugin)
    with open(scene_file) as f:
        scene_text = f.read()
    futures = [client.submit(run_train, plugin.name, scene_text, t, speeds, unit, pure=False)
               for t in trains]
    parts = client.gather(futures)
    table = pd.concat([pd.read_csv(io.StringIO(text)) for text, _ in parts], ignore_index=True)
    return table, {path for _, path in parts}


def plot(table, unit, track, path):
    """Peak deck acceleration and DAF against speed, one curve per train, the
    deck acceleration limit of `track` drawn."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    speed = table.columns[1]
    fig, (acc, daf) = plt.subplots(2, 1, figsize=(10, 9), sharex=True)
    for train, rows in table.groupby("train", sort=False):
        acc.plot(rows[speed], rows["peak_acceleration_m_s2"], label=train)
        daf.plot(rows[speed], rows["daf"], label=train)
    limit = LIMITS[track]
    acc.axhline(limit, color="black", linestyle="--", label=f"EN 1990 A2 limit, {track} {limit} m/s²")
    acc.set_ylabel("peak deck acceleration (m/s²)")
    daf.set_ylabel("dynamic amplification (deflection)")
    daf.set_xlabel(f"speed ({unit})")
    acc.legend(loc="upper left", fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("scene", help="scene file whose [body] is a moving force")
    p.add_argument("--speeds", default="100:400:5", help="START:STOP:STEP, as guideway sweep")
    p.add_argument("--unit", default="km/h", choices=["m/s", "km/h"])
    p.add_argument("--trains", default="hslm", help="hslm, or a comma list of HSLM-A1 ... HSLM-A10")
    p.add_argument("--track", default="ballasted", choices=sorted(LIMITS))
    p.add_argument("--guideway", default=os.path.join("target", "release", "guideway"),
                   help="the guideway binary shipped to the workers")
    p.add_argument("--workers", type=int, default=2, help="local cluster size without --scheduler")
    p.add_argument("--scheduler", help="address of a running Dask scheduler")
    p.add_argument("--out", default="hslm_sweep.csv")
    p.add_argument("--plot")
    args = p.parse_args(argv)
    if args.trains.lower() == "hslm":
        args.trains = HSLM
    else:
        args.trains = [t.strip() for t in args.trains.split(",")]
        bad = [t for t in args.trains if t.upper() not in HSLM]
        if bad:
            p.error(f"--trains: {bad[0]!r} is not a train; want hslm or HSLM-A1 ... HSLM-A10")
    if args.workers < 1:
        p.error(f"--workers {args.workers}: want at least 1")
    if not os.path.isfile(args.guideway):
        p.error(f"--guideway {args.guideway}: no such file (cargo build --release)")
    return args


def main(argv=None):
    from distributed import Client, LocalCluster

    args = parse_args(argv)
    if args.scheduler:
        client, cluster = Client(args.scheduler), None
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                               dashboard_address=":0")
        client = Client(cluster)
    try:
        table, _ = sweep(client, args.guideway, args.scene, args.trains, args.speeds, args.unit)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    table.to_csv(args.out, index=False)
    worst = table.loc[table["peak_acceleration_m_s2"].idxmax()]
    limit = LIMITS[args.track]
    above = int((table["peak_acceleration_m_s2"] > limit).sum())
    print(f"{len(table)} runs; envelope: {args.out}")
    print(f"largest deck acceleration {worst['peak_acceleration_m_s2']:.3f} m/s² "
          f"({worst['train']} at {worst[table.columns[1]]} {args.unit}); "
          f"{above} runs above the {args.track} limit of {limit} m/s²")
    if args.plot:
        plot(table, args.unit, args.track, args.plot)
        print(f"plot: {args.plot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

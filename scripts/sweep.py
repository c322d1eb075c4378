#!/usr/bin/env python3
"""Parameter sweep of a guideway wheel FMU on Dask: initial speed x bending
stiffness x wheel mass, one table and a plot of the dynamic amplification.

    .venv/bin/python scripts/sweep.py dist/0.3.0/lee1994_wheel_10.fmu \
        [--speeds 5:300:5] [--stiffness 5e8,1e9,2e9] [--mass 1500,3000,6000] \
        [--workers 2 | --scheduler tcp://HOST:8786] \
        [--out sweep.csv] [--plot sweep.png]

Each run sets `wheel.initial_speed`, `beam.bending_stiffness` and
`wheel.mass` as start values, steps the FMU with communication steps of its
`solver.step` until the wheel leaves the beam, and records the peak
|midspan deflection| over the static deflection P L^3 / (48 EI) of the
span. A wheel that lifts off flies and lands within the run (an event, not
a failure). Runs that stop early (a step that fails: fmi2Discard, or
fmi2Error once no smaller step gets further; state rolled back) are kept in
the table with their status, message and the time reached.

Without --scheduler a LocalCluster of --workers processes (one thread each)
is started. With --scheduler the runs go to that cluster; the FMU file is
shipped to the workers in a worker plugin, so it need not exist on their
machines. Each worker extracts the FMU once and reuses one instance per
thread (fmi2Reset between runs).
"""

import argparse
import hashlib
import math
import os
import sys
import tempfile
import threading
import time
import zipfile
from ctypes import byref

import pandas as pd
from distributed.diagnostics.plugin import WorkerPlugin

BODY = "wheel"
SENSOR = "sensor.midspan.deflection"


# ---------------------------------------------------------------- the grid

def parse_range(text):
    """`start:stop:step` (inclusive) or `a,b,c` -> list of floats."""
    if ":" in text:
        start, stop, step = (float(x) for x in text.split(":"))
        if step <= 0 or stop < start:
            raise argparse.ArgumentTypeError(f"{text!r}: want start:stop:step with step > 0, stop >= start")
        n = int(math.floor((stop - start) / step + 1e-9)) + 1
        return [start + i * step for i in range(n)]
    try:
        return [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: want numbers separated by commas, or start:stop:step")


def grid(speeds, stiffnesses, masses):
    """Every combination, as dicts of FMU start values."""
    return [
        {f"{BODY}.initial_speed": v, "beam.bending_stiffness": ei, f"{BODY}.mass": m}
        for ei in stiffnesses for m in masses for v in speeds
    ]


# ------------------------------------------------- one FMU per worker, once

class FMUPlugin(WorkerPlugin):
    """Dask worker plugin: the FMU's bytes travel to each worker once, are
    extracted once into the worker's local directory, and each worker thread
    keeps one instantiated FMU2Slave that is reset between runs."""

    def __init__(self, fmu_path):
        with open(fmu_path, "rb") as f:
            self.fmu_bytes = f.read()
        self.name = "guideway-fmu-" + hashlib.sha256(self.fmu_bytes).hexdigest()[:16]

    def setup(self, worker=None):
        from fmpy import extract, read_model_description

        root = worker.local_directory if worker is not None else None
        self.unzipdir = tempfile.mkdtemp(prefix="guideway-fmu-", dir=root)
        fmu = os.path.join(self.unzipdir, "model.fmu")
        with open(fmu, "wb") as f:
            f.write(self.fmu_bytes)
        extract(fmu, self.unzipdir)
        self.md = read_model_description(fmu)
        self.local = threading.local()
        # fmpy's logger proxy has one Python logger per process: one run at
        # a time per worker process keeps the messages apart.
        self.lock = threading.Lock()

    def teardown(self, worker=None):
        pass

    def slave(self):
        """This thread's FMU instance and the list its logger appends to."""
        if getattr(self.local, "slave", None) is None:
            from fmpy.fmi2 import FMU2Slave

            callbacks, messages = _callbacks()
            s = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzipdir,
                          modelIdentifier=self.md.coSimulation.modelIdentifier,
                          instanceName=f"sweep-{threading.get_ident()}")
            s.instantiate(callbacks=callbacks)
            self.local.slave, self.local.messages, self.local.fresh = s, messages, True
        return self.local.slave, self.local.messages


_MESSAGES = []
_CALLBACKS = None


def _callbacks():
    global _CALLBACKS
    if _CALLBACKS is None:
        from fmpy import calloc, free
        from fmpy.fmi2 import (fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                               fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
        from fmpy.logging import addLoggerProxy

        def logger(env, instance, status, category, message):
            _MESSAGES.append(message.decode(errors="replace"))

        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(logger)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(cb))
        _CALLBACKS = cb
    return _CALLBACKS, _MESSAGES


def start_value(md, name):
    v = next(v for v in md.modelVariables if v.name == name)
    return float(v.start)


def run_case(plugin, params):
    """Run one case on `plugin`'s FMU; returns a row of the table."""
    from fmpy.fmi1 import FMICallException
    from fmpy.fmi2 import fmi2Discard, fmi2Error, fmi2LastSuccessfulTime, fmi2Terminated

    md = plugin.md
    vr = {v.name: (v.valueReference, v.type) for v in md.modelVariables}
    with plugin.lock:
        slave, messages = plugin.slave()
        if not plugin.local.fresh:
            slave.reset()
        plugin.local.fresh = False
        del messages[:]
        length = params.get("beam.length", start_value(md, "beam.length"))
        speed = params[f"{BODY}.initial_speed"]
        ei = params["beam.bending_stiffness"]
        load = -params.get(f"{BODY}.force_y", start_value(md, f"{BODY}.force_y"))
        h = params.get("solver.step", start_value(md, "solver.step"))
        stop = 10.0 * length / speed
        row = dict(params, status="stopped", time_reached=0.0, peak_deflection=float("nan"),
                   message="", extract_dir=plugin.unzipdir, pid=os.getpid())
        t, peak = 0.0, 0.0
        try:
            slave.setupExperiment(startTime=0.0)
            for name, value in params.items():
                ref, ty = vr[name]
                if ty == "Integer":
                    slave.setInteger([ref], [int(value)])
                else:
                    slave.setReal([ref], [float(value)])
            slave.enterInitializationMode()
            slave.exitInitializationMode()
            sensor = vr[SENSOR][0]
            # Leaving the beam is an event, not the end of the FMU's run:
            # the case ends at the first communication point after it.
            on_beam = vr.get("contact.on_beam", (None,))[0]
            while t < stop - 1e-9 * h:
                step = min(h, stop - t)
                try:
                    slave.doStep(currentCommunicationPoint=t, communicationStepSize=step)
                except FMICallException as e:
                    lift_off = "lift-off" in " ".join(messages)
                    # a lift-off no smaller step gets past is an fmi2Error
                    if e.status != fmi2Discard and not (e.status == fmi2Error and lift_off):
                        raise
                    if e.status == fmi2Discard and slave.getBooleanStatus(fmi2Terminated):
                        t = slave.getRealStatus(fmi2LastSuccessfulTime)
                        peak = max(peak, abs(slave.getReal([sensor])[0]))
                        row["status"] = "exited"  # left the beam
                    else:  # rolled back: the state is still at t
                        row["status"] = "lift-off" if lift_off else "discarded"
                    break
                t += step
                if on_beam is not None and slave.getInteger([on_beam])[0] == 0:
                    row["status"] = "exited"  # left the beam
                    break
                peak = max(peak, abs(slave.getReal([sensor])[0]))
        except FMICallException as e:
            row["status"] = "error"
            row["message"] = f"{e}: " + " ".join(messages)
        if not row["message"]:
            row["message"] = " ".join(messages)
        static = load * length**3 / (48.0 * ei)
        row.update(time_reached=t, peak_deflection=peak, static_deflection=static,
                   amplification=peak / static)
        return row


def _run_on_worker(plugin_name, cases):
    from distributed import get_worker

    plugin = get_worker().plugins[plugin_name]
    return [run_case(plugin, params) for params in cases]


# ------------------------------------------------------------------ sweep

def sweep(client, fmu_path, cases, chunk=10):
    """Run `cases` (dicts of start values) on the Dask `client`, `chunk`
    runs per task (a run takes milliseconds: one task per run would cost
    more in scheduling than in simulation); one DataFrame, in the order of
    `cases`."""
    if __name__ != "__main__":
        # imported (tests, notebooks): ship this module's code to the
        # workers, which need not have scripts/ on their path
        import cloudpickle
        cloudpickle.register_pickle_by_value(sys.modules[__name__])
    plugin = FMUPlugin(fmu_path)
    client.register_plugin(plugin, name=plugin.name)
    chunks = [cases[i:i + chunk] for i in range(0, len(cases), chunk)]
    futures = client.map(_run_on_worker, [plugin.name] * len(chunks), chunks, pure=False)
    return pd.DataFrame([row for rows in client.gather(futures) for row in rows])


def critical_speed(length, mass_per_length, ei):
    """Speed of a moving constant load that resonates with the first mode of
    a simply supported span: (pi / L) sqrt(EI / mu)."""
    return math.pi / length * math.sqrt(ei / mass_per_length)


def plot(table, png, length, mass_per_length):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 5.5))
    stiffnesses = sorted(table["beam.bending_stiffness"].unique())
    masses = sorted(table[f"{BODY}.mass"].unique())
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    styles = ["-", "--", ":", "-."]
    for i, ei in enumerate(stiffnesses):
        colour = colours[i % len(colours)]
        vcr = critical_speed(length, mass_per_length, ei)
        ax.axvline(vcr, color=colour, lw=0.8, alpha=0.6)
        ax.text(vcr, 0.02, f" {vcr:.0f} m/s", color=colour, transform=ax.get_xaxis_transform(),
                rotation=90, va="bottom", fontsize=8)
        for j, m in enumerate(masses):
            rows = table[(table["beam.bending_stiffness"] == ei) & (table[f"{BODY}.mass"] == m)]
            rows = rows.sort_values(f"{BODY}.initial_speed")
            done = rows[rows["status"] == "exited"]
            ax.plot(done[f"{BODY}.initial_speed"], done["amplification"], styles[j % len(styles)],
                    color=colour, marker=".", label=f"EI = {ei:.3g} N m², m = {m:g} kg")
            early = rows[rows["status"] != "exited"]
            if len(early):
                ax.plot(early[f"{BODY}.initial_speed"], early["amplification"], "x", color=colour)
    ax.plot([], [], "kx", label="stopped early: peak before the stop")
    ax.set_xlabel("initial speed V0 (m/s)")
    ax.set_ylabel("peak |midspan deflection| / (P L³ / 48 EI)")
    ax.set_title("Dynamic amplification of midspan deflection (vertical lines: critical speeds)")
    ax.grid(True, alpha=0.4)
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("fmu", help="a wheel FMU, e.g. dist/<version>/lee1994_wheel_10.fmu")
    p.add_argument("--speeds", type=parse_range, default=parse_range("5:300:5"),
                   help="initial speeds in m/s: start:stop:step or a,b,c (default 5:300:5)")
    p.add_argument("--stiffness", type=parse_range, default=parse_range("5e8,1e9,2e9"),
                   help="bending stiffnesses EI in N m^2 (default 5e8,1e9,2e9)")
    p.add_argument("--mass", type=parse_range, default=parse_range("1500,3000,6000"),
                   help="wheel masses in kg (default 1500,3000,6000)")
    p.add_argument("--workers", type=int, default=2,
                   help="processes of the LocalCluster (default 2; ignored with --scheduler)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="address of an existing Dask scheduler, e.g. tcp://10.0.0.5:8786")
    p.add_argument("--chunk", type=int, default=10, help="runs per Dask task (default 10)")
    p.add_argument("--out", default="sweep.csv", help="the table, CSV (default sweep.csv)")
    p.add_argument("--plot", help="write the amplification plot to this PNG")
    args = p.parse_args(argv)

    if not zipfile.is_zipfile(args.fmu):
        p.error(f"{args.fmu}: not an FMU (not a zip archive)")
    from fmpy import read_model_description
    md = read_model_description(args.fmu)
    names = {v.name for v in md.modelVariables}
    for needed in [f"{BODY}.initial_speed", f"{BODY}.mass", "beam.bending_stiffness", SENSOR]:
        if needed not in names:
            p.error(f"{args.fmu}: no variable {needed} (the sweep needs a wheel FMU with a `midspan` sensor)")
    if args.chunk < 1:
        p.error("--chunk must be >= 1")
    for option, values in [("--speeds", args.speeds), ("--stiffness", args.stiffness), ("--mass", args.mass)]:
        if not values or min(values) <= 0:
            p.error(f"{option}: want values > 0, got {values}")
    cases = grid(args.speeds, args.stiffness, args.mass)

    from distributed import Client, LocalCluster
    started = time.perf_counter()
    if args.scheduler:
        cluster, client = None, Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                               dashboard_address=":0")
        client = Client(cluster)
    try:
        ready = time.perf_counter()
        table = sweep(client, args.fmu, cases, chunk=args.chunk)
        wall = time.perf_counter() - ready
        workers = len(client.scheduler_info()["workers"])
    finally:
        client.close()
        if cluster is not None:
            cluster.close()

    table.to_csv(args.out, index=False)
    if args.plot:
        plot(table, args.plot, start_value(md, "beam.length"), start_value(md, "beam.mass_per_length"))
    counts = table["status"].value_counts().to_dict()
    print(f"{len(table)} runs on {workers} workers in {wall:.2f} s "
          f"(cluster start-up {ready - started:.2f} s): {counts}")
    print(f"table: {args.out}" + (f", plot: {args.plot}" if args.plot else ""))
    return table


if __name__ == "__main__":
    main()

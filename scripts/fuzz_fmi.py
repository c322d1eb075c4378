#!/usr/bin/env python3
"""Fuzz the FMI 2.0 C boundary of guideway FMUs with random call sequences.

Usage:
    python scripts/fuzz_fmi.py [--calls 100000] [--seed 1] [FMU ...]

Each sequence (one seed) instantiates an FMU and makes random calls to every
fmi2 function, in random order and mode, with hostile arguments: NULL
pointers and callbacks, zero and huge array lengths, unknown value
references, NaN, +-inf, subnormal and huge numbers, zero/negative step
sizes, wrong communication points, foreign, truncated and corrupted
serialized states, forged states (valid framing and checksum, hostile
payload: scripts/fuzz_state.py), double frees of FMU states, terminate
twice.  It never
calls a function on a freed instance: without a global registry of
instances an FMU cannot detect that (a limit of the FMI C API).

Checks, per sequence:
  - the process neither crashes nor hangs (batches of sequences run in
    worker processes under a time limit; a failing batch is re-run one
    sequence per process to name the seed);
  - every non-OK status on an instance comes with a message through the
    logger callback (if the importer gave one);
  - Real values read with status OK are finite;
  - after a step ends in fmi2Discard or fmi2Error, fmi2GetFMUstate works
    and the state, restored in a fresh instance, gives the same outputs;
  - a forged state that is accepted (deserialized and set) holds only
    parameter values that fmi2SetReal/fmi2SetInteger accept on a fresh
    instance: no state reaches what the API refuses; and every accepted
    forgery is counted under the benign reason that lets it pass
    (fuzz_state.classify_accepted: unchanged as read, a parameter or input,
    a run integral, a finite history or phase-space point that keeps every
    closed contact's body within 1 cm); one with no such reason fails;
  - at the end, the instance either had a fatal error (then only
    fmi2FreeInstance is called) or, after fmi2Reset, runs a valid sequence
    bit-identically to a fresh instance.

Exit status 0 when all sequences pass.  Reproduce one seed with
    python scripts/fuzz_fmi.py --only-seed SEED
"""

import argparse
import ctypes as C
import json
import math
import os
import pathlib
import queue
import random
import struct
import subprocess
import sys
import tempfile
import threading
import time
import zipfile
import xml.etree.ElementTree as ET

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import fuzz_state  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
DEFAULT_FMU_DIR = pathlib.Path(os.environ.get("GUIDEWAY_FMU_DIR", ROOT / "out" / "fmu"))

OK, WARNING, DISCARD, ERROR, FATAL = 0, 1, 2, 3, 4
STATUS_NAMES = ["OK", "Warning", "Discard", "Error", "Fatal"]
CO_SIMULATION = 1
HUGE_LEN = (1 << 64) - 1
REFERENCE_STEPS = 8
TRACE = os.environ.get("FUZZ_FMI_TRACE") == "1"  # print each checked call to stderr
REFERENCE_H = 0.01

# guideway calls the (variadic) logger with the format "%s" and the message as
# its one argument: on x86-64 a sixth fixed argument reads it.
LOGGER = C.CFUNCTYPE(None, C.c_void_p, C.c_char_p, C.c_int, C.c_char_p, C.c_char_p,
                     C.c_char_p)
ALLOC = C.CFUNCTYPE(C.c_void_p, C.c_size_t, C.c_size_t)
FREE = C.CFUNCTYPE(None, C.c_void_p)
STEP_FINISHED = C.CFUNCTYPE(None, C.c_void_p, C.c_int)


class Callbacks(C.Structure):
    _fields_ = [("logger", LOGGER), ("allocateMemory", ALLOC), ("freeMemory", FREE),
                ("stepFinished", STEP_FINISHED), ("componentEnvironment", C.c_void_p)]


class FuzzFailure(Exception):
    pass


# ---- the FMU under test -------------------------------------------------------

def extract(fmu, into):
    """Unzip `fmu` into `into`; return (directory, model description info)."""
    d = pathlib.Path(into) / pathlib.Path(fmu).stem
    with zipfile.ZipFile(fmu) as z:
        z.extractall(d)
    return d


P, SZ, I, D = C.c_void_p, C.c_size_t, C.c_int, C.c_double


class Model:
    """An unzipped FMU: its shared library with typed fmi2 functions and its
    variables from modelDescription.xml."""

    SIGNATURES = {
        "fmi2GetTypesPlatform": (C.c_char_p, []),
        "fmi2GetVersion": (C.c_char_p, []),
        "fmi2SetDebugLogging": (I, [P, I, SZ, P]),
        "fmi2Instantiate": (P, [P, I, P, P, P, I, I]),
        "fmi2FreeInstance": (None, [P]),
        "fmi2SetupExperiment": (I, [P, I, D, D, I, D]),
        "fmi2EnterInitializationMode": (I, [P]),
        "fmi2ExitInitializationMode": (I, [P]),
        "fmi2Terminate": (I, [P]),
        "fmi2Reset": (I, [P]),
        **{f"fmi2{op}{t}": (I, [P, P, SZ, P])
           for op in ("Get", "Set") for t in ("Real", "Integer", "Boolean", "String")},
        "fmi2GetFMUstate": (I, [P, P]),
        "fmi2SetFMUstate": (I, [P, P]),
        "fmi2FreeFMUstate": (I, [P, P]),
        "fmi2SerializedFMUstateSize": (I, [P, P, P]),
        "fmi2SerializeFMUstate": (I, [P, P, P, SZ]),
        "fmi2DeSerializeFMUstate": (I, [P, P, SZ, P]),
        "fmi2GetDirectionalDerivative": (I, [P, P, SZ, P, SZ, P, P]),
        "fmi2SetRealInputDerivatives": (I, [P, P, SZ, P, P]),
        "fmi2GetRealOutputDerivatives": (I, [P, P, SZ, P, P]),
        "fmi2DoStep": (I, [P, D, D, I]),
        "fmi2CancelStep": (I, [P]),
        "fmi2GetStatus": (I, [P, I, P]),
        "fmi2GetRealStatus": (I, [P, I, P]),
        "fmi2GetIntegerStatus": (I, [P, I, P]),
        "fmi2GetBooleanStatus": (I, [P, I, P]),
        "fmi2GetStringStatus": (I, [P, I, P]),
    }

    def __init__(self, directory):
        directory = pathlib.Path(directory)
        root = ET.parse(directory / "modelDescription.xml").getroot()
        self.guid = root.get("guid").encode()
        ident = root.find("CoSimulation").get("modelIdentifier")
        self.resources = (directory / "resources").as_uri().encode()
        self.lib = C.CDLL(str(directory / "binaries" / "linux64" / f"{ident}.so"))
        self.f = {}
        for name, (restype, argtypes) in self.SIGNATURES.items():
            fn = getattr(self.lib, name)
            fn.restype, fn.argtypes = restype, argtypes
            self.f[name] = fn
        self.vars = {}  # type -> [(vr, causality, name)]
        for sv in root.find("ModelVariables"):
            kind = next(iter(sv)).tag
            self.vars.setdefault(kind, []).append(
                (int(sv.get("valueReference")), sv.get("causality"), sv.get("name")))
        self.outputs = [vr for vr, c, _ in self.vars["Real"] if c == "output"]
        self.names = {vr: name for vs in self.vars.values() for vr, _, name in vs}
        self.all_vrs = sorted({vr for vs in self.vars.values() for vr, _, _ in vs})
        # Bodies in the state's order (their `.x` outputs), and which of them
        # carry a contact (a `.nominal_speed` output): a swap involving one
        # puts a body away from where its contact says.
        names = [n for _, c, n in self.vars["Real"] if c == "output"]
        bodies = [n[:-2] for n in names if n.endswith(".x")]
        self.contact_bodies = {k for k, b in enumerate(bodies)
                               if f"{b}.nominal_speed" in names}


# ---- logging -----------------------------------------------------------------

MESSAGES = []  # (instance name, status, message)


@LOGGER
def _log(env, instance, status, category, fmt, message):
    MESSAGES.append((instance, status, message if fmt == b"%s" else fmt))


@ALLOC
def _alloc(n, size):
    return C.cast(C.create_string_buffer(n * size), C.c_void_p).value


@FREE
def _free(p):
    pass


def callbacks(logger=True, alloc=True):
    cb = Callbacks()
    if logger:
        cb.logger = _log
    if alloc:
        cb.allocateMemory, cb.freeMemory = _alloc, _free
    return cb


# ---- hostile values ------------------------------------------------------------

SPECIAL_REALS = [0.0, -0.0, 1.0, -1.0, math.nan, -math.nan, math.inf, -math.inf, 5e-324,
                 -5e-324, 2.2250738585072014e-308, 1e308, -1e308, 1.7976931348623157e308,
                 1e-300, 1e300, 0.01, 1e-9]
SPECIAL_INTS = [0, 1, -1, 2, 7, 100, 2**31 - 1, -2**31, 10**6]
SPECIAL_STRINGS = [b"", b"x", "ünïcødé ✓".encode(), b"\xff\xfe\xfd", b"%s%n%s%d", b"a" * 5000]


def real_value(rng):
    r = rng.random()
    if r < 0.5:
        return rng.choice(SPECIAL_REALS)
    if r < 0.8:
        return rng.uniform(-1e3, 1e3)
    return rng.uniform(-1, 1) * 10.0 ** rng.randint(-320, 308)


def int_value(rng):
    return rng.choice(SPECIAL_INTS) if rng.random() < 0.7 else rng.randint(-2**31, 2**31 - 1)


# ---- one sequence ---------------------------------------------------------------

class Sequence:
    """One seeded random call sequence on one instance of one model."""

    def __init__(self, models, references, seed, max_calls):
        self.rng = random.Random(seed)
        self.seed = seed
        self.models = models
        self.references = references
        self.model = self.rng.choice(models)
        self.max_calls = max_calls
        self.calls = 0
        self.time = 0.0
        self.states = []        # FMUstate pointers of this instance, maybe freed
        self.blobs = []         # serialized states, of any model
        self.keep = []          # ctypes buffers that must outlive a call
        self.fatal = False
        self.logger = True
        self.tally = {}         # "function status" -> count of checked calls

    # -- checked calls --

    def call(self, name, *args):
        """Call `name`, check the status and the log; return the status."""
        before = len(MESSAGES)
        if TRACE:
            shown = [list(a)[:8] if isinstance(a, C.Array) else a for a in args]
            print(f"call {self.calls}: {name}{shown}", file=sys.stderr, flush=True)
        status = self.model.f[name](*args)
        if TRACE:
            print(f"  -> {status} {MESSAGES[before:]}", file=sys.stderr, flush=True)
        self.calls += 1
        if status not in (OK, WARNING, DISCARD, ERROR, FATAL):
            self.fail(f"{name} returned the unknown status {status}")
        if status != OK and self.logger and len(MESSAGES) == before:
            self.fail(f"{name} returned status {status} without a log message")
        if status == FATAL:
            self.fatal = True
        key = f"{name} {STATUS_NAMES[status]}"
        self.tally[key] = self.tally.get(key, 0) + 1
        return status

    def fail(self, message):
        raise FuzzFailure(f"seed {self.seed} ({self.model.guid.decode()}), call {self.calls}: "
                          f"{message}")

    def instantiate(self, name=b"fuzz", guid=None, location=None, cb=None, kind=CO_SIMULATION):
        cb = cb if cb is not None else callbacks()
        self.keep.append(cb)
        before = len(MESSAGES)
        c = self.model.f["fmi2Instantiate"](
            name, kind, self.model.guid if guid is None else guid,
            self.model.resources if location is None else location,
            C.addressof(cb), 0, self.rng.random() < 0.3)
        self.calls += 1
        return c, len(MESSAGES) > before

    # -- the run --

    def run(self):
        self.hostile_instantiations()
        self.logger = self.rng.random() > 0.1
        c, _ = self.instantiate(cb=callbacks(logger=self.logger,
                                             alloc=self.rng.random() > 0.1))
        if not c:
            self.fail("fmi2Instantiate with valid arguments returned NULL")
        self.c = c
        try:
            if self.rng.random() < 0.7:  # most sequences explore stepping
                for _ in range(self.rng.choice([0, 0, 1, 2, 3])):
                    self.set_one_special_real()
                for name in ("fmi2EnterInitializationMode", "fmi2ExitInitializationMode"):
                    self.call(name, c)
            while self.calls < self.max_calls and not self.fatal:
                self.random_call()
            if not self.fatal:
                self.check_recovers()
        finally:
            self.model.f["fmi2FreeInstance"](c)
        return self.calls

    def hostile_instantiations(self):
        """Instantiations with wrong arguments: NULL and a logged reason."""
        for _ in range(self.rng.randint(0, 2)):
            m = self.model
            variant = self.rng.randrange(6)
            if variant == 0:
                c = m.f["fmi2Instantiate"](b"x", 1, m.guid, m.resources, None, 0, 0)
                self.calls += 1
                logged = True  # no logger to log through
            elif variant == 1:
                c, logged = self.instantiate(guid=b"{00000000-wrong-guid}")
            elif variant == 2:
                c, logged = self.instantiate(kind=self.rng.choice([0, 2, -1, 99]))
            elif variant == 3:
                c, logged = self.instantiate(location=self.rng.choice(
                    [b"file:///nonexistent/dir", b"http://x/", b"", "file:///ü%zz".encode()]))
            elif variant == 4:
                c, logged = self.instantiate(name=None)
            else:
                cb = callbacks()
                before = len(MESSAGES)
                c = m.f["fmi2Instantiate"](b"x", 1, None, None, C.addressof(cb), 0, 0)
                self.calls += 1
                logged = len(MESSAGES) > before
            if c:
                self.fail(f"hostile fmi2Instantiate variant {variant} returned an instance")
            if not logged:
                self.fail(f"hostile fmi2Instantiate variant {variant} logged nothing")

    def random_call(self):
        actions = [
            (1, self.lifecycle), (6, self.get_values), (5, self.set_values),
            (8, self.do_step), (4, self.fmu_states), (3, self.serialization),
            (3, self.forged_state), (3, self.physics_forgery), (1, self.threaded_instances),
            (2, self.status), (1, self.debug_logging), (1, self.unsupported),
            (1, self.null_component), (1, self.platform), (1, self.push_hard),
        ]
        total = sum(w for w, _ in actions)
        r = self.rng.uniform(0, total)
        for w, action in actions:
            r -= w
            if r <= 0:
                return action()
        return actions[-1][1]()

    # -- argument makers --

    def vr_array(self, kind):
        """(pointer, length, count of real elements) of value references."""
        rng = self.rng
        r = rng.random()
        if r < 0.05:
            return None, rng.choice([0, 1, 5, HUGE_LEN, 1 << 62]), 0
        known = [vr for vr, _, _ in self.model.vars.get(kind, [])] or [0]
        n = rng.choice([0, 1, 1, 2, 3, len(known)])
        if r < 0.8:
            vrs = [rng.choice(known) for _ in range(n)]
        else:
            vrs = [rng.choice(known + self.model.all_vrs + [2**32 - 1, 99999, rng.getrandbits(32)])
                   for _ in range(n)]
        arr = (C.c_uint * max(n, 1))(*vrs)
        self.keep.append(arr)
        return arr, n, n

    def values(self, kind, n):
        rng = self.rng
        if kind == "Real":
            return (C.c_double * max(n, 1))(*[real_value(rng) for _ in range(n)])
        if kind == "Integer":
            return (C.c_int * max(n, 1))(*[int_value(rng) for _ in range(n)])
        if kind == "Boolean":
            return (C.c_int * max(n, 1))(*[rng.choice([0, 1, 2, -1, 255]) for _ in range(n)])
        strings = [None if rng.random() < 0.2 else rng.choice(SPECIAL_STRINGS) for _ in range(n)]
        return (C.c_char_p * max(n, 1))(*strings)

    # -- actions --

    def lifecycle(self):
        rng = self.rng
        name = rng.choice(["fmi2SetupExperiment", "fmi2EnterInitializationMode",
                           "fmi2ExitInitializationMode", "fmi2Terminate", "fmi2Reset"])
        if name == "fmi2SetupExperiment":
            start = rng.choice([0.0, 0.0, 1.0, real_value(rng)])
            status = self.call(name, self.c, rng.randint(0, 1), real_value(rng), start,
                               rng.randint(0, 1), real_value(rng))
            if status == OK:
                self.time = start
        else:
            status = self.call(name, self.c)
            if status == OK and name == "fmi2Reset":
                self.time = 0.0
                if rng.random() < 0.7:  # back to stepping, mostly
                    for name in ("fmi2EnterInitializationMode", "fmi2ExitInitializationMode"):
                        self.call(name, self.c)

    def get_values(self):
        kind = self.rng.choice(["Real", "Real", "Integer", "Boolean", "String"])
        vrs, n, real_n = self.vr_array(kind)
        if self.rng.random() < 0.05:
            out = None
        else:
            ctype = {"Real": C.c_double, "Integer": C.c_int, "Boolean": C.c_int,
                     "String": C.c_char_p}[kind]
            out = (ctype * max(real_n, 1))()
            self.keep.append(out)
        status = self.call(f"fmi2Get{kind}", self.c, vrs, n, out)
        if status == OK and kind == "Real" and out is not None:
            for k in range(real_n):
                if not math.isfinite(out[k]):
                    self.fail(f"fmi2GetReal gave {out[k]} for vr {vrs[k]} with status OK")

    def set_values(self):
        if self.rng.random() < 0.3:
            return self.set_one_special_real()
        kind = self.rng.choice(["Real", "Real", "Real", "Integer", "Boolean", "String"])
        vrs, n, real_n = self.vr_array(kind)
        vals = None if self.rng.random() < 0.05 else self.values(kind, real_n)
        self.keep.append(vals)
        self.call(f"fmi2Set{kind}", self.c, vrs, n, vals)

    def set_one_special_real(self):
        """One Real variable set to a boundary value: such single settings
        (a zero speed, a subnormal solver step) reach the solver's corners
        far more often than random arrays do."""
        reals = self.model.vars["Real"]
        params = [v for v in reals if v[1] == "parameter"]
        vr = self.rng.choice(params if self.rng.random() < 0.7 else reals)[0]
        self.call("fmi2SetReal", self.c, (C.c_uint * 1)(vr), 1,
                  (C.c_double * 1)(self.rng.choice(SPECIAL_REALS)))

    def outputs(self):
        n = len(self.model.outputs)
        vrs = (C.c_uint * n)(*self.model.outputs)
        out = (C.c_double * n)()
        if self.model.f["fmi2GetReal"](self.c, vrs, n, out) != OK:
            return None
        return list(out)

    def do_step(self):
        rng = self.rng
        h = rng.choice([0.01, 0.01, 0.02, 0.005, 1e-6]) if rng.random() < 0.7 else \
            rng.choice([0.0, -0.0, -0.01, math.nan, math.inf, -math.inf, 5e-324, 1e-300, 1e6,
                        1e300])
        t = self.time if rng.random() < 0.85 else real_value(rng)
        status = self.call("fmi2DoStep", self.c, t, h, rng.randint(0, 1))
        if status == OK:
            self.time = t + h
            out = self.outputs()
            if out is None or not all(math.isfinite(x) for x in out):
                self.fail(f"after fmi2DoStep OK the outputs are {out}")
        elif status in (DISCARD, ERROR):
            self.check_state_survives_failed_step()

    def push_hard(self):
        """An input set to a large allowed magnitude, then long steps until
        one fails (or the body's exit, or 40 steps): the failing-step paths
        (fmi2Discard, the roll-back), which random short steps seldom reach,
        are searched too."""
        inputs = [vr for vr, c, _ in self.model.vars.get("Real", []) if c == "input"]
        if inputs:
            value = self.rng.choice([1e15, -1e15, 1e12, -1e12, 1e9, -1e9])
            self.call("fmi2SetReal", self.c, (C.c_uint * 1)(self.rng.choice(inputs)), 1,
                      (C.c_double * 1)(value))
        for _ in range(40):
            status = self.call("fmi2DoStep", self.c, self.time, 0.25, 1)
            if status != OK:
                if status in (DISCARD, ERROR):
                    self.check_state_survives_failed_step()
                return
            self.time += 0.25

    def check_state_survives_failed_step(self):
        """fmi2GetFMUstate works after a refused step; the state restored in a
        fresh instance reads the same outputs as this one."""
        here = self.outputs()
        state = C.c_void_p()
        if self.call("fmi2GetFMUstate", self.c, C.byref(state)) != OK:
            self.fail("fmi2GetFMUstate refused after a failed step")
        blob = self.serialize(state)
        self.call("fmi2FreeFMUstate", self.c, C.byref(state))
        if blob is None:
            self.fail("fmi2SerializeFMUstate refused after a failed step")
        if here is None:
            return  # not initialized: there are no outputs to compare
        other, _ = self.instantiate(name=b"witness")
        try:
            # in initialization mode, so that a state from before
            # initialization restores to a mode where outputs can be read
            f = self.model.f
            if (f["fmi2SetupExperiment"](other, 0, 0.0, 0.0, 0, 0.0) != OK
                    or f["fmi2EnterInitializationMode"](other) != OK):
                self.fail("a fresh witness instance refuses to initialize")
            restored = C.c_void_p()
            buf = C.create_string_buffer(blob, len(blob))
            ok = (self.model.f["fmi2DeSerializeFMUstate"](other, buf, len(blob),
                                                           C.byref(restored)) == OK
                  and self.model.f["fmi2SetFMUstate"](other, restored) == OK)
            if not ok:
                self.fail("the state saved after a failed step does not restore: "
                          f"{MESSAGES[-1][2] if MESSAGES else ''}")
            n = len(self.model.outputs)
            vrs, out = (C.c_uint * n)(*self.model.outputs), (C.c_double * n)()
            if self.model.f["fmi2GetReal"](other, vrs, n, out) != OK:
                self.fail("the state saved after a failed step does not read: "
                          f"{MESSAGES[-1][2]}")
            if list(out) != here:
                diff = [(self.model.names[vr], a, b) for vr, a, b in
                        zip(self.model.outputs, here, out) if a != b]
                self.fail(f"the state saved after a failed step gives other outputs: {diff}")
        finally:
            self.model.f["fmi2FreeInstance"](other)

    def serialize(self, state):
        size = C.c_size_t()
        if self.model.f["fmi2SerializedFMUstateSize"](self.c, state, C.byref(size)) != OK:
            return None
        buf = C.create_string_buffer(size.value)
        if self.model.f["fmi2SerializeFMUstate"](self.c, state, buf, size.value) != OK:
            return None
        return buf.raw

    def some_state(self):
        """A live, freed, foreign or garbage FMUstate pointer."""
        rng = self.rng
        r = rng.random()
        if self.states and r < 0.7:
            return rng.choice(self.states)
        return rng.choice([None, 1, 0xdeadbeef, rng.getrandbits(48) & ~7])

    def fmu_states(self):
        rng = self.rng
        op = rng.choice(["get", "get", "set", "free", "free_null"])
        if op == "get":
            if rng.random() < 0.05:
                self.call("fmi2GetFMUstate", self.c, None)
                return
            state = C.c_void_p(self.some_state() if rng.random() < 0.3 else None)
            if self.call("fmi2GetFMUstate", self.c, C.byref(state)) == OK:
                self.states.append(state.value)
        elif op == "set":
            if self.call("fmi2SetFMUstate", self.c, self.some_state()) == OK:
                self.time = self.current_time()
        elif op == "free":
            state = C.c_void_p(self.some_state())
            self.call("fmi2FreeFMUstate", self.c, C.byref(state))
        else:
            self.call("fmi2FreeFMUstate", self.c, None)

    def current_time(self):
        t = C.c_double()
        if self.model.f["fmi2GetRealStatus"](self.c, 2, C.byref(t)) == OK:
            return t.value
        return self.time

    def serialization(self):
        rng = self.rng
        op = rng.choice(["size", "serialize", "deserialize", "deserialize"])
        if op == "size":
            size = C.c_size_t()
            self.call("fmi2SerializedFMUstateSize", self.c, self.some_state(),
                      None if rng.random() < 0.1 else C.byref(size))
        elif op == "serialize":
            state = self.some_state()
            size = C.c_size_t()
            if self.model.f["fmi2SerializedFMUstateSize"](self.c, state, C.byref(size)) == OK:
                n = max(0, size.value + rng.choice([0, 0, 0, -1, 1, 100, -size.value]))
            else:
                n = rng.choice([0, 16, 1000])
            buf = C.create_string_buffer(max(n, 1))
            status = self.call("fmi2SerializeFMUstate", self.c, state,
                               None if rng.random() < 0.05 else buf, n)
            if status == OK:
                self.blobs.append(buf.raw[:n])
        else:
            self.deserialize()

    def deserialize(self):
        rng = self.rng
        pool = self.blobs + [b for m in self.references.values() for b in m["blobs"]]
        blob = rng.choice(pool) if pool else b""
        kind = rng.randrange(7)
        if kind == 1:
            blob = blob[:rng.randint(0, len(blob))]
        elif kind == 2 and blob:
            b = bytearray(blob)
            for _ in range(rng.randint(1, 4)):
                b[rng.randrange(len(b))] ^= 1 << rng.randrange(8)
            blob = bytes(b)
        elif kind == 3:
            blob = rng.randbytes(rng.randint(0, 300))
        elif kind == 4:
            blob = blob + rng.randbytes(rng.randint(1, 50))
        state = C.c_void_p()
        if kind == 5:
            self.call("fmi2DeSerializeFMUstate", self.c, None, rng.choice([1, 100, HUGE_LEN]),
                      C.byref(state))
            return
        buf = C.create_string_buffer(blob, max(len(blob), 1))
        out = None if kind == 6 else C.byref(state)
        if self.call("fmi2DeSerializeFMUstate", self.c, buf, len(blob), out) == OK and out:
            self.states.append(state.value)

    def forged_state(self):
        """A good state of this model with one hostile change in its payload,
        framed with a correct checksum: deserialized, set, and if accepted
        checked to be reachable through the API."""
        own = self.references[self.model.guid]["blobs"] + [
            b for b in self.blobs if b.startswith(fuzz_state.MAGIC)
            and self.model.guid in b[:200]]
        try:
            good = self.rng.choice(own)
            blob, path = fuzz_state.forge(self.rng, good)
        except (ValueError, struct.error, IndexError):
            return  # a truncated blob of our own: nothing to forge
        state = C.c_void_p()
        buf = C.create_string_buffer(blob, len(blob))
        self.keep.append(buf)
        accepted = (self.call("fmi2DeSerializeFMUstate", self.c, buf, len(blob),
                              C.byref(state)) == OK)
        if accepted:
            self.states.append(state.value)
            accepted = self.call("fmi2SetFMUstate", self.c, state) == OK
        why = "refused"
        if accepted:
            why = fuzz_state.classify_accepted(good, blob, path, self.model.contact_bodies)
            if why is None and self.reads_as(state.value, good):
                why = "unchanged as read (the FMU's own serialization of it is the original)"
            if why is None:
                self.fail(f"a forged state (changed at {'/'.join(map(str, path))}) was "
                          "accepted and no benign reason holds")
        key = f"forged state {'accepted: ' + why if accepted else why}"
        self.tally[key] = self.tally.get(key, 0) + 1
        if accepted:
            self.time = self.current_time()
            self.check_parameters_reachable(path)

    def reads_as(self, state, good):
        """Whether the FMU, serializing the state it accepted, gives the
        payload of `good` back: what it read is the original (a section
        dropped and defaulted to the same values, bytes read as the same
        numbers), whatever the forged bytes looked like."""
        mine = self.serialize(state)
        try:
            return mine is not None and fuzz_state.payload(mine) == fuzz_state.payload(good)
        except (ValueError, struct.error, IndexError):
            return False

    def physics_forgery(self):
        """A running state of this model made physically hostile (two bodies
        swapped, NaN positions, wrong body or coupling counts, non-finite
        coupling loads, exit or event times outside the run): refused at
        fmi2DeSerializeFMUstate already, where it must be refused at all."""
        own = self.references[self.model.guid]["blobs"]
        forged = fuzz_state.forge_physics(self.rng, self.rng.choice(own),
                                          self.model.contact_bodies)
        if forged is None:
            return
        blob, what, must_refuse = forged
        state = C.c_void_p()
        buf = C.create_string_buffer(blob, len(blob))
        self.keep.append(buf)
        accepted = self.call("fmi2DeSerializeFMUstate", self.c, buf, len(blob),
                             C.byref(state)) == OK
        # The only forgery that may pass: a swap that moves no contact body
        # by more than 1 cm (contact-free bodies, or equal heights), which
        # contact geometry cannot tell from the true state.
        why = "accepted: no contact body moved > 1 cm" if accepted else "refused"
        key = f"physics forgery {what} {why}"
        self.tally[key] = self.tally.get(key, 0) + 1
        if accepted and must_refuse:
            self.fail(f"fmi2DeSerializeFMUstate accepted a forged state ({what})")
        if accepted:
            self.states.append(state.value)
            if self.call("fmi2SetFMUstate", self.c, state) == OK:
                self.time = self.current_time()

    def threaded_instances(self):
        """Two to four fresh instances of this model run the reference
        sequence at once on threads (ctypes releases the GIL in the calls):
        each must give the reference outputs bit for bit."""
        reference = self.references[self.model.guid]["rows"]
        results = []

        def one():
            cb = callbacks()
            c = self.model.f["fmi2Instantiate"](b"thread", 1, self.model.guid,
                                                self.model.resources, C.addressof(cb), 0, 0)
            try:
                results.append(run_reference_sequence(self.model, c) if c else "NULL")
            finally:
                if c:
                    self.model.f["fmi2FreeInstance"](c)

        threads = [threading.Thread(target=one) for _ in range(self.rng.randint(2, 4))]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        self.calls += len(threads) * (REFERENCE_STEPS * 2 + 5)
        self.tally["threaded instances"] = self.tally.get("threaded instances", 0) + len(threads)
        for r in results:
            if r != reference and not (r is None and reference is None):
                self.fail("an instance on a thread differs from the reference run")

    def check_parameters_reachable(self, path):
        """Each parameter and input of the instance, set on a fresh instance,
        is accepted (unless the instance is in a mode where they cannot be
        read): a state carries in nothing the setters refuse."""
        values = []
        for kind, ctype in (("Real", C.c_double), ("Integer", C.c_int)):
            for vr, causality, name in self.model.vars.get(kind, []):
                if causality not in ("parameter", "input"):
                    continue
                out = (ctype * 1)()
                if self.model.f[f"fmi2Get{kind}"](self.c, (C.c_uint * 1)(vr), 1, out) != OK:
                    return
                values.append((kind, ctype, vr, name, out[0]))
        other, _ = self.instantiate(name=b"witness")
        try:
            for kind, ctype, vr, name, x in values:
                before = len(MESSAGES)
                if self.model.f[f"fmi2Set{kind}"](other, (C.c_uint * 1)(vr), 1,
                                                  (ctype * 1)(x)) != OK:
                    said = MESSAGES[before:][-1:]
                    self.fail(f"a forged state (changed at {'/'.join(map(str, path))}) was "
                              f"accepted with {name} = {x}, which fmi2Set{kind} refuses: {said}")
        finally:
            self.model.f["fmi2FreeInstance"](other)

    def status(self):
        rng = self.rng
        name = rng.choice(["fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus",
                           "fmi2GetBooleanStatus", "fmi2GetStringStatus"])
        kind = rng.choice([0, 1, 2, 3, -1, 4, 1000])
        out = {"fmi2GetRealStatus": C.c_double, "fmi2GetStringStatus": C.c_char_p}.get(
            name, C.c_int)()
        status = self.call(name, self.c, kind, None if rng.random() < 0.1 else C.byref(out))
        if status == OK and name == "fmi2GetRealStatus" and not math.isfinite(out.value):
            self.fail(f"fmi2GetRealStatus gave {out.value} with status OK")

    def debug_logging(self):
        rng = self.rng
        names = [None, b"logAll", b"logStatusError", b"nonsense", b"", "ü".encode(), b"%s"]
        n = rng.choice([0, 1, 2, 3])
        cats = (C.c_char_p * max(n, 1))(*[rng.choice(names) for _ in range(n)])
        ptr = None if rng.random() < 0.1 else cats
        length = rng.choice([n, n, HUGE_LEN]) if ptr is None else n
        self.call("fmi2SetDebugLogging", self.c, rng.randint(0, 1), length, ptr)

    def unsupported(self):
        rng = self.rng
        vrs, n, real_n = self.vr_array("Real")
        buf = (C.c_double * max(real_n, 1))()
        orders = (C.c_int * max(real_n, 1))()
        name = rng.choice(["fmi2GetDirectionalDerivative", "fmi2SetRealInputDerivatives",
                           "fmi2GetRealOutputDerivatives", "fmi2CancelStep"])
        if name == "fmi2GetDirectionalDerivative":
            self.call(name, self.c, vrs, n, vrs, n, buf, buf)
        elif name == "fmi2CancelStep":
            self.call(name, self.c)
        else:
            self.call(name, self.c, vrs, n, orders, buf)

    def null_component(self):
        name = self.rng.choice([n for n, (_, a) in Model.SIGNATURES.items()
                                if a and a[0] is P and n != "fmi2Instantiate"])
        args = [None] + [0 if t in (I, SZ) else 0.0 if t is D else None
                         for t in Model.SIGNATURES[name][1][1:]]
        status = self.model.f[name](*args)
        self.calls += 1
        if name != "fmi2FreeInstance" and status != ERROR:
            self.fail(f"{name} on a NULL instance returned {status}, not fmi2Error")

    def platform(self):
        f = self.model.f
        if f["fmi2GetTypesPlatform"]() != b"default" or f["fmi2GetVersion"]() != b"2.0":
            self.fail("fmi2GetTypesPlatform or fmi2GetVersion wrong")
        self.calls += 2

    # -- the final check --

    def check_recovers(self):
        """fmi2Reset, then the standard sequence gives the reference outputs."""
        f, c = self.model.f, self.c
        for name in ("fmi2Terminate", "fmi2Terminate"):  # terminate twice
            self.call(name, c)
        if self.call("fmi2Reset", c) != OK:
            self.fail("fmi2Reset refused after the random calls")
        rows = run_reference_sequence(self.model, c)
        if rows != self.references[self.model.guid]["rows"]:
            self.fail("after fmi2Reset the standard sequence gives other outputs "
                      f"({rows[:1]} vs {self.references[self.model.guid]['rows'][:1]})")
        for state in self.states:  # double frees included: refused, not crashed
            s = C.c_void_p(state)
            self.call("fmi2FreeFMUstate", c, C.byref(s))


def run_reference_sequence(model, c):
    """Setup, initialize, a few steps: the outputs after each step (None on
    any refused call)."""
    f = model.f
    if (f["fmi2SetupExperiment"](c, 0, 0.0, 0.0, 0, 0.0) != OK
            or f["fmi2EnterInitializationMode"](c) != OK
            or f["fmi2ExitInitializationMode"](c) != OK):
        return None
    n = len(model.outputs)
    vrs, out = (C.c_uint * n)(*model.outputs), (C.c_double * n)()
    rows = []
    for k in range(REFERENCE_STEPS):
        if f["fmi2DoStep"](c, k * REFERENCE_H, REFERENCE_H, 1) != OK:
            return None
        f["fmi2GetReal"](c, vrs, n, out)
        rows.append(list(out))
    return rows


def references(models):
    """Per model: reference outputs of a fresh instance and a few good
    serialized states (to use as foreign states in other models)."""
    refs = {}
    for m in models:
        cb = callbacks()
        c = m.f["fmi2Instantiate"](b"reference", 1, m.guid, m.resources, C.addressof(cb), 0, 0)
        rows = run_reference_sequence(m, c)
        state = C.c_void_p()
        m.f["fmi2GetFMUstate"](c, C.byref(state))
        size = C.c_size_t()
        m.f["fmi2SerializedFMUstateSize"](c, state, C.byref(size))
        buf = C.create_string_buffer(size.value)
        m.f["fmi2SerializeFMUstate"](c, state, buf, size.value)
        m.f["fmi2FreeInstance"](c)
        refs[m.guid] = {"rows": rows, "blobs": [buf.raw]}
    return refs


# ---- worker and driver ---------------------------------------------------------

def harness_self_test(seed):
    """Crash or hang on purpose at the seed named by FUZZ_FMI_SELFTEST_CRASH
    or FUZZ_FMI_SELFTEST_HANG: the tests check that the driver catches both
    and names the seed."""
    if str(seed) == os.environ.get("FUZZ_FMI_SELFTEST_CRASH"):
        C.string_at(0)  # SIGSEGV
    if str(seed) == os.environ.get("FUZZ_FMI_SELFTEST_HANG"):
        time.sleep(1e6)


def worker(directories, seeds, max_calls):
    """Run the sequences of `seeds`; one JSON line per finished sequence."""
    models = [Model(d) for d in directories]
    refs = references(models)
    for seed in seeds:
        harness_self_test(seed)
        try:
            seq = Sequence(models, refs, seed, max_calls)
            calls = seq.run()
            print(json.dumps({"seed": seed, "calls": calls, "tally": seq.tally}), flush=True)
        except FuzzFailure as e:
            print(json.dumps({"seed": seed, "failure": str(e)}), flush=True)


def run_batch(directories, seeds, max_calls, timeout):
    """Run `seeds` in one worker process, which must finish a sequence at
    least every `timeout` seconds: (results by seed, problem or None)."""
    cmd = [sys.executable, "-u", "-X", "faulthandler", __file__, "--worker",
           "--max-calls", str(max_calls), "--seeds", ",".join(map(str, seeds)),
           *map(str, directories)]
    err = tempfile.TemporaryFile("w+")  # a file: a full pipe would block the worker
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=err, text=True)
    lines = queue.Queue()
    threading.Thread(target=lambda: [lines.put(x) for x in p.stdout] + [lines.put(None)],
                     daemon=True).start()
    results, problem = {}, None
    while True:
        try:
            line = lines.get(timeout=timeout)
        except queue.Empty:
            p.kill()
            problem = f"hang (no sequence ended within {timeout} s)"
            break
        if line is None:
            break
        r = json.loads(line)
        results[r["seed"]] = r
    p.wait()
    err.seek(0)
    stderr = err.read()
    err.close()
    if problem is None and p.returncode != 0:
        problem = f"crash (exit status {p.returncode}): {stderr.strip()[-500:]}"
    return results, problem


def fuzz(fmus, total_calls, first_seed, batch, max_calls, timeout, log=print):
    """Fuzz until `total_calls` calls are made; return a summary dict."""
    summary = {"calls": 0, "sequences": 0, "crashes": 0, "hangs": 0, "failures": [],
               "tally": {}}
    started = time.monotonic()
    with tempfile.TemporaryDirectory() as tmp:
        dirs = [extract(f, tmp) for f in fmus]
        seed = first_seed
        while summary["calls"] < total_calls:
            remaining = total_calls - summary["calls"]
            n = min(batch, remaining // max_calls + 1)
            seeds = list(range(seed, seed + n))
            seed += n
            results, problem = run_batch(dirs, seeds, max_calls, timeout)
            if problem:  # isolate: the unfinished seeds one per process
                for s in seeds:
                    if s in results:
                        continue
                    one, p = run_batch(dirs, [s], max_calls, timeout)
                    results.update(one)
                    if p:
                        kind = "hangs" if p.startswith("hang") else "crashes"
                        summary[kind] += 1
                        summary["failures"].append(f"seed {s}: {p}")
                        results[s] = {"seed": s, "calls": 0}
            for r in results.values():
                summary["sequences"] += 1
                summary["calls"] += r.get("calls", 0)
                for k, v in r.get("tally", {}).items():
                    summary["tally"][k] = summary["tally"].get(k, 0) + v
                if "failure" in r:
                    summary["failures"].append(r["failure"])
            log(f"{summary['calls']} calls, {summary['sequences']} sequences, "
                f"{len(summary['failures'])} failures")
    summary["seconds"] = round(time.monotonic() - started, 1)
    summary["tally"] = dict(sorted(summary["tally"].items()))
    return summary


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("fmus", nargs="*", help="FMUs (default: all in out/fmu)")
    ap.add_argument("--calls", type=int, default=5000, help="total calls to make")
    ap.add_argument("--seed", type=int, default=1, help="first seed")
    ap.add_argument("--only-seed", type=int, help="run this one seed in this process")
    ap.add_argument("--batch", type=int, default=50, help="sequences per worker process")
    ap.add_argument("--max-calls", type=int, default=150, help="calls per sequence")
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds per sequence")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--seeds", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        worker(args.fmus, [int(s) for s in args.seeds.split(",")], args.max_calls)
        return 0
    fmus = args.fmus or sorted(map(str, DEFAULT_FMU_DIR.glob("*.fmu")))
    if not fmus:
        sys.exit(f"no FMUs given and none in {DEFAULT_FMU_DIR}: run scripts/test.sh first")
    if args.only_seed is not None:
        with tempfile.TemporaryDirectory() as tmp:
            models = [Model(extract(f, tmp)) for f in fmus]
            print(Sequence(models, references(models), args.only_seed, args.max_calls).run(),
                  "calls, passed")
        return 0
    s = fuzz(fmus, args.calls, args.seed, args.batch, args.max_calls, args.timeout)
    print(json.dumps(s, indent=1))
    return 1 if s["failures"] else 0


if __name__ == "__main__":
    sys.exit(main())

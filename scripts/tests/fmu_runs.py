"""Plain runs of an unzipped guideway FMU through ctypes (no fmpy), for the
determinism and independence tests: one instance, a fixed input schedule,
the outputs after every step as raw bytes (bit-exact comparisons).

Also a command line, to continue a serialized state in another process:
    python fmu_runs.py UNZIPPED_DIR STATE_FILE T0 STEPS OUT_FILE
"""

import ctypes as C
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from fuzz_fmi import OK, Model, callbacks  # noqa: E402

H = 0.01


class Instance:
    """One instance of `model`, checked calls (an assertion names a refusal)."""

    def __init__(self, model, name=b"run"):
        self.m, self.f = model, model.f
        self.cb = callbacks()
        self.c = self.f["fmi2Instantiate"](name, 1, model.guid, model.resources,
                                           C.addressof(self.cb), 0, 0)
        assert self.c, "fmi2Instantiate returned NULL"
        n = len(model.outputs)
        self.vrs, self.out = (C.c_uint * n)(*model.outputs), (C.c_double * n)()

    def ok(self, name, *args):
        status = self.f[name](self.c, *args)
        assert status == OK, f"{name} returned {status}"

    def vr(self, name):
        return next(vr for vs in self.m.vars.values() for vr, _, n in vs if n == name)

    def set_real(self, name, x):
        self.ok("fmi2SetReal", (C.c_uint * 1)(self.vr(name)), 1, (C.c_double * 1)(x))

    def initialize(self, **params):
        self.ok("fmi2SetupExperiment", 0, 0.0, 0.0, 0, 0.0)
        for name, x in params.items():
            self.set_real(name, x)
        self.ok("fmi2EnterInitializationMode")
        self.ok("fmi2ExitInitializationMode")
        return self

    def outputs(self):
        self.ok("fmi2GetReal", self.vrs, len(self.m.outputs), self.out)
        return bytes(self.out)

    def step(self, t, h=H):
        return self.f["fmi2DoStep"](self.c, t, h, 1)

    def run(self, t0, steps, force=None):
        """`steps` steps from `t0`; the force input (if any) varies per step.
        The outputs after each step, concatenated as bytes."""
        rows = []
        for k in range(steps):
            if force is not None:
                self.set_real(force[0], force[1](k))
            assert self.step(t0 + k * H) == OK, f"step {k} refused"
            rows.append(self.outputs())
        return b"".join(rows)

    def get_state(self):
        state = C.c_void_p()
        self.ok("fmi2GetFMUstate", C.byref(state))
        return state

    def serialize(self, state):
        size = C.c_size_t()
        self.ok("fmi2SerializedFMUstateSize", state, C.byref(size))
        buf = C.create_string_buffer(size.value)
        self.ok("fmi2SerializeFMUstate", state, buf, size.value)
        return buf.raw

    def restore(self, blob):
        state = C.c_void_p()
        self.ok("fmi2DeSerializeFMUstate", C.create_string_buffer(blob, len(blob)), len(blob),
                C.byref(state))
        self.ok("fmi2SetFMUstate", state)
        self.ok("fmi2FreeFMUstate", C.byref(state))

    def free(self):
        self.f["fmi2FreeInstance"](self.c)


def main(directory, state_file, t0, steps, out_file):
    inst = Instance(Model(directory), b"other process")
    inst.restore(pathlib.Path(state_file).read_bytes())
    pathlib.Path(out_file).write_bytes(inst.run(float(t0), int(steps)))
    inst.free()


if __name__ == "__main__":
    main(*sys.argv[1:])

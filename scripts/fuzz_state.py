"""Structured forging of guideway's serialized FMU states, for the FMI
fuzzer (scripts/fuzz_fmi.py): valid framing and SHA-256, hostile payload.

A serialized state is `GWSTATE\\0`, a format version, the model GUID, the
SHA-256 of the payload, its length and the payload: MessagePack with field
names (src/model/snapshot.rs). `forge` decodes the payload, changes one
place in it (a number made extreme, a vector resized, a field removed,
renamed or retyped, a length header that lies, deep nesting) and frames it
again with a correct checksum, so that the change reaches the model's
checks instead of being stopped by the checksum.

Standard library only: a MessagePack subset (what rmp-serde writes) is
implemented here.
"""

import hashlib
import math
import struct

MAGIC = b"GWSTATE\0"


# ---- framing -------------------------------------------------------------------

def unframe(blob):
    """(header up to the checksum, payload) of a serialized state."""
    n = struct.unpack_from("<I", blob, 12)[0]
    head = blob[:16 + n]
    return head, blob[16 + n + 32 + 8:]


def frame(head, payload):
    return head + hashlib.sha256(payload).digest() + struct.pack("<Q", len(payload)) + payload


# ---- MessagePack (the subset rmp-serde writes) ------------------------------------

class Raw(bytes):
    """Bytes put into the payload as they are (a lying header, say)."""


def unpack(b, i=0):
    """(value, next index) of the MessagePack value at b[i]."""
    t = b[i]
    if t <= 0x7f:
        return t, i + 1
    if t >= 0xe0:
        return t - 0x100, i + 1
    if 0x80 <= t <= 0x8f:
        return _map(b, i + 1, t & 0x0f)
    if 0x90 <= t <= 0x9f:
        return _array(b, i + 1, t & 0x0f)
    if 0xa0 <= t <= 0xbf:
        n = t & 0x1f
        return b[i + 1:i + 1 + n].decode(), i + 1 + n
    simple = {0xc0: None, 0xc2: False, 0xc3: True}
    if t in simple:
        return simple[t], i + 1
    fixed = {0xca: ">f", 0xcb: ">d", 0xcc: ">B", 0xcd: ">H", 0xce: ">I", 0xcf: ">Q",
             0xd0: ">b", 0xd1: ">h", 0xd2: ">i", 0xd3: ">q"}
    if t in fixed:
        fmt = fixed[t]
        return struct.unpack_from(fmt, b, i + 1)[0], i + 1 + struct.calcsize(fmt)
    sized = {0xd9: (">B", "str"), 0xda: (">H", "str"), 0xdb: (">I", "str"),
             0xc4: (">B", "bin"), 0xc5: (">H", "bin"), 0xc6: (">I", "bin"),
             0xdc: (">H", "array"), 0xdd: (">I", "array"),
             0xde: (">H", "map"), 0xdf: (">I", "map")}
    if t in sized:
        fmt, kind = sized[t]
        n = struct.unpack_from(fmt, b, i + 1)[0]
        j = i + 1 + struct.calcsize(fmt)
        if kind == "array":
            return _array(b, j, n)
        if kind == "map":
            return _map(b, j, n)
        data = b[j:j + n]
        return (data.decode() if kind == "str" else bytes(data)), j + n
    raise ValueError(f"MessagePack type 0x{t:02x} not handled")


def _array(b, i, n):
    out = []
    for _ in range(n):
        v, i = unpack(b, i)
        out.append(v)
    return out, i


def _map(b, i, n):
    out = {}
    for _ in range(n):
        k, i = unpack(b, i)
        v, i = unpack(b, i)
        out[k] = v
    return out, i


def pack(v):
    if isinstance(v, Raw):
        return bytes(v)
    if v is None:
        return b"\xc0"
    if v is True or v is False:
        return b"\xc3" if v else b"\xc2"
    if isinstance(v, int):
        if 0 <= v <= 0x7f:
            return bytes([v])
        if -32 <= v < 0:
            return struct.pack(">b", v)
        if 0 <= v < 1 << 64:
            return b"\xcf" + struct.pack(">Q", v)
        if -(1 << 63) <= v < 0:
            return b"\xd3" + struct.pack(">q", v)
        return b"\xcb" + struct.pack(">d", float(v))  # too big for an integer
    if isinstance(v, float):
        return b"\xcb" + struct.pack(">d", v)
    if isinstance(v, str):
        s = v.encode()
        return b"\xdb" + struct.pack(">I", len(s)) + s
    if isinstance(v, bytes):
        return b"\xc6" + struct.pack(">I", len(v)) + v
    if isinstance(v, list):
        return b"\xdd" + struct.pack(">I", len(v)) + b"".join(map(pack, v))
    if isinstance(v, dict):
        return b"\xdf" + struct.pack(">I", len(v)) + b"".join(pack(k) + pack(x)
                                                                for k, x in v.items())
    raise TypeError(type(v))


# ---- forging -------------------------------------------------------------------------

HOSTILE_NUMBERS = [0, -1, 1, 2**31 - 1, 2**32 - 1, 2**53 + 1, 2**63 - 1, 2**64 - 1, -2**63,
                   10**7, 10**6, 100001, 0.0, -0.0, -3000.0, 1e9, 1e308, -1e308, 5e-324,
                   math.nan, math.inf, -math.inf]


def places(v, path=()):
    """Every (path, value) in a decoded payload, containers included."""
    yield path, v
    if isinstance(v, dict):
        for k, x in v.items():
            yield from places(x, path + (k,))
    elif isinstance(v, list):
        for k, x in enumerate(v):
            yield from places(x, path + (k,))


def replace(v, path, new):
    if not path:
        return new
    head, rest = path[0], path[1:]
    if isinstance(v, dict):
        out = dict(v)
    else:
        out = list(v)
    out[head] = replace(v[head], rest, new)
    return out


def hostile(rng, old):
    """A value to put where `old` was."""
    r = rng.random()
    if isinstance(old, (int, float)) and not isinstance(old, bool) and r < 0.6:
        return rng.choice(HOSTILE_NUMBERS)
    if isinstance(old, list) and r < 0.6:
        n = len(old)
        return rng.choice([[], old[:max(n - 1, 0)], old + old[-1:] * rng.randint(1, 4),
                           [rng.choice(HOSTILE_NUMBERS)] * n,
                           Raw(b"\xdd\xff\xff\xff\xff")])  # claims 2^32-1 elements
    if isinstance(old, dict) and r < 0.6 and old:
        k = rng.choice(list(old))
        out = dict(old)
        choice = rng.randrange(3)
        if choice == 0:
            del out[k]
        elif choice == 1:
            out[k + "_x"] = out.pop(k)
        else:
            out["unknown"] = Raw(b"\x91" * 100000 + b"\xc0")  # nested 100 000 deep
        return out
    if isinstance(old, str) and r < 0.6:
        return rng.choice(["", "x" * 70000, "glider", "wheel", "\u0000", "é"])
    return rng.choice([None, True, "text", [], {}, 1.5, -1, b"\x00" * 8])


def forge(rng, blob):
    """`blob` (a valid serialized state) with one hostile change in its
    payload, framed again with a correct length and checksum; the path of
    the change. ValueError if `blob` is not a well-formed state."""
    head, payload = unframe(blob)
    value, end = unpack(payload)
    if end != len(payload):
        raise ValueError("not a well-formed state (bytes after the payload)")
    path, old = rng.choice(list(places(value)))
    return frame(head, pack(replace(value, path, hostile(rng, old)))), path


# ---- physical forgeries of multi-body states (issue 30) ---------------------------------

def _sim(value):
    sim = value.get("sim") if isinstance(value, dict) else None
    return sim if isinstance(sim, dict) and isinstance(sim.get("dynamic"), dict) else None


def _height(body):
    """The vertical position of a decoded BodyState (position is [x, y])."""
    p = body.get("position") if isinstance(body, dict) else None
    return p[1] if isinstance(p, list) and len(p) == 2 else None


def forge_physics(rng, blob, contact_bodies=frozenset()):
    """`blob` with one physically hostile change of a running multi-body
    state, framed again: two bodies swapped, a NaN in a body, a body vector
    or the coupling loads shortened or lengthened, a non-finite coupling
    load, an exit or event time outside [0, time]. Returns (blob, what,
    must_refuse): `must_refuse` is True where the FMU has to refuse it (a
    swap only where one of the two bodies carries a contact, an index in
    `contact_bodies`, and their heights differ by more than 1 cm: then a
    body no longer sits where its contact says; a swap of two bodies
    without contacts, such as a car body and a bogie, is not detectable
    from contact geometry). None if `blob` holds no running state to
    change."""
    head, payload = unframe(blob)
    value, end = unpack(payload)
    sim = _sim(value) if end == len(payload) else None
    if sim is None:
        return None
    dyn = sim["dynamic"]
    bodies = dyn.get("bodies") or []
    time = sim.get("time", 0.0)
    kinds = ["nan body", "body count", "coupling count", "coupling nan", "exit time",
             "event time"]
    if len(bodies) >= 2:
        kinds += ["swap"] * 4
    kind = rng.choice(kinds)
    must = True
    if kind == "swap":
        i, j = rng.sample(range(len(bodies)), 2)
        yi, yj = _height(bodies[i]), _height(bodies[j])
        must = (yi is not None and yj is not None and abs(yi - yj) > 0.01
                and bool({i, j} & set(contact_bodies)))
        bodies = list(bodies)
        bodies[i], bodies[j] = bodies[j], bodies[i]
        dyn = dict(dyn, bodies=bodies)
    elif kind == "nan body" and bodies:
        k = rng.randrange(len(bodies))
        body = dict(bodies[k])
        body["position"] = [math.nan, _height(bodies[k]) or 0.0]
        dyn = dict(dyn, bodies=bodies[:k] + [body] + bodies[k + 1:])
    elif kind == "body count" and bodies:
        dyn = dict(dyn, bodies=bodies[:-1] if rng.random() < 0.5 else bodies + bodies[-1:])
    elif kind == "coupling count":
        loads = sim.get("coupling_loads") or []
        sim = dict(sim, coupling_loads=loads + [[0.0, 0.0, 0.0]] if rng.random() < 0.5 or
                   not loads else loads[:-1])
    elif kind == "coupling nan":
        loads = sim.get("coupling_loads") or []
        if not loads:
            return None
        k = rng.randrange(len(loads))
        bad = rng.choice([math.nan, math.inf, -math.inf])
        sim = dict(sim, coupling_loads=loads[:k] + [[bad, 0.0, 0.0]] + loads[k + 1:])
    elif kind == "exit time":
        sim = dict(sim, exit_time=rng.choice([-1.0, time + 1.0, 1e300, -5e-324]))
    elif kind == "event time":
        events = list(sim.get("events") or [])
        if not events:
            return None
        k = rng.randrange(len(events))
        events[k] = dict(events[k], time=rng.choice([-1.0, time + 1.0, 1e300]))
        sim = dict(sim, events=events)
    else:
        return None
    if kind in ("swap", "nan body", "body count"):
        sim = dict(sim, dynamic=dyn)
    value = dict(value, sim=sim)
    return frame(head, pack(value)), kind, must


# ---- why an accepted forgery is acceptable (issue 30) -------------------------------

# Run integrals and solver diagnostics: sums over the path the run took, not
# functions of the state, so no check of the state can tell a forged value
# from a true one; they feed only the energy books and diagnostics outputs.
RUN_INTEGRALS = {"dissipated", "beam_dissipated", "tractive_work", "numerical_dissipation",
                 "external_work", "gravity_work", "initial_energy", "impact_loss", "steps",
                 "total_iterations", "last_iterations", "last_position_iterations",
                 "last_velocity_error", "last_gap_error", "events_dropped"}
# Histories the next step extrapolates from (loads, step sizes, impulses):
# any finite values are a possible past of some run.
HISTORIES = {"force_history", "step_history", "last_applied", "pending_restart",
             "vehicle_forces", "coupling_loads"}
# The phase-space point of beam and bodies: any finite values are a
# possible initial condition, except a body height that leaves a closed
# contact (checked below).
PHASE = {"beam_displacement", "beam_velocity", "beam_acceleration", "body_accelerations",
         "beam_load", "body_loads", "bodies", "contact_x"}
CONTACT_HISTORY = {"impulse", "gap"}


def _finite_numbers(v):
    """True if `v` is a number or nested lists/dicts of finite numbers only."""
    if isinstance(v, bool):
        return False
    if isinstance(v, (int, float)):
        return math.isfinite(v)
    if isinstance(v, list):
        return all(_finite_numbers(x) for x in v)
    if isinstance(v, dict):
        return all(_finite_numbers(x) for x in v.values())
    return False


def _at(v, path):
    for p in path:
        v = v[p]
    return v


def _shape(v):
    """The lengths and keys of `v` without its numbers."""
    if isinstance(v, list):
        return [_shape(x) for x in v]
    if isinstance(v, dict):
        return {k: _shape(x) for k, x in v.items()}
    return "number" if isinstance(v, (int, float)) and not isinstance(v, bool) else repr(v)


def payload(blob):
    """The decoded payload of a serialized state, packed again: equal for
    two states that hold the same values."""
    value, _ = unpack(unframe(blob)[1])
    return pack(value)


def classify_accepted(blob, forged, path, contact_bodies):
    """Why the FMU may accept `forged` (`blob` with a change at `path`), or
    None if no benign reason holds (then accepting it is a fuzzer failure).
    Reasons: the payload decodes to the same values; a parameter or input
    (the caller checks it reachable through fmi2Set*); a run integral or
    diagnostic; a history or phase-space value moved to another finite value
    of the same shape, not lifting a body out of a closed contact."""
    old, _ = unpack(unframe(blob)[1])
    new, end = unpack(unframe(forged)[1])
    if pack(old) == pack(new):
        return "unchanged value"
    if pack(_as_read(old)) == pack(_as_read(new)):
        return "unchanged as read (unknown field ignored, absent field its default)"
    if pack(_as_read(_without_integrals(old))) == pack(_as_read(_without_integrals(new))):
        return "run integral or diagnostic"  # one dropped: it reads as 0
    if "input_history" in old and pack(_as_read(dict(old, input_history=None))) == pack(
            _as_read(new)):
        return "input history dropped (inputs held over the next step, as after a restart)"
    if path and path[0] in ("scene", "inputs", "input_history", "start_time"):
        # Parameters are numbers: a scene whose names, kinds, flags or list
        # lengths changed is not the FMU's scene with parameters moved.
        if _text_leaves(_as_read(old.get(path[0]))) != _text_leaves(_as_read(new.get(path[0]))):
            return None
        return "parameter or input, reachable through fmi2Set*"
    if path == ("sim",) and _only_histories_differ(old["sim"], new["sim"]):
        return "history, finite"  # one renamed or dropped reads as none: a restart's
    if len(path) < 2 or path[0] != "sim":
        return None
    try:
        before, after = _at(old, path), _at(new, path)
    except (KeyError, IndexError, TypeError):
        return None
    if path[1] == "contacts" and path[-1] == "open" and after is True:
        return "contact marked open (a lift-off state; the next step closes it again)"
    after = _as_read(after)
    events = _as_read(new["sim"].get("events")) if path[1] == "events" else None
    contacts, now = len(old["sim"].get("contacts") or []), new["sim"].get("time", 0.0)
    if events is not None and _event_log(events, contacts, now):
        return "event log, another past (reported, never stepped on)"
    if path[1] in HISTORIES and _finite_numbers(after):
        return "history, finite"  # a shorter or longer history: another past
    if not _finite_numbers(after) or _shape(before) != _shape(after):
        return None
    field = path[2] if path[1] == "dynamic" and len(path) > 2 else path[1]
    if field in RUN_INTEGRALS:
        return "run integral or diagnostic"
    if path[1] != "dynamic" and field in HISTORIES:
        return "history, finite"
    if path[1] == "contacts" and len(path) > 3 and path[3] in CONTACT_HISTORY:
        return "contact history, finite"
    if path[1] == "dynamic" and field in PHASE:
        if field == "bodies" and _lifts_closed_contact(old, new, contact_bodies):
            return None
        return "phase-space point, finite"
    return None


def _only_histories_differ(old, new):
    """True if, as read, the two simulation states differ only in
    histories, each absent or finite in `new`."""
    a, b = _as_read(old), _as_read(new)
    differ = {k for k in set(a) | set(b) if a.get(k) != b.get(k)}
    return bool(differ) and all(
        k in HISTORIES and (k not in b or _finite_numbers(b[k])) for k in differ)


def _event_log(events, contacts, now):
    """A list of events (as read: a zero field absent), each of a known
    contact at a finite time no later than the state's `now`."""
    return isinstance(events, list) and all(
        isinstance(e, dict) and type(e.get("contact", 0)) is int
        and 0 <= e.get("contact", 0) < contacts and _finite_numbers(e.get("time", 0.0))
        and e.get("time", 0.0) <= now for e in events)


def _lifts_closed_contact(old, new, contact_bodies):
    """True if a body with a closed contact moved up or down by > 1 cm."""
    contacts = old["sim"].get("contacts") or []
    bodies_old, bodies_new = old["sim"]["dynamic"]["bodies"], new["sim"]["dynamic"]["bodies"]
    for c, k in enumerate(sorted(contact_bodies)):
        closed = c < len(contacts) and not contacts[c].get("open", True)
        yo, yn = _height(bodies_old[k]), _height(bodies_new[k])
        if closed and yo is not None and yn is not None and abs(yo - yn) > 0.01:
            return True
    return False


# TrackPart's unit variants in declaration order (src/system.rs): the
# decoder reads a variant index as the variant.
TRACK_PARTS = ["Approach", "Beam", "RunOff", "Beyond"]


def _as_read(v, key=None):
    """`v` as serde reads it: unknown fields (`unknown`, a renamed `k_x`)
    ignored, an absent field the same as its default (none, empty, zero),
    bytes a list of integers, a track part's variant index its name."""
    if isinstance(v, bytes) and not isinstance(v, Raw):
        return list(v)
    if key == "parts" and isinstance(v, list):
        return [TRACK_PARTS[x] if isinstance(x, int) and not isinstance(x, bool)
                and 0 <= x < len(TRACK_PARTS) else _as_read(x) for x in v]
    if isinstance(v, list):
        return [_as_read(x) for x in v]
    if isinstance(v, dict):
        return {k: _as_read(x, k) for k, x in v.items()
                if x is not None and x != [] and not (type(x) in (int, float) and x == 0)
                and k != "unknown" and not (k.endswith("_x") and k[:-2] not in v and k[:-2])}
    return v


def _without_integrals(v):
    """`v` without the run integrals and diagnostics anywhere in it."""
    if isinstance(v, dict):
        return {k: _without_integrals(x) for k, x in v.items()
                if k not in RUN_INTEGRALS and k.removesuffix("_x") not in RUN_INTEGRALS}
    if isinstance(v, list):
        return [_without_integrals(x) for x in v]
    return v


def _text_leaves(v, path=()):
    """The (path, value) of every leaf of `v` that is not a number."""
    if isinstance(v, dict):
        return set().union(*(_text_leaves(x, path + (k,)) for k, x in v.items()))
    if isinstance(v, list):
        return set().union(*(_text_leaves(x, path + (k,)) for k, x in enumerate(v)))
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return set()
    return {(path, repr(v))}

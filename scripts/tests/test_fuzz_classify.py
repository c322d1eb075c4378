"""The FMI fuzzer's sorting of accepted forged states (issue 30): each
forgery of a small hand-made two-body state is given the benign reason
written here by hand, and the forgeries that no reason covers get none
(so that the fuzzer fails on them)."""

import pathlib
import struct
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
import fuzz_state as fs  # noqa: E402

HEAD = fs.MAGIC + struct.pack("<I", 3) + struct.pack("<I", 4) + b"guid"
# Body 0 is a car body without contact, body 1 a wheelset on a closed contact.
STATE = {
    "scene": {"name": "s", "body": {"name": "car", "mass": 1000.0}},
    "inputs": [0.0, 0.0],
    "start_time": 0.0,
    "input_history": {"time": 0.1, "values": [0.0, 0.0]},
    "sim": {
        "time": 0.2,
        "dynamic": {"bodies": [{"position": [0.0, 1.5]}, {"position": [0.0, 0.5]}],
                    "beam_displacement": [0.0, 0.0], "dissipated": 0.0},
        "contacts": [{"open": False, "gap": 0.0, "impulse": [0.0, 0.0], "landed_in": None}],
        "step_history": [0.001, 0.001],
        "events": [{"contact": 0, "time": 0.05, "kind": "Entry"}],
        "steps": 200,
        "exit_time": None,
    },
}
CONTACT_BODIES = {1}


def why(path, new):
    blob = fs.frame(HEAD, fs.pack(STATE))
    return fs.classify_accepted(blob, fs.frame(HEAD, fs.pack(fs.replace(STATE, path, new))),
                                path, CONTACT_BODIES)


def test_benign_forgeries_are_named_by_their_reason():
    assert why(("sim", "steps"), 200) == "unchanged value"
    assert why(("sim", "contacts", 0), {"open": False, "gap": 0.0, "impulse": [0.0, 0.0],
                                        "landed_in_x": None}).startswith("unchanged as read")
    assert why(("input_history",), None).startswith("input history dropped")
    sim = {k: x for k, x in STATE["sim"].items() if k != "steps"}
    # A renamed field whose value was not its default is missing, not unchanged.
    timeless = {k: x for k, x in STATE["sim"].items() if k != "time"}
    assert why(("sim",), dict(timeless, time_x=0.2)) is None
    dynamic = {k: x for k, x in STATE["sim"]["dynamic"].items() if k != "dissipated"}
    assert why(("sim", "dynamic"), dict(dynamic, dissipated_x=0.0)).startswith("unchanged as")
    assert why(("sim",), dict(sim, parts=[1])) is None  # a field the state lacks
    parts = dict(STATE, sim=dict(STATE["sim"], parts=["Beam"]))
    blob = fs.frame(HEAD, fs.pack(parts))
    by_index = fs.frame(HEAD, fs.pack(fs.replace(parts, ("sim", "parts"), [1])))
    assert fs.classify_accepted(blob, by_index, ("sim", "parts"), CONTACT_BODIES).startswith(
        "unchanged as read")
    assert why(("scene", "body", "mass"), 2000.0).startswith("parameter or input")
    assert why(("sim", "steps"), 7) == "run integral or diagnostic"
    assert why(("sim", "dynamic", "dissipated"), 1e9) == "run integral or diagnostic"
    assert why(("sim",), {k: x for k, x in STATE["sim"].items() if k != "steps"}) == \
        "run integral or diagnostic"
    assert why(("sim", "step_history"), [0.002]) == "history, finite"
    assert why(("sim", "contacts", 0, "open"), True).startswith("contact marked open")
    # The car body, without a contact, may be anywhere finite.
    assert why(("sim", "dynamic", "bodies", 0, "position", 1), 9.0).startswith("phase-space")
    # The wheelset by less than 1 cm too.
    assert why(("sim", "dynamic", "bodies", 1, "position", 1), 0.505).startswith("phase-space")
    # A history renamed, so read as absent (seed 802313): a restart's past.
    renamed = {k: x for k, x in STATE["sim"].items() if k != "step_history"}
    assert why(("sim",), dict(renamed, step_history_x=[0.001])) == "history, finite"
    # An event dropped from the log (found by seed 700112): another past.
    assert why(("sim", "events"), []).startswith("event log")
    # An event's time moved within the run (seed 703628).
    assert why(("sim", "events", 0, "time"), 0.0).startswith("event log")


def test_forgeries_without_a_benign_reason_get_none():
    # The wheelset 1 m above its closed contact.
    assert why(("sim", "dynamic", "bodies", 1, "position", 1), 1.5) is None
    # A name or a list length of the scene is no parameter.
    assert why(("scene", "body", "name"), "other") is None
    # Non-finite numbers, an exit before the state's time, a retyped flag.
    assert why(("sim", "dynamic", "beam_displacement", 0), float("nan")) is None
    assert why(("sim", "exit_time"), 0.1) is None
    assert why(("sim", "contacts", 0, "open"), None) is None
    assert why(("sim", "dynamic", "beam_displacement"), [0.0]) is None
    # An event of a contact the model does not have, or at no finite time.
    assert why(("sim", "events"), [{"contact": 3, "time": 0.05, "kind": "Entry"}]) is None
    assert why(("sim", "events"), [{"contact": 0, "time": float("inf"), "kind": "Exit"}]) is None
    assert why(("sim", "events", 0, "contact"), 5) is None
    assert why(("sim", "events", 0, "time"), 0.3) is None  # after the state's time


def test_a_parameter_moved_to_zero_or_the_input_time_moved_is_a_parameter_move():
    assert why(("scene", "body", "mass"), 0.0).startswith("parameter or input")
    assert why(("input_history", "time"), 0.0).startswith("parameter or input")

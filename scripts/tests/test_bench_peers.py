"""scripts/bench_peers.py's own logic, without running Exudyn: the scene
edits, the parsing of the runs' results, the pairing rule, the order of a
round."""

import json
import sys
import tomllib
from types import SimpleNamespace

import pytest

from conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))

import bench_peers  # noqa: E402

SCENE = """name = "x"
[beam]
length = 24.0
elements = 2                        # Hermite cubic elements, >= 1
[solver]
step = 0.0025                       # s
velocity_tolerance = 1e-7
max_iterations = 50
integrator = "rk4"                  # rk4 | hht | auto
numerical_damping = 0.0
"""


def test_scene_edits_set_mesh_solver_and_modes():
    text = bench_peers.edit_scene(SCENE, 32, 0.00125, "hht", 0.05, 1e-11)
    scene = tomllib.loads(text)
    assert scene["beam"]["elements"] == 32
    assert scene["solver"] == {"step": 0.00125, "velocity_tolerance": 1e-11,
                               "max_iterations": 200, "integrator": "hht",
                               "numerical_damping": 0.05}
    modal = tomllib.loads(bench_peers.edit_scene(SCENE, 32, 0.0025, "rk4", modes=6))
    assert modal["solver"]["structure"] == "modal"
    assert modal["solver"]["modes"] == 6
    assert modal["solver"]["integrator"] == "rk4"
    assert "structure" not in tomllib.loads(text)["solver"]


def test_scene_edits_refuse_a_scene_they_do_not_fit():
    with pytest.raises(ValueError, match="elements"):
        bench_peers.edit_scene(SCENE.replace("elements = 2", "cells = 2"), 32, 0.0025, "rk4")
    twice = SCENE + 'structure = "full"\n'
    with pytest.raises(ValueError, match="structure"):
        bench_peers.edit_scene(twice, 32, 0.0025, "rk4", modes=4)


def test_edits_of_the_built_in_scene_run(tmp_path):
    guideway = bench_peers.GUIDEWAY
    if not guideway.exists():
        pytest.skip("target/release/guideway is not built")
    scene = tmp_path / "modal.toml"
    text = bench_peers.guideway_scene(32, 0.0025, "rk4", modes=4)
    scene.write_text(text.replace("initial_position = 0.0", "initial_position = 23.0"))
    summary = tmp_path / "summary.json"
    bench_peers.sh([str(guideway), "run", str(scene), "-q", "--summary", str(summary)])
    speed, solve = bench_peers.parse_result("guideway", summary.read_text())
    assert speed == pytest.approx(10.0, abs=0.1) and solve > 0


def test_results_are_parsed_per_code():
    guideway = json.dumps({"exit_nominal_speed": 9.96, "wall_time_s": 0.002, "steps": 909})
    assert bench_peers.parse_result("guideway", guideway) == (9.96, 0.002)
    exudyn = json.dumps({"exitSpeed": 9.99, "wallSolve_s": 1.2})
    assert bench_peers.parse_result("exudyn", exudyn) == (9.99, 1.2)
    for bad in ({"exit_nominal_speed": None, "wall_time_s": 0.1}, {"wall_time_s": 0.1}):
        with pytest.raises(ValueError, match="no exit speed"):
            bench_peers.parse_result("guideway", json.dumps(bad))
    with pytest.raises(ValueError):
        bench_peers.parse_result("exudyn", "not json")


def run(label, error, time):
    return SimpleNamespace(label=label, error=error, time=time)


def pair(exudyn, guideway):
    pairs = bench_peers.pairings(exudyn, guideway, lambda c: c.error, lambda c: c.time)
    return [(e.label, g.label if g else None) for e, g in pairs]


def test_each_exudyn_run_gets_the_cheapest_guideway_run_at_least_as_accurate():
    guideway = [run("modal4", 1.4e-3, 0.008), run("modal6", 4.4e-4, 0.009),
                run("modal8", 1.0e-4, 0.010), run("hht-0.625", 2.8e-4, 0.032),
                run("hht-2.5", 2.8e-3, 0.016)]
    exudyn = [run("e-0.25", 2.2e-4, 2.5), run("e-1", 1.2e-3, 1.4), run("e-0.5", 4.5e-4, 1.8)]
    # cheapest Exudyn run first; an equal error counts as at least as accurate
    assert pair(exudyn, guideway) == [("e-1", "modal6"), ("e-0.5", "modal6"),
                                      ("e-0.25", "modal8")]
    assert pair([run("e", 4.4e-4, 1.0)], guideway) == [("e", "modal6")]
    # none accurate enough: paired with nothing, not with the most accurate
    assert pair([run("e", 1e-5, 1.0)], guideway) == [("e", None)]
    assert pair([run("e", 1e-3, 1.0)], []) == [("e", None)]


def test_a_round_alternates_and_runs_everything_once():
    a, b = [f"g{i}" for i in range(10)], ["e1", "e2", "e3"]
    order = bench_peers.alternate(a, b)
    assert sorted(order) == sorted(a + b)
    assert [x for x in order if x in b] == b
    assert order[0] == "g0"
    assert all(not (x in b and y in b) for x, y in zip(order, order[1:]))
    # the first and last Exudyn runs are not bunched at one end
    assert 1 <= order.index("e1") <= 4 and order.index("e3") >= len(order) - 4
    assert bench_peers.alternate([], b) == b
    assert bench_peers.alternate(a, []) == a


def test_ratios_are_taken_round_by_round():
    assert bench_peers.ratios([2.0, 3.0], [1.0, 0.5]) == [2.0, 6.0]
    assert bench_peers.spread([3.0, 1.0, 2.0]) == (2.0, 1.0, 3.0)


def test_a_timed_run_is_killed_at_its_bound_and_a_failure_is_an_error():
    with pytest.raises(bench_peers.subprocess.TimeoutExpired):
        bench_peers.run_bounded(["sleep", "5"], 0.2)
    with pytest.raises(bench_peers.subprocess.CalledProcessError):
        bench_peers.run_bounded(["false"], 5.0)
    bench_peers.run_bounded(["true"], 5.0)

"""scripts/bench_peers.py's own logic, without running a peer: the scene
edits, the parsing of the runs' results, the pairing rule, the order of a
round, the ratios; the OpenSees half's references, shape functions and
pairing within the reference's resolution."""

import json
import sys
import tomllib
from types import SimpleNamespace

import numpy as np
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
        pytest.skip(f"{guideway} is not built")
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


# The OpenSees half: references, shape functions, pairing within the
# reference's resolution, the ratio rows, on numbers whose answer is known.

from peers import opensees_bench, opensees_models, references  # noqa: E402
from peers.timing import Config  # noqa: E402


def test_a_slow_force_at_midspan_deflects_the_beam_as_the_static_closed_form():
    # α = 0.001: the series' midspan deflection when the force is at
    # midspan is the static P L³ / (48 EI) (within α², and the series' tail).
    case = dict(length=24.0, mass_per_length=1250.0, bending_stiffness=1e9, force=600e3)
    omega1 = (3.141592653589793 / 24.0) ** 2 * (1e9 / 1250.0) ** 0.5
    case["speed"] = 0.001 * omega1 * 24.0 / 3.141592653589793
    half = 12.0 / case["speed"]
    static = 600e3 * 24.0**3 / (48.0 * 1e9)
    assert references.fryba_midspan(case, [half])[0] == pytest.approx(-static, rel=1e-4)
    assert references.green(24.0, 1e9, 12.0, 12.0) == pytest.approx(static / 600e3, rel=1e-12)
    assert references.green(24.0, 1e9, 6.0, 18.0) == references.green(24.0, 1e9, 18.0, 6.0)
    with pytest.raises(ValueError, match="resonance"):
        references.fryba_midspan(dict(case, speed=omega1 * 24.0 / 3.141592653589793), [0.1])


def test_the_history_error_is_the_largest_difference_over_the_passage_over_the_peak():
    times = [0.0, 0.1, 0.2, 0.3, 0.4]
    reference = lambda t: -2.0 * np.asarray(t)  # noqa: E731
    values = [0.0, -0.2, -0.41, -0.6, 5.0]  # the last row is past the passage
    assert references.history_error(times, values, reference, 0.3) == pytest.approx(0.01 / 0.6)
    with pytest.raises(ValueError, match="no row"):
        references.history_error([0.5], [0.0], reference, 0.3)


def test_hermite_shape_functions_interpolate_a_cubic_and_share_a_load():
    length, elements = 24.0, 8
    cubic = lambda x: 1e-3 * x**3 - 0.02 * x**2 + 0.1 * x  # noqa: E731
    slope = lambda x: 3e-3 * x**2 - 0.04 * x + 0.1  # noqa: E731
    for x in (0.0, 1.3, 12.0, 17.9, 24.0):
        e, shape, dshape = opensees_models.hermite(x, length, elements)
        nodes = [e * 3.0, (e + 1) * 3.0]
        dofs = [cubic(nodes[0]), slope(nodes[0]), cubic(nodes[1]), slope(nodes[1])]
        assert sum(s * d for s, d in zip(shape, dofs)) == pytest.approx(cubic(x), abs=1e-12)
        assert sum(s * d for s, d in zip(dshape, dofs)) == pytest.approx(slope(x), abs=1e-12)
        # The nodal forces add up to the force, their moments about x to nothing.
        assert shape[0] + shape[2] == pytest.approx(1.0)
        moment = shape[1] + shape[3] + shape[0] * (nodes[0] - x) + shape[2] * (nodes[1] - x)
        assert moment == pytest.approx(0.0, abs=1e-12)


def case_run(code, case, label, error, process, solve):
    config = Config(code, label, [], None, 8, 0.001)
    config.case, config.error = case, error
    config.process, config.solve, config.cpu = process, solve, process
    return config


def test_each_opensees_run_gets_the_cheapest_guideway_run_as_accurate_within_the_resolution():
    runs = [case_run("opensees", "mf", "o-a", 7.434986480e-5, [1.0], [0.5]),
            case_run("opensees", "mf", "o-b", 1e-3, [0.5], [0.1]),
            case_run("guideway", "mf", "g-same", 7.434986489e-5, [0.02], [0.005]),
            case_run("guideway", "mf", "g-fine", 1e-6, [0.05], [0.02]),
            case_run("guideway", "mf", "g-coarse", 9e-4, [0.01], [0.001]),
            case_run("opensees", "sm", "o-c", 1e-7, [2.0], [1.0]),
            case_run("guideway", "sm", "g-other-case", 1e-8, [0.01], [0.001])]
    refs = {"mf": SimpleNamespace(resolution=1e-9), "sm": SimpleNamespace(resolution=0.0)}
    paired = opensees_bench.pairs(runs, refs, Config.median_process)
    names = {k: [(o.label, g.label if g else None) for o, g in v] for k, v in paired.items()}
    # An error larger by less than the resolution counts as equal; runs
    # of another case are never candidates.
    assert names == {"mf": [("o-b", "g-coarse"), ("o-a", "g-same")], "sm": [("o-c", "g-other-case")]}
    refs["mf"].resolution = 0.0
    strict = opensees_bench.pairs(runs, refs, Config.median_process)["mf"]
    assert [(o.label, g.label) for o, g in strict] == [("o-b", "g-coarse"), ("o-a", "g-fine")]


def test_the_ratio_rows_and_summary_take_each_round_apart():
    o = case_run("opensees", "mf", "o", 1e-4, [1.0, 2.0, 3.0], [0.5, 0.6, 0.9])
    g = case_run("guideway", "mf", "g", 1e-4, [0.01, 0.01, 0.1], [0.001, 0.002, 0.003])
    h = case_run("guideway", "mf", "h", 1e-5, [0.5, 0.5, 0.5], [0.1, 0.1, 0.1])
    floors = [None, case_run("floor", "", "v", 0, [0.002, 0.004, 0.003], [None] * 3)]
    # g: solve per round 500, 300, 300; process 100, 200, 30 (and CPU);
    # h: solve 5, 6, 9; process 2, 4, 6; floor: 500, 500, 1000
    paired = {"solve": {"mf": [(o, h)], "sm": [(o, None)]},
              "process": {"mf": [(o, g)], "sm": [(o, None)]}}
    rows = opensees_bench.ratio_lines(paired, floors)
    row = next(r for r in rows if r.startswith("| mf |"))
    assert row.replace(" ", "") == (
        "|mf|o|1.00e-04|h|1.00e-05|6×[5,9]|g|1.00e-04|100×[30,200]|100×[30,200]|500×[500,1000]|")
    none = next(r for r in rows if r.startswith("| sm |"))
    assert none.count("|") == row.count("|") and "none as accurate" in none
    assert opensees_bench.summary(paired) == {"mf": pytest.approx((6.0, 6.0, 100.0, 100.0))}


def test_the_case_scenes_are_the_cases():
    for name, case in opensees_bench.CASES.items():
        scene = tomllib.loads(opensees_bench.scene_text(name, 16, 0.001))
        assert scene["beam"]["elements"] == 16 and scene["solver"]["step"] == 0.001
        assert scene["beam"]["bending_stiffness"] == case["bending_stiffness"]
        assert scene["sensors"][0]["position"] == case["length"] / 2
        assert scene["body"]["initial_speed"] == case["speed"]
    sprung = tomllib.loads(opensees_bench.scene_text("sprung_mass", 8, 0.001))
    assert sprung["body"]["suspension"]["unsprung_mass"] == 0.0
    assert opensees_bench.step_of("moving_force", 250) == pytest.approx(
        opensees_bench.passage(opensees_bench.CASES["moving_force"]) / 250)


from peers import error_spectrum  # noqa: E402


def test_error_spectrum_splits_the_modes_bands():
    """A sum of sines at f1, 9 f1 and 30 f1 comes apart into the three
    bands with each amplitude; f1 is the simply supported closed form."""
    case = opensees_bench.CASES["sprung_mass"]
    f1 = error_spectrum.first_frequency(case)
    omega = (np.pi / case["length"]) ** 2 * np.sqrt(case["bending_stiffness"]
                                                    / case["mass_per_length"])
    assert f1 == pytest.approx(omega / (2 * np.pi), rel=1e-12)
    times = np.arange(0, 2.0, 1e-4)
    # Whole periods over the record, so the FFT sees no edge.
    f1 = 1.0 / (times[-1] + 1e-4) * 30
    signal = (3e-4 * np.sin(2 * np.pi * f1 * times) + 2e-4 * np.sin(2 * np.pi * 9 * f1 * times)
              + 1e-4 * np.sin(2 * np.pi * 30 * f1 * times))
    parts = error_spectrum.band_parts(times, signal, f1)
    assert parts == pytest.approx([3e-4, 2e-4, 1e-4], rel=1e-6)


def test_error_spectrum_table_names_every_run():
    found = [("guideway", 8, 1e-3, 2e-3, [1e-3, 2e-4, 1e-4])]
    text = error_spectrum.table(found, 15.3)
    assert "| guideway | 8 | 0.001 | 2.00e-03 | 1.00e-03 | 2.00e-04 | 1.00e-04 |" in text

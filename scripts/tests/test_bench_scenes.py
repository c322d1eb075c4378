"""scripts/bench_scenes.py: the measurement scenes of docs/performance.md
are valid scenes, and the followers' scene is the rail scene without its
rail, its contact laws and its wheelsets' mass."""

import json
import subprocess
import sys
import tomllib

from conftest import GUIDEWAY, ROOT

sys.path.insert(0, str(ROOT / "scripts"))

import bench_scenes  # noqa: E402


def written(tmp_path, *args):
    subprocess.run([sys.executable, str(ROOT / "scripts" / "bench_scenes.py"), str(tmp_path), *args],
                   check=True, capture_output=True)
    return {p.name: tomllib.loads(p.read_text()) for p in tmp_path.glob("*.toml")}


def test_the_followers_are_the_rail_scene_without_the_rail(tmp_path):
    scenes = written(tmp_path)
    rail, followers = scenes["rail.toml"], scenes["followers.toml"]
    assert "on_deck" in rail["track"] and "on_deck" not in followers["track"]
    assert rail["track"]["approach"] == followers["track"]["approach"] == 190.0
    vehicles = [followers["body"], *followers["vehicles"]]
    assert len(vehicles) == 8
    assert all(v["bogie"]["wheelset_mass"] == 0.0 and "contact_law" not in v for v in vehicles)
    assert [v["initial_position"] for v in vehicles] == \
        [v["initial_position"] for v in [rail["body"], *rail["vehicles"]]]
    assert all(s["solver"]["end_time"] == 0.3 for n, s in scenes.items() if n != "S100_1s.toml")
    assert scenes["S100_1s.toml"]["beam"]["elements"] == 2500
    assert scenes["S100_1s.toml"]["solver"]["end_time"] == 1.0


def test_variants_scale_the_track_and_cut_the_train(tmp_path):
    scenes = written(tmp_path, "--track-scale", "2", "--coaches", "2", "--end-time", "0.002")
    sleepers = scenes["sleepers.toml"]
    assert sleepers["track"]["approach"] == 380.0 and sleepers["track"]["run_off"] == 460.0
    assert len(sleepers["vehicles"]) == 1 and sleepers["solver"]["end_time"] == 0.002
    for name in ("rail.toml", "sleepers.toml", "followers.toml"):
        summary = tmp_path / f"{name}.json"
        subprocess.run([str(GUIDEWAY), "run", str(tmp_path / name), "-q", "--summary", str(summary)],
                       check=True, capture_output=True)
        assert json.loads(summary.read_text())["steps"] == 8


def test_more_coaches_than_the_template_has_are_refused(tmp_path):
    result = subprocess.run([sys.executable, str(ROOT / "scripts" / "bench_scenes.py"), str(tmp_path),
                             "--coaches", "9"], capture_output=True, text=True)
    assert result.returncode != 0 and "--coaches 9" in result.stderr
    assert bench_scenes.replaced("end_time = 1\n", "end_time", 2) == "end_time = 2\n"

"""The release built by scripts/test.sh (`guideway release` into
$GUIDEWAY_RELEASE_DIR): cross-check files pass fmpy's validation and agree
with fmpy's own run of each FMU; checksums hold."""

import hashlib
import os
import pathlib
import tomllib

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.cross_check.validate_vendor_repo import validate_test_fmu

from conftest import ROOT, read_csv

RELEASE_ROOT = pathlib.Path(os.environ.get("GUIDEWAY_RELEASE_DIR", ROOT / "out" / "dist"))
VERSION = tomllib.loads((ROOT / "Cargo.toml").read_text())["package"]["version"]
RELEASE = RELEASE_ROOT / VERSION
MODELS = ["lee1994_wheel_1", "lee1994_wheel_10", "lee1994_wheel_100", "lee1994_glider_30"]


def model_dir(model):
    d = RELEASE / "cross-check" / "fmus" / "2.0" / "cs" / "linux64" / "guideway" / VERSION / model
    if not d.is_dir():
        pytest.fail(f"{d} missing: run scripts/test.sh (it builds the release first)")
    return d


def test_the_release_has_one_fmu_per_builtin_scene_and_nothing_else():
    assert sorted(p.stem for p in RELEASE.glob("*.fmu")) == sorted(MODELS)
    coupled = sorted(p.stem for p in (RELEASE / "coupling").glob("*.fmu"))
    assert coupled == sorted(f"{m}_coupling" for m in MODELS)
    models = model_dir(MODELS[0]).parent
    assert sorted(p.name for p in models.iterdir()) == sorted(MODELS)


@pytest.mark.parametrize("model", MODELS)
def test_cross_check_files_pass_fmpys_validation(model):
    assert validate_test_fmu(str(model_dir(model))) == []


@pytest.mark.parametrize("model", MODELS)
def test_fmpy_reproduces_the_reference_result(model):
    d = model_dir(model)
    opt = dict(line.split(",", 1) for line in (d / f"{model}_ref.opt").read_text().splitlines())
    opt = {k.strip(): float(v) for k, v in opt.items()}
    names, ref = read_csv(d / f"{model}_ref.csv")
    result = simulate_fmu(str(d / f"{model}.fmu"), start_time=opt["StartTime"],
                          stop_time=opt["StopTime"], output_interval=opt["StepSize"])
    assert len(result) == len(ref)
    np.testing.assert_allclose(result["time"], ref[:, 0], rtol=0, atol=1e-9)
    for k, name in enumerate(names[1:], start=1):
        scale = max(np.abs(ref[:, k]).max(), 1e-12)
        err = np.abs(result[name] - ref[:, k]).max() / scale
        assert err <= opt["RelTol"], f"{name}: {err:.3g} > RelTol {opt['RelTol']}"


def test_the_fmus_state_the_released_version():
    for model in MODELS:
        md = read_model_description(str(RELEASE / f"{model}.fmu"))
        assert md.version == VERSION
        assert md.generationTool == f"guideway {VERSION}"


def test_sha256sums_match_every_file():
    lines = (RELEASE / "SHA256SUMS").read_text().splitlines()
    listed = {}
    for line in lines:
        digest, path = line.split("  ", 1)
        listed[path] = digest
    files = sorted(p.relative_to(RELEASE).as_posix() for p in RELEASE.rglob("*")
                   if p.is_file() and p.name != "SHA256SUMS")
    assert sorted(listed) == files
    for path in files:
        assert hashlib.sha256((RELEASE / path).read_bytes()).hexdigest() == listed[path], path


def test_release_notes_are_this_versions_changelog_section():
    notes = (RELEASE / "RELEASE_NOTES.md").read_text()
    changelog = (ROOT / "CHANGELOG.md").read_text()
    section = changelog.split(f"## [{VERSION}]", 1)[1].split("\n## ", 1)[0]
    assert section.strip().splitlines()[-1] in notes
    assert "[Unreleased]" not in notes


@pytest.mark.parametrize("model", ["lee1994_wheel_10", "lee1994_glider_30"])
def test_a_coupling_fmu_is_its_model_with_coupling_ports(model):
    """Issue 27 item 3: coupling-ready FMUs in the release. With nothing
    connected (coupling forces 0, their start) it is the plain model, to
    the bit; a coupling force acts on the body."""
    coupled = RELEASE / "coupling" / f"{model}_coupling.fmu"
    md = read_model_description(str(coupled))
    body = "wheel" if "wheel" in model else "glider"
    inputs = {v.name for v in md.modelVariables if v.causality == "input"}
    assert {f"{body}.coupling_force_x", f"{body}.coupling_force_y"} <= inputs, inputs
    plain = simulate_fmu(str(RELEASE / f"{model}.fmu"), stop_time=0.3, output_interval=0.01)
    same = simulate_fmu(str(coupled), stop_time=0.3, output_interval=0.01)
    y = f"{body}.y"
    assert np.array_equal(plain[y], same[y])
    pushed = simulate_fmu(str(coupled), stop_time=0.3, output_interval=0.01,
                          start_values={f"{body}.coupling_force_y": -1e5})
    assert pushed[y][-1] < plain[y][-1]

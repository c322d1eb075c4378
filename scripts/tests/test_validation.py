"""The FMUs of the built-in scenes pass fmpy's and fmutool's checks."""

import shutil
import subprocess
import zipfile

import pytest
from fmpy import read_model_description
from fmpy.cross_check.validate_vendor_repo import validate_test_fmu
from fmpy.validation import validate_fmu

from conftest import FMU_DIR, ROOT, SCENES, WHEEL, GLIDER, fmu_path, identifier


@pytest.mark.parametrize("scene", SCENES)
def test_validate_fmu_reports_no_problem(scene):
    assert validate_fmu(str(fmu_path(scene))) == []


@pytest.mark.parametrize("scene", SCENES)
def test_fmutool_check_passes(scene):
    r = subprocess.run(
        [str(ROOT / ".venv" / "bin" / "fmutool"), "-input", str(fmu_path(scene)), "-check"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    out = r.stdout + r.stderr
    assert r.returncode == 0, out
    assert "compliant with FMI-2.0" in out, out
    assert "No semantic error" in out, out
    assert "ERROR" not in out, out


def test_glider_has_no_wheel_only_variables_and_wheel_has_them():
    g = {v.name for v in read_model_description(str(fmu_path(GLIDER))).modelVariables}
    w = {v.name for v in read_model_description(str(fmu_path(WHEEL))).modelVariables}
    for name in ["radius", "inertia", "angular_velocity"]:
        assert f"wheel.{name}" in w
        assert f"glider.{name}" not in g
    assert "contact.tangential_force" in w and "contact.tangential_force" not in g
    for names in (g, w):
        assert "sensor.midspan.position" in names and "sensor.midspan.deflection" in names


@pytest.mark.parametrize("scene", SCENES)
def test_fmu_is_self_contained_and_documented(scene):
    md = read_model_description(str(fmu_path(scene)))
    with zipfile.ZipFile(fmu_path(scene)) as z:
        names = set(z.namelist())
        assert f"binaries/linux64/{md.coSimulation.modelIdentifier}.so" in names
        assert "resources/scene.toml" in names
        assert "documentation/style.css" in names
        html = z.read("documentation/index.html").decode()
    for v in md.modelVariables:
        assert f"<code>{v.name}</code>" in html, v.name
    assert md.guid in html
    assert md.generationTool.startswith("guideway ")
    assert float(md.defaultExperiment.stepSize) > 0


@pytest.mark.parametrize("scene", SCENES)
def test_cross_check_files_follow_the_rules(scene, tmp_path):
    ident = identifier(scene)
    model_dir = tmp_path / "fmus" / "2.0" / "cs" / "linux64" / "guideway" / "0.1.0" / ident
    model_dir.mkdir(parents=True)
    shutil.copy(fmu_path(scene), model_dir / f"{ident}.fmu")
    for suffix in ["_ref.csv", "_ref.opt"]:
        shutil.copy(FMU_DIR / "cross-check" / f"{ident}{suffix}", model_dir)
    assert validate_test_fmu(str(model_dir)) == []

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
    version = read_model_description(str(fmu_path(scene))).generationTool.split()[1]
    model_dir = tmp_path / "fmus" / "2.0" / "cs" / "linux64" / "guideway" / version / ident
    model_dir.mkdir(parents=True)
    shutil.copy(fmu_path(scene), model_dir / f"{ident}.fmu")
    for suffix in ["_ref.csv", "_ref.opt"]:
        shutil.copy(FMU_DIR / "cross-check" / f"{ident}{suffix}", model_dir)
    assert validate_test_fmu(str(model_dir)) == []


@pytest.mark.parametrize("scene", SCENES)
def test_no_output_depends_directly_on_an_input(scene):
    """Outputs are the state at a communication point: declared
    dependencies="" (present and empty), so masters see no algebraic loop.
    Initial unknowns depend only on parameters and inputs."""
    md = read_model_description(str(fmu_path(scene)))
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    assert {u.variable.name for u in md.outputs} == {v.name for v in outputs}
    for u in md.outputs:
        assert u.dependencies == [], u.variable.name
    assert {u.variable.name for u in md.initialUnknowns} == {v.name for v in outputs}
    for u in md.initialUnknowns:
        assert u.dependencies is not None, u.variable.name
        for d in u.dependencies:
            assert d.causality in ("parameter", "input"), (u.variable.name, d.name)


def test_start_contact_force_depends_on_the_load_input():
    md = read_model_description(str(fmu_path(WHEEL)))
    deps = {u.variable.name: [d.name for d in u.dependencies] for u in md.initialUnknowns}
    # (a wheel started above the track carries no contact force: since every
    # vehicle field became a parameter, wheel.initial_height is one, and the
    # export's measurement finds that dependency too)
    assert sorted(deps["contact.normal_force"]) == ["wheel.force_y", "wheel.initial_height"]
    assert deps["wheel.x"] == ["wheel.initial_position"]
    assert deps["sensor.midspan.deflection"] == []


def test_units_bounds_and_nominals_are_declared():
    md = read_model_description(str(fmu_path(WHEEL)))
    v = {x.name: x for x in md.modelVariables}
    shown = {u.name: {d.name: d.factor for d in u.displayUnits} for u in md.unitDefinitions}
    assert shown["N"] == {"kN": 0.001}
    assert shown["m/s"] == {"km/h": 3.6}
    assert shown["m"] == {"mm": 1000.0}
    assert v["wheel.force_y"].displayUnit == "kN"
    assert v["wheel.initial_speed"].displayUnit == "km/h"
    assert v["sensor.midspan.deflection"].displayUnit == "mm"
    # the scene's rules with its magnitude limit: > 0 and >= 1e-15, |x| <= 1e15
    assert (float(v["wheel.mass"].min), float(v["wheel.mass"].max)) == (1e-15, 1e15)
    assert float(v["beam.surface_offset"].min) == 0.0
    assert (float(v["wheel.force_y"].min), float(v["wheel.force_y"].max)) == (-1e15, 1e15)
    assert (int(v["beam.elements"].min), int(v["beam.elements"].max)) == (1, 100000)
    assert float(v["beam.bending_stiffness"].nominal) == 1e9
    assert float(v["contact.normal_force"].nominal) == 1e5


def test_outputs_at_start_follow_the_inputs_set_in_initialization(slave):
    s = slave(WHEEL).init(**{"wheel.force_y": -250e3})
    assert s.real("contact.normal_force") == [250e3]

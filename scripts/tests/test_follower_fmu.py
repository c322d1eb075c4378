"""A scene with a massless follower (sprung_mass, unsprung_mass = 0) through
the FMU: it exports, its variables are the follower's (no unsprung body),
and fmpy runs it to the native results, slack follower and all."""

import subprocess

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

from conftest import GUIDEWAY, native_reference, read_csv, set_in_toml

M, G = 5750.0, 9.81

# Yang & Yau's 25 m beam, 10 elements: the beam of both scenes below.
YANG_YAU_BEAM = """[beam]
length = 25.0
mass_per_length = 2303.0
bending_stiffness = 8.5347e10
surface_offset = 0.0
elements = 10
"""

# Yang & Yau's quarter car over their beam with HHT-α, from the approach
# onto the run-off, where a 50 mm bump unloads the follower (contact open).
SCENE = f"""
name = "follower-fmu"
gravity = {G}
{YANG_YAU_BEAM}[track]
approach = 10.0
run_off = 40.0
[[track.irregularities]]
type = "cosine_dip"
position = 35.0
wavelength = 4.0
depth = -0.05
[body]
name = "car"
kind = "sprung_mass"
mass = {M}
initial_position = -5.0
initial_speed = 27.78
[body.suspension]
stiffness = 1.595e6
damping = 2.0e4
unsprung_mass = 0.0
[[sensors]]
name = "midspan"
position = 12.5
[solver]
integrator = "hht"
step = 2.5e-4
end_time = 1.6
"""


def export_with_cross_check(d, stem, scene, reference):
    """Export `scene` into `d` with its native cross-check run; the FMU's
    path and the native reference's rows."""
    (d / f"{stem}.toml").write_text(scene)
    fmu, cc = d / f"{stem}.fmu", d / "cc"
    subprocess.run([str(GUIDEWAY), "export", str(d / f"{stem}.toml"), "-o", str(fmu),
                    "--cross-check", str(cc)], check=True, capture_output=True)
    return str(fmu), read_csv(cc / reference)


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    return export_with_cross_check(tmp_path_factory.mktemp("follower"), "follower", SCENE,
                                   "follower_fmu_ref.csv")


def test_the_follower_scene_exports_with_the_follower_variables(exported):
    fmu, _ = exported
    names = {v.name: v for v in read_model_description(fmu).modelVariables}
    for name in ["car.y", "car.ay", "contact.normal_force", "contact.state", "energy.spring",
                 "energy.dissipated", "energy.balance"]:
        assert names[name].causality == "output", name
    assert names["car.mass"].causality == "parameter"
    # The follower is a contact, not a body.
    assert not any(n.startswith("car_unsprung") for n in names)


def test_fmpy_runs_the_follower_to_the_native_results(exported):
    fmu, (names, data) = exported
    step = data[1, 0] - data[0, 0]  # the reference's communication step
    result = simulate_fmu(fmu, output_interval=step, output=names[1:], stop_time=data[-1, 0])
    assert len(result["time"]) == len(data)
    for k, name in enumerate(names[1:], start=1):
        np.testing.assert_allclose(result[name], data[:, k], rtol=1e-12, atol=0, err_msg=name)
    # Over the bump it goes slack (open, no force) and lands again.
    state, force = result["contact.state"], result["contact.normal_force"]
    assert state[0] == 1 and state[-1] == 1 and np.any(state == 0)
    assert np.all(force[state == 0] == 0.0) and np.all(force[state == 1] > 0.0)
    assert np.all(result["energy.impact_loss"] == 0.0)


def test_the_sprung_mass_start_value_sets_the_follower_preload(tmp_path, exported):
    fmu, _ = exported
    mass = 6000.0
    names, native = native_reference(set_in_toml(SCENE, "body", "mass", mass), tmp_path)
    step = native[1, 0] - native[0, 0]
    n = 400
    result = simulate_fmu(fmu, start_values={"car.mass": mass}, output_interval=step,
                          stop_time=native[n, 0], output=names[1:])
    for k, name in enumerate(names[1:], start=1):
        np.testing.assert_allclose(result[name], native[: n + 1, k], rtol=1e-12, atol=0,
                                   err_msg=name)
    # At rest on the approach the follower carries the new weight.
    assert result["contact.normal_force"][0] == pytest.approx(mass * G, rel=1e-12)


# The coach of tests/vehicles/bogie_vehicle.rs on massless followers (wheelset_mass
# = 0), HHT-α, from the static start on the approach over the 25 m beam.
BOGIE_SCENE = f"""
name = "bogie-followers-fmu"
gravity = {G}
{YANG_YAU_BEAM}[track]
approach = 25.0
run_off = 25.0
[body]
name = "coach"
kind = "bogie_vehicle"
mass = 38884.0
initial_position = -14.0
initial_speed = 27.78
[body.bogie]
car_inertia = 1.95e6
bogie_mass = 2400.0
bogie_inertia = 3200.0
wheelset_mass = 0.0
bogie_half_distance = 8.75
axle_half_distance = 1.25
primary_stiffness = 1.18e6
primary_damping = 2.0e4
secondary_stiffness = 5.3e5
secondary_damping = 2.0e4
[[sensors]]
name = "midspan"
position = 12.5
[solver]
integrator = "hht"
step = 2.5e-4
start = "static"
end_time = 1.0
"""


@pytest.fixture(scope="module")
def exported_bogie(tmp_path_factory):
    return export_with_cross_check(tmp_path_factory.mktemp("bogie_followers"), "bogie",
                                   BOGIE_SCENE, "bogie_followers_fmu_ref.csv")


def test_a_bogie_vehicle_on_followers_exports_its_followers(exported_bogie):
    fmu, _ = exported_bogie
    names = {v.name: v for v in read_model_description(fmu).modelVariables}
    for name in ["coach.ay", "coach.pitch", "coach_bogie1.ay", "coach_bogie1.pitch",
                 "coach_wheelset1.normal_force", "coach_wheelset4.state", "energy.spring"]:
        assert names[name].causality == "output", name
    # The followers are contacts, not bodies: no wheelset positions.
    assert not any(n.startswith("coach_wheelset1.y") for n in names)


def test_fmpy_runs_the_bogie_vehicle_on_followers_to_the_native_results(exported_bogie):
    fmu, (names, data) = exported_bogie
    step = data[1, 0] - data[0, 0]
    result = simulate_fmu(fmu, output_interval=step, output=names[1:], stop_time=data[-1, 0])
    assert len(result["time"]) == len(data)
    for k, name in enumerate(names[1:], start=1):
        np.testing.assert_allclose(result[name], data[:, k], rtol=1e-12, atol=0, err_msg=name)
    # The followers carry the vehicle: each about a quarter of its weight.
    quarter = (38884.0 + 2 * 2400.0) * G / 4
    force = result["coach_wheelset1.normal_force"]
    assert np.all(np.abs(force / quarter - 1) < 0.1)

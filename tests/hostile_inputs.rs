//! Issue 30's defects of the scene, the command line and the FMU, each as a
//! hostile or careless user meets them: products of counts, outputs onto
//! inputs, states the FMU made itself, duplicate names, forged states,
//! pipes and devices, unbounded reads, table paths and messages.

use guideway::scene::{builtin, MAX_CONTACT_ROWS};
use guideway::Scene;
use std::fmt::Write as _;

/// `count` maglev vehicles of `magnets` magnets each on a 100 m beam.
fn maglev_fleet(count: usize, magnets: usize) -> String {
    let mut text = String::from(
        "name = \"fleet\"\ngravity = 9.81\n[beam]\nlength = 100.0\nmass_per_length = 2303.0\n\
         bending_stiffness = 8.5e10\nsurface_offset = 0.0\nelements = 10\n\
         [solver]\nstep = 5e-5\nstart = \"static\"\n",
    );
    for k in 0..count {
        let table = if k == 0 { "[body]" } else { "[[vehicles]]" };
        let sub = if k == 0 { "body" } else { "vehicles" };
        let _ = write!(
            text,
            "{table}\nname = \"car{k}\"\nkind = \"maglev_vehicle\"\nmass = 30000.0\n\
             initial_position = 50.0\ninitial_speed = 0.0\n[{sub}.maglev]\ncar_inertia = 1.5e6\n\
             magnets = {magnets}\nmagnet_spacing = 0.001\nmagnet_mass = 600.0\nstiffness = 8.0e5\n"
        );
    }
    text
}

// ---- 1: the product of vehicles and contacts is bounded ----------------------------

#[test]
fn a_fleet_whose_contacts_would_need_gigabytes_is_refused_naming_the_bound() {
    // 100 vehicles × 1,000 magnets: each count allowed, together 100,000
    // rows (an 80 GB dense matrix on 86becc7, which aborted the process).
    let text = maglev_fleet(100, 1000);
    assert!(text.len() < 30_000, "a small file: {} bytes", text.len());
    let error = Scene::from_toml_str(&text).unwrap_err().to_string();
    assert!(
        error.contains("vehicles = 100 vehicles with 100000 contact rows"),
        "{error}"
    );
    assert!(
        error.contains(&format!("at most {MAX_CONTACT_ROWS} rows")),
        "{error}"
    );
    // 10 × 1,000 (2.4 GB and 296 s before the first step) likewise.
    assert!(Scene::from_toml_str(&maglev_fleet(10, 1000)).is_err());
}

#[test]
fn a_fleet_at_the_contact_bound_is_valid_and_one_more_magnet_is_not() {
    let half = MAX_CONTACT_ROWS / 2;
    let mut at_bound = maglev_fleet(2, half);
    assert!(Scene::from_toml_str(&at_bound).is_ok());
    at_bound = at_bound.replacen(
        &format!("magnets = {half}"),
        &format!("magnets = {}", half + 1),
        1,
    );
    let error = Scene::from_toml_str(&at_bound).unwrap_err().to_string();
    assert!(
        error.contains(&format!("{} contact rows", MAX_CONTACT_ROWS + 1)),
        "{error}"
    );
}

// ---- 4: names unique across vehicles and their generated bodies -------------------

fn with_extra_vehicle(scene: &str, vehicle: &str) -> Result<Scene, String> {
    let text = builtin(scene).unwrap().to_toml_string();
    Scene::from_toml_str(&format!("{text}\n{vehicle}")).map_err(|e| e.to_string())
}

#[test]
fn a_vehicle_named_like_a_generated_body_is_refused() {
    let glider = |name: &str| {
        format!(
            "[[vehicles]]\nname = \"{name}\"\nkind = \"glider\"\nmass = 100.0\n\
             initial_position = -60.0\ninitial_speed = 5.0\n"
        )
    };
    let error = with_extra_vehicle("train-3-coaches-2x25-5", &glider("coach1_bogie1")).unwrap_err();
    assert!(
        error.contains("vehicles[2].name = \"coach1_bogie1\"")
            && error.contains("which body already has"),
        "{error}"
    );
    let error =
        with_extra_vehicle("train-3-coaches-2x25-5", &glider("coach2_wheelset4")).unwrap_err();
    assert!(
        error.contains("\"coach2_wheelset4\", which vehicles[0] already has"),
        "{error}"
    );
    // A name of its own is fine.
    assert!(with_extra_vehicle("train-3-coaches-2x25-5", &glider("coach4")).is_ok());
}

#[test]
fn a_sprung_mass_and_a_glider_named_its_unsprung_mass_are_refused() {
    let text = builtin("lee1994-glider-30").unwrap().to_toml_string();
    let sprung = text
        .replacen("kind = \"glider\"", "kind = \"sprung_mass\"", 1)
        .replacen("name = \"glider\"", "name = \"car\"", 1);
    let sprung = format!(
        "{sprung}\n[body.suspension]\nstiffness = 1e6\nunsprung_mass = 10.0\n\
         [[vehicles]]\nname = \"car_unsprung\"\nkind = \"glider\"\nmass = 10.0\n\
         initial_position = 1.0\ninitial_speed = 1.0\n"
    );
    let error = Scene::from_toml_str(&sprung).unwrap_err().to_string();
    assert!(
        error.contains("\"car_unsprung\", which body already has"),
        "{error}"
    );
}

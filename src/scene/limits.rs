//! Scene rules that bound products of counts (what many vehicles with many
//! contacts cost together) and the uniqueness of every generated body name.
//!
//! Each count of a scene has its own limit (`validate`); these rules catch
//! scenes whose counts are each allowed but whose product would take the
//! memory or time of the host (a 26 KB scene of 100 maglev vehicles with
//! 1,000 magnets each asked for an 80 GB matrix).

use super::{BodySpec, Scene};
use crate::scene::error::Problem;
use std::collections::HashMap;

/// Most rows of the contact iteration over all vehicles (a wheel has two:
/// no-slip and normal; every other contact one). The iteration keeps dense
/// rows × rows operators (the Delassus matrix, its inverse and the gap
/// operator: about 24 bytes × rows²) and factorises them (rows³ / 3 flops):
/// at 2,000 rows that is 96 MB and about 3e9 flops (a few seconds) before
/// the first step; 10,000 rows took 2.4 GB and 296 s. Raise it only with
/// the memory and the time it implies.
pub const MAX_CONTACT_ROWS: usize = 2_000;

/// Bytes of the contact iteration's dense operators for `rows` rows: the
/// Delassus matrix, its inverse and the gap operator, 8 bytes an entry.
pub fn operator_bytes(rows: usize) -> f64 {
    24.0 * (rows as f64).powi(2)
}

/// A byte count at a readable scale (`96 MB`, `240 GB`).
fn bytes_shown(bytes: f64) -> String {
    let units = [(1e12, "TB"), (1e9, "GB"), (1e6, "MB"), (1e3, "kB")];
    match units.iter().find(|(scale, _)| bytes >= *scale) {
        Some((scale, unit)) => format!("{:.0} {unit}", bytes / scale),
        None => format!("{bytes:.0} bytes"),
    }
}

/// Rows of the contact iteration a vehicle brings: an upper bound from its
/// spec alone (before anything is assembled), saturating.
pub fn contact_rows(body: &BodySpec) -> usize {
    body.kind.contact_rows(body)
}

/// Every broken product limit and every name used twice.
pub(super) fn problems(scene: &Scene) -> Vec<Problem> {
    let mut problems = Vec::new();
    let rows = (scene.vehicles.iter()).fold(0usize, |sum, v| sum.saturating_add(contact_rows(v)));
    if rows > MAX_CONTACT_ROWS {
        problems.push(Problem::new(
            "vehicles",
            format!("{} vehicles with {rows} contact rows", scene.vehicles.len()),
            format!(
                "the contacts of all vehicles together must give at most {MAX_CONTACT_ROWS} \
                 rows of the contact iteration (a wheel 2, a bogie vehicle 8, a maglev \
                 vehicle one per magnet, a glider or sprung mass 1): its dense operators take \
                 {} for {rows} rows ({} at the bound) and rows³/3 flops to factorise, since \
                 every contact on one continuous beam moves every other within a step",
                bytes_shown(operator_bytes(rows)),
                bytes_shown(operator_bytes(MAX_CONTACT_ROWS))
            ),
        ));
    }
    problems.extend(duplicate_names(scene));
    problems
}

/// Names of the bodies the vehicles generate (`car_unsprung`,
/// `coach1_bogie1`, ...) that another vehicle or generated body also has:
/// each name becomes output and input names of the FMU and CSV columns.
fn duplicate_names(scene: &Scene) -> Vec<Problem> {
    // Each name's first owner, and whether it is that vehicle's own name
    // (two vehicles of one name are `validate`'s rule already).
    let mut owner: HashMap<String, (String, bool)> = HashMap::new();
    let mut problems = Vec::new();
    let vehicles = super::validate::bodies_with_paths(scene);
    for (path, vehicle) in vehicles {
        // A moving force has no bodies, but its name still names outputs.
        let mut names = vehicle.body_names();
        if names.is_empty() {
            names.push(vehicle.name.clone());
        }
        for name in names {
            let own = name == vehicle.name;
            match owner.get(&name) {
                Some((_, true)) if own => {}
                Some((first, _)) if first != &path => problems.push(Problem::new(
                    format!("{path}.name"),
                    format!("{:?}", vehicle.name),
                    format!(
                        "gives a body named {name:?}, which {first} already has: every \
                         vehicle and every body it generates (<name>_unsprung, \
                         <name>_bogie1, <name>_wheelset1, <name>_magnet1, ...) needs a name \
                         of its own"
                    ),
                )),
                _ => {
                    owner.insert(name, (path.clone(), own));
                }
            }
        }
    }
    problems
}

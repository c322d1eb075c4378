//! A vehicle's contact bodies on a compliant contact law (`contact_law`):
//! each contact becomes a force law of its body's gap (a follower on the
//! body's own centre, `crate::contact_law`), preloaded with the body's
//! share of the vehicle's weight, so that it starts where the law carries
//! that share.

use crate::contact::{ContactKind, Follower};
use crate::contact_law::{hertz_compression, magnet_equivalent, LawKind};
use crate::scene::ResolvedLaw;
use crate::vehicle::presets::Vehicle;

/// Put every contact of `vehicle` on `law`, each carrying `share` (N).
/// A Hertz contact body starts sunk by its static compression; a wheel
/// on a compliant law no longer rolls (no tangential force: it is a
/// point on its centre, its radius in the law's rest).
pub(super) fn apply(vehicle: &mut Vehicle, law: ResolvedLaw, share: f64) -> Result<(), String> {
    for contact in &mut vehicle.contacts {
        let radius = contact.radius();
        let (kind, stiffness, damping, rest) = match law {
            ResolvedLaw::Rigid => return Ok(()),
            ResolvedLaw::Hertz { coefficient } => {
                let sunk = hertz_compression(coefficient, share);
                vehicle.states[contact.body].position.y -= sunk;
                (LawKind::Hertz { coefficient }, 0.0, 0.0, radius - sunk)
            }
            ResolvedLaw::Ems {
                nominal_gap,
                proportional_gain,
                derivative_gain,
                max_force,
            } => {
                let max_force = max_force.unwrap_or(2.0 * share);
                // NaN-safe: a cap that is not above the load is refused.
                if max_force.partial_cmp(&share) != Some(std::cmp::Ordering::Greater) {
                    return Err(format!(
                        "contact_law.max_force = {max_force} N must exceed the magnet's static \
                         load {share} N"
                    ));
                }
                let (k, c) =
                    magnet_equivalent(share, nominal_gap, proportional_gain, derivative_gain);
                let kind = LawKind::Magnet {
                    max_force,
                    nominal_gap,
                };
                (kind, k, c, radius)
            }
        };
        contact.kind = ContactKind::Glider;
        contact.follower = Some(Follower {
            stiffness,
            damping,
            preload: share,
            rest,
            attachment: nalgebra::Vector2::zeros(),
            kind,
        });
    }
    Ok(())
}

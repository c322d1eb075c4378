//! A vehicle's contact bodies on a compliant contact law (`contact_law`):
//! each contact becomes a force law of its body's gap (a follower on the
//! body's own centre, `crate::contact_law`), preloaded with the body's
//! share of the vehicle's weight, so that it starts where the law carries
//! that share.

use crate::contact::{ContactKind, Follower};
use crate::contact_law::ResolvedLaw;
use crate::vehicle::presets::Vehicle;

/// Put every contact of `vehicle` on `law`, each carrying `share` (N).
/// A Hertz contact body starts sunk by its static compression; a wheel
/// on a compliant law no longer rolls (no tangential force: it is a
/// point on its centre, its radius in the law's rest).
pub(super) fn apply(vehicle: &mut Vehicle, law: ResolvedLaw, share: f64) -> Result<(), String> {
    for contact in &mut vehicle.contacts {
        let Some(f) = law.follower(share, contact.radius())? else {
            return Ok(());
        };
        vehicle.states[contact.body].position.y -= f.sunk;
        contact.kind = ContactKind::Glider;
        contact.follower = Some(Follower {
            stiffness: f.stiffness,
            damping: f.damping,
            preload: share,
            rest: f.rest,
            attachment: nalgebra::Vector2::zeros(),
            kind: f.kind,
        });
    }
    Ok(())
}

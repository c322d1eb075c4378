//! Massless followers as a preset's contact points (`wheelset_mass = 0`
//! of a bogie vehicle, `magnet_mass = 0` of a maglev vehicle): each
//! contact body and the suspension that carries it become one follower
//! hanging from the suspension's upper end, so the preset's geometry,
//! preloads and names stay those of its massive form.

use crate::contact::Follower;
use crate::force_element::Direction;
use crate::vehicle::presets::Vehicle;

/// Replace every contact body of `vehicle` by a massless follower: its
/// vertical suspension (stiffness, damping, preload, rest length) becomes
/// the follower's law, attached where that suspension met the body above;
/// the contact body, its suspension and its guide are removed.
pub(super) fn fold_contact_bodies(vehicle: &mut Vehicle) {
    let mut removed = Vec::with_capacity(vehicle.contacts.len());
    for contact in &mut vehicle.contacts {
        let carrier = vehicle
            .force_elements
            .iter()
            .find(|e| e.body_b == contact.body && e.direction == Direction::Vertical)
            .expect("a preset's contact body hangs from a vertical suspension");
        contact.follower = Some(Follower {
            stiffness: carrier.stiffness,
            damping: carrier.damping,
            preload: carrier.preload,
            rest: carrier.rest,
            attachment: carrier.point_a,
            kind: Default::default(),
        });
        removed.push(contact.body);
        contact.body = carrier.body_a;
    }
    vehicle
        .force_elements
        .retain(|e| !removed.contains(&e.body_b));
    removed.sort_unstable_by(|a, b| b.cmp(a));
    for &b in &removed {
        vehicle.bodies.remove(b);
        vehicle.states.remove(b);
        let shift = |i: &mut usize| *i -= usize::from(*i > b);
        vehicle.contacts.iter_mut().for_each(|c| shift(&mut c.body));
        for e in &mut vehicle.force_elements {
            shift(&mut e.body_a);
            shift(&mut e.body_b);
        }
    }
}

//! Advice on a scene that is valid but asks a question its model cannot
//! answer: contact bodies with mass held on the deck by Lee's rigid
//! contact, whose peaks do not converge (docs/contact-laws.md).
//!
//! A rigid unilateral contact of a mass on an Euler–Bernoulli beam is not
//! well posed wherever the surface's slope jumps (the beam's ends, a kink
//! at a support, a landing): the beam's point receptance behaves like
//! s^{−3/2} at high frequency, so the contact force after a jump v of the
//! normal velocity grows like v / √t, an integrable but unbounded peak,
//! and the beam's higher modes make the force pull where the continuum
//! would not. Peak forces, deck accelerations and lift-off counts then
//! grow with refinement. A compliant law (Hertz, the EMS magnet) bounds
//! the peak by its stiffness, and massless followers have no mass to
//! stop.

use super::{BodyKind, BodySpec, ResolvedLaw, Scene};

/// One line per kind of contact body (wheelsets, magnets) naming the
/// vehicles whose massive contact bodies are on the rigid contact, and
/// proposing the well-posed law.
pub fn advisories(scene: &Scene) -> Vec<String> {
    let vehicles: Vec<&BodySpec> = scene
        .vehicles
        .iter()
        .filter(|spec| rigid_massive_contacts(spec))
        .collect();
    let mut lines = Vec::new();
    for (magnets, bodies, preset) in [(false, "wheelsets", "wheel-rail"), (true, "magnets", "ems")]
    {
        let names: Vec<&str> = (vehicles.iter())
            .filter(|spec| (spec.kind == BodyKind::MaglevVehicle) == magnets)
            .map(|spec| spec.name.as_str())
            .collect();
        if names.is_empty() {
            continue;
        }
        lines.push(format!(
            "the {bodies} of {} have mass and meet the deck through Lee's rigid contact, \
             which is ill-posed for a mass where the track's slope jumps (beam ends, \
             supports, landings): peak contact forces, deck accelerations and lift-offs \
             grow as the step and the mesh shrink. For those figures give the vehicles \
             `contact_law.preset = \"{preset}\"` (or massless followers); see \
             docs/contact-laws.md",
            names.join(", ")
        ));
    }
    lines
}

/// A bogie or maglev vehicle whose wheelsets or magnets have mass and no
/// compliant law.
fn rigid_massive_contacts(spec: &BodySpec) -> bool {
    let preset = matches!(spec.kind, BodyKind::BogieVehicle | BodyKind::MaglevVehicle);
    let rigid = spec
        .contact_law
        .as_ref()
        .is_none_or(|law| law.resolve() == Ok(ResolvedLaw::Rigid));
    preset && !spec.massless_contacts() && rigid
}

//! The outputs' names: how the catalogue names a quantity
//! (`output_name`) and which quantity a name reports (`classify`), from
//! one rule (each kind's group and suffix, in its entry of the
//! `quantities!` list in `outputs/mod.rs`), so that a reader of a CSV
//! file (a column name, not the live catalogue) asks by type instead of
//! matching suffixes.
//!
//! A name is `<owner>.<suffix>` (a body's or a contact's quantity),
//! `<group>.<owner>.<suffix>` (a sensor's, a section's, a support's) or
//! `<group>.<suffix>` (the energies, the solver's counts).

pub use super::QuantityKind;
use strum::IntoEnumIterator;

/// The part of a name before its owner: none for a body's or a contact's
/// quantity, else the group (`sensor`, ..., `energy`, `solver`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Group {
    /// `<owner>.<suffix>`: a body's, a contact's (the nominal speed: a
    /// body's or an attached contact's).
    Owner,
    /// `<group>.<owner>.<suffix>`.
    Owned(&'static str),
    /// `<group>.<suffix>`: the run's own.
    Run(&'static str),
}

use Group::{Owned, Owner, Run};

/// Every kind's group and suffix: the one naming rule, from each kind's
/// entry in the `quantities!` list (`outputs/mod.rs`).
const fn row(kind: QuantityKind) -> (Group, &'static str) {
    kind.naming()
}

/// A name read back: what it reports and whose it is (the body's,
/// contact's, sensor's, section's or support's name; empty for the run's
/// own outputs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputName<'a> {
    pub kind: QuantityKind,
    pub owner: &'a str,
}

/// The name of the output reporting `kind` of `owner` (ignored for the
/// run's own outputs).
pub fn output_name(kind: QuantityKind, owner: &str) -> String {
    match row(kind) {
        (Owner, suffix) => format!("{owner}.{suffix}"),
        (Owned(group), suffix) => format!("{group}.{owner}.{suffix}"),
        (Run(group), suffix) => format!("{group}.{suffix}"),
    }
}

/// What the output (or CSV column) `name` reports, if it is a name the
/// catalogue gives; `None` for any other (`time`, a derived column such
/// as `sensor.s.acceleration_filtered`, an error estimate).
pub fn classify(name: &str) -> Option<OutputName<'_>> {
    let (head, suffix) = name.rsplit_once('.')?;
    let grouped = QuantityKind::iter().find_map(|kind| {
        let owner = match row(kind) {
            (_, s) if s != suffix => return None,
            (Owner, _) => return None,
            (Owned(g), _) => head.strip_prefix(g)?.strip_prefix('.')?,
            (Run(g), _) if head == g => "",
            (Run(_), _) => return None,
        };
        Some(OutputName { kind, owner })
    });
    grouped.or_else(|| {
        let kind = QuantityKind::iter().find(|&k| row(k) == (Owner, suffix))?;
        (!head.is_empty()).then_some(OutputName { kind, owner: head })
    })
}

/// Whether `name` is an output reporting `kind`.
pub fn reports(name: &str, kind: QuantityKind) -> bool {
    classify(name).is_some_and(|n| n.kind == kind)
}

#[cfg(test)]
mod tests {
    use super::*;
    use QuantityKind as K;

    #[test]
    fn every_group_and_suffix_names_one_kind() {
        let kinds: Vec<QuantityKind> = QuantityKind::iter().collect();
        for (i, &kind) in kinds.iter().enumerate() {
            for &other in &kinds[i + 1..] {
                let (group, suffix) = row(kind);
                assert_ne!(row(kind), row(other), "{group:?} {suffix}");
            }
        }
    }

    #[test]
    fn names_read_back_as_their_kind_and_owner() {
        for kind in QuantityKind::iter() {
            let (group, _) = row(kind);
            for owner in ["wheel", "front.bogie", "energy", "sensor"] {
                let name = output_name(kind, owner);
                let named = classify(&name).unwrap_or_else(|| panic!("{name}"));
                assert_eq!(named.kind, kind, "{name}");
                let expected = if matches!(group, Group::Run(_)) {
                    ""
                } else {
                    owner
                };
                assert_eq!(named.owner, expected, "{name}");
            }
        }
        assert_eq!(
            output_name(K::Sensor, "midspan"),
            "sensor.midspan.deflection"
        );
        assert_eq!(output_name(K::Balance, ""), "energy.balance");
        assert_eq!(output_name(K::NominalSpeed, "wheel"), "wheel.nominal_speed");
        assert!(reports("support.left.moment", K::ReactionMoment));
        assert!(reports("section.mid.moment", K::SectionMoment));
    }
}

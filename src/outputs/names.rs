//! The outputs' names: how the catalogue names a quantity
//! (`output_name`) and which quantity a name reports (`classify`), in one
//! table, so that a reader of a CSV file (a column name, not the live
//! catalogue) asks by type instead of matching suffixes.
//!
//! A name is `<owner>.<suffix>` (a body's or a contact's quantity),
//! `<group>.<owner>.<suffix>` (a sensor's, a section's, a support's) or
//! `<group>.<suffix>` (the energies, the solver's counts).

use super::Quantity;

/// What an output reports, without whose it is: a `Quantity` without its
/// index (`Quantity::kind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum QuantityKind {
    X,
    Y,
    Vx,
    Vy,
    Ax,
    Ay,
    AngularAcceleration,
    Angle,
    AngularVelocity,
    NominalSpeed,
    ContactPosition,
    TangentialForce,
    NormalForce,
    OnBeam,
    ContactClosed,
    Gap,
    MagnetAirGap,
    MagnetCurrent,
    ImpulseTangential,
    ImpulseNormal,
    Irregularity,
    Sensor,
    SensorVelocity,
    SensorFoundationLoad,
    SensorRailDeflection,
    SensorRailSeatForce,
    SensorAcceleration,
    SectionMoment,
    SectionShear,
    Reaction,
    ReactionMoment,
    BodyKinetic,
    BeamKinetic,
    BeamStrain,
    SpringEnergy,
    Dissipated,
    BeamDamping,
    GravityWork,
    ExternalWork,
    TractiveWork,
    ImpactLoss,
    NumericalDissipation,
    Balance,
    VelocityError,
    GapError,
    Iterations,
    PositionIterations,
}

/// The part of a name before its owner: none for a body's or a contact's
/// quantity, else the group (`sensor`, ..., `energy`, `solver`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Group {
    /// `<owner>.<suffix>`: a body's, a contact's (the nominal speed: a
    /// body's or an attached contact's).
    Owner,
    /// `<group>.<owner>.<suffix>`.
    Owned(&'static str),
    /// `<group>.<suffix>`: the run's own.
    Run(&'static str),
}

use Group::{Owned, Owner, Run};
use QuantityKind as K;

/// Every kind with its group and suffix: the one naming rule.
const NAMES: &[(QuantityKind, Group, &str)] = &[
    (K::X, Owner, "x"),
    (K::Y, Owner, "y"),
    (K::Vx, Owner, "vx"),
    (K::Vy, Owner, "vy"),
    (K::Ax, Owner, "ax"),
    (K::Ay, Owner, "ay"),
    (K::AngularAcceleration, Owner, "angular_acceleration"),
    (K::Angle, Owner, "pitch"),
    (K::AngularVelocity, Owner, "angular_velocity"),
    (K::NominalSpeed, Owner, "nominal_speed"),
    (K::ContactPosition, Owner, "position"),
    (K::TangentialForce, Owner, "tangential_force"),
    (K::NormalForce, Owner, "normal_force"),
    (K::OnBeam, Owner, "on_beam"),
    (K::ContactClosed, Owner, "state"),
    (K::Gap, Owner, "gap"),
    (K::MagnetAirGap, Owner, "air_gap"),
    (K::MagnetCurrent, Owner, "current"),
    (K::ImpulseTangential, Owner, "impact_impulse_tangential"),
    (K::ImpulseNormal, Owner, "impact_impulse"),
    (K::Irregularity, Owner, "irregularity"),
    (K::Sensor, Owned("sensor"), "deflection"),
    (K::SensorVelocity, Owned("sensor"), "velocity"),
    (K::SensorFoundationLoad, Owned("sensor"), "foundation_load"),
    (K::SensorRailDeflection, Owned("sensor"), "rail_deflection"),
    (K::SensorRailSeatForce, Owned("sensor"), "rail_seat_force"),
    (K::SensorAcceleration, Owned("sensor"), "acceleration"),
    (K::SectionMoment, Owned("section"), "moment"),
    (K::SectionShear, Owned("section"), "shear"),
    (K::Reaction, Owned("support"), "reaction"),
    (K::ReactionMoment, Owned("support"), "moment"),
    (K::BodyKinetic, Run("energy"), "body_kinetic"),
    (K::BeamKinetic, Run("energy"), "beam_kinetic"),
    (K::BeamStrain, Run("energy"), "beam_strain"),
    (K::SpringEnergy, Run("energy"), "spring"),
    (K::Dissipated, Run("energy"), "dissipated"),
    (K::BeamDamping, Run("energy"), "beam_damping"),
    (K::GravityWork, Run("energy"), "gravity_work"),
    (K::ExternalWork, Run("energy"), "external_work"),
    (K::TractiveWork, Run("energy"), "tractive_work"),
    (K::ImpactLoss, Run("energy"), "impact_loss"),
    (
        K::NumericalDissipation,
        Run("energy"),
        "numerical_dissipation",
    ),
    (K::Balance, Run("energy"), "balance"),
    (K::VelocityError, Run("solver"), "velocity_error"),
    (K::GapError, Run("solver"), "gap_error"),
    (K::Iterations, Run("solver"), "iterations"),
    (K::PositionIterations, Run("solver"), "position_iterations"),
];

/// A name read back: what it reports and whose it is (the body's,
/// contact's, sensor's, section's or support's name; empty for the run's
/// own outputs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputName<'a> {
    pub kind: QuantityKind,
    pub owner: &'a str,
}

fn row(kind: QuantityKind) -> (Group, &'static str) {
    let (_, group, suffix) = NAMES
        .iter()
        .find(|(k, _, _)| *k == kind)
        .expect("NAMES has a row for every kind (tested)");
    (*group, suffix)
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
    let grouped = NAMES.iter().find_map(|&(kind, group, s)| {
        let owner = match group {
            _ if s != suffix => return None,
            Owner => return None,
            Owned(g) => head.strip_prefix(g)?.strip_prefix('.')?,
            Run(g) if head == g => "",
            Run(_) => return None,
        };
        Some(OutputName { kind, owner })
    });
    grouped.or_else(|| {
        let kind = NAMES
            .iter()
            .find(|&&(_, group, s)| group == Owner && s == suffix)?
            .0;
        (!head.is_empty()).then_some(OutputName { kind, owner: head })
    })
}

/// Whether `name` is an output reporting `kind`.
pub fn reports(name: &str, kind: QuantityKind) -> bool {
    classify(name).is_some_and(|n| n.kind == kind)
}

impl Quantity {
    /// What this quantity reports, without its index. One exhaustive
    /// match (no `_` arm): a new quantity must answer here.
    pub fn kind(&self) -> QuantityKind {
        use Quantity::*;
        match self {
            X(_) => K::X,
            Y(_) => K::Y,
            Vx(_) => K::Vx,
            Vy(_) => K::Vy,
            Ax(_) => K::Ax,
            Ay(_) => K::Ay,
            AngularAcceleration(_) => K::AngularAcceleration,
            Angle(_) => K::Angle,
            AngularVelocity(_) => K::AngularVelocity,
            NominalSpeed(_) => K::NominalSpeed,
            ContactPosition(_) => K::ContactPosition,
            TangentialForce(_) => K::TangentialForce,
            NormalForce(_) => K::NormalForce,
            OnBeam(_) => K::OnBeam,
            ContactClosed(_) => K::ContactClosed,
            Gap(_) => K::Gap,
            MagnetAirGap(_) => K::MagnetAirGap,
            MagnetCurrent(_) => K::MagnetCurrent,
            ImpulseTangential(_) => K::ImpulseTangential,
            ImpulseNormal(_) => K::ImpulseNormal,
            Irregularity(_) => K::Irregularity,
            Sensor(_) => K::Sensor,
            SensorVelocity(_) => K::SensorVelocity,
            SensorFoundationLoad(_) => K::SensorFoundationLoad,
            SensorRailDeflection(_) => K::SensorRailDeflection,
            SensorRailSeatForce(_) => K::SensorRailSeatForce,
            SensorAcceleration(_) => K::SensorAcceleration,
            SectionMoment(_) => K::SectionMoment,
            SectionShear(_) => K::SectionShear,
            Reaction(_) => K::Reaction,
            ReactionMoment(_) => K::ReactionMoment,
            BodyKinetic => K::BodyKinetic,
            BeamKinetic => K::BeamKinetic,
            BeamStrain => K::BeamStrain,
            SpringEnergy => K::SpringEnergy,
            Dissipated => K::Dissipated,
            BeamDamping => K::BeamDamping,
            GravityWork => K::GravityWork,
            ExternalWork => K::ExternalWork,
            TractiveWork => K::TractiveWork,
            ImpactLoss => K::ImpactLoss,
            NumericalDissipation => K::NumericalDissipation,
            Balance => K::Balance,
            VelocityError => K::VelocityError,
            GapError => K::GapError,
            Iterations => K::Iterations,
            PositionIterations => K::PositionIterations,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_one_row_and_every_group_suffix_one_kind() {
        for (i, (kind, group, suffix)) in NAMES.iter().enumerate() {
            for (other, g, s) in &NAMES[i + 1..] {
                assert_ne!(kind, other);
                assert!(!(group == g && suffix == s), "{group:?} {suffix}");
            }
        }
        // One row per variant of `Quantity` (its `kind` match is exhaustive).
        assert_eq!(NAMES.len(), 47);
    }

    #[test]
    fn names_read_back_as_their_kind_and_owner() {
        for &(kind, group, _) in NAMES {
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

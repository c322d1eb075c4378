//! The solver's parameters as a scene gives them (`[solver]`: step,
//! tolerances, integrator, start, structure representation, end time), with
//! their serde form; `build` turns them into `SolverParameters`.

use serde::{Deserialize, Serialize};

use super::integrate::{ForceProfile, IntegratorKind};
use crate::structure::modal::{ModeSelection, StructureKind};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Fixed internal time step (s).
    #[serde(default = "default_step")]
    pub step: f64,
    /// Tolerance on the velocity error |e| (m/s); paper: 1e-7.
    #[serde(default = "default_velocity_tolerance")]
    pub velocity_tolerance: f64,
    /// Tolerance on the gap error |g| (m); paper: 1e-5.
    #[serde(default = "default_gap_tolerance")]
    pub gap_tolerance: f64,
    /// Cap on contact-force iterations per stage and step.
    #[serde(default = "default_max_iterations")]
    pub max_iterations: u32,
    /// Time integrator of the bodies.
    #[serde(default)]
    pub integrator: IntegratorKind,
    /// Numerical damping of the implicit scheme, −α of HHT-α, in [0, 1/3]
    /// (0: Newmark's average acceleration, energy-conserving).
    #[serde(default)]
    pub numerical_damping: f64,
    /// How the contact force varies within a step under RK4 (HHT-α's
    /// unknown force is its end-of-step value whatever this says).
    #[serde(default, skip_serializing_if = "ForceProfile::is_default")]
    pub force_profile: ForceProfile,
    /// Stop time (s) if the body has not left the beam before.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end_time: Option<f64>,
    /// The state at t = 0: `rest` on the undeformed beam, or `static`: the
    /// beam deflected under the vehicles' weight and every suspension at
    /// its preload (the vehicles start in equilibrium).
    #[serde(default, skip_serializing_if = "StartKind::is_rest")]
    pub start: StartKind,
    /// How the beam is represented: its finite elements (`full`), or its
    /// lowest natural modes (`modal`, with `modes` or `max_frequency`).
    #[serde(default, skip_serializing_if = "StructureKind::is_full")]
    pub structure: StructureKind,
    /// With `structure = "modal"`: how many of the lowest modes to keep.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modes: Option<usize>,
    /// With `structure = "modal"`: keep the modes up to this frequency (Hz).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_frequency: Option<f64>,
    /// Relative error the summary figures must meet: `guideway run` then
    /// chooses the step (as with `--rtol`; docs/error-estimates.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StartKind {
    #[default]
    Rest,
    Static,
}

impl StartKind {
    pub fn is_rest(&self) -> bool {
        *self == StartKind::Rest
    }
}

// The solver's defaults are `SolverParameters::DEFAULT`'s (one source).
const SOLVER_DEFAULTS: crate::solver::parameters::SolverParameters =
    crate::solver::parameters::SolverParameters::DEFAULT;

fn default_step() -> f64 {
    SOLVER_DEFAULTS.step
}
fn default_velocity_tolerance() -> f64 {
    SOLVER_DEFAULTS.iteration.velocity_tolerance
}
fn default_gap_tolerance() -> f64 {
    SOLVER_DEFAULTS.iteration.gap_tolerance
}
fn default_max_iterations() -> u32 {
    SOLVER_DEFAULTS.iteration.max_iterations
}

impl Default for SolverSpec {
    fn default() -> Self {
        SolverSpec {
            step: default_step(),
            velocity_tolerance: default_velocity_tolerance(),
            gap_tolerance: default_gap_tolerance(),
            max_iterations: default_max_iterations(),
            integrator: IntegratorKind::default(),
            numerical_damping: 0.0,
            force_profile: ForceProfile::default(),
            end_time: None,
            start: StartKind::Rest,
            structure: StructureKind::Full,
            modes: None,
            max_frequency: None,
            tolerance: None,
        }
    }
}

impl SolverSpec {
    /// The modes a (validated) spec keeps, `None` for the full structure.
    pub fn mode_selection(&self) -> Option<ModeSelection> {
        if self.structure == StructureKind::Full {
            return None;
        }
        match (self.modes, self.max_frequency) {
            (Some(k), _) => Some(ModeSelection::Count(k)),
            (None, Some(f)) => Some(ModeSelection::UpTo(f)),
            (None, None) => None,
        }
    }
}

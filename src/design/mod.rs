//! Design outputs: the static envelope of a scene's loads crossing the
//! structure (the reference of the dynamic amplification factor) and the
//! design outputs of a scene as probes of the structure's state. The
//! internal forces they read are the structure's
//! (`structure::section_forces`); they are re-exported here under their
//! earlier paths.

mod envelope;
mod probes;
pub use crate::contact::loads::contact_loads;
pub use crate::structure::section_forces::{
    load_vector, supports, BeamDynamics, PointLoad, SectionForces, Support,
};
pub use envelope::{envelope_of_loads, envelope_of_run, static_envelope, StaticEnvelope};
pub use probes::{probes, DesignPeaks, Probe, ProbeReader};

// The envelope's loads are the assembly's static shares (`build`).
pub use crate::build::static_shares;

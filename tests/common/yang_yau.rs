//! The sprung-mass example of Yang & Yau (1997): a moving oscillator
//! crossing a simply supported beam. Its numbers, which the sprung-mass,
//! error-estimate, follower and preset tests share.

/// Span (m).
pub const LENGTH: f64 = 25.0;
/// Bending stiffness (N m²): E = 2.943e10 N/m², I = 2.90 m⁴.
pub const EI: f64 = 2.943e10 * 2.90;
/// Mass per length (kg/m).
pub const MASS_PER_LENGTH: f64 = 2303.0;
/// The sprung mass M_v (kg).
pub const SPRUNG: f64 = 5750.0;
/// The contact's unsprung mass, 1 % of M_v (kg): the literature's contact
/// is massless; a small one keeps the contact a body of its own.
pub const UNSPRUNG: f64 = 57.5;
/// The suspension's stiffness k_v (N/m).
pub const STIFFNESS: f64 = 1.595e6;
/// The crossing speed, 100 km/h (m/s).
pub const SPEED: f64 = 100.0 / 3.6;

//! How a number is written in a message, one format for every layer
//! (solver failures, FMU refusals, reports), and the magnitudes every real
//! of a scene keeps.

/// Every real of a scene lies within ±`MAX_MAGNITUDE`, and one that must be
/// positive is at least `MIN_MAGNITUDE`: products of a few such values (an
/// energy, an angular speed V/r) then stay far from overflow, where
/// subnormal radii or speeds of 1e300 gave infinite energies.
pub const MAX_MAGNITUDE: f64 = 1e15;
pub const MIN_MAGNITUDE: f64 = 1e-15;

/// A number for a message: plain between 1e-3 and 1e6, else in exponent
/// form (shortest round-trip digits either way), so that 5e-324 is not
/// printed with 325 digits.
pub fn fmt_number(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-3..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

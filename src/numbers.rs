//! How a number is written in a message, one format for every layer
//! (solver failures, FMU refusals, reports).

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

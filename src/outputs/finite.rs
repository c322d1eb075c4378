//! The check that every output value of a step is a finite number, shared
//! by the command line's run and the FMU, which refuse the same values.

use super::OutputInfo;

/// The first output that is not a finite number, named with its value.
/// The CLI and the FMU refuse the same values with it.
#[allow(clippy::eq_op)] // x − x is the point: 0 or NaN
pub fn non_finite_output(outputs: &[OutputInfo], values: &[f64]) -> Option<String> {
    // x − x is 0 for a finite x, NaN otherwise: a sum without a branch per
    // value first (this runs after every step), the search only on failure.
    // Four sums side by side, which the compiler keeps in vector registers.
    let mut sums = [0.0; 4];
    let fours = values.chunks_exact(4);
    let rest = fours.remainder();
    for four in fours {
        for (sum, &x) in sums.iter_mut().zip(four) {
            *sum += x - x;
        }
    }
    let rest = rest.iter().fold(0.0, |sum, &x| sum + (x - x));
    if sums.iter().sum::<f64>() + rest == 0.0 {
        return None;
    }
    let k = values.iter().position(|x| !x.is_finite())?;
    let name = outputs.get(k).map_or("?", |o| o.name.as_str());
    Some(format!("output {name} is {}", values[k]))
}

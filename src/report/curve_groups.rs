//! The run plot's curves by group: a panel draws a few columns one by one
//! and many (a train's 32 contacts, its 24 sprung bodies) as their envelope,
//! so that its legend stays short; and the bodies split into the sprung
//! ones and the unsprung masses that carry the contacts.

use super::plot::Curve;
use super::trace::Trace;
use crate::outputs::{classify, output_name, QuantityKind};

/// Most curves a panel draws one by one; past it, their envelope.
pub const MAX_CURVES: usize = 6;

/// The named columns as curves over `x`, each value divided by `scale`:
/// one per column up to `MAX_CURVES`, else two, the largest and the least
/// of them at each row (`what` names them: "contacts", "vehicles").
pub fn grouped(x: &[f64], columns: &[(String, &[f64])], scale: f64, what: &str) -> Vec<Curve> {
    let curve = |label: String, values: &mut dyn Iterator<Item = f64>| Curve {
        label,
        points: x
            .iter()
            .zip(values)
            .map(|(&x, v)| (x, v / scale))
            .filter(|(_, y)| y.is_finite())
            .collect(),
    };
    if columns.len() <= MAX_CURVES {
        return columns
            .iter()
            .map(|(name, values)| curve(name.clone(), &mut values.iter().copied()))
            .collect();
    }
    let row = |k: usize| columns.iter().filter_map(move |(_, v)| v.get(k).copied());
    let finite = |k: usize| row(k).filter(|v| v.is_finite());
    let largest = (0..x.len()).map(|k| finite(k).fold(f64::NAN, f64::max));
    let least = (0..x.len()).map(|k| finite(k).fold(f64::NAN, f64::min));
    let n = columns.len();
    vec![
        curve(format!("largest of {n} {what}"), &mut largest.into_iter()),
        curve(format!("least of {n} {what}"), &mut least.into_iter()),
    ]
}

/// The trace's columns reporting one of `kinds` (`outputs::classify`)
/// whose owner passes `keep`, as (name, values).
pub fn columns_of<'t>(
    trace: &'t Trace,
    kinds: &[QuantityKind],
    keep: &dyn Fn(&str) -> bool,
) -> Vec<(String, &'t [f64])> {
    trace
        .names
        .iter()
        .filter_map(|name| {
            let named = classify(name).filter(|n| kinds.contains(&n.kind))?;
            keep(named.owner).then_some(())?;
            Some((name.clone(), trace.column(name)?))
        })
        .collect()
}

/// Whether `body` carries a contact (a wheelset, a magnet, the paper's
/// wheel, a sprung mass's unsprung mass): an unsprung mass, known by the
/// nominal speed (eq. 24) every contact body reports. The others (car
/// bodies, bogies, a sprung mass) ride on suspensions.
pub fn is_unsprung(trace: &Trace, body: &str) -> bool {
    let nominal_speed = output_name(QuantityKind::NominalSpeed, body);
    trace.column(&nominal_speed).is_some()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn many_columns_become_their_envelope_and_few_stay_as_they_are() {
        let x = [0.0, 1.0, 2.0];
        let columns: Vec<(String, Vec<f64>)> = (0..8)
            .map(|i| (format!("c{i}"), vec![i as f64, -(i as f64), f64::NAN]))
            .collect();
        let refs: Vec<(String, &[f64])> = columns
            .iter()
            .map(|(n, v)| (n.clone(), v.as_slice()))
            .collect();
        let curves = grouped(&x, &refs, 2.0, "contacts");
        assert_eq!(curves.len(), 2);
        assert_eq!(curves[0].label, "largest of 8 contacts");
        assert_eq!(curves[0].points, [(0.0, 3.5), (1.0, 0.0)]);
        assert_eq!(curves[1].label, "least of 8 contacts");
        assert_eq!(curves[1].points, [(0.0, 0.0), (1.0, -3.5)]);
        let few = grouped(&x, &refs[..MAX_CURVES], 1.0, "contacts");
        assert_eq!(few.len(), MAX_CURVES);
        assert_eq!(few[5].label, "c5");
        assert_eq!(few[5].points, [(0.0, 5.0), (1.0, -5.0)]);
    }
}

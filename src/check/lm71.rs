//! The static midspan moment and deflection of a simply supported span
//! under Load Model 71 (EN 1991-2 §6.3.2), from the influence lines, the
//! axle group moved along the span and the distributed load on both sides.

use super::rules::{LM71_AXLE, LM71_CLEAR, LM71_DISTRIBUTED, LM71_SPACING};

/// Largest midspan moment (N m) and deflection (m, magnitude) of a span
/// `l` (m) of bending stiffness `ei` (N m²) under LM71 × `alpha`.
pub fn lm71_midspan(l: f64, ei: f64, alpha: f64) -> (f64, f64) {
    let half_group = 1.5 * LM71_SPACING;
    let gap = half_group + LM71_CLEAR;
    let positions = 20_000;
    // The grid, and the centres that put an axle or an edge of the
    // distributed load on midspan, where the moment's influence line kinks.
    let grid = (0..=positions).map(|k| -gap + (l + 2.0 * gap) * k as f64 / positions as f64);
    let kinks = (0..4)
        .map(|i| 0.5 * l + half_group - i as f64 * LM71_SPACING)
        .chain([0.5 * l - gap, 0.5 * l + gap]);
    let (mut moment, mut deflection): (f64, f64) = (0.0, 0.0);
    for centre in grid.chain(kinks) {
        let axles = (0..4).map(|i| centre - half_group + i as f64 * LM71_SPACING);
        let (mut m, mut w) = (0.0, 0.0);
        for a in axles.filter(|a| (0.0..=l).contains(a)) {
            m += LM71_AXLE * moment_influence(l, a);
            w += LM71_AXLE * deflection_influence(l, ei, a);
        }
        for (from, to) in [(0.0, centre - gap), (centre + gap, l)] {
            let (from, to) = (from.max(0.0), to.min(l));
            if to > from {
                m += LM71_DISTRIBUTED * integral(from, to, l, |a| moment_influence(l, a));
                w += LM71_DISTRIBUTED * integral(from, to, l, |a| deflection_influence(l, ei, a));
            }
        }
        moment = moment.max(m);
        deflection = deflection.max(w);
    }
    (alpha * moment, alpha * deflection)
}

/// Midspan moment under a unit load at `a`: a/2 left of midspan.
fn moment_influence(l: f64, a: f64) -> f64 {
    0.5 * a.min(l - a)
}

/// Midspan deflection under a unit load at `a`: a (3L² − 4a²) / 48 EI for
/// a ≤ L/2, mirrored beyond.
fn deflection_influence(l: f64, ei: f64, a: f64) -> f64 {
    let a = a.min(l - a);
    a * (3.0 * l * l - 4.0 * a * a) / (48.0 * ei)
}

/// ∫ f from `from` to `to`, split at midspan `l`/2 where the influence
/// lines have their kink: each piece is a cubic, which Simpson's rule
/// integrates exactly.
fn integral(from: f64, to: f64, l: f64, f: impl Fn(f64) -> f64) -> f64 {
    let mid = 0.5 * l;
    if from < mid && mid < to {
        simpson(from, mid, &f) + simpson(mid, to, &f)
    } else {
        simpson(from, to, &f)
    }
}

fn simpson(from: f64, to: f64, f: &impl Fn(f64) -> f64) -> f64 {
    let panels = 20;
    let h = (to - from) / panels as f64;
    let mut sum = f(from) + f(to);
    for i in 1..panels {
        let weight = if i % 2 == 1 { 4.0 } else { 2.0 };
        sum += weight * f(from + i as f64 * h);
    }
    sum * h / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The moment by hand: with the group's centre δ right of midspan
    /// (0 ≤ δ ≤ 0.8 m) the axles' influence ordinates (L/2 − |e|)/2 sum
    /// to L − 3.2 whatever δ, and the distributed load misses the area
    /// 1.6 L − 5.12 − δ²/2 of the influence line (area L²/8), so the
    /// moment grows to δ = 0.8 (an axle on midspan); beyond, the axles lose
    /// 250 δ and the load gains 80 δ: M = 250 (L − 3.2) + 80 (L²/8 − 1.6 L
    /// + 5.12 + 0.32) kN m, at 20 m 4200 + 1875.2 = 6075.2 kN m.
    ///
    /// The deflection by hand: the closed forms of the axles' ordinates
    /// P a (3L² − 4a²)/48 EI and of the load's integral (3L²b²/2 − b⁴)/48
    /// EI from the support to b, maximised over the group's position.
    #[test]
    fn lm71_on_a_20_m_span_by_hand() {
        let (l, ei) = (20.0, 2.353893e10);
        let (m, w) = lm71_midspan(l, ei, 1.0);
        let by_hand = 250e3 * (l - 3.2) + 80e3 * (l * l / 8.0 - 1.6 * l + 5.12 + 0.32);
        assert!((by_hand - 6075.2e3).abs() < 1e-6);
        assert!((m - by_hand).abs() < 1e-9 * by_hand, "{m} vs {by_hand}");
        let point = |a: f64| {
            let a = a.min(l - a);
            a * (3.0 * l * l - 4.0 * a * a) / (48.0 * ei)
        };
        let area = |b: f64| (1.5 * l * l * b * b - b.powi(4)) / (48.0 * ei);
        let at = |delta: f64| {
            let c = 0.5 * l + delta;
            let axles: f64 = [-2.4, -0.8, 0.8, 2.4].iter().map(|e| point(c + e)).sum();
            let (p, r) = (c - 3.2, c + 3.2); // the gap, across midspan here
            let loaded = area(p) + area(l - r);
            250e3 * axles + 80e3 * loaded
        };
        let expected = (-30_000..=30_000)
            .map(|k| at(k as f64 * 1e-4))
            .fold(0.0, f64::max);
        assert!((w - expected).abs() < 1e-7 * expected, "{w} vs {expected}");
        let (m2, _) = lm71_midspan(l, ei, 1.33);
        assert!((m2 - 1.33 * m).abs() < 1e-9 * m);
    }
}

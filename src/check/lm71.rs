//! The static effects of Load Model 71 (EN 1991-2 §6.3.2): the midspan
//! moment and deflection of a simply supported span from its closed-form
//! influence lines, and the envelope at any station of a beam over any
//! supports (a continuous beam) from influence lines solved on its mesh;
//! the axle group moved along the beam, the distributed load where it is
//! unfavourable.

use super::rules::{LM71_AXLE, LM71_CLEAR, LM71_DISTRIBUTED, LM71_SPACING};
use crate::beam::Beam;
use crate::design::{BeamDynamics, PointLoad};

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

/// LM71's largest effects at one station of a beam: sagging moment (N m,
/// ≥ 0), hogging moment (N m, ≤ 0) and downward deflection (m, ≥ 0).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Lm71Effects {
    pub sagging: f64,
    pub hogging: f64,
    pub deflection: f64,
}

/// Influence lines of a beam: the moment and downward deflection at each
/// station under a unit downward load at each point of a grid (every
/// node and station, each interval split in `PANELS`), solved on the mesh
/// (static responses of point loads are exact on Hermite elements).
pub struct InfluenceLines {
    pub x: Vec<f64>,
    /// [station][grid point]
    pub moment: Vec<Vec<f64>>,
    pub deflection: Vec<Vec<f64>>,
}

/// Sub-intervals of the influence-line grid between breakpoints.
const PANELS: usize = 32;

impl InfluenceLines {
    pub fn new(beam: &Beam, stations: &[f64]) -> Result<InfluenceLines, String> {
        let mut breaks: Vec<f64> = beam.node_x.clone();
        breaks.extend_from_slice(stations);
        breaks.sort_by(f64::total_cmp);
        breaks.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        let mut x = vec![breaks[0]];
        for pair in breaks.windows(2) {
            let h = (pair[1] - pair[0]) / PANELS as f64;
            x.extend((1..=PANELS).map(|k| pair[0] + k as f64 * h));
        }
        let mut lines = InfluenceLines {
            moment: vec![Vec::with_capacity(x.len()); stations.len()],
            deflection: vec![Vec::with_capacity(x.len()); stations.len()],
            x: Vec::new(),
        };
        let factor = beam
            .stiffness_factor()
            .ok_or("the beam's stiffness cannot be factorised")?;
        for &at in &x {
            let response = BeamDynamics::static_response_with(
                beam,
                &factor,
                vec![PointLoad::vertical(beam, at, -1.0)],
            );
            for (i, &s) in stations.iter().enumerate() {
                lines.moment[i].push(response.section_forces(beam, s).moment);
                lines.deflection[i].push(-response.deflection_at(beam, s));
            }
        }
        lines.x = x;
        Ok(lines)
    }

    /// ∫ `line` × `keep`(value) dx from `from` to `to` by the trapezoidal
    /// rule on the grid (the interval's ends interpolated).
    fn integral(&self, line: &[f64], (from, to): (f64, f64), keep: fn(f64) -> f64) -> f64 {
        let value = |k: usize| keep(line[k]);
        let mut sum = 0.0;
        let first = self.x.partition_point(|&x| x <= from).max(1);
        let last = self.x.partition_point(|&x| x < to).min(self.x.len() - 1);
        for k in first..=last {
            let (a, b) = (self.x[k - 1], self.x[k]);
            let (lo, hi) = (a.max(from), b.min(to));
            if hi <= lo {
                continue;
            }
            let at = |t: f64| value(k - 1) + (value(k) - value(k - 1)) * (t - a) / (b - a);
            sum += 0.5 * (at(lo) + at(hi)) * (hi - lo);
        }
        sum
    }

    /// `line` at `at` by linear interpolation (0 off the beam).
    fn at(&self, line: &[f64], at: f64) -> f64 {
        let k = self.x.partition_point(|&x| x < at);
        if k == 0 {
            return if (at - self.x[0]).abs() < 1e-12 {
                line[0]
            } else {
                0.0
            };
        }
        if k == self.x.len() {
            return 0.0;
        }
        let (a, b) = (self.x[k - 1], self.x[k]);
        line[k - 1] + (line[k] - line[k - 1]) * (at - a) / (b - a)
    }

    /// The effect of a distributed load `q` (N/m, downward) over the whole
    /// beam on `line` (the UDL as its own influence-line integral).
    pub fn uniform(&self, line: &[f64], q: f64) -> f64 {
        let ends = (self.x[0], self.x[self.x.len() - 1]);
        q * self.integral(line, ends, |v| v)
    }

    /// The largest effect of LM71 × `alpha` on `line` in the direction
    /// `sign` (+1 or −1): the four axles with their centre anywhere (on a
    /// grid and with an axle on the `station`, where the line kinks), the
    /// distributed load wherever the line has that sign outside the axles.
    fn lm71(&self, line: &[f64], station: f64, sign: f64, alpha: f64) -> f64 {
        let half = 1.5 * LM71_SPACING;
        let gap = half + LM71_CLEAR;
        let (start, end) = (self.x[0], self.x[self.x.len() - 1]);
        let keep: fn(f64) -> f64 = if sign > 0.0 {
            |v| v.max(0.0)
        } else {
            |v| v.min(0.0)
        };
        let whole = self.integral(line, (start, end), keep);
        let step = LM71_SPACING / 64.0;
        let count = ((end - start + 2.0 * gap) / step).ceil() as usize;
        let grid = (0..=count).map(|k| start - gap + k as f64 * step);
        let on_points = (0..4).map(|i| station + half - i as f64 * LM71_SPACING);
        let mut best = 0.0f64;
        for centre in grid.chain(on_points) {
            let axles: f64 = (0..4)
                .map(|i| self.at(line, centre - half + i as f64 * LM71_SPACING))
                .map(keep)
                .sum();
            let under = self.integral(line, (centre - gap, centre + gap), keep);
            let effect = LM71_AXLE * axles + LM71_DISTRIBUTED * (whole - under);
            best = best.max(sign * effect);
        }
        alpha * best
    }
}

/// LM71 × `alpha` at each of `stations` of `beam` (any supports): the
/// largest sagging and hogging moments and downward deflection.
pub fn lm71_envelope(
    beam: &Beam,
    stations: &[f64],
    alpha: f64,
) -> Result<Vec<Lm71Effects>, String> {
    let lines = InfluenceLines::new(beam, stations)?;
    Ok(stations
        .iter()
        .enumerate()
        .map(|(i, &s)| Lm71Effects {
            sagging: lines.lm71(&lines.moment[i], s, 1.0, alpha),
            hogging: -lines.lm71(&lines.moment[i], s, -1.0, alpha),
            deflection: lines.lm71(&lines.deflection[i], s, 1.0, alpha),
        })
        .collect())
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

    /// A beam of `spans` (m) over pinned supports, 20 elements per span.
    fn continuous(spans: &[f64]) -> Beam {
        let mut x = 0.0;
        let mut inner = Vec::new();
        for l in &spans[..spans.len() - 1] {
            x += l;
            inner.push(x);
        }
        let length: f64 = spans.iter().sum();
        let text = format!(
            "name = \"c\"\ngravity = 9.81\n[beam]\nlength = {length:?}\nmass_per_length = 1e4\n\
             bending_stiffness = 2e10\nsurface_offset = 0.0\nelements = {}\n\
             supports = {{ intermediate = {inner:?} }}\n[body]\nname = \"f\"\n\
             kind = \"moving_force\"\nmass = 1.0\ninitial_position = 0.0\n\
             initial_speed = 50.0\n[solver]\nstep = 0.001\n",
            20 * spans.len()
        );
        let scene = crate::scene::Scene::from_toml_str(&text).unwrap();
        Beam::new(&scene.beam).unwrap()
    }

    /// Two equal spans L under a uniform load q over both: the moment over
    /// the middle support is −qL²/8 (the closed form of the propped
    /// cantilever, each span fixed at the middle support by symmetry).
    #[test]
    fn hogging_of_two_equal_spans_under_a_uniform_load_is_ql2_over_8() {
        let (l, q) = (20.0, 80e3);
        let beam = continuous(&[l, l]);
        let lines = InfluenceLines::new(&beam, &[l, 0.5 * l]).unwrap();
        let hogging = lines.uniform(&lines.moment[0], q);
        let expected = -q * l * l / 8.0;
        assert!(
            (hogging / expected - 1.0).abs() < 1e-5,
            "{hogging} vs {expected}"
        );
        // and midspan of a loaded span: R_A = 3qL/8, M = 3qL²/16 − qL²/8 = qL²/16
        let sagging = lines.uniform(&lines.moment[1], q);
        let expected = q * l * l / 16.0;
        assert!(
            (sagging / expected - 1.0).abs() < 1e-5,
            "{sagging} vs {expected}"
        );
    }

    /// LM71 over the middle support of two equal spans against the closed
    /// form written here: a unit load at a from the nearer end support
    /// gives M_B = −a (L² − a²) / (4 L²), negative on both spans, so the
    /// distributed load covers both spans outside the axles' 6.4 m; the
    /// axle group's centre searched on a 1 mm grid.
    #[test]
    fn lm71_hogging_over_the_middle_support_of_two_equal_spans() {
        let l = 20.0;
        let beam = continuous(&[l, l]);
        let found = lm71_envelope(&beam, &[l], 1.0).unwrap()[0];
        let eta = |x: f64| {
            if !(0.0..=2.0 * l).contains(&x) {
                return 0.0;
            }
            let a = x.min(2.0 * l - x);
            -a * (l * l - a * a) / (4.0 * l * l)
        };
        // ∫ η over [0, b] of one span, from the closed form: −(L² b²/2 − b⁴/4)/(4L²)
        let area = |b: f64| -(l * l * b * b / 2.0 - b.powi(4) / 4.0) / (4.0 * l * l);
        let span_area = |from: f64, to: f64| {
            // on span 1 (0..L) with a = x
            let (from, to) = (from.clamp(0.0, l), to.clamp(0.0, l));
            area(to) - area(from)
        };
        let whole = 2.0 * span_area(0.0, l);
        let under = |c: f64| {
            let (from, to) = (c - 3.2, c + 3.2);
            // mirror span 2 onto span 1
            span_area(from, to) + span_area(2.0 * l - to, 2.0 * l - from)
        };
        let best = (0..=46_400)
            .map(|k| -3.2 + k as f64 * 1e-3)
            .map(|c| {
                let axles: f64 = [-2.4, -0.8, 0.8, 2.4].iter().map(|e| eta(c + e)).sum();
                250e3 * axles + 80e3 * (whole - under(c))
            })
            .fold(0.0, f64::min);
        assert!((whole - (-l * l / 8.0)).abs() < 1e-9);
        assert!(
            (found.hogging / best - 1.0).abs() < 1e-4,
            "{} vs {best}",
            found.hogging
        );
    }

    /// The envelope on one simply supported span agrees with the closed
    /// form of `lm71_midspan`.
    #[test]
    fn lm71_envelope_of_one_span_is_the_closed_form() {
        let l = 20.0;
        let beam = continuous(&[l]);
        let e = lm71_envelope(&beam, &[0.5 * l], 1.0).unwrap()[0];
        let (m, w) = lm71_midspan(l, 2e10, 1.0);
        assert!((e.sagging / m - 1.0).abs() < 1e-4, "{} vs {m}", e.sagging);
        assert!(
            (e.deflection / w - 1.0).abs() < 1e-4,
            "{} vs {w}",
            e.deflection
        );
        assert!(e.hogging.abs() < 1e-6 * m);
    }

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

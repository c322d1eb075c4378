//! The code rules of a railway bridge's dynamic check, each a formula of
//! EN 1991-2:2003 §6.4 or EN 1990:2002 Annex A2 with its clause: pure
//! functions of the bridge's description, tested against values computed
//! by hand.

use std::f64::consts::PI;

/// The bridge types of EN 1991-2 Table 6.6 (damping lower limits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BridgeType {
    SteelComposite,
    PrestressedConcrete,
    ReinforcedConcrete,
    FillerBeam,
}

impl BridgeType {
    pub fn label(self) -> &'static str {
        match self {
            BridgeType::SteelComposite => "steel and composite",
            BridgeType::PrestressedConcrete => "prestressed concrete",
            BridgeType::ReinforcedConcrete => "reinforced concrete",
            BridgeType::FillerBeam => "filler beam",
        }
    }
}

/// EN 1991-2 Table 6.6: the lower limit of the percentage of critical
/// damping ζ (%) for span `l` (m):
/// steel and composite 0.5 + 0.125 (20 − L) below 20 m, else 0.5;
/// prestressed concrete 1.0 + 0.07 (20 − L), else 1.0;
/// filler beam and reinforced concrete 1.5 + 0.07 (20 − L), else 1.5.
pub fn damping_lower_limit(kind: BridgeType, l: f64) -> f64 {
    let short = (20.0 - l).max(0.0);
    match kind {
        BridgeType::SteelComposite => 0.5 + 0.125 * short,
        BridgeType::PrestressedConcrete => 1.0 + 0.07 * short,
        BridgeType::ReinforcedConcrete | BridgeType::FillerBeam => 1.5 + 0.07 * short,
    }
}

/// EN 1991-2 §6.4.6.4(3), eq. (6.13): the additional damping Δζ (%) of a
/// span `l` < 30 m for moving-force analyses (vehicle–bridge interaction
/// not modelled): (0.0187 L − 0.00064 L²) / (1 − 0.0441 L − 0.0044 L² +
/// 0.000255 L³); 0 from 30 m.
pub fn additional_damping(l: f64) -> f64 {
    if l >= 30.0 {
        return 0.0;
    }
    (0.0187 * l - 0.00064 * l * l) / (1.0 - 0.0441 * l - 0.0044 * l * l + 0.000255 * l.powi(3))
}

/// EN 1991-2 §6.4.4, Figure 6.10: the limits of the first natural
/// frequency n0 (Hz) of a span `l` (m) within which §6.4.4 lets a bridge
/// at up to 200 km/h go without dynamic analysis: upper 94.76 L^−0.748;
/// lower 80 / L for 4 m ≤ L ≤ 20 m and 23.58 L^−0.592 for 20 m < L ≤ 100 m.
pub fn frequency_limits(l: f64) -> (f64, f64) {
    let upper = 94.76 * libm::pow(l, -0.748);
    let lower = if l <= 20.0 {
        80.0 / l
    } else {
        23.58 * libm::pow(l, -0.592)
    };
    (lower, upper)
}

/// EN 1991-2 §6.4.4 and its flow chart (Figure 6.9), as far as a simply
/// supported span's inputs reach: above 200 km/h a dynamic analysis is
/// required; at or below, when n0 is outside the limits of Figure 6.10 or
/// the span is outside 4 m … 100 m. Returns (required, reason).
pub fn dynamic_analysis_required(line_speed_kmh: f64, l: f64, n0: f64) -> (bool, String) {
    if line_speed_kmh > 200.0 {
        return (
            true,
            format!("maximum line speed {line_speed_kmh} km/h > 200 km/h"),
        );
    }
    if !(4.0..=100.0).contains(&l) {
        return (
            true,
            format!("span {l} m outside the 4–100 m of Figure 6.10"),
        );
    }
    let (lower, upper) = frequency_limits(l);
    if n0 < lower || n0 > upper {
        return (
            true,
            format!("n0 = {n0:.3} Hz outside Figure 6.10's {lower:.3}–{upper:.3} Hz"),
        );
    }
    (
        false,
        format!(
            "V ≤ 200 km/h and n0 = {n0:.3} Hz within {lower:.3}–{upper:.3} Hz: the flow chart's \
             further conditions (torsion n_T > 1.2 n0, Annex F (v/n0)lim) are not coded; the \
             dynamic analysis is run anyway"
        ),
    )
}

/// EN 1991-2 §6.4.6.2(1): the maximum design speed, 1.2 × the maximum
/// line speed at the site.
pub fn maximum_design_speed(line_speed: f64) -> f64 {
    1.2 * line_speed
}

/// EN 1991-2 §6.4.6.2(3) (speeds from 40 m/s) and §6.4.6.2(2) (smaller
/// increments near resonance): km/h speeds from 144 km/h (40 m/s) to
/// `top` in `coarse` steps, and each of `resonances` (km/h) with `fine`
/// steps either side of it within ±`band` (a fraction of it), kept
/// within that range;
/// sorted, each once (to 1e-9 km/h).
pub fn speed_series(top: f64, coarse: f64, fine: f64, band: f64, resonances: &[f64]) -> Vec<f64> {
    let bottom = 144.0;
    let mut speeds = steps(bottom, top, coarse);
    for &v in resonances {
        // the resonant speed itself and `fine` steps either side of it
        let n = (band * v / fine + 1e-9).floor() as i64;
        let near = (-n..=n).map(|k| v + k as f64 * fine);
        speeds.extend(near.filter(|s| (bottom..=top).contains(s)));
    }
    speeds.sort_by(f64::total_cmp);
    speeds.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    speeds
}

/// `low`, `low + step`, … up to `high` inclusive (`high` itself last).
fn steps(low: f64, high: f64, step: f64) -> Vec<f64> {
    let count = ((high - low) / step + 1e-9).floor() as usize;
    let mut out: Vec<f64> = (0..=count).map(|i| low + i as f64 * step).collect();
    if out.last().is_some_and(|&v| v < high - 1e-9) {
        out.push(high);
    }
    out
}

/// EN 1991-2 §6.4.4, eq. (6.9): the resonant speeds v_i = n0 λ_i of a
/// train of regular spacing `spacing` (m) at natural frequency `n0` (Hz):
/// λ_i = D / i for i = 1 … `orders`, in km/h.
pub fn resonant_speeds(n0: f64, spacing: f64, orders: usize) -> Vec<f64> {
    (1..=orders)
        .map(|i| 3.6 * n0 * spacing / i as f64)
        .collect()
}

/// EN 1990 A2.4.4.2.1(4)P: the deck acceleration limits (m/s²), the
/// recommended values γ_bt = 3.5 (ballasted track) and γ_df = 5
/// (direct fastened track); National Annex choices.
pub const BALLASTED_ACCELERATION_LIMIT: f64 = 3.5;
pub const DIRECT_FASTENED_ACCELERATION_LIMIT: f64 = 5.0;

/// EN 1991-2 Annex C, eq. (C.4): the dynamic increment φ″ of track
/// irregularities for determinant length `l_phi` (m), first frequency
/// `n0` (Hz) and speed `v` (m/s): α/100 [56 e^−(LΦ/10)² + 50 (LΦ n0/80 −
/// 1) e^−(LΦ/20)²], α = v/22 up to 22 m/s, else 1; not below 0.
pub fn phi_irregularity(l_phi: f64, n0: f64, v: f64) -> f64 {
    let alpha = if v <= 22.0 { v / 22.0 } else { 1.0 };
    let value = alpha / 100.0
        * (56.0 * libm::exp(-(l_phi / 10.0).powi(2))
            + 50.0 * (l_phi * n0 / 80.0 - 1.0) * libm::exp(-(l_phi / 20.0).powi(2)));
    value.max(0.0)
}

/// EN 1991-2 §6.4.5.2(2), eqs. (6.4) and (6.5): the dynamic factor Φ for
/// determinant length `l_phi` (m): carefully maintained track Φ2 =
/// 1.44/(√LΦ − 0.2) + 0.82 within 1.00 … 1.67; standard maintenance Φ3 =
/// 2.16/(√LΦ − 0.2) + 0.73 within 1.00 … 2.00.
pub fn dynamic_factor(l_phi: f64, carefully_maintained: bool) -> f64 {
    let root = l_phi.sqrt() - 0.2;
    if carefully_maintained {
        (1.44 / root + 0.82).clamp(1.0, 1.67)
    } else {
        (2.16 / root + 0.73).clamp(1.0, 2.0)
    }
}

/// EN 1991-2 §6.4.6.5(3), eq. (6.15): the dynamic load effect to compare
/// with Φ × LM71: (1 + φ′_dyn + φ″/2) × the static effect of the real
/// train or HSLM for carefully maintained track, (1 + φ′_dyn + φ″) for
/// standard maintenance (Annex C note).
pub fn enhanced_dynamic_effect(
    static_effect: f64,
    phi_dyn: f64,
    phi_irr: f64,
    carefully_maintained: bool,
) -> f64 {
    let share = if carefully_maintained { 0.5 } else { 1.0 };
    (1.0 + phi_dyn + share * phi_irr) * static_effect
}

/// EN 1991-2 §6.3.2: Load Model 71: four 250 kN axles 1.6 m apart and
/// 80 kN/m on both sides of them (from 0.8 m beyond the outer axles),
/// times the classification factor α. (force N, spacing m, UDL N/m, clear
/// distance from the outer axles to the UDL m)
pub const LM71_AXLE: f64 = 250e3;
pub const LM71_SPACING: f64 = 1.6;
pub const LM71_DISTRIBUTED: f64 = 80e3;
pub const LM71_CLEAR: f64 = 0.8;

/// EI (N m²) of a simply supported span `l` (m) of mass `m` (kg/m) with
/// first natural frequency `f1` (Hz): f1 = (π / 2L²) √(EI/m).
pub fn stiffness_from_frequency(l: f64, m: f64, f1: f64) -> f64 {
    m * (2.0 * l * l * f1 / PI).powi(2)
}

/// The first natural frequency (Hz) of a simply supported span: the
/// inverse of `stiffness_from_frequency`.
pub fn first_frequency(l: f64, m: f64, ei: f64) -> f64 {
    PI / (2.0 * l * l) * (ei / m).sqrt()
}

/// EN 1991-2 §6.4.5.3, Table 6.2 case 5.1: the determinant length LΦ
/// (m) of the dynamic factor for a continuous beam of n spans: k × L_m,
/// L_m = (L1 + … + Ln)/n the mean span, k = 1.2, 1.3, 1.4 for n = 2, 3, 4
/// and 1.5 from 5; not less than the longest span. One span: its length.
pub fn determinant_length(spans: &[f64]) -> f64 {
    let n = spans.len();
    let longest = spans.iter().fold(0.0, |a: f64, &b| a.max(b));
    if n < 2 {
        return longest;
    }
    let mean = spans.iter().sum::<f64>() / n as f64;
    let k = match n {
        2 => 1.2,
        3 => 1.3,
        4 => 1.4,
        _ => 1.5,
    };
    (k * mean).max(longest)
}

/// EN 1990 A2.4.4.2.3(3): the largest total vertical deflection along a
/// track under rail traffic, L/600.
pub fn deflection_limit(l: f64) -> f64 {
    l / 600.0
}

/// How the spans of a bridge are arranged, for EN 1990 A2.4.4.3.2(5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpanArrangement {
    /// One span, or two simply supported spans, or two continuous spans.
    OneOrTwo,
    /// Three or more simply supported spans in succession (Figure A2.3's
    /// own case).
    SimplySupportedThreeOrMore,
    /// A continuous beam of three or more spans.
    ContinuousThreeOrMore,
}

/// EN 1990 A2.4.4.3.2, passenger comfort: the largest vertical deflection
/// δ (m) of a span `l` (m) under LM71 × Φ (α = 1), given `figure_ratio`,
/// the L/δ read off Figure A2.3 for this span and the maximum line speed
/// (the figure's curves are for b_v = 1 m/s² and three or more simply
/// supported spans). (4): for another comfort level b_v (m/s²) L/δ is
/// divided by b_v; (5): multiplied by 0.7 for one span or two spans and
/// by 0.9 for a continuous beam of three or more spans.
pub fn comfort_deflection_limit(
    l: f64,
    figure_ratio: f64,
    comfort_acceleration: f64,
    spans: SpanArrangement,
) -> f64 {
    let factor = match spans {
        SpanArrangement::OneOrTwo => 0.7,
        SpanArrangement::SimplySupportedThreeOrMore => 1.0,
        SpanArrangement::ContinuousThreeOrMore => 0.9,
    };
    l / (figure_ratio * factor / comfort_acceleration)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// EN 1990 A2.4.4.3.2 by hand, for L = 20 m and an L/δ of 1600 read
    /// off Figure A2.3: one span, b_v = 1: L/δ = 0.7 × 1600 = 1120, δ =
    /// 20/1120 = 17.857 mm; b_v = 1.3 (A2.4.4.3.1(2) "good"): 1120/1.3 =
    /// 861.54, δ = 23.214 mm; three continuous spans: 0.9 × 1600 = 1440,
    /// δ = 13.889 mm; three simply supported spans: 1600, δ = 12.5 mm.
    #[test]
    fn comfort_deflection_limits_of_a2_4_4_3_2() {
        use SpanArrangement::*;
        let cases = [
            (1.0, OneOrTwo, 0.017857142857),
            (1.3, OneOrTwo, 0.023214285714),
            (1.0, ContinuousThreeOrMore, 0.013888888889),
            (1.0, SimplySupportedThreeOrMore, 0.0125),
        ];
        for (bv, spans, expected) in cases {
            let got = comfort_deflection_limit(20.0, 1600.0, bv, spans);
            assert!(close(got, expected, 1e-9), "{spans:?} b_v {bv}: {got}");
        }
    }

    fn close(a: f64, b: f64, tolerance: f64) -> bool {
        (a - b).abs() <= tolerance * b.abs().max(1e-12)
    }

    /// EN 1991-2 Table 6.6, by hand: RC at 20 m 1.5 %; at 10 m 1.5 + 0.7
    /// = 2.2 %; steel at 12 m 0.5 + 1.0 = 1.5 %; prestressed at 25 m 1.0 %.
    #[test]
    fn table_6_6_damping_lower_limits() {
        assert!(close(
            damping_lower_limit(BridgeType::ReinforcedConcrete, 20.0),
            1.5,
            1e-12
        ));
        assert!(close(
            damping_lower_limit(BridgeType::FillerBeam, 10.0),
            2.2,
            1e-12
        ));
        assert!(close(
            damping_lower_limit(BridgeType::SteelComposite, 12.0),
            1.5,
            1e-12
        ));
        assert!(close(
            damping_lower_limit(BridgeType::PrestressedConcrete, 25.0),
            1.0,
            1e-12
        ));
        assert!(close(
            damping_lower_limit(BridgeType::PrestressedConcrete, 15.0),
            1.35,
            1e-12
        ));
    }

    /// EN 1991-2 §6.4.6.4 eq. (6.13) at L = 20 m by hand: numerator 0.374
    /// − 0.256 = 0.118, denominator 1 − 0.882 − 1.76 + 2.04 = 0.398,
    /// Δζ = 0.29648 %; at 10 m: 0.123 / (1 − 0.441 − 0.44 + 0.255) =
    /// 0.123 / 0.374 = 0.32888 %; none from 30 m.
    #[test]
    fn eq_6_13_additional_damping() {
        assert!(close(additional_damping(20.0), 0.118 / 0.398, 1e-12));
        assert!(close(additional_damping(10.0), 0.123 / 0.374, 1e-12));
        assert_eq!(additional_damping(30.0), 0.0);
    }

    /// Figure 6.10 at 20 m: lower 80/20 = 4 Hz, upper 94.76 × 20^−0.748 =
    /// 94.76 / 9.40092 = 10.0799 Hz (20^0.748 = e^(0.748 × 2.995732) =
    /// e^2.240808 = 9.40092).
    #[test]
    fn section_6_4_4_need_for_dynamic_analysis() {
        let (lower, upper) = frequency_limits(20.0);
        assert!(close(lower, 4.0, 1e-12));
        assert!(close(upper, 10.0799, 1e-5));
        assert!(dynamic_analysis_required(350.0, 20.0, 5.5).0);
        assert!(!dynamic_analysis_required(160.0, 20.0, 5.5).0);
        assert!(dynamic_analysis_required(160.0, 20.0, 3.0).0);
        assert!(dynamic_analysis_required(160.0, 20.0, 11.0).0);
    }

    /// §6.4.6.2: 1.2 × 350 = 420 km/h; from 144 km/h in 5s with 1s around
    /// 356.4 km/h (5.5 Hz × 18 m × 3.6) within ± 1 % (3.564 km/h): 353.4 …
    /// 359.4.
    #[test]
    fn section_6_4_6_2_speed_range() {
        assert!(close(maximum_design_speed(350.0), 420.0, 1e-12));
        let resonance = resonant_speeds(5.5, 18.0, 2);
        assert!(close(resonance[0], 356.4, 1e-12));
        assert!(close(resonance[1], 178.2, 1e-12));
        let speeds = speed_series(420.0, 5.0, 1.0, 0.01, &resonance[..1]);
        assert_eq!(speeds[0], 144.0);
        assert_eq!(*speeds.last().unwrap(), 420.0);
        let fine: Vec<f64> = speeds
            .iter()
            .copied()
            .filter(|v| (352.0..=360.0).contains(v))
            .collect();
        // 353.4, 354.4, …, 359.4 and the coarse 354, 359
        assert_eq!(fine.len(), 7 + 2);
        assert!(speeds.iter().any(|v| (v - 356.4).abs() < 1e-9));
    }

    /// Annex C at L = 20 m, n0 = 5.5 Hz, v = 97.2 m/s: 56 e^−4 = 1.025676,
    /// 50 × 0.375 × e^−1 = 6.897740, φ″ = 0.0792342; at v = 11 m/s half.
    #[test]
    fn annex_c_phi_irregularity() {
        let expected = (56.0 * libm::exp(-4.0f64) + 18.75 * libm::exp(-1.0f64)) / 100.0;
        assert!(close(expected, 0.0792342, 1e-6));
        assert!(close(phi_irregularity(20.0, 5.5, 97.2), expected, 1e-12));
        assert!(close(
            phi_irregularity(20.0, 5.5, 11.0),
            0.5 * expected,
            1e-12
        ));
        assert_eq!(phi_irregularity(60.0, 1.0, 97.2), 0.0); // negative, floored
    }

    /// §6.4.5.2 at LΦ = 20 m: √20 − 0.2 = 4.272136; Φ2 = 1.44/4.272136 +
    /// 0.82 = 1.157068; Φ3 = 2.16/4.272136 + 0.73 = 1.235602; short spans
    /// capped at 1.67 and 2.0.
    #[test]
    fn eq_6_4_and_6_5_dynamic_factors() {
        assert!(close(dynamic_factor(20.0, true), 1.157068, 1e-6));
        assert!(close(dynamic_factor(20.0, false), 1.235602, 1e-6));
        assert_eq!(dynamic_factor(2.0, true), 1.67);
        assert_eq!(dynamic_factor(2.0, false), 2.0);
    }

    /// eq. (6.15): (1 + 0.3 + 0.08/2) × 100 = 134; standard maintenance
    /// (1 + 0.3 + 0.08) × 100 = 138.
    #[test]
    fn eq_6_15_enhanced_dynamic_effect() {
        assert!(close(
            enhanced_dynamic_effect(100.0, 0.3, 0.08, true),
            134.0,
            1e-12
        ));
        assert!(close(
            enhanced_dynamic_effect(100.0, 0.3, 0.08, false),
            138.0,
            1e-12
        ));
    }

    /// Table 6.2 case 5.1 by hand: two spans 20 + 20 m: 1.2 × 20 = 24 m;
    /// three 15 + 20 + 15: 1.3 × 50/3 = 21.667 m; 10 + 30 (mean 20, 1.2 ×
    /// 20 = 24 < 30): the longest span 30 m; five of 10 m: 1.5 × 10 = 15;
    /// one span: itself.
    #[test]
    fn table_6_2_determinant_length_of_continuous_beams() {
        assert!(close(determinant_length(&[20.0, 20.0]), 24.0, 1e-12));
        assert!(close(
            determinant_length(&[15.0, 20.0, 15.0]),
            65.0 / 3.0,
            1e-12
        ));
        assert!(close(determinant_length(&[10.0, 30.0]), 30.0, 1e-12));
        assert!(close(determinant_length(&[10.0; 5]), 15.0, 1e-12));
        assert!(close(determinant_length(&[10.0; 4]), 14.0, 1e-12));
        assert!(close(determinant_length(&[17.0]), 17.0, 1e-12));
    }

    /// 20 m, 12 t/m, 5.5 Hz: EI = 12000 × (2 × 400 × 5.5 / π)² = 12000 ×
    /// 1400.5635² = 2.353893e10 N m².
    #[test]
    fn stiffness_from_the_first_frequency() {
        let ei = stiffness_from_frequency(20.0, 12000.0, 5.5);
        assert!(close(ei, 12000.0 * (4400.0 / PI).powi(2), 1e-12));
        assert!(close(ei, 2.353893e10, 1e-6));
        assert!(close(first_frequency(20.0, 12000.0, ei), 5.5, 1e-12));
        assert!(close(deflection_limit(20.0), 0.033333, 1e-4));
    }
}

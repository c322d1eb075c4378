//! Random profiles from a one-sided displacement power spectral density:
//! ISO 8608 classes A–H, the FRA track classes 1–6 and the German track
//! spectra for low and high interference.
//!
//! Generation: a sum of cosines at the frequencies k/P of a periodic grid
//! of N samples (period P = N Δx) within the wavelength band, amplitudes
//! √(2 G(n_k) Δn) and phases uniform from a ChaCha20 stream seeded with the
//! scene's seed, summed by an inverse FFT (rustfft), then interpolated by a
//! periodic C² cubic spline. The FFT makes N = 2²¹ samples cost a
//! fraction of a second where a direct sum of N/2 cosines at N points would
//! cost N²/2; its scalar planner is used so that the result does not depend
//! on the SIMD instructions of the machine: the same seed, band and
//! spacing give the same bits, whatever the track (see `MIN_PERIOD`). The
//! phases' sines and cosines are libm's, the same on every CPU; rustfft's
//! twiddle factors are glibc's, whose variant glibc picks by the CPU, and
//! gave the same bits with and without FMA (docs/robustness.md, "The same
//! bits on every CPU").

use rand_chacha::rand_core::{RngCore, SeedableRng};
use rand_chacha::ChaCha20Rng;
use rustfft::num_complex::Complex;
use rustfft::FftPlannerScalar;

use super::spline::PeriodicSpline;

/// Reference spatial frequency n₀ of ISO 8608 (cycles/m).
pub const ISO_REFERENCE_FREQUENCY: f64 = 0.1;

/// ISO 8608 (2016), table of road classes: the geometric mean of G_d(n₀)
/// of each class (m³, i.e. m² per cycle/m); each class is 4 times the one
/// before. Source: ISO 8608:2016, *Mechanical vibration — Road surface
/// profiles — Reporting of measured data*, Table 2 (n₀ = 0.1 cycles/m,
/// waviness w = 2); checked 2026-11-22, unchanged.
pub const ISO_CLASSES: [(&str, f64); 8] = [
    ("A", 16e-6),
    ("B", 64e-6),
    ("C", 256e-6),
    ("D", 1024e-6),
    ("E", 4096e-6),
    ("F", 16384e-6),
    ("G", 65536e-6),
    ("H", 262144e-6),
];

/// FRA track classes 1–6, vertical profile: roughness A_v (cm²·rad/m).
/// Source: the US Federal Railroad Administration's track-geometry spectra
/// as tabulated in W. Zhai, *Vehicle–Track Coupled Dynamics* (Springer,
/// 2020), ch. 3 (vertical profile: A_v, Ω_c = 0.8245 rad/m, k = 0.25; the
/// spectrum one-sided in Ω); checked 2026-11-22 against that table, no
/// constant differs. Other tabulations omit k (a profile twice as large)
/// or give Ω_c = 0.8242 rad/m.
pub const FRA_CLASSES: [(&str, f64); 6] = [
    ("1", 1.2107),
    ("2", 1.0181),
    ("3", 0.6816),
    ("4", 0.5376),
    ("5", 0.2095),
    ("6", 0.0339),
];
/// FRA vertical-profile cut-off wavenumber Ω_c (rad/m) and factor k.
pub const FRA_CUTOFF: f64 = 0.8245;
pub const FRA_FACTOR: f64 = 0.25;

/// German track spectra, vertical profile: cut-off wavenumbers Ω_c, Ω_r
/// (rad/m) and A_v (m·rad) for low and high interference. Source: the
/// German high-speed track spectra as tabulated in Zhai (2020), ch. 3
/// (vertical: Ω_c = 0.8246, Ω_r = 0.0206 rad/m, A_v = 4.032e-7 and
/// 1.080e-6 m·rad; the spectrum one-sided in Ω); checked 2026-11-22, no
/// constant differs.
pub const GERMAN_CUTOFF: f64 = 0.8246;
pub const GERMAN_ROLL_OFF: f64 = 0.0206;
pub const GERMAN_LOW: f64 = 4.032e-7;
pub const GERMAN_HIGH: f64 = 1.080e-6;

/// Most samples of a random profile's grid (memory about 100 MB while it
/// is generated).
pub const MAX_SAMPLES: usize = 1 << 21;

/// A displacement spectrum.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Spectrum {
    /// G_d(n) = G_d(n₀) (n/n₀)⁻², G_d(n₀) in m³.
    Iso8608 { reference: f64 },
    /// S(Ω) = k A_v Ω_c² / (Ω² (Ω² + Ω_c²)) cm²/(rad/m), A_v in cm²·rad/m.
    Fra { roughness: f64 },
    /// S(Ω) = A_v Ω_c² / ((Ω² + Ω_r²)(Ω² + Ω_c²)) m²/(rad/m), A_v in m·rad.
    German { roughness: f64 },
}

impl Spectrum {
    /// The spectrum named in a scene (`iso8608` with class A–H, `fra` with
    /// class 1–6, `german_low`, `german_high` without); the error says what
    /// is allowed.
    pub fn from_name(spectrum: &str, class: Option<&str>) -> Result<Spectrum, String> {
        let find = |table: &[(&str, f64)], class: Option<&str>| {
            table
                .iter()
                .find(|(name, _)| Some(*name) == class)
                .map(|&(_, value)| value)
        };
        match (spectrum, class) {
            ("iso8608", _) => find(&ISO_CLASSES, class)
                .map(|reference| Spectrum::Iso8608 { reference })
                .ok_or_else(|| "iso8608 needs class = \"A\" ... \"H\"".to_string()),
            ("fra", _) => find(&FRA_CLASSES, class)
                .map(|roughness| Spectrum::Fra { roughness })
                .ok_or_else(|| "fra needs class = \"1\" ... \"6\"".to_string()),
            ("german_low", None) => Ok(Spectrum::German {
                roughness: GERMAN_LOW,
            }),
            ("german_high", None) => Ok(Spectrum::German {
                roughness: GERMAN_HIGH,
            }),
            ("german_low" | "german_high", Some(_)) => {
                Err("the German spectra take no class".to_string())
            }
            _ => Err("must be iso8608, fra, german_low or german_high".to_string()),
        }
    }

    /// One-sided displacement PSD G(n) at the spatial frequency n
    /// (cycles/m), in m³ (m² per cycle/m): σ² = ∫ G(n) dn. The railway
    /// spectra are given per rad/m, S(Ω) with σ² = ∫ S(Ω) dΩ, so
    /// G(n) = 2π S(2πn).
    pub fn density(&self, n: f64) -> f64 {
        let omega = 2.0 * std::f64::consts::PI * n;
        let w2 = omega * omega;
        match *self {
            Spectrum::Iso8608 { reference } => reference * (n / ISO_REFERENCE_FREQUENCY).powi(-2),
            Spectrum::Fra { roughness } => {
                let c2 = FRA_CUTOFF * FRA_CUTOFF;
                // cm² → m².
                let s = 1e-4 * FRA_FACTOR * roughness * c2 / (w2 * (w2 + c2));
                2.0 * std::f64::consts::PI * s
            }
            Spectrum::German { roughness } => {
                let c2 = GERMAN_CUTOFF * GERMAN_CUTOFF;
                let r2 = GERMAN_ROLL_OFF * GERMAN_ROLL_OFF;
                let s = roughness * c2 / ((w2 + r2) * (w2 + c2));
                2.0 * std::f64::consts::PI * s
            }
        }
    }
}

/// The period (m) a random profile has at least where its spacing allows
/// (`MAX_SAMPLES` samples): its grid starts at x = 0 and repeats after its
/// period whatever the track's extent, so that a seed gives the same
/// profile at the same abscissa on any track (a speed sweep lengthens the
/// run-off with the speed).
pub const MIN_PERIOD: f64 = 10_000.0;

/// Where and how finely a random profile is sampled, and its band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    pub start: f64,
    pub spacing: f64,
    /// Number of samples, a power of two.
    pub samples: usize,
    /// Wavelengths kept (m): shortest, longest.
    pub band: (f64, f64),
}

impl Grid {
    /// The grid of a random profile at `spacing` in `band`: from x = 0,
    /// over `MIN_PERIOD` (or `MAX_SAMPLES` samples if fewer) and at least
    /// two longest wavelengths, a power of two samples; None when two
    /// longest wavelengths need more than `MAX_SAMPLES`. It depends on the
    /// spacing and the band only, never on the track.
    pub fn of_band(spacing: f64, band: (f64, f64)) -> Option<Grid> {
        let period = (MIN_PERIOD / spacing).min(MAX_SAMPLES as f64);
        let needed = (2.0 * band.1 / spacing).max(period).ceil();
        if !(needed.is_finite() && needed <= MAX_SAMPLES as f64) {
            return None;
        }
        let samples = (needed as usize).max(4).next_power_of_two();
        if samples > MAX_SAMPLES {
            return None;
        }
        Some(Grid {
            start: 0.0,
            spacing,
            samples,
            band,
        })
    }

    /// The period (m) after which the profile repeats.
    pub fn period(&self) -> f64 {
        self.samples as f64 * self.spacing
    }
}

/// A random profile of `spectrum` on `grid`, from `seed`.
pub fn generate(spectrum: &Spectrum, grid: &Grid, seed: u64) -> PeriodicSpline {
    let n = grid.samples;
    let period = n as f64 * grid.spacing;
    let dn = 1.0 / period;
    let (lowest, highest) = (1.0 / grid.band.1, 1.0 / grid.band.0);
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    let mut values = vec![Complex::new(0.0, 0.0); n];
    let mut curvatures = vec![Complex::new(0.0, 0.0); n];
    let tau = 2.0 * std::f64::consts::PI;
    for k in 1..n / 2 {
        // One phase per frequency of the grid, drawn in order whether or
        // not it is in the band: the band does not reshuffle the phases.
        let phase = (rng.next_u64() >> 11) as f64 * (tau / (1u64 << 53) as f64);
        let frequency = k as f64 * dn;
        if frequency < lowest || frequency > highest {
            continue;
        }
        let amplitude = (2.0 * spectrum.density(frequency) * dn).sqrt();
        // `Complex::from_polar` would take glibc's sine and cosine.
        let (sine, cosine) = libm::sincos(phase);
        let c = Complex::new(amplitude * cosine, amplitude * sine);
        let theta = tau * k as f64 / n as f64;
        values[k] = c;
        curvatures[k] = c * PeriodicSpline::curvature_factor(theta, grid.spacing);
    }
    let fft = FftPlannerScalar::new().plan_fft_inverse(n);
    fft.process(&mut values);
    fft.process(&mut curvatures);
    PeriodicSpline {
        start: grid.start,
        spacing: grid.spacing,
        y: values.iter().map(|c| c.re).collect(),
        m: curvatures.iter().map(|c| c.re).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iso_class_at_reference_frequency_is_its_mean() {
        let c = Spectrum::from_name("iso8608", Some("C")).unwrap();
        assert_eq!(c.density(0.1), 256e-6);
        assert!((c.density(0.2) - 64e-6).abs() < 1e-18);
        assert!(Spectrum::from_name("iso8608", Some("I")).is_err());
        assert!(Spectrum::from_name("fra", None).is_err());
        assert!(Spectrum::from_name("german_low", Some("1")).is_err());
    }

    #[test]
    fn railway_spectra_per_cycle_are_2pi_times_per_radian() {
        // FRA class 6 at Ω = 1 rad/m: k A_v Ω_c²/(1 + Ω_c²) cm²/(rad/m).
        let s = 0.25 * 0.0339 * 0.8245f64.powi(2) / (1.0 + 0.8245f64.powi(2)) * 1e-4;
        let fra = Spectrum::from_name("fra", Some("6")).unwrap();
        let n = 1.0 / (2.0 * std::f64::consts::PI);
        assert!((fra.density(n) / (2.0 * std::f64::consts::PI * s) - 1.0).abs() < 1e-12);
        let high = Spectrum::from_name("german_high", None).unwrap();
        let low = Spectrum::from_name("german_low", None).unwrap();
        assert!((high.density(0.3) / low.density(0.3) - 1.080e-6 / 4.032e-7).abs() < 1e-12);
    }

    /// Each spectrum at one point, worked out by hand from the published
    /// formula and constants (the literals here are not read from the
    /// tables above): G(n) = 2π S(Ω) at n = Ω / 2π.
    #[test]
    fn each_spectrum_at_a_known_point() {
        let per_cycle = |omega: f64| omega / (2.0 * std::f64::consts::PI);
        let close = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-9;
        // ISO 8608 class A at n = 1 cycle/m: 16e-6 m³ × (1 / 0.1)⁻².
        let a = Spectrum::from_name("iso8608", Some("A")).unwrap();
        assert!(close(a.density(1.0), 1.6e-7), "{}", a.density(1.0));
        // Class H at n = 0.05: 262144e-6 × 0.5⁻² = 1.048576 m³.
        let h = Spectrum::from_name("iso8608", Some("H")).unwrap();
        assert!(close(h.density(0.05), 1.048576));
        // FRA class 1 at Ω = Ω_c: k A_v / (2 Ω_c²) = 0.25 × 1.2107 /
        // (2 × 0.8245²) = 0.222621 cm²/(rad/m); × 2π × 1e-4 m²/cm².
        let fra1 = Spectrum::from_name("fra", Some("1")).unwrap();
        assert!(close(fra1.density(per_cycle(0.8245)), 1.398766117584e-4));
        // FRA class 5 at Ω = 2 rad/m: 0.25 × 0.2095 × 0.8245² /
        // (4 × (4 + 0.8245²)) = 1.902033e-3 cm²/(rad/m).
        let fra5 = Spectrum::from_name("fra", Some("5")).unwrap();
        assert!(close(fra5.density(per_cycle(2.0)), 1.195082581888e-6));
        // German low interference at Ω = 1 rad/m: 4.032e-7 × 0.8246² /
        // ((1 + 0.0206²)(1 + 0.8246²)) = 1.631258e-7 m²/(rad/m).
        let low = Spectrum::from_name("german_low", None).unwrap();
        assert!(close(low.density(per_cycle(1.0)), 1.024949621551e-6));
        // German high interference at Ω = Ω_c: 1.080e-6 × 0.8246² /
        // ((0.8246² + 0.0206²) × 2 × 0.8246²) = 7.936630e-7 m²/(rad/m).
        let high = Spectrum::from_name("german_high", None).unwrap();
        assert!(close(high.density(per_cycle(0.8246)), 4.986731814854e-6));
    }

    #[test]
    fn the_spline_passes_through_the_samples_with_their_curvature() {
        let grid = Grid::of_band(0.1, (1.0, 20.0)).unwrap();
        let spline = generate(
            &Spectrum::from_name("iso8608", Some("D")).unwrap(),
            &grid,
            3,
        );
        // At the samples the spline's second derivative is m; it is the
        // derivative of its slope between them.
        let x = -5.0 + 0.1 * 37.0 + 0.04;
        let d = 1e-6;
        let bend = (spline.at(x + d)[1] - spline.at(x - d)[1]) / (2.0 * d);
        assert!((bend - spline.at(x)[2]).abs() < 1e-6 * spline.at(x)[2].abs().max(1e-3));
        // Periodic: the profile repeats after N Δx.
        let period = grid.samples as f64 * grid.spacing;
        let (a, b) = (spline.at(1.234), spline.at(1.234 + period));
        assert!((a[0] - b[0]).abs() < 1e-12);
    }
}

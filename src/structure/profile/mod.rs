//! The track's vertical irregularity profile r(x) (m, up positive) and its
//! derivatives r', r'', r''': the sum of a scene's irregularities. The
//! contacts run on the beam's top plus r(x), and on the rigid approach and
//! run-off plus r(x) (see `crate::contact`).
//!
//! Every shape is at least C¹ (steps and ramps are rounded over a length of
//! the scene), so a contact that stays closed follows it with a bounded
//! force; r'' may jump where a shape starts or ends.

mod spec;
pub mod spectrum;
pub mod spline;

use std::f64::consts::PI;

pub use spec::IrregularitySpec;
use spectrum::{Grid, Spectrum};
use spline::{PeriodicSpline, TableSpline};

/// r, r', r'', r''' at one abscissa.
pub type Value = [f64; 4];

/// The summed profile.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    shapes: Vec<Shape>,
}

#[derive(Debug, Clone, PartialEq)]
enum Shape {
    Step {
        position: f64,
        height: f64,
        smoothing: f64,
    },
    Ramp {
        start: f64,
        end: f64,
        height: f64,
        smoothing: f64,
    },
    CosineDip {
        position: f64,
        wavelength: f64,
        depth: f64,
    },
    Sine {
        amplitude: f64,
        wavenumber: f64,
        phase: f64,
    },
    Table(TableSpline),
    Random(PeriodicSpline),
}

impl Profile {
    /// The profile of `specs` (validated); None without irregularities.
    /// It depends on the specs alone, not on the track's extent: a random
    /// profile is sampled from x = 0 over its own period
    /// (`spectrum::Grid::of_band`).
    pub fn new(specs: &[IrregularitySpec]) -> Result<Option<Profile>, String> {
        if specs.is_empty() {
            return Ok(None);
        }
        let shapes = specs.iter().map(Shape::new).collect::<Result<_, _>>()?;
        Ok(Some(Profile { shapes }))
    }

    /// r, r', r'', r''' at `x`.
    pub fn at(&self, x: f64) -> Value {
        let mut sum = [0.0; 4];
        for shape in &self.shapes {
            let v = shape.at(x);
            for k in 0..4 {
                sum[k] += v[k];
            }
        }
        sum
    }
}

impl Shape {
    fn new(spec: &IrregularitySpec) -> Result<Shape, String> {
        Ok(match *spec {
            IrregularitySpec::Step {
                position,
                height,
                smoothing,
            } => Shape::Step {
                position,
                height,
                smoothing,
            },
            IrregularitySpec::Ramp {
                start,
                length,
                height,
                smoothing,
            } => Shape::Ramp {
                start,
                end: start + length,
                height,
                smoothing,
            },
            IrregularitySpec::CosineDip {
                position,
                wavelength,
                depth,
            } => Shape::CosineDip {
                position,
                wavelength,
                depth,
            },
            IrregularitySpec::Sine {
                amplitude,
                wavelength,
                phase,
            } => Shape::Sine {
                amplitude,
                wavenumber: 2.0 * PI / wavelength,
                phase,
            },
            IrregularitySpec::Table { ref points, .. } => {
                if points.len() < 2 {
                    return Err("a profile table needs at least two points".into());
                }
                Shape::Table(TableSpline::new(points))
            }
            IrregularitySpec::Random { .. } => Shape::random(spec)?,
        })
    }

    /// A random profile's samples, generated once from its spectrum.
    fn random(spec: &IrregularitySpec) -> Result<Shape, String> {
        let IrregularitySpec::Random {
            ref spectrum,
            ref class,
            seed,
            shortest_wavelength,
            longest_wavelength,
            spacing,
        } = *spec
        else {
            return Err("not a random profile".into());
        };
        let spectrum = Spectrum::from_name(spectrum, class.as_deref())?;
        let spacing = IrregularitySpec::random_spacing(shortest_wavelength, spacing);
        let band = (shortest_wavelength, longest_wavelength);
        let grid = Grid::of_band(spacing, band).ok_or("a random profile has too many samples")?;
        Ok(Shape::Random(spectrum::generate(
            &spectrum,
            &grid,
            u64::from(seed),
        )))
    }

    fn at(&self, x: f64) -> Value {
        match *self {
            Shape::Step {
                position,
                height,
                smoothing,
            } => scale(smooth_step(x - position, smoothing), height),
            Shape::Ramp {
                start,
                end,
                height,
                smoothing,
            } => {
                let (a, b) = (
                    smooth_ramp(x - start, smoothing),
                    smooth_ramp(x - end, smoothing),
                );
                scale(
                    [a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]],
                    height / (end - start),
                )
            }
            Shape::CosineDip {
                position,
                wavelength,
                depth,
            } => {
                let u = x - position;
                if u.abs() >= 0.5 * wavelength {
                    return [0.0; 4];
                }
                let k = 2.0 * PI / wavelength;
                let (s, c) = libm::sincos(k * u);
                let d = 0.5 * depth;
                [-d * (1.0 + c), d * k * s, d * k * k * c, -d * k * k * k * s]
            }
            Shape::Sine {
                amplitude: a,
                wavenumber: k,
                phase,
            } => {
                let (s, c) = libm::sincos(k * x + phase);
                [a * s, a * k * c, -a * k * k * s, -a * k * k * k * c]
            }
            Shape::Table(ref spline) => spline.at(x),
            Shape::Random(ref spline) => spline.at(x),
        }
    }
}

fn scale(v: Value, factor: f64) -> Value {
    v.map(|x| x * factor)
}

/// A unit step at u = 0 rounded over `s` (half a sine period): C¹.
fn smooth_step(u: f64, s: f64) -> Value {
    if u <= -0.5 * s {
        [0.0; 4]
    } else if u >= 0.5 * s {
        [1.0, 0.0, 0.0, 0.0]
    } else {
        let k = PI / s;
        let (sn, c) = libm::sincos(k * u);
        [
            0.5 * (1.0 + sn),
            0.5 * k * c,
            -0.5 * k * k * sn,
            -0.5 * k * k * k * c,
        ]
    }
}

/// max(u, 0) with its corner rounded over `s`: the integral of the rounded
/// step, so C² (its curvature is zero where the rounding ends).
fn smooth_ramp(u: f64, s: f64) -> Value {
    if u <= -0.5 * s {
        [0.0; 4]
    } else if u >= 0.5 * s {
        [u, 1.0, 0.0, 0.0]
    } else {
        let step = smooth_step(u, s);
        let value = 0.5 * (u + 0.5 * s) - s / (2.0 * PI) * libm::cos(PI * u / s);
        [value, step[0], step[1], step[2]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn profile(spec: IrregularitySpec) -> Profile {
        Profile::new(&[spec]).unwrap().unwrap()
    }

    /// r' and r'' are the derivatives of r and r' (central differences).
    fn assert_consistent(p: &Profile, xs: &[f64]) {
        for &x in xs {
            let d = 1e-6;
            let (lo, hi, mid) = (p.at(x - d), p.at(x + d), p.at(x));
            for k in 0..2 {
                let rate = (hi[k] - lo[k]) / (2.0 * d);
                let scale = mid[k + 1].abs().max(1e-3);
                assert!(
                    (rate - mid[k + 1]).abs() < 1e-5 * scale,
                    "x {x}, derivative {k}: {rate} vs {}",
                    mid[k + 1]
                );
            }
        }
    }

    #[test]
    fn step_rises_smoothly_by_its_height() {
        let p = profile(IrregularitySpec::Step {
            position: 5.0,
            height: 0.01,
            smoothing: 0.4,
        });
        assert_eq!(p.at(4.7), [0.0; 4]);
        assert_eq!(p.at(5.3)[0], 0.01);
        assert!((p.at(5.0)[0] - 0.005).abs() < 1e-15);
        // C¹: the slope vanishes where the rounding meets the flat parts.
        assert!(p.at(4.8 + 1e-12)[1].abs() < 1e-9 && p.at(5.2 - 1e-12)[1].abs() < 1e-9);
        assert_consistent(&p, &[4.85, 5.0, 5.13]);
    }

    #[test]
    fn ramp_rises_linearly_between_rounded_corners() {
        let p = profile(IrregularitySpec::Ramp {
            start: 2.0,
            length: 4.0,
            height: 0.02,
            smoothing: 1.0,
        });
        assert_eq!(p.at(1.0), [0.0; 4]);
        assert!((p.at(4.0)[0] - 0.01).abs() < 1e-15 && (p.at(4.0)[1] - 0.005).abs() < 1e-15);
        assert!((p.at(7.0)[0] - 0.02).abs() < 1e-15 && p.at(7.0)[1] == 0.0);
        // Continuous at the ends of the rounding.
        for x in [1.5, 2.5, 5.5, 6.5] {
            let (l, r) = (p.at(x - 1e-9), p.at(x + 1e-9));
            assert!(
                (l[0] - r[0]).abs() < 1e-10 && (l[1] - r[1]).abs() < 1e-9,
                "{x}"
            );
        }
        assert_consistent(&p, &[1.7, 2.0, 2.3, 5.9]);
    }

    #[test]
    fn cosine_dip_and_sine_have_their_shapes() {
        let dip = profile(IrregularitySpec::CosineDip {
            position: 3.0,
            wavelength: 2.0,
            depth: 0.004,
        });
        assert_eq!(dip.at(3.0)[0], -0.004);
        assert_eq!(dip.at(4.0), [0.0; 4]);
        assert_consistent(&dip, &[2.3, 3.0, 3.6]);
        let sine = profile(IrregularitySpec::Sine {
            amplitude: 0.002,
            wavelength: 4.0,
            phase: 0.5,
        });
        assert!((sine.at(1.0)[0] - 0.002 * libm::sin(PI / 2.0 + 0.5)).abs() < 1e-18);
        assert_consistent(&sine, &[-3.0, 0.1, 7.7]);
    }

    #[test]
    fn irregularities_add_up() {
        let specs = [
            IrregularitySpec::Sine {
                amplitude: 0.002,
                wavelength: 4.0,
                phase: 0.0,
            },
            IrregularitySpec::CosineDip {
                position: 3.0,
                wavelength: 2.0,
                depth: 0.004,
            },
        ];
        let both = Profile::new(&specs).unwrap().unwrap();
        let (a, b) = (profile(specs[0].clone()), profile(specs[1].clone()));
        for x in [2.5, 3.1] {
            assert_eq!(both.at(x)[0], a.at(x)[0] + b.at(x)[0]);
        }
        assert_eq!(Profile::new(&[]).unwrap(), None);
    }
}

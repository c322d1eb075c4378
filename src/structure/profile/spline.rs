//! Cubic splines through profile samples: C² inside, so that the contact's
//! surface slope (in its normal) and curvature (in the foot-point search and
//! the nominal speed) are continuous, and a contact follows the profile with
//! a bounded force.
//!
//! Written by hand: two small solves (a clamped tridiagonal one, and a
//! periodic one done in the Fourier domain, where the profile already is)
//! and the textbook evaluation; the spline crates interpolate without the
//! second and third derivatives the contact needs.

/// r, r', r'', r''' on the interval [x_i, x_i + h] from the values y and the
/// second derivatives m at its ends.
fn cubic(t: f64, h: f64, (y0, y1): (f64, f64), (m0, m1): (f64, f64)) -> [f64; 4] {
    let s = 1.0 - t;
    let r = s * y0 + t * y1 + h * h / 6.0 * ((s * s * s - s) * m0 + (t * t * t - t) * m1);
    let slope = (y1 - y0) / h + h / 6.0 * (-(3.0 * s * s - 1.0) * m0 + (3.0 * t * t - 1.0) * m1);
    [r, slope, s * m0 + t * m1, (m1 - m0) / h]
}

/// A spline through (x_i, y_i), x strictly increasing, with zero slope at
/// the first and last point and constant beyond them: r and r' continuous
/// everywhere, r'' inside the table.
#[derive(Debug, Clone, PartialEq)]
pub struct TableSpline {
    x: Vec<f64>,
    y: Vec<f64>,
    m: Vec<f64>,
}

impl TableSpline {
    /// `points`: at least two, abscissae strictly increasing (the scene's
    /// validation checks it).
    pub fn new(points: &[[f64; 2]]) -> TableSpline {
        let x: Vec<f64> = points.iter().map(|p| p[0]).collect();
        let y: Vec<f64> = points.iter().map(|p| p[1]).collect();
        let n = x.len();
        let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
        let secant: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
        // Rows (sub, diag, sup) = rhs of the clamped spline (r' = 0 at both
        // ends), solved by Thomas' algorithm (diagonally dominant).
        let mut diag = vec![0.0; n];
        let mut sup = vec![0.0; n];
        let mut sub = vec![0.0; n];
        let mut rhs = vec![0.0; n];
        diag[0] = 2.0 * h[0];
        sup[0] = h[0];
        rhs[0] = 6.0 * secant[0];
        for i in 1..n - 1 {
            sub[i] = h[i - 1];
            diag[i] = 2.0 * (h[i - 1] + h[i]);
            sup[i] = h[i];
            rhs[i] = 6.0 * (secant[i] - secant[i - 1]);
        }
        sub[n - 1] = h[n - 2];
        diag[n - 1] = 2.0 * h[n - 2];
        rhs[n - 1] = -6.0 * secant[n - 2];
        for i in 1..n {
            let w = sub[i] / diag[i - 1];
            diag[i] -= w * sup[i - 1];
            rhs[i] -= w * rhs[i - 1];
        }
        let mut m = vec![0.0; n];
        m[n - 1] = rhs[n - 1] / diag[n - 1];
        for i in (0..n - 1).rev() {
            m[i] = (rhs[i] - sup[i] * m[i + 1]) / diag[i];
        }
        TableSpline { x, y, m }
    }

    pub fn at(&self, x: f64) -> [f64; 4] {
        let n = self.x.len();
        if x.is_nan() {
            return [f64::NAN; 4];
        }
        if x <= self.x[0] {
            return [self.y[0], 0.0, 0.0, 0.0];
        }
        if x >= self.x[n - 1] {
            return [self.y[n - 1], 0.0, 0.0, 0.0];
        }
        let i = self.x.partition_point(|&xi| xi <= x).clamp(1, n - 1) - 1;
        let h = self.x[i + 1] - self.x[i];
        cubic(
            (x - self.x[i]) / h,
            h,
            (self.y[i], self.y[i + 1]),
            (self.m[i], self.m[i + 1]),
        )
    }
}

/// A periodic spline through samples y_j at x = start + j·spacing, of
/// period N·spacing; `m` its second derivatives at the samples.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicSpline {
    pub start: f64,
    pub spacing: f64,
    pub y: Vec<f64>,
    pub m: Vec<f64>,
}

impl PeriodicSpline {
    pub fn at(&self, x: f64) -> [f64; 4] {
        let n = self.y.len();
        let u = (x - self.start) / self.spacing;
        if !u.is_finite() {
            return [f64::NAN; 4];
        }
        // The cell is wrapped into the period, not the abscissa: wrapping
        // x < start to x + period left t with the round-off of the period
        // (3e-12 m at 13 km), enough to stall the foot-point search on the
        // approach at its 1e-14 |x| tolerance.
        let cell = u.floor();
        let t = (u - cell).clamp(0.0, 1.0);
        // rem_euclid may round up to n itself.
        let i = (cell.rem_euclid(n as f64) as usize).min(n - 1);
        let j = (i + 1) % n;
        cubic(
            t,
            self.spacing,
            (self.y[i], self.y[j]),
            (self.m[i], self.m[j]),
        )
    }

    /// The spline's second-derivative equations m_{j−1} + 4 m_j + m_{j+1} =
    /// 6 (y_{j−1} − 2 y_j + y_{j+1})/Δx² are a circulant system: diagonal in
    /// the Fourier domain, where mode k (angle θ = 2πk/N) is scaled by this.
    pub fn curvature_factor(theta: f64, spacing: f64) -> f64 {
        let c = libm::cos(theta);
        6.0 * (2.0 * c - 2.0) / (spacing * spacing * (4.0 + 2.0 * c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_spline_interpolates_and_is_c1_and_c2_inside() {
        let points = [
            [0.0, 0.0],
            [1.0, 0.01],
            [2.5, -0.02],
            [3.0, 0.0],
            [5.0, 0.004],
        ];
        let s = TableSpline::new(&points);
        for p in &points {
            assert!((s.at(p[0])[0] - p[1]).abs() < 1e-15, "{p:?}");
        }
        for p in &points[1..points.len() - 1] {
            let (l, r) = (s.at(p[0] - 1e-9), s.at(p[0] + 1e-9));
            assert!((l[1] - r[1]).abs() < 1e-7, "slope jump at {}", p[0]);
            assert!((l[2] - r[2]).abs() < 1e-6, "curvature jump at {}", p[0]);
        }
        // Zero slope at the ends, constant beyond.
        assert!(s.at(1e-12)[1].abs() < 1e-9 && s.at(5.0 - 1e-12)[1].abs() < 1e-9);
        assert_eq!(s.at(-3.0), [0.0, 0.0, 0.0, 0.0]);
        assert_eq!(s.at(9.0), [0.004, 0.0, 0.0, 0.0]);
    }

    #[test]
    fn table_spline_slope_is_the_derivative_of_its_value() {
        let s = TableSpline::new(&[[0.0, 0.0], [0.7, 0.003], [1.1, 0.001], [2.0, 0.0]]);
        for x in [0.2, 0.69, 0.9, 1.5] {
            let d = 1e-6;
            let rate = (s.at(x + d)[0] - s.at(x - d)[0]) / (2.0 * d);
            let bend = (s.at(x + d)[1] - s.at(x - d)[1]) / (2.0 * d);
            assert!((rate - s.at(x)[1]).abs() < 1e-8, "{x}");
            assert!((bend - s.at(x)[2]).abs() < 1e-6, "{x}");
        }
    }
}

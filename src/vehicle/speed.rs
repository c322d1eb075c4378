//! A body's prescribed horizontal speed (`body.prescribed_speed`):
//! constant or a table over time, and its value at an instant.

use serde::{Deserialize, Serialize};

/// A prescribed horizontal speed: constant, or a table of (time, speed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "a speed in m/s, or a table [[t0, v0], [t1, v1], ...] of times (s) and speeds (m/s)"
)]
pub enum SpeedSpec {
    Constant(f64),
    Table(Vec<[f64; 2]>),
}

impl SpeedSpec {
    /// The speed at time `t` (m/s): linear between the table's rows, held
    /// before the first and after the last.
    pub fn speed_at(&self, t: f64) -> f64 {
        match self {
            SpeedSpec::Constant(v) => *v,
            SpeedSpec::Table(rows) => {
                let after = rows.partition_point(|row| row[0] <= t);
                match (after.checked_sub(1).map(|i| rows[i]), rows.get(after)) {
                    (Some(a), Some(b)) => a[1] + (b[1] - a[1]) * (t - a[0]) / (b[0] - a[0]),
                    (Some(a), None) => a[1],
                    (None, Some(b)) => b[1],
                    (None, None) => 0.0,
                }
            }
        }
    }
}

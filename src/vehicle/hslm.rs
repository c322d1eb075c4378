//! The High Speed Load Model HSLM-A of EN 1991-2:2003, Annex E: ten
//! articulated trains, A1 … A10, each two power cars, two end coaches and N
//! intermediate coaches of length D on shared (Jacobs) bogies of axle
//! spacing d, every axle carrying the point force P.

/// One row of EN 1991-2, Annex E, Table E.1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HslmTrain {
    pub name: &'static str,
    /// Number of intermediate coaches N.
    pub coaches: usize,
    /// Coach length D (m).
    pub coach_length: f64,
    /// Bogie axle spacing d (m).
    pub bogie_axle_spacing: f64,
    /// Point force P per axle (N).
    pub axle_force: f64,
}

/// EN 1991-2:2003, Annex E, Table E.1 (HSLM-A): N, D (m), d (m), P (kN).
pub const HSLM_TRAINS: [HslmTrain; 10] = [
    train("HSLM-A1", 18, 18.0, 2.0, 170.0),
    train("HSLM-A2", 17, 19.0, 3.5, 200.0),
    train("HSLM-A3", 16, 20.0, 2.0, 180.0),
    train("HSLM-A4", 15, 21.0, 3.0, 190.0),
    train("HSLM-A5", 14, 22.0, 2.0, 170.0),
    train("HSLM-A6", 13, 23.0, 2.0, 180.0),
    train("HSLM-A7", 13, 24.0, 2.0, 190.0),
    train("HSLM-A8", 12, 25.0, 2.5, 190.0),
    train("HSLM-A9", 11, 26.0, 2.0, 210.0),
    train("HSLM-A10", 11, 27.0, 2.0, 210.0),
];

const fn train(name: &'static str, n: usize, d_coach: f64, d_bogie: f64, p_kn: f64) -> HslmTrain {
    HslmTrain {
        name,
        coaches: n,
        coach_length: d_coach,
        bogie_axle_spacing: d_bogie,
        axle_force: p_kn * 1e3,
    }
}

/// The fixed dimensions of EN 1991-2, Annex E, Figure E.1 (m): a power car's
/// bogie axle spacing and the distance between its inner axles; the
/// overhang of a power car and of an end coach beyond their outer axles
/// (two of them between the cars); an end coach's bogie axle spacing and
/// the distance from its bogie to the first shared bogie.
pub const POWER_CAR_BOGIE: f64 = 3.0;
pub const POWER_CAR_INNER: f64 = 11.0;
pub const OVERHANG: f64 = 3.525;
pub const END_COACH_BOGIE: f64 = 3.0;
pub const END_COACH_TO_SHARED_BOGIE: f64 = 15.0;

/// The HSLM-A train of that name (`HSLM-A1` … `HSLM-A10`, any case).
pub fn hslm(name: &str) -> Option<HslmTrain> {
    HSLM_TRAINS
        .iter()
        .find(|t| t.name.eq_ignore_ascii_case(name))
        .copied()
}

impl HslmTrain {
    /// Each axle's distance behind the leading axle (m) and its vertical
    /// force (N, y up), front to rear: power car, end coach, the N + 1
    /// shared bogies, end coach, power car (2N + 14 axles).
    pub fn axles(&self) -> Vec<(f64, f64)> {
        let power_car = [
            0.0,
            POWER_CAR_BOGIE,
            POWER_CAR_BOGIE + POWER_CAR_INNER,
            2.0 * POWER_CAR_BOGIE + POWER_CAR_INNER,
        ];
        let power_car_length = power_car[3];
        let mut offsets: Vec<f64> = power_car.to_vec();
        let end_coach = power_car_length + 2.0 * OVERHANG;
        offsets.extend([end_coach, end_coach + END_COACH_BOGIE]);
        let first_shared = end_coach + END_COACH_BOGIE + END_COACH_TO_SHARED_BOGIE;
        for k in 0..=self.coaches {
            let bogie = first_shared + k as f64 * self.coach_length;
            offsets.extend([bogie, bogie + self.bogie_axle_spacing]);
        }
        let last_shared = *offsets.last().expect("shared bogies");
        let rear_coach = last_shared + END_COACH_TO_SHARED_BOGIE;
        offsets.extend([rear_coach, rear_coach + END_COACH_BOGIE]);
        let rear_power = rear_coach + END_COACH_BOGIE + 2.0 * OVERHANG;
        offsets.extend(power_car.iter().map(|x| rear_power + x));
        offsets.into_iter().map(|x| (x, -self.axle_force)).collect()
    }

    /// Distance from the leading to the trailing axle (m).
    pub fn length(&self) -> f64 {
        self.axles().last().map_or(0.0, |a| a.0)
    }
}

//! Real high-speed trains as moving forces, from published axle-load
//! tables shipped as TOML files (src/moving_load/trains/*.toml), each file
//! naming its source: read, validated, and given as axle offsets and forces.

use serde::Deserialize;

/// One real train: its name, its source, the regular spacing (m) that
/// sets its resonant speeds, and its axles as (distance behind the leading
/// axle (m), load (kN)).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RealTrain {
    pub name: String,
    pub source: String,
    pub regular_spacing: f64,
    pub axles: Vec<[f64; 2]>,
}

/// The shipped tables (name of the file, its text).
const TABLES: [(&str, &str); 2] = [
    ("ice2.toml", include_str!("trains/ice2.toml")),
    ("talgo_av.toml", include_str!("trains/talgo_av.toml")),
];

impl RealTrain {
    /// Parse and validate one table: at least one axle, offsets from 0
    /// increasing, loads and spacing positive and finite.
    pub fn from_toml_str(text: &str) -> Result<RealTrain, String> {
        let train: RealTrain = toml::from_str(text).map_err(|e| e.to_string())?;
        let first = train.axles.first().ok_or("axles: at least one axle")?;
        if first[0] != 0.0 {
            return Err(format!(
                "axles[0] at {} m: the first axle is at 0 m",
                first[0]
            ));
        }
        for (i, pair) in train.axles.windows(2).enumerate() {
            if !(pair[1][0] > pair[0][0] && pair[1][0].is_finite()) {
                return Err(format!(
                    "axles[{}] at {} m: offsets must increase",
                    i + 1,
                    pair[1][0]
                ));
            }
        }
        if let Some((i, a)) = train
            .axles
            .iter()
            .enumerate()
            .find(|(_, a)| !(a[1] > 0.0 && a[1] <= 1000.0))
        {
            return Err(format!(
                "axles[{i}] load {} kN: must be in (0, 1000] kN",
                a[1]
            ));
        }
        if !(train.regular_spacing > 0.0 && train.regular_spacing <= 100.0) {
            return Err(format!(
                "regular_spacing = {}: must be in (0, 100] m",
                train.regular_spacing
            ));
        }
        Ok(train)
    }

    /// Every shipped train.
    pub fn shipped() -> Vec<RealTrain> {
        TABLES
            .iter()
            .map(|(file, text)| {
                RealTrain::from_toml_str(text)
                    .unwrap_or_else(|e| panic!("shipped train table {file}: {e}"))
            })
            .collect()
    }

    /// Number of axles, total load (kN) and length from the first to the
    /// last axle (m).
    pub fn totals(&self) -> (usize, f64, f64) {
        let total = self.axles.iter().map(|a| a[1]).sum();
        let length = self.axles.last().map_or(0.0, |a| a[0]);
        (self.axles.len(), total, length)
    }

    /// The axles as (offset (m), force (N, up positive)).
    pub fn forces(&self) -> Vec<(f64, f64)> {
        self.axles.iter().map(|a| (a[0], -1e3 * a[1])).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Totals of the published tables (IAPF-07 Annex C), added by hand:
    // ICE 2: 2 power cars × 4 axles × 195 kN + 12 coaches × 4 × 112 kN =
    // 1560 + 5376 = 6936 kN on 56 axles, 350.52 m from first to last axle;
    // Talgo AV: 40 axles × 170 kN = 6800 kN, 356.05 m.
    #[test]
    fn shipped_trains_have_their_published_totals() {
        let trains = RealTrain::shipped();
        let expect = [
            ("ICE2", 56, 6936.0, 350.52),
            ("TalgoAV", 40, 6800.0, 356.05),
        ];
        assert_eq!(trains.len(), expect.len());
        for (train, (name, axles, total, length)) in trains.iter().zip(expect) {
            assert_eq!(train.name, name);
            let (n, sum, l) = train.totals();
            assert_eq!(n, axles, "{name}");
            assert!((sum - total).abs() < 1e-9, "{name}: {sum} kN");
            assert!((l - length).abs() < 1e-9, "{name}: {l} m");
            assert!(train.source.contains("IAPF"), "{name} names its source");
        }
    }

    #[test]
    fn ice2_coaches_repeat_at_their_regular_spacing() {
        // Each ICE 2 coach's leading axle is 26.40 m behind the previous one's.
        let ice2 = &RealTrain::shipped()[0];
        for k in 0..11 {
            let a = ice2.axles[4 + 4 * k][0];
            let b = ice2.axles[8 + 4 * k][0];
            assert!((b - a - ice2.regular_spacing).abs() < 1e-9, "coach {k}");
        }
    }

    #[test]
    fn bad_tables_are_refused_naming_the_field() {
        let base = "name = \"x\"\nsource = \"s\"\nregular_spacing = 10.0\n";
        let cases = [
            ("axles = []", "at least one axle"),
            ("axles = [[1.0, 100.0]]", "axles[0] at 1 m"),
            ("axles = [[0.0, 100.0], [0.0, 100.0]]", "axles[1] at 0 m"),
            ("axles = [[0.0, -5.0]]", "axles[0] load -5 kN"),
        ];
        for (axles, message) in cases {
            let e = RealTrain::from_toml_str(&format!("{base}{axles}")).unwrap_err();
            assert!(e.contains(message), "{axles}: {e}");
        }
    }
}

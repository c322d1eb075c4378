//! `guideway check` (issue 28): the built-in 20 m bridge's check, its
//! verdicts against the runs and the code's formulas written out here, bad
//! descriptions refused naming the field, and the report rendered headless
//! in Chromium with its PASS/FAIL table.

use guideway::check::report::{input_hash, write_report};
use guideway::check::spec::EXAMPLE;
use guideway::check::{run_check, BridgeSpec};
use std::f64::consts::PI;
use std::process::Command;

/// A quick variant of the example: coarse speeds, two mass bounds.
const QUICK: &str = r#"
name = "quick"
span = 20.0
mass_per_length = 12000.0
mass_lower = 10800.0
mass_upper = 13200.0
first_frequency = 5.5
bridge_type = "reinforced_concrete"
track = "ballasted"
line_speed = 300.0
[settings]
speed_step = 20.0
fine_speed_step = 10.0
"#;

#[test]
fn the_built_in_bridge_is_checked_by_the_code_rules() {
    let spec = BridgeSpec::from_toml_str(EXAMPLE).unwrap();
    let r = run_check(&spec, 2).unwrap();
    // EI from f1 = 5.5 Hz at 12 t/m: 12000 (2 × 400 × 5.5 / π)²
    let ei = 12000.0 * (4400.0 / PI).powi(2);
    assert!((r.bending_stiffness - ei).abs() < 1e-9 * ei);
    // Table 6.6 (RC, L = 20 m) 1.5 % + eq. (6.13) 0.118 / 0.398 %
    assert!((r.damping_percent - (1.5 + 0.118 / 0.398)).abs() < 1e-12);
    // §6.4.6.2: to 1.2 × 350 km/h, from 40 m/s
    let top = r.runs.iter().map(|x| x.speed_kmh).fold(0.0, f64::max);
    let bottom = r
        .runs
        .iter()
        .map(|x| x.speed_kmh)
        .fold(f64::INFINITY, f64::min);
    assert_eq!((bottom, top), (144.0, 420.0));
    // the cut-off max(30, 1.5 × 5.5, 9 × 5.5) = 49.5 Hz
    assert!((r.mass_cases[0].cut_off - 49.5).abs() < 1e-9);
    // the acceleration verdict is the largest filtered peak, against 3.5
    let worst = r
        .runs
        .iter()
        .map(|x| x.acceleration_filtered)
        .fold(0.0, f64::max);
    let acc = r
        .verdicts
        .iter()
        .find(|v| v.clause.starts_with("EN 1990 A2.4.4.2.1"))
        .unwrap();
    assert!(
        acc.value.starts_with(&format!("{worst:.3} m/s²")),
        "{}",
        acc.value
    );
    assert_eq!(acc.status, if worst <= 3.5 { "PASS" } else { "FAIL" });
    // HSLM-A1's first resonance f1 D = 5.5 × 18 × 3.6 = 356.4 km/h is run
    // in the fine steps, and its DAF there is a resonance peak
    let a1 = |v: f64| {
        r.runs
            .iter()
            .find(|x| x.train == "HSLM-A1" && (x.speed_kmh - v).abs() < 1e-6)
    };
    let near = r
        .runs
        .iter()
        .filter(|x| x.train == "HSLM-A1" && (x.speed_kmh - 356.4).abs() < 10.7);
    // ±3 % of 356.4 = ±10.69 km/h in 1 km/h steps: 21 speeds, and the coarse ones
    assert!(near.count() >= 20, "fine steps around 356.4 km/h");
    assert!(a1(356.4).unwrap().daf_deflection > 2.0 * a1(299.0).unwrap().daf_deflection);
    // the deflection verdict: Φ2 α LM71 against L/600 (hand values in
    // check::lm71 and check::rules)
    let defl = r
        .verdicts
        .iter()
        .find(|v| v.clause == "EN 1990 A2.4.4.2.3(3)")
        .unwrap();
    assert_eq!(defl.status, "PASS");
}

#[test]
fn mass_bounds_give_two_cases_with_their_frequencies() {
    let spec = BridgeSpec::from_toml_str(QUICK).unwrap();
    let r = run_check(&spec, 2).unwrap();
    let names: Vec<&str> = r.mass_cases.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["lower", "upper"]);
    // EI held: f1 ∝ 1/√m
    assert!((r.mass_cases[0].f1 - 5.5 * (12000.0f64 / 10800.0).sqrt()).abs() < 1e-9);
    assert!((r.mass_cases[1].f1 - 5.5 * (12000.0f64 / 13200.0).sqrt()).abs() < 1e-9);
    assert!(r.runs.iter().any(|x| x.mass_case == "upper"));
    // the acceleration verdict reads the lower bound (§6.4.6.3.2)
    let acc = r
        .verdicts
        .iter()
        .find(|v| v.clause.starts_with("EN 1990 A2.4.4.2.1"))
        .unwrap();
    assert!(acc.value.contains("lower mass"), "{}", acc.value);
}

#[test]
fn bad_descriptions_are_refused_naming_the_field() {
    let cases = [
        ("span = 20.0", "span = -1.0", "span = -1"),
        (
            "line_speed = 300.0",
            "line_speed = 1e9",
            "line_speed = 1000000000",
        ),
        (
            "mass_lower = 10800.0",
            "mass_lower = 20000.0",
            "mass_lower = 20000",
        ),
        (
            "first_frequency = 5.5",
            "first_frequency = nan",
            "first_frequency = NaN",
        ),
        (
            "speed_step = 20.0",
            "speed_step = 0.0",
            "settings.speed_step = 0",
        ),
        ("span = 20.0", "span = 5.0", "HSLM-B"),
    ];
    for (from, to, needle) in cases {
        let text = QUICK.replace(from, to);
        let error = BridgeSpec::from_toml_str(&text).unwrap_err();
        assert!(error.contains(needle), "{to}: {error}");
    }
    let both = QUICK.replace(
        "first_frequency = 5.5",
        "first_frequency = 5.5\nbending_stiffness = 1e10",
    );
    assert!(BridgeSpec::from_toml_str(&both)
        .unwrap_err()
        .contains("one of first_frequency"));
    let unknown = QUICK.replace("track =", "colour = \"red\"\ntrack =");
    assert!(BridgeSpec::from_toml_str(&unknown)
        .unwrap_err()
        .contains("colour"));
}

/// The report opens with no network (only data: images) and Chromium
/// renders its PASS/FAIL table.
#[test]
fn the_report_renders_headless_with_its_verdicts() {
    let spec = BridgeSpec::from_toml_str(QUICK).unwrap();
    let r = run_check(&spec, 2).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let files = write_report(&r, QUICK, dir.path()).unwrap();
    let html_path = &files[0];
    assert!(html_path.ends_with("report.html"));
    let html = std::fs::read_to_string(html_path).unwrap();
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "self-contained"
    );
    assert_eq!(html.matches("data:image/png;base64,").count(), 3);
    assert!(html.contains(&input_hash(QUICK)));
    for name in ["runs.csv", "checks.csv", "check.json", "worst_history.csv"] {
        assert!(dir.path().join(name).exists(), "{name}");
    }
    let chromium = ["chromium", "chromium-browser"]
        .into_iter()
        .find(|c| Command::new(c).arg("--version").output().is_ok())
        .expect("Chromium is needed for this test: bash scripts/setup.sh installs it");
    let out = Command::new(chromium)
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--dump-dom"])
        .arg(format!("file://{}", html_path.display()))
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&out.stdout);
    assert!(
        dom.contains("<table id=\"verdicts\">"),
        "rendered DOM: {}",
        &dom[..dom.len().min(500)]
    );
    let statuses = dom.matches("<td class=\"PASS\">PASS</td>").count()
        + dom.matches("<td class=\"FAIL\">FAIL</td>").count();
    assert_eq!(
        statuses,
        r.verdicts.iter().filter(|v| v.status != "INFO").count()
    );
    assert!(statuses >= 2);
    assert!(dom.contains("id=\"overall\""));
}

/// Midspan deflection (m, largest |w|) of a simply supported span under
/// moving forces by modal superposition (`modal_peaks`).
fn modal_midspan_peak(
    bridge: (f64, f64, f64),
    zeta_of: &dyn Fn(f64) -> f64,
    axles: &[(f64, f64)],
    speed: f64,
) -> f64 {
    modal_peaks(bridge, zeta_of, axles, speed).0
}

/// Largest |w| at midspan (m) and largest |ẅ| (m/s²) over the check's
/// stations L/10, 3L/10, L/2, 7L/10, 9L/10 of a simply supported span
/// under moving forces by modal superposition, each mode's equation
/// q̈ + 2ζₙωₙq̇ + ωₙ²q = (2/mL) Σ F sin(nπx/L) integrated with RK4 at a
/// step far below the check's: the series of Frýba's moving-force
/// solution, independent of the check's finite elements and Newmark steps.
fn modal_peaks(
    (l, m, ei): (f64, f64, f64),
    zeta_of: &dyn Fn(f64) -> f64,
    axles: &[(f64, f64)],
    speed: f64,
) -> (f64, f64) {
    const MODES: usize = 15;
    let omega: [f64; MODES] =
        std::array::from_fn(|n| ((n + 1) as f64 * PI / l).powi(2) * (ei / m).sqrt());
    let zeta = omega.map(zeta_of);
    // Every mode's generalised force at once: one pass over the axles per
    // instant, not one per mode (the ICE 2 runs took 48 s that way).
    let forces = |t: f64| -> [f64; MODES] {
        let mut sum = [0.0; MODES];
        let on = axles.iter().map(|&(o, f)| (speed * t - o, f));
        for (x, f) in on.filter(|&(x, _)| (0.0..=l).contains(&x)) {
            for (n, s) in sum.iter_mut().enumerate() {
                *s += f * libm::sin((n + 1) as f64 * PI / l * x);
            }
        }
        sum.map(|s| s * 2.0 / (m * l))
    };
    let stations = [0.1, 0.3, 0.5, 0.7, 0.9];
    let shape =
        |x: f64| -> [f64; MODES] { std::array::from_fn(|n| libm::sin((n + 1) as f64 * PI * x)) };
    let (midspan, station_shapes) = (shape(0.5), stations.map(shape));
    let at = |shape: &[f64; MODES], values: &[f64; MODES]| -> f64 {
        shape.iter().zip(values).map(|(s, q)| s * q).sum()
    };
    let dt = 2e-5;
    let end = (axles.last().unwrap().0 + l) / speed;
    let (mut q, mut v) = ([0.0_f64; MODES], [0.0_f64; MODES]);
    let (mut peak, mut peak_acceleration) = (0.0_f64, 0.0_f64);
    let mut t = 0.0;
    let mut force_now = forces(t);
    while t < end {
        let (force_half, force_next) = (forces(t + 0.5 * dt), forces(t + dt));
        let mut accelerations = [0.0; MODES];
        for n in 0..MODES {
            let (w, z) = (omega[n], zeta[n]);
            let rate = |q: f64, v: f64, f: f64| (v, f - 2.0 * z * w * v - w * w * q);
            let k1 = rate(q[n], v[n], force_now[n]);
            let k2 = rate(
                q[n] + 0.5 * dt * k1.0,
                v[n] + 0.5 * dt * k1.1,
                force_half[n],
            );
            let k3 = rate(
                q[n] + 0.5 * dt * k2.0,
                v[n] + 0.5 * dt * k2.1,
                force_half[n],
            );
            let k4 = rate(q[n] + dt * k3.0, v[n] + dt * k3.1, force_next[n]);
            q[n] += dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            v[n] += dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            accelerations[n] = rate(q[n], v[n], force_next[n]).1;
        }
        t += dt;
        force_now = force_next;
        peak = peak.max(at(&midspan, &q).abs());
        for shape in &station_shapes {
            peak_acceleration = peak_acceleration.max(at(shape, &accelerations).abs());
        }
    }
    (peak, peak_acceleration)
}

/// The real train ICE 2 (IAPF-07 Annex C) over the 20 m bridge: every
/// run's peak midspan deflection against the modal series with the same
/// damping (the check's ζ in every mode), within 1 %. No published bridge
/// with its real-train response and every input was found (see
/// docs/bridge-check.md), so the reference is this independent solution.
#[test]
fn ice2_runs_agree_with_the_modal_series() {
    let text = QUICK.replace("mass_lower = 10800.0\nmass_upper = 13200.0\n", "");
    let spec = BridgeSpec::from_toml_str(&text).unwrap();
    let result = run_check(&spec, 2).unwrap();
    let ice2 = guideway::moving_load::RealTrain::shipped()
        .into_iter()
        .find(|t| t.name == "ICE2")
        .unwrap();
    let (l, m) = (20.0, 12000.0);
    let ei = m * (2.0 * l * l * 5.5 / PI).powi(2);
    let zeta = result.damping_percent / 100.0;
    let zeta_of = |_: f64| zeta;
    let runs: Vec<_> = result.runs.iter().filter(|r| r.train == "ICE2").collect();
    assert!(!runs.is_empty());
    let mut worst: f64 = 0.0;
    for run in runs {
        let reference =
            modal_midspan_peak((l, m, ei), &zeta_of, &ice2.forces(), run.speed_kmh / 3.6);
        let got = run.deflections[2];
        worst = worst.max((got / reference - 1.0).abs());
        assert!(
            (got - reference).abs() <= 0.01 * reference,
            "{} km/h: {got} m against {reference} m",
            run.speed_kmh
        );
    }
    eprintln!("ICE 2: largest relative departure from the series {worst:.2e}");
}

/// The check's worst case on the 20 m bridge, HSLM-A4 at its first
/// resonance f1 D = 5.5 × 21 × 3.6 = 415.8 km/h, and HSLM-A1 at 5.5 × 18
/// × 3.6 = 356.4 km/h: each run's raw peak deck acceleration over the
/// stations against the modal series written in this file (15 modes, RK4
/// at 20 µs, the check's ζ in every mode), within 5 % (the acceptance of
/// issue 28 for a published example; no published bridge with its peak
/// and every input was found, see docs/bridge-check.md, so the reference
/// is this independent solution). `-- --nocapture` prints the departures.
#[test]
fn hslm_resonance_accelerations_agree_with_the_modal_series() {
    let text = QUICK
        .replace("mass_lower = 10800.0\nmass_upper = 13200.0\n", "")
        .replace("line_speed = 300.0", "line_speed = 350.0")
        .replace("speed_step = 20.0", "speed_step = 100.0")
        .replace(
            "fine_speed_step = 10.0",
            "fine_speed_step = 1.0\nresonance_band = 0.004\nreal_trains = false",
        );
    let spec = BridgeSpec::from_toml_str(&text).unwrap();
    let result = run_check(&spec, 2).unwrap();
    let (l, m) = (20.0, 12000.0);
    let ei = m * (2.0 * l * l * 5.5 / PI).powi(2);
    let zeta = result.damping_percent / 100.0;
    let mut checked = 0;
    for (name, resonance) in [("HSLM-A4", 415.8), ("HSLM-A1", 356.4)] {
        let train = guideway::moving_load::HSLM_TRAINS
            .iter()
            .find(|t| t.name == name)
            .unwrap();
        let near = result
            .runs
            .iter()
            .filter(|r| r.train == name && (r.speed_kmh - resonance).abs() <= 1.5);
        for run in near {
            let (_, reference) =
                modal_peaks((l, m, ei), &|_| zeta, &train.axles(), run.speed_kmh / 3.6);
            let departure = run.acceleration / reference - 1.0;
            eprintln!(
                "{name} at {} km/h: {:.3} m/s² against the series' {reference:.3} ({departure:+.2e})",
                run.speed_kmh, run.acceleration
            );
            assert!(departure.abs() <= 0.05, "{name} at {} km/h", run.speed_kmh);
            checked += 1;
        }
    }
    assert!(checked >= 4, "runs at the resonances: {checked}");
}

/// EN 1991-2 §6.4.6.3.1 gives one damping ratio for the structure: the
/// check's structure damps modes 1, 2 and 3 each at 2 ζ ωₙ with ζ = Table
/// 6.6's 1.5 % (reinforced concrete, L = 20 m) + eq. (6.13)'s Δζ =
/// 0.118 / 0.398 %, by hand; Rayleigh damping at modes 1 and 3 would give
/// mode 2 ζ (ω₁ω₃ + ω₂²) / (ω₂ (ω₁ + ω₃)) = 0.63 ζ (ωₙ ∝ n²).
#[test]
fn the_check_damps_every_mode_at_the_table_ratio() {
    let spec = BridgeSpec::from_toml_str(EXAMPLE).unwrap();
    let zeta = (1.5 + 0.118 / 0.398) / 100.0;
    let ei = 12000.0 * (4400.0 / PI).powi(2);
    let scene = guideway::check::scene_for(&spec, 12000.0, ei, zeta).unwrap();
    let structure = guideway::study::sweep::structure_of(&scene).unwrap();
    let basis = structure.modal().expect("a modal structure");
    assert_eq!(basis.modes(), structure.free_dofs(), "every mode kept");
    // ωₙ = (nπ/L)² √(EI/m) of the continuous span, f1 = 5.5 Hz
    for n in 1..=3 {
        let omega = (n as f64 * PI / 20.0).powi(2) * (ei / 12000.0).sqrt();
        let found = basis.omega()[n - 1];
        assert!(
            (found / omega - 1.0).abs() < 1e-3,
            "ω{n}: {found} vs {omega}"
        );
        let ratio = basis.mode_damping()[n - 1] / (2.0 * found);
        assert!(
            (ratio - zeta).abs() < 1e-12,
            "mode {n}: ζ = {ratio}, table {zeta}"
        );
    }
}

/// Natural values λL (L = 1) of a beam of `spans` equal spans over pinned
/// supports in (from, to): where the determinant of its span-by-span
/// conditions changes sign. Each span's w = A sin λξ + B cos λξ + C sinh
/// λξ + D cosh λξ; w = 0 at both ends of every span, w'' = 0 at the two
/// outer ends, w' and w'' continuous over each intermediate support.
fn multi_span_eigenvalues(spans: usize, (from, to): (f64, f64)) -> Vec<f64> {
    let det = |lam: f64| {
        let n = 4 * spans;
        let mut a = nalgebra::DMatrix::<f64>::zeros(n, n);
        let (s, c, sh, ch) = (libm::sin(lam), libm::cos(lam), lam.sinh(), lam.cosh());
        let value_end = [s, c, sh, ch];
        let slope_start = [1.0, 0.0, 1.0, 0.0];
        let slope_end = [c, -s, ch, sh];
        let curvature_start = [0.0, -1.0, 0.0, 1.0];
        let curvature_end = [-s, -c, sh, ch];
        let mut row = 0;
        let mut put = |row: usize, span: usize, coefficients: [f64; 4], sign: f64| {
            for (k, v) in coefficients.iter().enumerate() {
                a[(row, 4 * span + k)] += sign * v;
            }
        };
        for i in 0..spans {
            put(row, i, [0.0, 1.0, 0.0, 1.0], 1.0); // w(0) = 0
            put(row + 1, i, value_end, 1.0); // w(L) = 0
            row += 2;
            if i + 1 < spans {
                put(row, i, slope_end, 1.0);
                put(row, i + 1, slope_start, -1.0);
                put(row + 1, i, curvature_end, 1.0);
                put(row + 1, i + 1, curvature_start, -1.0);
                row += 2;
            }
        }
        put(row, 0, curvature_start, 1.0);
        put(row + 1, spans - 1, curvature_end, 1.0);
        a.determinant()
    };
    let steps = 20_000;
    let h = (to - from) / steps as f64;
    let mut roots = Vec::new();
    for k in 0..steps {
        let (mut lo, mut hi) = (from + k as f64 * h, from + (k + 1) as f64 * h);
        if det(lo).signum() == det(hi).signum() {
            continue;
        }
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if det(lo).signum() == det(mid).signum() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        roots.push(0.5 * (lo + hi));
    }
    roots
}

/// A continuous beam's f1 and f3 from the check (its mesh) against the
/// span-by-span frequency equation above: two equal spans have the single
/// span's f1 (closed form, λL = π) and f3 at the root above 2π; three
/// equal spans f1 (λL = π again) and f3 at the third root.
#[test]
fn continuous_spans_have_the_frequencies_of_the_span_equations() {
    let (l, m, ei): (f64, f64, f64) = (20.0, 12000.0, 2.353893e10);
    let single = PI / (2.0 * l * l) * (ei / m).sqrt();
    for count in [2, 3] {
        let spans = vec![format!("{l:?}"); count].join(", ");
        let text = format!(
            "name = \"c\"\nsupports = \"continuous\"\nspans = [{spans}]\n\
             mass_per_length = {m:?}\nbending_stiffness = {ei:?}\n\
             bridge_type = \"reinforced_concrete\"\ntrack = \"ballasted\"\nline_speed = 300.0\n"
        );
        let spec = BridgeSpec::from_toml_str(&text).unwrap();
        let case = &guideway::check::mass_cases(&spec, ei).unwrap()[0];
        let roots = multi_span_eigenvalues(count, (3.0, 7.0));
        eprintln!(
            "{count} spans: λL = {roots:?}; f1 = {} Hz, f3 = {} Hz",
            case.f1, case.f3
        );
        assert!((roots[0] - PI).abs() < 1e-9, "λ1 L = π: {roots:?}");
        let third = roots[2];
        if count == 2 {
            // the third mode of two equal spans: one full sine per span
            assert!((third - 2.0 * PI).abs() < 1e-9, "{roots:?}");
        }
        let f3 = single * (third / PI).powi(2);
        assert!(
            (case.f1 / single - 1.0).abs() < 1e-6,
            "{count}: f1 {} vs {single}",
            case.f1
        );
        assert!(
            (case.f3 / f3 - 1.0).abs() < 1e-4,
            "{count}: f3 {} vs {f3}",
            case.f3
        );
    }
}

/// Two continuous spans end to end: the stations of both spans and the
/// middle support, LΦ = 1.2 × 20 m (Table 6.2 case 5.1), the hogging row;
/// bad continuous descriptions refused naming the field.
#[test]
fn two_continuous_spans_are_checked_with_their_hogging() {
    let text = QUICK
        .replace(
            "span = 20.0",
            "supports = \"continuous\"\nspans = [20.0, 20.0]",
        )
        .replace("mass_lower = 10800.0\nmass_upper = 13200.0\n", "")
        .replace("[settings]", "[settings]\nreal_trains = false");
    let spec = BridgeSpec::from_toml_str(&text).unwrap();
    let r = run_check(&spec, 2).unwrap();
    assert_eq!(r.stations.len(), 11);
    assert_eq!(r.stations[5].name, "support1");
    assert!((r.stations[5].position - 20.0).abs() < 1e-12);
    assert_eq!(r.stations[r.main_station].name, "s1x50");
    assert!((r.determinant_length - 24.0).abs() < 1e-12);
    // f1 of two equal spans is the single span's: 5.5 Hz as given
    assert!((r.mass_cases[0].f1 - 5.5).abs() < 1e-9);
    let hogging = r
        .verdicts
        .iter()
        .find(|v| v.check.starts_with("hogging moment"))
        .expect("a hogging row");
    assert!(hogging.value.contains("support1"), "{}", hogging.value);
    assert!(r.runs.iter().all(|run| run.deflections[5] < 1e-9));
    assert!(r.runs.iter().any(|run| run.moments[5] > 1e5));
    let cases = [
        (
            "spans = [20.0, 20.0]",
            "spans = [20.0]",
            "spans (count) = 1",
        ),
        (
            "spans = [20.0, 20.0]",
            "spans = [20.0, 0.5]",
            "spans[1] = 0.5",
        ),
        (
            "spans = [20.0, 20.0]",
            "span = 20.0\nspans = [20.0, 20.0]",
            "span = 20",
        ),
    ];
    for (from, to, needle) in cases {
        let error = BridgeSpec::from_toml_str(&text.replace(from, to)).unwrap_err();
        assert!(error.contains(needle), "{to}: {error}");
    }
}

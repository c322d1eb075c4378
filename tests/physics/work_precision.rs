//! The work-precision study's reference and error measures behave as a
//! converging second-order method should.

use guideway::study::work_precision::{cases, measure, reference};

#[test]
fn reference_is_converged_and_rk4_errors_shrink_with_the_step() {
    let case = cases(true).into_iter().next().expect("the 10 m/s case");
    let reference = reference(&case).expect("reference runs");
    // The two fine runs behind the reference agree far below every error
    // the sweep measures (the smallest is about 1e-4 m/s).
    assert!(
        reference.exit_speed_spread < 1e-5,
        "{}",
        reference.exit_speed_spread
    );
    assert!(
        reference.deflection_spread < 1e-6,
        "{}",
        reference.deflection_spread
    );
    let points = measure(&case, &reference, 1, |_| {});
    let mut rk4: Vec<_> = points
        .iter()
        .filter(|p| p.scheme == "rk4" && p.velocity_tolerance == 1e-7)
        .collect();
    rk4.sort_by(|a, b| b.step.total_cmp(&a.step));
    assert!(rk4.len() >= 3);
    for pair in rk4.windows(2) {
        // Halving the step at least halves the deflection error.
        assert!(
            pair[1].rms_deflection_error < 0.5 * pair[0].rms_deflection_error,
            "{:?}",
            rk4.iter()
                .map(|p| p.rms_deflection_error)
                .collect::<Vec<_>>()
        );
    }
    // The quadratic force profile: fourth order once the step resolves the
    // force (from 1.25 ms on the paper's mesh).
    let quadratic = |step: f64| {
        points
            .iter()
            .find(|p| p.scheme == "rk4-quadratic" && p.step == step && p.velocity_tolerance == 1e-7)
            .expect("measured")
    };
    let (coarse, fine) = (quadratic(1.25e-3), quadratic(6.25e-4));
    assert!(coarse.max_energy_drift > 12.0 * fine.max_energy_drift);
    assert!(coarse.rms_deflection_error > 12.0 * fine.rms_deflection_error);
    let paper = points
        .iter()
        .find(|p| p.paper_setting)
        .expect("paper's setting measured");
    // At the paper's setting the exit speed is within the acceptance ±0.01 m/s
    // of the converged solution.
    assert!(paper.exit_speed_error < 0.01, "{}", paper.exit_speed_error);
}

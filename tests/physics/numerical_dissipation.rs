//! HHT-α's numerical dissipation, a term of the energy balance computed
//! step by step from the scheme's discrete energy identity.

use guideway::scene::{BodyKind, DampingSpec, IntegratorKind, Scene};
use guideway::Simulation;

/// The paper's beam on 16 elements vibrating freely under HHT-α with
/// `damping` = −α at the paper's step: a glider waits unloaded on rigid
/// ground before the beam, and the beam starts with a velocity field that
/// puts energy in every mode, the highest included.
fn free_vibration(damping: f64, structural: Option<DampingSpec>, rough: bool) -> Simulation {
    let mut scene = Scene::lee1994(BodyKind::Glider, 1.0, 0.0025);
    scene.beam.elements = 16;
    scene.beam.damping = structural;
    scene.vehicles[0].force_y = 0.0;
    scene.vehicles[0].initial_position = -50.0;
    scene.track.approach = 60.0;
    scene.solver.integrator = IntegratorKind::Hht;
    scene.solver.numerical_damping = damping;
    scene.solver.end_time = Some(1.0);
    scene.validate().expect("valid");
    let mut sim = Simulation::new(&scene).expect("builds");
    let mut state = sim.state();
    let d = &mut state.dynamic;
    if rough {
        for (i, v) in d.beam_velocity.iter_mut().enumerate() {
            *v = libm::sin(i as f64 * 1.7) + 0.5 * libm::cos(i as f64 * 0.3);
        }
    } else {
        // The shape of the static deflection under a uniform load: the
        // first mode mostly, resolved at this step.
        let beam = &sim.system().beam;
        let load = nalgebra::DVector::from_element(d.beam_velocity.len(), 1e4);
        let shape = beam.static_deflection(&load).expect("deflects");
        let scale = 0.5 / shape.amax();
        d.beam_velocity.copy_from(&(shape * scale));
    }
    // At rest otherwise, the consistent start acceleration is −M⁻¹ C v.
    let n = d.beam_velocity.len();
    let (u, v) = (d.beam_displacement.clone(), d.beam_velocity.clone());
    let loads = d.beam_load.clone();
    sim.system()
        .beam
        .accelerations((&u, &v), &loads, &mut d.beam_acceleration);
    assert_eq!(d.beam_acceleration.len(), n);
    sim.restore(&state).expect("restores");
    sim
}

/// (beam energy at the start, the balance's largest departure from its
/// start, the numerical dissipation at the end) over 0.5 s.
fn run(sim: &mut Simulation) -> (f64, f64, f64, Vec<f64>) {
    let start = sim.energy_balance();
    let energy = |sim: &Simulation| {
        let d = &sim.state().dynamic;
        let beam = &sim.system().beam;
        beam.kinetic_energy(&d.beam_velocity) + beam.strain_energy(&d.beam_displacement)
    };
    let initial = energy(sim);
    let mut worst = 0.0f64;
    let mut dissipation = Vec::new();
    for k in 1..=200 {
        sim.advance_to(k as f64 * 0.0025).expect("runs");
        worst = worst.max((sim.energy_balance() - start).abs());
        dissipation.push(sim.state().dynamic.numerical_dissipation);
    }
    let last = *dissipation.last().unwrap();
    eprintln!("initial {initial} J, balance moved {worst} J, numerical {last} J");
    (initial, worst, last, dissipation)
}

#[test]
fn newmark_average_acceleration_dissipates_nothing() {
    // α = 0 is the trapezoidal rule, which conserves the energy of a
    // linear free vibration exactly: zero to round-off (measured 1.4e-12 of
    // the energy after 200 steps, on 2026-11-22).
    let mut sim = free_vibration(0.0, None, true);
    let (initial, worst, _, dissipation) = run(&mut sim);
    assert!(initial > 1.0);
    for d in dissipation {
        assert!(d.abs() <= 1e-11 * initial, "{d} J");
    }
    assert!(worst <= 1e-11 * initial, "{worst} J of {initial} J");
}

#[test]
fn hht_alpha_dissipation_closes_the_balance_and_grows_with_the_damping() {
    let mut removed = Vec::new();
    for damping in [0.05, 0.1, 0.3] {
        let mut sim = free_vibration(damping, None, true);
        let (initial, worst, last, dissipation) = run(&mut sim);
        // It removes the unresolved modes' energy, a good share of the
        // whole here, and the balance holds with it as a term.
        assert!(last > 0.05 * initial, "{damping}: {last} of {initial}");
        assert!(
            worst <= 1e-10 * initial,
            "{damping}: {worst} J of {initial} J"
        );
        // Never a gain: HHT-α's algorithmic energy only decreases.
        let first = dissipation[0];
        assert!(first >= 0.0, "{first}");
        removed.push(last);
    }
    assert!(
        removed[0] < removed[1] && removed[1] < removed[2],
        "{removed:?}"
    );
}

#[test]
fn with_structural_damping_the_balance_still_closes() {
    let rayleigh = DampingSpec::Modes {
        ratio: 0.05,
        modes: [1, 2],
    };
    // A resolved vibration: the structural damping takes most of the
    // energy, the numerical a little; the sum closes.
    let mut sim = free_vibration(0.1, Some(rayleigh.clone()), false);
    let (initial, worst, last, _) = run(&mut sim);
    let beam_damping = sim.state().dynamic.beam_dissipated;
    eprintln!("resolved: beam damping {beam_damping} J, numerical {last} J");
    assert!(beam_damping > 0.5 * initial, "{beam_damping} of {initial}");
    assert!(last >= 0.0 && last < beam_damping, "{last}");
    assert!(worst <= 1e-10 * initial, "{worst} J of {initial} J");
    // With energy in the mesh's highest modes, over-damped within a step
    // (ζ ω Δt ≫ 1), the damping power at the step's mean velocity
    // over-books and the numerical term, negative, corrects it: only the
    // sum means something there, and it still closes.
    let mut sim = free_vibration(0.1, Some(rayleigh), true);
    let (initial, worst, last, _) = run(&mut sim);
    let beam_damping = sim.state().dynamic.beam_dissipated;
    eprintln!("rough: beam damping {beam_damping} J, numerical {last} J");
    assert!(
        worst <= 1e-10 * (initial + beam_damping),
        "{worst} J of {initial} J"
    );
}

/// The paper's beam on 8 elements under RK4 at ω Δt = `omega_dt` of mode
/// `mode` (1-based; 0 the highest), moving in that mode alone, a glider
/// standing unloaded on rigid ground before it: (the simulation, ω Δt).
fn rk4_in_one_mode(mode: usize, omega_dt: f64) -> (Simulation, f64) {
    let mut beam_only = Scene::lee1994(BodyKind::Glider, 0.0, 1e-5);
    beam_only.beam.elements = 8;
    let built = Simulation::new(&beam_only).expect("builds");
    let beam = &built.system().beam;
    let modes = beam.modes(beam.free_dofs()).expect("modes");
    let highest = modes.omega.len() - 1;
    let k = if mode == 0 { highest } else { mode - 1 };
    // Every step is set by the highest mode's ω Δt (RK4's limit 2√2).
    let step = omega_dt / modes.omega[highest];
    let mut scene = Scene::lee1994(BodyKind::Glider, 0.0, step);
    scene.beam.elements = 8;
    scene.vehicles[0].force_y = 0.0;
    scene.vehicles[0].initial_position = -50.0;
    scene.track.approach = 60.0;
    scene.solver.integrator = IntegratorKind::Rk4;
    scene.validate().expect("valid");
    let mut sim = Simulation::new(&scene).expect("builds");
    let mut state = sim.state();
    let shape = modes.shapes.column(k).into_owned();
    // ½ vᵀ M v = 5000 J (the shapes are mass-normalized).
    state.dynamic.beam_velocity.copy_from(&(shape * 100.0));
    sim.restore(&state).expect("restores");
    (sim, modes.omega[k] * step)
}

#[test]
fn rk4_dissipation_is_its_amplification_factor_on_each_mode() {
    // RK4 multiplies a free mode's energy by |R(iωΔt)|² = 1 − (ωΔt)⁶/72 +
    // (ωΔt)⁸/576 per step, exactly (the mode's two states rotate and
    // shrink as one complex number): a quarter at ωΔt = √6, nearly one
    // for the resolved modes. That loss is `energy.numerical_dissipation`
    // under RK4, and the balance with it holds to round-off; the impacts
    // that excite a mesh's highest modes made it most of the stress
    // case's drift before it was booked (tests/vehicles/impacts.rs).
    for (mode, omega_dt) in [(0, 6f64.sqrt()), (0, 2.0), (1, 2.4)] {
        let (mut sim, y) = rk4_in_one_mode(mode, omega_dt);
        // The glider stands still: all the energy is the beam's.
        let start = sim.energy_balance();
        assert!((start - 5000.0).abs() < 1e-9 * 5000.0, "{start}");
        let steps = 6;
        for k in 1..=steps {
            sim.advance_to(k as f64 * sim.step_size()).expect("runs");
        }
        let factor = 1.0 - y.powi(6) / 72.0 + y.powi(8) / 576.0;
        let expected = start * (1.0 - factor.powi(steps));
        let booked = sim.state().dynamic.numerical_dissipation;
        assert!(
            (booked - expected).abs() <= 1e-9 * start,
            "mode {mode}, ωΔt = {y}: booked {booked} J, |R|^2n says {expected} J of {start} J"
        );
        assert!(
            (sim.energy_balance() - start).abs() <= 1e-12 * start,
            "mode {mode}"
        );
        if mode == 0 {
            // Most of the highest mode's energy is gone.
            assert!(booked > 0.5 * start, "{booked} J of {start} J");
        }
    }
}

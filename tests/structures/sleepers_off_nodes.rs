//! Sleepers where the track has them, not where the deck's nodes are
//! (issue 24): the rail meshed at the sleepers
//! (`track.on_deck.sleepers.rail_elements_per_bay`), the deck on its own
//! mesh, each sleeper's ballast on the deck through the deck element's
//! shape functions. Checked against the infinite rail on discrete
//! supports (its Fourier series, written here) over a stiff deck, and the
//! deck against a simply supported beam under the sleepers' point loads
//! (closed form, written here) with the bearings carrying the load.

use guideway::beam::Rayleigh;
use guideway::structure::rail_on_deck::RailOnDeck;
use guideway::structure::track_on_deck::{TrackAssembly, TrackOnDeck};
use guideway::structure::track_sleepers::{SleeperPreset, Sleepers};
use std::f64::consts::PI;

/// Two UIC 60 rails (the line a wheelset loads).
const RAIL_EI: f64 = 1.28e7;
const RAIL_MU: f64 = 120.0;
const LOAD: f64 = 120e3;
const SPAN: f64 = 20.0;

/// The ballasted preset doubled for both rail seats of a sleeper, at 0.6
/// m, the rail in `per_bay` elements a bay.
fn sleepers(per_bay: usize) -> Sleepers {
    let seat = SleeperPreset::Ballasted.values();
    Sleepers {
        spacing: 0.6,
        pad_stiffness: 2.0 * seat.pad_stiffness,
        ballast_stiffness: 2.0 * seat.ballast_stiffness,
        sleeper_mass: 2.0 * seat.sleeper_mass,
        rail_elements_per_bay: Some(per_bay),
        ..seat
    }
}

/// The rail on `sleepers` over a simply supported 20 m deck of EI
/// `deck_ei` in elements of `deck_h`, with `side` m of approach and
/// run-off on the ground.
fn track(sleepers: Sleepers, deck_ei: f64, deck_h: f64, side: f64) -> TrackOnDeck {
    TrackOnDeck {
        layout: RailOnDeck {
            deck_length: SPAN,
            deck_bending_stiffness: deck_ei,
            rail_bending_stiffness: RAIL_EI,
            track_stiffness: 0.0,
            ground_stiffness: 0.0,
            approach: side,
            run_off: side,
            element_length: deck_h,
            sleepers: Some(sleepers),
        },
        rail_mass_per_length: RAIL_MU,
        deck_mass_per_length: 12_000.0,
        track_damping: 0.0,
        ground_damping: 0.0,
        deck_damping: Rayleigh::default(),
    }
}

/// Deflection under a downward `load` at a support of the infinite rail
/// (EI) on springs `k` (N/m) at spacing `a`, by its Fourier series: with
/// F(θ) = (a³/EI)(2 + cos θ) / (48 sin⁴(θ/2)) the rail's flexibility
/// between supports j a apart summed over j, w₀ = −(P/2π) ∫ F / (1 + k F)
/// dθ over [−π, π] (trapezoid rule, geometric on a smooth periodic
/// integrand).
fn discrete_support_deflection(load: f64, ei: f64, k: f64, a: f64) -> f64 {
    let n = 20_000;
    let sum: f64 = (0..n)
        .map(|i| {
            let theta = -PI + 2.0 * PI * i as f64 / n as f64;
            let inverse_f =
                ei / a.powi(3) * 48.0 * libm::sin(theta / 2.0).powi(4) / (2.0 + libm::cos(theta));
            1.0 / (inverse_f + k)
        })
        .sum();
    -load * sum / n as f64
}

/// The static state under a downward `load` on the rail at `x`.
fn static_state(assembly: &TrackAssembly, x: f64, load: f64) -> Vec<f64> {
    let mut force = vec![0.0; assembly.free_dofs()];
    assembly
        .add_rail_force(x, -load, &mut force)
        .expect("on the rail");
    assembly.static_deflection(&force).expect("solves")
}

/// Downward deflection at `x` of a simply supported beam (L, EI) under
/// downward point loads `(a, P)`: P b x (L² − b² − x²) / 6 L EI left of
/// a load, b = L − a, and its mirror right of it (Roark, simply
/// supported beam under a concentrated load).
fn simply_supported(loads: &[(f64, f64)], (length, ei): (f64, f64), x: f64) -> f64 {
    loads
        .iter()
        .map(|&(a, p)| {
            // Right of the load, the mirror: a ↔ b and x ↔ L − x.
            let (b, x) = if x <= a {
                (length - a, x)
            } else {
                (a, length - x)
            };
            p * b * x * (length * length - b * b - x * x) / (6.0 * length * ei)
        })
        .sum()
}

/// A sleeper at 10.2 m over a 20 m deck in 1 m elements (the sleepers at
/// 0.6 m from the approach's start lie off the deck's nodes but for one
/// in five): under a load at that sleeper the rail over a very stiff
/// deck deflects as the infinite rail on discrete supports, whatever the
/// rail's elements a bay (the Hermite rail is exact between point
/// supports), and the pad carries k_eq w.
#[test]
fn over_a_stiff_deck_in_1_m_elements_the_rail_on_0_6_m_sleepers_is_the_discrete_series() {
    for per_bay in [1, 2, 3] {
        let s = sleepers(per_bay);
        let assembly = track(s, 1e16, 1.0, 12.0).assemble().expect("assembles");
        let x = 10.2;
        let u = static_state(&assembly, x, LOAD);
        let rail = assembly.rail_deflection(x, &u).expect("on the rail")
            - assembly.deck_deflection(x, &u).expect("on the deck");
        let zero = vec![0.0; u.len()];
        let seat = assembly.rail_seat_force(x, &u, &zero).expect("sleepers");
        let k = s.series_stiffness();
        let expected = discrete_support_deflection(LOAD, RAIL_EI, k, s.spacing);
        let error = (rail / expected - 1.0).abs();
        let seat_error = (seat / (-k * expected) - 1.0).abs();
        println!(
            "{per_bay} a bay: rail over the deck {rail:.9e} m against {expected:.9e} m \
             ({error:.1e}); pad {seat:.6e} N ({seat_error:.1e}); half-bandwidth {}",
            assembly.half_bandwidth()
        );
        assert!(error < 1e-8, "{per_bay} a bay: {rail:e} vs {expected:e}");
        assert!(seat_error < 1e-8, "{per_bay} a bay: pad {seat:e}");
    }
}

/// The sleepers' forces reach the deck through its shape functions: the
/// bearings and the ground carry the load, and the deck's nodes deflect
/// as a simply supported beam under the pads' forces at the sleepers'
/// abscissae (statics: each sleeper passes its pad's force to the deck),
/// for a deck in 1 m elements and one in 4 m elements, coarser than the
/// spacing (the Hermite beam's nodes are exact under consistent point
/// loads anywhere in an element).
#[test]
fn a_sleeper_off_the_decks_nodes_loads_the_deck_as_a_point_force_there() {
    let deck_ei = 2.3539e10;
    for (deck_h, at) in [(1.0, 10.2), (1.0, 7.5), (4.0, 13.35)] {
        let spec = track(sleepers(2), deck_ei, deck_h, 6.0);
        let solution = spec.layout.static_solution(at, LOAD).expect("solves");
        let bearings: f64 = solution.reactions.iter().map(|r| r.1).sum();
        let balance = (bearings + solution.ground_force) / LOAD - 1.0;
        let assembly = spec.assemble().expect("assembles");
        let u = static_state(&assembly, at, LOAD);
        let zero = vec![0.0; u.len()];
        let loads: Vec<(f64, f64)> = (assembly.sleeper_x().into_iter())
            .filter(|x| *x > 1e-9 && *x < SPAN - 1e-9)
            .map(|x| {
                (
                    x,
                    assembly.rail_seat_force(x, &u, &zero).expect("a sleeper"),
                )
            })
            .collect();
        let nodes = (SPAN / deck_h).round() as usize;
        let (mut worst, mut peak) = (0.0f64, 0.0f64);
        for i in 1..nodes {
            let x = i as f64 * deck_h;
            let found = -assembly.deck_deflection(x, &u).expect("on the deck");
            let expected = simply_supported(&loads, (SPAN, deck_ei), x);
            worst = worst.max((found - expected).abs());
            peak = peak.max(expected.abs());
        }
        println!(
            "deck in {deck_h} m elements, load at {at} m: bearings {bearings:.6e} N + ground \
             {:.6e} N ({balance:.1e}); {} sleepers on the span; deck nodes within {:.1e} of the \
             simply supported beam's peak {peak:.4e} m",
            solution.ground_force,
            loads.len(),
            worst / peak
        );
        assert_eq!(solution.reactions.len(), 2, "{:?}", solution.reactions);
        assert!(balance.abs() < 1e-9, "{balance:e}");
        assert!(worst < 1e-10 * peak, "{worst:e} against {peak:e}");
    }
}

/// A scene: a 10 t glider at rest at `at` on a stiff 20 m deck in
/// `elements`, on the doubled ballasted sleepers given by `sleepers`.
fn scene(elements: usize, sleepers: &str, at: f64) -> String {
    format!(
        r#"
name = "sleepers-off-the-decks-nodes"
gravity = 9.81
[beam]
length = 20.0
mass_per_length = 12000.0
bending_stiffness = 1e14
surface_offset = 0.0
elements = {elements}
[beam.damping]
ratio = 0.02
modes = [1, 3]
[track]
approach = 10.0
run_off = 10.0
[track.on_deck]
rail_bending_stiffness = {RAIL_EI:?}
rail_mass_per_length = {RAIL_MU:?}
[track.on_deck.sleepers]
preset = "ballasted"
pad_stiffness = 4.5e8
sleeper_mass = 340.0
ballast_stiffness = 4.0e7
{sleepers}
[body]
name = "glider"
kind = "glider"
mass = 10000.0
initial_position = {at:?}
initial_speed = 0.0
[[sensors]]
name = "under"
position = {at:?}
[solver]
step = 0.001
integrator = "hht"
start = "static"
end_time = 0.01
"#
    )
}

/// The outputs `names` after the first step of `text`.
fn first_step(text: &str, names: &[&str]) -> Vec<f64> {
    let scene = guideway::Scene::from_toml_str(text).expect("a valid scene");
    let mut sim = guideway::Simulation::new(&scene).expect("builds");
    let all: Vec<String> = sim.outputs().iter().map(|o| o.name.clone()).collect();
    let mut values = vec![0.0; all.len()];
    sim.advance_to(scene.solver.step).expect("steps");
    sim.output_values(&mut values);
    names
        .iter()
        .map(|n| values[all.iter().position(|x| x == n).expect(n)])
        .collect()
}

const READ: [&str; 3] = [
    "sensor.under.rail_deflection",
    "sensor.under.rail_seat_force",
    "sensor.under.deflection",
];

/// In a scene, sleepers at 0.6 m over a deck in 0.5 m elements (which the
/// rail at the deck's nodes refuses): under a glider at rest on the
/// sleeper at 10.4 m the rail over the deck and the pad's force are the
/// discrete-support series'.
#[test]
fn in_a_scene_a_glider_on_0_6_m_sleepers_over_0_5_m_deck_elements_meets_the_series() {
    let text = scene(40, "spacing = 0.6\nrail_elements_per_bay = 2", 10.4);
    let found = first_step(&text, &READ);
    let s = sleepers(2);
    let k = s.series_stiffness();
    let weight = 10_000.0 * 9.81;
    let expected = discrete_support_deflection(weight, RAIL_EI, k, 0.6);
    let rail = found[0] - found[2];
    println!(
        "rail over the deck {rail:.6e} m against {expected:.6e} m; pad {:.6e} N against {:.6e} N",
        found[1],
        -k * expected
    );
    assert!((rail / expected - 1.0).abs() < 1e-6, "{found:?}");
    assert!((found[1] / (-k * expected) - 1.0).abs() < 1e-6, "{found:?}");
}

/// Sleepers at the deck's nodes, the rail meshed at the sleepers (one
/// element a bay) or at the deck's nodes: the same rail, the same answer
/// (the nodes' abscissae differ only in rounding).
#[test]
fn sleepers_on_the_decks_nodes_give_the_same_answer_meshed_either_way() {
    let at_deck = first_step(&scene(40, "spacing = 0.5", 10.0), &READ);
    let at_sleepers = first_step(
        &scene(40, "spacing = 0.5\nrail_elements_per_bay = 1", 10.0),
        &READ,
    );
    println!("at the deck's nodes {at_deck:?}; at the sleepers {at_sleepers:?}");
    for (a, b) in at_deck.iter().zip(&at_sleepers) {
        assert!((a - b).abs() <= 1e-9 * a.abs(), "{a:e} vs {b:e}");
    }
}

#[test]
fn the_rail_elements_a_bay_are_refused_naming_field_and_value() {
    for (sleepers, path, words) in [
        (
            "spacing = 0.6\nrail_elements_per_bay = 0",
            "track.on_deck.sleepers.rail_elements_per_bay",
            ">= 1",
        ),
        (
            "spacing = 0.6",
            "track.on_deck.sleepers.spacing",
            "rail_elements_per_bay",
        ),
        (
            "spacing = 0.0001\nrail_elements_per_bay = 100",
            "track.on_deck.sleepers.rail_elements_per_bay",
            "more than",
        ),
    ] {
        let text = scene(40, sleepers, 10.4);
        let error = guideway::Scene::from_toml_str(&text)
            .expect_err(sleepers)
            .to_string();
        println!("{error}");
        assert!(
            error.contains(path) && error.contains(words),
            "{sleepers}: {error}"
        );
    }
}

/// The rail seat's two masses: m_r (the rail's mass per sleeper) on the
/// pad k_p over m_s on the ballast k_b; ω² solves m_r m_s ω⁴ − (m_r (k_p +
/// k_b) + m_s k_p) ω² + k_p k_b = 0, and the mode's sleeper amplitude per
/// rail amplitude is k_p / (k_p + k_b − m_s ω²).
fn two_mass(m_r: f64, s: &Sleepers) -> [(f64, f64); 2] {
    let (kp, kb, ms) = (s.pad_stiffness, s.ballast_stiffness, s.sleeper_mass);
    let (a, b, c) = (m_r * ms, m_r * (kp + kb) + ms * kp, kp * kb);
    let root = (b * b - 4.0 * a * c).sqrt();
    [(b - root) / (2.0 * a), (b + root) / (2.0 * a)].map(|w2| (w2.sqrt(), kp / (kp + kb - ms * w2)))
}

/// A rigid rail (EI 1e15 N m²: β L = 0.33 over its 30 m) on 51 undamped
/// sleepers at 0.6 m, 33 of them on a rigid deck (EI 1e20 N m², 1e6
/// kg/m: its first mode at 39 kHz) in 1 m elements, off its nodes but for
/// one in five, the others on the ground; the sleepers symmetric about
/// the rail's middle, so the rail's translation is a mode. Started in
/// each closed-form mode, it oscillates at that frequency (HHT α = 0,
/// T/400 a step: period error (ωΔt)²/12 = 2e-5) and keeps its amplitude:
/// the sleepers' masses and springs on the deck are the seat's.
#[test]
fn sleepers_on_a_deck_off_its_nodes_vibrate_at_the_rail_seats_two_mass_frequencies() {
    let s = Sleepers {
        pad_damping: 0.0,
        ballast_damping: 0.0,
        ..sleepers(2)
    };
    let mut spec = track(s, 1e20, 1.0, 5.0);
    spec.layout.rail_bending_stiffness = 1e15;
    spec.deck_mass_per_length = 1e6;
    let assembly = spec.assemble().expect("assembles");
    let on_deck = (assembly.sleeper_x().iter())
        .filter(|x| **x > 0.0 && **x < SPAN)
        .count();
    let count = assembly.sleeper_dofs().len();
    assert_eq!((count, on_deck), (51, 33));
    let rail_mass = RAIL_MU * 30.0;
    for (omega, ratio) in two_mass(rail_mass / count as f64, &s) {
        let amplitude = 1e-3;
        let mut u = assembly.nodal_field(&|_| [amplitude, 0.0], &|_| [0.0, 0.0]);
        for dof in assembly.sleeper_dofs() {
            u[dof] = ratio * amplitude;
        }
        let n = u.len();
        let mut a = vec![0.0; n];
        assembly.stiffness.mul_to(&u, &mut a);
        a.iter_mut().for_each(|x| *x = -*x);
        assembly
            .mass
            .ldlt()
            .expect("definite")
            .solve_in_place(&mut a);
        let mut state = guideway::structure::track_on_deck::TrackState {
            u,
            v: vec![0.0; n],
            a,
        };
        let period = 2.0 * PI / omega;
        let dt = period / 400.0;
        let hht = assembly.hht(dt, 0.0).expect("stepper");
        let zero = vec![0.0; n];
        let mut rail = Vec::new();
        for _ in 0..2000 {
            hht.advance(&assembly, &mut state, (&zero, &zero));
            rail.push(
                assembly
                    .rail_deflection(10.3, &state.u)
                    .expect("on the rail"),
            );
        }
        let crossings: Vec<f64> = (1..rail.len())
            .filter(|&i| rail[i - 1] < 0.0 && rail[i] >= 0.0)
            .map(|i| dt * (i as f64 - 1.0 + rail[i - 1] / (rail[i - 1] - rail[i])))
            .collect();
        let found = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
        let peak = rail.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        println!(
            "two-mass mode {:.3} Hz: period {found:.6e} s against {period:.6e} s ({:.1e}); \
             peak {peak:.6e} m",
            omega / (2.0 * PI),
            (found / period - 1.0).abs()
        );
        assert!(crossings.len() >= 4, "{} crossings", crossings.len());
        assert!(
            (found / period - 1.0).abs() < 1e-3,
            "{found:e} vs {period:e}"
        );
        assert!((peak / amplitude - 1.0).abs() < 1e-3, "{peak:e}");
    }
}

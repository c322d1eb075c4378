//! HHT-α books the energy its steps remove (dampers, structural and
//! numerical damping) only when some read output needs it
//! (`Simulation::read_only`): a run that reads none moves exactly as the
//! full run, a run that reads one gets the full run's totals, and the
//! totals of a run that skipped the bookkeeping are NaN, never wrong.

use guideway::model::{Model, Value, VarType};
use guideway::scene::builtin;
use guideway::{Advance, Scene, Simulation};

/// The outputs that need the steps' bookkeeping.
const BOOKED: [&str; 4] = [
    "energy.dissipated",
    "energy.beam_damping",
    "energy.numerical_dissipation",
    "energy.balance",
];

fn names(sim: &Simulation) -> Vec<String> {
    sim.outputs().iter().map(|o| o.name.clone()).collect()
}

fn booked(name: &str) -> bool {
    BOOKED.contains(&name)
}

/// The train to `end` in steps of `every`, with each row's outputs.
fn rows(scene: &Scene, read: Option<&dyn Fn(&str) -> bool>, every: f64, end: f64) -> Vec<Vec<f64>> {
    let mut sim = Simulation::new(scene).unwrap();
    if let Some(read) = read {
        let flags: Vec<bool> = names(&sim).iter().map(|n| read(n)).collect();
        sim.read_only(Some(&flags));
    }
    let n = sim.outputs().len();
    let mut out = Vec::new();
    let steps = (end / every).ceil() as usize;
    for k in 1..=steps {
        let t = (k as f64 * every).min(end);
        assert_eq!(sim.advance_to(t).unwrap(), Advance::Reached);
        let mut values = vec![f64::NAN; n];
        sim.output_values(&mut values);
        out.push(values);
    }
    out
}

fn train() -> Scene {
    builtin("train-8-coaches-3x25-300").unwrap()
}

#[test]
fn a_train_that_reads_no_energy_moves_as_the_full_run() {
    // Every output but the booked ones: the trajectory, the forces, the
    // events and the other energies are the full run's to the bit, from
    // the approach over the bridge (32 entries and exits) to the end.
    let scene = train();
    let end = scene.solver.end_time.unwrap();
    let full = rows(&scene, None, 0.25, end);
    let unbooked = |n: &str| !booked(n);
    let masked = rows(&scene, Some(&unbooked), 0.25, end);
    let names = names(&Simulation::new(&scene).unwrap());
    let present: Vec<usize> = (0..names.len()).filter(|&k| booked(&names[k])).collect();
    assert!(present.len() >= 3, "dampers, numerical damping, balance");
    for (row, (f, m)) in full.iter().zip(&masked).enumerate() {
        for k in 0..names.len() {
            if booked(&names[k]) {
                assert_eq!(m[k], 0.0, "unread {} in row {row}", names[k]);
                assert!(f[k].is_finite(), "{} = {}", names[k], f[k]);
            } else {
                assert_eq!(f[k].to_bits(), m[k].to_bits(), "{} in row {row}", names[k]);
            }
        }
    }
}

#[test]
fn a_train_that_reads_the_balance_gets_the_full_runs_energy() {
    let scene = train();
    let full = rows(&scene, None, 0.5, 3.0);
    let balance = |n: &str| n == "energy.balance";
    let masked = rows(&scene, Some(&balance), 0.5, 3.0);
    let names = names(&Simulation::new(&scene).unwrap());
    let k = names.iter().position(|n| n == "energy.balance").unwrap();
    for (f, m) in full.iter().zip(&masked) {
        assert_eq!(f[k].to_bits(), m[k].to_bits());
    }
    // The dampers have worked by then: the balance holds them.
    let d = names.iter().position(|n| n == "energy.dissipated").unwrap();
    assert!(full.last().unwrap()[d] > 1.0);
}

#[test]
fn totals_after_steps_without_the_bookkeeping_are_nan() {
    let scene = train();
    let mut sim = Simulation::new(&scene).unwrap();
    let names = names(&sim);
    let none = vec![false; names.len()];
    sim.read_only(Some(&none));
    sim.advance_to(0.01).unwrap();
    sim.read_only(None);
    sim.advance_to(0.02).unwrap();
    let mut values = vec![0.0; names.len()];
    sim.output_values(&mut values);
    for (name, v) in names.iter().zip(&values) {
        if booked(name) {
            assert!(v.is_nan(), "{name} = {v}");
        } else {
            assert!(v.is_finite(), "{name} = {v}");
        }
    }
    assert!(sim.energy_balance().is_nan());
}

#[test]
fn rk4_books_always() {
    // The paper's wheel (RK4) keeps its bookkeeping in its stages: masked
    // or not, its balance is the same.
    let scene = builtin("lee1994-wheel-10").unwrap();
    let full = rows(&scene, None, 0.1, 1.0);
    let mut sim = Simulation::new(&scene).unwrap();
    let flags = vec![false; sim.outputs().len()];
    sim.read_only(Some(&flags));
    for k in 1..=10 {
        sim.advance_to(k as f64 * 0.1).unwrap();
    }
    sim.read_only(None);
    let k = names(&sim)
        .iter()
        .position(|n| n == "energy.balance")
        .unwrap();
    let mut values = vec![0.0; sim.outputs().len()];
    sim.output_values(&mut values);
    assert!(values[k].is_finite());
    assert_eq!(values[k].to_bits(), full.last().unwrap()[k].to_bits());
}

#[test]
fn the_fmu_model_of_the_train_reports_its_energy() {
    // The FMU computes every output at each communication point, so it
    // books the energy: its totals are finite and the dampers' grows.
    let mut model = Model::<Simulation>::new(train()).unwrap();
    model.initialize().unwrap();
    let table = model.table().clone();
    let vr = |name: &str| table.by_name(name).unwrap().value_reference;
    let read = |model: &mut Model<Simulation>, name: &str| match model
        .get(VarType::Real, &[vr(name)])
        .unwrap()[0]
    {
        Value::Real(x) => x,
        ref v => panic!("{v:?}"),
    };
    let mut last = 0.0;
    for k in 0..5 {
        model.do_step(model.time(), 0.1).unwrap();
        for name in BOOKED.iter().filter(|n| table.by_name(n).is_some()) {
            let v = read(&mut model, name);
            assert!(v.is_finite(), "{name} = {v} after step {k}");
        }
        let dissipated = read(&mut model, "energy.dissipated");
        assert!(dissipated > last, "{dissipated} after {last}");
        last = dissipated;
    }
    assert!(read(&mut model, "energy.numerical_dissipation") != 0.0);
}

//! What each output's value at the end of initialization depends on, found
//! by running the model: every parameter and input is moved off its start
//! value, alone, and the outputs that change depend on it.
//!
//! Measured rather than declared by hand, so that it follows the model as
//! its variables change. A move that the model refuses (a rule, a stability
//! limit) is tried the other way; a variable that cannot be moved at all is
//! declared a dependency of every output, which is always true to say.

use super::variables::Input;
use super::{Dynamics, Model, Role, Value, VarType, VariableTable};
use crate::scene::Scene;

/// For output `k` of the model of `scene`, the value references of the
/// parameters and inputs its start value depends on (`result[k]`).
pub fn initial_dependencies<D: Dynamics>(scene: &Scene) -> Result<Vec<Vec<u32>>, String> {
    let mut base = Model::<D>::new(scene.clone()).map_err(|e| e.0)?;
    let reference = outputs_at_start(&mut base)?;
    let table = base.table().clone();
    let mut deps = vec![Vec::new(); reference.len()];
    for v in table.variables() {
        if !matches!(
            v.role,
            Role::Parameter(_) | Role::Setting(_) | Role::Input(_)
        ) {
            continue;
        }
        let Some(start) = v.start else { continue };
        let changed = moved_outputs(&mut base, v.value_reference, start, &reference);
        for (k, d) in deps.iter_mut().enumerate() {
            if changed.as_ref().is_none_or(|c| c[k]) {
                d.push(v.value_reference);
            }
        }
    }
    Ok(deps)
}

/// Output values of a model before initialization is left.
fn outputs_at_start<D: Dynamics>(model: &mut Model<D>) -> Result<Vec<Value>, String> {
    let vrs = output_refs(model.table());
    let mut values = Vec::with_capacity(vrs.len());
    for (vr, ty) in vrs {
        values.push(model.get(ty, &[vr]).map_err(|e| e.0)?[0]);
    }
    Ok(values)
}

fn output_refs(table: &VariableTable) -> Vec<(u32, VarType)> {
    let mut refs: Vec<(usize, u32, VarType)> = table
        .variables()
        .iter()
        .filter_map(|v| match v.role {
            Role::Output(k) => Some((k, v.value_reference, v.ty)),
            _ => None,
        })
        .collect();
    refs.sort_by_key(|r| r.0);
    refs.into_iter().map(|(_, vr, ty)| (vr, ty)).collect()
}

/// Which outputs change when variable `vr` moves off `start`; `None` if the
/// model accepts no move of it. Each move starts from `model` reset to its
/// start values, the state a new model of the same scene is in: a new model
/// per move rebuilt the variable table of every vehicle each time, which
/// made `export` grow as (variables)² × vehicles (issue 30).
fn moved_outputs<D: Dynamics>(
    model: &mut Model<D>,
    vr: u32,
    start: Value,
    reference: &[Value],
) -> Option<Vec<bool>> {
    // A coupling load does not enter the build of the start state: it is
    // put on and taken off again by the setter, with no rebuild (a reset per
    // move rebuilt the model for every coupling input: export grew as
    // inputs × vehicles, issue 30). Anything else starts from a reset.
    let coupling = matches!(
        model.table().get(vr).map(|v| v.role),
        Some(Role::Input(Input::Coupling { .. }))
    );
    let mut changed = None;
    for value in moves(start) {
        if !coupling {
            model.reset();
        }
        if model.set(&[vr], &[value]).is_err() {
            continue;
        }
        let values = outputs_at_start(model);
        if coupling && model.set(&[vr], &[start]).is_err() {
            model.reset();
        }
        if let Ok(values) = values {
            changed = Some(values.iter().zip(reference).map(|(a, b)| a != b).collect());
            break;
        }
    }
    if !coupling {
        model.reset();
    }
    changed
}

/// Values off `start`, up then down: by 10 % and a little more, so that a
/// zero start moves too.
fn moves(start: Value) -> Vec<Value> {
    match start {
        Value::Real(x) => vec![
            Value::Real(x * 1.1 + 1e-3),
            Value::Real(x * 0.9 - 1e-3),
            Value::Real(x * 0.9),
        ],
        Value::Integer(n) => vec![
            Value::Integer(n.saturating_add(1)),
            Value::Integer(n.saturating_sub(1)),
        ],
        Value::Boolean(b) => vec![Value::Boolean(!b)],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::BodyKind;
    use crate::Simulation;

    /// Issue 30, defect 8: export grew with coupling bodies because every
    /// coupling input's move rebuilt the start state. The analysis of a
    /// scene with a coupling on every body builds as many start states as
    /// that of the same scene with one coupling.
    #[test]
    fn coupling_inputs_cost_the_dependency_analysis_no_builds() {
        let builds = |couplings: &[&str]| {
            let mut scene = Scene::load("train-3-coaches-2x25-5").unwrap();
            scene.couplings = couplings.iter().map(|c| c.to_string()).collect();
            let before = crate::model::BUILDS.with(|b| b.get());
            initial_dependencies::<Simulation>(&scene).unwrap();
            crate::model::BUILDS.with(|b| b.get()) - before
        };
        let one = builds(&["coach1"]);
        let all = [
            "coach1",
            "coach1_bogie1",
            "coach1_bogie2",
            "coach1_wheelset1",
        ];
        let every: Vec<&str> = all
            .iter()
            .copied()
            .chain(["coach2", "coach2_wheelset1", "coach3", "coach3_wheelset4"])
            .collect();
        assert_eq!(builds(&every), one, "builds with 8 couplings against 1");
        assert!(one > 0);
    }

    /// A coupling load set on a start state already built (no rebuild, as
    /// the export's analysis now does) gives the start outputs of a model
    /// built with it, bit for bit; and taken off again, the outputs before.
    #[test]
    fn a_coupling_load_put_on_and_off_the_built_start_state_is_a_rebuild() {
        let mut scene = Scene::lee1994(BodyKind::Glider, 30.0, 0.005);
        scene.couplings = vec!["glider".into()];
        let mut built = Model::<Simulation>::new(scene.clone()).unwrap();
        let before = outputs_at_start(&mut built).unwrap();
        let vr = built
            .table()
            .by_name("glider.coupling_force_y")
            .unwrap()
            .value_reference;
        let load = [Value::Real(-2.5e4)];
        built.set(&[vr], &load).unwrap();
        assert!(built.sim.is_some(), "the start state was rebuilt");
        let on_built = outputs_at_start(&mut built).unwrap();
        let mut fresh = Model::<Simulation>::new(scene).unwrap();
        fresh.set(&[vr], &load).unwrap();
        let rebuilt = outputs_at_start(&mut fresh).unwrap();
        assert_eq!(on_built, rebuilt);
        assert_ne!(on_built, before, "the load changes some start output");
        built.set(&[vr], &[Value::Real(0.0)]).unwrap();
        assert_eq!(outputs_at_start(&mut built).unwrap(), before);
    }

    fn scene() -> Scene {
        Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025)
    }

    fn named(table: &VariableTable, deps: &[Vec<u32>], output: &str) -> Vec<String> {
        let Role::Output(k) = table.by_name(output).unwrap().role else {
            panic!("{output} is not an output")
        };
        let name = |vr: &u32| table.get(*vr).unwrap().name.clone();
        deps[k].iter().map(name).collect()
    }

    #[test]
    fn start_outputs_depend_on_what_sets_them() {
        let deps = initial_dependencies::<Simulation>(&scene()).unwrap();
        let m = Model::<Simulation>::new(scene()).unwrap();
        let t = m.table();
        // (a wheel started above the track, wheel.initial_height > 0, is
        // higher and carries no contact force)
        assert_eq!(
            named(t, &deps, "contact.normal_force"),
            ["wheel.initial_height", "wheel.force_y"]
        );
        assert_eq!(named(t, &deps, "wheel.x"), ["wheel.initial_position"]);
        assert_eq!(
            named(t, &deps, "wheel.y"),
            [
                "beam.surface_offset",
                "wheel.radius",
                "wheel.initial_height"
            ]
        );
        assert_eq!(named(t, &deps, "wheel.vx"), ["wheel.initial_speed"]);
        assert!(named(t, &deps, "sensor.midspan.deflection").is_empty());
    }

    /// What was not declared does not matter, checked with moves of another
    /// size than the analysis uses (halving, doubling).
    #[test]
    fn undeclared_dependencies_do_not_change_start_outputs() {
        let deps = initial_dependencies::<Simulation>(&scene()).unwrap();
        let mut base = Model::<Simulation>::new(scene()).unwrap();
        let reference = outputs_at_start(&mut base).unwrap();
        let known: Vec<_> = base
            .table()
            .variables()
            .iter()
            .filter(|v| {
                matches!(
                    v.role,
                    Role::Parameter(_) | Role::Setting(_) | Role::Input(_)
                )
            })
            .cloned()
            .collect();
        let mut checked = 0;
        for v in known {
            let value = match v.start.unwrap() {
                Value::Real(0.0) => Value::Real(0.5),
                Value::Real(x) => Value::Real(x * 0.5),
                Value::Integer(n) => Value::Integer(n * 2),
                b => b,
            };
            let mut m = Model::<Simulation>::new(scene()).unwrap();
            if m.set(&[v.value_reference], &[value]).is_err() {
                continue;
            }
            let Ok(values) = outputs_at_start(&mut m) else {
                continue;
            };
            for (k, (a, b)) in values.iter().zip(&reference).enumerate() {
                if !deps[k].contains(&v.value_reference) {
                    assert_eq!(a, b, "output {k} moved with {}", v.name);
                    checked += 1;
                }
            }
        }
        assert!(checked > 100, "only {checked} pairs checked");
    }

    /// One model reset between moves gives what a new model per move gave
    /// (the analysis before issue 30's fix, written out here as the
    /// reference), on a train with coupling ports on every body of a coach.
    #[test]
    fn a_reset_model_finds_what_a_new_model_per_move_found() {
        let mut scene = crate::scene::builtin("train-3-coaches-2x25-5").unwrap();
        scene.couplings = ["coach1", "coach1_bogie2", "coach2_wheelset3"]
            .map(String::from)
            .to_vec();
        let deps = initial_dependencies::<Simulation>(&scene).unwrap();
        let mut base = Model::<Simulation>::new(scene.clone()).unwrap();
        let reference = outputs_at_start(&mut base).unwrap();
        let mut expected = vec![Vec::new(); reference.len()];
        for v in base.table().variables() {
            let probed = matches!(
                v.role,
                Role::Parameter(_) | Role::Setting(_) | Role::Input(_)
            );
            let Some(start) = v.start.filter(|_| probed) else {
                continue;
            };
            let changed = moves(start).into_iter().find_map(|value| {
                let mut model = Model::<Simulation>::new(scene.clone()).ok()?;
                model.set(&[v.value_reference], &[value]).ok()?;
                let values = outputs_at_start(&mut model).ok()?;
                Some(
                    values
                        .iter()
                        .zip(&reference)
                        .map(|(a, b)| a != b)
                        .collect::<Vec<_>>(),
                )
            });
            for (k, e) in expected.iter_mut().enumerate() {
                if changed.as_ref().is_none_or(|c| c[k]) {
                    e.push(v.value_reference);
                }
            }
        }
        assert_eq!(deps, expected);
        assert!(deps.iter().any(|d| !d.is_empty()));
    }
}

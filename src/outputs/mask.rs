//! Outputs computed only for the columns a sink reads: a run whose rows go
//! to no file needs only the summary's few columns, and the others (body
//! accelerations, section forces, energies) were a sixth of a train's run.

use crate::outputs::{evaluate, Needs, Probes, Quantity};
use crate::state::SimState;
use crate::system::System;

/// The outputs a sink reads, in column order.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputMask {
    quantities: Vec<Quantity>,
    /// What the read quantities need, found once (`Needs::of`).
    needs: Needs,
    columns: Vec<usize>,
}

impl OutputMask {
    /// The quantities of `all` whose flag in `read` is set (a column beyond
    /// `read` is not read).
    pub fn new(all: &[Quantity], read: &[bool]) -> OutputMask {
        let columns: Vec<usize> = (0..all.len())
            .filter(|&k| read.get(k).copied().unwrap_or(false))
            .collect();
        let quantities: Vec<Quantity> = columns.iter().map(|&k| all[k]).collect();
        OutputMask {
            needs: Needs::of(&quantities),
            quantities,
            columns,
        }
    }

    /// Whether a read output needs the energy the steps remove (booked by
    /// the integrator step by step, not computable at the end).
    pub fn reads_energy_books(&self) -> bool {
        self.needs.energy_books
    }

    /// Every output in `state` into `out`: the read ones computed, the
    /// others 0.
    pub fn values(&self, system: &System, state: &SimState, probes: &Probes, out: &mut [f64]) {
        let read = self.columns.len();
        let read_quantities = (self.quantities.as_slice(), self.needs);
        evaluate(system, state, probes, read_quantities, &mut out[..read]);
        spread(&self.columns, out);
    }
}

/// Move `out[i]` to `out[columns[i]]` for the increasing `columns`, and set
/// every other entry to 0. In place: column i is at or after entry i, so
/// going backwards no entry is overwritten before it is moved.
fn spread(columns: &[usize], out: &mut [f64]) {
    let mut next = out.len();
    for (i, &column) in columns.iter().enumerate().rev() {
        let v = out[i];
        out[column + 1..next].fill(0.0);
        out[column] = v;
        next = column;
    }
    out[..next].fill(0.0);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{builtin, builtins};
    use crate::Simulation;

    #[test]
    fn spread_moves_each_value_to_its_column_and_zeroes_the_rest() {
        let mut out = [1.0, 2.0, 3.0, 9.0, 9.0, 9.0, 9.0];
        spread(&[1, 2, 5], &mut out);
        assert_eq!(out, [0.0, 1.0, 2.0, 0.0, 0.0, 3.0, 0.0]);
        let mut all = [4.0, 5.0];
        spread(&[0, 1], &mut all);
        assert_eq!(all, [4.0, 5.0]);
        let mut none = [7.0; 3];
        spread(&[], &mut none);
        assert_eq!(none, [0.0; 3]);
    }

    #[test]
    fn a_masked_train_reports_the_read_columns_as_the_full_outputs_do() {
        let scene = builtin("train-8-coaches-3x25-300").unwrap();
        let mut sim = Simulation::new(&scene).unwrap();
        sim.advance_to(0.02).unwrap();
        let n = sim.outputs().len();
        let mut full = vec![0.0; n];
        sim.output_values(&mut full);
        // Every third column, and the last (the energy balance's
        // neighbours and the solver's counts).
        let read: Vec<bool> = (0..n).map(|k| k % 3 == 1 || k == n - 1).collect();
        sim.read_only(Some(&read));
        let mut masked = vec![f64::NAN; n];
        sim.output_values(&mut masked);
        for k in 0..n {
            let expected = if read[k] { full[k] } else { 0.0 };
            assert_eq!(masked[k].to_bits(), expected.to_bits(), "column {k}");
        }
        assert!(masked.iter().any(|&v| v != 0.0));
        sim.read_only(None);
        sim.output_values(&mut masked);
        assert_eq!(masked, full);
    }

    /// The first non-finite value of `values`, named.
    fn first_not_finite(outputs: &[crate::outputs::OutputInfo], values: &[f64]) -> Option<String> {
        let k = values.iter().position(|v| !v.is_finite())?;
        Some(format!("{} = {}", outputs[k].name, values[k]))
    }

    /// Every output of every built-in scene, a few steps in, is a finite
    /// number; read alone (a mask of its one column, so that only its own
    /// `Quantity::needs` is computed) it has the bits it has among all the
    /// outputs: no output leans on what another output needs. (An output
    /// missing from the needs reads NaN alone.) The moving forces' runs
    /// read every output with the beam's dynamics: all finite.
    #[test]
    fn every_output_of_every_builtin_scene_is_finite_and_the_same_read_alone() {
        for (name, _) in builtins() {
            let scene = builtin(name).unwrap();
            let steps = |k: u32| k as f64 * scene.solver.step;
            if crate::moving_load::is_moving_force_scene(&scene) {
                use crate::simulation::Steppable;
                let mut run = crate::moving_load::ForceRun::new(&scene).unwrap();
                run.advance_to(steps(5)).unwrap();
                let mut values = vec![0.0; run.outputs().len()];
                run.output_values(&mut values);
                let bad = first_not_finite(run.outputs(), &values);
                assert!(bad.is_none(), "{name}: {bad:?}");
                continue;
            }
            let mut sim = Simulation::new(&scene).unwrap();
            sim.advance_to(steps(5)).unwrap();
            let n = sim.outputs().len();
            let mut all = vec![0.0; n];
            sim.output_values(&mut all);
            let bad = first_not_finite(sim.outputs(), &all);
            assert!(bad.is_none(), "{name}: {bad:?}");
            let mut alone = vec![0.0; n];
            for k in 0..n {
                let read: Vec<bool> = (0..n).map(|j| j == k).collect();
                sim.read_only(Some(&read));
                sim.output_values(&mut alone);
                let output = &sim.outputs()[k].name;
                assert_eq!(
                    alone[k].to_bits(),
                    all[k].to_bits(),
                    "{name}: {output} read alone"
                );
            }
            sim.read_only(None);
        }
    }

    /// A quantity's needs are what its value reads: the balance needs the
    /// springs' energy and the books; a position nothing.
    #[test]
    fn the_needs_of_a_few_quantities() {
        let balance = Quantity::Balance.needs();
        assert!(balance.spring_energy && balance.energy_books && !balance.frames);
        assert_eq!(Quantity::X(0).needs(), Needs::of(&[]));
        let some = Needs::of(&[Quantity::NominalSpeed(0), Quantity::SectionShear(1)]);
        assert!(some.frames && some.beam_dynamics && !some.body_accelerations);
    }
}

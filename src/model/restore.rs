//! Restoring a saved state, which may come from a forged serialized FMU
//! state: checked to be a state of this model before anything is built from
//! it, and all or nothing.

use crate::scene::{Scene, MAX_MAGNITUDE};

use super::{
    apply_inputs, err, first_non_finite, param_value, set_param, validate, Dynamics, Model,
    ModelError, Phase, Role, Snapshot,
};

impl<D: Dynamics> Model<D> {
    /// Check a snapshot before anything of it is used: it may come from a
    /// forged serialized state. It must be a state of this model: its scene
    /// this model's with at most the parameters changed, each within its
    /// rule (checked before any vector is sized by them), the whole scene
    /// valid once running; finite inputs and times.
    pub fn check_snapshot(&self, snap: &Snapshot<D::State>) -> Result<(), ModelError> {
        let refuse = |why: String| err(format!("the state does not fit this model: {why}"));
        self.scene_fits(&snap.scene).or_else(refuse)?;
        if snap.phase == Phase::Running {
            validate(&snap.scene)
                .map_err(|e| ModelError(format!("the state's scene is invalid: {e}")))?;
        }
        self.inputs_fit(snap).or_else(refuse)?;
        if (snap.phase == Phase::Running) != snap.sim.is_some() {
            return refuse(format!(
                "phase {:?} with the dynamics' state {}",
                snap.phase,
                if snap.sim.is_some() {
                    "present"
                } else {
                    "missing"
                }
            ));
        }
        Ok(())
    }

    /// Whether `theirs` is this model's scene with at most the parameters
    /// changed, each within its rule; else why not.
    fn scene_fits(&self, theirs: &Scene) -> Result<(), String> {
        if theirs.sensors.len() != self.start_scene.sensors.len() {
            return Err(format!(
                "it has {} sensors, this model {}",
                theirs.sensors.len(),
                self.start_scene.sensors.len()
            ));
        }
        let mut mine = self.start_scene.clone();
        for v in self.table.variables() {
            if let Role::Parameter(p) = v.role {
                let value = param_value(theirs, p);
                if let Err(rule) = set_param(&mut mine, p, value) {
                    return Err(format!("{} = {value:?}: {rule}", v.name));
                }
            }
        }
        if mine != *theirs {
            return Err("its scene differs from this model's in more than parameters".into());
        }
        Ok(())
    }

    /// Whether the snapshot's inputs, their history and its start time are
    /// what the setters would accept; else why not.
    fn inputs_fit(&self, snap: &Snapshot<D::State>) -> Result<(), String> {
        if snap.inputs.len() != self.inputs.len() {
            return Err(format!(
                "it has {} inputs, this model {}",
                snap.inputs.len(),
                self.inputs.len()
            ));
        }
        if !snap.start_time.is_finite() {
            return Err("its start time is not finite".into());
        }
        // The rule fmi2SetReal applies to an input: a state must not carry
        // in what the setter refuses.
        if let Some((i, x)) = (snap.inputs.iter().enumerate())
            .find(|(_, x)| !(x.is_finite() && x.abs() <= MAX_MAGNITUDE))
        {
            return Err(format!(
                "its input {i} = {x:e} is not finite or not within ±{MAX_MAGNITUDE:e} (the magnitude limit)"
            ));
        }
        if let Some(history) = &snap.input_history {
            history.check(self.inputs.len())?;
        }
        Ok(())
    }

    /// `check_snapshot` and the dynamics' state checked as a whole (shape,
    /// numbers, the bodies where their contacts say), as `restore` would:
    /// what `fmi2DeSerializeFMUstate` accepts, `fmi2SetFMUstate` restores.
    pub fn check_whole(&self, snap: &Snapshot<D::State>) -> Result<(), ModelError> {
        self.check_snapshot(snap)?;
        let Some(state) = &snap.sim else {
            return Ok(());
        };
        let refuse = |e: String| err(format!("the state does not fit this model: {e}"));
        match &self.sim {
            Some(sim) if self.scene == snap.scene => sim.check_restorable(state).or_else(refuse),
            _ => {
                let sim = D::build(&snap.scene)
                    .map_err(|e| ModelError(format!("cannot rebuild the model: {e}")))?;
                sim.check_restorable(state).or_else(refuse)
            }
        }
    }

    /// Restore `snap` (checked first); on any refusal the model is unchanged.
    pub fn restore(&mut self, snap: &Snapshot<D::State>) -> Result<(), ModelError> {
        self.changing();
        self.check_snapshot(snap)?;
        let sim = match &snap.sim {
            Some(state) => Some(self.restored_sim(snap, state)?),
            None => None,
        };
        self.scene = snap.scene.clone();
        self.inputs = snap.inputs.clone();
        self.start_time = snap.start_time;
        self.phase = snap.phase;
        self.sim = sim;
        self.discarded = None;
        self.input_history = snap.input_history.clone();
        self.input_derivatives.clear();
        self.loads_ramped = false;
        if let Some(e) = &mut self.estimator {
            e.clear();
        }
        Ok(())
    }

    /// The dynamics at `state`: this model's own (when the scene is the
    /// same) or new ones built for the state's (valid) scene. The state must
    /// fit them and give finite outputs; if not, this model's own dynamics
    /// are put back as they were.
    fn restored_sim(
        &mut self,
        snap: &Snapshot<D::State>,
        state: &D::State,
    ) -> Result<D, ModelError> {
        let own = match self.sim.take() {
            Some(sim) if self.scene == snap.scene => Some(sim),
            other => {
                self.sim = other;
                None
            }
        };
        let old = own.as_ref().map(|s| s.state());
        let mut sim = match own {
            Some(sim) => sim,
            None => D::build(&snap.scene)
                .map_err(|e| ModelError(format!("cannot rebuild the model: {e}")))?,
        };
        let fitted = sim.restore(state).and_then(|()| {
            apply_inputs(&mut sim, &snap.inputs, snap.scene.vehicles.len());
            match first_non_finite(&sim) {
                Some(bad) => Err(bad),
                None if !sim.time().is_finite() => Err(format!("its time is {}", sim.time())),
                None => Ok(()),
            }
        });
        match (fitted, old) {
            (Ok(()), _) => Ok(sim),
            (Err(e), old) => {
                if let Some(old) = old {
                    sim.restore(&old)
                        .map_err(|e| ModelError(format!("cannot put the model back: {e}")))?;
                    apply_inputs(&mut sim, &self.inputs, self.scene.vehicles.len());
                    self.sim = Some(sim);
                }
                err(format!("cannot restore the state: {e}"))
            }
        }
    }
}

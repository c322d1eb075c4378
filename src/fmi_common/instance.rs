//! One FMU instance of either FMI version: the co-simulation life cycle
//! around an `FmuModel`, plus the FMU states handed out to the importer.
//!
//! Every operation checks the instance's mode against its front's rules
//! first; a call in the wrong mode is refused (the exports turn the `Err`
//! into an error status and a log line naming the function, the mode and
//! the modes it is allowed in) and leaves the instance as it was.

use super::logging::Logger;
use super::states::States;
use super::{mode_after_restore, Call, Front, Status};
use crate::model::{FmuModel, ModelError, StepOutcome, Value, VarType};

/// How a doStep ended: its status, whether the run is over, whether it
/// ended early at an event, and the time reached.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepReport<S> {
    pub status: S,
    pub terminate: bool,
    pub early_return: bool,
    pub last_successful_time: f64,
}

pub struct Instance<M: FmuModel, F: Front> {
    pub logger: Logger<F::Sink>,
    mode: F::Mode,
    model: M,
    token: String,
    /// The read-only variable holding the model time, if the front declares
    /// one (FMI 3.0's independent variable).
    time_vr: Option<u32>,
    states: States<M::Snapshot>,
    /// The importer allows doStep to return early: it then ends at the end
    /// of the internal step of a simulation event.
    early_return_allowed: bool,
}

/// The error of `function` about `e`.
fn in_call(function: &str) -> impl Fn(ModelError) -> String + '_ {
    move |e| format!("{function}: {e}")
}

impl<M: FmuModel, F: Front> Instance<M, F> {
    /// An instance of the model of `config`, whose model description must
    /// have the token (GUID) `token`.
    pub fn new(
        config: M::Config,
        token: &str,
        logger: Logger<F::Sink>,
    ) -> Result<Self, (Logger<F::Sink>, String)> {
        let model = match M::new(config) {
            Ok(m) => m,
            Err(e) => {
                let noun = M::CONFIG_NOUN;
                return Err((logger, format!("the FMU's {noun} is invalid: {e}")));
            }
        };
        let (_, own) = F::generate(&model.info(), model.table());
        if own != token {
            return Err((logger, F::token_mismatch(token, &own)));
        }
        Ok(Instance {
            logger,
            mode: F::INSTANTIATED,
            time_vr: F::independent_variable(model.table()),
            model,
            token: own,
            states: States::new(F::STATE_NOUN),
            early_return_allowed: false,
        })
    }

    /// `earlyReturnAllowed` of the instantiation.
    pub fn allow_early_return(&mut self, allowed: bool) {
        self.early_return_allowed = allowed;
    }

    pub fn mode(&self) -> F::Mode {
        self.mode
    }

    pub fn model(&self) -> &M {
        &self.model
    }

    pub fn set_fatal(&mut self) {
        self.mode = F::FATAL;
    }

    /// Refuse `function` unless the instance is in one of `allowed`.
    pub fn require(&self, function: &str, allowed: &[F::Mode]) -> Result<(), String> {
        if allowed.contains(&self.mode) {
            return Ok(());
        }
        Err(format!(
            "{function} is not allowed in state {:?} (allowed in: {allowed:?})",
            self.mode
        ))
    }

    fn require_call(&self, call: Call) -> Result<(), String> {
        self.require(F::name(call), F::allowed(call))
    }

    /// Refuse setting inputs with `function` where the rules forbid it;
    /// after a rolled-back failure (Discard, not the end of the run) the
    /// master may change inputs and retry the step, beyond the standard's
    /// state machine.
    pub fn require_inputs_settable(&self, function: &str) -> Result<(), String> {
        if self.mode != F::DISCARDED || self.terminated() {
            self.require(function, F::allowed(Call::Set))?;
        }
        Ok(())
    }

    /// The run has ended (the model's `exit_time`).
    pub fn terminated(&self) -> bool {
        self.model.exit_time().is_some()
    }

    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), String> {
        self.require_call(Call::SetupExperiment)?;
        self.model.set_experiment(start, stop).map_err(|e| e.0)
    }

    /// Moves to `to` by `call`, where the rules allow `call`.
    fn enter(&mut self, call: Call, to: F::Mode) -> Result<(), String> {
        self.require_call(call)?;
        self.mode = to;
        Ok(())
    }

    pub fn enter_initialization_mode(&mut self) -> Result<(), String> {
        self.enter(Call::EnterInitializationMode, F::INITIALIZATION_MODE)
    }

    pub fn exit_initialization_mode(&mut self) -> Result<(), String> {
        self.require_call(Call::ExitInitializationMode)?;
        self.model.initialize().map_err(|e| e.0)?;
        self.mode = F::STEPPING;
        self.logger.log(Status::Ok, "initialized");
        Ok(())
    }

    pub fn terminate(&mut self) -> Result<(), String> {
        self.enter(Call::Terminate, F::TERMINATED)
    }

    pub fn reset(&mut self) -> Result<(), String> {
        self.require_call(Call::Reset)?;
        self.model.reset();
        self.mode = F::INSTANTIATED;
        Ok(())
    }

    /// The values of `vrs` of type `ty` (`function` names the call).
    pub fn get(&mut self, function: &str, ty: VarType, vrs: &[u32]) -> Result<Vec<Value>, String> {
        let mut values = Vec::with_capacity(vrs.len());
        self.get_each(function, ty, vrs, |v| values.push(v))?;
        Ok(values)
    }

    /// `get`, each value handed to `put` in the order of `vrs`.
    pub fn get_each(
        &mut self,
        function: &str,
        ty: VarType,
        vrs: &[u32],
        put: impl FnMut(Value),
    ) -> Result<(), String> {
        self.require(function, F::allowed(Call::Get))?;
        self.model.get_each(ty, vrs, put).map_err(in_call(function))
    }

    /// `get_each` into `out`, each value converted by `store`.
    pub fn get_into<T>(
        &mut self,
        function: &str,
        ty: VarType,
        vrs: &[u32],
        out: &mut [T],
        store: impl Fn(Value) -> T,
    ) -> Result<(), String> {
        let mut out = out.iter_mut();
        self.get_each(function, ty, vrs, |v| {
            if let Some(o) = out.next() {
                *o = store(v);
            }
        })
    }

    /// The real values of `vrs` (and of the time variable, if declared)
    /// written into `out`.
    pub fn get_reals(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        let function = F::name(Call::GetReal);
        self.require(function, F::allowed(Call::Get))?;
        let e = in_call(function);
        let Some(time_vr) = self.time_vr.filter(|t| vrs.contains(t)) else {
            return self.model.get_reals(vrs, out).map_err(e);
        };
        for (vr, o) in vrs.iter().zip(out.iter_mut()) {
            if *vr == time_vr {
                *o = self.model.time();
            } else {
                let (vr, o) = (std::slice::from_ref(vr), std::slice::from_mut(o));
                self.model.get_reals(vr, o).map_err(&e)?;
            }
        }
        Ok(())
    }

    pub fn set(&mut self, function: &str, vrs: &[u32], values: &[Value]) -> Result<(), String> {
        self.require_inputs_settable(function)?;
        if let Some(time_vr) = self.time_vr.filter(|t| vrs.contains(t)) {
            return Err(format!(
                "{function}: time (value reference {time_vr}) is the independent variable and cannot be set"
            ));
        }
        self.model.set(vrs, values).map_err(in_call(function))
    }

    /// `set` from `values`, each converted by `load`.
    pub fn set_from<T: Copy>(
        &mut self,
        function: &str,
        vrs: &[u32],
        values: &[T],
        load: impl Fn(T) -> Value,
    ) -> Result<(), String> {
        let values: Vec<Value> = values.iter().map(|&x| load(x)).collect();
        self.set(function, vrs, &values)
    }

    /// Derivatives of inputs for the next step (allowed where inputs may
    /// be set).
    pub fn set_input_derivatives(
        &mut self,
        function: &str,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), String> {
        self.require_inputs_settable(function)?;
        self.model
            .set_input_derivatives(vrs, orders, values)
            .map_err(in_call(function))
    }

    /// doStep: OK, or Discard at the end of the run (`terminate`) or after a
    /// failure a smaller step cures (rolled back to `t`), or `Err` for a
    /// failure no retry of it cures (rolled back).
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<StepReport<F::Status>, String> {
        let function = F::name(Call::DoStep);
        self.require_call(Call::DoStep)?;
        if self.terminated() {
            let refusal = M::after_end(self.model.time());
            return Err(format!("{function}: {refusal}"));
        }
        let outcome = if self.early_return_allowed {
            self.model.do_step_until_event(t, h)
        } else {
            self.model.do_step(t, h)
        }
        .map_err(in_call(function))?;
        let early_return = self.model.ended_at_event();
        for event in self.model.take_events() {
            self.logger.log(Status::Ok, &format!("event: {event}"));
        }
        let (status, terminate) = self.settle(function, outcome)?;
        Ok(StepReport {
            status: F::status(status),
            terminate,
            early_return,
            last_successful_time: self.model.time(),
        })
    }

    /// The mode and status after a step's `outcome`; a Discard is logged.
    fn settle(&mut self, function: &str, outcome: StepOutcome) -> Result<(Status, bool), String> {
        let (message, terminate) = match outcome {
            StepOutcome::Completed => {
                self.mode = F::STEPPING;
                return Ok((Status::Ok, false));
            }
            StepOutcome::Exited { time } => (format!("{function}: {}", M::end_reached(time)), true),
            StepOutcome::Failed {
                message,
                curable: true,
            } => (format!("{function}: {message}"), false),
            // A master retrying this would loop forever: an error, not a
            // Discard. The state is rolled back; other inputs may cure it.
            StepOutcome::Failed {
                message,
                curable: false,
            } => return Err(format!("{function}: {message}")),
        };
        self.mode = F::DISCARDED;
        self.logger.log(Status::Discard, &message);
        Ok((Status::Discard, terminate))
    }

    // ---- FMU states -------------------------------------------------------

    /// GetFMUState: a new state, or `existing` (one of ours) overwritten.
    pub fn get_state(&mut self, existing: usize) -> Result<usize, String> {
        let function = F::name(Call::GetState);
        self.require_call(Call::GetState)?;
        let snap = self.model.snapshot();
        if existing == 0 {
            return Ok(self.states.keep(F::next_state_handle(), snap));
        }
        self.states.overwrite(function, existing, snap)?;
        Ok(existing)
    }

    pub fn set_state(&mut self, key: usize) -> Result<(), String> {
        let function = F::name(Call::SetState);
        self.require_call(Call::SetState)?;
        let snap = self.states.get(function, key)?.clone();
        self.model.restore(&snap).map_err(in_call(function))?;
        let (phase, terminated) = (self.model.phase(), self.terminated());
        self.mode = mode_after_restore::<F>(self.mode, phase, terminated);
        self.logger.log(Status::Ok, "FMU state restored");
        Ok(())
    }

    pub fn free_state(&mut self, key: usize) -> Result<(), String> {
        self.states.free(F::name(Call::FreeState), key)
    }

    /// The bytes of the state `key` (for the serializing call and the size
    /// query alike).
    pub fn serialize_state(&self, key: usize) -> Result<Vec<u8>, String> {
        let function = F::name(Call::SerializeState);
        self.require_call(Call::SerializeState)?;
        let snap = self.states.get(function, key)?;
        M::serialize(snap, &self.token).map_err(in_call(function))
    }

    pub fn deserialize_state(&mut self, bytes: &[u8]) -> Result<usize, String> {
        let function = F::name(Call::DeserializeState);
        self.require_call(Call::DeserializeState)?;
        let snap = self
            .model
            .deserialize_checked(bytes, &self.token)
            .map_err(in_call(function))?;
        Ok(self.states.keep(F::next_state_handle(), snap))
    }
}

//! What the FMI 2.0 and FMI 3.0 fronts share: one instance life cycle over
//! an `FmuModel` (modes, call rules, value access, steps, FMU states), the
//! guards of the C boundary (no panic crosses it, every refusal is logged),
//! the logger's filtering and the parts of modelDescription.xml the two
//! schemas agree on.
//!
//! A front (`crate::fmi2`, `crate::fmi3`) keeps only its C ABI (the
//! `fmi-sys` types, its status numbers, its function names and argument
//! shapes) and its XML dialect; it tells this layer those through the
//! `Front` trait. Like the fronts, this layer sees the model only through
//! `model::FmuModel` (its table, its `ModelInfo`, its life cycle).

pub mod abi;
pub mod description;
pub mod instance;
pub mod logging;
mod states;

pub use instance::{Instance, StepReport};
pub use logging::{LogSink, Logger};

use crate::model::{FmuModel, ModelInfo, Phase, VariableTable};

/// The statuses both standards know, before a front turns them into its
/// own numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    Ok,
    Warning,
    Discard,
    Error,
    Fatal,
}

/// The operations on an instance whose name and allowed modes a front
/// declares (getters and setters of typed values are named by the front at
/// the call, since each standard has several).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Call {
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    FreeInstance,
    GetReal,
    Get,
    Set,
    DoStep,
    GetState,
    SetState,
    FreeState,
    StateSize,
    SerializeState,
    DeserializeState,
}

/// One FMI version's view of the shared instance: its status numbers, its
/// modes and call rules (one list of allowed modes per call), the names it
/// gives the calls and its model description.
pub trait Front: Sized + 'static {
    /// The status type of the C ABI.
    type Status: Copy + PartialEq + std::fmt::Debug;
    /// The modes of the version's co-simulation state machine.
    type Mode: Copy + Eq + std::fmt::Debug;
    /// How the version's logger callback is called.
    type Sink: LogSink;

    const INSTANTIATED: Self::Mode;
    const INITIALIZATION_MODE: Self::Mode;
    /// After initialization and after a completed step.
    const STEPPING: Self::Mode;
    /// After a step that returned Discard (the end of the run, or a
    /// rolled-back failure that a smaller step may cure).
    const DISCARDED: Self::Mode;
    const TERMINATED: Self::Mode;
    /// After a caught panic: only freeing the instance is left.
    const FATAL: Self::Mode;
    /// What the standard calls an FMU state in messages.
    const STATE_NOUN: &'static str;

    fn status(status: Status) -> Self::Status;
    /// The standard's name of `call`.
    fn name(call: Call) -> &'static str;
    /// The modes in which `call` is allowed.
    fn allowed(call: Call) -> &'static [Self::Mode];
    /// A fresh FMU state handle: a token, never an address, never reused
    /// within the process.
    fn next_state_handle() -> usize;
    /// The refusal of an instantiation token (GUID) that is not `own`.
    fn token_mismatch(given: &str, own: &str) -> String;
    /// The value reference of a read-only variable holding the model time,
    /// if the version declares one.
    fn independent_variable(table: &VariableTable) -> Option<u32>;
    /// The modelDescription.xml of a model described by `info` and
    /// `table`, with its token.
    fn generate(info: &ModelInfo, table: &VariableTable) -> (String, String);
}

/// The mode an instance is in after a state of `phase` was restored in
/// `current` (a state taken before initialization keeps the instance in
/// the mode it had, if that was before initialization too).
fn mode_after_restore<F: Front>(current: F::Mode, phase: Phase, terminated: bool) -> F::Mode {
    match phase {
        Phase::Running if terminated => F::DISCARDED,
        Phase::Running => F::STEPPING,
        Phase::Configuring if current == F::INSTANTIATED => F::INSTANTIATED,
        Phase::Configuring => F::INITIALIZATION_MODE,
    }
}

/// What an FMU of a model declares: its modelDescription.xml, its GUID or
/// instantiation token and its variable table (built by the same code an
/// instance uses, so the two always agree).
pub struct Description {
    pub xml: String,
    pub guid: String,
    pub model_identifier: String,
    pub table: VariableTable,
}

/// The description of the model of `config` in `F`'s dialect.
pub fn describe<M: FmuModel, F: Front>(config: M::Config) -> Result<Description, String> {
    let model = M::new(config).map_err(|e| e.0)?;
    let mut table = model.table().clone();
    table.set_initial_dependencies(&model.initial_dependencies()?);
    let info = model.info();
    let (xml, guid) = F::generate(&info, &table);
    Ok(Description {
        xml,
        guid,
        model_identifier: description::model_identifier(&info.name),
        table,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi2::instance::Fmi2;
    use crate::fmi3::instance::Fmi3;

    const CALLS: [Call; 16] = [
        Call::SetupExperiment,
        Call::EnterInitializationMode,
        Call::ExitInitializationMode,
        Call::Terminate,
        Call::Reset,
        Call::FreeInstance,
        Call::GetReal,
        Call::Get,
        Call::Set,
        Call::DoStep,
        Call::GetState,
        Call::SetState,
        Call::FreeState,
        Call::StateSize,
        Call::SerializeState,
        Call::DeserializeState,
    ];

    /// A front's table of rules lets the co-simulation life cycle be walked
    /// (instantiate, initialize, step, retry after a Discard, terminate,
    /// reset), keeps a fatal instance closed to every call, and allows the
    /// FMU state calls wherever the instance is alive.
    fn walkable<F: Front>(prefix: &str) {
        let allows = |call, mode| F::allowed(call).contains(&mode);
        for call in CALLS {
            assert!(
                !allows(call, F::FATAL),
                "{prefix}: {call:?} after a fatal error"
            );
            assert!(
                F::name(call).starts_with(prefix),
                "{call:?}: {}",
                F::name(call)
            );
        }
        assert!(allows(Call::SetupExperiment, F::INSTANTIATED));
        assert!(allows(Call::EnterInitializationMode, F::INSTANTIATED));
        assert!(allows(Call::ExitInitializationMode, F::INITIALIZATION_MODE));
        assert!(allows(Call::Get, F::INITIALIZATION_MODE) && allows(Call::Get, F::STEPPING));
        assert!(allows(Call::DoStep, F::STEPPING) && allows(Call::DoStep, F::DISCARDED));
        assert!(allows(Call::Terminate, F::STEPPING) && allows(Call::Reset, F::TERMINATED));
        assert!(!allows(Call::DoStep, F::TERMINATED) && !allows(Call::Set, F::TERMINATED));
        let alive = [
            F::INSTANTIATED,
            F::INITIALIZATION_MODE,
            F::STEPPING,
            F::TERMINATED,
        ];
        for call in [Call::GetState, Call::SetState, Call::SerializeState] {
            assert!(alive.iter().all(|&m| allows(call, m)), "{call:?}");
        }
    }

    #[test]
    fn both_fronts_rules_walk_the_life_cycle_and_close_a_fatal_instance() {
        walkable::<Fmi2>("fmi2");
        walkable::<Fmi3>("fmi3");
    }

    #[test]
    fn state_handles_are_never_null_aligned_and_differ_between_fronts() {
        let handles = [Fmi2::next_state_handle(), Fmi3::next_state_handle()];
        assert!(
            handles.iter().all(|&h| h != 0 && h % 8 == 0),
            "{handles:x?}"
        );
        assert_ne!(handles[0], handles[1]);
        assert_ne!(Fmi2::next_state_handle(), handles[0], "never reused");
    }

    #[test]
    fn a_restored_state_puts_the_instance_in_the_mode_of_its_phase() {
        use crate::fmi2::instance::Mode::*;
        let after =
            |current, phase, terminated| mode_after_restore::<Fmi2>(current, phase, terminated);
        assert_eq!(after(Instantiated, Phase::Configuring, false), Instantiated);
        assert_eq!(
            after(Terminated, Phase::Configuring, false),
            InitializationMode
        );
        assert_eq!(after(Instantiated, Phase::Running, false), StepComplete);
        assert_eq!(after(StepComplete, Phase::Running, true), StepFailed);
    }
}

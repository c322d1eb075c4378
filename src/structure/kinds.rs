//! What a kind of structure knows of itself besides its operations
//! (`ChosenKind`: when a scene chooses it, the scene fields it owns),
//! and the `structure_kinds!` macro that turns the list of kinds (in
//! `structure/mod.rs`) into their modules, the `Structure` enum, its
//! `each!` dispatch, the choice of a kind and `BeamSpec`'s kind fields.

use crate::structure::beam::BeamSpec;
use crate::structure::ops::StructureOps;
use crate::structure::track_spec::TrackSpec;

/// The row of the scene's field table that a kind's own fields stand
/// before by default: the first after the beam's rows.
pub const KIND_FIELDS_BEFORE: &str = "body.name";

/// One field of `[beam]` a kind owns (declared in its line of the list,
/// an `Option` in `BeamSpec`): the scene's field table makes it a row
/// (`scene::fields`), left out by default, its value read and written
/// through `value` and `set`.
#[derive(Debug, Clone, Copy)]
pub struct KindField {
    /// Dotted path in the scene file (`beam.<field>`).
    pub path: &'static str,
    /// SI unit as FMI writes it, empty for none.
    pub unit: &'static str,
    /// Unit, meaning, rule in a few words (the annotated scene's comment).
    pub note: &'static str,
    /// What it means as an FMU parameter; empty: not a parameter.
    pub doc: &'static str,
    /// The rule the value must satisfy on its own.
    pub rule: KindRule,
    /// The value in a spec, None where left out.
    pub value: fn(&BeamSpec) -> Option<f64>,
    /// Write the value into a spec.
    pub set: fn(&mut BeamSpec, f64),
}

/// The rule of one kind field's value on its own (the field table's rules
/// that apply to an optional physical number).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KindRule {
    /// Finite and > 0.
    Positive,
    /// Finite and >= 0.
    NonNegative,
}

/// What a kind of structure knows of itself, besides its operations.
pub(in crate::structure) trait ChosenKind: StructureOps + Sized {
    /// Its fields of `[beam]` (declared in its line of the list) as rows
    /// of the scene's field table, and the row they stand before.
    const FIELDS: &'static [KindField] = &[];
    const FIELDS_BEFORE: &'static str = KIND_FIELDS_BEFORE;

    /// This kind, built, when a (validated) scene's beam and track choose
    /// it; None where they do not. The kinds are asked in the list's
    /// order; when none answers the structure is the Hermite mesh.
    fn chosen(_spec: &BeamSpec, _track: &TrackSpec) -> Option<Result<Self, String>> {
        None
    }
}

/// The type a variant of `Structure` holds: the kind, or the kind boxed
/// (`in Box` in its line) where it is much larger than the others.
macro_rules! kind_payload {
    (Box $kind:ty) => { Box<$kind> };
    ($kind:ty) => { $kind };
}

/// The list of structure kinds, each line a variant of `Structure`, the
/// kind's module and type (`in Box` to hold it boxed), and the fields of
/// `[beam]` it owns (`fields { .. }`, each an `Option` in `BeamSpec`, after
/// the common ones). From it come the `pub mod` of each kind's file, the
/// enum, `each!`, `Structure::chosen_kind`, `kind_fields` and (through
/// `with_kind_fields!`, which `beam/spec.rs` calls) `BeamSpec`.
macro_rules! structure_kinds {
    (@with ($d:tt) $(
        $(#[$attr:meta])* $variant:ident => $module:ident :: $kind:ident $(in $boxed:ident)?
        $(, fields { $($(#[$fattr:meta])* $field:ident: $fty:ty),* $(,)? })?
    ;)*) => {
        /// Calls `$callback! { field: type, .. }` with every kind's fields
        /// of `[beam]`, in the list's order (`BeamSpec`'s tail).
        macro_rules! with_kind_fields {
            ($d callback:ident) => {
                $d callback! { $($($($(#[$fattr])* $field: $fty,)*)?)* }
            };
        }

        $(pub mod $module;)*

        /// The flexible structure under the vehicles: one variant per kind.
        pub enum Structure {
            $($(#[$attr])* $variant(kind_payload!($($boxed)? $module::$kind)),)*
        }

        /// One expression per kind: `each!(self, b => b.f(..))`, `b` bound
        /// to the kind's implementation of `StructureOps`.
        macro_rules! each {
            ($d value:expr, $d b:ident => $d e:expr) => {
                match $d value {
                    $(Structure::$variant($d b) => $d e,)*
                }
            };
        }

        impl Structure {
            /// The first kind in the list's order that a (validated)
            /// scene's beam and track choose, built; None: none does.
            fn chosen_kind(
                spec: &beam::BeamSpec,
                track: &track_spec::TrackSpec,
            ) -> Option<Result<Structure, String>> {
                use kinds::ChosenKind;
                $(if let Some(kind) = <$module::$kind>::chosen(spec, track) {
                    return Some(kind.map(|k| Structure::$variant(k.into())));
                })*
                None
            }
        }

        /// Each kind's fields of `[beam]` as rows of the scene's field
        /// table, with the row they stand before, in the list's order.
        pub fn kind_fields() -> [(&'static str, &'static [kinds::KindField]); [$(stringify!($variant)),*].len()] {
            use kinds::ChosenKind;
            [$((<$module::$kind>::FIELDS_BEFORE, <$module::$kind>::FIELDS)),*]
        }
    };
    ($($list:tt)*) => {
        structure_kinds! { @with ($) $($list)* }
    };
}

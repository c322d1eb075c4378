//! `BodySpec`, one vehicle of a scene (`[body]`, each `[[vehicles]]`): the
//! fields every kind has, written here, and the fields each preset owns,
//! written in its line of `presets!` and placed by `body_spec!` (so a new
//! preset's block is its file and its line, never a field added here).

/// The struct of `[body]`: the common fields in the file's order, the
/// presets' flat fields after `mass` (`$head`) and their blocks after
/// `force_y` (`$tail`), each optional (left out: `None`). Called once, by
/// `presets!`.
macro_rules! body_spec {
    (
        head { $($(#[$hattr:meta])* $hfield:ident: $hty:ty,)* }
        tail { $($(#[$tattr:meta])* $tfield:ident: $tty:ty,)* }
    ) => {
        /// The vehicle (or moving force): its kind, mass, start and loads.
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct BodySpec {
            /// Prefix of the body's variables (`wheel.x`, `glider.x`, ...).
            pub name: String,
            pub kind: BodyKind,
            /// Mass m (kg).
            pub mass: f64,
            $(
                $(#[$hattr])*
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $hfield: Option<$hty>,
            )*
            /// Abscissa of the contact point at t = 0 (m).
            #[serde(default)]
            pub initial_position: f64,
            /// Initial travel speed (m/s), positive to the right.
            pub initial_speed: f64,
            /// Hold the body's horizontal speed (m/s): a number, or a table of
            /// (time s, speed m/s) rows, linear between rows and held beyond them;
            /// tractive forces computed each step hold it on every body of the
            /// vehicle (any kind but a moving force).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub prescribed_speed: Option<SpeedSpec>,
            /// Constant force on the body's centre, x component (N).
            #[serde(default)]
            pub force_x: f64,
            /// Constant force on the body's centre, y component (N); the paper's
            /// scenes use -600 kN.
            #[serde(default)]
            pub force_y: f64,
            $(
                $(#[$tattr])*
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $tfield: Option<$tty>,
            )*
            /// Newton's coefficient of restitution e ∈ [0, 1] of the vehicle's
            /// contacts at a landing (0: plastic, 1: elastic).
            #[serde(default, skip_serializing_if = "body_spec::is_zero")]
            pub restitution: f64,
            /// Height (m) of the whole vehicle above its place on the track at
            /// t = 0: its contacts start open and it falls (needs `start = "rest"`).
            #[serde(default, skip_serializing_if = "body_spec::is_zero")]
            pub initial_height: f64,
            /// How the vehicle's contact bodies meet the track: Lee's rigid
            /// contact when left out, or a compliant law (`contact_law`).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub contact_law: Option<ContactLawSpec>,
        }

        impl BodySpec {
            /// A vehicle of `kind` with every optional field left out (no
            /// block, no load, no law, at the origin, at rest).
            pub fn bare(name: &str, kind: BodyKind, mass: f64) -> BodySpec {
                BodySpec {
                    name: name.to_string(),
                    kind,
                    mass,
                    $($hfield: None,)*
                    initial_position: 0.0,
                    initial_speed: 0.0,
                    prescribed_speed: None,
                    force_x: 0.0,
                    force_y: 0.0,
                    $($tfield: None,)*
                    restitution: 0.0,
                    initial_height: 0.0,
                    contact_law: None,
                }
            }
        }
    };
}

pub(super) fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

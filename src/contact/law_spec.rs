//! The scene's side of the contact laws, generated from their one list
//! (`contact_laws!` in `law.rs`): the `[body.contact_law]` table
//! (`ContactLawSpec`, each law's fields), the laws' names, the presets,
//! how a preset's values sit under the scene's own, and the rows the
//! scene's field table shows for each field.

use crate::numbers::{MAX_MAGNITUDE, MIN_MAGNITUDE};

/// A broken rule: the field (under `contact_law`), its value, the rule.
pub type LawProblem = (&'static str, String, String);

/// One field of `[body.contact_law]` as the scene's field table shows it:
/// its path, its unit and its note (what, unit, rule in a few words).
pub type LawRow = (&'static str, &'static str, &'static str);

/// The list of contact laws, each line its name in a scene (`law = ".."`),
/// the function that checks its fields and resolves it, its presets (a
/// name and the values it gives) and its own fields, each with its unit
/// and note. The first law is the default. Called once, in `law.rs`.
macro_rules! contact_laws {
    (
        law_note: $law_note:literal,
        preset_note: $preset_note:literal,
        $(
            $name:literal => $resolve:path,
            presets { $($preset:literal { $($pfield:ident: $pvalue:expr),* $(,)? })* },
            fields { $($(#[$fattr:meta])* $field:ident [$unit:literal, $note:literal]),* $(,)? };
        )*
    ) => {
        /// The scene's choice of contact law for one vehicle's contact bodies.
        #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct ContactLawSpec {
            /// The law's name (`LAW_NAMES`), the first one if left out.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub law: Option<String>,
            /// A preset's name (`PRESETS`): its law and values, under the
            /// scene's own.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub preset: Option<String>,
            $($(
                $(#[$fattr])*
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $field: Option<f64>,
            )*)*
        }

        /// The laws' names, the default first.
        pub const LAW_NAMES: &[&str] = &[$($name),*];

        /// The presets' names.
        pub const PRESETS: &[&str] = &[$($($preset,)*)*];

        /// The rows of the scene's field table for `[body.contact_law]`.
        pub const LAW_ROWS: &[$crate::contact::law_spec::LawRow] = &[
            ("body.contact_law.law", "", $law_note),
            ("body.contact_law.preset", "", $preset_note),
            $($((concat!("body.contact_law.", stringify!($field)), $unit, $note),)*)*
        ];

        impl ContactLawSpec {
            /// The preset of this name: its law and its values.
            fn preset_named(name: &str) -> Option<ContactLawSpec> {
                match name {
                    $($($preset => Some(ContactLawSpec {
                        law: Some($name.into()),
                        $($pfield: Some($pvalue),)*
                        ..ContactLawSpec::default()
                    }),)*)*
                    _ => None,
                }
            }

            /// The scene's own values over `under`'s (a preset's).
            fn over(&self, under: ContactLawSpec) -> ContactLawSpec {
                ContactLawSpec {
                    law: self.law.clone().or(under.law),
                    preset: under.preset,
                    $($($field: self.$field.or(under.$field),)*)*
                }
            }

            /// The law with the preset's values under the scene's own.
            fn with_preset(&self) -> Result<ContactLawSpec, LawProblem> {
                let under = match self.preset.as_deref() {
                    None => ContactLawSpec::default(),
                    Some(name) => ContactLawSpec::preset_named(name).ok_or_else(|| {
                        let rule = format!("must be one of {}", PRESETS.join(", "));
                        ("preset", format!("{name:?}"), rule)
                    })?,
                };
                Ok(self.over(under))
            }

            /// The law the scene asks for, or the first rule it breaks.
            pub fn resolve(&self) -> Result<ResolvedLaw, LawProblem> {
                let spec = self.with_preset()?;
                match spec.law.as_deref().unwrap_or(LAW_NAMES[0]) {
                    $($name => $resolve(&spec),)*
                    other => Err((
                        "law",
                        format!("{other:?}"),
                        format!("must be {}", $crate::contact::law_spec::alternatives(LAW_NAMES)),
                    )),
                }
            }
        }
    };
}

/// `a, b or c`.
pub fn alternatives(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => one.to_string(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

/// `value` if it is a finite positive real within the scene's magnitudes.
pub fn positive(field: &'static str, value: f64) -> Result<f64, LawProblem> {
    let (low, high) = (MIN_MAGNITUDE, MAX_MAGNITUDE);
    if value.is_finite() && (low..=high).contains(&value) {
        Ok(value)
    } else {
        Err((
            field,
            value.to_string(),
            format!("must be a real in [{low:e}, {high:e}]"),
        ))
    }
}

/// `value`, or the law's refusal naming `field` as missing by `rule`.
pub fn needed(field: &'static str, value: Option<f64>, rule: &str) -> Result<f64, LawProblem> {
    value.ok_or((field, "missing".to_string(), rule.to_string()))
}

#[cfg(test)]
mod tests {
    use super::super::law::{ContactLawSpec, ResolvedLaw, LAW_ROWS, PRESETS};
    use super::*;

    #[test]
    fn every_preset_resolves_to_a_compliant_law_of_the_list() {
        for preset in PRESETS {
            let spec = ContactLawSpec {
                preset: Some(preset.to_string()),
                ..ContactLawSpec::default()
            };
            let law = spec.resolve().unwrap_or_else(|e| panic!("{preset}: {e:?}"));
            assert_ne!(law, ResolvedLaw::Rigid, "{preset}");
        }
        assert_eq!(ContactLawSpec::default().resolve(), Ok(ResolvedLaw::Rigid));
    }

    #[test]
    fn an_unknown_law_or_preset_is_refused_naming_every_one() {
        let unknown = |law: Option<&str>, preset: Option<&str>| {
            let spec = ContactLawSpec {
                law: law.map(str::to_string),
                preset: preset.map(str::to_string),
                ..ContactLawSpec::default()
            };
            spec.resolve().expect_err("refused")
        };
        let (field, value, rule) = unknown(Some("bump"), None);
        assert_eq!((field, value.as_str()), ("law", "\"bump\""));
        // The names come from the list, in the words the scenes have had.
        assert_eq!(rule, "must be rigid, hertz or ems");
        let (field, _, rule) = unknown(None, Some("rail"));
        assert_eq!(field, "preset");
        assert_eq!(rule, "must be one of wheel-rail, ems");
        assert_eq!(alternatives(&["a", "b", "c"]), "a, b or c");
        assert_eq!(alternatives(&["a"]), "a");
    }

    #[test]
    fn every_row_is_a_field_the_table_accepts() {
        for (path, _, _) in LAW_ROWS {
            let field = path.strip_prefix("body.contact_law.").unwrap();
            let value = if matches!(field, "law" | "preset") {
                "\"x\""
            } else {
                "1.0"
            };
            let parsed = toml::from_str::<ContactLawSpec>(&format!("{field} = {value}"));
            assert!(parsed.is_ok(), "{path}: {parsed:?}");
        }
        assert!(toml::from_str::<ContactLawSpec>("bump = 1.0").is_err());
    }
}

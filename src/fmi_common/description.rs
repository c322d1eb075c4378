//! The parts of modelDescription.xml that the FMI 2.0 and FMI 3.0 schemas
//! agree on (model identifier, units, log categories, default experiment,
//! the number format) and the way both derive their token.
//!
//! The GUID (FMI 3.0: the instantiation token) is derived from the document
//! itself: the SHA-256 of the XML written with an empty token, formatted
//! like a UUID. Two FMUs that differ in anything their description says
//! never share it, and an identical rebuild keeps it. The initial unknowns'
//! dependencies are left out of the digest: they are measured from the rest
//! of the description (see `model::initial_dependencies`), and an instance,
//! which does not need them, checks its token without measuring them.

use crate::model::{ModelInfo, VariableTable};
use serde::Serialize;
use sha2::{Digest, Sha256};

/// Log categories the FMU declares (and filters on with
/// fmiXSetDebugLogging); the first one's description is completed with the
/// model's events (`log_categories`).
pub const LOG_CATEGORIES: &[(&str, &str)] = &[
    ("logEvents", "initialization; state save and restore"),
    ("logStatusWarning", "calls that returned fmi2Warning"),
    (
        "logStatusDiscard",
        "steps that returned fmi2Discard (exit, solver failure)",
    ),
    (
        "logStatusError",
        "calls that returned fmi2Error, with the reason",
    ),
    ("logStatusFatal", "internal faults (fmi2Fatal)"),
];

/// The model identifier for a model name: a C identifier.
pub fn model_identifier(model_name: &str) -> String {
    let mut id: String = model_name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if id.is_empty() || id.starts_with(|c: char| c.is_ascii_digit()) {
        id.insert_str(0, "m_");
    }
    id
}

/// Base-unit exponents (kg, m, s, rad) of the units the outputs may use.
fn base_unit(unit: &str) -> Option<BaseUnit> {
    let (kg, m, s, rad) = match unit {
        "m" => (0, 1, 0, 0),
        "kg" => (1, 0, 0, 0),
        "s" => (0, 0, 1, 0),
        "N" => (1, 1, -2, 0),
        "N.s" => (1, 1, -1, 0),
        "J" => (1, 2, -2, 0),
        "W" => (1, 2, -3, 0),
        "m/s" => (0, 1, -1, 0),
        "m/s2" => (0, 1, -2, 0),
        "rad" => (0, 0, 0, 1),
        "rad/s" => (0, 0, -1, 1),
        "rad/s2" => (0, 0, -2, 1),
        "kg/m" => (1, -1, 0, 0),
        "kg.m2" => (1, 2, 0, 0),
        "N.m2" => (1, 3, -2, 0),
        "N/m" => (1, 0, -2, 0),
        "N.m" => (1, 2, -2, 0),
        _ => return None,
    };
    let nz = |x: i32| (x != 0).then_some(x);
    Some(BaseUnit {
        kg: nz(kg),
        m: nz(m),
        s: nz(s),
        rad: nz(rad),
    })
}

#[derive(Serialize)]
pub struct Units {
    #[serde(rename = "Unit")]
    units: Vec<Unit>,
}

#[derive(Serialize)]
struct Unit {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "BaseUnit", skip_serializing_if = "Option::is_none")]
    base: Option<BaseUnit>,
    #[serde(rename = "DisplayUnit", skip_serializing_if = "Vec::is_empty")]
    display: Vec<DisplayUnitElement>,
}

#[derive(Serialize)]
struct DisplayUnitElement {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@factor")]
    factor: f64,
}

#[derive(Serialize)]
struct BaseUnit {
    #[serde(rename = "@kg", skip_serializing_if = "Option::is_none")]
    kg: Option<i32>,
    #[serde(rename = "@m", skip_serializing_if = "Option::is_none")]
    m: Option<i32>,
    #[serde(rename = "@s", skip_serializing_if = "Option::is_none")]
    s: Option<i32>,
    #[serde(rename = "@rad", skip_serializing_if = "Option::is_none")]
    rad: Option<i32>,
}

#[derive(Serialize)]
pub struct LogCategories {
    #[serde(rename = "Category")]
    categories: Vec<Category>,
}

#[derive(Serialize)]
struct Category {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@description")]
    description: String,
}

#[derive(Serialize)]
pub struct DefaultExperiment {
    #[serde(rename = "@startTime")]
    start_time: f64,
    #[serde(rename = "@stopTime")]
    stop_time: f64,
    #[serde(rename = "@stepSize")]
    step_size: f64,
}

/// A real number as an attribute: the shorter of the plain and the exponent
/// form (both read back exactly): `5e-324`, not 324 decimals.
pub fn real_text(x: f64) -> String {
    let (plain, exp) = (format!("{x}"), format!("{x:e}"));
    if exp.len() < plain.len() {
        exp
    } else {
        plain
    }
}

/// The units of `table`'s variables, with their base units and display
/// units.
pub fn units(table: &VariableTable) -> Units {
    Units {
        units: table
            .units()
            .into_iter()
            .map(|(u, display)| Unit {
                name: u.to_string(),
                base: base_unit(u),
                display: display
                    .into_iter()
                    .map(|d| DisplayUnitElement {
                        name: d.name,
                        factor: d.factor,
                    })
                    .collect(),
            })
            .collect(),
    }
}

/// The declared log categories; `logEvents` names the model's events
/// (`ModelInfo::events`) beside the instance's own.
pub fn log_categories(info: &ModelInfo) -> LogCategories {
    let events = format!("initialization; {}; state save and restore", info.events);
    LogCategories {
        categories: LOG_CATEGORIES
            .iter()
            .map(|&(name, description)| Category {
                name,
                description: match name {
                    "logEvents" => events.clone(),
                    _ => description.to_string(),
                },
            })
            .collect(),
    }
}

/// The model's default experiment: from 0 to its stop time in its steps.
pub fn default_experiment(info: &ModelInfo) -> DefaultExperiment {
    DefaultExperiment {
        start_time: 0.0,
        stop_time: info.stop_time,
        step_size: info.step_size,
    }
}

/// A token from a description written without it: its SHA-256, formatted
/// like a UUID.
fn digest_token(unsigned: &str) -> String {
    let digest = Sha256::digest(unsigned.as_bytes());
    let h: String = digest[..16].iter().map(|b| format!("{b:02x}")).collect();
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &h[0..8],
        &h[8..12],
        &h[12..16],
        &h[16..20],
        &h[20..32]
    )
}

/// `doc` (written without its token and without the initial unknowns'
/// dependencies) signed: `finish` puts in the token derived from it and the
/// dependencies; the XML of the finished document and the token.
pub fn signed<Doc: Serialize>(
    mut doc: Doc,
    finish: impl FnOnce(&mut Doc, &str),
) -> (String, String) {
    let token = digest_token(&to_xml(&doc));
    finish(&mut doc, &token);
    (to_xml(&doc), token)
}

fn to_xml<Doc: Serialize>(doc: &Doc) -> String {
    let mut body = String::new();
    let mut ser = quick_xml::se::Serializer::new(&mut body);
    ser.indent(' ', 2);
    doc.serialize(ser)
        .expect("the model description is plain data and always serializes");
    format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{body}\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_are_c_identifiers() {
        assert_eq!(model_identifier("lee1994-wheel-10"), "lee1994_wheel_10");
        assert_eq!(model_identifier("3d beam"), "m_3d_beam");
        assert_eq!(model_identifier(""), "m_");
    }

    #[test]
    fn reals_take_the_shorter_exact_form() {
        for x in [5e-324, 0.1, 1e300, -2.5, 24.0, 1.0 / 3.0] {
            let t = real_text(x);
            assert_eq!(t.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{t}");
            assert!(t.len() <= format!("{x}").len() && t.len() <= format!("{x:e}").len());
        }
        assert_eq!(real_text(5e-324), "5e-324");
        assert_eq!(real_text(0.001), "1e-3");
        assert_eq!(real_text(24.0), "24");
    }
}

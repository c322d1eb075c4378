//! FMI 3.0 modelDescription.xml, generated from the same variable table as
//! the FMI 2.0 one (`crate::fmi2::model_description`), in the element order
//! of the FMI 3.0 schema. Units, log categories, the default experiment,
//! the number format and the token's derivation are shared
//! (`fmi_common::description`: the two schemas agree on them).
//!
//! Differences from 2.0: typed variable elements (`Float64`, `Int32`,
//! `Boolean`), the independent variable `time` (FMI 3.0 wants exactly one;
//! its value reference is the first after the table's), dependencies given
//! as value references, and the instantiation token in place of the GUID
//! (derived the same way: the SHA-256 of the XML written without it).

use crate::fmi_common::description::{
    default_experiment, log_categories, model_identifier, real_text, signed, units,
    DefaultExperiment, LogCategories, Units,
};
use crate::model::{Causality, ModelInfo, Value, VarType, Variable, VariableTable};
use serde::Serialize;

/// The value reference of the independent variable `time`: the first one
/// after the table's (which are numbered from 0).
pub fn time_value_reference(table: &VariableTable) -> u32 {
    table.variables().len() as u32
}

#[derive(Serialize)]
#[serde(rename = "fmiModelDescription")]
struct Document<'a> {
    #[serde(rename = "@fmiVersion")]
    fmi_version: &'a str,
    #[serde(rename = "@modelName")]
    model_name: &'a str,
    #[serde(rename = "@instantiationToken")]
    token: String,
    #[serde(rename = "@description", skip_serializing_if = "str::is_empty")]
    description: &'a str,
    #[serde(rename = "@version")]
    version: &'a str,
    #[serde(rename = "@generationTool")]
    generation_tool: String,
    #[serde(rename = "@variableNamingConvention")]
    naming: &'a str,
    #[serde(rename = "CoSimulation")]
    co_simulation: CoSimulation,
    #[serde(rename = "UnitDefinitions")]
    units: Units,
    #[serde(rename = "LogCategories")]
    log_categories: LogCategories,
    #[serde(rename = "DefaultExperiment")]
    default_experiment: DefaultExperiment,
    #[serde(rename = "ModelVariables")]
    variables: ModelVariables,
    #[serde(rename = "ModelStructure")]
    structure: ModelStructure,
}

#[derive(Serialize)]
struct CoSimulation {
    #[serde(rename = "@modelIdentifier")]
    model_identifier: String,
    #[serde(rename = "@canGetAndSetFMUState")]
    get_set_state: bool,
    #[serde(rename = "@canSerializeFMUState")]
    serialize_state: bool,
    #[serde(rename = "@canHandleVariableCommunicationStepSize")]
    variable_step: bool,
    #[serde(rename = "@hasEventMode")]
    has_event_mode: bool,
    #[serde(rename = "@providesIntermediateUpdate")]
    intermediate_update: bool,
    #[serde(rename = "@mightReturnEarlyFromDoStep")]
    might_return_early: bool,
}

#[derive(Serialize)]
struct ModelVariables {
    #[serde(rename = "$value")]
    variables: Vec<TypedVariable>,
}

/// One variable element: its type is the element's name (the variant);
/// the attributes a type does not have are absent.
#[derive(Serialize)]
struct Attributes {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "@valueReference")]
    value_reference: u32,
    #[serde(rename = "@description", skip_serializing_if = "String::is_empty")]
    description: String,
    #[serde(rename = "@causality")]
    causality: &'static str,
    #[serde(rename = "@variability")]
    variability: &'static str,
    #[serde(rename = "@initial", skip_serializing_if = "Option::is_none")]
    initial: Option<&'static str>,
    #[serde(rename = "@unit", skip_serializing_if = "Option::is_none")]
    unit: Option<String>,
    #[serde(rename = "@displayUnit", skip_serializing_if = "Option::is_none")]
    display_unit: Option<&'static str>,
    #[serde(rename = "@min", skip_serializing_if = "Option::is_none")]
    min: Option<String>,
    #[serde(rename = "@max", skip_serializing_if = "Option::is_none")]
    max: Option<String>,
    #[serde(rename = "@nominal", skip_serializing_if = "Option::is_none")]
    nominal: Option<String>,
    #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
    start: Option<String>,
}

#[derive(Serialize)]
enum TypedVariable {
    Float64(Attributes),
    Int32(Attributes),
    Boolean(Attributes),
}

/// A value as an attribute (a Float64 as in the FMI 2.0 description).
fn text(v: Value) -> String {
    match v {
        Value::Real(x) => real_text(x),
        Value::Integer(n) => n.to_string(),
        Value::Boolean(b) => b.to_string(),
    }
}

#[derive(Serialize)]
struct ModelStructure {
    #[serde(rename = "Output")]
    outputs: Vec<Unknown>,
    #[serde(rename = "InitialUnknown")]
    initial_unknowns: Vec<Unknown>,
}

#[derive(Serialize)]
struct Unknown {
    #[serde(rename = "@valueReference")]
    value_reference: u32,
    /// Space-separated value references; empty: on none; absent: on all.
    #[serde(rename = "@dependencies", skip_serializing_if = "Option::is_none")]
    dependencies: Option<String>,
}

fn typed_variable(v: &Variable) -> TypedVariable {
    let real = v.ty == VarType::Real;
    let attributes = Attributes {
        name: v.name.clone(),
        value_reference: v.value_reference,
        description: v.description.clone(),
        causality: v.causality.as_str(),
        variability: v.variability.as_str(),
        initial: (v.causality == Causality::Parameter).then_some("exact"),
        unit: v.unit.clone().filter(|_| real),
        // A display unit is declared only with a unit to belong to.
        display_unit: v
            .display_unit
            .filter(|_| real && v.unit.is_some())
            .map(|d| d.name),
        min: v.min.map(text),
        max: v.max.map(text),
        nominal: v.nominal.filter(|_| real).map(|x| text(Value::Real(x))),
        start: v.start.map(text),
    };
    match v.ty {
        VarType::Real => TypedVariable::Float64(attributes),
        VarType::Integer => TypedVariable::Int32(attributes),
        VarType::Boolean => TypedVariable::Boolean(Attributes {
            min: None,
            max: None,
            ..attributes
        }),
    }
}

/// `time`: the independent variable.
fn time_variable(table: &VariableTable) -> TypedVariable {
    TypedVariable::Float64(Attributes {
        name: "time".into(),
        value_reference: time_value_reference(table),
        description: "simulation time".into(),
        causality: "independent",
        variability: "continuous",
        initial: None,
        unit: Some("s".into()),
        display_unit: None,
        min: None,
        max: None,
        nominal: None,
        start: None,
    })
}

fn references(vrs: Option<&[u32]>) -> Option<String> {
    vrs.map(|l| l.iter().map(u32::to_string).collect::<Vec<_>>().join(" "))
}

fn structure(table: &VariableTable, with_initial_dependencies: bool) -> ModelStructure {
    let outputs: Vec<&Variable> = table.outputs().collect();
    ModelStructure {
        outputs: outputs
            .iter()
            .map(|v| Unknown {
                value_reference: v.value_reference,
                dependencies: references(v.dependencies.as_deref()),
            })
            .collect(),
        initial_unknowns: outputs
            .iter()
            .map(|v| Unknown {
                value_reference: v.value_reference,
                dependencies: references(v.initial_dependencies.as_deref())
                    .filter(|_| with_initial_dependencies),
            })
            .collect(),
    }
}

/// The FMI 3.0 modelDescription.xml of the model `info` describes and its
/// variable table, with its instantiation token.
pub fn generate(info: &ModelInfo, table: &VariableTable) -> (String, String) {
    let mut variables: Vec<TypedVariable> = vec![time_variable(table)];
    variables.extend(table.variables().iter().map(typed_variable));
    let doc = Document {
        fmi_version: "3.0",
        model_name: &info.name,
        token: String::new(),
        description: &info.description,
        version: env!("CARGO_PKG_VERSION"),
        generation_tool: format!("guideway {}", env!("CARGO_PKG_VERSION")),
        naming: "structured",
        co_simulation: CoSimulation {
            model_identifier: model_identifier(&info.name),
            get_set_state: true,
            serialize_state: true,
            variable_step: info.variable_communication_steps,
            has_event_mode: false,
            intermediate_update: false,
            might_return_early: true,
        },
        units: units(table),
        log_categories: log_categories(info),
        default_experiment: default_experiment(info),
        variables: ModelVariables { variables },
        structure: structure(table, false),
    };
    signed(doc, |doc, token| {
        doc.token = token.to_string();
        doc.structure = structure(table, true);
    })
}

//! FMI 2.0's modelDescription.xml, generated from the variable table with
//! quick-xml and serde, in the element order of the FMI 2.0 schema: its
//! co-simulation capabilities, `ScalarVariable` elements and dependencies
//! as 1-based indices into ModelVariables. The parts both versions share
//! (units, log categories, default experiment, number format, the GUID
//! derived from the document) are `fmi_common::description`.

use crate::fmi_common::description::{
    default_experiment, log_categories, model_identifier, real_text, signed, units,
    DefaultExperiment, LogCategories, Units,
};
use crate::model::{Causality, ModelInfo, Value, VarType, VariableTable};
use serde::Serialize;

#[derive(Serialize)]
#[serde(rename = "fmiModelDescription")]
struct Document<'a> {
    #[serde(rename = "@fmiVersion")]
    fmi_version: &'a str,
    #[serde(rename = "@modelName")]
    model_name: &'a str,
    #[serde(rename = "@guid")]
    guid: String,
    #[serde(rename = "@description", skip_serializing_if = "str::is_empty")]
    description: &'a str,
    #[serde(rename = "@version")]
    version: &'a str,
    #[serde(rename = "@generationTool")]
    generation_tool: String,
    #[serde(rename = "@variableNamingConvention")]
    naming: &'a str,
    #[serde(rename = "@numberOfEventIndicators")]
    event_indicators: u32,
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
    #[serde(rename = "@needsExecutionTool")]
    needs_execution_tool: bool,
    #[serde(rename = "@canHandleVariableCommunicationStepSize")]
    variable_step: bool,
    #[serde(rename = "@canInterpolateInputs")]
    interpolate_inputs: bool,
    #[serde(rename = "@maxOutputDerivativeOrder")]
    max_output_derivative_order: u32,
    #[serde(rename = "@canRunAsynchronuously")]
    asynchronous: bool,
    #[serde(rename = "@canBeInstantiatedOnlyOncePerProcess")]
    once_per_process: bool,
    #[serde(rename = "@canNotUseMemoryManagementFunctions")]
    no_memory_management: bool,
    #[serde(rename = "@canGetAndSetFMUstate")]
    get_set_state: bool,
    #[serde(rename = "@canSerializeFMUstate")]
    serialize_state: bool,
    #[serde(rename = "@providesDirectionalDerivative")]
    directional_derivative: bool,
}

#[derive(Serialize)]
struct ModelVariables {
    #[serde(rename = "ScalarVariable")]
    variables: Vec<ScalarVariable>,
}

#[derive(Serialize)]
struct ScalarVariable {
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
    #[serde(rename = "$value")]
    ty: TypeElement,
}

#[derive(Serialize)]
enum TypeElement {
    Real {
        #[serde(rename = "@unit", skip_serializing_if = "Option::is_none")]
        unit: Option<String>,
        #[serde(rename = "@displayUnit", skip_serializing_if = "Option::is_none")]
        display_unit: Option<&'static str>,
        #[serde(rename = "@min", skip_serializing_if = "Option::is_none")]
        min: Option<Real>,
        #[serde(rename = "@max", skip_serializing_if = "Option::is_none")]
        max: Option<Real>,
        #[serde(rename = "@nominal", skip_serializing_if = "Option::is_none")]
        nominal: Option<Real>,
        #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
        start: Option<Real>,
    },
    Integer {
        #[serde(rename = "@min", skip_serializing_if = "Option::is_none")]
        min: Option<i32>,
        #[serde(rename = "@max", skip_serializing_if = "Option::is_none")]
        max: Option<i32>,
        #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
        start: Option<i32>,
    },
    Boolean {
        #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
        start: Option<bool>,
    },
}

#[derive(Serialize)]
struct ModelStructure {
    #[serde(rename = "Outputs")]
    outputs: Unknowns,
    #[serde(rename = "InitialUnknowns")]
    initial_unknowns: Unknowns,
}

#[derive(Serialize)]
struct Unknowns {
    #[serde(rename = "Unknown")]
    unknowns: Vec<Unknown>,
}

#[derive(Serialize)]
struct Unknown {
    #[serde(rename = "@index")]
    index: usize,
    /// Space-separated indices; empty: depends on none; absent: on all.
    #[serde(rename = "@dependencies", skip_serializing_if = "Option::is_none")]
    dependencies: Option<String>,
}

/// A Real attribute (`description::real_text`).
struct Real(f64);

impl Serialize for Real {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&real_text(self.0))
    }
}

fn real(v: Option<Value>) -> Option<Real> {
    match v {
        Some(Value::Real(x)) => Some(Real(x)),
        _ => None,
    }
}

fn integer(v: Option<Value>) -> Option<i32> {
    match v {
        Some(Value::Integer(n)) => Some(n),
        _ => None,
    }
}

fn scalar_variable(v: &crate::model::Variable) -> ScalarVariable {
    let ty = match v.ty {
        VarType::Real => TypeElement::Real {
            unit: v.unit.clone(),
            // A display unit is declared only with a unit to belong to.
            display_unit: v.display_unit.filter(|_| v.unit.is_some()).map(|d| d.name),
            min: real(v.min),
            max: real(v.max),
            nominal: v.nominal.map(Real),
            start: real(v.start),
        },
        VarType::Integer => TypeElement::Integer {
            min: integer(v.min),
            max: integer(v.max),
            start: integer(v.start),
        },
        VarType::Boolean => TypeElement::Boolean {
            start: match v.start {
                Some(Value::Boolean(b)) => Some(b),
                _ => None,
            },
        },
    };
    ScalarVariable {
        name: v.name.clone(),
        value_reference: v.value_reference,
        description: v.description.clone(),
        causality: v.causality.as_str(),
        variability: v.variability.as_str(),
        initial: (v.causality == Causality::Parameter).then_some("exact"),
        ty,
    }
}

/// The `dependencies` attribute: value references as 1-based indices into
/// ModelVariables.
fn indices(table: &VariableTable, vrs: Option<&[u32]>) -> Option<String> {
    let vrs = vrs?;
    let index = |vr: &u32| {
        table
            .variables()
            .iter()
            .position(|v| v.value_reference == *vr)
            .map(|i| (i + 1).to_string())
    };
    // An unknown reference would make the attribute a lie: declare nothing.
    let list: Option<Vec<String>> = vrs.iter().map(index).collect();
    list.map(|l| l.join(" "))
}

/// Outputs and initial unknowns, with their dependencies.
fn structure(table: &VariableTable, with_initial_dependencies: bool) -> ModelStructure {
    let outputs: Vec<(usize, &crate::model::Variable)> = table
        .variables()
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == Causality::Output)
        .collect();
    let unknowns = |deps: &dyn Fn(&crate::model::Variable) -> Option<String>| Unknowns {
        unknowns: outputs
            .iter()
            .map(|&(i, v)| Unknown {
                index: i + 1,
                dependencies: deps(v),
            })
            .collect(),
    };
    ModelStructure {
        outputs: unknowns(&|v| indices(table, v.dependencies.as_deref())),
        initial_unknowns: unknowns(&|v| {
            if with_initial_dependencies {
                indices(table, v.initial_dependencies.as_deref())
            } else {
                None
            }
        }),
    }
}

/// The modelDescription.xml of the model `info` describes and its variable
/// table, with its GUID.
pub fn generate(info: &ModelInfo, table: &VariableTable) -> (String, String) {
    let doc = Document {
        fmi_version: "2.0",
        model_name: &info.name,
        guid: String::new(),
        description: &info.description,
        version: env!("CARGO_PKG_VERSION"),
        generation_tool: format!("guideway {}", env!("CARGO_PKG_VERSION")),
        naming: "structured",
        event_indicators: 0,
        co_simulation: CoSimulation {
            model_identifier: model_identifier(&info.name),
            needs_execution_tool: false,
            variable_step: info.variable_communication_steps,
            interpolate_inputs: true,
            max_output_derivative_order: 0,
            asynchronous: false,
            once_per_process: false,
            no_memory_management: true,
            get_set_state: true,
            serialize_state: true,
            directional_derivative: false,
        },
        units: units(table),
        log_categories: log_categories(info),
        default_experiment: default_experiment(info),
        variables: ModelVariables {
            variables: table.variables().iter().map(scalar_variable).collect(),
        },
        structure: structure(table, false),
    };
    signed(doc, |doc, guid| {
        doc.guid = guid.to_string();
        doc.structure = structure(table, true);
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{fake::FakeDynamics, Dynamics, FmuModel, Model};
    use crate::scene::{BodyKind, Scene};
    use crate::simulation::Steppable;

    fn info(scene: &Scene) -> ModelInfo {
        Model::<FakeDynamics>::new(scene.clone()).unwrap().info()
    }

    fn xml(scene: &Scene) -> (String, String) {
        let sim = FakeDynamics::build(scene).unwrap();
        generate(&info(scene), &VariableTable::new(scene, sim.outputs()))
    }

    #[test]
    fn guid_is_deterministic_and_depends_on_content() {
        let a = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        let (xa, ga) = xml(&a);
        assert_eq!(xml(&a).1, ga);
        assert!(xa.contains(&format!("guid=\"{ga}\"")));
        let mut b = a.clone();
        b.beam.length = 25.0;
        assert_ne!(xml(&b).1, ga);
    }

    #[test]
    fn dependencies_do_not_change_the_guid_and_reference_variables() {
        let scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
        let sim = FakeDynamics::build(&scene).unwrap();
        let mut table = VariableTable::new(&scene, sim.outputs());
        let (plain, guid) = generate(&info(&scene), &table);
        let n = table.outputs().count();
        table.set_initial_dependencies(&vec![vec![0, 2]; n]);
        let (with, guid2) = generate(&info(&scene), &table);
        assert_eq!(guid, guid2);
        assert!(!plain.contains("dependencies=\"1 3\""));
        assert_eq!(with.matches("dependencies=\"1 3\"").count(), n);
        // Outputs section: no direct dependency
        let outputs = &with[with.find("<Outputs>").unwrap()..with.find("</Outputs>").unwrap()];
        assert_eq!(outputs.matches("dependencies=\"\"").count(), n);
        assert!(with.contains("<DisplayUnit name=\"kN\" factor=\"0.001\"/>"));
        assert!(with.contains("min=\"5e-324\""));
    }

    #[test]
    fn elements_in_schema_order() {
        let (x, _) = xml(&Scene::lee1994(BodyKind::Glider, 10.0, 0.0025));
        let pos = |s: &str| x.find(s).unwrap_or_else(|| panic!("{s} missing in\n{x}"));
        let order = [
            "<fmiModelDescription",
            "<CoSimulation",
            "<UnitDefinitions",
            "<LogCategories",
            "<DefaultExperiment",
            "<ModelVariables",
            "<ModelStructure",
            "<Outputs",
            "<InitialUnknowns",
        ];
        for w in order.windows(2) {
            assert!(pos(w[0]) < pos(w[1]), "{} before {}", w[0], w[1]);
        }
        assert!(x.contains("modelIdentifier=\"lee1994_glider_10\""));
        assert!(x.contains("canNotUseMemoryManagementFunctions=\"true\""));
        assert!(!x.contains("radius"));
    }
}

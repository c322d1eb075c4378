//! An SSP system (`.ssp`): the guideway FMU and a vehicle FMU wired by
//! connections from outputs to inputs, in one archive, as SSP 1.0 (the
//! default) or 2.0, either holding FMI 2.0 or 3.0 FMUs.
//!
//! Layout: `SystemStructure.ssd`, `resources/guideway.fmu`,
//! `resources/vehicle.fmu`. Every connection is checked against the two
//! model descriptions (the variables exist, an output feeds an input, both
//! 64-bit floating point: FMI 2.0 `Real`, FMI 3.0 `Float64`) before
//! anything is written (`check_connections`, run by `export` before the FMU
//! itself is written). The SSD carries a DefaultExperiment and the
//! fixed-step master settings OMSimulator needs to load a system (its
//! `SimulationInformation` annotation; other masters ignore it).

use std::collections::HashMap;
use std::io::{Read, Write};
use std::path::Path;
use zip::write::SimpleFileOptions;

/// The components of the system, in the order they appear.
pub const COMPONENTS: [&str; 2] = ["guideway", "vehicle"];

/// One connection `from` (an output) → `to` (an input), each
/// `component.variable`.
#[derive(Debug, Clone, PartialEq)]
pub struct Connection {
    pub from: (String, String),
    pub to: (String, String),
}

impl std::str::FromStr for Connection {
    type Err = String;
    /// `vehicle.force=guideway.wheel.force_y`
    fn from_str(s: &str) -> Result<Connection, String> {
        let end = |part: &str| -> Result<(String, String), String> {
            let (c, v) = part.trim().split_once('.').unwrap_or(("", ""));
            if !COMPONENTS.contains(&c) || v.is_empty() {
                return Err(format!(
                    "`{part}`: expected COMPONENT.VARIABLE with COMPONENT one of {COMPONENTS:?}"
                ));
            }
            Ok((c.to_string(), v.to_string()))
        };
        let (from, to) = s.split_once('=').ok_or_else(|| {
            format!("`{s}`: expected FROM=TO, e.g. vehicle.force=guideway.wheel.force_y")
        })?;
        Ok(Connection {
            from: end(from)?,
            to: end(to)?,
        })
    }
}

/// Which SSP standard a system follows. Both hold FMI 2.0 and 3.0 FMUs
/// here; 1.0 is the default because every master tested here reads only
/// 1.0 (docs/fmu.md, scripts/tests/test_ssp2.py).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SspVersion {
    /// SSP 1.0 (2019).
    #[default]
    V1,
    /// SSP 2.0 (2024): `Float64` connectors for FMI 3.0 variables.
    V2,
}

impl SspVersion {
    /// `1` or `2`, as `--ssp-version` takes it.
    pub fn parse(text: &str) -> Option<SspVersion> {
        match text {
            "1" => Some(SspVersion::V1),
            "2" => Some(SspVersion::V2),
            _ => None,
        }
    }

    /// The SSD's `version` attribute.
    pub fn label(self) -> &'static str {
        match self {
            SspVersion::V1 => "1.0",
            SspVersion::V2 => "2.0",
        }
    }

    /// The connector type of a variable of `fmu`: SSP 1.0 has one
    /// floating-point type, `Real` (an FMI 3.0 `Float64` in it is typed so);
    /// SSP 2.0 types each by its FMU, `Real` (FMI 2.0) or `Float64` (FMI 3.0).
    fn connector_type(self, fmu: &Interface) -> &'static str {
        match self {
            SspVersion::V1 => "Real",
            SspVersion::V2 => fmu.float_type(),
        }
    }
}

/// One variable of an FMU: its causality and type, as the model
/// description names them (`Real` in FMI 2.0, `Float64` in FMI 3.0).
#[derive(Debug, Clone, PartialEq)]
struct Variable {
    causality: String,
    ty: String,
}

/// What a connection needs of one FMU's model description.
#[derive(Debug, Clone, PartialEq)]
struct Interface {
    /// The `fmiVersion` attribute: "2.0", "3.0", ...
    fmi_version: String,
    variables: HashMap<String, Variable>,
}

impl Interface {
    /// The FMU's name of a 64-bit floating-point variable.
    fn float_type(&self) -> &'static str {
        if self.fmi_version.starts_with('3') {
            "Float64"
        } else {
            "Real"
        }
    }
}

/// The model description inside an FMU archive.
fn model_description(fmu: &[u8]) -> Result<String, String> {
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(fmu)).map_err(|e| e.to_string())?;
    let mut xml = String::new();
    zip.by_name("modelDescription.xml")
        .map_err(|e| format!("no modelDescription.xml: {e}"))?
        .read_to_string(&mut xml)
        .map_err(|e| e.to_string())?;
    Ok(xml)
}

/// The value of attribute `name` of element `e`.
fn attribute(e: &quick_xml::events::BytesStart, name: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.as_ref() == name)
        .and_then(|a| {
            a.normalized_value(quick_xml::XmlVersion::Implicit1_0)
                .ok()
                .map(|v| v.into_owned())
        })
}

/// The name and causality of a variable element (one with a name and a
/// value reference).
fn named_variable(e: &quick_xml::events::BytesStart) -> Option<(String, String)> {
    let name = attribute(e, "name")?;
    attribute(e, "valueReference")?;
    let causality = attribute(e, "causality").unwrap_or_else(|| "local".into());
    Some((name, causality))
}

/// The FMI version and variables a model description declares. A variable
/// is an element of `ModelVariables` with a name and a value reference: an
/// FMI 2.0 `ScalarVariable` (typed by its first child) or an FMI 3.0
/// `Float64`, `Int32`, ... (typed by its own name). FMI 3.0's `Alias` (no
/// value reference) and `Dimension` (no name) are not variables.
fn interface(xml: &str) -> Result<Interface, String> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(xml);
    let (mut fmi_version, mut variables) = (String::new(), HashMap::new());
    let (mut in_variables, mut scalar): (bool, Option<(String, String)>) = (false, None);
    loop {
        let (e, starts) = match reader
            .read_event()
            .map_err(|e| format!("modelDescription.xml: {e}"))?
        {
            Event::Eof => break,
            Event::Start(e) => (e, true),
            Event::Empty(e) => (e, false),
            Event::End(e) if e.name().as_ref() == "ModelVariables" => {
                in_variables = false;
                continue;
            }
            _ => continue,
        };
        let element = e.name().as_ref().to_string();
        match element.as_str() {
            "fmiModelDescription" => fmi_version = attribute(&e, "fmiVersion").unwrap_or_default(),
            "ModelVariables" => in_variables = starts,
            _ if !in_variables => {}
            _ if scalar.is_some() => {
                let (name, causality) = scalar.take().unwrap_or_default();
                let ty = element;
                variables.insert(name, Variable { causality, ty });
            }
            _ => match named_variable(&e) {
                Some(named) if element == "ScalarVariable" => scalar = Some(named),
                Some((name, causality)) => {
                    let ty = element;
                    variables.insert(name, Variable { causality, ty });
                }
                None => {}
            },
        }
    }
    Ok(Interface {
        fmi_version,
        variables,
    })
}

/// Whether a variable type is a 64-bit float (what a connection carries).
fn is_float(ty: &str) -> bool {
    ty == "Real" || ty == "Float64"
}

/// Check `c` against the interfaces of the two FMUs; a refusal lists the
/// variables that would fit where the wrong one is.
fn check(c: &Connection, fmus: &HashMap<&str, Interface>) -> Result<(), String> {
    for ((component, name), want) in [(&c.from, "output"), (&c.to, "input")] {
        let fmu = &fmus[component.as_str()];
        let fitting = || fitting(component, fmu, want);
        let Some(Variable { causality, ty }) = fmu.variables.get(name) else {
            return Err(format!(
                "--connect {}: {component} has no variable `{name}`; {}",
                c,
                fitting()
            ));
        };
        if causality != want || !is_float(ty) {
            let float = fmu.float_type();
            return Err(format!(
                "--connect {c}: {component}.{name} is a {ty} {causality}; a connection goes from a {float} output to a {float} input; {}",
                fitting()
            ));
        }
    }
    Ok(())
}

/// "the Real outputs of vehicle: a, b, c" (sorted).
fn fitting(component: &str, fmu: &Interface, causality: &str) -> String {
    let mut names: Vec<&str> = (fmu.variables.iter())
        .filter(|(_, v)| v.causality == causality && is_float(&v.ty))
        .map(|(n, _)| n.as_str())
        .collect();
    names.sort_unstable();
    let float = fmu.float_type();
    if names.is_empty() {
        return format!("{component} has no {float} {causality}");
    }
    format!(
        "the {float} {causality}s of {component}: {}",
        names.join(", ")
    )
}

impl std::fmt::Display for Connection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (a, b) = (&self.from, &self.to);
        write!(f, "{}.{}={}.{}", a.0, a.1, b.0, b.1)
    }
}

/// What the SSD's DefaultExperiment and master settings say: the
/// guideway FMU's stop time and communication step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Experiment {
    pub stop_time: f64,
    pub step_size: f64,
}

/// A checked system, ready to write once the guideway FMU exists.
pub struct System {
    name: String,
    version: SspVersion,
    vehicle: Vec<u8>,
    wires: Vec<Wire>,
    experiment: Experiment,
}

/// A checked connection with the SSP connector type of each end (`Real`
/// for an FMI 2.0 variable, `Float64` for an FMI 3.0 one).
#[derive(Debug, Clone, PartialEq)]
struct Wire {
    connection: Connection,
    types: [&'static str; 2],
}

/// Why a system was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SystemError {
    /// A connection does not fit the two FMUs (a usage error).
    Connection(String),
    /// The vehicle FMU could not be read.
    Io(String),
}

/// Check `connections` against the guideway FMU's model description
/// `guideway_xml` (not yet written) and the vehicle FMU at `vehicle`, for a
/// system of SSP `version`.
pub fn check_connections(
    name: &str,
    version: SspVersion,
    guideway_xml: &str,
    vehicle: &Path,
    connections: &[Connection],
    experiment: Experiment,
) -> Result<System, SystemError> {
    let vehicle_bytes = crate::input_file::read_bounded(vehicle, crate::input_file::MAX_FMU_BYTES)
        .map_err(SystemError::Io)?;
    let vehicle_fmu = model_description(&vehicle_bytes)
        .and_then(|xml| interface(&xml))
        .map_err(|e| SystemError::Connection(format!("{}: {e}", vehicle.display())))?;
    let guideway_fmu = interface(guideway_xml).map_err(SystemError::Connection)?;
    let fmus = HashMap::from([("guideway", guideway_fmu), ("vehicle", vehicle_fmu)]);
    let mut wires = Vec::new();
    for c in connections {
        check(c, &fmus).map_err(SystemError::Connection)?;
        let end =
            |(component, _): &(String, String)| version.connector_type(&fmus[component.as_str()]);
        wires.push(Wire {
            types: [end(&c.from), end(&c.to)],
            connection: c.clone(),
        });
    }
    Ok(System {
        name: name.to_string(),
        version,
        vehicle: vehicle_bytes,
        wires,
        experiment,
    })
}

/// Escape an attribute value.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('"', "&quot;")
}

/// The components with the connectors their connections use.
fn elements(wires: &[Wire]) -> String {
    let mut elements = String::new();
    for component in COMPONENTS {
        let mut connectors = String::new();
        for Wire {
            connection: c,
            types,
        } in wires
        {
            let ends = [(&c.from, "output", types[0]), (&c.to, "input", types[1])];
            for ((comp, var), kind, ty) in ends {
                if comp == component {
                    connectors += &format!(
                        "          <ssd:Connector name=\"{}\" kind=\"{kind}\"><ssc:{ty}/></ssd:Connector>\n",
                        esc(var)
                    );
                }
            }
        }
        elements += &format!(
            "      <ssd:Component name=\"{component}\" type=\"application/x-fmu-sharedlibrary\" source=\"resources/{component}.fmu\">\n        <ssd:Connectors>\n{connectors}        </ssd:Connectors>\n      </ssd:Component>\n"
        );
    }
    elements
}

/// OMSimulator refuses a system without its master settings ("[NewSystem]
/// internal error"): a fixed-step master at the experiment's step.
fn oms_master(step_size: f64) -> String {
    format!(
        "    <ssd:Annotations>\n      <ssc:Annotation type=\"org.openmodelica\">\n        <oms:Annotations>\n          <oms:SimulationInformation>\n            <oms:FixedStepMaster description=\"oms-ma\" stepSize=\"{step_size}\" absoluteTolerance=\"1e-4\" relativeTolerance=\"1e-4\"/>\n          </oms:SimulationInformation>\n        </oms:Annotations>\n      </ssc:Annotation>\n    </ssd:Annotations>\n"
    )
}

/// OMSimulator reads its result settings from the DefaultExperiment's
/// annotation and warns that the file holds "wrong/deprecated content"
/// when the annotation is missing.
fn oms_results(name: &str) -> String {
    format!(
        "    <ssd:Annotations>\n      <ssc:Annotation type=\"org.openmodelica\">\n        <oms:Annotations>\n          <oms:SimulationInformation resultFile=\"{name}_res.mat\" loggingInterval=\"0\" bufferSize=\"10\"/>\n        </oms:Annotations>\n      </ssc:Annotation>\n    </ssd:Annotations>\n"
    )
}

/// The system's name: the scene's, as an identifier. SSP allows any
/// string, but OMSimulator names a model only by `[a-zA-Z][a-zA-Z0-9_]*`
/// and refuses the whole file otherwise ("is not a valid ident").
fn system_name(scene_name: &str) -> String {
    let id = crate::fmi_common::description::model_identifier(scene_name);
    if id.starts_with(|c: char| c.is_ascii_alphabetic()) {
        id
    } else {
        format!("m{id}")
    }
}

/// The SSD. SSP 2.0 keeps SSP 1.0's namespaces; only `version` and the
/// connector types differ.
fn ssd(name: &str, version: SspVersion, wires: &[Wire], experiment: Experiment) -> String {
    let connections: String = wires
        .iter()
        .map(|Wire { connection: c, .. }| {
            format!(
                "      <ssd:Connection startElement=\"{}\" startConnector=\"{}\" endElement=\"{}\" endConnector=\"{}\"/>\n",
                c.from.0,
                esc(&c.from.1),
                c.to.0,
                esc(&c.to.1)
            )
        })
        .collect();
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<ssd:SystemStructureDescription xmlns:ssd=\"http://ssp-standard.org/SSP1/SystemStructureDescription\" xmlns:ssc=\"http://ssp-standard.org/SSP1/SystemStructureCommon\" xmlns:oms=\"https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd\" version=\"{v}\" name=\"{n}\">\n  <ssd:System name=\"{n}\">\n    <ssd:Elements>\n{elements}    </ssd:Elements>\n    <ssd:Connections>\n{connections}    </ssd:Connections>\n{master}  </ssd:System>\n  <ssd:DefaultExperiment startTime=\"0\" stopTime=\"{stop}\">\n{results}  </ssd:DefaultExperiment>\n</ssd:SystemStructureDescription>\n",
        v = version.label(),
        n = system_name(name),
        results = oms_results(&system_name(name)),
        elements = elements(wires),
        master = oms_master(experiment.step_size),
        stop = experiment.stop_time,
    )
}

impl System {
    /// Write the system to `out`, with the guideway FMU at `guideway`
    /// (written after the system was checked). Reproducible: entries in a
    /// fixed order, stamped with the zip epoch.
    pub fn write(&self, guideway: &Path, out: &Path) -> Result<(), String> {
        let guideway = crate::input_file::read_bounded(guideway, crate::input_file::MAX_FMU_BYTES)?;
        let io = |e: std::io::Error| format!("cannot write {}: {e}", out.display());
        let zerr = |e: zip::result::ZipError| format!("cannot write {}: {e}", out.display());
        let staged = crate::output_file::Staged::new(out)?;
        let mut zip = zip::ZipWriter::new(staged.file()?);
        let options = SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated)
            .last_modified_time(zip::DateTime::default());
        zip.start_file("SystemStructure.ssd", options)
            .map_err(zerr)?;
        let text = ssd(&self.name, self.version, &self.wires, self.experiment);
        zip.write_all(text.as_bytes()).map_err(io)?;
        for (component, fmu) in COMPONENTS.iter().zip([&guideway, &self.vehicle]) {
            zip.start_file(format!("resources/{component}.fmu"), options)
                .map_err(zerr)?;
            zip.write_all(fmu).map_err(io)?;
        }
        zip.finish().map_err(zerr)?.sync_all().map_err(io)?;
        staged.commit().map(drop)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn connections_parse_and_bad_ones_are_refused() {
        let c: Connection = "vehicle.force=guideway.wheel.force_y".parse().unwrap();
        assert_eq!(c.from, ("vehicle".into(), "force".into()));
        assert_eq!(c.to, ("guideway".into(), "wheel.force_y".into()));
        for bad in [
            "vehicle.force",
            "car.f=guideway.x",
            "vehicle.=guideway.x",
            "=",
            "",
        ] {
            assert!(bad.parse::<Connection>().is_err(), "{bad}");
        }
    }

    fn wire(text: &str, types: [&'static str; 2]) -> Wire {
        Wire {
            connection: text.parse().unwrap(),
            types,
        }
    }

    const EXPERIMENT: Experiment = Experiment {
        stop_time: 3.5,
        step_size: 1e-3,
    };

    #[test]
    fn the_ssd_declares_the_connectors_it_wires() {
        let w = wire("vehicle.f=guideway.wheel.force_y", ["Real", "Real"]);
        let x = ssd("s&t", SspVersion::V1, &[w], EXPERIMENT);
        assert!(x.contains("version=\"1.0\" name=\"s_t\""));
        assert!(x.contains("<ssd:DefaultExperiment startTime=\"0\" stopTime=\"3.5\">"));
        assert!(x.contains("<oms:SimulationInformation resultFile=\"s_t_res.mat\""));
        assert!(x.contains("<oms:FixedStepMaster description=\"oms-ma\" stepSize=\"0.001\""));
        assert!(x.contains("<ssd:Connector name=\"wheel.force_y\" kind=\"input\"><ssc:Real/>"));
        assert!(x.contains("<ssd:Connector name=\"f\" kind=\"output\"><ssc:Real/>"));
        assert!(x.contains("startElement=\"vehicle\" startConnector=\"f\" endElement=\"guideway\""));
    }

    #[test]
    fn the_system_is_named_by_an_identifier_omsimulator_accepts() {
        for (scene, name) in [
            ("lee1994-wheel-10", "lee1994_wheel_10"),
            ("10 spans", "m_10_spans"),
        ] {
            assert_eq!(system_name(scene), name);
            let x = ssd(scene, SspVersion::V1, &[], EXPERIMENT);
            assert!(x.contains(&format!("<ssd:System name=\"{name}\">")), "{x}");
        }
        assert_eq!(system_name("_x"), "m_x");
    }

    #[test]
    fn an_ssp_2_ssd_types_each_connector_by_its_fmu() {
        // an FMI 2.0 vehicle's Real output into an FMI 3.0 guideway's Float64 input
        let w = wire("vehicle.f=guideway.wheel.force_y", ["Real", "Float64"]);
        let x = ssd("s", SspVersion::V2, &[w], EXPERIMENT);
        assert!(x.contains("version=\"2.0\""));
        assert!(x.contains("<ssd:Connector name=\"wheel.force_y\" kind=\"input\"><ssc:Float64/>"));
        assert!(x.contains("<ssd:Connector name=\"f\" kind=\"output\"><ssc:Real/>"));
    }

    const FMI3: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="m" instantiationToken="{x}">
  <ModelVariables>
    <Float64 name="time" valueReference="0" causality="independent" variability="continuous"/>
    <Float64 name="wheel.force_y" valueReference="1" causality="input" start="0">
      <Alias name="not.a.variable"/>
    </Float64>
    <Float64 name="wheel.y" valueReference="2" causality="output"/>
    <Int32 name="contact.count" valueReference="3" causality="output"/>
    <Float64 name="matrix" valueReference="4"><Dimension valueReference="3"/></Float64>
  </ModelVariables>
  <ModelStructure><Output valueReference="2"/></ModelStructure>
</fmiModelDescription>"#;

    #[test]
    fn an_fmi_3_model_description_gives_its_typed_variables() {
        let fmu = interface(FMI3).unwrap();
        assert_eq!(fmu.fmi_version, "3.0");
        assert_eq!(fmu.float_type(), "Float64");
        let names = |c: &str| {
            let mut n: Vec<_> = (fmu.variables.iter())
                .filter(|(_, v)| v.causality == c)
                .map(|(n, v)| format!("{n}:{}", v.ty))
                .collect();
            n.sort();
            n
        };
        assert_eq!(names("input"), ["wheel.force_y:Float64"]);
        assert_eq!(names("output"), ["contact.count:Int32", "wheel.y:Float64"]);
        assert_eq!(names("local"), ["matrix:Float64"]);
        assert_eq!(fmu.variables.len(), 5);
        let c: Connection = "guideway.contact.count=vehicle.f".parse().unwrap();
        let err = check(
            &c,
            &HashMap::from([("guideway", fmu.clone()), ("vehicle", fmu)]),
        );
        assert!(err.unwrap_err().contains(
            "is a Int32 output; a connection goes from a Float64 output to a Float64 input; \
                 the Float64 outputs of guideway: wheel.y"
        ),);
    }

    #[test]
    fn an_fmi_2_model_description_gives_its_typed_variables() {
        let xml = r#"<fmiModelDescription fmiVersion="2.0"><ModelVariables>
            <ScalarVariable name="a" valueReference="1" causality="input"><Real start="0"/></ScalarVariable>
            <ScalarVariable name="n" valueReference="2" causality="output"><Integer/></ScalarVariable>
            </ModelVariables></fmiModelDescription>"#;
        let fmu = interface(xml).unwrap();
        assert_eq!(fmu.float_type(), "Real");
        assert_eq!(fmu.variables["a"].ty, "Real");
        assert_eq!(fmu.variables["a"].causality, "input");
        assert_eq!(fmu.variables["n"].ty, "Integer");
    }

    #[test]
    fn ssp_1_types_every_float_real_and_ssp_2_by_its_fmu() {
        let fmi3 = interface(FMI3).unwrap();
        assert_eq!(SspVersion::parse("1").unwrap().label(), "1.0");
        assert_eq!(SspVersion::parse("2").unwrap().label(), "2.0");
        assert_eq!(SspVersion::parse("1.0"), None);
        assert_eq!(SspVersion::V1.connector_type(&fmi3), "Real");
        assert_eq!(SspVersion::V2.connector_type(&fmi3), "Float64");
    }
}

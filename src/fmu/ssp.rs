//! An SSP 1.0 system (`.ssp`): the guideway FMU and a vehicle FMU wired by
//! connections from outputs to inputs, in one archive.
//!
//! Layout: `SystemStructure.ssd`, `resources/guideway.fmu`,
//! `resources/vehicle.fmu`. Every connection is checked against the two
//! model descriptions (the variables exist, an output feeds an input, both
//! Real) before anything is written (`check_connections`, run by `export`
//! before the FMU itself is written). The SSD carries a DefaultExperiment
//! and the fixed-step master settings OMSimulator needs to load a system
//! (its `SimulationInformation` annotation; other masters ignore it).

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

/// Name → (causality, type) of the variables of one FMU.
type Variables = HashMap<String, (String, String)>;

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

/// The variables a model description declares.
fn variables(xml: &str) -> Result<Variables, String> {
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut vars = HashMap::new();
    let mut current: Option<(String, String)> = None;
    loop {
        use quick_xml::events::Event;
        let e = match reader
            .read_event()
            .map_err(|e| format!("modelDescription.xml: {e}"))?
        {
            Event::Eof => break,
            Event::Start(e) | Event::Empty(e) => e,
            _ => continue,
        };
        let attr = |name: &str| {
            e.attributes()
                .flatten()
                .find(|a| a.key.as_ref() == name)
                .and_then(|a| {
                    a.normalized_value(quick_xml::XmlVersion::Implicit1_0)
                        .ok()
                        .map(|v| v.into_owned())
                })
        };
        match e.name().as_ref() {
            "ScalarVariable" => {
                let name = attr("name").unwrap_or_default();
                let causality = attr("causality").unwrap_or_else(|| "local".into());
                current = Some((name, causality));
            }
            ty @ ("Real" | "Integer" | "Boolean" | "String" | "Enumeration") => {
                if let Some((name, causality)) = current.take() {
                    let ty = ty.to_string();
                    vars.insert(name, (causality, ty));
                }
            }
            _ => {}
        }
    }
    Ok(vars)
}

/// Check `c` against the variables of the two FMUs; a refusal lists the
/// variables that would fit where the wrong one is.
fn check(c: &Connection, vars: &HashMap<&str, Variables>) -> Result<(), String> {
    for ((component, name), want) in [(&c.from, "output"), (&c.to, "input")] {
        let fitting = || fitting(component, &vars[component.as_str()], want);
        let Some((causality, ty)) = vars[component.as_str()].get(name) else {
            return Err(format!(
                "--connect {}: {component} has no variable `{name}`; {}",
                c,
                fitting()
            ));
        };
        if causality != want || ty != "Real" {
            return Err(format!(
                "--connect {c}: {component}.{name} is a {ty} {causality}; a connection goes from a Real output to a Real input; {}",
                fitting()
            ));
        }
    }
    Ok(())
}

/// "the Real outputs of vehicle: a, b, c" (sorted).
fn fitting(component: &str, vars: &Variables, causality: &str) -> String {
    let mut names: Vec<&str> = vars
        .iter()
        .filter(|(_, (c, ty))| c == causality && ty == "Real")
        .map(|(n, _)| n.as_str())
        .collect();
    names.sort_unstable();
    if names.is_empty() {
        return format!("{component} has no Real {causality}");
    }
    format!("the Real {causality}s of {component}: {}", names.join(", "))
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
    vehicle: Vec<u8>,
    connections: Vec<Connection>,
    experiment: Experiment,
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
/// `guideway_xml` (not yet written) and the vehicle FMU at `vehicle`.
pub fn check_connections(
    name: &str,
    guideway_xml: &str,
    vehicle: &Path,
    connections: &[Connection],
    experiment: Experiment,
) -> Result<System, SystemError> {
    let vehicle_bytes = crate::input_file::read_bounded(vehicle, crate::input_file::MAX_FMU_BYTES)
        .map_err(SystemError::Io)?;
    let vehicle_vars = model_description(&vehicle_bytes)
        .and_then(|xml| variables(&xml))
        .map_err(|e| SystemError::Connection(format!("{}: {e}", vehicle.display())))?;
    let guideway_vars = variables(guideway_xml).map_err(SystemError::Connection)?;
    let vars = HashMap::from([("guideway", guideway_vars), ("vehicle", vehicle_vars)]);
    for c in connections {
        check(c, &vars).map_err(SystemError::Connection)?;
    }
    Ok(System {
        name: name.to_string(),
        vehicle: vehicle_bytes,
        connections: connections.to_vec(),
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
fn elements(connections: &[Connection]) -> String {
    let mut elements = String::new();
    for component in COMPONENTS {
        let mut connectors = String::new();
        for c in connections {
            for ((comp, var), kind) in [(&c.from, "output"), (&c.to, "input")] {
                if comp == component {
                    connectors += &format!(
                        "          <ssd:Connector name=\"{}\" kind=\"{kind}\"><ssc:Real/></ssd:Connector>\n",
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

fn ssd(name: &str, connections: &[Connection], experiment: Experiment) -> String {
    let wires: String = connections
        .iter()
        .map(|c| {
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
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<ssd:SystemStructureDescription xmlns:ssd=\"http://ssp-standard.org/SSP1/SystemStructureDescription\" xmlns:ssc=\"http://ssp-standard.org/SSP1/SystemStructureCommon\" xmlns:oms=\"https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd\" version=\"1.0\" name=\"{n}\">\n  <ssd:System name=\"{n}\">\n    <ssd:Elements>\n{elements}    </ssd:Elements>\n    <ssd:Connections>\n{wires}    </ssd:Connections>\n{master}  </ssd:System>\n  <ssd:DefaultExperiment startTime=\"0\" stopTime=\"{stop}\"/>\n</ssd:SystemStructureDescription>\n",
        n = esc(name),
        elements = elements(connections),
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
        let text = ssd(&self.name, &self.connections, self.experiment);
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

    #[test]
    fn the_ssd_declares_the_connectors_it_wires() {
        let c: Connection = "vehicle.f=guideway.wheel.force_y".parse().unwrap();
        let x = ssd(
            "s&t",
            &[c],
            Experiment {
                stop_time: 3.5,
                step_size: 1e-3,
            },
        );
        assert!(x.contains("<ssd:DefaultExperiment startTime=\"0\" stopTime=\"3.5\"/>"));
        assert!(x.contains("<oms:FixedStepMaster description=\"oms-ma\" stepSize=\"0.001\""));
        assert!(x.contains("name=\"s&amp;t\""));
        assert!(x.contains("<ssd:Connector name=\"wheel.force_y\" kind=\"input\">"));
        assert!(x.contains("<ssd:Connector name=\"f\" kind=\"output\">"));
        assert!(x.contains("startElement=\"vehicle\" startConnector=\"f\" endElement=\"guideway\""));
    }
}

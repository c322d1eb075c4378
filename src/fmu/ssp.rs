//! An SSP 1.0 system (`.ssp`): the guideway FMU and a vehicle FMU wired by
//! connections from outputs to inputs, in one archive.
//!
//! Layout: `SystemStructure.ssd`, `resources/guideway.fmu`,
//! `resources/vehicle.fmu`. Every connection is checked against the two
//! model descriptions (the variables exist, an output feeds an input, both
//! Real) before anything is written.

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

/// Name → (causality, type) of the variables of an FMU's model description.
fn variables(fmu: &[u8]) -> Result<HashMap<String, (String, String)>, String> {
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(fmu)).map_err(|e| e.to_string())?;
    let mut xml = String::new();
    zip.by_name("modelDescription.xml")
        .map_err(|e| format!("no modelDescription.xml: {e}"))?
        .read_to_string(&mut xml)
        .map_err(|e| e.to_string())?;
    let mut reader = quick_xml::Reader::from_str(&xml);
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

/// Check `c` against the variables of the two FMUs.
fn check(
    c: &Connection,
    vars: &HashMap<&str, HashMap<String, (String, String)>>,
) -> Result<(), String> {
    for ((component, name), want) in [(&c.from, "output"), (&c.to, "input")] {
        let Some((causality, ty)) = vars[component.as_str()].get(name) else {
            return Err(format!("{component} has no variable `{name}`"));
        };
        if causality != want || ty != "Real" {
            return Err(format!(
                "{component}.{name} is a {ty} {causality}; a connection goes from a Real output to a Real input"
            ));
        }
    }
    Ok(())
}

fn ssd(name: &str, connections: &[Connection]) -> String {
    let esc = |s: &str| {
        s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('"', "&quot;")
    };
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
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<ssd:SystemStructureDescription xmlns:ssd=\"http://ssp-standard.org/SSP1/SystemStructureDescription\" xmlns:ssc=\"http://ssp-standard.org/SSP1/SystemStructureCommon\" version=\"1.0\" name=\"{n}\">\n  <ssd:System name=\"{n}\">\n    <ssd:Elements>\n{elements}    </ssd:Elements>\n    <ssd:Connections>\n{wires}    </ssd:Connections>\n  </ssd:System>\n</ssd:SystemStructureDescription>\n",
        n = esc(name)
    )
}

/// Write the system `name` of the FMUs `guideway` and `vehicle` with
/// `connections` to `out`.
pub fn write(
    name: &str,
    guideway: &Path,
    vehicle: &Path,
    connections: &[Connection],
    out: &Path,
) -> Result<(), String> {
    let read = |p: &Path| crate::input_file::read_bounded(p, crate::input_file::MAX_FMU_BYTES);
    let fmus = [read(guideway)?, read(vehicle)?];
    let mut vars = HashMap::new();
    for (component, (fmu, path)) in COMPONENTS.iter().zip(fmus.iter().zip([guideway, vehicle])) {
        let v = variables(fmu).map_err(|e| format!("{}: {e}", path.display()))?;
        vars.insert(*component, v);
    }
    for c in connections {
        check(c, &vars)?;
    }
    let io = |e: std::io::Error| format!("cannot write {}: {e}", out.display());
    let zerr = |e: zip::result::ZipError| format!("cannot write {}: {e}", out.display());
    let mut zip = zip::ZipWriter::new(std::fs::File::create(out).map_err(io)?);
    let options = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .last_modified_time(zip::DateTime::default());
    zip.start_file("SystemStructure.ssd", options)
        .map_err(zerr)?;
    zip.write_all(ssd(name, connections).as_bytes())
        .map_err(io)?;
    for (component, fmu) in COMPONENTS.iter().zip(&fmus) {
        zip.start_file(format!("resources/{component}.fmu"), options)
            .map_err(zerr)?;
        zip.write_all(fmu).map_err(io)?;
    }
    zip.finish().map_err(zerr)?;
    Ok(())
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
        let x = ssd("s&t", &[c]);
        assert!(x.contains("name=\"s&amp;t\""));
        assert!(x.contains("<ssd:Connector name=\"wheel.force_y\" kind=\"input\">"));
        assert!(x.contains("<ssd:Connector name=\"f\" kind=\"output\">"));
        assert!(x.contains("startElement=\"vehicle\" startConnector=\"f\" endElement=\"guideway\""));
    }
}

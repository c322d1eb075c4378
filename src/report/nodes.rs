//! Every node's deflection and acceleration over time (`guideway run
//! --nodes FILE`), streamed to CSV beside the run's outputs: one row per
//! row of the run, `time` then `deflection@<x>` for each node, then
//! `acceleration@<x>` (m and m/s², up positive; x in m). CSV and not
//! Parquet: the run's other outputs are CSV, and a Parquet writer would add
//! the largest dependency of the build for a file that is read once.

use std::io::{self, Write};

use super::shortest::push_debug;

use crate::design::BeamDynamics;
use crate::simulation::{Advance, OutputInfo, Simulation, SolverError, Steppable};

/// Most values (rows × nodes) a node file may have: two numbers of about
/// 22 characters each per value, about 2 GB of CSV.
pub const MAX_NODE_VALUES: u64 = 50_000_000;

/// Refuse, before the run, a node file of more than `MAX_NODE_VALUES`
/// rows × nodes (`rows` counts the initial state).
pub fn check_node_output(rows: u64, nodes: usize) -> Result<(), String> {
    let values = rows.saturating_mul(nodes as u64);
    if values > MAX_NODE_VALUES {
        return Err(format!(
            "--nodes: {rows} rows × {nodes} nodes = {values} values, more than the limit of \
             {MAX_NODE_VALUES} (fewer beam.elements or a shorter run, solver.end_time)"
        ));
    }
    Ok(())
}

/// Writes the header at creation and a row per state.
pub struct NodeWriter<W: Write> {
    out: io::BufWriter<W>,
    nodes: Vec<f64>,
    /// A row's text, made in memory and written at once.
    line: Vec<u8>,
}

impl<W: Write> NodeWriter<W> {
    /// The header for nodes at abscissae `nodes`.
    pub fn new(out: W, nodes: &[f64]) -> io::Result<NodeWriter<W>> {
        let mut out = io::BufWriter::new(out);
        write!(out, "time")?;
        for what in ["deflection", "acceleration"] {
            for x in nodes {
                write!(out, ",{what}@{x}")?;
            }
        }
        writeln!(out)?;
        Ok(NodeWriter {
            out,
            nodes: nodes.to_vec(),
            line: Vec::new(),
        })
    }

    /// One row: the beam at `time` (NaN where its state is not known),
    /// each number in `{:?}`'s text (`shortest`).
    pub fn row(
        &mut self,
        time: f64,
        beam: &crate::beam::Beam,
        state: Option<&BeamDynamics>,
    ) -> io::Result<()> {
        let line = &mut self.line;
        line.clear();
        push_debug(line, time);
        let read = [BeamDynamics::deflection_at, BeamDynamics::acceleration_at];
        for value in read {
            for &x in &self.nodes {
                let v = state.map_or(f64::NAN, |s| value(s, beam, x));
                line.push(b',');
                push_debug(line, v);
            }
        }
        line.push(b'\n');
        self.out.write_all(line)
    }

    /// Flush and hand back the underlying writer.
    pub fn finish(self) -> io::Result<W> {
        self.out.into_inner().map_err(|e| e.into_error())
    }
}

/// A simulation that writes its nodes after each advance: driven by
/// `drive_into`, the node file has a row for each row of the run.
pub struct WithNodes<'s, W: Write> {
    simulation: &'s mut Simulation,
    writer: NodeWriter<W>,
}

impl<'s, W: Write> WithNodes<'s, W> {
    /// Write the header and the initial state.
    pub fn new(simulation: &'s mut Simulation, out: W) -> io::Result<WithNodes<'s, W>> {
        let beam = &simulation.system().beam;
        let mut writer = NodeWriter::new(out, &beam.node_x)?;
        let state = simulation.beam_dynamics();
        writer.row(simulation.time(), beam, state.as_ref())?;
        Ok(WithNodes { simulation, writer })
    }

    pub fn finish(self) -> io::Result<W> {
        self.writer.finish()
    }
}

impl<W: Write> super::exits::Watched for WithNodes<'_, W> {
    fn simulation(&self) -> &Simulation {
        self.simulation
    }
}

impl<W: Write> Steppable for WithNodes<'_, W> {
    fn time(&self) -> f64 {
        self.simulation.time()
    }
    fn outputs(&self) -> &[OutputInfo] {
        self.simulation.outputs()
    }
    fn output_values(&self, values: &mut [f64]) {
        self.simulation.output_values(values)
    }
    /// Advance, then write the nodes; a write error stops the run as a
    /// failed step would.
    fn advance_to(&mut self, t: f64) -> Result<Advance, SolverError> {
        let advance = self.simulation.advance_to(t)?;
        let time = self.simulation.time();
        let beam = &self.simulation.system().beam;
        let state = self.simulation.beam_dynamics();
        self.writer
            .row(time, beam, state.as_ref())
            .map_err(|e| SolverError {
                time,
                message: format!("cannot write the node file: {e}"),
            })?;
        Ok(advance)
    }
}

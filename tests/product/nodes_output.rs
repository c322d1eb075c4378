//! `guideway run --nodes FILE` (issue 11): every node's deflection and
//! acceleration at every row of the run, streamed; refused up front beyond
//! its bound.

use crate::common;
use common::cli::{guideway, refusal, stderr};
use guideway::scene::{BodyKind, IntegratorKind};
use guideway::Scene;

/// Header and rows of a CSV file.
fn read_csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).expect("file written");
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

fn column(header: &[String], rows: &[Vec<f64>], name: &str) -> Vec<f64> {
    let k = header.iter().position(|h| h == name).expect(name);
    rows.iter().map(|r| r[k]).collect()
}

#[test]
fn every_node_is_written_at_every_row_and_matches_the_sensor() {
    // The paper's wheel on 4 elements with a sensor on the node at 6 m.
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 0.0025);
    scene.beam.elements = 4;
    scene.solver.integrator = IntegratorKind::Hht;
    scene.sensors[0].position = 6.0;
    let dir = tempfile::tempdir().unwrap();
    let scene_file = dir.path().join("scene.toml");
    std::fs::write(&scene_file, scene.to_toml_string()).unwrap();
    let (out, nodes) = (dir.path().join("out.csv"), dir.path().join("nodes.csv"));
    let output = guideway(&[
        "run",
        scene_file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--nodes",
        nodes.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let (header, rows) = read_csv(&nodes);
    let xs = ["0", "6", "12", "18", "24"];
    let mut expected = vec!["time".to_string()];
    for what in ["deflection", "acceleration"] {
        expected.extend(xs.iter().map(|x| format!("{what}@{x}")));
    }
    assert_eq!(header, expected);
    let (out_header, out_rows) = read_csv(&out);
    assert_eq!(rows.len(), out_rows.len(), "a node row per output row");
    assert_eq!(
        column(&header, &rows, "time"),
        column(&out_header, &out_rows, "time")
    );
    let sensor = &scene.sensors[0].name;
    for (node, output) in [
        ("deflection@6", "deflection"),
        ("acceleration@6", "acceleration"),
    ] {
        let found = column(&header, &rows, node);
        let wanted = column(&out_header, &out_rows, &format!("sensor.{sensor}.{output}"));
        assert_eq!(found, wanted, "{node}");
    }
    // The supports do not move; the midspan node does.
    assert!(column(&header, &rows, "deflection@0")
        .iter()
        .all(|&w| w == 0.0));
    let midspan = column(&header, &rows, "deflection@12");
    assert!(midspan.iter().any(|w| w.abs() > 1e-3));
}

#[test]
fn a_node_file_beyond_its_bound_is_refused_before_running() {
    // 2000 elements and 240 000 steps: 2001 × 240 001 values.
    let mut scene = Scene::lee1994(BodyKind::Wheel, 10.0, 1e-5);
    scene.beam.elements = 2000;
    scene.solver.integrator = IntegratorKind::Hht;
    scene.solver.end_time = Some(2.4);
    let dir = tempfile::tempdir().unwrap();
    let scene_file = dir.path().join("scene.toml");
    std::fs::write(&scene_file, scene.to_toml_string()).unwrap();
    let nodes = dir.path().join("nodes.csv");
    let output = guideway(&[
        "run",
        scene_file.to_str().unwrap(),
        "--nodes",
        nodes.to_str().unwrap(),
        "--quiet",
    ]);
    let message = refusal(&output, "");
    assert!(
        message.contains("--nodes: 240001 rows × 2001 nodes")
            && message.contains("more than the limit of 50000000"),
        "{message}"
    );
    assert!(!nodes.exists(), "nothing written");
}

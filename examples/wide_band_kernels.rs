//! The wide band's kernels alone, for instruction counts: a rail's band of
//! `rows` rows (w, ψ at each node, each element coupling four places), its
//! middle tenth a rail and a deck interleaved (four DOFs a node, eight
//! places an element), as the rail-over-deck scenes number them;
//! `reps` solves, products or quadratic forms (`recall`: the recalling
//! solve of a right-hand side that changes in every row every time, so
//! that every row is solved again):
//! `valgrind --tool=callgrind target/release/examples/wide_band_kernels 922 1000 solve`
//! run at two `reps`; the difference divided by the difference of the
//! counts is the cost of one call, the set-up excluded.

use guideway::wide_band::{RecallingLdlt, WideBand};
use std::hint::black_box;

/// Each node's DOFs (two on the rail alone, four with the deck) until
/// `rows` rows.
fn node_widths(rows: usize) -> Vec<usize> {
    let (deck_from, deck_to) = (rows * 9 / 20, rows * 11 / 20);
    let mut widths = Vec::new();
    let mut at = 0;
    while at < rows {
        let width = if (deck_from..deck_to).contains(&at) {
            4
        } else {
            2
        };
        widths.push(width.min(rows - at));
        at += width;
    }
    widths
}

/// The band: each element couples its two nodes' shared DOFs (the rail's
/// where one node has no deck), diagonally dominant.
fn band(rows: usize) -> WideBand {
    let widths = node_widths(rows);
    let starts: Vec<usize> = (widths.iter())
        .scan(0, |at, w| {
            let start = *at;
            *at += w;
            Some(start)
        })
        .collect();
    let mut a = WideBand::zeros(rows, 7);
    for e in 0..widths.len() - 1 {
        let shared = widths[e].min(widths[e + 1]);
        let dofs: Vec<usize> = (starts[e]..starts[e] + shared)
            .chain(starts[e + 1]..starts[e + 1] + shared)
            .collect();
        for (p, &i) in dofs.iter().enumerate() {
            for (q, &j) in dofs.iter().enumerate().take(p + 1) {
                let value = ((p * 5 + q * 3 + e) % 13) as f64 * 0.1 - 0.6;
                a.add_symmetric(i, j, value).expect("in band");
            }
        }
    }
    for i in 0..rows {
        a.add_symmetric(i, i, 12.0 + (i % 5) as f64)
            .expect("diagonal");
    }
    a
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: wide_band_kernels <rows> <reps> <solve|recall|product|form>";
    let rows: usize = args.get(1).and_then(|a| a.parse().ok()).expect(usage);
    let reps: usize = args.get(2).and_then(|a| a.parse().ok()).expect(usage);
    let a = band(rows);
    let factor = a.ldlt().expect("positive definite");
    let x: Vec<f64> = (0..rows)
        .map(|i| ((i * 7) % 11) as f64 * 0.37 - 1.9)
        .collect();
    let mut out = vec![0.0; rows];
    let mut total = 0.0;
    let mut recalling = RecallingLdlt::new(factor.clone());
    for rep in 0..reps {
        match args.get(3).map(String::as_str) {
            Some("solve") => {
                out.copy_from_slice(&x);
                factor.solve_in_place(black_box(&mut out));
            }
            Some("recall") => {
                let scale = 1.0 + rep as f64 * 1e-9;
                out.iter_mut().zip(&x).for_each(|(o, x)| *o = scale * x);
                recalling.solve_in_place(black_box(&mut out));
            }
            Some("product") => a.mul_to(black_box(&x), &mut out),
            Some("form") => total += a.quadratic_form(black_box(&x)),
            _ => panic!("{usage}"),
        }
    }
    let sum: f64 = out.iter().sum();
    println!("{rows} rows: Σ out = {sum:e}, Σ forms = {total:e}");
}

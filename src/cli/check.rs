//! `guideway check BRIDGE.toml [--out DIR] [--threads N]`: the dynamic
//! check of a railway bridge, its report written into DIR; exit code 0
//! whatever the verdict (the report says PASS or FAIL), 2 for a bad
//! description.

use std::time::Instant;

use super::{CheckArgs, Failure};
use guideway::check::report::write_report;
use guideway::check::spec::{EXAMPLE, EXAMPLE_NAME};
use guideway::check::{run_check as check, BridgeSpec};

pub(super) fn run_check(args: CheckArgs) -> Result<(), Failure> {
    let input = if args.bridge == EXAMPLE_NAME && !std::path::Path::new(&args.bridge).exists() {
        EXAMPLE.to_string()
    } else {
        let meta = std::fs::metadata(&args.bridge)
            .map_err(|e| Failure::Scene(format!("{}: {e}", args.bridge)))?;
        if meta.len() > 1 << 20 {
            return Err(Failure::Scene(format!("{}: over 1 MiB", args.bridge)));
        }
        std::fs::read_to_string(&args.bridge)
            .map_err(|e| Failure::Scene(format!("{}: {e}", args.bridge)))?
    };
    let spec = BridgeSpec::from_toml_str(&input)
        .map_err(|e| Failure::Scene(format!("{}: {e}", args.bridge)))?;
    let threads = args.threads.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    let started = Instant::now();
    let result = check(&spec, threads).map_err(Failure::Scene)?;
    let elapsed = started.elapsed().as_secs_f64();
    let files = write_report(&result, &input, &args.out).map_err(Failure::Run)?;
    println!(
        "{} runs in {elapsed:.2} s on {threads} threads",
        result.runs.len()
    );
    for v in &result.verdicts {
        println!(
            "{:4}  {}: {} ({}; {})",
            v.status, v.clause, v.check, v.value, v.limit
        );
    }
    if let Some(html) = files.first() {
        println!("report: {}", html.display());
    }
    Ok(())
}

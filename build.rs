//! Link-time settings of the shared library (the FMU binary).
//!
//! - Its dynamic symbol table is the FMI 2.0 and 3.0 APIs only: a
//!   dependency (`fmi-sys`) defines `callback_log` with `#[no_mangle]`,
//!   which rustc would export beside our `fmi2*` and `fmi3*` functions
//!   (src/fmi_common/exports.map).
//! - In release it is stripped: the shipped binary needs no symbol table.
//!   Done here rather than in the cargo profile so that only the cdylib is
//!   stripped (the CLI and the tests keep their backtraces) and the
//!   dependencies need no rebuild.
//! - The `guideway` command is linked as a position-dependent executable:
//!   the dynamic loader then has no relocations to apply to it (about
//!   6,500 in a PIE, each page it touches a page fault), a measurable part
//!   of a run of a few milliseconds.
//! - The portable build (`GUIDEWAY_PORTABLE` set, scripts/lib/portable.sh)
//!   is refused when the Rust flags, from the environment or a cargo
//!   config file, build for one CPU: it ships in the wheel and in every
//!   FMU and must run on any x86-64 (docs/performance.md, "Building for
//!   your own CPU").

fn main() {
    let script =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/fmi_common/exports.map");
    println!("cargo:rerun-if-changed={}", script.display());
    println!("cargo:rerun-if-changed=build.rs");
    println!(
        "cargo:rustc-cdylib-link-arg=-Wl,--version-script={}",
        script.display()
    );
    println!("cargo:rustc-link-arg-bins=-no-pie");
    refuse_cpu_features();
    if std::env::var("PROFILE").as_deref() == Ok("release") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,--strip-all");
    }
}

/// Stops the portable build when the target's features go beyond what every
/// x86-64 CPU has: a binary built for AVX2 stops with an illegal
/// instruction on a CPU without it, inside the tool that imports the FMU.
fn refuse_cpu_features() {
    println!("cargo:rerun-if-env-changed=GUIDEWAY_PORTABLE");
    let var = |name: &str| std::env::var(name).unwrap_or_default();
    if std::env::var_os("GUIDEWAY_PORTABLE").is_none() || var("CARGO_CFG_TARGET_ARCH") != "x86_64" {
        return;
    }
    const EVERY_X86_64: [&str; 4] = ["fxsr", "sse", "sse2", "x87"];
    let features = var("CARGO_CFG_TARGET_FEATURE");
    let beyond: Vec<&str> = (features.split(','))
        .filter(|f| !f.is_empty() && !EVERY_X86_64.contains(f))
        .collect();
    if !beyond.is_empty() {
        eprintln!(
            "the portable build must run on any x86-64 CPU, but its Rust flags enable {} \
             (a target-cpu or target-feature in RUSTFLAGS or a cargo config file): \
             build it without them",
            beyond.join(", ")
        );
        std::process::exit(1);
    }
}

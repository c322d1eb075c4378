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
    if std::env::var("PROFILE").as_deref() == Ok("release") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,--strip-all");
    }
}

//! Link-time settings of the shared library (the FMU binary).
//!
//! A dependency (`fmi-sys`) defines `callback_log` with `#[no_mangle]`, so
//! rustc exports it from the cdylib beside our `fmi2*` functions. The version
//! script keeps the dynamic symbol table to the FMI 2.0 API.

fn main() {
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/fmi2/exports.map");
    println!("cargo:rerun-if-changed={}", script.display());
    println!(
        "cargo:rustc-cdylib-link-arg=-Wl,--version-script={}",
        script.display()
    );
}

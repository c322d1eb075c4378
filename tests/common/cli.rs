//! The `guideway` binary run as a user would, shared by the integration
//! tests of the command line: one way to start it, read its streams and
//! insist that it succeeded.

use std::path::Path;
use std::process::{Command, Output};

/// `guideway args` with the test build's cdylib for `export` (cargo builds
/// it next to the test binaries, not next to the binary where `export`
/// looks by default) and no table search path from the caller's shell.
pub fn command(args: &[&str]) -> Command {
    // `option_env!`: the stress_balance example shares tests/common and
    // has no binary to run (it never calls this); the tests always do.
    #[allow(clippy::option_env_unwrap)]
    let binary = option_env!("CARGO_BIN_EXE_guideway").expect("set by cargo for tests");
    let mut command = Command::new(binary);
    command.args(args).env_remove("GUIDEWAY_TABLE_PATHS");
    if let Ok(cdylib) = guideway::fmu::default_cdylib() {
        command.env("GUIDEWAY_CDYLIB", cdylib);
    }
    command
}

/// `guideway args`, whatever its exit status.
pub fn guideway(args: &[&str]) -> Output {
    command(args).output().expect("the guideway binary runs")
}

/// `guideway args`, failing the test with its stderr unless it succeeded.
pub fn guideway_ok(args: &[&str]) -> Output {
    let output = guideway(args);
    assert!(
        output.status.success(),
        "guideway {args:?} failed: {}",
        stderr(&output)
    );
    output
}

pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A path as the `&str` argument the command line takes.
pub fn arg(path: &Path) -> &str {
    path.to_str().expect("test paths are UTF-8")
}

/// The message of a refusal: fails the test (naming `context`) unless the
/// run exited with status 2, the command line's "refused before running".
pub fn refusal(output: &Output, context: &str) -> String {
    let message = stderr(output);
    assert_eq!(output.status.code(), Some(2), "{context}: {message}");
    message
}

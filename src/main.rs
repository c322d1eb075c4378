//! The `guideway` command: see `guideway --help`.

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}

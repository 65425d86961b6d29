//! `uniphys`: the UniPhys command line. See `uniphys --help`.

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = uniphys_cli::Cli::parse();
    match uniphys_cli::execute(cli) {
        Ok(code) => code,
        Err(error) => {
            eprintln!("error: {}", uniphys_cli::error_message(&error));
            ExitCode::from(2)
        }
    }
}

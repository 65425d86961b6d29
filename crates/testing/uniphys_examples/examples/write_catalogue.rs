//! Writes every example GLB into a directory (default `test_data/examples`), e.g.
//! `cargo run -p uniphys_examples --example write_catalogue -- test_data/examples`
//! from the workspace root.

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let dir = std::env::args_os()
        .nth(1)
        .map_or_else(|| PathBuf::from("test_data/examples"), PathBuf::from);
    match uniphys_examples::write_catalogue(&dir) {
        Ok(paths) => {
            for path in paths {
                println!("{}", path.display());
            }
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}

//! `uniphys-replay --recording <file.json> [--listen 127.0.0.1:0]`: serves a recording, prints
//! its URL on stdout and serves until killed.

use std::io::Write;
use std::process::ExitCode;

use uniphys_replay::{Recording, ReplayServer};

const USAGE: &str = "usage: uniphys-replay --recording <file.json> [--listen 127.0.0.1:0]";

fn main() -> ExitCode {
    let mut recording_path = None;
    let mut listen = "127.0.0.1:0".to_owned();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--recording" => recording_path = args.next(),
            "--listen" => match args.next() {
                Some(value) => listen = value,
                None => return usage("--listen needs an address"),
            },
            "-h" | "--help" => {
                println!("{USAGE}");
                return ExitCode::SUCCESS;
            }
            other => return usage(&format!("unknown argument {other:?}")),
        }
    }
    let Some(recording_path) = recording_path else {
        return usage("--recording is required");
    };
    let server = match Recording::load(&recording_path)
        .and_then(|recording| ReplayServer::bind(&listen, recording.into_responder()))
    {
        Ok(server) => server,
        Err(error) => {
            eprintln!("uniphys-replay: {error}");
            return ExitCode::FAILURE;
        }
    };
    let mut stdout = std::io::stdout();
    if writeln!(stdout, "{}", server.url())
        .and_then(|()| stdout.flush())
        .is_err()
    {
        return ExitCode::FAILURE;
    }
    loop {
        std::thread::park();
    }
}

fn usage(problem: &str) -> ExitCode {
    eprintln!("uniphys-replay: {problem}\n{USAGE}");
    ExitCode::from(2)
}

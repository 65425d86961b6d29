//! `uniphysgen-test-server [ADDR]`: the rule-based TEST model server of
//! `uniphys_uniphysgen::test_server` (not a model), on `ADDR` (default `127.0.0.1:8000`).

use std::process::ExitCode;

fn main() -> ExitCode {
    let addr = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "127.0.0.1:8000".to_owned());
    match uniphys_uniphysgen::test_server::TestServer::bind(&addr) {
        Ok(server) => {
            println!(
                "UniPhysGen TEST server (rule-based answers, not a model) on {}",
                server.url()
            );
            server.wait();
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: cannot listen on {addr}: {e}; pass a free address as the argument");
            ExitCode::from(2)
        }
    }
}

//! `moorfret` binary: parse arguments, install logging, run, map errors to exit codes.

use clap::Parser;
use std::process::ExitCode;

mod cli;

fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .init();
    let args = cli::Cli::parse();
    match cli::execute(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            let output = err
                .chain()
                .find_map(|e| e.downcast_ref::<cli::output::StdoutError>());
            if output.is_some_and(cli::output::StdoutError::is_closed_pipe) {
                // the reader went away (`| head -1`): nothing is wrong
                return ExitCode::SUCCESS;
            }
            eprintln!("error: {}", moorfret_worker::failure::error_text(&err));
            ExitCode::from(1)
        }
    }
}

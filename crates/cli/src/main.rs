//! `starcages-cli`: the headless StarCages tool over the core crate.
//!
//! Exit status: 0 on success, 2 when an input file or its content is bad (the message names
//! the file, the line or element, and the fix), 1 for any other failure.

mod commands;
mod progress;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// StarCages command-line tool: bind cage coordinates and, later, deform and render scenes.
#[derive(Debug, Parser)]
#[command(name = "starcages-cli", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Coordinates of points with respect to one cage, as JSON on standard output.
    Weights(commands::weights::WeightsArgs),
}

/// An error the user caused with their input (exit status 2).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Weights(args) => commands::weights::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            if error.downcast_ref::<InputError>().is_some()
                || error
                    .downcast_ref::<starcages_core::io::FileError>()
                    .is_some()
            {
                ExitCode::from(2)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}

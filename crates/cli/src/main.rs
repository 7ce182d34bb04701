//! `starcages-cli`: the headless StarCages tool over the core crate (the commands are the
//! `starcages_cli` library's; benchmarks are `starcages-bench`'s).
//!
//! Exit status: 0 on success, 2 when an input file or its content is bad (the message names
//! the file, the line or element, and the fix), 1 for any other failure (a write the system
//! refuses among them: a full disk is not bad input).

use std::process::ExitCode;

use clap::{CommandFactory as _, FromArgMatches as _, Parser, Subcommand};
use starcages_cli::{
    commands, exit_status, negative_numbers_as_values, remove_unfinished_saves_on_signals,
};
/// StarCages command-line tool: scenes, cages, coordinates.
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
    /// Write a generated demo scene (`demo --list` names them).
    Demo(commands::demo::DemoArgs),
    /// Print a scene's diagnostics; exit 0 only for a valid scene.
    Validate(commands::validate::ValidateArgs),
    /// Counts, bounds and per-cage settings of a scene.
    Info(commands::info::InfoArgs),
    /// A grid of box cages around a mesh, written as a scene.
    Autocage(commands::autocage::AutocageArgs),
    /// A shape-following rig around a mesh: chains of cages along its limbs, written as a scene.
    Autorig(commands::autorig::AutorigArgs),
    /// Add a box internal cage around chosen cage vertices, as their parent.
    InternalCage(commands::internal_cage::InternalCageArgs),
    /// Assemble a scene from a mesh and a cage OBJ file.
    New(commands::new::NewArgs),
    /// Build or change a rig with a script of operations (add-box, extrude, delete, mirror,
    /// rest moves).
    Edit(commands::edit::EditArgs),
    /// Write a scene's leaf cages, in a pose, to OBJ.
    Cages(commands::cages::CagesArgs),
    /// Deform a scene's mesh into a pose and write it (OBJ or GLB).
    Deform(commands::deform::DeformArgs),
    /// Bake the animation (or a cage point cache from another tool) to PC2, MDD or animated
    /// glTF.
    Bake(commands::bake::BakeArgs),
    /// Render the scene in a pose to a PNG image (offscreen), with optional influence maps.
    Render(commands::render::RenderArgs),
    /// Deformed positions of arbitrary points, as JSON.
    Eval(commands::eval::EvalArgs),
    /// Moved to `starcages-bench` (kept to say so).
    #[command(hide = true, name = "bench", alias = "bench-gpu")]
    MovedBench {
        /// Whatever followed.
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        rest: Vec<String>,
    },
}

/// The command line parsed, negative numbers taken as values ([`negative_numbers_as_values`]).
fn parse_command_line() -> Cli {
    let command = Cli::command().mut_subcommands(negative_numbers_as_values);
    let matches = command.get_matches();
    Cli::from_arg_matches(&matches).unwrap_or_else(|error| error.exit())
}

fn main() -> ExitCode {
    remove_unfinished_saves_on_signals();
    let cli = parse_command_line();
    let result = match cli.command {
        Command::Weights(args) => commands::weights::run(&args),
        Command::Demo(args) => commands::demo::run(&args),
        Command::Validate(args) => commands::validate::run(&args),
        Command::Info(args) => commands::info::run(&args),
        Command::Autocage(args) => commands::autocage::run(&args),
        Command::Autorig(args) => commands::autorig::run(&args),
        Command::InternalCage(args) => commands::internal_cage::run(&args),
        Command::New(args) => commands::new::run(&args),
        Command::Edit(args) => commands::edit::run(&args),
        Command::Cages(args) => commands::cages::run(&args),
        Command::Deform(args) => commands::deform::run(&args),
        Command::Bake(args) => commands::bake::run(&args),
        Command::Eval(args) => commands::eval::run(&args),
        Command::Render(args) => commands::render::run(&args),
        Command::MovedBench { .. } => Err(starcages_cli::InputError(
            "the benchmarks moved to their own binary: run `starcages-bench` (bench) or \
             `starcages-bench gpu` (bench-gpu), e.g. `cargo run --release -p starcages-bench -- \
             --json`"
                .into(),
        )
        .into()),
    };
    exit_status(result)
}

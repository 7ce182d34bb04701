//! `starcages-cli`: the headless StarCages tool over the core crate.
//!
//! Exit status: 0 on success, 2 when an input file or its content is bad (the message names
//! the file, the line or element, and the fix), 1 for any other failure (a write the system
//! refuses among them: a full disk is not bad input).

mod commands;
mod output;
mod progress;

use std::process::ExitCode;

use clap::{CommandFactory as _, FromArgMatches as _, Parser, Subcommand};
use peakmem_alloc::{INSTRUMENTED_SYSTEM, PeakMemAlloc};

/// The system allocator, counting the heap's peak since a reset: `bench --scale` reports each
/// bind's peak memory from it (two atomic adds per allocation; the binds allocate in large
/// blocks).
#[global_allocator]
static ALLOCATOR: &PeakMemAlloc<std::alloc::System> = &INSTRUMENTED_SYSTEM;

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
    /// GPU deformation and drawing against the CPU operator, per frame (prism demo).
    BenchGpu(commands::bench_gpu::BenchGpuArgs),
    /// *Cages against single-cage baselines: memory, bind, frame and move times.
    Bench(commands::bench::BenchArgs),
}

/// An error the user caused with their input (exit status 2).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

/// Exit status after Ctrl-C or SIGTERM: 128 + SIGINT, as shells report an interrupted program.
const INTERRUPTED: i32 = 130;

/// On Ctrl-C, SIGTERM or SIGHUP: remove the temporary file of a save in progress (the target
/// keeps its old content) and exit. Without this the default action would kill the process
/// before the temporary file's destructor ran.
fn remove_unfinished_saves_on_signals() {
    let installed = ctrlc::set_handler(|| {
        let removed = starcages_io::remove_unfinished_saves();
        if removed > 0 {
            crate::note!(
                "interrupted: the unfinished save was removed; the file keeps its old content"
            );
        } else {
            crate::note!("interrupted");
        }
        std::process::exit(INTERRUPTED);
    });
    if let Err(e) = installed {
        crate::note!(
            "warning: no Ctrl-C handler ({e}); an interrupted save may leave a temporary file"
        );
    }
}

/// The command line parsed, with negative numbers taken as values everywhere (`--margin -1`
/// reaches the range check that names the allowed range, instead of clap's "unexpected
/// argument '-1'" and its wrong tip), and values that start with a minus (`--frames -10..-5`)
/// taken by the options whose values may (see their `allow_hyphen_values`).
fn parse_command_line() -> Cli {
    let command = Cli::command().mut_subcommands(|subcommand| {
        subcommand.mut_args(|arg| {
            if arg.get_long().is_some() && arg.get_action().takes_values() {
                arg.allow_negative_numbers(true)
            } else {
                arg
            }
        })
    });
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
        Command::Bench(args) => commands::bench::run(&args),
        Command::BenchGpu(args) => commands::bench_gpu::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) if output::is_broken_pipe(&error) => ExitCode::SUCCESS,
        Err(error) => {
            crate::note!("error: {error:#}");
            if is_bad_input(&error) {
                ExitCode::from(2)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}

/// Whether `error` is the user's input (exit status 2) rather than a failure of the system
/// (exit status 1): a write the system refused (a full disk, a read-only folder, a quota) is
/// not bad input, though the file is ours to name.
fn is_bad_input(error: &anyhow::Error) -> bool {
    use starcages_io::FileError;
    use starcages_io::SceneFileError;
    if error.downcast_ref::<InputError>().is_some() {
        return true;
    }
    let file_error = error.downcast_ref::<FileError>().or_else(|| {
        match error.downcast_ref::<SceneFileError>() {
            Some(SceneFileError::File(file)) => Some(file),
            _ => None,
        }
    });
    match file_error {
        Some(FileError::Write { .. }) => false,
        Some(_) => true,
        None => error.downcast_ref::<SceneFileError>().is_some(),
    }
}

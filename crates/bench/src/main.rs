//! `starcages-bench`: the benchmarks, apart from the user's tool (`starcages-cli`) so that
//! the counting allocator wraps only them. Without a subcommand, *Cages against single-cage
//! baselines (and `--scale`, `--drags`, `--rest-edits`); `gpu`, GPU deformation and drawing;
//! `frame`, the editor's whole 3D frame with shading and ghosts.
//! Exit status as `starcages-cli`'s: 2 for bad input, 1 for other failures.

mod bench;
mod bench_drag;
mod bench_frame;
mod bench_gpu;
mod bench_rest_edit;
mod bench_scale;

use std::process::ExitCode;

use clap::{CommandFactory as _, FromArgMatches as _, Parser, Subcommand};
use peakmem_alloc::{INSTRUMENTED_SYSTEM, PeakMemAlloc};
use starcages_cli::{exit_status, negative_numbers_as_values, remove_unfinished_saves_on_signals};

/// The system allocator, counting the heap's peak since a reset: `--scale` reports each bind's
/// peak memory from it (two atomic adds per allocation; the binds allocate in large blocks).
#[global_allocator]
static ALLOCATOR: &PeakMemAlloc<std::alloc::System> = &INSTRUMENTED_SYSTEM;

/// StarCages benchmarks: *Cages against single-cage baselines (memory, bind, frame and move
/// times), the bind's scaling, drags and rest edits; `gpu` for the GPU path.
#[derive(Debug, Parser)]
#[command(
    name = "starcages-bench",
    version,
    about,
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    tool: Option<Tool>,
    #[command(flatten)]
    bench: bench::BenchArgs,
}

#[derive(Debug, Subcommand)]
enum Tool {
    /// GPU deformation and drawing against the CPU operator, per frame (prism demo).
    Gpu(bench_gpu::BenchGpuArgs),
    /// The editor's whole 3D frame: plain, with a look, textured, textured with ghosts.
    Frame(bench_frame::BenchFrameArgs),
}

fn main() -> ExitCode {
    remove_unfinished_saves_on_signals();
    let command =
        negative_numbers_as_values(Cli::command()).mut_subcommands(negative_numbers_as_values);
    let matches = command.get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|error| error.exit());
    exit_status(match &cli.tool {
        Some(Tool::Gpu(args)) => bench_gpu::run(args),
        Some(Tool::Frame(args)) => bench_frame::run(args),
        None => bench::run(&cli.bench),
    })
}

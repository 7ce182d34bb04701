//! The StarCages command-line tool's commands, as a library: `starcages-cli` (the user's tool)
//! runs them, and `starcages-bench` (the benchmarks, with their counting allocator) reuses
//! their loading, binding and output plumbing.
//!
//! Exit status: 0 on success, 2 when an input file or its content is bad (the message names
//! the file, the line or element, and the fix), 1 for any other failure (a write the system
//! refuses among them: a full disk is not bad input).

pub mod commands;
pub mod output;
pub mod progress;

use std::process::ExitCode;

/// An error the user caused with their input (exit status 2).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

/// Exit status after Ctrl-C or SIGTERM: 128 + SIGINT, as shells report an interrupted program.
const INTERRUPTED: i32 = 130;

/// On Ctrl-C, SIGTERM or SIGHUP: remove the temporary file of a save in progress (the target
/// keeps its old content) and exit. Without this the default action would kill the process
/// before the temporary file's destructor ran.
pub fn remove_unfinished_saves_on_signals() {
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

/// `command` with negative numbers taken as values by every long option that takes one
/// (`--margin -1` reaches the range check that names the allowed range, instead of clap's
/// "unexpected argument '-1'" and its wrong tip); values that start with a minus
/// (`--frames -10..-5`) are taken by the options whose values may (their
/// `allow_hyphen_values`).
pub fn negative_numbers_as_values(command: clap::Command) -> clap::Command {
    command.mut_args(|arg| {
        if arg.get_long().is_some() && arg.get_action().takes_values() {
            arg.allow_negative_numbers(true)
        } else {
            arg
        }
    })
}

/// The exit status for a command's result, its error printed: 2 for bad input, 1 otherwise; a
/// closed standard output is a normal end.
pub fn exit_status(result: anyhow::Result<()>) -> ExitCode {
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
pub fn is_bad_input(error: &anyhow::Error) -> bool {
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

//! Standard output and standard error for commands. Output write errors are returned naming
//! standard output, and `main` treats a closed pipe (`starcages-cli info … | head`) as a normal
//! end; diagnostics on standard error never panic (`note!`): where it cannot be written there
//! is no one left to tell, and the exit status still says how the command ended.

use std::io::Write as _;

use anyhow::Context as _;

/// Writes `text` and a newline to standard output.
pub fn line(text: impl std::fmt::Display) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    writeln!(out, "{text}")
        .and_then(|()| out.flush())
        .context("cannot write to standard output")
}

/// Writes a diagnostic to standard error, ignoring a standard error that cannot be written
/// (`eprint!` panics there).
pub fn diagnostic(text: std::fmt::Arguments<'_>) {
    let mut err = std::io::stderr().lock();
    let _ = err.write_fmt(text).and_then(|()| err.flush());
}

/// `eprintln!` that never panics (see [`diagnostic`]).
#[macro_export]
macro_rules! note {
    () => {
        $crate::output::diagnostic(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::output::diagnostic(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `eprint!` that never panics (see [`diagnostic`]).
#[macro_export]
macro_rules! note_inline {
    ($($arg:tt)*) => {
        $crate::output::diagnostic(format_args!($($arg)*))
    };
}

/// Whether an error chain ends in a closed standard output pipe.
pub fn is_broken_pipe(error: &anyhow::Error) -> bool {
    error.chain().any(|e| {
        e.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

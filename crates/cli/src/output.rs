//! Standard output for commands: write errors are returned, and `main` treats a closed pipe
//! (`starcages-cli info … | head`) as a normal end instead of a panic.

use std::io::Write as _;

/// Writes `text` and a newline to standard output.
pub fn line(text: impl std::fmt::Display) -> std::io::Result<()> {
    let mut out = std::io::stdout().lock();
    writeln!(out, "{text}")?;
    out.flush()
}

/// Whether an error chain ends in a closed standard output pipe.
pub fn is_broken_pipe(error: &anyhow::Error) -> bool {
    error.chain().any(|e| {
        e.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

//! `starcages-cli validate`: print a scene's diagnostics; exit 0 only for a valid scene.

use std::path::PathBuf;

use clap::Args;

use crate::InputError;

/// Arguments of `validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// Scene file.
    scene: PathBuf,
}

/// Runs the command.
pub fn run(args: &ValidateArgs) -> anyhow::Result<()> {
    let scene = super::load(&args.scene)?;
    let report = super::report(&scene, &args.scene.display().to_string()).report;
    if report.is_valid() {
        crate::output::line(format_args!(
            "{}: valid ({} leaf cages, {} internal)",
            args.scene.display(),
            scene.cages.leaves.len(),
            scene.cages.internals.len()
        ))?;
        Ok(())
    } else {
        Err(InputError(format!(
            "{}: {} problem(s), listed above",
            args.scene.display(),
            report.errors.len()
        ))
        .into())
    }
}

//! One module per subcommand.

pub mod autocage;
pub mod bench;
pub mod cages;
pub mod deform;
pub mod demo;
pub mod eval;
pub mod info;
pub mod new;
pub mod pose;
pub mod validate;
pub mod weights;

use std::path::Path;

use starcages_core::scene::{Scene, ValidationReport, load_scene, validate_scene};

/// Loads a scene file (errors are input errors: exit status 2).
pub fn load(path: &Path) -> anyhow::Result<Scene> {
    Ok(load_scene(path)?)
}

/// Saves a new scene, prints its diagnostics and `summary`; an invalid scene is still written
/// (so it can be fixed) but the command fails with status 2.
pub fn save_new_scene(scene: &Scene, out: &Path, summary: &str) -> anyhow::Result<()> {
    starcages_core::scene::save_scene(scene, out)?;
    let report = report(scene, &out.display().to_string());
    crate::output::line(format_args!("{}: {summary}", out.display()))?;
    if report.is_valid() {
        Ok(())
    } else {
        Err(crate::InputError(
            "the scene was written but does not validate; see the problems above".into(),
        )
        .into())
    }
}

/// Prints a validation report to standard error; returns whether the scene is valid.
pub fn report(scene: &Scene, label: &str) -> ValidationReport {
    let report = validate_scene(scene);
    for warning in &report.warnings {
        eprintln!("warning: {label}: {warning}");
    }
    for error in &report.errors {
        eprintln!("error: {label}: {error}");
    }
    report
}

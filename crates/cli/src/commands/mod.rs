//! One module per subcommand.

pub mod autocage;
pub mod cages;
pub mod demo;
pub mod info;
pub mod new;
pub mod validate;
pub mod weights;

use std::path::Path;

use starcages_core::scene::{Scene, ValidationReport, load_scene, validate_scene};

/// Loads a scene file (errors are input errors: exit status 2).
pub fn load(path: &Path) -> anyhow::Result<Scene> {
    Ok(load_scene(path)?)
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

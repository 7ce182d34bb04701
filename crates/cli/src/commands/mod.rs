//! One module per subcommand.

pub mod autocage;
pub mod autorig;
pub mod bake;
pub mod cages;
pub mod deform;
pub mod demo;
pub mod edit;
pub mod eval;
pub mod frames;
pub mod info;
pub mod internal_cage;
pub mod new;
pub mod pose;
pub mod render;
pub mod validate;
pub mod weights;

use std::path::Path;

use starcages_core::check::{CheckedScene, check_scene};
use starcages_core::scene::{MeshSource, Scene};
use starcages_io::load_scene;

/// Loads a scene file (errors are input errors: exit status 2).
pub fn load(path: &Path) -> anyhow::Result<Scene> {
    Ok(load_scene(path)?)
}

/// Saves a new scene, prints its diagnostics and `summary`; an invalid scene is still written
/// (so it can be fixed) but the command fails with status 2.
pub fn save_new_scene(scene: &Scene, out: &Path, summary: &str) -> anyhow::Result<()> {
    starcages_io::save_scene(scene, out)?;
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
pub fn report(scene: &Scene, label: &str) -> CheckedScene {
    let checked = check_scene(scene);
    print_capped("warning", label, &checked.report.warnings);
    print_capped("error", label, &checked.report.errors);
    checked
}

/// The most problems of one severity printed for a scene: a file with millions of problems
/// gets a summary line, not millions of lines.
pub const MAX_PROBLEMS_SHOWN: usize = 50;

/// Prints up to [`MAX_PROBLEMS_SHOWN`] of `problems`, then how many more there are.
fn print_capped(severity: &str, label: &str, problems: &[impl std::fmt::Display]) {
    for problem in problems.iter().take(MAX_PROBLEMS_SHOWN) {
        crate::note!("{severity}: {label}: {problem}");
    }
    if problems.len() > MAX_PROBLEMS_SHOWN {
        crate::note!(
            "{severity}: {label}: … and {} more ({} in all); fix the ones above first, most \
             repeat the same mistake",
            problems.len() - MAX_PROBLEMS_SHOWN,
            problems.len()
        );
    }
}

/// Three counts NX NY NZ given to `flag`, each in 1..=`max`.
pub fn three_counts(values: &[u32], flag: &str, max: u32) -> anyhow::Result<[u32; 3]> {
    let counts: [u32; 3] = values
        .try_into()
        .map_err(|_| crate::InputError(format!("{flag} needs three numbers: NX NY NZ")))?;
    if counts.iter().any(|&n| n == 0 || n > max) {
        return Err(crate::InputError(format!(
            "{flag} {counts:?}: each count must be between 1 and {max}"
        ))
        .into());
    }
    Ok(counts)
}

/// Reads a mesh file for a new scene, turned to the scene's Z-up: glTF is Y-up by
/// specification and FBX is read Y-up from the axes it declares; OBJ, PLY, STL and OFF by
/// `--up` (Y-up, the convention, unless told otherwise). Returns the mesh and the up axis the
/// scene records.
pub fn read_new_scene_mesh(
    path: &std::path::Path,
    up: Option<starcages_core::scene::UpAxis>,
) -> anyhow::Result<(starcages_core::mesh::Mesh, starcages_core::scene::UpAxis)> {
    use starcages_core::scene::UpAxis;
    let up = match (starcages_io::declares_axes(path), up) {
        (true, Some(UpAxis::Z)) => {
            return Err(crate::InputError(format!(
                "--up z: {} declares its own axes (glTF is Y-up by specification; FBX is read \
                 Y-up from the axes its header names); --up applies to OBJ, PLY, STL and OFF \
                 files",
                path.display()
            ))
            .into());
        }
        (_, Some(up)) => up,
        (_, None) => UpAxis::Y,
    };
    Ok((starcages_io::read_mesh_as(path, up)?, up))
}

/// A padding fraction in [0, 10].
pub fn check_padding(padding: f64) -> anyhow::Result<()> {
    if (0.0..=10.0).contains(&padding) {
        Ok(())
    } else {
        Err(crate::InputError(format!(
            "--padding {padding} is out of range; use a value in [0, 10]"
        ))
        .into())
    }
}

/// Refuses an output path before any long work: one that would overwrite one of the
/// command's `inputs` (often in another format, losing it), one whose folder does not exist,
/// and one whose extension the command does not write (`extensions`, lower case).
pub fn check_output(
    flag: &str,
    out: &Path,
    inputs: &[&Path],
    extensions: &[&str],
) -> anyhow::Result<()> {
    let extension = out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    if !extensions.contains(&extension.as_str()) {
        let list: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
        return Err(crate::InputError(format!(
            "{flag} {}: this command writes {}; choose a name ending in one of them",
            out.display(),
            list.join(" or ")
        ))
        .into());
    }
    let folder = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        return Err(crate::InputError(format!(
            "{flag} {}: the folder {} does not exist; create it first",
            out.display(),
            folder.display()
        ))
        .into());
    }
    if let Some(input) = inputs
        .iter()
        .find(|input| starcages_io::is_same_file(out, input))
    {
        return Err(crate::InputError(format!(
            "{flag} {} is the command's input {}; writing it would destroy that input, choose \
             another output file",
            out.display(),
            input.display()
        ))
        .into());
    }
    Ok(())
}

/// The scene's mesh file, if it has one (an input that no output may overwrite).
pub fn mesh_file(scene: &Scene) -> Option<&Path> {
    match &scene.mesh_source {
        MeshSource::File(path) => Some(path),
        MeshSource::Embedded => None,
    }
}

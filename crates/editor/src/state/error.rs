//! [`EditorError`]: everything that can go wrong in the editor, each shown once in the status
//! bar with what to do next.

use std::path::PathBuf;

use starcages_core::hierarchy::{AutoInternalCageError, HierarchyError, RemoveInternalCageError};
use starcages_core::star::StarError;
use starcages_io::FileError;
use starcages_io::SceneFileError;

/// An error of an editor operation. The core's errors already name the file, line or element;
/// these variants add what the editor did and what stays as it was.
#[derive(Debug, thiserror::Error)]
pub enum EditorError {
    /// A file that cannot be opened at all (checked before any question about unsaved work).
    #[error("cannot open {}: {why}. The current scene is unchanged", path.display())]
    CannotOpen {
        /// The file.
        path: PathBuf,
        /// Why: its type, or that it is not a file.
        why: String,
    },
    /// A scene file could not be read.
    #[error("could not open {0}. The current scene is unchanged")]
    OpenScene(#[source] SceneFileError),
    /// No demo of that name.
    #[error("there is no demo '{0}'; File > Open demo lists them")]
    UnknownDemo(String),
    /// The auto rig could not rig the mesh (or was cancelled).
    #[error("{0}. The current scene is unchanged")]
    AutoRig(#[source] starcages_core::generate::AutorigError),
    /// A mesh file could not be read.
    #[error("could not open {0}. The current scene is unchanged")]
    OpenMesh(#[source] FileError),
    /// The scene file was read but is not a valid scene.
    #[error(
        "could not open {}: {problem} ({count} problem(s); `starcages-cli validate` lists them all). The current scene is unchanged",
        path.display()
    )]
    InvalidScene {
        /// The file.
        path: PathBuf,
        /// The first problem.
        problem: String,
        /// How many problems.
        count: usize,
    },
    /// Saving failed; the file on disk is untouched (saves are atomic).
    #[error("could not save: {0}. Nothing was overwritten")]
    Save(#[source] SceneFileError),
    /// Writing an export failed.
    #[error("could not export: {0}")]
    Export(#[source] FileError),
    /// The mesh binding failed.
    #[error(
        "binding failed: {0}. The previous binding stays in use; undo (Ctrl+Z) the last change or fix the scene"
    )]
    Bind(#[source] StarError),
    /// The internal cages could not be bound.
    #[error(
        "the internal cages could not be bound: {0}. The previous binding stays in use; undo (Ctrl+Z) the last change"
    )]
    Hierarchy(#[source] HierarchyError),
    /// The single-cage baseline of the difference map failed.
    #[error("the single-cage baseline of the difference map could not be bound: {0}")]
    Baseline(#[source] StarError),
    /// Adding an internal cage failed.
    #[error("{0}")]
    AddInternalCage(#[source] AutoInternalCageError),
    /// Removing an internal cage failed.
    #[error("{0}")]
    RemoveInternalCage(#[source] RemoveInternalCageError),
    /// A hand edit could not be propagated through the hierarchy.
    #[error("the move could not be applied: {0}")]
    Move(#[source] HierarchyError),
    /// A worker thread ended without an answer (it panicked).
    #[error("the {0} worker stopped unexpectedly; try again")]
    WorkerLost(&'static str),
    /// A rig operation could not apply (the reason names the operation's problem).
    #[error("{0}")]
    Rig(String),
    /// The action needs a binding that is not there yet.
    #[error("the scene is still being bound; try again in a moment")]
    NotBound,
    /// The action needs the full binding, and only the quick preview is in use.
    #[error(
        "the binding in use is a quick preview (mean value join cages); the full bind with \
         harmonic join cages is running: export again when it has finished"
    )]
    PreviewOnly,
    /// An export over the scene's own mesh or scene file.
    #[error(
        "{} is the scene's own mesh or scene file; exporting over it would destroy it, choose another file",
        .0.display()
    )]
    OutputIsInput(PathBuf),
    /// Saving to the document's own file, which it does not have yet.
    #[error("this scene has no file yet: use File > Save as… to choose one")]
    NoFile,
    /// A pose name that cannot be used.
    #[error("{0}")]
    Pose(String),
    /// A key edit that cannot be made.
    #[error("{0}")]
    Animation(String),
    /// A cage point cache could not be read.
    #[error("could not import the cage animation: {0}. The animation is unchanged")]
    ImportCageAnimation(#[source] FileError),
}

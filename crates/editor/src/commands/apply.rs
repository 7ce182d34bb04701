//! The one place that changes the editor's state: each command goes to its domain's module
//! (files, jobs, history, rig, pose, selection, view, animation), which records its undo point
//! (one per gesture), changes the document or the view, revalidates what depends on the
//! document and schedules binds in the background. The dispatch below names every command, so
//! a new one does not compile until it has a domain.

use super::{Command, Effect};
use crate::state::EditorState;

/// Carries out `commands` in order.
pub fn apply_all(state: &mut EditorState, commands: Vec<Command>) -> Vec<Effect> {
    commands
        .into_iter()
        .flat_map(|command| apply(state, command))
        .collect()
}

/// Carries out one command; returns what it asks of the UI (E's grab).
pub fn apply(state: &mut EditorState, command: Command) -> Vec<Effect> {
    let mut effects = Vec::new();
    apply_to(state, command, &mut effects);
    effects
}

/// [`apply`], the effects pushed onto `effects`.
fn apply_to(state: &mut EditorState, command: Command, effects: &mut Vec<Effect>) {
    match command {
        command @ (Command::SetFrame(_)
        | Command::SetPlaying(_)
        | Command::InsertKey
        | Command::DeleteKey(_)
        | Command::MoveKey { .. }
        | Command::SetKeyInterpolation { .. }
        | Command::SetAnimationRange { .. }
        | Command::SetAutoKey(_)
        | Command::ImportCageAnimation(_)) => super::animation::apply_animation(state, command),
        command @ (Command::Open(..)
        | Command::OpenDemo(..)
        | Command::NewFromMesh(..)
        | Command::Save
        | Command::SaveAs(..)
        | Command::ExportMesh(..)
        | Command::ExportCages(..)
        | Command::ImportCages(..)
        | Command::ImportInternalCages(..)
        | Command::AnswerUnsaved(..)
        | Command::RequestClose) => super::files::apply_files(state, command),
        command @ (Command::AutoRig { .. }
        | Command::CancelAutoRig
        | Command::CancelLoad
        | Command::CancelBind
        | Command::CancelBaseline) => super::jobs::apply_jobs(state, command),
        command @ (Command::Undo
        | Command::Redo
        | Command::BeginGesture { .. }
        | Command::EndGesture { .. }) => super::history::apply_history(state, command),
        command @ (Command::MoveRestVertices(..)
        | Command::SetCageKind(..)
        | Command::SetCageH { .. }
        | Command::SetBorderH { .. }
        | Command::SetSettings { .. }
        | Command::AddInternalCage(..)
        | Command::RemoveInternalCage(..)
        | Command::Rig(..)
        | Command::RigOps(..)
        | Command::SetMode(..)) => super::rig::apply_rig(state, command, effects),
        command @ (Command::MoveVertices(..)
        | Command::StorePose(..)
        | Command::SwitchPose(..)
        | Command::DeletePose(..)) => super::pose::apply_pose(state, command),
        command @ (Command::SelectFaces { .. }
        | Command::SetSelectElement(..)
        | Command::SelectMeshVertices { .. }
        | Command::Select { .. }
        | Command::SelectAll
        | Command::SelectNone
        | Command::InspectCage(..)
        | Command::Hover(..)) => super::selection::apply_selection(state, command),
        command @ (Command::SetCageHidden(..)
        | Command::SetLayers(..)
        | Command::SetGhosts(..)
        | Command::SetInfluence(..)
        | Command::SetMirrorX(..)
        | Command::SetSnapToVertices(..)
        | Command::SetPivotPoint(..)
        | Command::SetLeafVertices(..)
        | Command::SetCursor(..)
        | Command::Camera(..)
        | Command::SetViewport(..)
        | Command::Info(..)) => super::view::apply_view(state, command),
    }
}

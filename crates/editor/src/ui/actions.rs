//! Carrying out a [`UiCommand`] from a menu or a key: file dialogs and the G / R / S tool are
//! the UI's; everything else becomes a [`Command`].

use glam::Vec2;
use starcages_viewport::View;

use super::UiState;
use super::file_dialog::FilePurpose;
use super::transform_tool::{Axis, Mode, TransformTool};
use crate::commands::{CameraChange, Command, CommandSender, UiCommand, UnsavedAnswer};
use crate::state::{EditMode, EditorState, NewMeshOptions};

/// Carries out `action` with the pointer at `pointer` (screen points; for G / R / S).
pub fn execute(
    action: UiCommand,
    state: &EditorState,
    ui_state: &mut UiState,
    pointer: Vec2,
    sender: &mut CommandSender,
) {
    let camera = |change| Command::Camera(change);
    let animation = &state.doc.scene.animation;
    let mut choose = |purpose: FilePurpose| {
        let name = purpose.suggested_name_for(state);
        ui_state.files.request(purpose, name, None);
    };
    let command = match action {
        UiCommand::NewFromMesh => return choose(FilePurpose::NewFromMesh),
        UiCommand::Open => return choose(FilePurpose::Open),
        UiCommand::Save if state.doc.path.is_some() => Command::Save,
        UiCommand::Save | UiCommand::SaveAs => return choose(FilePurpose::SaveScene),
        UiCommand::ExportMesh => return choose(FilePurpose::ExportMesh),
        UiCommand::ExportCages => return choose(FilePurpose::ExportCages),
        UiCommand::ImportCages => return choose(FilePurpose::ImportCages),
        UiCommand::ImportInternalCages => return choose(FilePurpose::ImportInternalCages),
        UiCommand::Undo => Command::Undo,
        UiCommand::Redo => Command::Redo,
        UiCommand::ToggleMirrorX => Command::SetMirrorX(!state.view.mirror_x),
        UiCommand::SelectAll => Command::SelectAll,
        UiCommand::SelectNone => Command::SelectNone,
        UiCommand::Grab => return start_tool(Mode::Grab, state, ui_state, pointer, sender),
        UiCommand::Rotate => return start_tool(Mode::Rotate, state, ui_state, pointer, sender),
        UiCommand::Scale => return start_tool(Mode::Scale, state, ui_state, pointer, sender),
        UiCommand::FrameAll => camera(CameraChange::FrameAll),
        UiCommand::FrameSelection => camera(CameraChange::FrameSelection),
        UiCommand::ViewFront => camera(CameraChange::View(View::Front)),
        UiCommand::ViewSide => camera(CameraChange::View(View::Side)),
        UiCommand::ViewTop => camera(CameraChange::View(View::Top)),
        UiCommand::ViewBack => camera(CameraChange::View(View::Back)),
        UiCommand::ViewLeft => camera(CameraChange::View(View::Left)),
        UiCommand::ViewBottom => camera(CameraChange::View(View::Bottom)),
        UiCommand::ToggleOrthographic => camera(CameraChange::ToggleOrthographic),
        UiCommand::ToggleItemPanel => {
            ui_state.show_item_panel = !ui_state.show_item_panel;
            // The Item panel lives in the right panel: showing it shows that.
            ui_state.show_properties |= ui_state.show_item_panel;
            return;
        }
        UiCommand::ToggleXray => {
            let mut layers = state.view.layers;
            layers.xray = !layers.xray;
            Command::SetLayers(layers)
        }
        UiCommand::ToggleOutliner => {
            ui_state.show_outliner = !ui_state.show_outliner;
            return;
        }
        UiCommand::ToggleProperties => {
            ui_state.show_properties = !ui_state.show_properties;
            return;
        }
        UiCommand::ShowShortcuts => {
            ui_state.show_shortcuts = !ui_state.show_shortcuts;
            return;
        }
        UiCommand::ToggleMode => Command::SetMode(match state.mode {
            EditMode::Pose => EditMode::Rig,
            EditMode::Rig => EditMode::Pose,
        }),
        UiCommand::Extrude
        | UiCommand::InsetFaces
        | UiCommand::LoopCut
        | UiCommand::AddBox
        | UiCommand::DeleteCage
        | UiCommand::MergeCages
        | UiCommand::MirrorCage
        | UiCommand::FitCage
        | UiCommand::SubdivideCages
            if state.mode == EditMode::Pose =>
        {
            Command::Info(format!(
                "{}: Rig mode only (it edits the rest cages); Tab switches to Rig mode",
                action.label()
            ))
        }
        UiCommand::Extrude if !state.selection.faces.is_empty() => {
            match super::rig_keys::extrude_faces(state) {
                Ok(ops) => Command::RigOps(ops),
                Err(why) => Command::Info(why),
            }
        }
        UiCommand::Extrude => rig(super::rig_keys::extrude(state)),
        UiCommand::InsetFaces => {
            match super::inset_tool::InsetTool::begin(state, pointer - state.view.viewport.min) {
                Ok(inset) => {
                    ui_state.inset = Some(inset);
                    return;
                }
                Err(why) => Command::Info(why),
            }
        }
        UiCommand::LoopCut => match super::loop_cut_tool::LoopCutTool::begin(state) {
            Ok(cut) => {
                ui_state.loop_cut = Some(cut);
                return;
            }
            Err(why) => Command::Info(why),
        },
        UiCommand::AddBox => {
            ui_state.add_menu = Some(pointer);
            return;
        }
        UiCommand::DeleteCage => rig(super::rig_keys::delete(state)),
        UiCommand::MergeCages => rig(super::rig_keys::merge(state)),
        UiCommand::MirrorCage => rig(super::rig_keys::mirror(state)),
        UiCommand::FitCage => rig(super::rig_keys::fit(state)),
        UiCommand::SubdivideCages => rig(Ok(starcages_core::rig::RigOp::Subdivide)),
        UiCommand::ImportCageAnimation => return choose(FilePurpose::ImportCageAnimation),
        UiCommand::PlayPause => Command::SetPlaying(state.timeline.playing.is_none()),
        UiCommand::JumpToStart => Command::SetFrame(animation.frame_start as f64),
        UiCommand::JumpToEnd => Command::SetFrame(animation.frame_end as f64),
        UiCommand::NextFrame => Command::SetFrame(state.timeline.frame + 1.0),
        UiCommand::PreviousFrame => Command::SetFrame(state.timeline.frame - 1.0),
        UiCommand::NextKey | UiCommand::PreviousKey => {
            let frame = state.timeline.frame;
            let found = if action == UiCommand::NextKey {
                animation.next_key_frame(frame)
            } else {
                animation.previous_key_frame(frame)
            };
            match found {
                Some(key) => Command::SetFrame(key),
                None => Command::Info("no key further that way".into()),
            }
        }
        UiCommand::InsertKey | UiCommand::DeleteKey if state.mode == EditMode::Rig => {
            Command::Info(format!(
                "{}: Pose mode only (keys hold poses); Tab switches to Pose mode",
                action.label()
            ))
        }
        UiCommand::InsertKey => Command::InsertKey,
        UiCommand::DeleteKey => match super::timeline::selected_or_current_key(state, ui_state) {
            Some(frame) => {
                ui_state.selected_key = None;
                Command::DeleteKey(frame)
            }
            None => Command::Info(
                "no key here: select a key on the timeline, or go to a keyed frame".into(),
            ),
        },
        UiCommand::ToggleAutoKey => Command::SetAutoKey(!state.timeline.auto_key),
        UiCommand::AutoRig => {
            ui_state.autorig_dialog = Some(super::prompts::AutorigDialog::default());
            return;
        }
    };
    sender.send(command);
}

/// A rig operation, or why there is none (said in the status bar).
fn rig(op: Result<starcages_core::rig::RigOp, String>) -> Command {
    match op {
        Ok(op) => Command::Rig(op),
        Err(why) => Command::Info(why),
    }
}

/// Carries out what a file was chosen for.
pub fn file_chosen(
    purpose: FilePurpose,
    path: std::path::PathBuf,
    ui_state: &mut UiState,
    sender: &mut CommandSender,
) {
    let command = match purpose {
        FilePurpose::Open => Command::Open(path),
        FilePurpose::NewFromMesh => {
            ui_state.new_mesh_dialog = Some((path, NewMeshOptions::default()));
            return;
        }
        FilePurpose::SaveScene => Command::SaveAs(path),
        FilePurpose::SaveBeforeContinuing => {
            Command::AnswerUnsaved(UnsavedAnswer::Save(Some(path)))
        }
        FilePurpose::ExportMesh => Command::ExportMesh(path),
        FilePurpose::ExportCages => Command::ExportCages(path),
        FilePurpose::ImportCages => Command::ImportCages(path),
        FilePurpose::ImportInternalCages => Command::ImportInternalCages(path),
        FilePurpose::ImportCageAnimation => Command::ImportCageAnimation(path),
    };
    sender.send(command);
}

/// G on the selection with the axis `axis` (0 x, 1 y, 2 z) locked.
pub fn grab_along(
    state: &EditorState,
    ui_state: &mut UiState,
    pointer: Vec2,
    axis: usize,
    sender: &mut CommandSender,
) {
    start_tool(Mode::Grab, state, ui_state, pointer, sender);
    if let Some(tool) = &mut ui_state.tool {
        tool.axis = Some([Axis::X, Axis::Y, Axis::Z][axis.min(2)]);
    }
}

fn start_tool(
    mode: Mode,
    state: &EditorState,
    ui_state: &mut UiState,
    pointer: Vec2,
    sender: &mut CommandSender,
) {
    if ui_state.tool.is_some() {
        return;
    }
    let gesture = ui_state.new_gesture();
    match TransformTool::begin(state, mode, pointer, gesture) {
        Some(tool) => {
            ui_state.tool = Some(tool);
            sender.send(Command::BeginGesture {
                id: gesture,
                label: mode.label().into(),
            });
        }
        None => sender.send(Command::Info(
            "select cage vertices first (click, Shift+click, drag a rectangle, or A)".into(),
        )),
    }
}

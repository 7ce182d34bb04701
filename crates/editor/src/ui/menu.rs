//! The menu bar, built from the [`UiCommand`] table (labels, shortcuts, tooltips).

use super::UiState;
use super::actions::execute;
use crate::commands::{Command, CommandSender, UiCommand};
use crate::state::EditorState;

/// File, Edit, Select, View.
pub fn menu_bar(
    state: &EditorState,
    ui_state: &mut UiState,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    let pointer = state.view.viewport.center();
    let mut chosen = None;
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            item(ui, UiCommand::NewFromMesh, None, true, &mut chosen);
            item(ui, UiCommand::Open, None, true, &mut chosen);
            ui.menu_button("Open recent", |ui| {
                if state.recent.is_empty() {
                    ui.label("nothing yet");
                }
                for path in &state.recent {
                    if ui
                        .button(path.display().to_string())
                        .on_hover_text("Open this file again")
                        .clicked()
                    {
                        sender.send(Command::Open(path.clone()));
                    }
                }
            });
            ui.menu_button("Open demo", |ui| {
                for (name, description) in starcages_core::generate::demo::DEMOS {
                    if ui.button(name).on_hover_text(description).clicked() {
                        sender.send(Command::OpenDemo(name.to_owned()));
                    }
                }
            });
            ui.separator();
            item(ui, UiCommand::Save, None, true, &mut chosen);
            item(ui, UiCommand::SaveAs, None, true, &mut chosen);
            ui.separator();
            item(
                ui,
                UiCommand::ExportMesh,
                None,
                state.rig.is_some(),
                &mut chosen,
            );
            item(ui, UiCommand::ExportCages, None, true, &mut chosen);
            item(ui, UiCommand::ImportCages, None, true, &mut chosen);
            item(ui, UiCommand::ImportInternalCages, None, true, &mut chosen);
            item(ui, UiCommand::ImportCageAnimation, None, true, &mut chosen);
        });
        ui.menu_button("Edit", |ui| {
            let undo = state.undo.undo_label();
            let redo = state.undo.redo_label();
            item(ui, UiCommand::Undo, undo, undo.is_some(), &mut chosen);
            item(ui, UiCommand::Redo, redo, redo.is_some(), &mut chosen);
            ui.separator();
            let mode = match state.mode {
                crate::state::EditMode::Pose => "(now Pose)",
                crate::state::EditMode::Rig => "(now Rig)",
            };
            item(ui, UiCommand::ToggleMode, Some(mode), true, &mut chosen);
            ui.separator();
            let mut mirror = state.view.mirror_x;
            if ui
                .checkbox(&mut mirror, UiCommand::ToggleMirrorX.label())
                .on_hover_text(UiCommand::ToggleMirrorX.tooltip())
                .changed()
            {
                sender.send(Command::SetMirrorX(mirror));
            }
        });
        ui.menu_button("Select", |ui| {
            for action in [UiCommand::SelectAll, UiCommand::SelectNone] {
                item(ui, action, None, true, &mut chosen);
            }
            ui.separator();
            for action in [UiCommand::Grab, UiCommand::Rotate, UiCommand::Scale] {
                let enabled = !state.selection.vertices.is_empty();
                item(ui, action, None, enabled, &mut chosen);
            }
        });
        ui.menu_button("View", |ui| {
            for action in [
                UiCommand::FrameAll,
                UiCommand::FrameSelection,
                UiCommand::ViewFront,
                UiCommand::ViewSide,
                UiCommand::ViewTop,
                UiCommand::ViewBack,
                UiCommand::ViewLeft,
                UiCommand::ViewBottom,
            ] {
                item(ui, action, None, true, &mut chosen);
            }
            ui.separator();
            ui.menu_button("Shading", |ui| {
                super::shading::shading_controls(state, ui, sender);
            });
            ui.menu_button("Ghosts", |ui| {
                super::shading::ghost_controls(state, ui, sender);
            });
            item(ui, UiCommand::ToggleItemPanel, None, true, &mut chosen);
            item(ui, UiCommand::ToggleXray, None, true, &mut chosen);
            item(ui, UiCommand::ToggleOutliner, None, true, &mut chosen);
            item(ui, UiCommand::ToggleProperties, None, true, &mut chosen);
            let projection = if state.view.camera.orthographic {
                "(now orthographic)"
            } else {
                "(now perspective)"
            };
            item(
                ui,
                UiCommand::ToggleOrthographic,
                Some(projection),
                true,
                &mut chosen,
            );
        });
        ui.menu_button("Rig", |ui| {
            let rig = state.mode == crate::state::EditMode::Rig;
            for action in [
                UiCommand::Extrude,
                UiCommand::InsetFaces,
                UiCommand::LoopCut,
            ] {
                item(ui, action, None, rig, &mut chosen);
            }
            ui.add_enabled_ui(rig, |ui| {
                ui.menu_button(UiCommand::AddBox.label(), |ui| {
                    let opened = super::add_menu::Opened::FromMenu;
                    if super::add_menu::entries(state, ui, opened, sender) {
                        ui.close();
                    }
                })
                .response
                .on_hover_text(UiCommand::AddBox.tooltip());
            });
            for action in [
                UiCommand::DeleteCage,
                UiCommand::MergeCages,
                UiCommand::MirrorCage,
                UiCommand::FitCage,
                UiCommand::SubdivideCages,
            ] {
                item(ui, action, None, rig, &mut chosen);
            }
            ui.separator();
            item(ui, UiCommand::AutoRig, None, true, &mut chosen);
        });
        ui.menu_button("Animation", |ui| {
            for action in [
                UiCommand::PlayPause,
                UiCommand::JumpToStart,
                UiCommand::JumpToEnd,
                UiCommand::NextFrame,
                UiCommand::PreviousFrame,
                UiCommand::NextKey,
                UiCommand::PreviousKey,
                UiCommand::InsertKey,
                UiCommand::DeleteKey,
            ] {
                item(ui, action, None, true, &mut chosen);
            }
            let mut auto_key = state.timeline.auto_key;
            if ui
                .checkbox(&mut auto_key, UiCommand::ToggleAutoKey.label())
                .on_hover_text(UiCommand::ToggleAutoKey.tooltip())
                .changed()
            {
                chosen = Some(UiCommand::ToggleAutoKey);
            }
        });
        ui.menu_button("Help", |ui| {
            item(ui, UiCommand::ShowShortcuts, None, true, &mut chosen);
        });
    });
    if let Some(action) = chosen {
        execute(action, state, ui_state, pointer, sender);
    }
}

/// One menu entry: the table's label (with `detail` after it), its first shortcut and its
/// tooltip; sets `chosen` when clicked.
fn item(
    ui: &mut egui::Ui,
    action: UiCommand,
    detail: Option<&str>,
    enabled: bool,
    chosen: &mut Option<UiCommand>,
) {
    let label = match detail {
        Some(detail) => format!("{} {detail}", action.label()),
        None => action.label().to_owned(),
    };
    let mut button = egui::Button::new(label);
    if let Some(shortcut) = action.shortcuts().first() {
        button = button.shortcut_text(ui.ctx().format_shortcut(shortcut));
    }
    if ui
        .add_enabled(enabled, button)
        .on_hover_text(action.tooltip())
        .clicked()
    {
        *chosen = Some(action);
        ui.close();
    }
}

//! Modal prompts: unsaved changes (Save / Don't save / Cancel) and File ▸ New from mesh's
//! automatic-cages dialog.

use super::UiState;
use super::file_dialog::FilePurpose;
use super::inspector::{KINDS, kind_name};
use crate::commands::{Command, CommandSender, UnsavedAnswer};
use crate::state::{EditorState, NewRig};
use starcages_core::generate::Mirror;
use starcages_core::scene::UpAxis;
use starcages_io::declares_axes;

/// "Unsaved changes" while an action waits for the answer.
pub fn unsaved_prompt(
    state: &EditorState,
    ui_state: &mut UiState,
    ctx: &egui::Context,
    sender: &mut CommandSender,
) {
    // Hidden while a file dialog asks where to save (it would cover that dialog); shown again
    // if that one is cancelled.
    if state.pending.is_none() || ui_state.files.is_open() {
        return;
    }
    let mut answer = None;
    egui::Modal::new(egui::Id::unique("unsaved-changes")).show(ctx, |ui| {
        ui.heading("Unsaved changes");
        ui.label(format!(
            "{} has changes that are not saved.",
            state.doc.name()
        ));
        if let Some(loaded) = &state.loaded {
            ui.label(format!(
                "{} is read and opens in its place.",
                loaded.source_name()
            ));
        }
        ui.horizontal(|ui| {
            if ui.button("Save").clicked() {
                if state.doc.path.is_some() {
                    answer = Some(UnsavedAnswer::Save(None));
                } else {
                    // Answered when a file is chosen (or not, if the dialog is cancelled).
                    let purpose = FilePurpose::SaveBeforeContinuing;
                    let name = purpose.suggested_name_for(state);
                    ui_state.files.request(purpose, name, None);
                }
            }
            if ui.button("Don't save").clicked() {
                answer = Some(UnsavedAnswer::Discard);
            }
            if ui.button("Cancel").clicked() {
                answer = Some(UnsavedAnswer::Cancel);
            }
        });
    });
    if let Some(answer) = answer {
        sender.send(Command::AnswerUnsaved(answer));
    }
}

/// How an up axis is offered in the New from mesh dialog.
fn up_name(up: UpAxis) -> &'static str {
    match up {
        UpAxis::Y => "Y up (OBJ convention)",
        UpAxis::Z => "Z up (read as is)",
    }
}

/// File ▸ New from mesh: the auto rig (its detail and symmetry) or the automatic grid (size, padding,
/// coordinates), and the file's up axis.
pub fn new_mesh_dialog(ui_state: &mut UiState, ctx: &egui::Context, sender: &mut CommandSender) {
    let Some((path, options)) = &mut ui_state.new_mesh_dialog else {
        return;
    };
    let mut answer = None;
    egui::Modal::new(egui::Id::unique("new-from-mesh")).show(ctx, |ui| {
        ui.heading("New from mesh");
        ui.label(path.display().to_string());
        ui.horizontal(|ui| {
            ui.label("Cages");
            ui.radio_value(&mut options.rig, NewRig::Auto, "Auto rig")
                .on_hover_text("chains of cages along the limbs, a few across the body");
            ui.radio_value(&mut options.rig, NewRig::Grid, "Box grid")
                .on_hover_text("a regular grid of box cages around the mesh");
        });
        match options.rig {
            NewRig::Auto => {
                ui.add(egui::Slider::new(&mut options.detail, 1..=5).text("detail"))
                    .on_hover_text("1: few, coarse cages; 5: many, tight ones");
                symmetry_choice(ui, &mut options.mirror);
            }
            NewRig::Grid => {
                ui.horizontal(|ui| {
                    ui.label("Grid cells");
                    for n in &mut options.cages.grid {
                        ui.add(egui::DragValue::new(n).range(1..=16));
                    }
                });
                ui.add(egui::Slider::new(&mut options.cages.padding, 0.0..=0.5).text("padding"));
                egui::ComboBox::from_label("Coordinates")
                    .selected_text(kind_name(options.cages.kind))
                    .show_ui(ui, |ui| {
                        for k in KINDS {
                            ui.selectable_value(&mut options.cages.kind, k, kind_name(k));
                        }
                    });
            }
        }
        if declares_axes(path) {
            ui.label(
                "Up axis: Y (glTF is Y-up by specification; FBX is turned to Y-up from the axes \
                 it declares), turned to Z-up",
            );
        } else {
            egui::ComboBox::from_label("Up axis of the file")
                .selected_text(up_name(options.up))
                .show_ui(ui, |ui| {
                    for up in [UpAxis::Y, UpAxis::Z] {
                        ui.selectable_value(&mut options.up, up, up_name(up));
                    }
                })
                .response
                .on_hover_text(
                    "OBJ files are Y-up by convention (Blender's OBJ export); they are turned \
                     to StarCages' Z-up and turned back on export",
                );
        }
        ui.horizontal(|ui| {
            if ui.button("Create").clicked() {
                answer = Some(true);
            }
            if ui.button("Cancel").clicked() {
                answer = Some(false);
            }
        });
    });
    match answer {
        Some(true) => {
            if let Some((path, options)) = ui_state.new_mesh_dialog.take() {
                sender.send(Command::NewFromMesh(path, options));
            }
        }
        Some(false) => ui_state.new_mesh_dialog = None,
        None => {}
    }
}

/// Rig ▸ Auto rig's settings, while its dialog is open.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AutorigDialog {
    /// How fine, 1 to 5.
    pub detail: u32,
    /// Also the controls: one per limb segment, turning about its joint, and `root`.
    pub controls: bool,
    /// A plane the rig is a mirror image of itself across.
    pub mirror: Mirror,
}

impl Default for AutorigDialog {
    fn default() -> Self {
        Self {
            detail: starcages_core::generate::AutorigSettings::default().detail,
            controls: true,
            mirror: Mirror::None,
        }
    }
}

/// The auto rig's Symmetry choice (Rig ▸ Auto rig and New from mesh).
fn symmetry_choice(ui: &mut egui::Ui, mirror: &mut Mirror) {
    egui::ComboBox::from_label("Symmetry")
        .selected_text(mirror_label(*mirror))
        .show_ui(ui, |ui| {
            for choice in [
                Mirror::None,
                Mirror::Auto,
                Mirror::Axis(0),
                Mirror::Axis(1),
                Mirror::Axis(2),
            ] {
                ui.selectable_value(mirror, choice, mirror_label(choice));
            }
        })
        .response
        .on_hover_text(
            "make the rig its own mirror image across the plane through the origin (the \
             mesh's centre where the mesh is not centred on the origin); Detect: across the \
             axis the mesh is most symmetric about, if any",
        );
}

/// What the symmetry choice says, in the viewport's axes (Z-up).
fn mirror_label(mirror: Mirror) -> &'static str {
    match mirror {
        Mirror::None => "None",
        Mirror::Auto => "Detect",
        Mirror::Axis(0) => "Across x",
        Mirror::Axis(1) => "Across y",
        Mirror::Axis(_) => "Across z",
    }
}

/// Rig ▸ Auto rig: detail, controls and symmetry, then the rig replaces the current one (one undo
/// step, on a worker).
pub fn autorig_dialog(ui_state: &mut UiState, ctx: &egui::Context, sender: &mut CommandSender) {
    let Some(dialog) = &mut ui_state.autorig_dialog else {
        return;
    };
    let mut answer = None;
    egui::Modal::new(egui::Id::unique("auto-rig-dialog")).show(ctx, |ui| {
        ui.heading("Auto rig");
        ui.label("Replace the rig with cages that follow the mesh (one undo step).");
        ui.add(egui::Slider::new(&mut dialog.detail, 1..=5).text("detail"))
            .on_hover_text("1: few, coarse cages; 5: many, tight ones");
        ui.checkbox(&mut dialog.controls, "Controls").on_hover_text(
            "a control per limb segment that turns about its joint and carries the \
                 segments after it (leg.L.1 at the hip, leg.L.2 at the knee), and root over \
                 the whole rig",
        );
        symmetry_choice(ui, &mut dialog.mirror);
        ui.horizontal(|ui| {
            if ui.button("Make rig").clicked() {
                answer = Some(true);
            }
            if ui.button("Cancel").clicked() {
                answer = Some(false);
            }
        });
    });
    match answer {
        Some(true) => {
            if let Some(dialog) = ui_state.autorig_dialog.take() {
                sender.send(Command::AutoRig {
                    detail: dialog.detail,
                    controls: dialog.controls,
                    mirror: dialog.mirror,
                });
            }
        }
        Some(false) => ui_state.autorig_dialog = None,
        None => {}
    }
}

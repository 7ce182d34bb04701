//! The status bar: file loading and bind progress with Cancel, the tool's description, the
//! last message.

use egui::RichText;

use super::UiState;
use crate::commands::{Command, CommandSender};
use crate::state::EditorState;

/// The status bar.
pub fn status_bar(
    state: &EditorState,
    ui_state: &UiState,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    ui.horizontal(|ui| {
        let (mode, colour) = match state.mode {
            crate::state::EditMode::Pose => ("Pose mode", ui.visuals().text_color()),
            crate::state::EditMode::Rig => ("Rig mode", egui::Color32::from_rgb(255, 170, 60)),
        };
        ui.label(RichText::new(mode).strong().color(colour))
            .on_hover_text("Tab switches: Pose mode poses the mesh, Rig mode edits the rest cages");
        ui.separator();
        if let Some(load) = &state.load_job {
            ui.spinner();
            ui.label(&load.label);
            if ui.button("Cancel").clicked() {
                sender.send(Command::CancelLoad);
            }
        }
        if let Some(job) = &state.autorig_job {
            job_progress(ui, &job.label, job.progress(), Command::CancelAutoRig, sender);
        }
        if let Some(job) = &state.bind_job {
            job_progress(ui, &job.label, job.progress(), Command::CancelBind, sender);
        }
        if let Some((label, fraction)) = state.map.baseline_progress() {
            ui.label(label);
            ui.add(egui::ProgressBar::new(fraction as f32).desired_width(120.0));
            if ui.button("Cancel baseline").clicked() {
                sender.send(Command::CancelBaseline);
            }
        }
        if let Some(dialog) = ui_state.files.waiting_for() {
            ui.spinner();
            ui.label(format!("waiting for the {dialog} dialog"));
        }
        if let Some(tool) = &ui_state.tool {
            ui.label(tool.describe());
        } else if let Some(cut) = &ui_state.loop_cut {
            ui.label(cut.describe());
        } else if let Some(inset) = &ui_state.inset {
            ui.label(inset.describe());
        } else if let Some(message) = state.message.as_ref().filter(|m| m.opacity() > 0.0) {
            let colour = if message.error {
                egui::Color32::from_rgb(255, 110, 100)
            } else {
                ui.visuals().text_color()
            };
            // Cut with "…" at the window's edge, the whole text on hover: an error's fix comes
            // last, and a long one ran off the bar unread.
            ui.add(
                egui::Label::new(
                    RichText::new(&message.text).color(colour.gamma_multiply(message.opacity())),
                )
                .truncate(),
            );
            // Keep drawing until it has faded.
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(100));
        } else {
            ui.label(
                "Click a cage vertex to select it, drag to move; G/R/S transform; middle mouse orbits.",
            );
        }
    });
}

/// A background job's label, progress bar and Cancel button (which sends `cancel`).
fn job_progress(
    ui: &mut egui::Ui,
    label: &str,
    fraction: f64,
    cancel: Command,
    sender: &mut CommandSender,
) {
    ui.label(label);
    ui.add(
        egui::ProgressBar::new(fraction as f32)
            .desired_width(160.0)
            .show_percentage(),
    );
    if ui.button("Cancel").clicked() {
        sender.send(cancel);
    }
}

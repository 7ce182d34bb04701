//! The Item panel (N, as Blender's sidebar): the selected vertices' median, posed and at rest,
//! both editable (the whole selection moves; one undo step per drag), and the one vertex's
//! index when a single vertex is selected.

use glam::DVec3;

use super::UiState;
use super::inspector::slider_edit;
use crate::commands::{Command, CommandSender};
use crate::state::EditorState;

/// The median (mean) of `vertices` in `positions`, if any.
fn median(positions: &[DVec3], vertices: impl Iterator<Item = u32>) -> Option<DVec3> {
    let (sum, count) = vertices
        .filter_map(|v| positions.get(v as usize))
        .fold((DVec3::ZERO, 0usize), |(s, n), p| (s + *p, n + 1));
    (count > 0).then(|| sum / count as f64)
}

/// The panel's contents.
pub fn item_panel(
    state: &EditorState,
    ui_state: &mut UiState,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    ui.heading("Item");
    let selected = &state.selection.vertices;
    let scene = &state.doc.scene;
    let Some(posed) = median(&scene.pose, selected.iter().copied()) else {
        ui.label("Select cage vertices to see and edit their coordinates.");
        ui.separator();
        return;
    };
    let rest = median(&scene.cages.vertices, selected.iter().copied()).unwrap_or(posed);
    match selected.iter().next() {
        Some(v) if selected.len() == 1 => ui.label(format!("vertex {v}")),
        _ => ui.label(format!("{} vertices: their median", selected.len())),
    };
    ui.label("Posed");
    let mut edited = posed;
    ui.horizontal(|ui| {
        for (k, name) in ["X", "Y", "Z"].into_iter().enumerate() {
            ui.label(name);
            let response = ui.add(
                egui::DragValue::new(&mut edited[k])
                    .speed(0.01)
                    .max_decimals(4),
            );
            let response = response.on_hover_text(format!(
                "{name} of the selection's median in the current pose; drag or type to move \
                 the whole selection"
            ));
            let delta = edited - posed;
            slider_edit(
                ui_state,
                &response,
                "move in the Item panel",
                sender,
                || {
                    Command::MoveVertices(
                        selected
                            .iter()
                            .filter_map(|&v| scene.pose.get(v as usize).map(|p| (v, *p + delta)))
                            .collect(),
                    )
                },
            );
        }
    });
    ui.label("Rest").on_hover_text(
        "Where the selection is in the rest cages, which the binding is made for. Moving it \
         binds again the part of the mesh it reaches; every pose moves with it",
    );
    let mut edited = rest;
    ui.horizontal(|ui| {
        for (k, name) in ["X", "Y", "Z"].into_iter().enumerate() {
            ui.label(name);
            let response = ui
                .add(
                    egui::DragValue::new(&mut edited[k])
                        .speed(0.01)
                        .max_decimals(4),
                )
                .on_hover_text(format!(
                    "{name} of the selection's median at rest; drag or type to move the rest \
                     cages (the poses follow)"
                ));
            let delta = edited - rest;
            slider_edit(ui_state, &response, "move rest positions", sender, || {
                Command::MoveRestVertices(
                    selected
                        .iter()
                        .filter_map(|&v| {
                            scene
                                .cages
                                .vertices
                                .get(v as usize)
                                .map(|p| (v, *p + delta))
                        })
                        .collect(),
                )
            });
        }
    });
    ui.separator();
}

//! The right-hand panels below the inspector: view options with the legend, stats, poses.

use egui::RichText;
use starcages_core::coords::CoordinateKind;

use super::UiState;
use crate::commands::{Command, CommandSender};
use crate::state::{EditorState, InfluenceChoice};

fn influence_name(choice: InfluenceChoice) -> String {
    match choice {
        InfluenceChoice::None => "none".to_owned(),
        InfluenceChoice::SelectedCage => "b of the selected cage".to_owned(),
        InfluenceChoice::AllCages => "b of all cages".to_owned(),
        InfluenceChoice::JoinWeight => "W of the selected vertex".to_owned(),
        InfluenceChoice::Difference(k) => format!("difference to single {}", k.short_name()),
    }
}

/// Influence map, layers, shading, mirroring.
pub fn view_options(state: &EditorState, ui: &mut egui::Ui, sender: &mut CommandSender) {
    ui.separator();
    ui.heading("View");
    let current = state.view.influence;
    let mut choice = current;
    egui::ComboBox::from_label("Influence map")
        .selected_text(influence_name(current))
        .show_ui(ui, |ui| {
            for c in [
                InfluenceChoice::None,
                InfluenceChoice::SelectedCage,
                InfluenceChoice::AllCages,
                InfluenceChoice::JoinWeight,
                InfluenceChoice::Difference(CoordinateKind::MeanValue),
                InfluenceChoice::Difference(CoordinateKind::Green),
            ] {
                ui.selectable_value(&mut choice, c, influence_name(c));
            }
        });
    if choice != current {
        sender.send(Command::SetInfluence(choice));
    }
    let mut layers = state.view.layers;
    ui.checkbox(&mut layers.wireframe, "Wireframe");
    ui.checkbox(&mut layers.flat, "Flat shading");
    ui.checkbox(&mut layers.cages, "Cages");
    egui::CollapsingHeader::new("Cage colours")
        .default_open(false)
        .show(ui, super::help::legend);
    ui.checkbox(&mut layers.vertices, "Cage vertices");
    ui.checkbox(&mut layers.ground, "Ground grid")
        .on_hover_text("The plane z = 0, with the X axis in red and the Y axis in green");
    if layers != state.view.layers {
        sender.send(Command::SetLayers(layers));
    }
    let mut mirror = state.view.mirror_x;
    if ui.checkbox(&mut mirror, "X mirror editing").changed() {
        sender.send(Command::SetMirrorX(mirror));
    }
    if let Some(values) = state.map.values() {
        ui.label(RichText::new(&values.title).small());
        ui.label(
            RichText::new(format!("blue {} — red {}", values.range.0, values.range.1)).small(),
        );
    } else if let Some(note) = &state.map.note
        && current != InfluenceChoice::None
    {
        ui.label(RichText::new(note).small());
    }
}

/// Sizes and timings (the paper's Table II columns).
pub fn stats(state: &EditorState, ui_state: &UiState, ui: &mut egui::Ui) {
    ui.separator();
    ui.heading("Stats");
    let scene = &state.doc.scene;
    egui::Grid::new("stats").num_columns(2).show(ui, |ui| {
        let mut row = |k: &str, v: String| {
            ui.label(k);
            ui.label(v);
            ui.end_row();
        };
        row("vertices", scene.mesh.welded_positions().len().to_string());
        row("triangles", scene.mesh.welded_triangles().len().to_string());
        row(
            "cages",
            format!(
                "{} leaf, {} internal",
                scene.cages.leaves.len(),
                scene.cages.internals.len()
            ),
        );
        row("cage vertices", scene.cages.vertices.len().to_string());
        if let Some(rig) = &state.rig {
            let b = &rig.binding;
            let bytes =
                b.stats.operator_bytes + b.stats.transpose_bytes + b.join_weights.byte_size();
            row("weights memory", format!("{:.2} MB", bytes as f64 / 1e6));
        }
        if ui_state.show_timings {
            row("last bind", format!("{:.2} s", state.stats.bind_seconds));
            row("deform update", format!("{:.2} ms", state.stats.deform_ms));
            row("frame", format!("{:.1} ms", ui_state.frame_ms));
        }
    });
}

/// Stored poses: switch, delete, store, reset to rest.
pub fn poses(
    state: &EditorState,
    ui_state: &mut UiState,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    ui.separator();
    ui.heading("Poses");
    for name in state.doc.scene.poses.keys() {
        ui.horizontal(|ui| {
            if ui
                .button(name)
                .on_hover_text("switch to this pose")
                .clicked()
            {
                sender.send(Command::SwitchPose(Some(name.clone())));
            }
            if ui
                .small_button("delete")
                .on_hover_text("delete this pose")
                .clicked()
            {
                sender.send(Command::DeletePose(name.clone()));
            }
        });
    }
    ui.horizontal(|ui| {
        ui.add(egui::TextEdit::singleline(&mut ui_state.new_pose_name).hint_text("pose name"));
        if ui.button("Store pose").clicked() {
            sender.send(Command::StorePose(ui_state.new_pose_name.trim().to_owned()));
            ui_state.new_pose_name.clear();
        }
    });
    if ui.button("Reset to rest").clicked() {
        sender.send(Command::SwitchPose(None));
    }
}

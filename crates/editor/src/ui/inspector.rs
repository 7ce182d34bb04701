//! The cage inspector: coordinates, h (with per-border overrides) of the inspected cage,
//! adding or removing internal cages, and the scene-wide settings.

use egui::RichText;
use starcages_core::coords::CoordinateKind;
use starcages_core::scene::{JoinPolicy, SceneSettings, Smoothing};

use super::UiState;
use crate::commands::{Command, CommandSender};
use crate::state::{CageId, EditorState, InfluenceChoice};

/// What a coordinate kind does, in plain words.
fn kind_tooltip(kind: CoordinateKind) -> &'static str {
    match kind {
        CoordinateKind::MeanValue => "Mean value coordinates: smooth and fast to bind",
        CoordinateKind::Harmonic => {
            "Harmonic coordinates: never negative, so concave cages pull no part the wrong way; \
             solved on a grid, slower to bind"
        }
        CoordinateKind::Green => {
            "Green coordinates: also use the faces' normals, so shapes keep their proportions \
             (quasi-conformal)"
        }
    }
}

/// The coordinate kinds a cage can use, in menu order.
pub const KINDS: [CoordinateKind; 3] = [
    CoordinateKind::MeanValue,
    CoordinateKind::Harmonic,
    CoordinateKind::Green,
];

/// The kind's name in menus.
pub fn kind_name(kind: CoordinateKind) -> &'static str {
    match kind {
        CoordinateKind::MeanValue => "Mean Value (MVC)",
        CoordinateKind::Harmonic => "Harmonic (HC)",
        CoordinateKind::Green => "Green (GC)",
    }
}

/// The inspector panel.
pub fn inspector(
    state: &EditorState,
    ui_state: &mut UiState,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    ui.heading("Cage");
    if !state.selection.vertices.is_empty() {
        ui.menu_button("Add internal cage around selection", |ui| {
            for k in KINDS {
                if ui
                    .button(kind_name(k))
                    .on_hover_text(kind_tooltip(k))
                    .clicked()
                {
                    sender.send(Command::AddInternalCage(k));
                }
            }
        })
        .response
        .on_hover_text("a box cage that owns the selected vertices and drives them");
    }
    let set = &state.doc.scene.cages;
    let inspected = state
        .selection
        .cage()
        .and_then(|id| Some((id, id.name(set)?, id.kind(set)?)));
    let Some((cage, name, kind)) = inspected else {
        ui.label("Select a cage in the outliner.");
        scene_settings(state, ui_state, ui, sender);
        return;
    };
    ui.label(RichText::new(name).strong());
    let mut chosen = kind;
    egui::ComboBox::from_label("Coordinates")
        .selected_text(kind_name(kind))
        .show_ui(ui, |ui| {
            for k in KINDS {
                ui.selectable_value(&mut chosen, k, kind_name(k))
                    .on_hover_text(kind_tooltip(k));
            }
        })
        .response
        .on_hover_text(
            "How this cage's vertices move the mesh inside it: MVC (smooth, fast), HC \
             (harmonic: never negative, best in concave cages, slower to bind) or GC (Green: \
             keeps shapes, also uses the faces' normals)",
        );
    if chosen != kind {
        sender.send(Command::SetCageKind(cage, chosen));
    }
    match cage {
        CageId::Leaf(leaf) => leaf_h(state, ui_state, leaf, ui, sender),
        CageId::Internal(index) => {
            if ui
                .button("Remove internal cage")
                .on_hover_text("what it drives becomes free and stays where it is")
                .clicked()
            {
                sender.send(Command::RemoveInternalCage(index));
            }
        }
    }
    scene_settings(state, ui_state, ui, sender);
}

fn leaf_h(
    state: &EditorState,
    ui_state: &mut UiState,
    leaf: usize,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    let scene = &state.doc.scene;
    let Some(cage) = scene.cages.leaves.get(leaf) else {
        return;
    };
    let mut h = cage.h.unwrap_or(scene.settings.default_h);
    let response = ui
        .add(egui::Slider::new(&mut h, 0.05..=1.0).text("h"))
        .on_hover_text(
            "h: how far into this cage its neighbours blend in. Small h: the cage's own \
             coordinates (b = 1, red in the b map) almost up to its borders; h = 1: blending \
             with the neighbours (b < 1, blue) reaches deep inside. The b map is shown while \
             you drag",
        );
    // While dragging, show this cage's b map, so the change is visible even at rest.
    if response.drag_started() && state.view.influence != InfluenceChoice::SelectedCage {
        ui_state.influence_before_h_drag = Some(state.view.influence);
        sender.send(Command::SetInfluence(InfluenceChoice::SelectedCage));
    }
    slider_edit(ui_state, &response, "change h", sender, || {
        Command::SetCageH { leaf, h: Some(h) }
    });
    if response.drag_stopped()
        && let Some(before) = ui_state.influence_before_h_drag.take()
    {
        sender.send(Command::SetInfluence(before));
    }
    if !cage.border_h.is_empty() {
        ui.label("Per-border h:");
    }
    for (neighbour, value) in &cage.border_h {
        let mut value = *value;
        let response = ui.add(egui::Slider::new(&mut value, 0.05..=1.0).text(neighbour));
        slider_edit(ui_state, &response, "change border h", sender, || {
            Command::SetBorderH {
                leaf,
                neighbour: neighbour.clone(),
                h: Some(value),
            }
        });
    }
    let neighbours = neighbour_names(state, leaf);
    if !neighbours.is_empty() {
        ui.menu_button("Override h on a border", |ui| {
            for n in neighbours {
                if ui
                    .button(&n)
                    .on_hover_text(format!(
                        "Give the border with {n} its own h (how far that neighbour blends in)"
                    ))
                    .clicked()
                {
                    sender.send(Command::SetBorderH {
                        leaf,
                        neighbour: n,
                        h: Some(cage.h.unwrap_or(scene.settings.default_h)),
                    });
                }
            }
        })
        .response
        .on_hover_text("Set a different h on the border with one neighbouring cage");
    }
}

/// A slider that edits the document: one undo step per drag (a gesture from the drag's start
/// to its end), or one per change when set without dragging (keyboard, accessibility).
pub(super) fn slider_edit(
    ui_state: &mut UiState,
    response: &egui::Response,
    label: &str,
    sender: &mut CommandSender,
    command: impl FnOnce() -> Command,
) {
    if response.drag_started() && ui_state.slider_gesture.is_none() {
        let id = ui_state.new_gesture();
        ui_state.slider_gesture = Some(id);
        sender.send(Command::BeginGesture {
            id,
            label: label.to_owned(),
        });
    }
    if response.changed() {
        sender.send(command());
    }
    if response.drag_stopped() && ui_state.slider_gesture.take().is_some() {
        sender.send(Command::EndGesture { keep: true });
    }
}

fn neighbour_names(state: &EditorState, leaf: usize) -> Vec<String> {
    let set = &state.doc.scene.cages;
    let Some(cage) = set.leaves.get(leaf) else {
        return Vec::new();
    };
    set.adjacency()
        .iter()
        .filter_map(|a| {
            (a.first == leaf)
                .then_some(a.second)
                .or((a.second == leaf).then_some(a.first))
        })
        .filter_map(|n| set.leaves.get(n).map(|c| c.name.clone()))
        .filter(|n| !cage.border_h.contains_key(n))
        .collect()
}

fn scene_settings(
    state: &EditorState,
    ui_state: &mut UiState,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    egui::CollapsingHeader::new("Scene settings").show(ui, |ui| {
        let current = state.doc.scene.settings;
        let set = |label: &str, settings: SceneSettings| Command::SetSettings {
            label: label.to_owned(),
            settings,
        };
        let mut settings = current;
        let response = ui
            .add(egui::Slider::new(&mut settings.default_h, 0.05..=1.0).text("default h"))
            .on_hover_text(
                "h of every cage that sets none: how far into a cage its neighbours blend in",
            );
        slider_edit(ui_state, &response, "change default h", sender, || {
            set("change default h", settings)
        });
        let mut settings = current;
        egui::ComboBox::from_label("Smoothing")
            .selected_text(format!("{:?}", current.smoothing))
            .show_ui(ui, |ui| {
                for s in [Smoothing::Sine, Smoothing::Cubic, Smoothing::Quintic] {
                    ui.selectable_value(&mut settings.smoothing, s, format!("{s:?}"));
                }
            })
            .response
            .on_hover_text(
                "The curve that turns the distance from a border into the blend b (the \
                 paper's f_h): all three are smooth (C1); quintic is also C2",
            );
        if settings != current {
            sender.send(set("change smoothing", settings));
        }
        let mut settings = current;
        egui::ComboBox::from_label("Join cages")
            .selected_text(format!("{:?}", current.join_coordinates))
            .show_ui(ui, |ui| {
                for j in [
                    JoinPolicy::Auto,
                    JoinPolicy::Mvc,
                    JoinPolicy::Hc,
                    JoinPolicy::Gc,
                ] {
                    ui.selectable_value(&mut settings.join_coordinates, j, format!("{j:?}"));
                }
            })
            .response
            .on_hover_text(
                "The coordinates of the join cages, which blend neighbouring cages smoothly \
                 across their shared faces. Mvc (the default) is exact at rest and fast to \
                 bind; Auto uses harmonic coordinates where a join cage is concave (mean \
                 value coordinates can go negative there), refined in the background",
            );
        if settings != current {
            sender.send(set("change join policy", settings));
        }
        let mut settings = current;
        let response = ui
            .add(egui::Slider::new(&mut settings.harmonic.resolution, 16..=128).text("HC grid"))
            .on_hover_text(
                "Harmonic coordinates are solved on a grid: cells along the longest side of \
                 each harmonic cage. Finer is more accurate and slower to bind",
            );
        slider_edit(ui_state, &response, "change HC grid", sender, || {
            set("change HC grid", settings)
        });
    });
}

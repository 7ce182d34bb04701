//! The right-hand panels below the inspector: view options with the legend, stats, poses.

use egui::RichText;
use starcages_core::coords::CoordinateKind;

use super::UiState;
use crate::commands::{Command, CommandSender};
use crate::state::{EditorState, InfluenceChoice, PivotPoint};

fn influence_name(choice: InfluenceChoice) -> String {
    match choice {
        InfluenceChoice::None => "none".to_owned(),
        InfluenceChoice::SelectedCage => "b of the selected cage".to_owned(),
        InfluenceChoice::AllCages => "b of all cages".to_owned(),
        InfluenceChoice::JoinWeight => "W of the selected vertex".to_owned(),
        InfluenceChoice::Difference(k) => format!("difference to single {}", k.short_name()),
    }
}

/// What an influence map shows, in plain words.
fn influence_tooltip(choice: InfluenceChoice) -> &'static str {
    match choice {
        InfluenceChoice::None => "The mesh in its own colour",
        InfluenceChoice::SelectedCage | InfluenceChoice::AllCages => {
            "b: how much a mesh point follows its own cage. Red (b = 1): only this cage's own \
             coordinates; blue (b = 0): blended with its neighbours through the join cages, \
             which is what makes the deformation smooth across borders. h sets how far blue \
             reaches in"
        }
        InfluenceChoice::JoinWeight => {
            "W: how much one cage vertex's join transformation moves each mesh point (red: \
             fully, blue: not at all); select or hover one cage vertex"
        }
        InfluenceChoice::Difference(_) => {
            "How far the *Cages deformation is from deforming with one single cage of that \
             kind around everything (red: the largest difference); pose the cages to compare"
        }
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
                ui.selectable_value(&mut choice, c, influence_name(c))
                    .on_hover_text(influence_tooltip(c));
            }
        })
        .response
        .on_hover_text(influence_tooltip(current));
    if choice != current {
        sender.send(Command::SetInfluence(choice));
    }
    super::shading::shading_controls(state, ui, sender);
    super::shading::ghost_controls(state, ui, sender);
    let mut layers = state.view.layers;
    ui.checkbox(&mut layers.wireframe, "Wireframe")
        .on_hover_text("Draw the mesh's edges over it");
    ui.checkbox(&mut layers.flat, "Flat shading")
        .on_hover_text("One shade per triangle instead of smooth shading");
    ui.checkbox(&mut layers.cages, "Cages")
        .on_hover_text("Draw the cages' edges (colours: see Cage colours)");
    egui::CollapsingHeader::new("Cage colours")
        .default_open(false)
        .show(ui, super::help::legend);
    ui.checkbox(&mut layers.vertices, "Cage vertices")
        .on_hover_text("Draw the cage vertices you pick and move");
    ui.checkbox(&mut layers.ground, "Ground grid")
        .on_hover_text("The plane z = 0, with the X axis in red and the Y axis in green");
    ui.checkbox(&mut layers.xray, "X-ray")
        .on_hover_text("See the cages through the mesh, drawn translucent (Alt+Z)");
    if layers.xray {
        ui.add(egui::Slider::new(&mut layers.xray_opacity, 0.05..=1.0).text("Mesh opacity"))
            .on_hover_text("How opaque the mesh is in X-ray");
    }
    ui.add(egui::Slider::new(&mut layers.cage_opacity, 0.05..=1.0).text("Cage opacity"))
        .on_hover_text("How opaque the cages' edges and vertices are");
    if layers != state.view.layers {
        sender.send(Command::SetLayers(layers));
    }
    let mut mirror = state.view.mirror_x;
    if ui
        .checkbox(&mut mirror, "X mirror editing")
        .on_hover_text("Moving a cage vertex also moves its mirror image across x = 0")
        .changed()
    {
        sender.send(Command::SetMirrorX(mirror));
    }
    let mut snap = state.view.snap_to_vertices;
    if ui
        .checkbox(&mut snap, "Snap to vertices")
        .on_hover_text(
            "G puts the selected vertex nearest the pointer's target exactly on the cage vertex \
             under the pointer (holding Ctrl does the opposite of this box). In Rig mode, \
             vertices that land on others become one, so the cages share that border",
        )
        .changed()
    {
        sender.send(Command::SetSnapToVertices(snap));
    }
    let mut pivot = state.view.pivot_point;
    egui::ComboBox::from_label("Pivot point")
        .selected_text(pivot.label())
        .show_ui(ui, |ui| {
            for choice in PivotPoint::ALL {
                ui.selectable_value(&mut pivot, choice, choice.label());
            }
        })
        .response
        .on_hover_text(
            "What R and S turn and scale about. A whole control's origin is its joint (as a \
             bone's is its head), another whole cage's its centroid, a loose vertex itself; \
             the 3D cursor is placed by Shift+right click on the mesh",
        );
    if pivot != state.view.pivot_point {
        sender.send(Command::SetPivotPoint(pivot));
    }
    if !state.doc.scene.cages.internals.is_empty() {
        let mut leaf = state.view.leaf_vertices;
        egui::ComboBox::from_label("Leaf vertices in Pose mode")
            .selected_text(leaf.label())
            .show_ui(ui, |ui| {
                for choice in crate::state::LeafVertices::ALL {
                    ui.selectable_value(&mut leaf, choice, choice.label());
                }
            })
            .response
            .on_hover_text(
                "How Pose mode draws the leaf cage vertices under the rig's controls: you pose \
                 the controls, Rig mode edits the leaf cages. Hidden ones are not picked",
            );
        if leaf != state.view.leaf_vertices {
            sender.send(Command::SetLeafVertices(leaf));
        }
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
    let active = active_pose(&state.doc.scene, state.timeline.frame);
    ui.label(match &active {
        ActivePose::Rest => "current: the rest pose".to_owned(),
        ActivePose::Stored(name) => format!("current: '{name}'"),
        ActivePose::Animated(frame) => format!("current: the animation at frame {frame}"),
        ActivePose::Unstored => "current: edited, not stored".to_owned(),
    })
    .on_hover_text(
        "The pose the cages are in now: a stored one, the rest pose, the animation between \
         keys, or edits not stored yet",
    );
    for name in state.doc.scene.poses.keys() {
        ui.horizontal(|ui| {
            let is_active = matches!(&active, ActivePose::Stored(n) if n == name);
            if ui
                .selectable_label(is_active, name)
                .on_hover_text("switch to this pose")
                .clicked()
                && !is_active
            {
                switch_pose(ui_state, &active, Some(name.clone()), sender);
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
        if ui
            .button("Store pose")
            .on_hover_text("Store the current pose under the typed name")
            .clicked()
        {
            let name = ui_state.new_pose_name.trim().to_owned();
            if state.doc.scene.poses.contains_key(&name) {
                ui_state.pose_prompt = Some(PosePrompt::Overwrite(name));
            } else {
                sender.send(Command::StorePose(name));
                ui_state.new_pose_name.clear();
            }
        }
    });
    if ui
        .button("Reset to rest")
        .on_hover_text("Put every cage vertex back at its rest position")
        .clicked()
        && active != ActivePose::Rest
    {
        switch_pose(ui_state, &active, None, sender);
    }
}

/// Which pose the cages are in: found by comparing positions, so it is always true.
#[derive(Debug, Clone, PartialEq)]
pub enum ActivePose {
    /// The rest pose.
    Rest,
    /// A stored pose (the first by name when several are equal).
    Stored(String),
    /// The animation at this frame, between keys.
    Animated(f64),
    /// Edits not stored under any name.
    Unstored,
}

/// The active pose of `scene`, the timeline at `frame`.
pub fn active_pose(scene: &starcages_core::scene::Scene, frame: f64) -> ActivePose {
    // The rest pose first: a stored copy of it (a key's "rest") is still the rest pose.
    if scene.pose == scene.cages.vertices {
        return ActivePose::Rest;
    }
    if let Some(name) = scene
        .poses
        .iter()
        .find(|(_, p)| **p == scene.pose)
        .map(|(n, _)| n.clone())
    {
        ActivePose::Stored(name)
    } else if !scene.animation.is_empty()
        && scene.animation.pose_at(&scene.poses, frame).as_ref() == Some(&scene.pose)
    {
        ActivePose::Animated(frame)
    } else {
        ActivePose::Unstored
    }
}

/// Switches to `target` (rest for `None`), asking first when the current pose has edits that
/// are not stored.
fn switch_pose(
    ui_state: &mut UiState,
    active: &ActivePose,
    target: Option<String>,
    sender: &mut CommandSender,
) {
    if *active == ActivePose::Unstored {
        ui_state.pose_prompt = Some(PosePrompt::UnstoredEdits(target));
    } else {
        sender.send(Command::SwitchPose(target));
    }
}

/// A question about poses, while open.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PosePrompt {
    /// Switching to this pose (rest for `None`) would drop edits that are not stored.
    UnstoredEdits(Option<String>),
    /// A pose of this name exists: overwrite it?
    Overwrite(String),
}

/// Name under which "Keep them" stores unstored edits (with a number when taken).
fn unsaved_name(scene: &starcages_core::scene::Scene) -> String {
    (1..)
        .map(|k| {
            if k == 1 {
                "unsaved".to_owned()
            } else {
                format!("unsaved {k}")
            }
        })
        .find(|n| !scene.poses.contains_key(n))
        .unwrap_or_default()
}

/// The pose prompt, when one is open.
pub fn pose_prompt(
    state: &EditorState,
    ui_state: &mut UiState,
    ctx: &egui::Context,
    sender: &mut CommandSender,
) {
    let Some(prompt) = ui_state.pose_prompt.clone() else {
        return;
    };
    let mut close = false;
    egui::Modal::new(egui::Id::unique("pose-prompt")).show(ctx, |ui| match &prompt {
        PosePrompt::UnstoredEdits(target) => {
            ui.heading("Edits not stored");
            ui.label("The current pose has edits that are not stored in any pose.");
            let keep = unsaved_name(&state.doc.scene);
            ui.horizontal(|ui| {
                if ui
                    .button(format!("Keep them as '{keep}'"))
                    .on_hover_text("Store the edits as a pose, then switch")
                    .clicked()
                {
                    sender.send(Command::StorePose(keep.clone()));
                    sender.send(Command::SwitchPose(target.clone()));
                    close = true;
                }
                if ui.button("Discard them").clicked() {
                    sender.send(Command::SwitchPose(target.clone()));
                    close = true;
                }
                if ui.button("Cancel").clicked() {
                    close = true;
                }
            });
        }
        PosePrompt::Overwrite(name) => {
            ui.heading("Overwrite pose?");
            ui.label(format!("A pose called '{name}' exists."));
            ui.horizontal(|ui| {
                if ui.button("Overwrite").clicked() {
                    sender.send(Command::StorePose(name.clone()));
                    ui_state.new_pose_name.clear();
                    close = true;
                }
                if ui.button("Cancel").clicked() {
                    close = true;
                }
            });
        }
    });
    if close {
        ui_state.pose_prompt = None;
    }
}

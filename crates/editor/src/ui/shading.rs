//! The Shading and Ghosts controls (View ▸ Shading, View ▸ Ghosts, and the View panel):
//! Solid, MatCap with its matcap, Textured (the mesh file's materials); ghosts of the animation
//! with their counts and step. Each change is one command.

use starcages_viewport::{Matcap, Shading};

use crate::commands::{Command, CommandSender};
use crate::state::{EditorState, GhostSettings};

/// The shading choices: radio buttons for the modes, the matcaps under MatCap.
pub fn shading_controls(state: &EditorState, ui: &mut egui::Ui, sender: &mut CommandSender) {
    let mut layers = state.view.layers;
    let current = layers.shading;
    let textured_hint = match (&state.look, &state.look_job) {
        (_, Some(_)) => "The mesh file's materials are being read",
        (Some(look), None) if look.look.has_textures() => {
            "The mesh file's materials: base colour factor × image"
        }
        (Some(_), None) => "The mesh file's material colours (it has no images)",
        (None, None) => "The mesh has no materials: drawn as Solid",
    };
    ui.horizontal(|ui| {
        ui.label("Shading");
        if ui
            .radio(current == Shading::Solid, "Solid")
            .on_hover_text("Studio light on the mesh's colour")
            .clicked()
        {
            layers.shading = Shading::Solid;
        }
        let matcap = match current {
            Shading::MatCap(m) => m,
            _ => Matcap::default(),
        };
        if ui
            .radio(matches!(current, Shading::MatCap(_)), "MatCap")
            .on_hover_text("A lit sphere's colours at each normal: reads forms and kinks")
            .clicked()
        {
            layers.shading = Shading::MatCap(matcap);
        }
        if ui
            .radio(current == Shading::Textured, "Textured")
            .on_hover_text(textured_hint)
            .clicked()
        {
            layers.shading = Shading::Textured;
        }
    });
    if let Shading::MatCap(matcap) = current {
        ui.horizontal(|ui| {
            for choice in Matcap::ALL {
                if ui
                    .selectable_label(matcap == choice, choice.label())
                    .clicked()
                {
                    layers.shading = Shading::MatCap(choice);
                }
            }
        });
    }
    if layers != state.view.layers {
        sender.send(Command::SetLayers(layers));
    }
}

/// The ghost choices: shown, how many before and after, and the step in frames.
pub fn ghost_controls(state: &EditorState, ui: &mut egui::Ui, sender: &mut CommandSender) {
    let mut ghosts = state.view.ghosts;
    let keys = !state.doc.scene.animation.keys.is_empty();
    ui.add_enabled(keys, egui::Checkbox::new(&mut ghosts.shown, "Ghosts"))
        .on_hover_text(if keys {
            "The mesh at frames around the current one, translucent: red before, blue after \
             (Pose mode)"
        } else {
            "Ghosts show an animation: key a pose first (I)"
        })
        .on_disabled_hover_text("Ghosts show an animation: key a pose first (I)");
    if ghosts.shown {
        let max = GhostSettings::MAX_PER_SIDE;
        ui.horizontal(|ui| {
            ui.add(egui::DragValue::new(&mut ghosts.before).range(0..=max))
                .on_hover_text("Ghosts before the current frame");
            ui.label("before");
            ui.add(egui::DragValue::new(&mut ghosts.after).range(0..=max))
                .on_hover_text("Ghosts after the current frame");
            ui.label("after, every");
            ui.add(egui::DragValue::new(&mut ghosts.step).range(1..=48))
                .on_hover_text("Frames between ghosts");
            ui.label("frames");
        });
    }
    if ghosts != state.view.ghosts {
        sender.send(Command::SetGhosts(ghosts));
    }
}

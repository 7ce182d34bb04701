//! The outliner: the mesh layer, leaf and internal cages with visibility; clicking a cage
//! inspects it and selects its vertices.

use crate::commands::{Command, CommandSender};
use crate::state::{CageId, EditorState};

/// The outliner panel.
pub fn outliner(state: &EditorState, ui: &mut egui::Ui, sender: &mut CommandSender) {
    ui.heading("Outliner");
    let mut layers = state.view.layers;
    if ui
        .checkbox(&mut layers.mesh, "Mesh")
        .on_hover_text("Draw the deformed mesh")
        .changed()
    {
        sender.send(Command::SetLayers(layers));
    }
    let set = &state.doc.scene.cages;
    let groups: [(&str, Vec<CageId>); 2] = [
        (
            "Leaf cages",
            CageId::all(set)
                .filter(|c| matches!(c, CageId::Leaf(_)))
                .collect(),
        ),
        (
            "Internal cages",
            CageId::all(set)
                .filter(|c| matches!(c, CageId::Internal(_)))
                .collect(),
        ),
    ];
    for (title, cages) in groups {
        if cages.is_empty() {
            continue;
        }
        egui::CollapsingHeader::new(title)
            .default_open(true)
            .show(ui, |ui| {
                for id in cages {
                    cage_row(state, id, ui, sender);
                }
            });
    }
}

fn cage_row(state: &EditorState, id: CageId, ui: &mut egui::Ui, sender: &mut CommandSender) {
    let set = &state.doc.scene.cages;
    let (Some(name), Some(kind)) = (id.name(set), id.kind(set)) else {
        return;
    };
    ui.horizontal(|ui| {
        let mut visible = !state.view.is_hidden(id);
        if ui
            .checkbox(&mut visible, "")
            .on_hover_text("Show or hide this cage (hidden cages cannot be picked)")
            .changed()
        {
            sender.send(Command::SetCageHidden(id, !visible));
        }
        let selected = state.selection.cage() == Some(id);
        let label = format!("{name} ({})", kind.short_name());
        let what = match id {
            CageId::Leaf(_) => "a leaf cage: it deforms the mesh inside it",
            CageId::Internal(_) => "an internal cage: it moves the cage vertices it owns",
        };
        if ui
            .selectable_label(selected, label)
            .on_hover_text(format!(
                "{name}, {what}; click to inspect it and select its vertices"
            ))
            .clicked()
        {
            sender.send(Command::InspectCage(Some(id)));
        }
    });
}

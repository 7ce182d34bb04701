//! Shift+A's add menu in Rig mode, as Blender's: a popup at the pointer listing where a new box
//! cage can go. The Rig menu's "Add box cage" submenu lists the same entries.

use glam::Vec2;

use super::UiState;
use super::rig_keys::{BoxPlacement, add_box};
use crate::commands::{Command, CommandSender};
use crate::state::EditorState;

/// Where the add menu was opened: Shift+A at the pointer, or the Rig menu (the view's centre
/// then stands in for the pointer).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Opened {
    /// By Shift+A with the pointer here (screen points).
    AtPointer(Vec2),
    /// From the menu bar.
    FromMenu,
}

/// The entries, each enabled when it can apply, with the reason in its tooltip otherwise.
/// True when one was chosen.
pub fn entries(
    state: &EditorState,
    ui: &mut egui::Ui,
    opened: Opened,
    sender: &mut CommandSender,
) -> bool {
    let (at, at_label) = match opened {
        Opened::AtPointer(at) => (at, BoxPlacement::At(at).label()),
        Opened::FromMenu => (state.view.viewport.center(), "Box at the view's centre"),
    };
    let mesh_selected = state.selection.mesh_vertices.len();
    let cage_selected = state.selection.vertices.len();
    let choices = [
        (
            BoxPlacement::AroundMeshSelection,
            mesh_selected >= 2,
            format!(
                "{mesh_selected} mesh vertices selected; pick a region in Mesh select mode \
                 (drag a rectangle, Ctrl+drag a lasso)"
            ),
        ),
        (
            BoxPlacement::AroundCageSelection,
            cage_selected >= 2,
            format!("{cage_selected} cage vertices selected"),
        ),
        (
            BoxPlacement::AroundMesh,
            true,
            "A box 5 % larger than the mesh".to_owned(),
        ),
        (
            BoxPlacement::At(at),
            true,
            "A cube in the part of the mesh under the pointer, as wide as it is deep there"
                .to_owned(),
        ),
    ];
    for (placement, enabled, tooltip) in choices {
        let label = match placement {
            BoxPlacement::At(_) => at_label,
            other => other.label(),
        };
        if ui
            .add_enabled(enabled, egui::Button::new(label))
            .on_hover_text(&tooltip)
            .on_disabled_hover_text(&tooltip)
            .clicked()
        {
            sender.send(match add_box(state, placement) {
                Ok(op) => Command::Rig(op),
                Err(why) => Command::Info(why),
            });
            return true;
        }
    }
    false
}

/// The popup while it is open: a click on an entry adds the box, a click elsewhere or Esc
/// closes it.
pub fn popup(
    state: &EditorState,
    ui_state: &mut UiState,
    ctx: &egui::Context,
    sender: &mut CommandSender,
) {
    let Some(at) = ui_state.add_menu else {
        return;
    };
    if state.mode != crate::state::EditMode::Rig || ctx.input(|i| i.key_pressed(egui::Key::Escape))
    {
        ui_state.add_menu = None;
        return;
    }
    let area = egui::Area::new(egui::Id::unique("add-menu"))
        .order(egui::Order::Foreground)
        .fixed_pos(egui::pos2(at.x, at.y))
        .show(ctx, |ui| {
            egui::Frame::popup(ui.style())
                .show(ui, |ui| {
                    ui.label(egui::RichText::new("Add").strong());
                    ui.separator();
                    entries(state, ui, Opened::AtPointer(at), sender)
                })
                .inner
        });
    if area.inner || area.response.clicked_elsewhere() {
        ui_state.add_menu = None;
    }
}

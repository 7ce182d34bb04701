//! Help: the keyboard shortcuts window (F1 or ?), read from the [`UiCommand`] table, the
//! [`ToolKey`] table (the keys of G / R / S, the loop cut and the inset while they run) and the
//! mouse, and the legend of the cage colours.

use super::UiState;
use crate::commands::{ToolKey, UiCommand};

/// What the mouse does.
const MORE: [(&str, &str); 5] = [
    (
        "Orbit / pan / zoom",
        "middle mouse or Alt+left drag / Shift+middle / wheel",
    ),
    (
        "Select / add to selection",
        "click / Shift+click a cage vertex",
    ),
    ("Rectangle selection", "drag on empty space (Shift adds)"),
    ("Move a vertex", "drag it"),
    ("Look along an axis", "click an end of the axis gizmo"),
];

/// The legend of what the colours of cages mean: (colour, meaning).
pub fn cage_legend() -> [(egui::Color32, &'static str); 6] {
    use starcages_viewport::colors;
    let c = |rgba| {
        let [r, g, b, _] = colors::to_u8(rgba);
        egui::Color32::from_rgb(r, g, b)
    };
    let kind = |k| c(colors::kind(k));
    use starcages_core::coords::CoordinateKind as K;
    [
        (kind(K::MeanValue), "MVC leaf cage (mean value coordinates)"),
        (kind(K::Green), "GC leaf cage (Green coordinates)"),
        (kind(K::Harmonic), "HC leaf cage (harmonic coordinates)"),
        (c(colors::INTERNAL), "internal cage (drives cage vertices)"),
        (c(colors::BORDER), "border: a face shared by two leaf cages"),
        (
            c(colors::WARNING),
            "problem: a cage, vertex or mesh vertex the rig's validation names (point at it for why)",
        ),
    ]
}

/// The keyboard shortcuts window.
pub fn shortcuts_window(ui_state: &mut UiState, ctx: &egui::Context) {
    let mut open = ui_state.show_shortcuts;
    let max_width = (ctx.content_rect().width() - 40.0).clamp(300.0, 900.0);
    // What is left beside the action and key columns.
    let description_width = (max_width - 340.0).max(200.0);
    egui::Window::new("Keyboard shortcuts")
        .open(&mut open)
        .collapsible(false)
        .default_width(620.0)
        .max_width(max_width)
        .default_height(440.0)
        .vscroll(true)
        .anchor(egui::Align2::CENTER_CENTER, egui::Vec2::ZERO)
        .show(ctx, |ui| {
            egui::Grid::new("shortcuts").striped(true).show(ui, |ui| {
                for command in UiCommand::ALL {
                    let mut keys: Vec<String> = command
                        .shortcuts()
                        .iter()
                        .map(|s| ctx.format_shortcut(s).replace("Questionmark", "?"))
                        .filter(|k| k != "Shift+?")
                        .collect();
                    keys.dedup();
                    ui.label(command.label());
                    ui.label(if keys.is_empty() {
                        "menu".to_owned()
                    } else {
                        keys.join(", ")
                    });
                    // Long descriptions wrap inside the window instead of widening it
                    // past the screen.
                    ui.vertical(|ui| {
                        ui.set_width(description_width);
                        ui.add(
                            egui::Label::new(egui::RichText::new(command.tooltip()).weak()).wrap(),
                        );
                    });
                    ui.end_row();
                }
                for (what, how) in MORE {
                    ui.label(what);
                    ui.label("mouse");
                    ui.vertical(|ui| {
                        ui.set_width(description_width);
                        ui.add(egui::Label::new(how).wrap());
                    });
                    ui.end_row();
                }
                for key in ToolKey::ALL {
                    ui.label(key.label());
                    ui.label(key.keys());
                    ui.vertical(|ui| {
                        ui.set_width(description_width);
                        ui.add(
                            egui::Label::new(
                                egui::RichText::new(format!("while {} runs", key.tools())).weak(),
                            )
                            .wrap(),
                        );
                    });
                    ui.end_row();
                }
            });
            ui.separator();
            ui.label("Cage colours");
            legend(ui);
        });
    ui_state.show_shortcuts = open;
}

/// The cage colour legend: a swatch and its meaning per line.
pub fn legend(ui: &mut egui::Ui) {
    for (colour, meaning) in cage_legend() {
        ui.horizontal(|ui| {
            let (swatch, _) = ui.allocate_exact_size(egui::vec2(14.0, 10.0), egui::Sense::hover());
            ui.painter().rect_filled(swatch, 2.0, colour);
            ui.label(meaning);
        });
    }
}

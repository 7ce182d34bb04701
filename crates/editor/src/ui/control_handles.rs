//! Pose mode's control handles: a ring at each control's joint (an internal cage with a
//! pivot, as the auto rig makes them), where the control stands in the pose, filled when the
//! control is selected and named on hover. A click on a handle selects the whole control, so
//! that R and S turn and scale it about its joint; handles are picked before cage vertices.

use glam::Vec2;

use crate::state::{EditMode, EditorState};

/// Radius of a handle, in points.
const RADIUS: f32 = 6.0;
/// How near (points) the pointer must come to a handle to pick it.
const PICK_RADIUS: f32 = 9.0;

/// One handle: the internal cage, its vertices (sorted) and where its joint is on screen.
struct Handle {
    name: String,
    vertices: Vec<u32>,
    at: egui::Pos2,
}

/// The handles in view, in Pose mode only.
fn handles(state: &EditorState) -> Vec<Handle> {
    if state.mode != EditMode::Pose {
        return Vec::new();
    }
    let set = &state.doc.scene.cages;
    let pose = &state.doc.scene.pose;
    let rect = state.view.viewport;
    set.internals
        .iter()
        .filter(|cage| cage.pivot.is_some())
        .filter_map(|cage| {
            let pivot = starcages_core::hierarchy::posed_pivot(set, cage, pose)?;
            let (pixel, _) = state.view.camera.project(pivot.as_vec3(), rect.size)?;
            let at = rect.min + pixel;
            let vertices = set.cage_vertices(&cage.name)?;
            Some(Handle {
                name: cage.name.clone(),
                vertices,
                at: egui::pos2(at.x, at.y),
            })
        })
        .collect()
}

/// The vertices of the control whose handle is under `pointer` (screen points), nearest first.
pub fn pick(state: &EditorState, pointer: Vec2) -> Option<Vec<u32>> {
    let pointer = egui::pos2(pointer.x, pointer.y);
    handles(state)
        .into_iter()
        .map(|h| (h.at.distance(pointer), h))
        .filter(|(d, _)| *d <= PICK_RADIUS)
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, h)| h.vertices)
}

/// Draws the handles; the one under `pointer` gets its control's name beside it.
pub fn draw(state: &EditorState, painter: &egui::Painter, pointer: Option<Vec2>) {
    let selected: Vec<u32> = state.selection.vertices.iter().copied().collect();
    let accent = egui::Color32::from_rgb(255, 170, 40);
    for handle in handles(state) {
        let is_selected = handle.vertices == selected;
        let fill = if is_selected {
            accent
        } else {
            egui::Color32::from_black_alpha(120)
        };
        painter.circle(
            handle.at,
            RADIUS,
            fill,
            egui::Stroke::new(
                1.5,
                if is_selected {
                    egui::Color32::WHITE
                } else {
                    accent
                },
            ),
        );
        let hovered =
            pointer.is_some_and(|p| handle.at.distance(egui::pos2(p.x, p.y)) <= PICK_RADIUS);
        if hovered {
            painter.text(
                handle.at + egui::vec2(RADIUS + 4.0, 0.0),
                egui::Align2::LEFT_CENTER,
                &handle.name,
                egui::FontId::proportional(13.0),
                egui::Color32::WHITE,
            );
        }
    }
}

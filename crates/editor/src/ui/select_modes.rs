//! Rig mode's select modes (Blender's vertex / face select, plus mesh vertices for Shift+A):
//! the switch at the viewport's top left, what a click or a region (rectangle or lasso) picks
//! in each, and the overlay of selected faces.

use std::collections::BTreeSet;

use glam::Vec2;
use starcages_viewport::colors;
use starcages_viewport::picking::{pick_nearest, pick_polygon, select_in_lasso};

use crate::commands::{Command, CommandSender};
use crate::state::{EditorState, SelectElement, SelectMode};

/// How near (points) a click must come to a mesh vertex to pick it.
const MESH_PICK_RADIUS: f32 = 8.0;

/// A selection region on screen (points).
#[derive(Debug, Clone, PartialEq)]
pub enum Region {
    /// The rectangle between two corners.
    Rectangle(Vec2, Vec2),
    /// A closed freehand outline.
    Lasso(Vec<Vec2>),
}

impl Region {
    /// The outline, as a polygon in viewport pixels (`origin`: the viewport's top left).
    fn polygon_in_viewport(&self, origin: Vec2) -> Vec<Vec2> {
        match self {
            Self::Rectangle(a, b) => {
                let (lo, hi) = (a.min(*b) - origin, a.max(*b) - origin);
                vec![lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)]
            }
            Self::Lasso(points) => points.iter().map(|p| *p - origin).collect(),
        }
    }
}

fn positions_f32(positions: &[glam::DVec3]) -> Vec<glam::Vec3> {
    positions.iter().map(|p| p.as_vec3()).collect()
}

/// The leaf-cage face under `pointer` (screen points), nearest the eye: (cage, face).
pub fn pick_face(state: &EditorState, pointer: Vec2) -> Option<(usize, usize)> {
    let rect = state.view.viewport;
    let set = &state.doc.scene.cages;
    let hidden = state.view.cage_style(&state.selection, set).hidden;
    let keys: Vec<(usize, usize)> = set
        .leaves
        .iter()
        .enumerate()
        .filter(|(c, _)| !hidden.contains(c))
        .flat_map(|(c, cage)| (0..cage.faces.len()).map(move |f| (c, f)))
        .collect();
    let polygons: Vec<&[u32]> = keys
        .iter()
        .map(|&(c, f)| set.leaves[c].faces[f].as_slice())
        .collect();
    let hit = pick_polygon(
        &state.view.camera,
        rect.size,
        &positions_f32(state.shown_positions()),
        &polygons,
        rect.local(pointer),
    )?;
    keys.get(hit).copied()
}

/// The mesh vertex (welded, at rest) drawn nearest `pointer` (screen points), if one is near.
pub fn pick_mesh_vertex(state: &EditorState, pointer: Vec2) -> Option<u32> {
    let rect = state.view.viewport;
    pick_nearest(
        &state.view.camera,
        rect.size,
        &positions_f32(state.doc.scene.mesh.welded_positions()),
        &[],
        rect.local(pointer),
        MESH_PICK_RADIUS,
    )
    .map(|v| v as u32)
}

/// The shown leaf-cage faces (cage, face) whose corners are all in `inside`.
fn faces_within(state: &EditorState, inside: &BTreeSet<u32>) -> Vec<(usize, usize)> {
    let set = &state.doc.scene.cages;
    let hidden = state.view.cage_style(&state.selection, set).hidden;
    set.leaves
        .iter()
        .enumerate()
        .filter(|(c, _)| !hidden.contains(c))
        .flat_map(|(c, cage)| {
            cage.faces
                .iter()
                .enumerate()
                .filter(|(_, face)| face.iter().all(|v| inside.contains(v)))
                .map(move |(f, _)| (c, f))
        })
        .collect()
}

/// A click (not a drag) in the viewport at `pointer`: selects what the current select mode
/// picks there (Shift toggles it); a click on nothing clears the selection.
pub fn click(state: &EditorState, pointer: Option<Vec2>, shift: bool, sender: &mut CommandSender) {
    let mode = if shift {
        SelectMode::Toggle
    } else {
        SelectMode::Replace
    };
    let command = match state.select_element() {
        // In Pose mode a click on a control's handle picks the control; on the mesh away from
        // any cage vertex, the control moving that part (the whole internal cage).
        SelectElement::CageVertices => pointer
            .and_then(|p| {
                super::control_handles::pick(state, p)
                    .or_else(|| super::picking::pick(state, p).map(|v| vec![v]))
                    .or_else(|| {
                        (state.mode == crate::state::EditMode::Pose)
                            .then(|| super::picking::control_under(state, p))
                            .flatten()
                    })
            })
            .map(|vertices| Command::Select { vertices, mode }),
        SelectElement::CageFaces => {
            pointer
                .and_then(|p| pick_face(state, p))
                .map(|face| Command::SelectFaces {
                    faces: vec![face],
                    mode,
                })
        }
        SelectElement::MeshVertices => {
            pointer
                .and_then(|p| pick_mesh_vertex(state, p))
                .map(|v| Command::SelectMeshVertices {
                    vertices: vec![v],
                    mode,
                })
        }
    };
    match command {
        Some(command) => sender.send(command),
        None if !shift => sender.send(Command::SelectNone),
        None => {}
    }
}

/// A finished region drag: selects what the current select mode has inside it (cage vertices
/// that are shown, faces whose corners are all inside, or mesh vertices at rest, the hidden
/// side included, as Blender's X-ray); `extend` (Shift) adds to the selection.
pub fn region(state: &EditorState, region: &Region, extend: bool, sender: &mut CommandSender) {
    let rect = state.view.viewport;
    let lasso = region.polygon_in_viewport(rect.min);
    let mode = if extend {
        SelectMode::Add
    } else {
        SelectMode::Replace
    };
    let inside = |points: &[glam::DVec3], pickable: &[bool]| -> Vec<u32> {
        select_in_lasso(
            &state.view.camera,
            rect.size,
            &positions_f32(points),
            pickable,
            &lasso,
        )
        .into_iter()
        .map(|i| i as u32)
        .collect()
    };
    let pickable = state.pickable();
    let command = match state.select_element() {
        SelectElement::CageVertices => Command::Select {
            vertices: inside(state.shown_positions(), &pickable),
            mode,
        },
        SelectElement::CageFaces => {
            let corners: BTreeSet<u32> = inside(state.shown_positions(), &pickable)
                .into_iter()
                .collect();
            Command::SelectFaces {
                faces: faces_within(state, &corners),
                mode,
            }
        }
        SelectElement::MeshVertices => Command::SelectMeshVertices {
            vertices: inside(state.doc.scene.mesh.welded_positions(), &[]),
            mode,
        },
    };
    sender.send(command);
}

/// The selected faces, tinted and outlined in the selection colour.
pub fn selected_faces_overlay(state: &EditorState, painter: &egui::Painter, rect: egui::Rect) {
    let set = &state.doc.scene.cages;
    let shown = state.shown_positions();
    let camera = &state.view.camera;
    let size = state.view.viewport.size;
    let [r, g, b, _] = colors::to_u8(colors::SELECTED);
    for (c, f) in state.selection.face_indices(set) {
        let Some(face) = set.leaves.get(c).and_then(|cage| cage.faces.get(f)) else {
            continue;
        };
        let mut outline: Vec<egui::Pos2> = face
            .iter()
            .filter_map(|&v| camera.project(shown.get(v as usize)?.as_vec3(), size))
            .map(|(q, _)| rect.min + egui::vec2(q.x, q.y))
            .collect();
        if outline.len() == face.len() && outline.len() >= 3 {
            // A faint fill (Blender tints selected faces), then the outline.
            painter.add(egui::Shape::convex_polygon(
                outline.clone(),
                egui::Color32::from_rgba_unmultiplied(r, g, b, 40),
                egui::Stroke::NONE,
            ));
            outline.push(outline[0]);
            painter.add(egui::Shape::line(
                outline,
                egui::Stroke::new(3.0, egui::Color32::from_rgb(r, g, b)),
            ));
        }
    }
}

/// In Rig mode, the select modes at the viewport's top left.
pub fn switch(state: &EditorState, ui: &egui::Ui, rect: egui::Rect, sender: &mut CommandSender) {
    if state.mode != crate::state::EditMode::Rig {
        return;
    }
    egui::Area::new(egui::Id::unique("select-mode"))
        .order(egui::Order::Foreground)
        .fixed_pos(rect.left_top() + egui::vec2(10.0, 10.0))
        .show(ui.ctx(), |ui| {
            ui.horizontal(|ui| {
                for element in SelectElement::ALL {
                    let label = match element {
                        SelectElement::MeshVertices
                            if !state.selection.mesh_vertices.is_empty() =>
                        {
                            format!(
                                "{} ({})",
                                element.label(),
                                state.selection.mesh_vertices.len()
                            )
                        }
                        _ => element.label().to_owned(),
                    };
                    if ui
                        .selectable_label(state.view.select_element == element, label)
                        .on_hover_text(element.tooltip())
                        .clicked()
                    {
                        sender.send(Command::SetSelectElement(element));
                    }
                }
            });
        });
}

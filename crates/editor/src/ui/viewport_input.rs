//! The viewport's mouse, as Blender users expect: orbit (middle or Alt+left), pan
//! (Shift+middle), zoom to the cursor (wheel), click to pick a cage vertex (Shift toggles),
//! drag a vertex to move the selection in the view plane, drag on empty space for a selection
//! rectangle; a click or a right click ends the G / R / S tool.

use egui::{Pos2, Sense};
use glam::{DVec3, Vec2};
use starcages_viewport::colors;

use super::picking::{SNAP_RADIUS, pick, snap_target};
use super::transform_tool::view_plane_delta;
use super::viewport_paint;
use super::{UiState, axis_gizmo};
use crate::commands::{CameraChange, Command, CommandSender};
use crate::state::{EditorState, GestureId, ScreenRect, SelectMode};

/// A mouse drag in the viewport.
#[derive(Debug)]
pub enum Drag {
    /// Moving the selected vertices in the view plane (one gesture, one undo step).
    Move {
        /// The state's gesture.
        gesture: GestureId,
        /// Where the drag started (screen points).
        start_pointer: Vec2,
        /// The selection's positions when it started.
        start: Vec<(u32, DVec3)>,
        /// The cage vertex the selection is snapped onto (snapping on, or Ctrl held once the
        /// drag has begun): index and position.
        snap: Option<(u32, DVec3)>,
    },
    /// A selection region: a rectangle from `start`, or with Ctrl held a lasso through the
    /// pointer's path (screen points).
    Region {
        /// Where the drag started: the rectangle's first corner, the lasso's first point.
        start: Vec2,
        /// The lasso's path so far (`None`: a rectangle).
        lasso: Option<Vec<Vec2>>,
        /// Shift held: add to the selection.
        extend: bool,
    },
    /// Orbiting or panning the camera.
    Camera,
}

fn vec2(p: Pos2) -> Vec2 {
    Vec2::new(p.x, p.y)
}

/// The viewport: input, the 3D view through the paint callback, overlays.
pub fn viewport(
    state: &EditorState,
    ui_state: &mut UiState,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    let (rect, response) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
    let screen_rect = ScreenRect {
        min: vec2(rect.min),
        size: vec2(rect.max) - vec2(rect.min),
    };
    if screen_rect != state.view.viewport {
        sender.send(Command::SetViewport(screen_rect));
    }
    let (pointer, secondary, shift_secondary) = ui.input(|i| {
        // Shift as the right button was released (the modifiers may change in the same frame).
        let shifted = i.modifiers.shift
            || i.events.iter().any(|e| {
                matches!(e, egui::Event::PointerButton {
                    button: egui::PointerButton::Secondary,
                    pressed: false,
                    modifiers,
                    ..
                } if modifiers.shift)
            });
        (
            i.pointer.latest_pos().map(vec2),
            i.pointer.secondary_clicked(),
            i.pointer.secondary_clicked() && shifted,
        )
    });
    let on_gizmo = pointer.is_some_and(|p| axis_gizmo::contains(rect, egui::pos2(p.x, p.y)));
    if let Some(cut) = &mut ui_state.loop_cut {
        // The cut follows the pointer; a click makes it, a right click drops it.
        if let Some(p) = pointer {
            let camera = &state.view.camera;
            let size = state.view.viewport.size;
            cut.follow(state, p - state.view.viewport.min, |w| {
                camera.project(w.as_vec3(), size).map(|(q, _)| q)
            });
        }
        if response.clicked() {
            sender.send(Command::Rig(cut.operation(state)));
            ui_state.loop_cut = None;
        } else if secondary {
            ui_state.loop_cut = None;
        }
    } else if let Some(inset) = &mut ui_state.inset {
        // The inset follows the pointer; a click makes it, a right click drops it.
        if let Some(p) = pointer {
            inset.follow(state, p - state.view.viewport.min);
        }
        if response.clicked() {
            sender.send(Command::RigOps(inset.operations()));
            ui_state.inset = None;
        } else if secondary {
            ui_state.inset = None;
        }
    } else if ui_state.tool.is_some() {
        // The tool follows the pointer in `keyboard`; here only its mouse confirm / cancel.
        if response.clicked() {
            ui_state.tool = None;
            sender.send(Command::EndGesture { keep: true });
        } else if secondary {
            ui_state.tool = None;
            sender.send(Command::EndGesture { keep: false });
        }
    } else if shift_secondary && !on_gizmo {
        // Shift+right click places the 3D cursor on the mesh point under the pointer.
        match pointer.and_then(|p| super::picking::mesh_point_under(state, p)) {
            Some(at) => sender.send(Command::SetCursor(at)),
            None => sender.send(Command::Info(
                "Shift+right click on the mesh to place the 3D cursor".into(),
            )),
        }
    } else if !on_gizmo || ui_state.drag.is_some() {
        mouse(state, ui_state, ui, &response, screen_rect, sender);
    }
    let hovered = if response.hovered() && !on_gizmo {
        pointer.and_then(|p| pick(state, p))
    } else {
        None
    };
    if hovered != state.selection.hovered {
        sender.send(Command::Hover(hovered));
    }
    viewport_paint::paint(state, ui_state, ui, rect);
    overlays(state, ui_state, ui, rect, pointer);
    rig_banner(state, ui, rect);
    problem_under_pointer(state, ui);
    super::select_modes::switch(state, ui, rect, sender);
    if let Some(cut) = &ui_state.loop_cut {
        loop_cut_overlay(state, cut, ui.painter(), rect);
    }
    if let Some(inset) = &ui_state.inset {
        inset_overlay(state, inset, ui.painter(), rect);
    }
    let click = pointer
        .filter(|_| response.clicked() && on_gizmo && ui_state.tool.is_none())
        .map(|p| egui::pos2(p.x, p.y));
    if let Some(view) = axis_gizmo::gizmo(&ui.painter_at(rect), rect, &state.view.camera, click) {
        sender.send(Command::Camera(CameraChange::View(view)));
    }
}

fn mouse(
    state: &EditorState,
    ui_state: &mut UiState,
    ui: &egui::Ui,
    response: &egui::Response,
    rect: ScreenRect,
    sender: &mut CommandSender,
) {
    let (pointer, modifiers, scroll) = ui.input(|i| {
        (
            i.pointer.latest_pos().map(vec2),
            i.modifiers,
            i.smooth_scroll_delta.y,
        )
    });
    if response.hovered() && scroll != 0.0 {
        sender.send(Command::Camera(CameraChange::Zoom {
            steps: scroll / 50.0,
            cursor_in_viewport: pointer.map(|p| rect.local(p)),
        }));
    }
    let camera_drag = response.dragged_by(egui::PointerButton::Middle)
        || (response.dragged_by(egui::PointerButton::Primary) && modifiers.alt);
    if camera_drag {
        let delta = vec2(response.drag_delta().to_pos2());
        let change = if modifiers.shift {
            CameraChange::Pan(delta)
        } else {
            CameraChange::Orbit(delta)
        };
        sender.send(Command::Camera(change));
        ui_state.drag = Some(Drag::Camera);
    } else if response.drag_started_by(egui::PointerButton::Primary) {
        let origin = ui
            .input(|i| i.pointer.press_origin().map(vec2))
            .or(pointer)
            .unwrap_or(rect.center());
        ui_state.drag = Some(start_drag(state, ui_state, origin, modifiers, sender));
    }
    if response.dragged_by(egui::PointerButton::Primary)
        && let (
            Some(Drag::Region {
                lasso: Some(path), ..
            }),
            Some(p),
        ) = (&mut ui_state.drag, pointer)
        && path.last().is_none_or(|last| last.distance(p) >= 2.0)
    {
        path.push(p);
    }
    if response.dragged_by(egui::PointerButton::Primary)
        && let (
            Some(Drag::Move {
                start_pointer,
                start,
                snap,
                ..
            }),
            Some(p),
        ) = (&mut ui_state.drag, pointer)
    {
        // Snapping as G's: onto the cage vertex under the pointer (Ctrl inverts the View
        // panel's switch; pressed at the start, Ctrl draws a lasso instead).
        let moving: std::collections::BTreeSet<u32> = start.iter().map(|s| s.0).collect();
        *snap = (state.view.snap_to_vertices != modifiers.command)
            .then(|| snap_target(state, p, &moving))
            .flatten();
        let delta = match snap {
            Some((_, at)) => super::transform_tool::snap_delta(start, *at),
            None => {
                let centre = start.iter().map(|s| s.1).sum::<DVec3>() / start.len().max(1) as f64;
                view_plane_delta(&state.view.camera, rect.size.y, centre, p - *start_pointer)
            }
        };
        let moves: Vec<(u32, DVec3)> = start.iter().map(|&(v, q)| (v, q + delta)).collect();
        sender.send(Command::MoveVertices(moves));
    }
    if response.drag_stopped() {
        match ui_state.drag.take() {
            Some(Drag::Move { .. }) => sender.send(Command::EndGesture { keep: true }),
            Some(Drag::Region {
                start,
                lasso,
                extend,
            }) => {
                let region = match lasso {
                    Some(points) => Some(super::select_modes::Region::Lasso(points)),
                    None => pointer.map(|end| super::select_modes::Region::Rectangle(start, end)),
                };
                if let Some(region) = region {
                    super::select_modes::region(state, &region, extend, sender);
                }
            }
            _ => {}
        }
    }
    if response.clicked() {
        super::select_modes::click(state, pointer, modifiers.shift, sender);
    }
}

/// A primary-button drag from `origin`: on a vertex it moves the selection (the vertex joins
/// it first), on empty space (or always in mesh select mode) it draws a selection rectangle,
/// with Ctrl a lasso.
fn start_drag(
    state: &EditorState,
    ui_state: &mut UiState,
    origin: Vec2,
    modifiers: egui::Modifiers,
    sender: &mut CommandSender,
) -> Drag {
    let shift = modifiers.shift;
    let on_vertex = (state.select_element() != crate::state::SelectElement::MeshVertices
        && !modifiers.command)
        .then(|| pick(state, origin))
        .flatten();
    let Some(v) = on_vertex else {
        return Drag::Region {
            start: origin,
            lasso: modifiers.command.then(|| vec![origin]),
            extend: shift,
        };
    };
    let mut selected = state.selection.vertices.clone();
    if !selected.contains(&v) {
        let mode = if shift {
            SelectMode::Toggle
        } else {
            SelectMode::Replace
        };
        sender.send(Command::Select {
            vertices: vec![v],
            mode,
        });
        if !shift {
            selected.clear();
        }
        selected.insert(v);
    }
    let pose = state.shown_positions();
    let start = selected
        .iter()
        .filter_map(|&s| pose.get(s as usize).map(|p| (s, *p)))
        .collect();
    let gesture = ui_state.new_gesture();
    sender.send(Command::BeginGesture {
        id: gesture,
        label: "move vertices".into(),
    });
    Drag::Move {
        gesture,
        start_pointer: origin,
        start,
        snap: None,
    }
}

/// Next to the pointer, over a cage vertex drawn as a problem (or of a cage drawn so): what is
/// wrong there.
fn problem_under_pointer(state: &EditorState, ui: &egui::Ui) {
    let Some(v) = state.selection.hovered else {
        return;
    };
    let Some(reason) = state.rig_warnings.reason_at_vertex(&state.doc.scene, v) else {
        return;
    };
    let Some(pointer) = ui.ctx().input(|i| i.pointer.latest_pos()) else {
        return;
    };
    egui::Area::new(egui::Id::unique("problem-under-pointer"))
        .order(egui::Order::Tooltip)
        .fixed_pos(pointer + egui::vec2(16.0, 16.0))
        .interactable(false)
        .show(ui.ctx(), |ui| {
            egui::Frame::popup(ui.style()).show(ui, |ui| {
                ui.set_max_width(360.0);
                ui.label(format!("Problem here: {reason}"));
            });
        });
}

/// A banner over the viewport while the rig has problems: how many, the first, and that the
/// last valid binding stays in use.
fn rig_banner(state: &EditorState, ui: &egui::Ui, rect: egui::Rect) {
    let Some(first) = state.rig_problems.first() else {
        return;
    };
    let text = format!(
        "The rig has {} problem(s); the last valid binding stays in use until they are fixed. \
         First: {first}",
        state.rig_problems.len()
    );
    egui::Area::new(egui::Id::unique("rig-problems"))
        .order(egui::Order::Foreground)
        .pivot(egui::Align2::CENTER_BOTTOM)
        .fixed_pos(rect.center_bottom() - egui::vec2(0.0, 70.0))
        .interactable(false)
        .show(ui.ctx(), |ui| {
            egui::Frame::new()
                .fill(egui::Color32::from_rgb(120, 40, 30))
                .corner_radius(4.0)
                .inner_margin(egui::Margin::symmetric(10, 6))
                .show(ui, |ui| {
                    ui.set_max_width(rect.width() * 0.8);
                    ui.label(egui::RichText::new(text).color(egui::Color32::WHITE));
                });
        });
}

/// While a loop cut is placed: the ring where it would cut, and a header with the fraction.
fn loop_cut_overlay(
    state: &EditorState,
    cut: &super::loop_cut_tool::LoopCutTool,
    painter: &egui::Painter,
    rect: egui::Rect,
) {
    let ring = on_screen(state, rect, &cut.ring_points(state));
    if ring.len() >= 2 {
        closed_outline(painter, ring);
    }
    header_label(painter.ctx(), rect, "loop-cut-header", cut.header());
}

/// Rest points on screen (those in front of the camera).
fn on_screen(state: &EditorState, rect: egui::Rect, points: &[glam::DVec3]) -> Vec<egui::Pos2> {
    let camera = &state.view.camera;
    let size = state.view.viewport.size;
    points
        .iter()
        .filter_map(|p| camera.project(p.as_vec3(), size))
        .map(|(q, _)| rect.min + egui::vec2(q.x, q.y))
        .collect()
}

/// A closed polyline through `points` (screen) in the selection colour: a preview of what a
/// tool would make.
fn closed_outline(painter: &egui::Painter, mut points: Vec<egui::Pos2>) {
    let [r, g, b, _] = colors::to_u8(colors::SELECTED);
    if let Some(&first) = points.first() {
        points.push(first);
    }
    painter.add(egui::Shape::line(
        points,
        egui::Stroke::new(2.5, egui::Color32::from_rgb(r, g, b)),
    ));
}

/// The inner faces the inset would make, outlined in the selection colour, and its header.
fn inset_overlay(
    state: &EditorState,
    inset: &super::inset_tool::InsetTool,
    painter: &egui::Painter,
    rect: egui::Rect,
) {
    for face in inset.inner_faces() {
        let outline = on_screen(state, rect, &face);
        if outline.len() == face.len() && outline.len() >= 3 {
            closed_outline(painter, outline);
        }
    }
    header_label(painter.ctx(), rect, "inset-header", inset.header());
}

/// A header at the top of the viewport: a label in an area (not painted text), so it is in
/// the accessibility tree.
fn header_label(ctx: &egui::Context, rect: egui::Rect, id: &str, text: String) {
    egui::Area::new(egui::Id::unique(id))
        .order(egui::Order::Foreground)
        .pivot(egui::Align2::CENTER_TOP)
        // Below the row of Rig mode's select modes, which it would otherwise cover.
        .fixed_pos(rect.center_top() + egui::vec2(0.0, 44.0))
        .interactable(false)
        .show(ctx, |ui| {
            egui::Frame::new()
                .fill(egui::Color32::from_black_alpha(170))
                .corner_radius(4.0)
                .inner_margin(egui::Margin::symmetric(8, 4))
                .show(ui, |ui| {
                    let text = egui::RichText::new(text)
                        .size(15.0)
                        .color(egui::Color32::WHITE);
                    // One line, however narrow the area was when it first appeared.
                    ui.add(egui::Label::new(text).extend());
                });
        });
}

/// The snap target `at`, ringed as Blender's snapping circle.
fn snap_ring(state: &EditorState, painter: &egui::Painter, rect: egui::Rect, at: DVec3) {
    let view = state.view.viewport;
    if let Some((q, _)) = state.view.camera.project(at.as_vec3(), view.size) {
        let [r, g, b, _] = colors::to_u8(colors::SELECTED);
        painter.circle_stroke(
            rect.min + egui::vec2(q.x, q.y),
            SNAP_RADIUS * 0.6,
            egui::Stroke::new(2.0, egui::Color32::from_rgb(r, g, b)),
        );
    }
}

/// While G / R / S runs: the locked axis as a line through the pivot, in the axis colour, and a
/// header with the live amount at the top of the viewport.
fn tool_overlay(
    state: &EditorState,
    tool: &super::TransformTool,
    painter: &egui::Painter,
    rect: egui::Rect,
    pointer: Vec2,
) {
    let camera = &state.view.camera;
    let view = state.view.viewport;
    if let Some(axis) = tool.axis {
        let pivot = tool.pivot().as_vec3();
        let direction = axis.vector().as_vec3();
        // Long enough to cross the view; both ends in front of the eye.
        let reach = camera.distance * 20.0;
        let ends = [pivot - direction * reach, pivot + direction * reach]
            .map(|p| camera.project(p, view.size).map(|(q, _)| q));
        if let [Some(a), Some(b)] = ends {
            let [r, g, bl, _] =
                colors::to_u8([colors::X_AXIS, colors::Y_AXIS, colors::Z_AXIS][axis.index()]);
            painter.line_segment(
                [
                    rect.min + egui::vec2(a.x, a.y),
                    rect.min + egui::vec2(b.x, b.y),
                ],
                egui::Stroke::new(1.5, egui::Color32::from_rgb(r, g, bl)),
            );
        }
    }
    if let Some((_, at)) = tool.snap {
        snap_ring(state, painter, rect, at);
    }
    let header = tool.header(tool.amount(camera, view, pointer));
    header_label(painter.ctx(), rect, "transform-header", header);
}

fn overlays(
    state: &EditorState,
    ui_state: &UiState,
    ui: &egui::Ui,
    rect: egui::Rect,
    pointer: Option<Vec2>,
) {
    let painter = ui.painter_at(rect);
    if let (Some(tool), Some(pointer)) = (&ui_state.tool, pointer) {
        tool_overlay(state, tool, &painter, rect, pointer);
    }
    super::select_modes::selected_faces_overlay(state, &painter, rect);
    super::control_handles::draw(state, &painter, pointer);
    match (&ui_state.drag, pointer) {
        (
            Some(Drag::Move {
                snap: Some((_, at)),
                ..
            }),
            _,
        ) => snap_ring(state, &painter, rect, *at),
        (
            Some(Drag::Region {
                lasso: Some(path), ..
            }),
            _,
        ) => {
            let mut outline: Vec<egui::Pos2> = path.iter().map(|p| egui::pos2(p.x, p.y)).collect();
            if let Some(first) = outline.first().copied() {
                outline.push(first);
            }
            painter.add(egui::Shape::dashed_line(
                &outline,
                egui::Stroke::new(1.0, egui::Color32::WHITE),
                6.0,
                4.0,
            ));
        }
        (Some(Drag::Region { start, .. }), Some(end)) => {
            let r =
                egui::Rect::from_two_pos(egui::pos2(start.x, start.y), egui::pos2(end.x, end.y));
            painter.rect_stroke(
                r,
                0.0,
                egui::Stroke::new(1.0, egui::Color32::WHITE),
                egui::StrokeKind::Inside,
            );
        }
        _ => {}
    }
    let font = egui::FontId::proportional(12.0);
    let text = egui::Color32::from_gray(230);
    let origin = rect.left_bottom() + egui::vec2(16.0, -40.0);
    let Some(values) = state.map.values() else {
        if let Some(note) = &state.map.note
            && state.view.influence != crate::state::InfluenceChoice::None
        {
            painter.text(origin, egui::Align2::LEFT_BOTTOM, note, font, text);
        }
        return;
    };
    // The legend: the ramp with its ends and title, bottom left.
    let width = 180.0;
    let steps = 36;
    for i in 0..steps {
        let t = i as f32 / (steps - 1) as f32;
        let [r, g, b, _] = colors::to_u8(colors::ramp(t));
        let x = origin.x + width * i as f32 / steps as f32;
        painter.rect_filled(
            egui::Rect::from_min_size(
                egui::pos2(x, origin.y),
                egui::vec2(width / steps as f32 + 0.5, 12.0),
            ),
            0.0,
            egui::Color32::from_rgb(r, g, b),
        );
    }
    painter.text(
        origin - egui::vec2(0.0, 4.0),
        egui::Align2::LEFT_BOTTOM,
        &values.title,
        font.clone(),
        text,
    );
    painter.text(
        origin + egui::vec2(0.0, 14.0),
        egui::Align2::LEFT_TOP,
        &values.range.0,
        font.clone(),
        text,
    );
    painter.text(
        origin + egui::vec2(width, 14.0),
        egui::Align2::RIGHT_TOP,
        &values.range.1,
        font,
        text,
    );
}

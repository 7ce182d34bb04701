//! The viewport's mouse and keyboard, as Blender users expect: orbit (middle or Alt+left),
//! pan (Shift+middle), zoom to the cursor (wheel), click to pick a cage vertex (Shift toggles),
//! drag a vertex to move the selection in the view plane, drag on empty space for a selection
//! rectangle, and G / R / S with X / Y / Z locks and typed numbers (Enter or click confirms,
//! Esc or right click cancels).

use std::sync::Arc;

use egui::{Pos2, Sense};
use glam::{DQuat, DVec3, Vec2, Vec3};
use starcages_viewport::layers::{cage_dots, cage_lines};
use starcages_viewport::picking::{pick_nearest, select_in_rectangle};
use starcages_viewport::{OrbitCamera, colors};

use crate::app::EditorApp;
use crate::undo::Snapshot;
use crate::viewport::{FrameData, MeshUpload, ViewportCallback};

/// Pick radius in points.
const PICK_RADIUS: f32 = 10.0;

/// A mouse drag in the viewport.
#[derive(Debug)]
pub enum Drag {
    /// Moving the selected vertices in the view plane.
    Move {
        /// The scene before the drag (one undo step for the whole drag).
        before: Box<Snapshot>,
        /// Where the drag started.
        start_pointer: Pos2,
        /// The selection's positions when it started.
        start: Vec<(u32, DVec3)>,
    },
    /// A selection rectangle from this corner.
    Rectangle {
        /// The first corner.
        start: Pos2,
        /// Shift held: add to the selection.
        extend: bool,
    },
    /// Orbiting or panning the camera.
    Camera,
}

/// G, R or S.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Grab: move.
    Grab,
    /// Rotate about the selection's centre.
    Rotate,
    /// Scale about the selection's centre.
    Scale,
}

/// An axis lock.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// X.
    X,
    /// Y.
    Y,
    /// Z.
    Z,
}

impl Axis {
    fn vector(self) -> DVec3 {
        match self {
            Self::X => DVec3::X,
            Self::Y => DVec3::Y,
            Self::Z => DVec3::Z,
        }
    }
}

/// A modal transform of the selection (Blender's G / R / S).
#[derive(Debug)]
pub struct TransformTool {
    /// Grab, rotate or scale.
    pub mode: Mode,
    /// Axis lock.
    pub axis: Option<Axis>,
    /// A typed value (distance, degrees or factor) overriding the mouse.
    pub typed: String,
    start_pointer: Pos2,
    centre: DVec3,
    start: Vec<(u32, DVec3)>,
    before: Box<Snapshot>,
}

/// World displacement for a pointer move of `delta` points, in the view plane through `at`.
fn view_plane_delta(camera: &OrbitCamera, height: f32, at: DVec3, delta: egui::Vec2) -> DVec3 {
    let (right, up) = camera.right_up();
    let depth = (at.as_vec3() - camera.eye())
        .dot(-camera.backward())
        .max(1e-4);
    let per_point = 2.0 * depth * (camera.fov_y * 0.5).tan() / height.max(1.0);
    ((right * delta.x - up * delta.y) * per_point).as_dvec3()
}

impl TransformTool {
    /// Starts `mode` on the current selection at `pointer`; `None` without a selection.
    pub fn begin(app: &EditorApp, mode: Mode, pointer: Pos2) -> Option<Self> {
        let pose = &app.doc.scene.pose;
        let start: Vec<(u32, DVec3)> = app
            .view
            .style
            .selected
            .iter()
            .filter_map(|&v| pose.get(v as usize).map(|p| (v, *p)))
            .collect();
        if start.is_empty() {
            return None;
        }
        let centre = start.iter().map(|s| s.1).sum::<DVec3>() / start.len() as f64;
        Some(Self {
            mode,
            axis: None,
            typed: String::new(),
            start_pointer: pointer,
            centre,
            start,
            before: Box::new(Snapshot::of(&app.doc.scene)),
        })
    }

    fn typed_value(&self) -> Option<f64> {
        self.typed.parse::<f64>().ok().filter(|v| v.is_finite())
    }

    /// The moves for the pointer at `pointer` in a viewport `rect`.
    pub fn moves(
        &self,
        camera: &OrbitCamera,
        rect: egui::Rect,
        pointer: Pos2,
    ) -> Vec<(u32, DVec3)> {
        let size = Vec2::new(rect.width(), rect.height());
        let local = |p: Pos2| Vec2::new(p.x - rect.min.x, p.y - rect.min.y);
        let centre_px = camera
            .project(self.centre.as_vec3(), size)
            .map_or(size * 0.5, |(p, _)| p);
        let map: Box<dyn Fn(DVec3) -> DVec3> = match self.mode {
            Mode::Grab => {
                let mut delta = match (self.typed_value(), self.axis) {
                    (Some(v), axis) => axis.unwrap_or(Axis::X).vector() * v,
                    (None, _) => view_plane_delta(
                        camera,
                        rect.height(),
                        self.centre,
                        pointer - self.start_pointer,
                    ),
                };
                if let Some(axis) = self.axis {
                    delta = axis.vector() * delta.dot(axis.vector());
                }
                Box::new(move |p| p + delta)
            }
            Mode::Rotate => {
                let angle = self.typed_value().map_or_else(
                    || {
                        let a = local(self.start_pointer) - centre_px;
                        let b = local(pointer) - centre_px;
                        // Screen y points down: counter-clockwise on screen is negative here.
                        f64::from(-(a.x * b.y - a.y * b.x).atan2(a.dot(b)))
                    },
                    f64::to_radians,
                );
                let axis = self
                    .axis
                    .map_or_else(|| camera.backward().as_dvec3(), Axis::vector);
                let turn = DQuat::from_axis_angle(axis, angle);
                let centre = self.centre;
                Box::new(move |p| centre + turn * (p - centre))
            }
            Mode::Scale => {
                let factor = self.typed_value().unwrap_or_else(|| {
                    let a = (local(self.start_pointer) - centre_px).length().max(1.0);
                    f64::from((local(pointer) - centre_px).length() / a)
                });
                let (centre, axis) = (self.centre, self.axis.map(Axis::vector));
                Box::new(move |p| match axis {
                    Some(a) => p + a * (p - centre).dot(a) * (factor - 1.0),
                    None => centre + (p - centre) * factor,
                })
            }
        };
        self.start.iter().map(|&(v, p)| (v, map(p))).collect()
    }

    /// A one-line description for the status bar.
    pub fn describe(&self) -> String {
        let name = match self.mode {
            Mode::Grab => "Grab",
            Mode::Rotate => "Rotate",
            Mode::Scale => "Scale",
        };
        let axis = self.axis.map_or(String::new(), |a| format!(" along {a:?}"));
        let typed = if self.typed.is_empty() {
            String::new()
        } else {
            format!(": {}", self.typed)
        };
        format!(
            "{name}{axis}{typed} — X/Y/Z lock, type a number, Enter or click to confirm, Esc or right click to cancel"
        )
    }
}

impl EditorApp {
    /// Ends the transform tool, keeping (one undo step) or reverting its edit.
    pub fn finish_tool(&mut self, keep: bool) {
        let Some(tool) = self.tool.take() else {
            return;
        };
        let label = match tool.mode {
            Mode::Grab => "grab",
            Mode::Rotate => "rotate",
            Mode::Scale => "scale",
        };
        if keep {
            self.undo.push(label, *tool.before);
        } else {
            tool.before.restore(&mut self.doc.scene);
            self.state_replaced();
        }
    }

    /// Selects vertex `v` (alone, or toggled into the selection with `toggle`).
    pub fn select_vertex(&mut self, v: u32, toggle: bool) {
        let selected = &mut self.view.style.selected;
        if toggle {
            if !selected.remove(&v) {
                selected.insert(v);
            }
        } else {
            selected.clear();
            selected.insert(v);
        }
    }

    /// Vertices of visible cages, per vertex (for picking).
    fn pickable(&self) -> Vec<bool> {
        let set = &self.doc.scene.cages;
        let mut pickable = vec![false; set.vertices.len()];
        let leaves = set.leaves.len();
        for (c, faces) in set
            .leaves
            .iter()
            .map(|l| &l.faces)
            .chain(set.internals.iter().map(|i| &i.faces))
            .enumerate()
        {
            if self.view.style.hidden.contains(&c) || (c >= leaves && !self.view.layers.cages) {
                continue;
            }
            for &v in faces.iter().flatten() {
                pickable[v as usize] = true;
            }
        }
        pickable
    }

    fn pose_f32(&self) -> Vec<Vec3> {
        self.doc.scene.pose.iter().map(|p| p.as_vec3()).collect()
    }

    /// The cage vertex under `pointer` (screen position in points), if any.
    pub fn pick(&self, pointer: Pos2) -> Option<u32> {
        let rect = self.view.viewport;
        let size = Vec2::new(rect.width(), rect.height());
        let cursor = Vec2::new(pointer.x - rect.min.x, pointer.y - rect.min.y);
        pick_nearest(
            &self.view.camera,
            size,
            &self.pose_f32(),
            &self.pickable(),
            cursor,
            PICK_RADIUS,
        )
        .map(|i| i as u32)
    }

    /// The screen position (points) of cage vertex `v` in the current view.
    pub fn vertex_on_screen(&self, v: u32) -> Option<Pos2> {
        let rect = self.view.viewport;
        let size = Vec2::new(rect.width(), rect.height());
        let p = self.doc.scene.pose.get(v as usize)?.as_vec3();
        let (pixel, _) = self.view.camera.project(p, size)?;
        Some(rect.min + egui::vec2(pixel.x, pixel.y))
    }

    /// Frames everything (Home) or the selection (F).
    pub fn frame(&mut self, selection_only: bool) {
        let pose = &self.doc.scene.pose;
        let points: Vec<DVec3> = if selection_only && !self.view.style.selected.is_empty() {
            self.view
                .style
                .selected
                .iter()
                .filter_map(|&v| pose.get(v as usize).copied())
                .collect()
        } else {
            let mut all = pose.clone();
            all.extend(self.deformed().iter().map(|p| p.as_dvec3()));
            all
        };
        let (lo, hi) = starcages_core::cage::bounds_of(&points);
        let pad = if selection_only { 0.2 } else { 0.0 };
        self.view
            .camera
            .frame(lo.as_vec3() - pad, hi.as_vec3() + pad);
    }
}

/// The viewport: input, the 3D view through the paint callback, overlays.
pub fn viewport_ui(app: &mut EditorApp, ui: &mut egui::Ui) {
    let (rect, response) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
    app.view.viewport = rect;
    let (pointer, modifiers, scroll, secondary) = ui.input(|i| {
        (
            i.pointer.latest_pos(),
            i.modifiers,
            i.smooth_scroll_delta.y,
            i.pointer.secondary_clicked(),
        )
    });
    let size = Vec2::new(rect.width(), rect.height());
    if app.tool.is_some() {
        // The tool follows the pointer in `shortcuts`; here only its mouse confirm / cancel.
        if response.clicked() {
            app.finish_tool(true);
        } else if secondary {
            app.finish_tool(false);
        }
    } else {
        if response.hovered() && scroll != 0.0 {
            let cursor = pointer.map(|p| Vec2::new(p.x - rect.min.x, p.y - rect.min.y));
            app.view.camera.zoom(scroll / 50.0, cursor, size);
        }
        let camera_drag = response.dragged_by(egui::PointerButton::Middle)
            || (response.dragged_by(egui::PointerButton::Primary) && modifiers.alt);
        if camera_drag {
            let delta = response.drag_delta();
            if modifiers.shift {
                app.view.camera.pan(Vec2::new(delta.x, delta.y), size.y);
            } else {
                app.view.camera.orbit(Vec2::new(delta.x, delta.y));
            }
            app.drag = Some(Drag::Camera);
        } else if response.drag_started_by(egui::PointerButton::Primary) {
            let origin = ui
                .input(|i| i.pointer.press_origin())
                .or(pointer)
                .unwrap_or(rect.center());
            match app.pick(origin) {
                Some(v) => {
                    if !app.view.style.selected.contains(&v) {
                        app.select_vertex(v, modifiers.shift);
                    }
                    let pose = &app.doc.scene.pose;
                    let start = app
                        .view
                        .style
                        .selected
                        .iter()
                        .map(|&s| (s, pose[s as usize]))
                        .collect();
                    app.drag = Some(Drag::Move {
                        before: Box::new(Snapshot::of(&app.doc.scene)),
                        start_pointer: origin,
                        start,
                    });
                }
                None => {
                    app.drag = Some(Drag::Rectangle {
                        start: origin,
                        extend: modifiers.shift,
                    });
                }
            }
        }
        if response.dragged_by(egui::PointerButton::Primary)
            && let (
                Some(Drag::Move {
                    start_pointer,
                    start,
                    ..
                }),
                Some(p),
            ) = (&app.drag, pointer)
        {
            let centre = start.iter().map(|s| s.1).sum::<DVec3>() / start.len().max(1) as f64;
            let delta =
                view_plane_delta(&app.view.camera, rect.height(), centre, p - *start_pointer);
            let moves: Vec<(u32, DVec3)> = start.iter().map(|&(v, q)| (v, q + delta)).collect();
            app.apply_moves(&moves);
        }
        if response.drag_stopped() {
            match app.drag.take() {
                Some(Drag::Move { before, .. }) if *before != Snapshot::of(&app.doc.scene) => {
                    app.undo.push("move vertices", *before);
                }
                Some(Drag::Rectangle { start, extend }) => {
                    if let Some(end) = pointer {
                        let local = |p: Pos2| Vec2::new(p.x - rect.min.x, p.y - rect.min.y);
                        let hits = select_in_rectangle(
                            &app.view.camera,
                            size,
                            &app.pose_f32(),
                            &app.pickable(),
                            local(start),
                            local(end),
                        );
                        if !extend {
                            app.view.style.selected.clear();
                        }
                        app.view
                            .style
                            .selected
                            .extend(hits.iter().map(|&i| i as u32));
                    }
                }
                _ => {}
            }
        }
        if response.clicked() {
            match pointer.and_then(|p| app.pick(p)) {
                Some(v) => app.select_vertex(v, modifiers.shift),
                None if !modifiers.shift => app.view.style.selected.clear(),
                None => {}
            }
        }
    }
    app.view.style.hovered = if response.hovered() {
        pointer.and_then(|p| app.pick(p))
    } else {
        None
    };
    paint(app, ui, rect);
    overlays(app, ui, rect, pointer);
}

fn paint(app: &mut EditorApp, ui: &mut egui::Ui, rect: egui::Rect) {
    if !app.gpu {
        ui.painter()
            .rect_filled(rect, 0.0, egui::Color32::from_gray(40));
        ui.painter().text(
            rect.center(),
            egui::Align2::CENTER_CENTER,
            "3D view unavailable: no wgpu device",
            egui::FontId::proportional(16.0),
            egui::Color32::LIGHT_GRAY,
        );
        return;
    }
    let colors = app.map_colors();
    let scene = &app.doc.scene;
    let lines = Arc::new(cage_lines(&scene.cages, &scene.pose, &app.view.style));
    let dots = Arc::new(cage_dots(&scene.cages, &scene.pose, &app.view.style));
    let mesh = app.rig.as_ref().map(|rig| {
        let generation = app.generations.mesh;
        match &app.mesh_upload {
            Some((g, m)) if *g == generation => (generation, Arc::clone(m)),
            _ => {
                let upload = Arc::new(MeshUpload {
                    positions: scene.mesh.welded_positions_f32(),
                    triangles: scene.mesh.welded_triangles().to_vec(),
                    binding: Arc::clone(&rig.binding),
                });
                app.mesh_upload = Some((generation, Arc::clone(&upload)));
                (generation, upload)
            }
        }
    });
    let deformation = app.rig.as_ref().map(|rig| {
        (
            app.generations.deformation,
            Arc::clone(&rig.dofs),
            Arc::clone(&rig.deformed),
        )
    });
    let data = FrameData {
        camera: app.view.camera,
        layers: app.view.layers,
        lines,
        dots,
        mesh,
        deformation,
        colors,
    };
    ui.painter().add(egui_wgpu::Callback::new_paint_callback(
        rect,
        ViewportCallback {
            data,
            size_points: rect.size(),
        },
    ));
}

fn overlays(app: &EditorApp, ui: &egui::Ui, rect: egui::Rect, pointer: Option<Pos2>) {
    let painter = ui.painter_at(rect);
    if let (Some(Drag::Rectangle { start, .. }), Some(end)) = (&app.drag, pointer) {
        let r = egui::Rect::from_two_pos(*start, end);
        painter.rect_stroke(
            r,
            0.0,
            egui::Stroke::new(1.0, egui::Color32::WHITE),
            egui::StrokeKind::Inside,
        );
    }
    if let Some(values) = app.map_values() {
        // The legend: the ramp with its ends and title, bottom left.
        let origin = rect.left_bottom() + egui::vec2(16.0, -40.0);
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
        let font = egui::FontId::proportional(12.0);
        let text = egui::Color32::from_gray(230);
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
}

/// Keyboard shortcuts of the viewport and the app (ignored while a text field has focus).
pub fn shortcuts(app: &mut EditorApp, ctx: &egui::Context) {
    use egui::{Key, KeyboardShortcut, Modifiers};
    if ctx.egui_wants_keyboard_input() {
        return;
    }
    let command = Modifiers::COMMAND;
    let consume =
        |m: Modifiers, k: Key| ctx.input_mut(|i| i.consume_shortcut(&KeyboardShortcut::new(m, k)));
    if consume(command | Modifiers::SHIFT, Key::Z) || consume(command, Key::Y) {
        app.redo();
    } else if consume(command, Key::Z) {
        app.undo();
    }
    if consume(command | Modifiers::SHIFT, Key::S) {
        crate::panels::save_as_dialog(app);
    } else if consume(command, Key::S) {
        crate::panels::save(app);
    }
    if consume(command, Key::O) {
        crate::panels::open_dialog(app);
    }
    let pointer = ctx
        .input(|i| i.pointer.latest_pos())
        .unwrap_or(app.view.viewport.center());
    if let Some(tool) = &mut app.tool {
        let (events, enter, escape) = ctx.input(|i| {
            (
                i.events.clone(),
                i.key_pressed(Key::Enter),
                i.key_pressed(Key::Escape),
            )
        });
        for event in events {
            match event {
                egui::Event::Text(text) => {
                    for c in text.chars() {
                        match c {
                            'x' | 'X' => tool.axis = toggle(tool.axis, Axis::X),
                            'y' | 'Y' => tool.axis = toggle(tool.axis, Axis::Y),
                            'z' | 'Z' => tool.axis = toggle(tool.axis, Axis::Z),
                            '0'..='9' | '.' | '-' => tool.typed.push(c),
                            _ => {}
                        }
                    }
                }
                egui::Event::Key {
                    key: Key::Backspace,
                    pressed: true,
                    ..
                } => {
                    tool.typed.pop();
                }
                _ => {}
            }
        }
        let moves = tool.moves(&app.view.camera, app.view.viewport, pointer);
        app.apply_moves(&moves);
        if enter {
            app.finish_tool(true);
        } else if escape {
            app.finish_tool(false);
        }
        return;
    }
    let pressed = |k: Key| ctx.input(|i| i.key_pressed(k) && !i.modifiers.command);
    let alt = ctx.input(|i| i.modifiers.alt);
    for (key, mode) in [
        (Key::G, Mode::Grab),
        (Key::R, Mode::Rotate),
        (Key::S, Mode::Scale),
    ] {
        if pressed(key) {
            app.tool = TransformTool::begin(app, mode, pointer);
            if app.tool.is_none() {
                app.info(
                    "select cage vertices first (click, Shift+click, drag a rectangle, or A)"
                        .into(),
                );
            }
        }
    }
    if pressed(Key::A) {
        if alt {
            app.view.style.selected.clear();
        } else {
            let all = app.pickable();
            app.view.style.selected = (0..all.len() as u32).filter(|&v| all[v as usize]).collect();
        }
    }
    if pressed(Key::Home) {
        app.frame(false);
    }
    if pressed(Key::F) || pressed(Key::Period) {
        app.frame(true);
    }
    for (key, view) in [
        (Key::Num1, starcages_viewport::View::Front),
        (Key::Num3, starcages_viewport::View::Side),
        (Key::Num7, starcages_viewport::View::Top),
    ] {
        if pressed(key) {
            app.view.camera.set_view(view);
        }
    }
}

fn toggle(current: Option<Axis>, axis: Axis) -> Option<Axis> {
    if current == Some(axis) {
        None
    } else {
        Some(axis)
    }
}

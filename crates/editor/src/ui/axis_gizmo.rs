//! The axis gizmo in the viewport's corner, as Blender's: the world axes as the camera sees
//! them (X red, Y green, Z blue; the negative ends as hollow circles), drawn nearest last; a
//! click on an end looks along that axis from there, and the projection is named below.

use egui::{Color32, Pos2, Stroke, pos2, vec2};
use starcages_viewport::{OrbitCamera, View, colors};

/// Radius of the gizmo (points) and of an axis end's circle.
const RADIUS: f32 = 40.0;
const END: f32 = 9.0;

/// One end of an axis on screen.
#[derive(Debug, Clone, Copy)]
struct AxisEnd {
    axis: usize,
    positive: bool,
    at: Pos2,
    /// Towards the viewer (drawn later, clicked first).
    depth: f32,
}

fn color(axis: usize) -> Color32 {
    let [r, g, b, _] = colors::to_u8([colors::X_AXIS, colors::Y_AXIS, colors::Z_AXIS][axis]);
    Color32::from_rgb(r, g, b)
}

/// The axis ends for `camera`, around `centre`, farthest first.
fn ends(camera: &OrbitCamera, centre: Pos2) -> Vec<AxisEnd> {
    let (right, up) = camera.right_up();
    let back = camera.backward();
    let mut ends: Vec<AxisEnd> = (0..3)
        .flat_map(|axis| [true, false].map(move |positive| (axis, positive)))
        .map(|(axis, positive)| {
            let mut direction = glam::Vec3::ZERO;
            direction[axis] = if positive { 1.0 } else { -1.0 };
            AxisEnd {
                axis,
                positive,
                at: centre + vec2(direction.dot(right), -direction.dot(up)) * (RADIUS - END),
                depth: direction.dot(back),
            }
        })
        .collect();
    ends.sort_by(|a, b| a.depth.total_cmp(&b.depth));
    ends
}

/// Where the gizmo's centre is in a viewport `rect`.
pub fn centre(rect: egui::Rect) -> Pos2 {
    pos2(rect.max.x - RADIUS - 12.0, rect.min.y + RADIUS + 12.0)
}

/// Draws the gizmo; the view to turn to when an axis end was clicked at `click`.
pub fn gizmo(
    painter: &egui::Painter,
    rect: egui::Rect,
    camera: &OrbitCamera,
    click: Option<Pos2>,
) -> Option<View> {
    let centre = centre(rect);
    let ends = ends(camera, centre);
    painter.circle_filled(centre, RADIUS, Color32::from_black_alpha(60));
    for end in &ends {
        let c = color(end.axis);
        if end.positive {
            painter.line_segment([centre, end.at], Stroke::new(2.0, c));
            painter.circle_filled(end.at, END, c);
            painter.text(
                end.at,
                egui::Align2::CENTER_CENTER,
                ["X", "Y", "Z"][end.axis],
                egui::FontId::proportional(11.0),
                Color32::BLACK,
            );
        } else {
            painter.circle(
                end.at,
                END * 0.8,
                c.gamma_multiply(0.35),
                Stroke::new(1.5, c),
            );
        }
    }
    let projection = if camera.orthographic {
        "Orthographic"
    } else {
        "Perspective"
    };
    painter.text(
        centre + vec2(0.0, RADIUS + 4.0),
        egui::Align2::CENTER_TOP,
        projection,
        egui::FontId::proportional(11.0),
        Color32::from_gray(200),
    );
    let click = click?;
    // The nearest end under the click (ends drawn last are nearest).
    ends.iter()
        .rev()
        .find(|end| end.at.distance(click) <= END)
        .map(|end| View::from_axis(end.axis, end.positive))
}

/// Whether `point` is on the gizmo (so a click there is not a pick in the scene).
pub fn contains(rect: egui::Rect, point: Pos2) -> bool {
    centre(rect).distance(point) <= RADIUS
}

/// Screen position of the end of `axis` (positive or not) for `camera` in `rect` (tests click
/// it).
pub fn end_position(rect: egui::Rect, camera: &OrbitCamera, axis: usize, positive: bool) -> Pos2 {
    ends(camera, centre(rect))
        .into_iter()
        .find(|e| e.axis == axis && e.positive == positive)
        .map_or(centre(rect), |e| e.at)
}

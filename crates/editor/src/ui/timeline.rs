//! The timeline strip under the viewport: transport buttons, the frame, range and rate, auto-key,
//! the selected key's interpolation, and the strip itself — frame ticks, keys as diamonds, the
//! current frame as a line. Pressing on the strip scrubs; dragging a diamond retimes its key.

use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Shape, Stroke, StrokeKind, Vec2};
use starcages_core::anim::Interpolation;

use super::UiState;
use crate::commands::{Command, CommandSender, UiCommand};
use crate::state::EditorState;

/// A key being dragged along the strip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeyDrag {
    /// The key's frame when the drag began.
    pub from: f64,
    /// Where it would land now.
    pub to: f64,
}

/// Height of the strip, points.
const STRIP_HEIGHT: f32 = 34.0;
/// Half the size of a key's diamond, points.
const DIAMOND: f32 = 5.5;

/// The timeline panel's contents.
pub fn timeline(
    state: &EditorState,
    ui_state: &mut UiState,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    let animation = &state.doc.scene.animation;
    let frame = state.timeline.frame;
    ui.horizontal(|ui| {
        transport(state, ui, sender);
        ui.separator();
        let mut typed = frame;
        let response = ui
            .add(
                egui::DragValue::new(&mut typed)
                    .speed(0.2)
                    .range(-1e6..=1e6)
                    .max_decimals(2),
            )
            .on_hover_text("The current frame; drag or type to go to another");
        response.widget_info(|| {
            egui::WidgetInfo::labeled(egui::Role::SpinButton, true, "Current frame")
        });
        if typed != frame {
            sender.send(Command::SetFrame(typed));
        }
        ui.separator();
        let (mut start, mut end, mut fps) =
            (animation.frame_start, animation.frame_end, animation.fps);
        ui.label("Start");
        let start_changed = ui
            .add(egui::DragValue::new(&mut start).range(-1_000_000..=end))
            .on_hover_text("First frame of playback and of a bake")
            .changed();
        ui.label("End");
        let end_changed = ui
            .add(egui::DragValue::new(&mut end).range(start..=1_000_000))
            .on_hover_text("Last frame of playback and of a bake")
            .changed();
        ui.label("fps");
        let fps_changed = ui
            .add(egui::DragValue::new(&mut fps).range(1.0..=240.0).speed(0.1))
            .on_hover_text("Frames per second")
            .changed();
        if start_changed || end_changed || fps_changed {
            sender.send(Command::SetAnimationRange { fps, start, end });
        }
        ui.separator();
        let mut auto_key = state.timeline.auto_key;
        if ui
            .toggle_value(&mut auto_key, "Auto-key")
            .on_hover_text(UiCommand::ToggleAutoKey.tooltip())
            .changed()
        {
            sender.send(Command::SetAutoKey(auto_key));
        }
        if ui
            .button(UiCommand::InsertKey.label())
            .on_hover_text(format!("{} (I)", UiCommand::InsertKey.tooltip()))
            .clicked()
        {
            sender.send(Command::InsertKey);
        }
        if let Some(key_frame) = selected_or_current_key(state, ui_state) {
            key_interpolation(state, key_frame, ui, sender);
        }
        if let Some(playing) = &state.timeline.playing
            && playing.shown_fps > 0.0
        {
            ui.label(format!(
                "playing {:.0} fps (deform {:.1} ms)",
                playing.shown_fps, state.stats.deform_ms
            ));
        }
    });
    strip(state, ui_state, ui, sender);
}

/// ⏮ ▶/⏸ ⏭ buttons.
fn transport(state: &EditorState, ui: &mut egui::Ui, sender: &mut CommandSender) {
    let animation = &state.doc.scene.animation;
    if ui
        .button("|<")
        .on_hover_text(UiCommand::JumpToStart.tooltip())
        .clicked()
    {
        sender.send(Command::SetFrame(animation.frame_start as f64));
    }
    let playing = state.timeline.playing.is_some();
    let (label, tip) = if playing {
        ("Pause", "Stop playback (Space)")
    } else {
        ("Play", "Play the animation in real time, looping (Space)")
    };
    if ui.button(label).on_hover_text(tip).clicked() {
        sender.send(Command::SetPlaying(!playing));
    }
    if ui
        .button(">|")
        .on_hover_text(UiCommand::JumpToEnd.tooltip())
        .clicked()
    {
        sender.send(Command::SetFrame(animation.frame_end as f64));
    }
}

/// The key selected on the strip, else the key at the current frame.
pub fn selected_or_current_key(state: &EditorState, ui_state: &UiState) -> Option<f64> {
    let animation = &state.doc.scene.animation;
    ui_state
        .selected_key
        .filter(|&f| animation.key_at(f).is_some())
        .or_else(|| {
            animation
                .key_at(state.timeline.frame)
                .map(|k| animation.keys[k].frame)
        })
}

/// The interpolation combo of the key at `key_frame`.
fn key_interpolation(
    state: &EditorState,
    key_frame: f64,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    let animation = &state.doc.scene.animation;
    let Some(index) = animation.key_at(key_frame) else {
        return;
    };
    let current = animation.keys[index].interpolation;
    egui::ComboBox::from_id_salt("key interpolation")
        .selected_text(format!("key {key_frame}: {}", current.name()))
        .show_ui(ui, |ui| {
            for mode in Interpolation::ALL {
                if ui.selectable_label(mode == current, mode.name()).clicked() && mode != current {
                    sender.send(Command::SetKeyInterpolation {
                        frame: key_frame,
                        interpolation: mode,
                    });
                }
            }
        })
        .response
        .on_hover_text(
            "How the key moves on to the next: constant holds, linear goes straight, bezier \
             eases (Blender's default)",
        );
}

/// Frame ↔ x on the strip.
struct FrameAxis {
    rect: Rect,
    first: f64,
    last: f64,
}

impl FrameAxis {
    fn x(&self, frame: f64) -> f32 {
        let t = (frame - self.first) / (self.last - self.first).max(1.0);
        self.rect.left() + 14.0 + (self.rect.width() - 28.0) * t as f32
    }

    fn frame(&self, x: f32) -> f64 {
        let t = f64::from((x - self.rect.left() - 14.0) / (self.rect.width() - 28.0).max(1.0));
        (self.first + t * (self.last - self.first).max(1.0)).round()
    }
}

/// The strip: ticks, keys, the current frame; scrubbing and key drags.
fn strip(
    state: &EditorState,
    ui_state: &mut UiState,
    ui: &mut egui::Ui,
    sender: &mut CommandSender,
) {
    let animation = &state.doc.scene.animation;
    let (rect, response) = ui.allocate_exact_size(
        Vec2::new(ui.available_width(), STRIP_HEIGHT),
        Sense::click_and_drag(),
    );
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Slider, true, "Timeline"));
    // The range, widened to show every key.
    let keys = animation.keys.iter().map(|k| k.frame);
    let first = keys
        .clone()
        .fold(animation.frame_start as f64, f64::min)
        .min(state.timeline.frame);
    let last = keys
        .fold(animation.frame_end as f64, f64::max)
        .max(state.timeline.frame);
    let axis = FrameAxis { rect, first, last };
    let painter = ui.painter_at(rect);
    let visuals = ui.visuals();
    painter.rect_filled(rect, 2.0, visuals.extreme_bg_color);
    // The playback range, lighter.
    let range = Rect::from_x_y_ranges(
        axis.x(animation.frame_start as f64)..=axis.x(animation.frame_end as f64),
        rect.y_range(),
    );
    painter.rect_filled(range, 0.0, visuals.faint_bg_color);
    let span = (last - first).max(1.0);
    let step = [1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0]
        .into_iter()
        .find(|s| span / s <= 25.0)
        .unwrap_or(1000.0);
    let mut tick = (first / step).ceil() * step;
    while tick <= last {
        let x = axis.x(tick);
        painter.line_segment(
            [Pos2::new(x, rect.top()), Pos2::new(x, rect.top() + 6.0)],
            Stroke::new(1.0, visuals.weak_text_color()),
        );
        painter.text(
            Pos2::new(x, rect.top() + 7.0),
            Align2::CENTER_TOP,
            format!("{tick}"),
            FontId::proportional(10.0),
            visuals.weak_text_color(),
        );
        tick += step;
    }
    let pointer = response.interact_pointer_pos();
    // A press on a diamond picks its key (where the press began: a drag is recognised only
    // once the pointer has moved); elsewhere it scrubs.
    let diamond_y = rect.bottom() - DIAMOND - 3.0;
    if response.drag_started() || response.clicked() {
        let origin = ui.input(|i| i.pointer.press_origin()).or(pointer);
        let hit = origin.and_then(|p| {
            animation.keys.iter().map(|k| k.frame).find(|&f| {
                (axis.x(f) - p.x).abs() <= DIAMOND + 2.0 && (p.y - diamond_y).abs() <= DIAMOND + 3.0
            })
        });
        ui_state.selected_key = hit;
        if response.drag_started() {
            ui_state.key_drag = hit.map(|from| KeyDrag { from, to: from });
        }
    }
    if let Some(p) = pointer
        && (response.dragged() || response.clicked() || response.drag_stopped())
    {
        let at = axis.frame(p.x);
        match &mut ui_state.key_drag {
            Some(drag) => drag.to = at,
            None if (ui_state.selected_key.is_none() || !response.clicked())
                && at != state.timeline.frame =>
            {
                sender.send(Command::SetFrame(at));
            }
            None => {}
        }
    }
    if response.drag_stopped()
        && let Some(drag) = ui_state.key_drag.take()
        && drag.to != drag.from
    {
        sender.send(Command::MoveKey {
            from: drag.from,
            to: drag.to,
        });
        ui_state.selected_key = Some(drag.to);
    }
    for key in &animation.keys {
        let shown = match ui_state.key_drag {
            Some(drag) if drag.from == key.frame => drag.to,
            _ => key.frame,
        };
        let centre = Pos2::new(axis.x(shown), diamond_y);
        let selected = ui_state.selected_key == Some(key.frame);
        let fill = if selected {
            Color32::from_rgb(255, 190, 60)
        } else {
            Color32::from_gray(210)
        };
        painter.add(Shape::convex_polygon(
            vec![
                centre + Vec2::new(0.0, -DIAMOND),
                centre + Vec2::new(DIAMOND, 0.0),
                centre + Vec2::new(0.0, DIAMOND),
                centre + Vec2::new(-DIAMOND, 0.0),
            ],
            fill,
            Stroke::new(1.0, Color32::BLACK),
        ));
    }
    // The current frame.
    let x = axis.x(state.timeline.frame);
    painter.line_segment(
        [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
        Stroke::new(2.0, Color32::from_rgb(80, 140, 255)),
    );
    let label = format!("{}", state.timeline.frame);
    let galley = painter.layout_no_wrap(label, FontId::proportional(11.0), Color32::WHITE);
    let tag = Rect::from_center_size(
        Pos2::new(x, rect.top() + 8.0),
        galley.size() + Vec2::new(8.0, 2.0),
    );
    painter.rect(
        tag,
        3.0,
        Color32::from_rgb(80, 140, 255),
        Stroke::NONE,
        StrokeKind::Inside,
    );
    painter.galley(tag.min + Vec2::new(4.0, 1.0), galley, Color32::WHITE);
}

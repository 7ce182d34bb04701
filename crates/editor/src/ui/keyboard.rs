//! Keys: while G / R / S runs, X / Y / Z, digits, Backspace, Enter and Esc drive the tool;
//! otherwise each key press looks up its action in the [`UiCommand`] table. Nothing happens
//! while a text field has the keyboard or a dialog is open.

use egui::{Event, Key};
use glam::Vec2;

use super::UiState;
use super::actions::execute;
use super::transform_tool::Axis;
use crate::commands::{Command, CommandSender, ToolKey, UiCommand};
use crate::state::EditorState;

/// This frame's keys.
pub fn shortcuts(
    state: &EditorState,
    ui_state: &mut UiState,
    ctx: &egui::Context,
    sender: &mut CommandSender,
) {
    if std::mem::take(&mut ui_state.drop_focus) {
        ctx.memory_mut(|m| {
            if let Some(id) = m.focused() {
                m.surrender_focus(id);
            }
        });
    }
    // A text field, the open add menu (which answers Esc itself) or a dialog has the keys:
    // typing a file name where the dialog's field lost focus must not rotate the rig.
    if ctx.egui_wants_keyboard_input() || ui_state.add_menu.is_some() || ui_state.dialog_open(state)
    {
        return;
    }
    let (events, pointer, ctrl) = ctx.input(|i| {
        let pointer = i.pointer.latest_pos().map(|p| Vec2::new(p.x, p.y));
        (i.events.clone(), pointer, i.modifiers.command)
    });
    let pointer = pointer.unwrap_or(state.view.viewport.center());
    if ui_state.tool.is_some() {
        let snapping = state.view.snap_to_vertices != ctrl;
        tool_keys(state, ui_state, &events, pointer, snapping, sender);
        return;
    }
    if ui_state.loop_cut.is_some() {
        loop_cut_keys(state, ui_state, &events, sender);
        return;
    }
    if ui_state.inset.is_some() {
        inset_keys(ui_state, &events, sender);
        return;
    }
    for event in events {
        if let Event::Key {
            key,
            pressed: true,
            repeat: false,
            modifiers,
            ..
        } = event
            && let Some(action) = UiCommand::for_key(key, modifiers, state.mode)
        {
            execute(action, state, ui_state, pointer, sender);
            // egui moves the keyboard focus on Tab; a Blender user pressing it meant the mode,
            // and the next key would go to that widget.
            ui_state.drop_focus = key == Key::Tab;
        }
    }
}

/// What the keys of a tool sized by the mouse or a typed number ended with.
enum Typed {
    /// Enter: make it.
    Confirm,
    /// Esc: drop it.
    Cancel,
}

/// The [`ToolKey`]s of a tool sized by a typed number: digits and '.' go into `typed` (a
/// fraction or a thickness is never negative), Backspace takes one back; Enter confirms, Esc
/// cancels.
fn typed_number_keys(typed: &mut String, events: &[Event]) -> Option<Typed> {
    for event in events {
        match event {
            Event::Text(text) => typed.extend(
                text.chars()
                    .filter(|&c| ToolKey::of_char(c) == Some(ToolKey::Digit) && c != '-'),
            ),
            Event::Key {
                key,
                pressed: true,
                modifiers,
                ..
            } => match ToolKey::of_key(*key, *modifiers) {
                Some(ToolKey::Backspace) => {
                    typed.pop();
                }
                Some(ToolKey::Confirm) => return Some(Typed::Confirm),
                Some(ToolKey::Cancel) => return Some(Typed::Cancel),
                _ => {}
            },
            _ => {}
        }
    }
    None
}

/// Keys of the loop cut being placed: digits type the fraction, Enter cuts, Esc drops it.
fn loop_cut_keys(
    state: &EditorState,
    ui_state: &mut UiState,
    events: &[Event],
    sender: &mut CommandSender,
) {
    let Some(cut) = &mut ui_state.loop_cut else {
        return;
    };
    match typed_number_keys(&mut cut.typed, events) {
        Some(Typed::Confirm) => {
            if let Ok(t) = cut.typed.parse::<f64>() {
                cut.t = t.clamp(0.02, 0.98);
            }
            sender.send(Command::Rig(cut.operation(state)));
            ui_state.loop_cut = None;
        }
        Some(Typed::Cancel) => ui_state.loop_cut = None,
        None => {}
    }
}

/// Keys of the inset being sized: digits type the thickness, Enter insets, Esc drops it.
fn inset_keys(ui_state: &mut UiState, events: &[Event], sender: &mut CommandSender) {
    let Some(inset) = &mut ui_state.inset else {
        return;
    };
    match typed_number_keys(&mut inset.typed, events) {
        Some(Typed::Confirm) => {
            sender.send(Command::RigOps(inset.operations()));
            ui_state.inset = None;
        }
        Some(Typed::Cancel) => ui_state.inset = None,
        None => {}
    }
}

/// Keys of the G / R / S tool; the tool follows the pointer once per frame.
fn tool_keys(
    state: &EditorState,
    ui_state: &mut UiState,
    events: &[Event],
    pointer: Vec2,
    snapping: bool,
    sender: &mut CommandSender,
) {
    let Some(tool) = &mut ui_state.tool else {
        return;
    };
    tool.snap = if snapping && tool.mode == super::transform_tool::Mode::Grab {
        let moving: std::collections::BTreeSet<u32> = tool.moving().collect();
        super::picking::snap_target(state, pointer, &moving)
    } else {
        None
    };
    let mut end = None;
    for event in events {
        match event {
            Event::Text(text) => {
                for c in text.chars() {
                    match ToolKey::of_char(c) {
                        Some(ToolKey::LockX) => tool.axis = Axis::X.toggle(tool.axis),
                        Some(ToolKey::LockY) => tool.axis = Axis::Y.toggle(tool.axis),
                        Some(ToolKey::LockZ) => tool.axis = Axis::Z.toggle(tool.axis),
                        Some(ToolKey::Digit) => tool.typed.push(c),
                        _ => {}
                    }
                }
            }
            Event::Key {
                key,
                pressed: true,
                modifiers,
                ..
            } => match ToolKey::of_key(*key, *modifiers) {
                Some(ToolKey::Backspace) => {
                    tool.typed.pop();
                }
                Some(ToolKey::Confirm) => end = Some(true),
                Some(ToolKey::Cancel) => end = Some(false),
                _ => {}
            },
            _ => {}
        }
    }
    sender.send(Command::MoveVertices(tool.moves(
        &state.view.camera,
        state.view.viewport,
        pointer,
    )));
    if let Some(keep) = end {
        ui_state.tool = None;
        sender.send(Command::EndGesture { keep });
    }
}

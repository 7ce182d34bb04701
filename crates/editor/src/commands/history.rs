//! Undo, redo and gestures (a drag or G/R/S is one undo step).

use super::Command;
use crate::state::EditorState;

/// Carries out a command of this domain (others are not its to apply, and do nothing here).
pub fn apply_history(state: &mut EditorState, command: Command) {
    match command {
        Command::Undo => {
            if state.gesture.is_some() {
                state.end_gesture(false);
                state.info("cancelled the edit in progress");
                return;
            }
            match state.undo.undo(&mut state.doc.scene) {
                Some(label) => {
                    state.info(format!("undid: {label}"));
                    state.document_changed();
                }
                None => state.info("nothing to undo"),
            }
        }
        Command::Redo => {
            state.end_gesture(true);
            match state.undo.redo(&mut state.doc.scene) {
                Some(label) => {
                    state.info(format!("redid: {label}"));
                    state.document_changed();
                }
                None => state.info("nothing to redo"),
            }
        }
        Command::BeginGesture { id, label } => state.begin_gesture(id, &label),
        Command::EndGesture { keep } => {
            if keep && state.mode == crate::state::EditMode::Rig {
                super::rig::weld_snapped_vertices(state);
            }
            state.end_gesture(keep);
        }
        _ => {}
    }
}

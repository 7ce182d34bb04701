//! Background jobs asked for or cancelled: the auto rig, opening, binding, the baseline.

use super::Command;
use crate::state::EditorState;

/// Carries out a command of this domain (others are not its to apply, and do nothing here).
pub fn apply_jobs(state: &mut EditorState, command: Command) {
    match command {
        Command::AutoRig {
            detail,
            controls,
            mirror,
        } => {
            state.start_autorig(starcages_core::generate::AutorigSettings {
                detail,
                controls,
                mirror,
                ..Default::default()
            });
        }
        Command::CancelAutoRig if state.autorig_job.is_some() => {
            state.autorig_job = None;
            state.info("auto rig cancelled; the rig is unchanged");
            state.bind_if_unbound();
        }
        Command::CancelLoad if state.load_job.is_some() => {
            state.load_job = None;
            state.info("opening cancelled; the current scene is unchanged");
        }
        Command::CancelBind => {
            if let Some(job) = &state.bind_job {
                job.cancel();
            }
        }
        Command::CancelBaseline => state.map.cancel_baseline(),
        _ => {}
    }
}

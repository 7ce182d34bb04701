//! Applying the timeline's commands: the current frame and playback (not edits), and key
//! edits (each one undo step).

use std::path::Path;

use starcages_core::anim::{FPS_RANGE, Interpolation, Key, MAX_FRAME};
use starcages_io::read_point_cache;

use super::Command;
use crate::state::timeline::{delete_key, key_current_pose, move_key};
use crate::state::{EditMode, EditorError, EditorState};

/// Carries out a timeline command (others are not its to apply, and do nothing here).
pub fn apply_animation(state: &mut EditorState, command: Command) {
    match command {
        Command::SetFrame(frame) => state.show_frame(frame.round()),
        Command::SetPlaying(true) if state.doc.scene.animation.is_empty() => {
            state.info("nothing to play: insert keys first (I keys the current pose)");
        }
        Command::SetPlaying(true) => state.timeline.play(std::time::Instant::now()),
        Command::SetPlaying(false) => state.timeline.playing = None,
        Command::InsertKey => insert_key(state),
        Command::DeleteKey(frame) => {
            let deleted = state.edit_scene("delete key", |scene| delete_key(scene, frame));
            if deleted {
                state.info(format!("deleted the key at frame {frame}"));
            } else {
                state.info(format!("no key at frame {frame}"));
            }
        }
        Command::MoveKey { from, to } => {
            let moved = state.edit_scene("move key", |scene| move_key(scene, from, to));
            match moved {
                Ok(()) => state.show_frame(state.timeline.frame),
                Err(why) => state.error(EditorError::Animation(why)),
            }
        }
        Command::SetKeyInterpolation {
            frame,
            interpolation,
        } => {
            state.edit_scene("key interpolation", |scene| {
                if let Some(k) = scene.animation.key_at(frame) {
                    scene.animation.keys[k].interpolation = interpolation;
                }
            });
            state.show_frame(state.timeline.frame);
        }
        Command::SetAnimationRange { fps, start, end } => {
            let far = start.abs() > MAX_FRAME || end.abs() > MAX_FRAME;
            if !FPS_RANGE.contains(&fps) || start > end || far {
                state.error(EditorError::Animation(format!(
                    "{fps} fps from frame {start} to {end}: the rate must be from {} to {}, \
                     the range not empty and within frame ±{MAX_FRAME}",
                    FPS_RANGE.start(),
                    FPS_RANGE.end()
                )));
            } else {
                state.edit_scene("animation range", |scene| {
                    scene.animation.fps = fps;
                    scene.animation.frame_start = start;
                    scene.animation.frame_end = end;
                });
            }
        }
        Command::SetAutoKey(on) => state.timeline.auto_key = on,
        Command::ImportCageAnimation(path) => import_cage_animation(state, &path),
        _ => {}
    }
}

fn insert_key(state: &mut EditorState) {
    if state.mode == EditMode::Rig {
        state.info("keys hold poses: switch to Pose mode (Tab) to key the current pose");
        return;
    }
    let frame = state.timeline.frame;
    state.edit_scene("insert key", |scene| key_current_pose(scene, frame));
    state.info(format!("keyed the current pose at frame {frame}"));
}

/// After a hand edit in Pose mode: a key at the current frame takes the new pose; with
/// auto-key on, a frame without a key gets one. Part of the edit's own undo step.
pub fn key_after_edit(state: &mut EditorState) {
    let frame = state.timeline.frame;
    let scene = &mut state.doc.scene;
    if state.mode == EditMode::Pose
        && (state.timeline.auto_key || scene.animation.key_at(frame).is_some())
    {
        key_current_pose(scene, frame);
    }
}

/// Each sample of a cage point cache becomes a pose and a linear key at its frame (keys at
/// those frames are replaced), one undo step.
fn import_cage_animation(state: &mut EditorState, path: &Path) {
    let scene = &state.doc.scene;
    let cache = read_point_cache(path, Some(scene.cages.vertices.len()), scene.animation.fps)
        .and_then(|cache| cache.check_as_cage_animation(path).map(|()| cache));
    let cache = match cache {
        Ok(cache) => cache,
        Err(e) => {
            state.error(EditorError::ImportCageAnimation(e));
            return;
        }
    };
    let up = scene.export_up();
    let stem = path
        .file_stem()
        .map_or_else(|| "cache".to_owned(), |s| s.to_string_lossy().into_owned());
    let count = cache.samples.len();
    state.edit_scene("import cage animation", |scene| {
        for (k, sample) in cache.samples.iter().enumerate() {
            let frame = cache.start_frame + k as f64 * cache.frame_step;
            let name = format!("{stem}_{k:04}");
            scene.poses.insert(
                name.clone(),
                sample.iter().map(|p| up.to_scene(p.as_dvec3())).collect(),
            );
            scene.pose_states.remove(&name);
            delete_key(scene, frame);
            let at = scene.animation.insertion_index(frame);
            scene.animation.keys.insert(
                at,
                Key {
                    frame,
                    pose: name,
                    interpolation: Interpolation::Linear,
                    h: Default::default(),
                },
            );
        }
        let first = cache.start_frame.floor() as i64;
        let last =
            (cache.start_frame + (count.saturating_sub(1)) as f64 * cache.frame_step).ceil() as i64;
        scene.animation.frame_start = scene.animation.frame_start.min(first);
        scene.animation.frame_end = scene.animation.frame_end.max(last);
    });
    state.show_frame(state.timeline.frame);
    state.info(format!(
        "imported {count} frames of cage animation from {}",
        path.display()
    ));
}

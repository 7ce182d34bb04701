//! The timeline: the current frame, playback and auto-key. Changing the frame poses the cages
//! as the animation says at that frame (not an edit: no undo step, as in Blender); keys are
//! edited through commands, each one undo step.

use std::time::Instant;

use starcages_core::anim::{Animation, Key};
use starcages_core::scene::Scene;

/// Playback in progress.
#[derive(Debug, Clone, Copy)]
pub struct Playback {
    /// When it started (or last wrapped around).
    pub started: Instant,
    /// The frame shown then.
    pub from_frame: f64,
    /// Frames shown since `measured_since`.
    frames_shown: u32,
    /// Start of the current measuring second.
    measured_since: Instant,
    /// Frames shown per second, measured over the last second (0 until then).
    pub shown_fps: f64,
}

/// The timeline's state.
#[derive(Debug, Clone)]
pub struct Timeline {
    /// The current frame.
    pub frame: f64,
    /// Playback, while playing.
    pub playing: Option<Playback>,
    /// Auto-key: an edit at a frame without a key inserts one (an edit at a keyed frame always
    /// updates that key).
    pub auto_key: bool,
}

impl Default for Timeline {
    fn default() -> Self {
        Self {
            frame: 1.0,
            playing: None,
            auto_key: false,
        }
    }
}

impl Timeline {
    /// Starts playing from the current frame.
    pub fn play(&mut self, now: Instant) {
        self.playing = Some(Playback {
            started: now,
            from_frame: self.frame,
            frames_shown: 0,
            measured_since: now,
            shown_fps: 0.0,
        });
    }

    /// The frame playback shows at `now` (whole frames at the animation's rate, wrapping from
    /// the end of the range to its start), and counts it for the measured rate. `None` when
    /// not playing or when the frame has not changed.
    pub fn playback_frame(&mut self, animation: &Animation, now: Instant) -> Option<f64> {
        let playing = self.playing.as_mut()?;
        let (start, end) = (
            animation.frame_start as f64,
            animation.frame_end.max(animation.frame_start) as f64,
        );
        let elapsed = now.duration_since(playing.started).as_secs_f64();
        let mut frame = (playing.from_frame + elapsed * animation.fps).floor();
        if frame > end || frame < start {
            let length = end - start + 1.0;
            frame = start + (frame - start).rem_euclid(length);
            // Restart the clock at the wrap so that rounding does not drift.
            playing.started = now;
            playing.from_frame = frame;
        }
        if frame == self.frame {
            return None;
        }
        playing.frames_shown += 1;
        let since = now.duration_since(playing.measured_since).as_secs_f64();
        if since >= 1.0 {
            playing.shown_fps = f64::from(playing.frames_shown) / since;
            playing.frames_shown = 0;
            playing.measured_since = now;
        }
        Some(frame)
    }
}

/// A pose name no pose of `scene` has, for the key at `frame`.
fn new_key_pose_name(scene: &Scene, frame: f64) -> String {
    let base = format!("key_{frame}");
    std::iter::once(base.clone())
        .chain((2..).map(|i| format!("{base}_{i}")))
        .find(|name| !scene.poses.contains_key(name))
        .unwrap_or(base)
}

/// Keys the current pose at `frame`: the key there, if any, takes it (in a pose of its own when
/// another key shares its pose); otherwise a new key with a new pose. Returns the key's index.
pub fn key_current_pose(scene: &mut Scene, frame: f64) -> usize {
    let pose = scene.pose.clone();
    let state = scene.pose_state.clone();
    let index = match scene.animation.key_at(frame) {
        Some(index) => {
            let name = scene.animation.keys[index].pose.clone();
            let shared = scene
                .animation
                .keys
                .iter()
                .filter(|k| k.pose == name)
                .count()
                > 1;
            if shared {
                let own = new_key_pose_name(scene, frame);
                scene.animation.keys[index].pose = own;
            }
            index
        }
        None => {
            let index = scene.animation.insertion_index(frame);
            let interpolation = scene
                .animation
                .keys
                .get(index.saturating_sub(1))
                .map(|k| k.interpolation)
                .unwrap_or_default();
            let key = Key {
                frame,
                pose: new_key_pose_name(scene, frame),
                interpolation,
                h: Default::default(),
            };
            scene.animation.keys.insert(index, key);
            index
        }
    };
    let name = scene.animation.keys[index].pose.clone();
    scene.poses.insert(name.clone(), pose);
    if state.is_rest() {
        scene.pose_states.remove(&name);
    } else {
        scene.pose_states.insert(name, state);
    }
    index
}

/// Deletes the key at `frame`; its pose goes too when it was made for a key (`key_…`) and no
/// other key uses it. Returns whether there was a key.
pub fn delete_key(scene: &mut Scene, frame: f64) -> bool {
    let Some(index) = scene.animation.key_at(frame) else {
        return false;
    };
    let key = scene.animation.keys.remove(index);
    let used = scene.animation.keys.iter().any(|k| k.pose == key.pose);
    if !used && key.pose.starts_with("key_") {
        scene.poses.remove(&key.pose);
        scene.pose_states.remove(&key.pose);
    }
    true
}

/// Moves the key at `from` to `to`. Refuses (returns why) when `to` already has a key.
pub fn move_key(scene: &mut Scene, from: f64, to: f64) -> Result<(), String> {
    if from == to {
        return Ok(());
    }
    if !to.is_finite() {
        return Err(format!("frame {to} is not a number"));
    }
    if scene.animation.key_at(to).is_some() {
        return Err(format!(
            "frame {to} has a key already; delete it first or move this one elsewhere"
        ));
    }
    let Some(index) = scene.animation.key_at(from) else {
        return Err(format!("no key at frame {from}"));
    };
    let mut key = scene.animation.keys.remove(index);
    key.frame = to;
    let at = scene.animation.insertion_index(to);
    scene.animation.keys.insert(at, key);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use starcages_core::generate::demo::demo_scene;

    #[test]
    fn keying_twice_at_a_frame_updates_one_key_and_deleting_it_removes_its_pose() {
        let mut scene = demo_scene("bar", 0.3).unwrap();
        let keys = scene.animation.keys.len();
        key_current_pose(&mut scene, 5.0);
        scene.pose[0].x += 1.0;
        let index = key_current_pose(&mut scene, 5.0);
        assert_eq!(scene.animation.keys.len(), keys + 1);
        let pose = scene.animation.keys[index].pose.clone();
        assert_eq!(scene.poses[&pose], scene.pose);
        move_key(&mut scene, 5.0, 9.0).unwrap();
        assert!(scene.animation.key_at(9.0).is_some());
        assert!(delete_key(&mut scene, 9.0));
        assert!(!scene.poses.contains_key(&pose));
    }

    #[test]
    fn playback_wraps_at_the_end_of_the_range() {
        let animation = Animation {
            frame_start: 1,
            frame_end: 10,
            ..Animation::default()
        };
        let mut timeline = Timeline {
            frame: 9.0,
            ..Timeline::default()
        };
        let start = Instant::now();
        timeline.play(start);
        let later = start + std::time::Duration::from_secs_f64(3.0 / 24.0 + 1e-6);
        assert_eq!(timeline.playback_frame(&animation, later), Some(2.0));
    }
}

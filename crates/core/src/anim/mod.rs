//! Animation: keys on a timeline, each a named pose of every cage vertex (and, where set, h of
//! some cages) at a frame, with an interpolation to the next key; the frame rate and the
//! playback range. Evaluating it gives the cage vertices (and h) at any frame, which the
//! compiled operator turns into the mesh without binding again.

pub mod curve;
pub mod sampling;

use std::collections::BTreeMap;

use glam::DVec3;
use serde::{Deserialize, Serialize};
use thiserror::Error;

pub use curve::Interpolation;
use curve::Segment;
pub use sampling::{SampleTimes, SamplingError};

/// One channel's key times, values and interpolations.
type Channel = (Vec<f64>, Vec<f64>, Vec<Interpolation>);

/// One key: at `frame`, the cage vertices stand as the named pose `pose`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Key {
    /// The frame (fractional frames are allowed, as Blender's sub-frame keys).
    pub frame: f64,
    /// The named pose (a scene `poses` entry) the cage vertices take at this frame.
    pub pose: String,
    /// How the values move on to the next key.
    #[serde(default)]
    pub interpolation: Interpolation,
    /// h of some leaf cages at this frame, by cage name (others keep their own h). Each cage's
    /// h is its own channel, interpolated between the keys that set it.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub h: BTreeMap<String, f64>,
}

/// A scene's animation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Animation {
    /// Frames per second (Blender's default 24).
    #[serde(default = "default_fps")]
    pub fps: f64,
    /// First frame of the playback range (and of a bake without `--frames`).
    #[serde(default = "default_start")]
    pub frame_start: i64,
    /// Last frame of the playback range, included.
    #[serde(default = "default_end")]
    pub frame_end: i64,
    /// Keys in strictly increasing frame order.
    #[serde(default)]
    pub keys: Vec<Key>,
}

fn default_fps() -> f64 {
    24.0
}
fn default_start() -> i64 {
    1
}
fn default_end() -> i64 {
    48
}

impl Default for Animation {
    fn default() -> Self {
        Self {
            fps: default_fps(),
            frame_start: default_start(),
            frame_end: default_end(),
            keys: Vec::new(),
        }
    }
}

/// The most frames a playback range may hold (a day at 120 fps): bakes and timelines stay
/// bounded.
pub const MAX_FRAMES: i64 = 10_368_000;

/// The largest frame number, in either direction, of a key or a playback range: Blender's
/// (`MAXFRAME`), so that every frame StarCages writes Blender can show. It also keeps every
/// frame exact in a point cache's 32-bit floats and MDD's times (frame / fps) distinct.
pub const MAX_FRAME: i64 = 1_048_574;

/// The frame rates an animation may have, frames per second: from one frame every 100
/// seconds (time lapse) to 1000 (high-speed footage). Within these and [`MAX_FRAME`] every
/// sample time a bake writes is finite and distinct in 32-bit floats.
pub const FPS_RANGE: std::ops::RangeInclusive<f64> = 0.01..=1000.0;

/// A number as a person reads it: plain where that is short, in scientific notation where
/// plain would run to hundreds of digits (1e-300 rather than 0.000…0001).
fn readable(value: f64) -> String {
    if value == 0.0 || (1e-6..1e15).contains(&value.abs()) || !value.is_finite() {
        value.to_string()
    } else {
        format!("{value:e}")
    }
}

/// Why an animation cannot be played.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AnimationProblem {
    /// The frame rate is not a number in [`FPS_RANGE`].
    #[error(
        "animation: fps = {} is outside {} to {} frames per second; write e.g. 24",
        readable(*fps),
        FPS_RANGE.start(),
        FPS_RANGE.end()
    )]
    Fps {
        /// The value.
        fps: f64,
    },
    /// The playback range is empty or too long.
    #[error(
        "animation: the range {start}..{end} is {why}; make frame_start at most frame_end, at most \
         {MAX_FRAMES} frames apart"
    )]
    Range {
        /// First frame.
        start: i64,
        /// Last frame.
        end: i64,
        /// "empty" or "too long".
        why: &'static str,
    },
    /// A playback range that starts or ends beyond ±[`MAX_FRAME`].
    #[error(
        "animation: the range {start}..{end} reaches beyond frame ±{MAX_FRAME} (Blender's \
         limit); move the range nearer frame 0"
    )]
    RangeFar {
        /// First frame.
        start: i64,
        /// Last frame.
        end: i64,
    },
    /// A key's frame is not a finite number within ±[`MAX_FRAME`].
    #[error(
        "animation: key {key} has frame {}, which is not a frame number within \
         ±{MAX_FRAME} (Blender's limit); give it a frame in range",
        readable(*frame)
    )]
    KeyFrame {
        /// The key (0-based, in file order).
        key: usize,
        /// The value.
        frame: f64,
    },
    /// A key does not come strictly after the one before it.
    #[error(
        "animation: key {key} (frame {frame}) does not come after key {previous} (frame \
         {previous_frame}); keys must be in increasing frame order, one per frame: reorder or \
         retime them"
    )]
    KeyOrder {
        /// The key.
        key: usize,
        /// Its frame.
        frame: f64,
        /// The key before it.
        previous: usize,
        /// That key's frame.
        previous_frame: f64,
    },
    /// A key names a pose the scene does not have.
    #[error(
        "animation: key {key} (frame {frame}) names pose '{pose}', which the scene does not have; \
         known poses: {known}"
    )]
    MissingPose {
        /// The key.
        key: usize,
        /// Its frame.
        frame: f64,
        /// The name.
        pose: String,
        /// The poses there are.
        known: String,
    },
    /// A key sets h of a cage that is not a leaf cage of the scene.
    #[error("animation: key {key} (frame {frame}) sets h of '{cage}', which is not a leaf cage")]
    UnknownCage {
        /// The key.
        key: usize,
        /// Its frame.
        frame: f64,
        /// The name.
        cage: String,
    },
    /// A key's h is outside (0, 1].
    #[error("animation: key {key} (frame {frame}) sets h of '{cage}' to {h:?}, outside (0, 1]")]
    KeyH {
        /// The key.
        key: usize,
        /// Its frame.
        frame: f64,
        /// The cage.
        cage: String,
        /// The value.
        h: f64,
    },
}

impl Animation {
    /// True when the animation has no keys (nothing moves over time).
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// True when this is the default: no keys, 24 fps, frames 1..48 (not written to files).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// Every problem of the animation against the scene's poses and leaf cage names.
    pub fn problems<'a>(
        &self,
        poses: &BTreeMap<String, Vec<DVec3>>,
        leaf_names: impl IntoIterator<Item = &'a str>,
    ) -> Vec<AnimationProblem> {
        let leaf_names: Vec<&str> = leaf_names.into_iter().collect();
        let mut problems = Vec::new();
        if !FPS_RANGE.contains(&self.fps) {
            problems.push(AnimationProblem::Fps { fps: self.fps });
        }
        if self.frame_start.abs() > MAX_FRAME || self.frame_end.abs() > MAX_FRAME {
            problems.push(AnimationProblem::RangeFar {
                start: self.frame_start,
                end: self.frame_end,
            });
        }
        let range = self.frame_end.checked_sub(self.frame_start);
        let why = match range {
            Some(r) if r < 0 => Some("empty"),
            Some(r) if r >= MAX_FRAMES => Some("too long"),
            None => Some("too long"),
            Some(_) => None,
        };
        if let Some(why) = why {
            problems.push(AnimationProblem::Range {
                start: self.frame_start,
                end: self.frame_end,
                why,
            });
        }
        let mut previous: Option<(usize, f64)> = None;
        for (k, key) in self.keys.iter().enumerate() {
            if !(key.frame.is_finite() && key.frame.abs() <= MAX_FRAME as f64) {
                problems.push(AnimationProblem::KeyFrame {
                    key: k,
                    frame: key.frame,
                });
                continue;
            }
            if let Some((p, previous_frame)) = previous
                && key.frame <= previous_frame
            {
                problems.push(AnimationProblem::KeyOrder {
                    key: k,
                    frame: key.frame,
                    previous: p,
                    previous_frame,
                });
            }
            previous = Some((k, key.frame));
            if !poses.contains_key(&key.pose) {
                let known: Vec<&str> = poses.keys().map(String::as_str).collect();
                problems.push(AnimationProblem::MissingPose {
                    key: k,
                    frame: key.frame,
                    pose: key.pose.clone(),
                    known: if known.is_empty() {
                        "none".to_owned()
                    } else {
                        known.join(", ")
                    },
                });
            }
            for (cage, &h) in &key.h {
                if !leaf_names.contains(&cage.as_str()) {
                    problems.push(AnimationProblem::UnknownCage {
                        key: k,
                        frame: key.frame,
                        cage: cage.clone(),
                    });
                } else if !(h > 0.0 && h <= 1.0) {
                    problems.push(AnimationProblem::KeyH {
                        key: k,
                        frame: key.frame,
                        cage: cage.clone(),
                        h,
                    });
                }
            }
        }
        problems
    }

    /// The frames of the playback range, first to last.
    pub fn frames(&self) -> std::ops::RangeInclusive<i64> {
        self.frame_start..=self.frame_end
    }

    /// The key exactly at `frame`, if any.
    pub fn key_at(&self, frame: f64) -> Option<usize> {
        self.keys.iter().position(|k| k.frame == frame)
    }

    /// The first key after `frame` (Blender's Up arrow).
    pub fn next_key_frame(&self, frame: f64) -> Option<f64> {
        self.keys.iter().map(|k| k.frame).find(|&f| f > frame)
    }

    /// The last key before `frame` (Blender's Down arrow).
    pub fn previous_key_frame(&self, frame: f64) -> Option<f64> {
        self.keys.iter().rev().map(|k| k.frame).find(|&f| f < frame)
    }

    /// Where a key at `frame` goes to keep the keys in order: the index of the first key at or
    /// after it.
    pub fn insertion_index(&self, frame: f64) -> usize {
        self.keys.partition_point(|k| k.frame < frame)
    }

    /// The cage vertices at `frame` (every vertex, leaf and internal): each coordinate
    /// interpolated between the keys' poses. `None` without keys, or when a key's pose is
    /// missing or of the wrong length (validation reports those).
    pub fn pose_at(&self, poses: &BTreeMap<String, Vec<DVec3>>, frame: f64) -> Option<Vec<DVec3>> {
        let key_poses: Vec<&[DVec3]> = self
            .keys
            .iter()
            .map(|k| poses.get(&k.pose).map(Vec::as_slice))
            .collect::<Option<_>>()?;
        let count = key_poses.first()?.len();
        if key_poses.iter().any(|p| p.len() != count) {
            return None;
        }
        let times: Vec<f64> = self.keys.iter().map(|k| k.frame).collect();
        match curve::segment(&times, frame) {
            Segment::Hold(k) => Some(key_poses[k].to_vec()),
            Segment::Between(k, u) => {
                let mode = self.keys[k].interpolation;
                // Only the keys that shape this segment: k − 1 ..= k + 2 (the tangents at k
                // and k + 1 read their neighbours).
                let first = k.saturating_sub(1);
                let last = (k + 2).min(self.keys.len() - 1);
                let window_times = &times[first..=last];
                let local = k - first;
                let mut values = vec![0.0; window_times.len()];
                let pose = (0..count)
                    .map(|v| {
                        let mut p = [0.0; 3];
                        for (axis, out) in p.iter_mut().enumerate() {
                            for (value, key_pose) in values.iter_mut().zip(&key_poses[first..=last])
                            {
                                *value = key_pose[v][axis];
                            }
                            let slopes = (mode == Interpolation::Bezier).then(|| {
                                (
                                    curve::auto_clamped_slope(window_times, &values, local),
                                    curve::auto_clamped_slope(window_times, &values, local + 1),
                                )
                            });
                            *out = curve::between(window_times, &values, mode, local, u, slopes);
                        }
                        DVec3::from_array(p)
                    })
                    .collect();
                Some(pose)
            }
        }
    }

    /// h at `frame` of every cage some key sets h for, by name: each cage's channel runs
    /// through the keys that set it, with those keys' interpolations.
    pub fn h_at(&self, frame: f64) -> BTreeMap<String, f64> {
        let mut channels: BTreeMap<&str, Channel> = BTreeMap::new();
        for key in &self.keys {
            for (cage, &h) in &key.h {
                let channel = channels.entry(cage.as_str()).or_default();
                channel.0.push(key.frame);
                channel.1.push(h);
                channel.2.push(key.interpolation);
            }
        }
        channels
            .into_iter()
            .map(|(cage, (times, values, modes))| {
                let h = curve::evaluate(&times, &values, &modes, frame);
                (cage.to_owned(), h.clamp(f64::MIN_POSITIVE, 1.0))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(frame: f64, pose: &str, interpolation: Interpolation) -> Key {
        Key {
            frame,
            pose: pose.into(),
            interpolation,
            h: BTreeMap::new(),
        }
    }

    #[test]
    fn next_and_previous_keys_skip_the_current_frame() {
        let animation = Animation {
            keys: vec![
                key(1.0, "a", Interpolation::Linear),
                key(10.0, "b", Interpolation::Linear),
            ],
            ..Animation::default()
        };
        assert_eq!(animation.next_key_frame(1.0), Some(10.0));
        assert_eq!(animation.next_key_frame(10.0), None);
        assert_eq!(animation.previous_key_frame(10.0), Some(1.0));
        assert_eq!(animation.previous_key_frame(0.0), None);
        assert_eq!(animation.insertion_index(5.0), 1);
        assert_eq!(animation.insertion_index(10.0), 1);
    }
}

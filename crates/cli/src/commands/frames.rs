//! Which frames a bake or a cage export takes: `--frames A..B` and `--fps F` over a scene's
//! animation.

use std::str::FromStr;

use starcages_core::anim::SampleTimes;
use starcages_core::anim::sampling::{self, SamplingError};
use starcages_core::scene::Scene;

use crate::InputError;

/// `--frames` and `--fps`: which frames of the animation a bake or a cage cache takes.
#[derive(Debug, clap::Args)]
pub struct SampleArgs {
    /// Scene frames to take, both included (default: the animation's playback range; with
    /// `bake --cage-cache`, every sample of the cache).
    #[arg(long, value_name = "A..B", allow_hyphen_values = true)]
    pub frames: Option<FrameRange>,
    /// Samples per second (default: the animation's frame rate); e.g. 30 resamples a 24 fps
    /// animation.
    #[arg(long)]
    pub fps: Option<f64>,
}

/// `--frames A..B`: scene frames A to B, both included.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameRange {
    /// First frame.
    pub first: i64,
    /// Last frame (included).
    pub last: i64,
}

impl FromStr for FrameRange {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let usage = || format!("'{text}' is not a frame range; write A..B, e.g. 1..48");
        let (a, b) = text.split_once("..").ok_or_else(usage)?;
        let first: i64 = a.trim().parse().map_err(|_| usage())?;
        let last: i64 = b.trim().parse().map_err(|_| usage())?;
        if first > last {
            return Err(format!(
                "'{text}': the first frame comes after the last; write A..B with A <= B"
            ));
        }
        Ok(Self { first, last })
    }
}

/// The scene frames to sample over `scene`'s animation (its playback range unless `range`
/// says otherwise), `fps` samples per second (the animation's own rate unless given), and when
/// they fall, for cache headers.
pub fn animation_samples(
    scene: &Scene,
    range: Option<FrameRange>,
    fps: Option<f64>,
) -> anyhow::Result<(Vec<f64>, SampleTimes)> {
    let range = range.map(|r| (r.first, r.last));
    sampling::animation_samples(&scene.animation, range, fps).map_err(|error| {
        let flag = match &error {
            SamplingError::Rate { .. } => "--fps: ",
            SamplingError::Far { .. } | SamplingError::Count { .. } if range.is_some() => {
                "--frames: "
            }
            _ => "",
        };
        InputError(format!("{flag}{error}")).into()
    })
}

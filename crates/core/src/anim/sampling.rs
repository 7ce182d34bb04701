//! Sampling an animation: which scene frames a bake or a cage cache takes, and when they fall
//! (the headers of point caches and the times of an animated glTF), within the bounds every
//! reader accepts.

/// When the samples of a cache were taken.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleTimes {
    /// The frame of the first sample.
    pub start_frame: f64,
    /// Frames from one sample to the next (1 for every frame).
    pub frame_step: f64,
    /// Frames per second (MDD stores seconds: frame / fps).
    pub fps: f64,
}

impl SampleTimes {
    /// The frame of sample `k`.
    pub fn frame(&self, k: usize) -> f64 {
        self.start_frame + k as f64 * self.frame_step
    }
}

/// The most samples one bake takes (a day at 120 frames per second).
pub const MAX_SAMPLES: usize = 10_368_000;

/// The scene frames `first`, `first + step`, … up to `last` (within a thousandth of a step, so
/// that `--fps` steps such as 24/30 land on `last`). `None` when the run is empty, the step is
/// not positive or there would be more than [`MAX_SAMPLES`].
pub fn sample_frames(first: f64, last: f64, step: f64) -> Option<Vec<f64>> {
    if !(first.is_finite() && last.is_finite() && step.is_finite() && step > 0.0 && first <= last) {
        return None;
    }
    let count = ((last - first) / step + 1e-3).floor() + 1.0;
    if count > MAX_SAMPLES as f64 {
        return None;
    }
    Some(
        (0..count as usize)
            .map(|k| first + k as f64 * step)
            .collect(),
    )
}

/// Why a run of frames cannot be sampled.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SamplingError {
    /// The sampling rate asked for is outside [`super::FPS_RANGE`].
    #[error(
        "a rate of {rate} samples per second is outside {} to {}",
        super::FPS_RANGE.start(),
        super::FPS_RANGE.end()
    )]
    Rate {
        /// The rate.
        rate: f64,
    },
    /// The animation's own frame rate is outside [`super::FPS_RANGE`] (a scene that does not
    /// validate).
    #[error(
        "the scene's animation has fps = {fps}, outside {} to {}; fix \"fps\" in the scene file",
        super::FPS_RANGE.start(),
        super::FPS_RANGE.end()
    )]
    SceneFps {
        /// The scene's rate.
        fps: f64,
    },
    /// The run reaches beyond frame ±[`super::MAX_FRAME`].
    #[error(
        "frames {first}..{last} reach beyond frame ±{} (Blender's limit); choose frames nearer 0",
        super::MAX_FRAME
    )]
    Far {
        /// First frame.
        first: i64,
        /// Last frame.
        last: i64,
    },
    /// An empty run, or more than [`MAX_SAMPLES`] samples.
    #[error(
        "frames {first}..{last} at {rate} samples per second: an empty run, or more than \
         {MAX_SAMPLES} samples; choose a shorter range"
    )]
    Count {
        /// First frame.
        first: i64,
        /// Last frame.
        last: i64,
        /// Samples per second.
        rate: f64,
    },
}

/// The scene frames to sample over `animation` (its playback range unless `range` gives first
/// and last frame), `rate` samples per second (the animation's own rate unless given), and
/// when they fall, for cache headers. Within the bounds validation holds a scene to
/// ([`super::FPS_RANGE`], [`super::MAX_FRAME`]), so that every header a bake writes is one the
/// readers accept.
pub fn animation_samples(
    animation: &super::Animation,
    range: Option<(i64, i64)>,
    rate: Option<f64>,
) -> Result<(Vec<f64>, SampleTimes), SamplingError> {
    let (first, last) = range.unwrap_or((animation.frame_start, animation.frame_end));
    if !super::FPS_RANGE.contains(&animation.fps) {
        return Err(SamplingError::SceneFps { fps: animation.fps });
    }
    let rate = rate.unwrap_or(animation.fps);
    if !super::FPS_RANGE.contains(&rate) {
        return Err(SamplingError::Rate { rate });
    }
    if first.abs() > super::MAX_FRAME || last.abs() > super::MAX_FRAME {
        return Err(SamplingError::Far { first, last });
    }
    let step = animation.fps / rate;
    let frames = sample_frames(first as f64, last as f64, step).ok_or(SamplingError::Count {
        first,
        last,
        rate,
    })?;
    Ok((
        frames,
        SampleTimes {
            start_frame: first as f64,
            frame_step: step,
            fps: animation.fps,
        },
    ))
}

/// The time in seconds of each sampled frame in an animated glTF: scene time (frame / fps), so
/// that Blender's importer puts frame N at frame N; glTF times cannot be negative, so a run
/// starting below frame 0 starts at 0.
pub fn gltf_seconds(frames: &[f64], fps: f64) -> Vec<f64> {
    let origin = frames.first().copied().unwrap_or(0.0).min(0.0);
    frames.iter().map(|frame| (frame - origin) / fps).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_land_on_the_last_frame_and_refuse_empty_runs() {
        assert_eq!(sample_frames(1.0, 4.0, 1.0), Some(vec![1.0, 2.0, 3.0, 4.0]));
        let thirty = sample_frames(1.0, 25.0, 24.0 / 30.0).unwrap();
        assert_eq!(thirty.len(), 31);
        assert!((thirty[30] - 25.0).abs() < 1e-9);
        assert_eq!(sample_frames(5.0, 4.0, 1.0), None);
        assert_eq!(sample_frames(1.0, 4.0, 0.0), None);
        assert_eq!(sample_frames(0.0, 1e12, 1.0), None);
    }
}

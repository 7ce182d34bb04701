//! Point caches: a position per vertex per sample, the way pipelines move deformation between
//! tools (Blender's Mesh Cache modifier, Maya, 3ds Max, Houdini).
//!
//! * **PC2** (3ds Max's Point Cache 2), little-endian: a 32-byte header (`"POINTCACHE2\0"`, i32
//!   version 1, i32 point count, f32 start frame, f32 sampling = frames between samples, i32
//!   sample count), then per sample per point three f32.
//! * **MDD** (LightWave), big-endian: i32 frame count, i32 point count, an f32 time in seconds
//!   per frame, then per frame per point three f32.
//!
//! Readers check every header field against the file's length before allocating, so a forged
//! or truncated cache is refused with the reason, never read past or trusted.

use std::path::{Path, PathBuf};

use glam::Vec3;

use starcages_core::anim::SampleTimes;

use super::{AtomicWriter, FileError, extension, read_file_bytes};

const PC2_SIGNATURE: &[u8; 12] = b"POINTCACHE2\0";
const PC2_HEADER_BYTES: usize = 32;

/// A point cache file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointCacheFormat {
    /// 3ds Max Point Cache 2 (`.pc2`).
    Pc2,
    /// LightWave MDD (`.mdd`).
    Mdd,
}

impl PointCacheFormat {
    /// The format of a file by its extension, if it is a point cache.
    pub fn of(path: &Path) -> Option<Self> {
        match extension(path).as_str() {
            "pc2" => Some(Self::Pc2),
            "mdd" => Some(Self::Mdd),
            _ => None,
        }
    }
}

/// A point cache read from a file.
#[derive(Debug, Clone, PartialEq)]
pub struct PointCache {
    /// The file's format.
    pub format: PointCacheFormat,
    /// Points per sample.
    pub points: usize,
    /// PC2: start frame and sampling from the header. MDD: the frame of each time (seconds
    /// times `fps` given to the reader) from the first two times.
    pub start_frame: f64,
    /// Frames between samples.
    pub frame_step: f64,
    /// The samples, each `points` positions.
    pub samples: Vec<Vec<Vec3>>,
}

/// Writes a point cache sample by sample (a bake streams frames; the file is never held whole)
/// and puts it in place atomically when every sample announced in the header is written.
pub struct PointCacheWriter {
    path: PathBuf,
    format: PointCacheFormat,
    points: usize,
    samples: usize,
    written: usize,
    file: AtomicWriter,
    buffer: Vec<u8>,
}

impl PointCacheWriter {
    /// Starts a cache of `samples` samples of `points` points at `times`.
    pub fn create(
        path: &Path,
        format: PointCacheFormat,
        points: usize,
        samples: usize,
        times: SampleTimes,
    ) -> Result<Self, FileError> {
        let (Ok(points_i32), Ok(samples_i32)) = (i32::try_from(points), i32::try_from(samples))
        else {
            return Err(FileError::format(
                path,
                format!(
                    "not written: {points} points × {samples} samples do not fit the format's \
                     32-bit counts"
                ),
            ));
        };
        let header = header(path, format, points_i32, samples_i32, times)?;
        let mut file = AtomicWriter::create(path)?;
        file.write(&header)?;
        Ok(Self {
            path: path.to_path_buf(),
            format,
            points,
            samples,
            written: 0,
            file,
            buffer: Vec::with_capacity(points * 12),
        })
    }

    /// Appends the next sample; refuses a sample of the wrong size or with a non-finite
    /// coordinate (nothing is written then: the target keeps its old content).
    pub fn write_sample(&mut self, positions: &[Vec3]) -> Result<(), FileError> {
        if positions.len() != self.points || self.written >= self.samples {
            return Err(FileError::format(
                &self.path,
                format!(
                    "not written: sample {} has {} points, the cache {} (and {} samples)",
                    self.written,
                    positions.len(),
                    self.points,
                    self.samples
                ),
            ));
        }
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            return Err(FileError::NonFinite {
                path: self.path.clone(),
                vertex,
            });
        }
        self.buffer.clear();
        for p in positions {
            for c in p.to_array() {
                let bytes = match self.format {
                    PointCacheFormat::Pc2 => c.to_le_bytes(),
                    PointCacheFormat::Mdd => c.to_be_bytes(),
                };
                self.buffer.extend_from_slice(&bytes);
            }
        }
        self.file.write(&self.buffer)?;
        self.written += 1;
        Ok(())
    }

    /// Puts the file in place; refuses when fewer samples were written than announced.
    pub fn finish(self) -> Result<(), FileError> {
        if self.written != self.samples {
            return Err(FileError::format(
                &self.path,
                format!(
                    "not written: {} of {} samples were written",
                    self.written, self.samples
                ),
            ));
        }
        self.file.commit()
    }
}

/// The header of a cache, checked before anything is written against what the readers (ours,
/// Blender's) accept: PC2's start frame and sampling finite in 32 bits and the sampling
/// positive; MDD's times (seconds, 32 bits) finite and increasing. A header that would fail
/// is refused naming the field, so no file is written that we would then refuse.
fn header(
    path: &Path,
    format: PointCacheFormat,
    points: i32,
    samples: i32,
    times: SampleTimes,
) -> Result<Vec<u8>, FileError> {
    let refuse = |why: String| {
        FileError::format(
            path,
            format!(
                "not written: {why}; the format stores it as a 32-bit float (bake fewer frames, \
                 frames nearer 0, or another frame rate)"
            ),
        )
    };
    let mut header = Vec::new();
    match format {
        PointCacheFormat::Pc2 => {
            let (start, sampling) = (times.start_frame as f32, times.frame_step as f32);
            if !(start.is_finite() && sampling.is_finite() && sampling > 0.0) {
                return Err(refuse(format!(
                    "the start frame {} and sampling {} (frames between samples) must be finite \
                     and the sampling positive",
                    times.start_frame, times.frame_step
                )));
            }
            header.extend_from_slice(PC2_SIGNATURE);
            header.extend_from_slice(&1i32.to_le_bytes());
            header.extend_from_slice(&points.to_le_bytes());
            header.extend_from_slice(&start.to_le_bytes());
            header.extend_from_slice(&sampling.to_le_bytes());
            header.extend_from_slice(&samples.to_le_bytes());
        }
        PointCacheFormat::Mdd => {
            header.extend_from_slice(&samples.to_be_bytes());
            header.extend_from_slice(&points.to_be_bytes());
            let mut previous: Option<f32> = None;
            for k in 0..samples.max(0) as usize {
                let seconds = (times.frame(k) / times.fps) as f32;
                if !seconds.is_finite() {
                    return Err(refuse(format!(
                        "sample {k}'s time, frame {} at {} fps, is {seconds} s",
                        times.frame(k),
                        times.fps
                    )));
                }
                if let Some(before) = previous
                    && seconds <= before
                {
                    return Err(refuse(format!(
                        "sample {k}'s time, frame {} at {} fps, is {seconds} s, not after the \
                         sample before it",
                        times.frame(k),
                        times.fps
                    )));
                }
                previous = Some(seconds);
                header.extend_from_slice(&seconds.to_be_bytes());
            }
        }
    }
    Ok(header)
}

impl PointCache {
    /// Checks that the cache can drive a rig's cage vertices: every coordinate within
    /// ±[`starcages_core::scene::MAX_COORDINATE`] (the deformation runs in 32-bit floats; a pose file is
    /// held to the same) and every sample's frame within ±[`starcages_core::anim::MAX_FRAME`].
    pub fn check_as_cage_animation(&self, path: &Path) -> Result<(), FileError> {
        use starcages_core::scene::MAX_COORDINATE;
        for (s, sample) in self.samples.iter().enumerate() {
            if let Some(p) = sample.iter().position(|p| {
                !(p.is_finite() && f64::from(p.abs().max_element()) <= MAX_COORDINATE)
            }) {
                let at = sample[p];
                return Err(FileError::format(
                    path,
                    format!(
                        "sample {s} puts cage vertex {p} at ({:e}, {:e}, {:e}), beyond \
                         ±{MAX_COORDINATE:e} (the deformation runs in 32-bit floats); scale \
                         the animation down in the program that wrote it",
                        at.x, at.y, at.z
                    ),
                ));
            }
        }
        let last = self.start_frame + self.samples.len().saturating_sub(1) as f64 * self.frame_step;
        let limit = starcages_core::anim::MAX_FRAME as f64;
        if !(self.start_frame.abs() <= limit && last.abs() <= limit) {
            return Err(FileError::format(
                path,
                format!(
                    "its samples run from frame {} to {last}, beyond frame ±{limit} (Blender's \
                     limit); write the cache nearer frame 0",
                    self.start_frame
                ),
            ));
        }
        Ok(())
    }
}

/// Reads a PC2 or MDD file (by extension). `expected_points`, when given, must equal the
/// cache's point count; `fps` turns MDD's seconds into frames.
pub fn read_point_cache(
    path: &Path,
    expected_points: Option<usize>,
    fps: f64,
) -> Result<PointCache, FileError> {
    let Some(format) = PointCacheFormat::of(path) else {
        return Err(FileError::Unsupported {
            path: path.to_path_buf(),
            extension: extension(path),
            supported: "pc2, mdd",
        });
    };
    let bytes = read_file_bytes(path)?;
    parse_point_cache(path, format, &bytes, expected_points, fps)
}

/// Parses the bytes of a point cache of `format`; `path` names it in errors.
pub fn parse_point_cache(
    path: &Path,
    format: PointCacheFormat,
    bytes: &[u8],
    expected_points: Option<usize>,
    fps: f64,
) -> Result<PointCache, FileError> {
    let bad = |reason: String| FileError::format(path, reason);
    let le_i32 = |at: usize| bytes.get(at..at + 4).map(|b| [b[0], b[1], b[2], b[3]]);
    let (points, samples, start_frame, frame_step, data_at, big_endian) = match format {
        PointCacheFormat::Pc2 => {
            if bytes.len() < PC2_HEADER_BYTES {
                return Err(bad(format!(
                    "a PC2 file has a {PC2_HEADER_BYTES}-byte header, this file only {} bytes: \
                     it is truncated or not a point cache",
                    bytes.len()
                )));
            }
            if &bytes[..12] != PC2_SIGNATURE {
                return Err(bad(
                    "does not start with \"POINTCACHE2\": not a PC2 point cache".to_owned(),
                ));
            }
            let field = |at: usize| le_i32(at).unwrap_or_default();
            let version = i32::from_le_bytes(field(12));
            if version != 1 {
                return Err(bad(format!(
                    "PC2 version {version}; only version 1 exists (a damaged header?)"
                )));
            }
            let points = i32::from_le_bytes(field(16));
            let start = f32::from_le_bytes(field(20));
            let sampling = f32::from_le_bytes(field(24));
            let samples = i32::from_le_bytes(field(28));
            if !(start.is_finite() && sampling.is_finite() && sampling > 0.0) {
                return Err(bad(format!(
                    "header: start frame {start} and sampling {sampling} must be finite, the \
                     sampling positive"
                )));
            }
            (
                points,
                samples,
                f64::from(start),
                f64::from(sampling),
                PC2_HEADER_BYTES,
                false,
            )
        }
        PointCacheFormat::Mdd => {
            let (Some(frames), Some(points)) = (le_i32(0), le_i32(4)) else {
                return Err(bad(format!(
                    "an MDD file starts with an 8-byte header, this file has {} bytes: it is \
                     truncated or not a point cache",
                    bytes.len()
                )));
            };
            let (frames, points) = (i32::from_be_bytes(frames), i32::from_be_bytes(points));
            (points, frames, 0.0, 1.0, 8, true)
        }
    };
    if points <= 0 || samples <= 0 {
        return Err(bad(format!(
            "header: {points} points and {samples} samples; both must be at least 1"
        )));
    }
    let (points, samples) = (points as usize, samples as usize);
    if let Some(expected) = expected_points
        && expected != points
    {
        return Err(bad(format!(
            "holds {points} points per sample, but {expected} are needed here: write the cache \
             with the same vertex count and order (`starcages-cli cages` for cages, `deform --out \
             x.obj` for the mesh)"
        )));
    }
    let times_bytes = if big_endian { 4 * samples as u128 } else { 0 };
    let expected_len = data_at as u128 + times_bytes + 12 * points as u128 * samples as u128;
    if bytes.len() as u128 != expected_len {
        let hint = if big_endian && bytes.len() as u128 == expected_len + 12 * points as u128 {
            " (one frame more than the header says: an exporter that writes the rest pose \
             first; re-export without it)"
        } else if (bytes.len() as u128) < expected_len {
            " (truncated, or the header's counts are wrong)"
        } else {
            " (data after the last sample: the header's counts are wrong)"
        };
        return Err(bad(format!(
            "the header announces {samples} samples of {points} points, {expected_len} bytes, \
             but the file has {} bytes{hint}",
            bytes.len()
        )));
    }
    let read_f32 = |at: usize| {
        let b = [bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]];
        if big_endian {
            f32::from_be_bytes(b)
        } else {
            f32::from_le_bytes(b)
        }
    };
    let (mut start_frame, mut frame_step) = (start_frame, frame_step);
    if big_endian {
        let times: Vec<f32> = (0..samples).map(|k| read_f32(data_at + 4 * k)).collect();
        if let Some(k) = times.iter().position(|t| !t.is_finite()) {
            return Err(bad(format!("frame {k}'s time {} is not finite", times[k])));
        }
        if let Some(k) = times.windows(2).position(|w| w[1] <= w[0]) {
            return Err(bad(format!(
                "frame {}'s time {} s does not come after frame {k}'s {} s; times must increase",
                k + 1,
                times[k + 1],
                times[k]
            )));
        }
        start_frame = f64::from(times[0]) * fps;
        if let [first, second, ..] = times[..] {
            frame_step = f64::from(second - first) * fps;
        }
    }
    let first_position = data_at + times_bytes as usize;
    let mut out = Vec::with_capacity(samples);
    for s in 0..samples {
        let base = first_position + 12 * points * s;
        let sample: Vec<Vec3> = (0..points)
            .map(|p| {
                let at = base + 12 * p;
                Vec3::new(read_f32(at), read_f32(at + 4), read_f32(at + 8))
            })
            .collect();
        if let Some(p) = sample.iter().position(|v| !v.is_finite()) {
            return Err(bad(format!(
                "sample {s}, point {p} has a coordinate that is not finite (NaN or infinity)"
            )));
        }
        out.push(sample);
    }
    Ok(PointCache {
        format,
        points,
        start_frame,
        frame_step,
        samples: out,
    })
}

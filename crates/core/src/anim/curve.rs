//! One animated channel (a coordinate of a cage vertex, or one cage's h) between keys, as
//! Blender's F-curves evaluate it: each key's interpolation governs the segment after it;
//! before the first key and after the last the value holds (constant extrapolation).
//!
//! Smooth segments are cubic Hermite curves whose tangents follow Blender's *auto clamped*
//! handles: at an interior key the mean of the two neighbouring secant slopes, flat where the
//! key is a local extremum (or equal to a neighbour) and at the first and last key, and limited
//! so that neither handle passes the neighbouring key's value (no overshoot). `docs/math.md`
//! ("Animation curves") says where this differs from Blender.

use serde::{Deserialize, Serialize};

/// How a key's value moves on to the next key's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Interpolation {
    /// Holds the key's value until the next key (Blender's *Constant*).
    Constant,
    /// A straight line to the next key (Blender's *Linear*).
    Linear,
    /// A smooth curve with auto-clamped handles (Blender's default *Bézier*).
    #[default]
    Bezier,
}

impl Interpolation {
    /// Every mode, in the order menus list them.
    pub const ALL: [Self; 3] = [Self::Constant, Self::Linear, Self::Bezier];

    /// The name files and the command line use.
    pub fn name(self) -> &'static str {
        match self {
            Self::Constant => "constant",
            Self::Linear => "linear",
            Self::Bezier => "bezier",
        }
    }
}

/// Where `frame` falls among the key times `times` (strictly increasing, at least one):
/// `Hold(k)` before the first key, after the last or exactly on a key; `Between(k, u)` inside
/// segment k (keys k and k + 1) at the fraction u in (0, 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Segment {
    /// The value of key k.
    Hold(usize),
    /// Inside the segment after key k, at fraction u of its length.
    Between(usize, f64),
}

/// The segment of `frame` among the strictly increasing key times `times` (not empty).
pub fn segment(times: &[f64], frame: f64) -> Segment {
    let last = times.len().saturating_sub(1);
    match times.first() {
        Some(&first) if frame <= first || frame.is_nan() => return Segment::Hold(0),
        None => return Segment::Hold(0),
        _ => {}
    }
    if frame >= times[last] {
        return Segment::Hold(last);
    }
    // The first key strictly after the frame; the one before it starts the segment.
    let next = times.partition_point(|&t| t <= frame);
    let k = next - 1;
    if times[k] == frame {
        return Segment::Hold(k);
    }
    // In (0, 1) for keys within validation's frame bounds; clamped so that keys far apart
    // (an unvalidated file: ±1e308, whose span overflows) hold rather than give NaN.
    let u = ((frame - times[k]) / (times[next] - times[k])).clamp(0.0, 1.0);
    if u.is_nan() {
        return Segment::Hold(k);
    }
    Segment::Between(k, u)
}

/// The auto-clamped tangent (value per frame) at key `k` of a channel with `values` at `times`.
pub fn auto_clamped_slope(times: &[f64], values: &[f64], k: usize) -> f64 {
    let (Some(&t), Some(&v)) = (times.get(k), values.get(k)) else {
        return 0.0;
    };
    let (Some(before), Some(after)) = (k.checked_sub(1), times.get(k + 1).map(|_| k + 1)) else {
        // First and last key: flat (Blender's auto handles under constant extrapolation).
        return 0.0;
    };
    let (rise_before, rise_after) = (v - values[before], values[after] - v);
    if rise_before * rise_after <= 0.0 {
        // A local extremum, or a plateau on one side: flat, so the curve does not overshoot.
        return 0.0;
    }
    let slope_before = rise_before / (t - times[before]);
    let slope_after = rise_after / (times[after] - t);
    let mean = 0.5 * (slope_before + slope_after);
    // A handle one third of its segment long stays within the neighbouring key's value when
    // |slope| <= 3 |secant| on that side (the monotone cubic condition of Fritsch and Carlson).
    let limit = 3.0 * slope_before.abs().min(slope_after.abs());
    mean.clamp(-limit, limit)
}

/// The channel's value at `frame`: `values` at strictly increasing `times`, `modes[k]` the
/// interpolation after key k.
pub fn evaluate(times: &[f64], values: &[f64], modes: &[Interpolation], frame: f64) -> f64 {
    match segment(times, frame) {
        Segment::Hold(k) => values.get(k).copied().unwrap_or(0.0),
        Segment::Between(k, u) => {
            let mode = modes.get(k).copied().unwrap_or_default();
            let slopes = (mode == Interpolation::Bezier).then(|| {
                (
                    auto_clamped_slope(times, values, k),
                    auto_clamped_slope(times, values, k + 1),
                )
            });
            between(times, values, mode, k, u, slopes)
        }
    }
}

/// The value inside segment k at fraction u, given the tangents at both ends for Bézier.
pub fn between(
    times: &[f64],
    values: &[f64],
    mode: Interpolation,
    k: usize,
    u: f64,
    slopes: Option<(f64, f64)>,
) -> f64 {
    let (p0, p1) = (values[k], values[k + 1]);
    match mode {
        Interpolation::Constant => p0,
        Interpolation::Linear => p0 + (p1 - p0) * u,
        Interpolation::Bezier => {
            let (m0, m1) = slopes.unwrap_or((0.0, 0.0));
            let span = times[k + 1] - times[k];
            let value = hermite(p0, span * m0, p1, span * m1, u);
            // Keys so far apart that the span overflows (never in a valid scene) give
            // 0 × ∞ tangents: the curve is then the straight line, not NaN.
            if value.is_finite() {
                value
            } else {
                p0 + (p1 - p0) * u
            }
        }
    }
}

/// The cubic Hermite curve from p0 (tangent d0 per unit u) to p1 (tangent d1) at u in [0, 1]
/// (equal to the cubic Bézier with handles p0 + d0/3 and p1 − d1/3).
pub fn hermite(p0: f64, d0: f64, p1: f64, d1: f64, u: f64) -> f64 {
    let (u2, u3) = (u * u, u * u * u);
    (2.0 * u3 - 3.0 * u2 + 1.0) * p0
        + (u3 - 2.0 * u2 + u) * d0
        + (-2.0 * u3 + 3.0 * u2) * p1
        + (u3 - u2) * d1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_hold_outside_and_on_keys() {
        let times = [1.0, 5.0, 9.0];
        assert_eq!(segment(&times, -3.0), Segment::Hold(0));
        assert_eq!(segment(&times, 1.0), Segment::Hold(0));
        assert_eq!(segment(&times, 5.0), Segment::Hold(1));
        assert_eq!(segment(&times, 12.0), Segment::Hold(2));
        assert_eq!(segment(&times, 3.0), Segment::Between(0, 0.5));
        assert_eq!(segment(&times, 8.0), Segment::Between(1, 0.75));
        assert_eq!(segment(&times, f64::NAN), Segment::Hold(0));
    }

    /// Keys at ±1e308 (a file that does not validate) hold their values on the keys and
    /// stay finite between them: the span overflows, the tangents would be 0 × ∞.
    #[test]
    fn keys_far_apart_stay_finite() {
        let times = [-1e308, 0.0, 1e308];
        let values = [1.0, 2.0, 1.0];
        let modes = [Interpolation::Bezier; 3];
        for frame in [-1e308, -1e307, -1.0, 0.0, 1e300, 1e308, f64::MAX] {
            let value = evaluate(&times, &values, &modes, frame);
            assert!(value.is_finite(), "{frame}: {value}");
        }
        assert_eq!(evaluate(&times, &values, &modes, -1e308), 1.0);
        assert_eq!(evaluate(&times, &values, &modes, 0.0), 2.0);
        let wide = [-1e308, 1e308];
        let value = evaluate(&wide, &[0.0, 4.0], &modes, 0.0);
        assert!(value.is_finite(), "{value}");
    }

    #[test]
    fn hermite_is_bezier_with_third_handles() {
        let (p0, d0, p1, d1) = (0.3, 1.2, -0.7, 0.4);
        let (c0, c1, c2, c3) = (p0, p0 + d0 / 3.0, p1 - d1 / 3.0, p1);
        for u in [0.0, 0.2, 0.5, 0.9, 1.0] {
            let s = 1.0 - u;
            let bezier =
                s * s * s * c0 + 3.0 * s * s * u * c1 + 3.0 * s * u * u * c2 + u * u * u * c3;
            assert!((hermite(p0, d0, p1, d1, u) - bezier).abs() < 1e-12);
        }
    }
}

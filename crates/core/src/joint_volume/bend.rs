//! A bent joint: the plane its ring lies in and the outer side of the bend, and the ring
//! scaled across that plane's normal (evenly when narrowing, on the outer side when widening).

use glam::{DAffine3, DVec3};

use crate::geometry::scatter_about;
use crate::hierarchy::affine_fit;

/// The swing (radians) from which a widening is on the outer side only; below it, blended
/// towards an even widening (a twist has no outer side).
const FULL_SWING: f64 = 20.0 * std::f64::consts::PI / 180.0;

/// How far (in the control's sizes) its farthest corner must stand from where the parent's
/// motion would put it for a joint to count as bent: below it the joint is at rest, its ring
/// left as the mitre put it. Controls posed through single-precision matrices (Blender's
/// empties, a glTF node) come out turned relative to their parents by rounding, about 1e-7
/// of their size; solved as bent, such a joint takes its region's volume back from what a
/// bent neighbour changed in the rows they share, and widened the horse's straight front
/// ankle into a lump beside its bent knee (docs/math.md, "Volume-keeping joints"). 1e-4 is a
/// turn of 0.006°.
const AT_REST: f64 = 1e-4;

/// How far (in the control's sizes, as [`AT_REST`]) its farthest corner must stand from where
/// the parent's motion would put it for the joint's ring to be scaled by the whole amount its
/// region's volume asks: from [`AT_REST`] up to here the amount is eased in (smoothstep), so
/// that the settle is continuous in the pose. A joint's own bend changes its region's volume
/// by next to nothing at a small turn; the whole amount there would take back what a bent
/// neighbour changed in the rows they share, and an ankle turned from 0° to 0.01° beside a
/// bent knee jumped from its mitre to a full widening (an animation pops at that frame;
/// docs/math.md, "Volume-keeping joints"). 0.1 is a turn of about 6° for a segment about as
/// long as it is wide.
const FULLY_BENT: f64 = 0.1;

/// A joint's bend in a pose: the mitre plane's normal and the outer side of the bend.
pub(super) struct Bend {
    /// The bisector of the two sides' axes (the ring's normal).
    normal: DVec3,
    /// Across the normal, away from where the control swings (zero without a swing).
    outer: DVec3,
    /// 0 for a pure twist, 1 from [`FULL_SWING`]: how much of a widening is one-sided.
    one_sided: f64,
    /// The share of the solved scale the ring takes: 0 at [`AT_REST`], 1 from
    /// [`FULLY_BENT`].
    pub(super) weight: f64,
}

impl Bend {
    /// The bend in `pose` of a control (its cage vertices and their rest positions) relative
    /// to its parent's, `axis` the limb's direction at rest; None where the control has not
    /// moved relative to its parent beyond [`AT_REST`] (or either is flat).
    pub(super) fn of(
        (control, control_rest): (&[u32], &[DVec3]),
        (parent, parent_rest): (&[u32], &[DVec3]),
        axis: DVec3,
        pose: &[DVec3],
    ) -> Option<Self> {
        let now = |vs: &[u32]| -> Option<Vec<DVec3>> {
            vs.iter().map(|&v| pose.get(v as usize).copied()).collect()
        };
        let first = *control_rest.first()?;
        let control: DAffine3 = affine_fit(control_rest, &now(control)?)?;
        let parent: DAffine3 = affine_fit(parent_rest, &now(parent)?)?;
        let size = control_rest
            .iter()
            .map(|p| (*p - first).length())
            .fold(0.0, f64::max);
        let apart = control_rest
            .iter()
            .map(|&p| (control.transform_point3(p) - parent.transform_point3(p)).length())
            .fold(0.0, f64::max);
        let size = size.max(f64::MIN_POSITIVE);
        if apart <= AT_REST * size {
            return None;
        }
        let eased = ((apart / size - AT_REST) / (FULLY_BENT - AT_REST)).clamp(0.0, 1.0);
        let along_control = control.transform_vector3(axis).try_normalize()?;
        let along_parent = parent.transform_vector3(axis).try_normalize()?;
        let normal = (along_control + along_parent).try_normalize()?;
        let away = along_parent - along_control;
        let outer = (away - away.dot(normal) * normal).normalize_or_zero();
        let swing = along_control.angle_between(along_parent);
        let t = (swing / FULL_SWING).clamp(0.0, 1.0);
        Some(Self {
            normal,
            outer,
            one_sided: t * t * (3.0 - 2.0 * t),
            weight: eased * eased * (3.0 - 2.0 * eased),
        })
    }

    /// The ring `base` scaled by `s` across the normal about its centre: evenly when
    /// narrowing, on the outer side (blended by `one_sided`) when widening.
    pub(super) fn bulged<'a>(
        &'a self,
        base: &'a [DVec3],
        s: f64,
    ) -> impl Iterator<Item = DVec3> + 'a {
        let centre = base.iter().sum::<DVec3>() / base.len().max(1) as f64;
        let normal = ring_normal(base, centre, self.normal);
        base.iter().map(move |&p| {
            let d = p - centre;
            let across = d - d.dot(normal) * normal;
            let even = across;
            let outer = d.dot(self.outer).max(0.0) * self.outer;
            let direction = if s < 0.0 {
                even
            } else {
                (1.0 - self.one_sided) * even + self.one_sided * outer
            };
            p + s * direction
        })
    }
}

/// The normal of the ring's least-squares plane (the covariance's least eigenvector, by
/// inverse iteration from `guess`): a ring laid across the limb at a slant is scaled in its
/// own plane. `guess` where the ring is a line or a point.
fn ring_normal(ring: &[DVec3], centre: DVec3, guess: DVec3) -> DVec3 {
    let spread = scatter_about(ring.iter().copied(), centre);
    let trace = spread.x_axis.x + spread.y_axis.y + spread.z_axis.z;
    let shifted = spread + glam::DMat3::from_diagonal(DVec3::splat(1e-9 * trace));
    if trace.is_nan() || trace <= 0.0 || shifted.determinant().abs() <= f64::MIN_POSITIVE {
        return guess;
    }
    let inverse = shifted.inverse();
    let mut normal = guess;
    for _ in 0..8 {
        match (inverse * normal).try_normalize() {
            Some(n) => normal = n,
            None => return guess,
        }
    }
    if normal.dot(guess) < 0.0 {
        -normal
    } else {
        normal
    }
}

//! Twist spread along a segment: a control's leaf vertices between two joints turn about the
//! segment's axis by a share of the twists at both ends, growing linearly from one joint's
//! ring to the other's, as a forearm's skin turns from the elbow to the wrist. A segment that
//! took its joint's twist rigidly would leave the whole of it to the cage coordinates between
//! the ring and the segment's nearest vertices, which blend along a chord and pull the
//! cross-section in by the cosine of half the angle between them (docs/math.md, "Joints").
//! Swings and scales stay rigid. The last segment of a limb (a hand, a foot, a head) takes its
//! joint's twist over a stretch as long as its ring is wide and is rigid beyond it.

use glam::{DAffine3, DQuat, DVec3};

use super::{Hierarchy, Joint, Level, affine_fit};
use crate::scene::Scene;

/// The leaf vertices of one control between its joint (if any) and its one child's joint.
#[derive(Debug, Clone)]
pub(super) struct Segment {
    /// The control's level.
    level: usize,
    /// The control's shape at rest, for its motion.
    rest: Vec<DVec3>,
    /// The segment's axis at rest: from the control's pivot towards the child's.
    origin: DVec3,
    axis: DVec3,
    /// The joint at the control's pivot (the control's own), if it has a ring.
    near: Option<usize>,
    /// The one child control's joint (none for the last segment of a limb).
    far: Option<usize>,
    /// (vertex, slot in the control's `owns`, share along the axis in [0, 1]).
    vertices: Vec<(u32, usize, f64)>,
}

/// The segments of the scene's controls: a control with a pivot and a joint of its own or
/// exactly one child joint (a joint whose ring the control owns), its leaf vertices (owned, in
/// no internal cage and in no joint's ring) placed along the axis from its pivot to the
/// child's pivot, or for the last segment along its joint's axis over twice the ring's radius.
pub(super) fn bind_segments(scene: &Scene, levels: &[Level], joints: &[Joint]) -> Vec<Segment> {
    let set = &scene.cages;
    let in_internal: std::collections::BTreeSet<u32> = levels
        .iter()
        .flat_map(|l| l.global.iter().copied())
        .chain(joints.iter().flat_map(|j| j.ring.iter().map(|&(v, _)| v)))
        .collect();
    let mut segments = Vec::new();
    for (l, level) in levels.iter().enumerate() {
        let mut children = joints.iter().enumerate().filter(|(_, j)| j.parent == l);
        let far = match (children.next(), children.next()) {
            (Some((far, _)), None) => Some(far),
            _ => None,
        };
        let near = joints.iter().position(|j| j.control == l);
        let Some(origin) = near
            .map(|j| joints[j].frame.pivot)
            .or_else(|| set.internals.get(l).and_then(|c| c.pivot))
        else {
            continue;
        };
        let leaves: Vec<(u32, usize, DVec3)> = level
            .owns
            .iter()
            .enumerate()
            .filter(|(_, v)| !in_internal.contains(v))
            .filter_map(|(k, &v)| Some((v, k, *set.vertices.get(v as usize)?)))
            .collect();
        let (axis, length) = match (far, near) {
            (Some(far), _) => {
                let span = joints[far].frame.pivot - origin;
                (span.try_normalize(), span.length())
            }
            // The last segment (a hand, a foot, a head) takes its joint's twist over a
            // stretch as long as the ring is wide, beyond which it stays rigid.
            (None, Some(near)) => {
                let joint = &joints[near];
                let axis = joint.frame.axis;
                let extent = leaves
                    .iter()
                    .map(|&(_, _, p)| (p - origin).dot(axis))
                    .fold(0.0, f64::max);
                (
                    Some(axis),
                    extent.min(2.0 * ring_radius(joint, &set.vertices)),
                )
            }
            (None, None) => continue,
        };
        let Some(axis) = axis.filter(|_| length > 0.0) else {
            continue;
        };
        let vertices: Vec<(u32, usize, f64)> = leaves
            .into_iter()
            .map(|(v, k, p)| (v, k, ((p - origin).dot(axis) / length).clamp(0.0, 1.0)))
            .collect();
        segments.push(Segment {
            level: l,
            rest: level.shape(&set.vertices),
            origin,
            axis,
            near,
            far,
            vertices,
        });
    }
    segments
}

impl Hierarchy {
    /// Turns the leaf vertices of every segment whose joints moved about the segment's axis:
    /// by −(1 − t)·ψ₀/2 + t·ψ₁/2 at share t along it, where ψ₀ is the control's twist relative
    /// to its parent (its joint ring took half of it) and ψ₁ the child's relative to the
    /// control (the child's ring took half of it), so that the twist grows evenly from ring to
    /// ring. Vertices moved by hand keep their place.
    pub(super) fn twist_segments(
        &self,
        pose: &mut [DVec3],
        changed: &mut [bool],
        by_hand: &[bool],
    ) {
        let moved = |level: usize| {
            self.levels[level]
                .global
                .iter()
                .any(|&v| changed[v as usize])
        };
        let touched: Vec<&Segment> = self
            .segments
            .iter()
            .filter(|s| {
                moved(s.level)
                    || s.far.is_some_and(|j| moved(self.joints[j].control))
                    || s.near.is_some_and(|j| moved(self.joints[j].parent))
            })
            .collect();
        // Each joint's twist, fitted once though two segments read it (nothing here moves a
        // control's vertices, so it stays valid through the pass).
        let mut twists: Vec<Option<f64>> = vec![None; self.joints.len()];
        let mut twist_of = |j: Option<usize>, pose: &[DVec3]| -> f64 {
            let Some(j) = j else { return 0.0 };
            *twists[j].get_or_insert_with(|| {
                let joint = &self.joints[j];
                self.joint_motions(joint, pose)
                    .map_or(0.0, |(control, parent)| {
                        joint.frame.twist_angle(&(parent.inverse() * control))
                    })
            })
        };
        for segment in touched {
            let level = &self.levels[segment.level];
            let Some(control) = affine_fit(&segment.rest, &level.shape(pose)) else {
                continue;
            };
            let near_twist = twist_of(segment.near, pose);
            let far_twist = twist_of(segment.far, pose);
            let shape = level.shape(pose);
            // p ↦ control ∘ (turn about the axis through the origin) ∘ control⁻¹, in halves.
            let from_axis = control * DAffine3::from_translation(segment.origin);
            let to_axis = DAffine3::from_translation(-segment.origin) * control.inverse();
            for &(v, slot, t) in &segment.vertices {
                let v = v as usize;
                if by_hand[v] || self.hand_moved[v] {
                    continue;
                }
                let base = level.follow[slot].position(&shape);
                let angle = -(1.0 - t) * 0.5 * near_twist + t * 0.5 * far_twist;
                let p = if angle.abs() < 1e-12 {
                    base
                } else {
                    // Into the control's rest frame, about the axis, and back.
                    let turn = DQuat::from_axis_angle(segment.axis, angle);
                    from_axis.transform_point3(turn * to_axis.transform_point3(base))
                };
                if p.is_finite() && p != pose[v] {
                    pose[v] = p;
                    changed[v] = true;
                }
            }
        }
    }
}

/// The mean distance of a joint's ring vertices from its pivot, at rest.
fn ring_radius(joint: &Joint, rest: &[DVec3]) -> f64 {
    let distances: Vec<f64> = joint
        .ring
        .iter()
        .filter_map(|&(v, _)| rest.get(v as usize))
        .map(|&p| (p - joint.frame.pivot).length())
        .collect();
    distances.iter().sum::<f64>() / distances.len().max(1) as f64
}

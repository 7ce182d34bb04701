//! A joint's turn spread along the segments beside it. Twist: a control's leaf vertices
//! between two joints turn about the segment's axis by a share of the twists at both ends,
//! growing linearly from one joint's ring to the other's, as a forearm's skin turns from the
//! elbow to the wrist; a segment that took its joint's twist rigidly would leave the whole of
//! it to the cage coordinates between the ring and the segment's nearest vertices, which blend
//! along a chord and pull the cross-section in by the cosine of half the angle between them.
//! The last segment of a limb (a hand, a foot, a head) takes its joint's twist over a stretch
//! as long as its ring is wide and is rigid beyond it. Swing: within twice a ring's radius of
//! it, a segment's vertices take a share of the joint's bend, half at the ring falling to none,
//! so that a knee bends over a stretch as long as it is thick instead of at its ring, whose
//! inner side a 90° turn slides by the ring's depth towards (and past) the nearest vertices.
//! The rings a segment's control owns (its child joints') take the same share where they
//! reach into that stretch ([`RingBack`]): an auto rig's rings are as thick as the limb is
//! wide, and a short shin's ankle ring reaches back to the knee. Scales stay rigid
//! (docs/math.md, "Joints").

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
    /// How far from each joint's ring its swing spreads into the segment (0 for none).
    near_reach: f64,
    far_reach: f64,
    vertices: Vec<SegmentVertex>,
}

/// A leaf vertex of a segment, placed along it at rest.
#[derive(Debug, Clone, Copy)]
struct SegmentVertex {
    vertex: u32,
    /// Its slot in the control's `owns`.
    slot: usize,
    /// Its share along the axis in [0, 1], for the twist.
    share: f64,
    /// Its distances along the limb from the near and the far joint's pivot (≥ 0).
    from_near: f64,
    from_far: f64,
}

/// How far a joint's swing spreads into each segment beside it, in mean radii of its ring
/// (at most the segment's length). A bend of θ spread evenly over 2·reach shortens the cage's
/// inner side, at a radius r, by θ·r/(2·reach) of its length: for a 90° bend about 0.4, where
/// a ring turned alone takes r·tan(θ/2) from the inner span between it and the segment's
/// nearest vertex and folds the crease where that span is shorter than the ring is wide
/// (docs/math.md, "Joints").
const SWING_REACH_IN_RADII: f64 = 2.0;

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
        // Each joint's swing spreads at most to the segment's other end: to the next joint's
        // pivot, or in a limb's last segment over the stretch that takes its twist.
        let reach = |j: Option<usize>| {
            j.and_then(|j| joints.get(j)).map_or(0.0, |joint| {
                (SWING_REACH_IN_RADII * ring_radius(joint, &set.vertices)).min(length)
            })
        };
        let (near_reach, far_reach) = (reach(near), reach(far));
        let distance = |j: Option<usize>, p: DVec3, sign: f64| {
            j.and_then(|j| joints.get(j))
                .map_or(f64::INFINITY, |joint| {
                    (sign * (p - joint.frame.pivot).dot(joint.frame.axis)).max(0.0)
                })
        };
        let vertices: Vec<SegmentVertex> = leaves
            .into_iter()
            .map(|(vertex, slot, p)| SegmentVertex {
                vertex,
                slot,
                share: ((p - origin).dot(axis) / length).clamp(0.0, 1.0),
                from_near: distance(near, p, 1.0),
                from_far: distance(far, p, -1.0),
            })
            .collect();
        segments.push(Segment {
            level: l,
            rest: level.shape(&set.vertices),
            origin,
            axis,
            near,
            far,
            near_reach,
            far_reach,
            vertices,
        });
    }
    segments
}

impl Hierarchy {
    /// Turns the leaf vertices of every segment whose joints moved: about the segment's axis
    /// by −(1 − t)·ψ₀/2 + t·ψ₁/2 at share t along it, where ψ₀ is the control's twist relative
    /// to its parent (its joint ring took half of it) and ψ₁ the child's relative to the
    /// control (the child's ring took half of it), so that the twist grows evenly from ring to
    /// ring; and within a joint's reach of its ring, back by (1 − a/reach)/2 of the control's
    /// swing relative to its parent (a the distance from the joint along the limb), or on by
    /// as much of the child's swing, so that a bend grows evenly through its ring from one
    /// segment into the next. Vertices moved by hand keep their place.
    pub(super) fn spread_segments(
        &self,
        pose: &mut [DVec3],
        changed: &mut [bool],
        by_hand: &[bool],
        turns: &mut JointTurns,
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
        let mut turn_of = |j: Option<usize>, pose: &[DVec3]| {
            j.map_or(JointTurn::STILL, |j| turns.of(self, j, pose))
        };
        for segment in touched {
            let level = &self.levels[segment.level];
            let Some(control) = affine_fit(&segment.rest, &level.shape(pose)) else {
                continue;
            };
            let near = turn_of(segment.near, pose);
            let far = turn_of(segment.far, pose);
            let far_pivot = segment
                .far
                .map_or(DVec3::ZERO, |j| self.joints[j].frame.pivot - segment.origin);
            let shape = level.shape(pose);
            // p ↦ control ∘ (turns about the axis through the origin) ∘ control⁻¹.
            let from_axis = control * DAffine3::from_translation(segment.origin);
            let to_axis = DAffine3::from_translation(-segment.origin) * control.inverse();
            for vertex in &segment.vertices {
                let v = vertex.vertex as usize;
                if by_hand[v] || self.hand_moved[v] {
                    continue;
                }
                let base = level.follow[vertex.slot].position(&shape);
                let t = vertex.share;
                let angle = -(1.0 - t) * 0.5 * near.twist_angle + t * 0.5 * far.twist_angle;
                let near_share = ramp(vertex.from_near, segment.near_reach);
                let far_share = ramp(vertex.from_far, segment.far_reach);
                let p = if angle.abs() < 1e-12
                    && (near_share == 0.0 || near.still())
                    && (far_share == 0.0 || far.still())
                {
                    base
                } else {
                    // Into the control's rest frame, through the turns, and back.
                    let mut x = to_axis.transform_point3(base);
                    x = DQuat::from_axis_angle(segment.axis, angle) * x;
                    if near_share > 0.0 {
                        x = near.back(near_share) * x;
                    }
                    if far_share > 0.0 {
                        x = far_pivot + far.on(far_share) * (x - far_pivot);
                    }
                    from_axis.transform_point3(x)
                };
                if p.is_finite() && p != pose[v] {
                    pose[v] = p;
                    changed[v] = true;
                }
            }
        }
    }
}

/// Where a joint's ring reaches into the stretch over which its parent control's own joint
/// spreads its swing (a short shin between a thick knee ring and a thick ankle ring): that
/// joint, and per ring vertex the share of its swing a segment vertex as far from it takes,
/// from the vertex's rest distance as the segment's vertices are placed.
#[derive(Debug, Clone)]
pub(super) struct RingBack {
    /// The parent control's own joint.
    joint: usize,
    /// Per ring vertex, in the ring's order.
    shares: Vec<f64>,
}

impl RingBack {
    /// `x`, ring vertex `k` in the parent control's rest frame, taken back by its share of
    /// `turn`, the parent's joint's turn about `pivot`.
    fn apply(&self, k: usize, x: DVec3, pivot: DVec3, turn: &JointTurn) -> DVec3 {
        match self.shares.get(k) {
            Some(&share) if share > 0.0 => pivot + turn.back(share) * (x - pivot),
            _ => x,
        }
    }
}

/// Binds each joint's [`RingBack`]: only where some vertex of its ring lies within the reach
/// of its parent control's own joint into that control's segment, so that an update fits the
/// parent joint's turn only for rings it moves.
pub(super) fn bind_ring_backs(joints: &mut [Joint], segments: &[Segment], rest: &[DVec3]) {
    for segment in segments {
        let Some(near) = segment.near.filter(|_| segment.near_reach > 0.0) else {
            continue;
        };
        let Some(frame) = joints.get(near).map(|j| j.frame) else {
            continue;
        };
        for joint in joints.iter_mut().filter(|j| j.parent == segment.level) {
            let shares: Vec<f64> = joint
                .ring
                .iter()
                .map(|&(v, _)| {
                    rest.get(v as usize).map_or(0.0, |&p| {
                        let along = (p - frame.pivot).dot(frame.axis).max(0.0);
                        ramp(along, segment.near_reach)
                    })
                })
                .collect();
            if shares.iter().any(|&s| s > 0.0) {
                joint.ring_back = Some(RingBack {
                    joint: near,
                    shares,
                });
            }
        }
    }
}

/// Each joint's turn relative to its parent, fitted at most once per update: the spread and
/// the rings read it, and neither moves a control's own vertices, so it stays valid through
/// both passes.
pub(super) struct JointTurns(Vec<Option<JointTurn>>);

impl JointTurns {
    pub(super) fn new(joints: usize) -> Self {
        Self(vec![None; joints])
    }

    fn of(&mut self, hierarchy: &Hierarchy, j: usize, pose: &[DVec3]) -> JointTurn {
        let (Some(slot), Some(joint)) = (self.0.get_mut(j), hierarchy.joints.get(j)) else {
            return JointTurn::STILL;
        };
        *slot.get_or_insert_with(|| {
            hierarchy
                .joint_motions(joint, pose)
                .map_or(JointTurn::STILL, |(control, parent)| {
                    JointTurn::of(&joint.frame, &(parent.inverse() * control))
                })
        })
    }
}

/// A joint's [`RingBack`] in one pose: the parent control's own joint's pivot and turn,
/// looked up once per ring.
pub(super) struct RingBackInPose<'a> {
    back: &'a RingBack,
    pivot: DVec3,
    turn: JointTurn,
}

impl RingBackInPose<'_> {
    /// `x`, ring vertex `k` in the parent control's rest frame, taken back by its share of
    /// the parent's joint's swing.
    pub(super) fn apply(&self, k: usize, x: DVec3) -> DVec3 {
        self.back.apply(k, x, self.pivot, &self.turn)
    }
}

impl Hierarchy {
    /// What `joint`'s ring takes back of its parent control's own joint's swing in `pose`
    /// ([`RingBack`]); None where the ring takes nothing or that joint is still.
    pub(super) fn ring_back_in_pose<'a>(
        &self,
        joint: &'a Joint,
        turns: &mut JointTurns,
        pose: &[DVec3],
    ) -> Option<RingBackInPose<'a>> {
        let back = joint.ring_back.as_ref()?;
        let turn = turns.of(self, back.joint, pose);
        let pivot = self.joints.get(back.joint)?.frame.pivot;
        (!turn.still()).then_some(RingBackInPose { back, pivot, turn })
    }
}

/// A joint's turn relative to its parent, about its pivot in rest coordinates.
#[derive(Debug, Clone, Copy)]
struct JointTurn {
    swing: DQuat,
    twist: DQuat,
    /// The twist's signed angle about the limb's axis.
    twist_angle: f64,
}

impl JointTurn {
    const STILL: Self = Self {
        swing: DQuat::IDENTITY,
        twist: DQuat::IDENTITY,
        twist_angle: 0.0,
    };

    fn of(frame: &super::JointFrame, relative: &DAffine3) -> Self {
        let (swing, twist) = frame.swing_and_twist(relative);
        Self {
            swing,
            twist,
            twist_angle: frame.twist_angle(relative),
        }
    }

    /// Whether the joint has no swing to spread.
    fn still(&self) -> bool {
        self.swing.w.abs() >= 1.0 - 1e-15
    }

    /// In the control's frame about the pivot, the turn that takes a point `share` of the
    /// swing back towards the parent: twist⁻¹ · swing^(−share) · twist, since the control
    /// applies the swing after the twist.
    fn back(&self, share: f64) -> DQuat {
        let back = DQuat::IDENTITY.slerp(self.swing.inverse(), share);
        (self.twist.inverse() * back * self.twist).normalize()
    }

    /// In the parent's frame about the pivot, `share` of the child's swing.
    fn on(&self, share: f64) -> DQuat {
        DQuat::IDENTITY.slerp(self.swing, share)
    }
}

/// The share of a joint's swing a vertex `distance` from it along the limb takes: half at the
/// ring, falling evenly to none at `reach`.
fn ramp(distance: f64, reach: f64) -> f64 {
    if reach > 0.0 && distance < reach {
        0.5 * (1.0 - distance / reach)
    } else {
        0.0
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

//! Joints of controls: a control (an internal cage with a pivot) turns what it owns rigidly,
//! and the ring of leaf vertices at its joint, which its parent control owns, turns half as
//! far about the pivot and stretches so that the two sides meet as a mitre. A ring that
//! followed either side alone would leave one segment's cage to take the whole bend between a
//! fixed face and a turned one, which halves its cross-section at 90° (docs/math.md,
//! "Joints"). The mitre is not a cage coordinate (not linear in the control's vertices), so a
//! drag over a joint takes the hierarchy's full path.

use glam::{DAffine3, DMat3, DQuat, DVec3};

/// The least-squares affine map taking `rest` to `now` (as many points each): exact for a
/// rigid or affine motion of points that do not lie in one plane. None for fewer than four
/// points, points in a plane, or non-finite input.
pub fn affine_fit(rest: &[DVec3], now: &[DVec3]) -> Option<DAffine3> {
    if rest.len() != now.len() || rest.len() < 4 {
        return None;
    }
    let n = rest.len() as f64;
    let rest_centre = rest.iter().sum::<DVec3>() / n;
    let now_centre = now.iter().sum::<DVec3>() / n;
    let (mut cross, mut spread) = (DMat3::ZERO, DMat3::ZERO);
    for (&r, &c) in rest.iter().zip(now) {
        let (r, c) = (r - rest_centre, c - now_centre);
        cross += outer(c, r);
        spread += outer(r, r);
    }
    // Points in a plane (or a line) leave the spread singular: no unique map.
    let scale = spread.x_axis.x + spread.y_axis.y + spread.z_axis.z;
    let determinant = spread.determinant().abs();
    if determinant.is_nan() || determinant <= 1e-12 * scale.powi(3) {
        return None;
    }
    let linear = cross * spread.inverse();
    let map = DAffine3::from_mat3_translation(linear, now_centre - linear * rest_centre);
    map.is_finite().then_some(map)
}

/// `a bᵀ`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Largest stretch of a mitre (a bend of about 140°): past it the ring's far side would run
/// off towards infinity as the bend nears 180°.
const MAX_MITRE_STRETCH: f64 = 3.0;

/// A joint at rest: the control's pivot and the limb's direction there (towards the control's
/// side), both in rest coordinates.
#[derive(Debug, Clone, Copy)]
pub struct JointFrame {
    /// The pivot.
    pub pivot: DVec3,
    /// Unit direction along the limb through the joint.
    pub axis: DVec3,
}

impl JointFrame {
    /// The map that takes a ring point in rest coordinates to its mitred place, for the
    /// control's motion `relative` relative to its parent (both maps of rest space; identity
    /// when the control has not turned relative to its parent): the half of the relative turn
    /// (swing and twist about the limb's axis taken apart, each halved), the stretch 1/cos of
    /// half the swing across the swing's axis in the ring's plane, a widening across the axis
    /// of 1/√(2/3 + cos(ψ/2)/3) for a twist ψ, the square root of a uniform scale, and half the
    /// pivot's move.
    pub fn mitre(&self, relative: &DAffine3) -> DAffine3 {
        let linear = relative.matrix3;
        let (rotation, scale) = rotation_and_scale(linear);
        let pivot_moved = relative.transform_point3(self.pivot);
        let centre = 0.5 * (self.pivot + pivot_moved);
        let d = self.axis;
        let (swing, twist) = swing_twist(rotation, d);
        let half = |q: DQuat| DQuat::IDENTITY.slerp(q, 0.5);
        let (swing_half, twist_half) = (half(swing), half(twist));
        let swing_angle = 2.0 * swing.w.abs().min(1.0).acos();
        let swing_axis = DVec3::new(swing.x, swing.y, swing.z);
        let stretch = if swing_axis.length_squared() > 1e-24 {
            let across = swing_axis.normalize().cross(d).normalize_or_zero();
            let k = (1.0 / (0.5 * swing_angle).cos()).min(MAX_MITRE_STRETCH);
            // Identity plus (k − 1) along `across`.
            DMat3::IDENTITY + (k - 1.0) * outer(across, across)
        } else {
            DMat3::IDENTITY
        };
        // A twist of ψ/2 on each side of the ring: cage coordinates blend the ring with its
        // neighbours along a chord, whose mean cross-section is 2/3 + cos(ψ/2)/3 of the arc's;
        // the ring widens across the axis by what gives it back.
        let twist_angle = 2.0 * twist.w.abs().min(1.0).acos();
        let widen = 1.0 / (2.0 / 3.0 + (0.5 * twist_angle).cos() / 3.0).sqrt();
        let widen = DMat3::IDENTITY + (widen - 1.0) * (DMat3::IDENTITY - outer(d, d));
        let half_linear = scale.sqrt()
            * DMat3::from_quat(swing_half)
            * stretch
            * DMat3::from_quat(twist_half)
            * widen;
        // x ↦ centre + H (x − pivot).
        DAffine3::from_mat3_translation(half_linear, centre - half_linear * self.pivot)
    }
}

impl JointFrame {
    /// The rotation of the control's motion `relative` to its parent as a swing (about an
    /// axis across the limb) after a twist (about the limb's axis): `rotation = swing * twist`,
    /// both about the pivot in rest coordinates.
    pub fn swing_and_twist(&self, relative: &DAffine3) -> (DQuat, DQuat) {
        let (rotation, _) = rotation_and_scale(relative.matrix3);
        swing_twist(rotation, self.axis)
    }

    /// The signed angle (radians, in (−π, π]) by which the control's motion `relative` to its
    /// parent turns about the limb's axis: the twist of its swing-twist decomposition.
    pub fn twist_angle(&self, relative: &DAffine3) -> f64 {
        let (rotation, _) = rotation_and_scale(relative.matrix3);
        let (_, twist) = swing_twist(rotation, self.axis);
        let along = DVec3::new(twist.x, twist.y, twist.z).dot(self.axis);
        let (along, w) = if twist.w < 0.0 {
            (-along, -twist.w)
        } else {
            (along, twist.w)
        };
        2.0 * along.atan2(w)
    }
}

/// A rotation as a swing (about an axis across unit `d`) after a twist (about `d`):
/// `rotation = swing * twist`.
fn swing_twist(rotation: DQuat, d: DVec3) -> (DQuat, DQuat) {
    let along = DVec3::new(rotation.x, rotation.y, rotation.z).dot(d);
    let twist = DQuat::from_xyzw(d.x * along, d.y * along, d.z * along, rotation.w);
    let twist = if twist.length_squared() > 1e-24 {
        twist.normalize()
    } else {
        DQuat::IDENTITY
    };
    ((rotation * twist.inverse()).normalize(), twist)
}

/// The rotation of a linear map and its uniform scale (the cube root of its determinant's
/// size): the orthogonal factor of its polar decomposition by Newton's iteration. Identity and
/// 1 for a singular or non-finite map.
fn rotation_and_scale(m: DMat3) -> (DQuat, f64) {
    let det = m.determinant();
    if !(det.is_finite() && det.abs() > 1e-300) {
        return (DQuat::IDENTITY, 1.0);
    }
    let scale = det.abs().cbrt();
    let mut r = m * (1.0 / scale);
    for _ in 0..30 {
        let inverse_transpose = r.inverse().transpose();
        let next = 0.5 * (r + inverse_transpose);
        let step = (next - r)
            .to_cols_array()
            .iter()
            .map(|x| x.abs())
            .sum::<f64>();
        r = next;
        if step < 1e-14 {
            break;
        }
    }
    if r.determinant() < 0.0 || !r.is_finite() {
        // A reflection has no rotation to halve: the ring stays with the parent.
        return (DQuat::IDENTITY, 1.0);
    }
    (DQuat::from_mat3(&r).normalize(), scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn box_points() -> Vec<DVec3> {
        (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
            .map(|p| p * DVec3::new(1.0, 2.0, 3.0) + DVec3::new(0.5, -1.0, 2.0))
            .collect()
    }

    #[test]
    fn an_affine_fit_recovers_a_rigid_motion_and_refuses_a_plane() {
        let motion = DAffine3::from_rotation_translation(
            DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 1.1),
            DVec3::new(0.3, -2.0, 4.0),
        );
        let rest = box_points();
        let now: Vec<DVec3> = rest.iter().map(|&p| motion.transform_point3(p)).collect();
        let fit = affine_fit(&rest, &now).unwrap();
        let p = DVec3::new(7.0, -3.0, 0.25);
        assert!((fit.transform_point3(p) - motion.transform_point3(p)).length() < 1e-9);
        let flat: Vec<DVec3> = rest.iter().map(|p| DVec3::new(p.x, p.y, 0.0)).collect();
        assert!(affine_fit(&flat, &flat).is_none());
    }

    #[test]
    fn a_mitre_halves_the_turn_and_meets_both_tubes() {
        // A tube along -z below the pivot (the child's side), bent 90° about x.
        let frame = JointFrame {
            pivot: DVec3::ZERO,
            axis: DVec3::NEG_Z,
        };
        let turn = DAffine3::from_rotation_x(90f64.to_radians());
        let mitre = frame.mitre(&turn);
        // A ring point on the bend's side stretches by 1/cos 45° along the bisector plane.
        let p = DVec3::new(0.0, 1.0, 0.0);
        let q = mitre.transform_point3(p);
        // The parent's tube (x, y, z ≥ 0 line through p along z) and the child's (the turned
        // line) both pass through q.
        let child_line_point = turn.transform_point3(p);
        let child_direction = turn.transform_vector3(DVec3::NEG_Z);
        let on_parent = (q - p).cross(DVec3::Z).length();
        let on_child = (q - child_line_point).cross(child_direction).length();
        assert!(on_parent < 1e-9 && on_child < 1e-9, "{q}");
        // A point on the swing's axis only turns by half (here it stays: the axis is x).
        let a = mitre.transform_point3(DVec3::X);
        assert!((a - DVec3::X).length() < 1e-9);
        // No turn: no change. A pure twist: half of it, no stretch.
        let still = frame.mitre(&DAffine3::IDENTITY);
        assert!((still.transform_point3(p) - p).length() < 1e-12);
        // A pure twist: half of it, no stretch along the axis, the ring widened across it by
        // what a chord of half the twist takes from the mean cross-section.
        let twist = frame.mitre(&DAffine3::from_rotation_z(1.0));
        let widen = 1.0 / (2.0 / 3.0 + 0.5f64.cos() / 3.0).sqrt();
        let q = p + DVec3::new(0.0, 0.0, -0.7);
        let expected = DQuat::from_rotation_z(0.5) * (widen * p) + DVec3::new(0.0, 0.0, -0.7);
        assert!((twist.transform_point3(q) - expected).length() < 1e-9);
        // Signed about the limb's axis (here −z).
        assert!((frame.twist_angle(&DAffine3::from_rotation_z(1.0)) + 1.0).abs() < 1e-12);
        assert!((frame.twist_angle(&DAffine3::from_rotation_z(-2.5)) - 2.5).abs() < 1e-12);
        // A swing about an axis across the limb has no twist.
        assert!(frame.twist_angle(&turn).abs() < 1e-12);
        let both = DAffine3::from_rotation_x(0.7) * DAffine3::from_rotation_z(0.4);
        assert!((frame.twist_angle(&both) + 0.4).abs() < 1e-12);
    }
}

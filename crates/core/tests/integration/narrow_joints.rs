//! Joints where a limb narrows (`autorig::narrowings`): a knee between a thick thigh and a
//! calf gets the joint a leg is cut at equal lengths would put elsewhere.

use std::collections::BTreeMap;

use glam::DVec3;
use starcages_core::generate::{AutorigSettings, Mirror};
use starcages_core::mesh::Mesh;

use crate::common::capsules;
use crate::posable_rig::rigged_with;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A standing human facing −Y, a pelvis across its hips, whose legs (hips at −0.1, soles at
/// −1.92) narrow to a knee of radius 0.08 at `knee_z` between a thigh of 0.15 and a calf of
/// 0.12 where `narrow`; else each leg is one capsule of 0.13.
fn human_with_knees(knee_z: f64, narrow: bool) -> Mesh {
    let mut parts = vec![
        (v(0.0, 0.0, 0.1), v(0.0, 0.0, 1.0), 0.38),
        (v(-0.3, 0.0, -0.05), v(0.3, 0.0, -0.05), 0.2),
        (v(0.0, 0.0, 1.3), v(0.0, 0.0, 1.5), 0.1),
        (v(0.0, -0.03, 1.75), v(0.0, 0.0, 1.85), 0.24),
    ];
    for side in [-1.0, 1.0] {
        let x = 0.3 * side;
        parts.push((v(0.4 * side, 0.0, 1.05), v(0.75 * side, 0.0, 0.3), 0.1));
        parts.push((v(0.75 * side, 0.0, 0.3), v(0.85 * side, 0.0, -0.3), 0.08));
        if narrow {
            parts.push((v(x, 0.0, -0.1), v(x, 0.0, knee_z + 0.2), 0.15));
            parts.push((v(x, 0.0, knee_z + 0.2), v(x, 0.0, knee_z - 0.2), 0.08));
            parts.push((v(x, 0.0, knee_z - 0.2), v(x, 0.0, -1.8), 0.12));
        } else {
            parts.push((v(x, 0.0, -0.1), v(x, 0.0, -1.8), 0.13));
        }
    }
    capsules(&parts, 0.035)
}

/// The heights of the pivots of each leg's controls, by control name.
fn leg_pivots(mesh: &Mesh, settings: &AutorigSettings) -> BTreeMap<String, f64> {
    let scene = rigged_with(mesh, settings);
    (scene.cages.internals.iter())
        .filter(|c| c.name.starts_with("leg."))
        .map(|c| (c.name.clone(), c.pivot.unwrap_or(DVec3::ZERO).z))
        .collect()
}

/// The knee joint lies where the leg narrows, on both legs, though cutting the leg at equal
/// lengths puts it elsewhere; the equal-length joint stands on a leg of one thickness (the
/// negative control). Mirrored, so that both legs run along a grid axis: without the mirror
/// one leg's top, ragged where it leaves the pelvis, tilts its distances from the body off
/// the axis, and neither leg is measured (`docs/autorig.md`, Limits). The cells are 0.125.
#[test]
fn the_knee_joint_is_where_the_leg_narrows() {
    let mirrored = AutorigSettings {
        mirror: Mirror::Auto,
        ..AutorigSettings::default()
    };
    let uniform = leg_pivots(&human_with_knees(-0.7, false), &mirrored);
    // A cell above and below where equal lengths put the joint.
    for knee in [-0.68, -0.92] {
        let pivots = leg_pivots(&human_with_knees(knee, true), &mirrored);
        for control in ["leg.L.2", "leg.R.2"] {
            let z = pivots[control];
            assert!(
                (z - knee).abs() < 0.06,
                "{control} at {z:.3}, the knee at {knee}: {pivots:?}"
            );
            let equal_lengths = uniform[control];
            assert!(
                (equal_lengths - knee).abs() > 0.1,
                "a uniform leg's joint at {equal_lengths:.3}: {uniform:?}"
            );
        }
    }
}

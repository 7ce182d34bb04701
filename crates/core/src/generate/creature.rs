//! The `creature` demo: a four-legged animal of about 64k triangles (the size of the paper's
//! Sintel, Fig. 16) rigged by a script of rig operations (`assets/creature/rig.ops`, the same
//! text `starcages-cli edit --script` runs) into chains of leaf cages along the limbs with few
//! neighbours each, with mixed coordinates: the paper's setup for Table II.

use glam::DVec3;

use crate::mesh::Mesh;
use crate::rig::{RigEditError, apply_rig_op, parse_rig_script};
use crate::scene::{CageSet, MeshSource, Scene, SceneSettings};
use crate::surface_nets::surface_nets;

/// The rig script: one rig operation per line, `#` starts a comment.
pub const CREATURE_RIG: &str = include_str!("../../../../assets/creature/rig.ops");

/// Polynomial smooth minimum (blends two distances over a band of width `k`).
fn smooth_min(a: f64, b: f64, k: f64) -> f64 {
    let h = (0.5 + 0.5 * (b - a) / k).clamp(0.0, 1.0);
    b + (a - b) * h - k * h * (1.0 - h)
}

/// Distance to a tube from `a` (radius `ra`) to `b` (radius `rb`), the radius varying along it.
fn tube(p: DVec3, a: DVec3, b: DVec3, ra: f64, rb: f64) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    p.distance(a + ab * t) - (ra + (rb - ra) * t)
}

/// An approximate distance to an ellipsoid of centre `c` and radii `r` (exact on the surface).
fn ellipsoid(p: DVec3, c: DVec3, r: DVec3) -> f64 {
    let q = (p - c) / r;
    let k0 = q.length();
    let k1 = ((p - c) / (r * r)).length();
    if k1 > 0.0 {
        k0 * (k0 - 1.0) / k1
    } else {
        -r.min_element()
    }
}

/// The creature's implicit surface (negative inside), z up, looking along +x: a body, a neck
/// rising from the front of the back with a head and snout, four legs that leave the body's
/// sides and bend down at the knee (thigh and shin), and a tail rising backwards.
pub fn creature_field(p: DVec3) -> f64 {
    let body = ellipsoid(p, DVec3::new(0.0, 0.0, 1.05), DVec3::new(0.75, 0.21, 0.23));
    let neck = tube(
        p,
        DVec3::new(0.72, 0.0, 1.12),
        DVec3::new(0.84, 0.0, 1.66),
        0.12,
        0.09,
    );
    let head = ellipsoid(p, DVec3::new(1.04, 0.0, 1.76), DVec3::new(0.23, 0.14, 0.12));
    let snout = tube(
        p,
        DVec3::new(1.15, 0.0, 1.76),
        DVec3::new(1.42, 0.0, 1.71),
        0.09,
        0.055,
    );
    let ears = [-1.0, 1.0].map(|side| {
        tube(
            p,
            DVec3::new(0.98, 0.07 * side, 1.84),
            DVec3::new(0.9, 0.13 * side, 1.95),
            0.04,
            0.015,
        )
    });
    let tail = tube(
        p,
        DVec3::new(-0.65, 0.0, 1.1),
        DVec3::new(-1.45, 0.0, 1.25),
        0.08,
        0.03,
    );
    let mut shape = smooth_min(body, neck, 0.08);
    shape = smooth_min(shape, head, 0.06);
    shape = smooth_min(shape, snout, 0.05);
    for ear in ears {
        shape = smooth_min(shape, ear, 0.03);
    }
    shape = smooth_min(shape, tail, 0.06);
    for x in [-0.48, 0.42] {
        for side in [-1.0, 1.0] {
            let hip = DVec3::new(x, 0.12 * side, 1.02);
            let knee = DVec3::new(x, 0.44 * side, 0.95);
            let foot = DVec3::new(x, 0.44 * side, 0.1);
            let thigh = tube(p, hip, knee, 0.085, 0.075);
            let shin = tube(p, knee, foot, 0.075, 0.055);
            shape = smooth_min(shape, smooth_min(thigh, shin, 0.03), 0.07);
        }
    }
    shape
}

/// The creature's mesh; `detail` 1 gives about 64k triangles (the count grows as its square).
pub fn creature_mesh(detail: f64) -> Mesh {
    let spacing = 0.0143 / detail.clamp(0.05, 8.0);
    let (positions, triangles) = surface_nets(
        creature_field,
        DVec3::new(-1.55, -0.65, -0.1),
        DVec3::new(1.6, 0.65, 2.1),
        spacing,
    );
    Mesh::new(positions, triangles, None, None)
        .unwrap_or_else(|e| unreachable!("creature mesh: {e}"))
}

/// The creature scene: its mesh rigged by [`CREATURE_RIG`].
pub fn creature(detail: f64) -> Scene {
    let mut scene = Scene::new(
        MeshSource::Embedded,
        creature_mesh(detail),
        CageSet::default(),
        SceneSettings::default(),
    );
    apply_rig_script(&mut scene, CREATURE_RIG)
        .unwrap_or_else(|e| unreachable!("creature rig: {e}"));
    // A pose: the head turned and lowered, the tail up, a front leg stepping forward.
    super::demo_pose::store_pose(
        &mut scene,
        "step",
        &[
            "head: rotate 0 0 1 30",
            "head: translate 0.05 0.1 -0.08",
            "tail: rotate 0 1 0 -25",
            "shin_front_left: rotate 0 1 0 -30",
            "shin_front_left: translate 0.12 0 0.04",
        ],
    );
    store_walk_cycle(&mut scene);
    scene
}

/// A shin swung forward (`+1`) or back (`-1`) about the knee: a rotation about its centre
/// and a shift that keeps its top (the knee) close to where it was.
fn swing(leg: &str, direction: f64) -> [String; 2] {
    let degrees = 18.0 * direction;
    let shift = 0.37 * degrees.to_radians().sin();
    [
        format!("shin_{leg}: rotate 0 1 0 {}", -degrees),
        format!("shin_{leg}: translate {shift} 0 0"),
    ]
}

/// A shin lifted and carried forward in the passing position.
fn lift(leg: &str) -> [String; 2] {
    [
        format!("shin_{leg}: rotate 0 1 0 -10"),
        format!("shin_{leg}: translate 0.07 0 0.07"),
    ]
}

/// The walk cycle: two seconds at 24 fps (frames 1 to 48, the key at 49 repeating frame 1 so
/// that playback loops), diagonal legs moving together as in a trot, the tail swinging and the
/// head nodding at each contact.
fn store_walk_cycle(scene: &mut Scene) {
    let contact = |forward: [&str; 2], back: [&str; 2], tail: f64| -> Vec<String> {
        let mut edits: Vec<String> = Vec::new();
        for leg in forward {
            edits.extend(swing(leg, 1.0));
        }
        for leg in back {
            edits.extend(swing(leg, -1.0));
        }
        edits.push(format!("tail: rotate 0 0 1 {tail}"));
        edits.push("head: rotate 0 1 0 6".into());
        edits
    };
    let passing = |lifted: [&str; 2]| -> Vec<String> {
        let mut edits: Vec<String> = lifted.iter().flat_map(|leg| lift(leg)).collect();
        edits.push("head: rotate 0 1 0 -4".into());
        edits
    };
    let poses = [
        (
            "walk_contact_1",
            contact(
                ["front_left", "rear_right"],
                ["front_right", "rear_left"],
                14.0,
            ),
        ),
        ("walk_passing_1", passing(["front_right", "rear_left"])),
        (
            "walk_contact_2",
            contact(
                ["front_right", "rear_left"],
                ["front_left", "rear_right"],
                -14.0,
            ),
        ),
        ("walk_passing_2", passing(["front_left", "rear_right"])),
    ];
    for (name, edits) in &poses {
        let edits: Vec<&str> = edits.iter().map(String::as_str).collect();
        super::demo_pose::store_pose(scene, name, &edits);
    }
    super::demo_pose::set_keys(
        scene,
        48,
        &[
            (1.0, "walk_contact_1"),
            (13.0, "walk_passing_1"),
            (25.0, "walk_contact_2"),
            (37.0, "walk_passing_2"),
            (49.0, "walk_contact_1"),
        ],
    );
}

/// Runs a rig script (see [`parse_rig_script`]) on `scene`, whole or not at all.
pub fn apply_rig_script(scene: &mut Scene, script: &str) -> Result<(), RigEditError> {
    let ops = parse_rig_script(script)?;
    let mut edited = scene.clone();
    for (line, op) in ops {
        apply_rig_op(&mut edited, &op).map_err(|e| RigEditError::AtLine {
            line,
            problem: Box::new(e),
        })?;
    }
    *scene = edited;
    Ok(())
}

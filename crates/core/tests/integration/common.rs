//! Random cages and points shared by the coordinate property tests, and shapes made of
//! capsules for the auto rig's tests.
#![allow(dead_code, missing_docs)]

use glam::{DMat3, DQuat, DVec3};
use proptest::prelude::*;
use starcages_core::Cage;
use starcages_core::cage::shapes;

/// Icosphere: the icosahedron subdivided once (42 vertices, 80 faces), unit radius.
pub fn icosphere_soup() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    shapes::icosphere_soup(1)
}

/// A convex cage: an icosahedron under a random well-conditioned linear map and translation.
pub fn convex_cage() -> impl Strategy<Value = Cage> {
    (
        prop::array::uniform9(-0.4f64..0.4),
        prop::array::uniform3(-2.0f64..2.0),
    )
        .prop_map(|(m, t)| {
            let map = DMat3::IDENTITY + DMat3::from_cols_array(&m);
            let (positions, faces) = shapes::icosahedron_soup(1.0);
            let flip = map.determinant() < 0.0;
            let positions = positions
                .into_iter()
                .map(|p| map * p + DVec3::from_array(t))
                .collect();
            let faces: Vec<[u32; 3]> = faces
                .into_iter()
                .map(|f| if flip { [f[0], f[2], f[1]] } else { f })
                .collect();
            Cage::from_triangles(positions, &faces).expect("affine image of a convex cage")
        })
}

/// A non-convex, star-shaped cage: an icosphere with random radii in [0.5, 1.3].
pub fn star_cage() -> impl Strategy<Value = Cage> {
    prop::collection::vec(0.5f64..1.3, 42).prop_map(|radii| {
        let (positions, faces) = icosphere_soup();
        let positions = positions.iter().zip(&radii).map(|(p, r)| *p * *r).collect();
        Cage::from_triangles(positions, &faces).expect("star-shaped cage")
    })
}

/// Random points inside a star-shaped or convex cage around the centroid of its vertices:
/// a fraction of the way from the centroid to the cage along random directions.
pub fn interior_points(cage: &Cage, seeds: &[(DVec3, f64)]) -> Vec<DVec3> {
    let centre = cage.positions().iter().sum::<DVec3>() / cage.vertex_count() as f64;
    seeds
        .iter()
        .filter_map(|&(dir, frac)| {
            let dir = dir.try_normalize()?;
            let hit = Some(cage.ray_exit(centre, dir)).filter(|t| t.is_finite())?;
            Some(centre + dir * hit * frac)
        })
        .collect()
}

pub fn seeds(n: usize) -> impl Strategy<Value = Vec<(DVec3, f64)>> {
    prop::collection::vec(
        (
            prop::array::uniform3(-1.0f64..1.0).prop_map(DVec3::from_array),
            0.02f64..0.95,
        ),
        n,
    )
}

pub fn similarity() -> impl Strategy<Value = (DQuat, f64, DVec3)> {
    (
        prop::array::uniform3(-1.0f64..1.0),
        -3.0f64..3.0,
        0.3f64..3.0,
        prop::array::uniform3(-5.0f64..5.0),
    )
        .prop_map(|(axis, angle, scale, t)| {
            let axis = DVec3::from_array(axis).try_normalize().unwrap_or(DVec3::Z);
            (
                DQuat::from_axis_angle(axis, angle),
                scale,
                DVec3::from_array(t),
            )
        })
}

pub fn affine() -> impl Strategy<Value = (DMat3, DVec3)> {
    (
        prop::array::uniform9(-1.0f64..1.0),
        prop::array::uniform3(-5.0f64..5.0),
    )
        .prop_map(|(m, t)| {
            (
                DMat3::IDENTITY + DMat3::from_cols_array(&m) * 0.5,
                DVec3::from_array(t),
            )
        })
}

/// A tall box mesh (0.1 .. 0.9 across, 0.1 .. 1.8 up) and no cages yet: where rig scripts start.
pub fn empty_scene() -> starcages_core::scene::Scene {
    use starcages_core::scene::{CageSet, MeshSource, Scene, SceneSettings};
    let mesh = starcages_core::generate::demo::box_mesh(
        glam::DVec3::new(0.1, 0.1, 0.1),
        glam::DVec3::new(0.9, 0.9, 1.8),
        [3, 3, 6],
    );
    Scene::new(
        MeshSource::Embedded,
        mesh,
        CageSet::default(),
        SceneSettings::default(),
    )
}

/// Distance from `p` to the capsule from `a` to `b` of radius `r` (negative inside).
pub fn capsule(p: DVec3, a: DVec3, b: DVec3, r: f64) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    (p - (a + ab * t)).length() - r
}

/// A closed mesh of the union of capsules (a, b, radius), by surface nets at `spacing`.
pub fn capsules(parts: &[(DVec3, DVec3, f64)], spacing: f64) -> starcages_core::mesh::Mesh {
    let field = |p: DVec3| {
        parts
            .iter()
            .map(|&(a, b, r)| capsule(p, a, b, r))
            .fold(f64::INFINITY, f64::min)
    };
    let (lo, hi) = parts.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &(a, b, r)| (lo.min(a.min(b) - r), hi.max(a.max(b) + r)),
    );
    let pad = DVec3::splat(2.0 * spacing);
    let (positions, triangles) =
        starcages_core::surface_nets::surface_nets(field, lo - pad, hi + pad, spacing);
    starcages_core::mesh::Mesh::new(positions, triangles, None, None).unwrap()
}

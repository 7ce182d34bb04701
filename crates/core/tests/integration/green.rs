//! Properties of Green Coordinates: reproduction Σ φ_i v_i + Σ ψ_j n_j = p, similarity
//! invariance of the deformation, and the guarded edge-line case.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use crate::common;

use common::*;
use glam::DVec3;
use proptest::prelude::*;
use starcages_core::cage::shapes;
use starcages_core::coords::GreenWeights;
use starcages_core::{BindControl, BindSettings, Cage, CageWeights, CoordinateKind, bind};

fn gc(cage: &Cage, points: &[DVec3]) -> GreenWeights {
    match bind(
        CoordinateKind::Green,
        cage,
        points,
        &BindSettings::default(),
        &BindControl::default(),
    ) {
        Ok(CageWeights::Green(g)) => g,
        other => panic!("unexpected {other:?}"),
    }
}

fn reproduce(cage: &Cage, g: &GreenWeights, i: usize) -> DVec3 {
    let normals = cage.triangle_normals();
    let a: DVec3 = g
        .phi_row(i)
        .iter()
        .zip(cage.positions())
        .map(|(&w, &v)| w * v)
        .sum();
    let b: DVec3 = g
        .psi_row(i)
        .iter()
        .zip(&normals)
        .map(|(&w, &n)| w * n)
        .sum();
    a + b
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn reproduces_points_inside(cage in star_cage(), s in seeds(30)) {
        let pts = interior_points(&cage, &s);
        let g = gc(&cage, &pts);
        for (i, p) in pts.iter().enumerate() {
            let sum: f64 = g.phi_row(i).iter().sum();
            prop_assert!((sum - 1.0).abs() < 1e-9, "Σφ = {sum}");
            let q = reproduce(&cage, &g, i);
            prop_assert!((q - *p).length() < 1e-9, "{q} vs {p}");
        }
    }

    #[test]
    fn similarity_is_reproduced_exactly(cage in convex_cage(), s in seeds(30), sim in similarity()) {
        let (rotation, scale, translation) = sim;
        let map = |p: DVec3| rotation * p * scale + translation;
        let pts = interior_points(&cage, &s);
        let weights = bind(CoordinateKind::Green, &cage, &pts, &BindSettings::default(), &BindControl::default()).unwrap();
        let posed: Vec<DVec3> = cage.positions().iter().map(|&v| map(v)).collect();
        let deformed = weights.deform(&cage, &posed).unwrap();
        for (p, q) in pts.iter().zip(&deformed) {
            prop_assert!((map(*p) - *q).length() < 1e-9 * scale.max(1.0) * 10.0, "{} vs {q}", map(*p));
        }
    }

    #[test]
    fn exterior_extension_reproduces_points_outside(cage in star_cage(), dir in prop::array::uniform3(-1.0f64..1.0), r in 1.4f64..3.0) {
        let p = DVec3::from_array(dir).try_normalize().unwrap_or(DVec3::X) * r;
        let g = gc(&cage, &[p]);
        let q = reproduce(&cage, &g, 0);
        prop_assert!((q - p).length() < 1e-9, "{q} vs {p}");
    }
}

#[test]
fn points_on_edge_lines_and_faces_stay_finite() {
    let cage = shapes::cuboid(DVec3::ZERO, DVec3::ONE);
    // Inside, on the line of an edge (x = 0.5, y = 0 extended is not inside), so use the
    // diagonal edges of the quads' fans: the face diagonal from (0,0,0) to (1,1,0) lies in the
    // bottom face; the point (0.25, 0.25, 0) is on it.
    let on_edge = DVec3::new(0.25, 0.25, 0.0);
    let on_face = DVec3::new(0.3, 0.6, 0.0);
    let near = DVec3::new(0.25, 0.25, 1e-12);
    let pts = [on_edge, on_face, near, DVec3::new(0.5, 0.5, 0.5)];
    let g = gc(&cage, &pts);
    assert!(g.phi.iter().chain(&g.psi).all(|x| x.is_finite()));
    for (i, p) in pts.iter().enumerate() {
        let q = reproduce(&cage, &g, i);
        assert!((q - *p).length() < 1e-8, "{i}: {q} vs {p}");
    }
}

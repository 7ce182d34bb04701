//! Properties of Harmonic Coordinates: partition of unity, non-negativity and the maximum
//! principle, linear precision converging with the grid, agreement with MVC on faces, and
//! typed errors outside the cage.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use crate::common;

use common::*;
use glam::DVec3;
use proptest::prelude::*;
use starcages_core::cage::shapes;
use starcages_core::coords::HarmonicSettings;
use starcages_core::{
    BindControl, BindSettings, Cage, CageWeights, CoordError, CoordinateKind, bind,
};

fn hc_at(cage: &Cage, points: &[DVec3], resolution: u32) -> Result<Vec<Vec<f64>>, CoordError> {
    let settings = BindSettings {
        harmonic: HarmonicSettings {
            resolution,
            ..Default::default()
        },
    };
    match bind(
        CoordinateKind::Harmonic,
        cage,
        points,
        &settings,
        &BindControl::default(),
    )? {
        CageWeights::Vertex { weights, .. } => {
            Ok((0..points.len()).map(|i| weights.row(i).to_vec()).collect())
        }
        CageWeights::Green(_) => panic!("green weights from hc"),
    }
}

fn linear_error(cage: &Cage, p: DVec3, w: &[f64]) -> f64 {
    let q: DVec3 = w.iter().zip(cage.positions()).map(|(&w, &v)| w * v).sum();
    (q - p).length() / cage.diagonal()
}

fn grid_points(cage: &Cage, n: usize) -> Vec<DVec3> {
    let (lo, hi) = cage.bounds();
    let mut pts = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let f = DVec3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) / n as f64;
                let p = lo + (hi - lo) * f;
                if cage.winding_number(p) > 0.5 {
                    pts.push(p);
                }
            }
        }
    }
    pts
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(6))]

    #[test]
    fn partition_of_unity_non_negative_maximum_principle(cage in star_cage(), s in seeds(40)) {
        let pts = interior_points(&cage, &s);
        for w in hc_at(&cage, &pts, 24).unwrap() {
            let sum: f64 = w.iter().sum();
            prop_assert!((sum - 1.0).abs() < 1e-12, "Σw = {sum}");
            prop_assert!(w.iter().all(|&x| (0.0..=1.0).contains(&x)), "{w:?}");
        }
    }
}

#[test]
fn linear_precision_error_shrinks_as_the_grid_refines() {
    for cage in [
        shapes::l_prism(),
        shapes::star_prism(),
        shapes::icosahedron(1.0),
    ] {
        let pts = grid_points(&cage, 7);
        let max_error = |res| {
            let w = hc_at(&cage, &pts, res).unwrap();
            pts.iter()
                .zip(&w)
                .map(|(p, w)| linear_error(&cage, *p, w))
                .fold(0.0, f64::max)
        };
        let (coarse, fine) = (max_error(16), max_error(32));
        assert!(coarse < 0.05, "error at 16: {coarse}");
        assert!(
            fine < 0.7 * coarse,
            "no convergence: {coarse} at 16 -> {fine} at 32"
        );
    }
}

#[test]
fn non_negative_in_non_convex_cages_where_mvc_is_not() {
    for cage in [shapes::l_prism(), shapes::star_prism()] {
        let pts = grid_points(&cage, 10);
        let w = hc_at(&cage, &pts, 32).unwrap();
        let min = w.iter().flatten().copied().fold(f64::INFINITY, f64::min);
        assert!(min >= 0.0, "negative HC weight {min}");
        // Interior maximum principle: no weight reaches 1 strictly inside.
        assert!(w.iter().flatten().all(|&x| x < 1.0));
    }
}

#[test]
fn agrees_with_mvc_on_a_convex_cages_faces() {
    let cage = shapes::icosahedron(1.0);
    let mut pts = Vec::new();
    for (t, &[a, b, c]) in cage.triangles().iter().enumerate() {
        let bary = [0.2 + 0.01 * t as f64, 0.3, 0.5 - 0.01 * t as f64];
        let p = cage.positions();
        pts.push(p[a as usize] * bary[0] + p[b as usize] * bary[1] + p[c as usize] * bary[2]);
    }
    let hc = hc_at(&cage, &pts, 16).unwrap();
    let mvc = match bind(
        CoordinateKind::MeanValue,
        &cage,
        &pts,
        &BindSettings::default(),
        &BindControl::default(),
    )
    .unwrap()
    {
        CageWeights::Vertex { weights, .. } => weights,
        CageWeights::Green(_) => unreachable!(),
    };
    for (i, w) in hc.iter().enumerate() {
        for (x, y) in w.iter().zip(mvc.row(i)) {
            assert!((x - y).abs() < 1e-9, "point {i}: hc {x} vs mvc {y}");
        }
    }
    // And continuously so: just inside a face, HC approaches the same values.
    let n = cage.triangle_normals()[0];
    let w_in = hc_at(&cage, &[pts[0] - n * 1e-6], 16).unwrap();
    let gap = w_in[0]
        .iter()
        .zip(mvc.row(0))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(gap < 1e-3, "jump {gap} next to the face");
}

#[test]
fn outside_points_are_named_in_a_typed_error() {
    let cage = shapes::cuboid(DVec3::ZERO, DVec3::ONE);
    let pts = [
        DVec3::splat(0.5),
        DVec3::splat(2.0),
        DVec3::new(0.5, 0.5, -0.1),
    ];
    match hc_at(&cage, &pts, 8) {
        Err(CoordError::OutsideCage { points, count, .. }) => {
            assert_eq!(points, vec![1, 2]);
            assert_eq!(count, 2);
        }
        other => panic!("expected OutsideCage, got {other:?}"),
    }
    let message = hc_at(&cage, &pts, 8).unwrap_err().to_string();
    assert!(
        message.contains("points 1, 2") && message.contains("use mvc or gc"),
        "{message}"
    );
}

#[test]
fn cancelled_bind_stops() {
    let cage = shapes::cuboid(DVec3::ZERO, DVec3::ONE);
    let control = BindControl::default();
    control.cancel();
    for kind in CoordinateKind::ALL {
        let r = bind(
            kind,
            &cage,
            &[DVec3::splat(0.5); 10],
            &BindSettings::default(),
            &control,
        );
        assert_eq!(r.unwrap_err(), CoordError::Cancelled);
    }
}

#[test]
fn continuous_where_two_faces_are_equally_near() {
    // (0.5, -0.5, 0) is 0.1 from both the x = 0.6 and the y = -0.6 faces, inside the blend band
    // towards the cage values: a single closest point would jump there (a regression).
    let cage = shapes::cuboid(DVec3::new(-0.6, -0.6, -0.1), DVec3::new(0.6, 0.6, 2.0));
    let p = DVec3::new(0.5, -0.5, 0.0);
    let nudged = [
        p,
        p + DVec3::new(1e-12, 0.0, 0.0),
        p + DVec3::new(0.0, -1e-12, 0.0),
        p + DVec3::splat(1e-9),
    ];
    let w = hc_at(&cage, &nudged, 16).unwrap();
    for other in &w[1..] {
        let gap = other
            .iter()
            .zip(&w[0])
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(gap < 1e-7, "jump {gap}");
    }
}

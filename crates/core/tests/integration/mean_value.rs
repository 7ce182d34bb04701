//! Properties of Mean Value Coordinates: partition of unity, linear precision, interpolation on
//! faces, and finite smooth values next to faces, edges and vertices.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use crate::common;

use common::*;
use glam::DVec3;
use proptest::prelude::*;
use starcages_core::cage::shapes;
use starcages_core::coords::MVC_RANGE_IN_DIAGONALS;
use starcages_core::{
    BindControl, BindSettings, Cage, CageWeights, CoordError, CoordinateKind, bind,
};

fn mvc(cage: &Cage, points: &[DVec3]) -> Vec<Vec<f64>> {
    match bind(
        CoordinateKind::MeanValue,
        cage,
        points,
        &BindSettings::default(),
        &BindControl::default(),
    ) {
        Ok(CageWeights::Vertex { weights, .. }) => {
            (0..points.len()).map(|i| weights.row(i).to_vec()).collect()
        }
        other => panic!("unexpected {other:?}"),
    }
}

fn assert_reproduces(cage: &Cage, p: DVec3, w: &[f64], tol: f64) {
    let sum: f64 = w.iter().sum();
    assert!((sum - 1.0).abs() < tol, "partition of unity: {sum}");
    let q: DVec3 = w.iter().zip(cage.positions()).map(|(&w, &v)| w * v).sum();
    assert!(
        (q - p).length() < tol * (1.0 + p.length()),
        "linear precision: {q} vs {p}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn partition_of_unity_and_linear_precision_convex(cage in convex_cage(), s in seeds(40), out in prop::array::uniform3(2.5f64..6.0)) {
        let pts = interior_points(&cage, &s);
        // A few exterior points too: MVC is defined everywhere.
        let outside = [cage.positions()[0] + DVec3::from_array(out), cage.positions()[3] * 3.0 - DVec3::from_array(out)];
        for (p, w) in pts.iter().zip(mvc(&cage, &pts)) {
            assert_reproduces(&cage, *p, &w, 1e-9);
        }
        // Outside, Σ w cancels between faces seen from both sides: the documented bound,
        // 1e-6 of the distance (docs/math.md, "Mean value coordinates far from the cage").
        for (p, w) in outside.iter().zip(mvc(&cage, &outside)) {
            assert_reproduces(&cage, *p, &w, 1e-6);
        }
    }

    #[test]
    fn partition_of_unity_and_linear_precision_star(cage in star_cage(), s in seeds(40)) {
        let pts = interior_points(&cage, &s);
        for (p, w) in pts.iter().zip(mvc(&cage, &pts)) {
            assert_reproduces(&cage, *p, &w, 1e-9);
        }
    }

    /// Anywhere within the documented range (from one cage diagonal to the limit, log-uniform),
    /// MVC reproduce a point to 1e-6 of its distance from the cage, on convex and on
    /// star-shaped cages.
    #[test]
    fn accurate_up_to_the_documented_range(
        convex in convex_cage(),
        star in star_cage(),
        direction in prop::array::uniform3(-1.0f64..1.0),
        log_reach in -3.0f64..0.0,
    ) {
        let direction = DVec3::from_array(direction);
        prop_assume!(direction.length() > 0.1);
        for cage in [&convex, &star] {
            let (lo, hi) = cage.bounds();
            let centre = 0.5 * (lo + hi);
            let distance = 10f64.powf(log_reach) * MVC_RANGE_IN_DIAGONALS * cage.diagonal();
            let p = centre + direction.normalize() * distance;
            let w = &mvc(cage, &[p])[0];
            let q: DVec3 = w.iter().zip(cage.positions()).map(|(&w, &v)| w * v).sum();
            prop_assert!((q - p).length() <= 1e-6 * distance, "{q} vs {p}: {:e} of the distance", (q - p).length() / distance);
            let sum: f64 = w.iter().sum();
            prop_assert!((sum - 1.0).abs() < 1e-9, "partition of unity: {sum}");
        }
    }

    #[test]
    fn interpolates_on_faces(cage in star_cage(), t in 0usize..80, b in prop::array::uniform2(0.01f64..1.0)) {
        let (u, v) = if b[0] + b[1] < 1.0 { (b[0], b[1]) } else { (1.0 - b[0], 1.0 - b[1]) };
        let bary = [1.0 - u - v, u, v];
        let tri = cage.triangles()[t];
        let p: DVec3 = (0..3).map(|k| cage.positions()[tri[k] as usize] * bary[k]).sum();
        let w = &mvc(&cage, &[p])[0];
        for (i, wi) in w.iter().enumerate() {
            let expected: f64 = (0..3).filter(|&k| tri[k] as usize == i).map(|k| bary[k]).sum();
            prop_assert!((wi - expected).abs() < 1e-9, "vertex {i}: {wi} vs {expected}");
        }
    }
}

#[test]
fn finite_and_smooth_next_to_face_edge_and_vertex() {
    let cage = shapes::cuboid(DVec3::ZERO, DVec3::ONE);
    // On the bottom face (z = 0), on the edge y = z = 0, and at the vertex 0.
    let sites = [
        DVec3::new(0.3, 0.6, 0.0),
        DVec3::new(0.3, 0.0, 0.0),
        DVec3::ZERO,
    ];
    for site in sites {
        let on = mvc(&cage, &[site])[0].clone();
        assert_reproduces(&cage, site, &on, 1e-12);
        let inward = DVec3::new(0.2, 0.3, 0.4).normalize();
        let mut previous = on.clone();
        for exponent in [10, 9, 8, 7, 6] {
            let delta = 10f64.powi(-exponent);
            for p in [site + inward * delta, site - inward * delta] {
                let w = &mvc(&cage, &[p])[0];
                assert!(w.iter().all(|x| x.is_finite()), "non-finite at {p}");
                assert_reproduces(&cage, p, w, 1e-8);
                let gap = w
                    .iter()
                    .zip(&on)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                // C0 and no blow-up: the change is bounded by a few times the distance.
                assert!(
                    gap < 20.0 * delta + 1e-7,
                    "jump {gap} at distance {delta} from {site}"
                );
            }
            let w = &mvc(&cage, &[site + inward * delta])[0];
            let step = w
                .iter()
                .zip(&previous)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(
                step < 20.0 * delta + 1e-7,
                "not smooth towards {site}: step {step}"
            );
            previous = w.clone();
        }
    }
}

#[test]
fn point_on_vertex_and_edge_are_exact() {
    let cage = shapes::l_prism();
    for (i, &v) in cage.positions().iter().enumerate() {
        let w = &mvc(&cage, &[v])[0];
        assert_eq!(w[i], 1.0);
        assert!(w.iter().enumerate().all(|(j, x)| j == i || *x == 0.0));
    }
    let [a, b] = cage.edges()[0];
    let p = cage.positions()[a as usize] * 0.25 + cage.positions()[b as usize] * 0.75;
    let w = &mvc(&cage, &[p])[0];
    assert!(
        (w[a as usize] - 0.25).abs() < 1e-12 && (w[b as usize] - 0.75).abs() < 1e-12,
        "{w:?}"
    );
}

#[test]
fn negative_somewhere_in_non_convex_cages() {
    for cage in [shapes::l_prism(), shapes::star_prism()] {
        let (lo, hi) = cage.bounds();
        let mut points = Vec::new();
        for i in 1..12 {
            for j in 1..12 {
                let p = lo + (hi - lo) * DVec3::new(i as f64 / 12.0, j as f64 / 12.0, 0.5);
                if cage.winding_number(p) > 0.5 {
                    points.push(p);
                }
            }
        }
        let min = mvc(&cage, &points)
            .iter()
            .flatten()
            .copied()
            .fold(f64::INFINITY, f64::min);
        assert!(
            min < 0.0,
            "MVC expected negative inside a non-convex cage, min {min}"
        );
    }
}

#[test]
fn point_on_the_diagonal_of_a_fanned_quad_interpolates_linearly() {
    // The face x = 1 of the unit cube is fanned into two triangles sharing the diagonal from
    // (1,0,0) to (1,1,1); on it, MVC are linear interpolation of the diagonal's ends (a
    // regression: cos(θ/2) from sqrt(1 − sin²) missed the θ = π case there).
    let cage = shapes::cuboid(DVec3::ZERO, DVec3::ONE);
    let p = DVec3::new(1.0, 0.3, 0.3);
    let w = &mvc(
        &cage,
        &[p, DVec3::splat(0.5), DVec3::splat(0.4), DVec3::splat(0.6)],
    )[0];
    assert!(
        (w[1] - 0.7).abs() < 1e-12 && (w[7] - 0.3).abs() < 1e-12,
        "{w:?}"
    );
    assert_reproduces(&cage, p, w, 1e-12);
}

#[test]
fn points_beyond_the_range_are_refused_and_green_coordinates_stay_accurate() {
    let cage = shapes::star_prism();
    let (lo, hi) = cage.bounds();
    let centre = 0.5 * (lo + hi);
    let far = centre + DVec3::new(0.3, -0.5, 0.81).normalize() * 1e4 * cage.diagonal();
    let near = centre + DVec3::X * 2.0 * cage.diagonal();
    let result = bind(
        CoordinateKind::MeanValue,
        &cage,
        &[near, far],
        &BindSettings::default(),
        &BindControl::default(),
    );
    match result {
        Err(e @ CoordError::TooFarForMeanValue { .. }) => {
            assert!(matches!(&e, CoordError::TooFarForMeanValue { points, .. } if points == &[1]));
            let message = e.to_string();
            assert!(message.contains("use gc"), "{message}");
        }
        other => panic!("a point 1e4 diagonals away was not refused: {other:?}"),
    }
    // Green coordinates reproduce the same far point to 1e-6 of its distance.
    let gc = bind(
        CoordinateKind::Green,
        &cage,
        &[far],
        &BindSettings::default(),
        &BindControl::default(),
    )
    .unwrap();
    let q = gc.deform(&cage, cage.positions()).unwrap()[0];
    assert!(
        (q - far).length() <= 1e-6 * (far - centre).length(),
        "{q} vs {far}"
    );
}

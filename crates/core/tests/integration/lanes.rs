//! The four-lane kernels agree with one-point evaluation, also when a lane group mixes regular
//! points with points on vertices, edges, faces and face planes (which fall back to the scalar
//! routine) and with points outside the cage.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use glam::DVec3;
use starcages_core::cage::shapes;
use starcages_core::{BindControl, BindSettings, Cage, CageWeights, CoordinateKind, bind};

fn rows(kind: CoordinateKind, cage: &Cage, points: &[DVec3]) -> Vec<Vec<f64>> {
    match bind(
        kind,
        cage,
        points,
        &BindSettings::default(),
        &BindControl::default(),
    )
    .expect("bind")
    {
        CageWeights::Vertex { weights, .. } => {
            (0..points.len()).map(|i| weights.row(i).to_vec()).collect()
        }
        CageWeights::Green(g) => (0..points.len())
            .map(|i| g.phi_row(i).iter().chain(g.psi_row(i)).copied().collect())
            .collect(),
    }
}

#[test]
fn mixed_lane_groups_match_single_points() {
    let cage = shapes::cuboid(DVec3::ZERO, DVec3::ONE);
    let points = vec![
        DVec3::new(0.3, 0.4, 0.5),  // regular
        DVec3::ZERO,                // on a vertex
        DVec3::new(0.2, 0.7, 0.9),  // regular
        DVec3::new(0.5, 0.0, 0.0),  // on an edge
        DVec3::new(0.25, 0.5, 0.0), // on a face
        DVec3::new(2.0, 0.5, 0.0),  // outside, in a face's plane
        DVec3::new(1.5, 1.2, -0.3), // outside
        DVec3::new(0.6, 0.1, 0.2),  // regular
        DVec3::new(0.1, 0.9, 0.4),  // regular (a partial last group)
    ];
    for kind in [CoordinateKind::MeanValue, CoordinateKind::Green] {
        let batch = rows(kind, &cage, &points);
        for (i, p) in points.iter().enumerate() {
            let single = rows(kind, &cage, &[*p]);
            for (a, b) in batch[i].iter().zip(&single[0]) {
                assert!((a - b).abs() < 1e-12, "{kind} point {i}: {a} vs {b}");
            }
        }
    }
}

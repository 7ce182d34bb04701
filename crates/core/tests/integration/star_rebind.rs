//! Partial re-binds (changed leaves, rest edits) against full binds, the bind's work count and
//! its refusal of borders beyond reach.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use crate::star::{control, grid_scene};
use glam::DVec3;
use starcages_core::coords::CoordinateKind;
use starcages_core::generate::demo::{box_mesh, demo_scene};
use starcages_core::scene::JoinPolicy;
use starcages_core::star::StarBinding;

/// Re-binding only the cages whose kind or h changed gives the same deformation as binding
/// everything again.
#[test]
fn rebinding_changed_leaves_matches_a_full_bind() {
    let mut scene = demo_scene("egg", 0.3).unwrap();
    let old = StarBinding::bind_scene(&scene, &control()).unwrap();
    scene.cages.leaves[0].h = Some(0.2);
    scene.cages.leaves[5].kind = CoordinateKind::Green;
    scene.cages.leaves[6].kind = CoordinateKind::MeanValue;
    let partial = old.rebind_leaves(&scene, &[0, 5, 6], &control()).unwrap();
    let full = StarBinding::bind_scene(&scene, &control()).unwrap();
    let pose = &scene.poses["dent"];
    let a = partial.deform(&scene.cages.vertices, pose);
    let b = full.deform(&scene.cages.vertices, pose);
    let worst = a
        .iter()
        .zip(&b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f32::max);
    // Mean value join cages and MVC/GC leaves: each point's coordinates are the same f64 work
    // in both binds, so the rows, and the frames, are equal to the bit.
    assert!(worst == 0.0, "{worst}");
    assert_eq!(partial.boundary_weight, full.boundary_weight);
    assert_eq!(partial.cage_of, full.cage_of);
    // Untouched cages keep their rows bit for bit.
    let untouched = (0..old.cage_of.len())
        .find(|&i| ![0, 5, 6].contains(&(old.cage_of[i] as usize)))
        .unwrap();
    assert_eq!(
        partial.operator.row(untouched).collect::<Vec<_>>(),
        old.operator.row(untouched).collect::<Vec<_>>()
    );
}

/// Largest difference between two bindings' rows (as sparse maps over the same columns).
fn worst_row_difference(a: &StarBinding, b: &StarBinding) -> f32 {
    assert_eq!(a.operator.row_count(), b.operator.row_count());
    (0..a.operator.row_count())
        .map(|i| {
            let green = |op: &starcages_core::star::StarOperator, c: u32| {
                // Green columns are numbered per binding: compare them by their triangle.
                let n = op.parts().0 as u32;
                if c < n {
                    (c, [u32::MAX; 3])
                } else {
                    (u32::MAX, op.green_dofs().triangles()[(c - n) as usize])
                }
            };
            let mut keyed: std::collections::BTreeMap<(u32, [u32; 3]), f32> = Default::default();
            for (c, w) in a.operator.row(i) {
                *keyed.entry(green(&a.operator, c)).or_default() += w;
            }
            for (c, w) in b.operator.row(i) {
                *keyed.entry(green(&b.operator, c)).or_default() -= w;
            }
            keyed.values().map(|d| d.abs()).fold(0.0, f32::max)
        })
        .fold(0.0, f32::max)
}

#[test]
fn a_rest_edit_rebinds_only_nearby_rows_and_equals_a_full_bind() {
    let mut grid = grid_scene(
        [3, 3, 1],
        &[CoordinateKind::MeanValue, CoordinateKind::Green],
        JoinPolicy::Auto,
    );
    grid.settings.outside = starcages_core::scene::OutsidePolicy::Nearest;
    let egg = demo_scene("egg", 0.3).unwrap();
    // (scene, moved vertex, its new rest position): an inner grid vertex pushed sideways (the
    // join cages around it become concave: HC under the automatic policy), and an outer vertex
    // of the egg pulled out.
    let inner = grid
        .cages
        .vertices
        .iter()
        .position(|p| *p == DVec3::new(1.0, 1.0, 0.0))
        .unwrap() as u32;
    // (…, whether some rows are far enough to be kept: the egg's few cages all read vertex 0.)
    let cases = [
        (grid, inner, DVec3::new(1.2, 0.9, 0.0), true),
        (egg.clone(), 0, egg.cages.vertices[0] * 1.1, false),
    ];
    for (before, vertex, to, local) in cases {
        let old = StarBinding::bind_scene(&before, &control()).unwrap();
        let mut after = before.clone();
        after.cages.vertices[vertex as usize] = to;
        after.pose = after.cages.vertices.clone();
        after.poses.clear();
        let rows = old.rows_affected_by_rest_edit(&after, &[vertex]).unwrap();
        let incremental = old.rebind_rest_edit(&after, &[vertex], &control()).unwrap();
        let full = StarBinding::bind_scene(&after, &control()).unwrap();
        assert!(
            !local || rows.len() < old.operator.row_count(),
            "vertex {vertex}: every row re-bound"
        );
        assert_eq!(incremental.cage_of, full.cage_of);
        assert_eq!(incremental.boundary_weight, full.boundary_weight);
        let worst = worst_row_difference(&incremental, &full);
        // Within round-off, not to the bit: the grid's concave join cages are harmonic, whose
        // solves sum in parallel (rayon's split points vary); the binds agree exactly only
        // through the solve cache.
        assert!(worst <= 1e-6, "vertex {vertex}: rows differ by {worst}");
        // The spliced join weights and rest offsets are the full bind's too.
        assert_eq!(
            incremental.join_weights.row_start,
            full.join_weights.row_start
        );
        assert_eq!(incremental.join_weights.vertex, full.join_weights.vertex);
        for (a, b) in incremental
            .operator
            .rest_offsets()
            .iter()
            .zip(full.operator.rest_offsets())
        {
            assert!((*a - *b).length() <= 1e-5, "rest offsets {a} and {b}");
        }
        // Rows outside the re-bound set kept their weights bit for bit.
        for kept in (0..old.operator.row_count()).filter(|i| rows.binary_search(i).is_err()) {
            assert_eq!(
                incremental.operator.row(kept).collect::<Vec<_>>(),
                old.operator.row(kept).collect::<Vec<_>>()
            );
        }
        // Negative control: without re-binding, the old rows differ from the full bind.
        assert!(worst_row_difference(&old, &full) > 1e-4);
    }
}

/// `BindStats::kernel_pairs` counts the closed-form kernels' work: for one MVC cage it is
/// exactly points × triangles; *Cages add the join cages of the blended points on top of each
/// point's own cage, and a partial re-bind counts only what it evaluates again.
#[test]
fn kernel_pairs_count_the_coordinate_work() {
    let scene = demo_scene("bar", 0.3).unwrap();
    let points = scene.mesh.welded_positions().len() as u64;
    let single = starcages_core::star::single_cage_scene(&scene, CoordinateKind::MeanValue);
    let triangles: u64 = single.cages.leaves[0]
        .faces
        .iter()
        .map(|f| f.len() as u64 - 2)
        .sum();
    let one = StarBinding::bind_scene(&single, &control()).unwrap();
    assert_eq!(one.stats.kernel_pairs, points * triangles);
    let star = StarBinding::bind_scene(&scene, &control()).unwrap();
    // Each point in its own box (12 triangles), and more for the blended ones.
    assert!(
        star.stats.kernel_pairs > points * 12,
        "{}",
        star.stats.kernel_pairs
    );
    let mut changed = scene.clone();
    changed.cages.leaves[0].h = Some(0.3);
    let partial = star.rebind_leaves(&changed, &[0], &control()).unwrap();
    assert!(partial.stats.kernel_pairs > 0);
    assert!(partial.stats.kernel_pairs < star.stats.kernel_pairs);
}

/// A border subdivided until eq. 8's work is out of reach (two boxes subdivided six times:
/// 3,969 vertices inside their shared face, each weighed against every other over 81,920
/// faces) is refused at once, naming the border and saying what to do.
#[test]
fn a_bind_whose_border_is_subdivided_beyond_reach_is_refused_naming_it() {
    use starcages_core::rig::{RigOp, apply_rig_op};
    let mut scene = grid_scene([2, 1, 1], &[CoordinateKind::MeanValue], JoinPolicy::Mvc);
    scene.mesh = box_mesh(DVec3::splat(0.2), DVec3::new(1.8, 0.8, 0.8), [2, 1, 1]);
    for _ in 0..6 {
        apply_rig_op(&mut scene, &RigOp::Subdivide).unwrap();
    }
    let error = StarBinding::bind_scene(&scene, &control())
        .unwrap_err()
        .to_string();
    for expected in [
        "'c0' and 'c1'",
        "3969 vertices inside it",
        "fewer subdivisions",
    ] {
        assert!(error.contains(expected), "{error}");
    }
}

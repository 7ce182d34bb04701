//! *Cages deformation properties on the demo scenes and on grids with mixed kinds: identity,
//! linear precision (similarity with Green cages), interpolation on free faces, C0 and C1
//! across borders (where plain piecewise T is only C0), locality, incremental = full, and the
//! f32 operator against f64 evaluation.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use glam::{DMat3, DQuat, DVec3};
use starcages_core::BindControl;
use starcages_core::cage::shapes::box_faces;
use starcages_core::coords::{BindSettings, CoordinateKind, bind};
use starcages_core::generate::demo::{box_mesh, demo_scene};
use starcages_core::scene::{
    CageSet, JoinPolicy, LeafCage, LocalCage, MeshSource, Scene, SceneSettings,
};
use starcages_core::star::{StarBinding, evaluate_points};

pub(crate) fn control() -> BindControl {
    BindControl::default()
}

/// A row of `n` unit box cages along x with the given kinds, around a tessellated bar.
fn row_scene(kinds: &[CoordinateKind], policy: JoinPolicy) -> Scene {
    let n = kinds.len();
    let mut set = CageSet::default();
    for z in [-0.6, 0.6] {
        for y in [-0.6, 0.6] {
            for i in 0..=n {
                set.vertices
                    .push(DVec3::new(i as f64 - n as f64 / 2.0, y, z));
            }
        }
    }
    let row = (n + 1) as u32;
    for (i, &kind) in kinds.iter().enumerate() {
        let corners = std::array::from_fn(|c| {
            let c = c as u32;
            i as u32 + (c & 1) + row * ((c >> 1) & 1) + 2 * row * (c >> 2)
        });
        set.leaves.push(LeafCage {
            name: format!("c{i}"),
            kind,
            h: None,
            border_h: Default::default(),
            faces: box_faces(corners),
        });
    }
    let half = n as f64 / 2.0 - 0.2;
    let mesh = box_mesh(
        DVec3::new(-half, -0.4, -0.4),
        DVec3::new(half, 0.4, 0.4),
        [8 * n as u32, 4, 4],
    );
    let mut settings = SceneSettings {
        join_coordinates: policy,
        ..Default::default()
    };
    settings.harmonic.resolution = 24; // enough for the properties, fast in tests
    Scene::new(MeshSource::Embedded, mesh, set, settings)
}

/// A smooth non-affine pose.
fn wavy(p: DVec3) -> DVec3 {
    p + DVec3::new(
        0.1 * (1.3 * p.y + 0.7 * p.z).sin(),
        0.15 * (0.9 * p.x).sin() * p.z,
        0.2 * (p.x * p.y).cos(),
    )
}

#[test]
fn rest_pose_is_the_identity() {
    for name in ["bar", "egg", "bumpy", "prism"] {
        let scene = demo_scene(name, 0.3).unwrap();
        let binding = StarBinding::bind_scene(&scene, &control()).unwrap();
        let out = binding.deform(&scene.cages.vertices, &scene.cages.vertices);
        let diag = (scene.mesh.bounds().1 - scene.mesh.bounds().0).length();
        for (a, b) in out.iter().zip(scene.mesh.welded_positions()) {
            assert!(
                (a.as_dvec3() - *b).length() < 1e-5 * diag,
                "{name}: {a} vs {b}"
            );
        }
    }
}

/// The rest pose gives every bound point back to f32 precision under every setting: each leaf
/// kind, each join policy, several h, an automatic grid's concave join cages (the displacement
/// form, docs/math.md). Harmonic grids alone moved points by about 1e-3 of the diagonal.
#[test]
fn the_rest_pose_gives_the_mesh_back_under_every_setting() {
    let mut scene = egg_in_a_grid();
    scene.settings.harmonic.resolution = 16;
    let diag = (scene.mesh.bounds().1 - scene.mesh.bounds().0).length();
    let kinds = [
        CoordinateKind::MeanValue,
        CoordinateKind::Harmonic,
        CoordinateKind::Green,
    ];
    for policy in [
        JoinPolicy::Mvc,
        JoinPolicy::Auto,
        JoinPolicy::Hc,
        JoinPolicy::Gc,
    ] {
        for (k, h) in [(0, 0.2), (1, 0.5), (2, 1.0), (3, 0.5)] {
            let mut scene = scene.clone();
            scene.settings.join_coordinates = policy;
            scene.settings.default_h = h;
            for (c, leaf) in scene.cages.leaves.iter_mut().enumerate() {
                // One kind for all (k < 3), or the three mixed.
                leaf.kind = kinds[if k < 3 { k } else { c % 3 }];
            }
            let worst = rigid_error(&scene, DQuat::IDENTITY, diag);
            assert!(worst < 2e-6, "{policy:?}, kinds {k}, h {h}: {worst:e}");
        }
    }
}

/// Under default settings a rigid turn of the whole rig turns the mesh rigidly (1e-5 of the
/// diagonal): join cages default to mean value coordinates, which reproduce affine maps. With
/// the automatic policy the harmonic join cages' grid error turns with the rig but the rest
/// offset does not: the negative control.
#[test]
fn a_rigid_turn_of_the_rig_is_rigid_under_the_defaults() {
    let mut scene = egg_in_a_grid();
    scene.settings = SceneSettings::default();
    assert_eq!(scene.settings.join_coordinates, JoinPolicy::Mvc);
    let diag = (scene.mesh.bounds().1 - scene.mesh.bounds().0).length();
    let turn = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.6);
    let worst = rigid_error(&scene, turn, diag);
    assert!(worst < 1e-5, "{worst:e}");
    scene.settings.join_coordinates = JoinPolicy::Auto;
    scene.settings.harmonic.resolution = 16;
    let worst = rigid_error(&scene, turn, diag);
    assert!(worst > 1e-5, "{worst:e}");
}

/// The egg demo's mesh in a 3×3×3 automatic grid (concave join cages everywhere).
fn egg_in_a_grid() -> Scene {
    let mut scene = demo_scene("egg", 0.3).unwrap();
    scene.cages = starcages_core::generate::autocage(
        &scene.mesh,
        &starcages_core::generate::AutocageOptions {
            grid: [3, 3, 3],
            ..Default::default()
        },
    );
    scene
}

/// The largest distance, over the diagonal, between the mesh deformed by the rig turned by
/// `turn` about the origin and the mesh turned alike.
fn rigid_error(scene: &Scene, turn: DQuat, diag: f64) -> f64 {
    let binding = StarBinding::bind_scene(scene, &control()).unwrap();
    let posed: Vec<DVec3> = scene.cages.vertices.iter().map(|&v| turn * v).collect();
    let out = binding.deform(&scene.cages.vertices, &posed);
    out.iter()
        .zip(scene.mesh.welded_positions())
        .map(|(a, b)| (a.as_dvec3() - turn * *b).length() / diag)
        .fold(0.0, f64::max)
}

#[test]
fn affine_maps_are_reproduced_with_every_join_policy() {
    let map = |p: DVec3| {
        DMat3::from_cols_array(&[1.1, 0.2, -0.1, 0.05, 0.9, 0.3, -0.2, 0.1, 1.2]) * p
            + DVec3::new(0.3, -0.2, 0.5)
    };
    for policy in [JoinPolicy::Auto, JoinPolicy::Mvc, JoinPolicy::Hc] {
        let kinds = [
            CoordinateKind::MeanValue,
            CoordinateKind::Harmonic,
            CoordinateKind::MeanValue,
            CoordinateKind::MeanValue,
        ];
        for scene in [
            row_scene(&kinds, policy),
            demo_scene("egg", 0.3)
                .map(|mut s| {
                    s.cages
                        .leaves
                        .iter_mut()
                        .for_each(|c| c.kind = CoordinateKind::MeanValue);
                    s.settings.join_coordinates = policy;
                    s.settings.harmonic.resolution = 24;
                    s
                })
                .unwrap(),
        ] {
            let posed: Vec<DVec3> = scene.cages.vertices.iter().map(|&p| map(p)).collect();
            let points = scene.mesh.welded_positions();
            let out = evaluate_points(&scene, points, &posed, &control()).unwrap();
            // HC is exact away from the grid cells the cage cuts and O(h) inside them: allow a
            // tenth of a cell of the whole set's grid (join cages are smaller, so finer).
            let uses_hc = policy != JoinPolicy::Mvc
                || scene
                    .cages
                    .leaves
                    .iter()
                    .any(|c| c.kind == CoordinateKind::Harmonic);
            let (lo, hi) = starcages_core::cage::bounds_of(&scene.cages.vertices);
            let cell = (hi - lo).max_element() / f64::from(scene.settings.harmonic.resolution);
            let tolerance = if uses_hc { 0.1 * cell } else { 1e-9 };
            let worst = points
                .iter()
                .zip(&out)
                .map(|(p, q)| (map(*p) - *q).length())
                .fold(0.0, f64::max);
            assert!(worst < tolerance, "{policy:?}: affine error {worst}");
        }
    }
}

#[test]
fn similarities_are_reproduced_with_green_cages_in_the_mix() {
    let rotation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
    let map = |p: DVec3| rotation * p * 1.3 + DVec3::new(-0.4, 0.2, 0.1);
    for policy in [JoinPolicy::Mvc, JoinPolicy::Gc] {
        let scene = row_scene(
            &[
                CoordinateKind::Green,
                CoordinateKind::MeanValue,
                CoordinateKind::Green,
            ],
            policy,
        );
        let posed: Vec<DVec3> = scene.cages.vertices.iter().map(|&p| map(p)).collect();
        let points = scene.mesh.welded_positions();
        let out = evaluate_points(&scene, points, &posed, &control()).unwrap();
        let worst = points
            .iter()
            .zip(&out)
            .map(|(p, q)| (map(*p) - *q).length())
            .fold(0.0, f64::max);
        assert!(worst < 1e-8, "{policy:?}: similarity error {worst}");
    }
}

fn plain_t(scene: &Scene, cage: usize, p: DVec3, posed: &[DVec3]) -> DVec3 {
    let local = LocalCage::new(&scene.cages.vertices, &scene.cages.leaves[cage].faces).unwrap();
    let w = bind(
        scene.cages.leaves[cage].kind,
        &local.cage,
        &[p],
        &BindSettings::default(),
        &control(),
    )
    .unwrap();
    let local_posed: Vec<DVec3> = local.global.iter().map(|&g| posed[g as usize]).collect();
    w.deform(&local.cage, &local_posed).unwrap()[0]
}

/// Jumps of the one-sided difference quotients across the border x = x0, at step `delta`.
fn derivative_jump(f: impl Fn(DVec3) -> DVec3, x0: f64, y: f64, z: f64, delta: f64) -> f64 {
    let at = |x: f64| f(DVec3::new(x, y, z));
    let left = (at(x0) - at(x0 - delta)) / delta;
    let right = (at(x0 + delta) - at(x0)) / delta;
    (right - left).length()
}

#[test]
fn c1_across_borders_where_plain_t_is_only_c0() {
    for kinds in [
        [CoordinateKind::MeanValue, CoordinateKind::MeanValue],
        [CoordinateKind::Green, CoordinateKind::MeanValue],
        [CoordinateKind::Harmonic, CoordinateKind::MeanValue],
    ] {
        let scene = row_scene(&kinds, JoinPolicy::Mvc);
        let posed: Vec<DVec3> = scene.cages.vertices.iter().map(|&p| wavy(p)).collect();
        let (y, z) = (0.13, -0.21);
        let star = |p: DVec3| evaluate_points(&scene, &[p], &posed, &control()).unwrap()[0];
        // C0: both sides meet.
        let e = 1e-9;
        let gap = (star(DVec3::new(-e, y, z)) - star(DVec3::new(e, y, z))).length();
        assert!(gap < 1e-6, "{kinds:?}: C0 gap {gap}");
        // C1: the jump of the difference quotients shrinks linearly with the step.
        let (j1, j2) = (
            derivative_jump(star, 0.0, y, z, 1e-2),
            derivative_jump(star, 0.0, y, z, 1e-3),
        );
        assert!(
            j2 < 0.2 * j1 + 1e-5,
            "{kinds:?}: jump {j1} at 1e-2, {j2} at 1e-3"
        );
        // Plain piecewise T keeps a constant jump.
        let plain = |p: DVec3| plain_t(&scene, if p.x < 0.0 { 0 } else { 1 }, p, &posed);
        let (p1, p2) = (
            derivative_jump(plain, 0.0, y, z, 1e-2),
            derivative_jump(plain, 0.0, y, z, 1e-3),
        );
        assert!(
            p1 > 1e-2 && p2 > 0.5 * p1,
            "{kinds:?}: plain T jump {p1} -> {p2}"
        );
        assert!(j2 < 0.1 * p2, "{kinds:?}: *Cages jump {j2} vs plain {p2}");
    }
}

mod random_h {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(8))]

        /// C0 and C1 across a border whatever h each side has and whatever h either side gives
        /// that one border (docs/math.md's per-border h row): the jump of the difference
        /// quotients shrinks with the step, at a random point of the shared face.
        #[test]
        fn c1_across_a_border_with_random_per_side_and_per_border_h(
            h in (0.1f64..1.0, 0.1f64..1.0),
            border in (prop::option::of(0.1f64..1.0), prop::option::of(0.1f64..1.0)),
            at in (-0.35f64..0.35, -0.35f64..0.35),
        ) {
            let mut scene = row_scene(
                &[CoordinateKind::MeanValue, CoordinateKind::MeanValue],
                JoinPolicy::Mvc,
            );
            scene.cages.leaves[0].h = Some(h.0);
            scene.cages.leaves[1].h = Some(h.1);
            if let Some(hb) = border.0 {
                scene.cages.leaves[0].border_h.insert("c1".into(), hb);
            }
            if let Some(hb) = border.1 {
                scene.cages.leaves[1].border_h.insert("c0".into(), hb);
            }
            let posed: Vec<DVec3> = scene.cages.vertices.iter().map(|&p| wavy(p)).collect();
            let (y, z) = at;
            let star = |p: DVec3| evaluate_points(&scene, &[p], &posed, &control()).unwrap()[0];
            let e = 1e-9;
            let gap = (star(DVec3::new(-e, y, z)) - star(DVec3::new(e, y, z))).length();
            prop_assert!(gap < 1e-6, "C0 gap {gap}");
            let (j1, j2) = (
                derivative_jump(star, 0.0, y, z, 1e-2),
                derivative_jump(star, 0.0, y, z, 1e-3),
            );
            prop_assert!(j2 < 0.2 * j1 + 1e-5, "jump {j1} at 1e-2, {j2} at 1e-3");
        }
    }
}

#[test]
fn free_faces_are_interpolated_and_borders_get_b_zero() {
    let scene = row_scene(
        &[CoordinateKind::MeanValue, CoordinateKind::MeanValue],
        JoinPolicy::Mvc,
    );
    let posed: Vec<DVec3> = scene.cages.vertices.iter().map(|&p| wavy(p)).collect();
    // The left end face x = -1 has no boundary vertex: S = T interpolates it.
    let on_free = DVec3::new(-1.0, 0.2, -0.3);
    let s = evaluate_points(&scene, &[on_free], &posed, &control()).unwrap()[0];
    let t = plain_t(&scene, 0, on_free, &posed);
    assert!((s - t).length() < 1e-9, "{s} vs {t}");
    // b = f_h(1 − Σ_{v ∈ B} w(v, p)); along x the border weights sum to x + 1 in the left cube,
    // so b = 1 up to x = -0.5 (h = 0.5) and blends between there and the border.
    let binding = StarBinding::bind_points(
        &scene,
        &[
            on_free,
            DVec3::new(0.0, 0.1, 0.2),
            DVec3::new(-0.2, 0.0, 0.0),
        ],
        &control(),
    )
    .unwrap();
    assert_eq!(binding.boundary_weight[0], 1.0);
    assert_eq!(binding.boundary_weight[1], 0.0);
    assert!(binding.boundary_weight[2] > 0.0 && binding.boundary_weight[2] < 1.0);
    // W_n (eq. 4) is kept where b < 1: non-negative over border vertices, summing to 1.
    let joins = &binding.join_weights;
    assert_eq!(joins.row_start[1], 0, "b = 1: no join weights");
    let border: Vec<u32> = (0..scene.cages.vertices.len() as u32)
        .filter(|&v| scene.cages.vertices[v as usize].x.abs() < 1e-12)
        .collect();
    for p in [1, 2] {
        let entries = joins.row_start[p] as usize..joins.row_start[p + 1] as usize;
        assert!(!entries.is_empty());
        let total: f32 = entries.clone().map(|k| joins.weight[k]).sum();
        assert!((total - 1.0).abs() < 1e-5, "{total}");
        assert!(
            entries
                .clone()
                .all(|k| joins.weight[k] >= 0.0 && border.contains(&joins.vertex[k]))
        );
    }
    let of_first = joins.of_vertex(border[0]);
    assert_eq!(of_first.len(), 3);
    assert_eq!(of_first[0], 0.0);
}

#[test]
fn moving_an_outer_vertex_of_the_first_cage_moves_nothing_in_the_third_and_fourth() {
    let kinds = [CoordinateKind::MeanValue; 4];
    let scene = row_scene(&kinds, JoinPolicy::Mvc);
    let binding = StarBinding::bind_scene(&scene, &control()).unwrap();
    let rest = &scene.cages.vertices;
    let before = binding.deform(rest, rest);
    let mut posed = rest.clone();
    posed[0] += DVec3::new(-0.3, 0.2, 0.1); // an outer corner of c0 (x = -2)
    let after = binding.deform(rest, &posed);
    let mut moved_somewhere = false;
    for (i, (a, b)) in before.iter().zip(&after).enumerate() {
        if binding.cage_of[i] >= 2 {
            assert_eq!(a, b, "vertex {i} in cage {} moved", binding.cage_of[i]);
        }
        moved_somewhere |= a != b;
    }
    assert!(moved_somewhere);
    // Incremental update: only the touched rows, same result as the full product.
    let columns = binding.operator.columns_of_moved_vertices(&[0]);
    let rows = binding.operator.rows_touched(&columns);
    assert!(rows.iter().all(|&r| binding.cage_of[r as usize] < 2));
    let x = binding.operator.dofs(rest, &posed);
    let mut incremental = before.clone();
    binding.operator.apply_rows(&rows, &x, &mut incremental);
    for (a, b) in incremental.iter().zip(&after) {
        assert!((*a - *b).length() < 1e-6);
    }
}

/// Following moves one vertex at a time (`update_dofs`, the touched rows only) gives what a
/// full frame gives, Green face DOFs included, and the columns a move touches are its vertex
/// and exactly the Green triangles that use it.
#[test]
fn moves_followed_incrementally_equal_full_frames_with_green_cages() {
    let scene = demo_scene("bumpy", 0.3).unwrap();
    let binding = StarBinding::bind_scene(&scene, &control()).unwrap();
    let operator = &binding.operator;
    assert!(
        !operator.green_dofs().is_empty(),
        "the bumpy demo has a GC cage"
    );
    let rest = &scene.cages.vertices;
    let mut posed = rest.clone();
    let mut x = operator.dofs(rest, &posed);
    let mut followed = binding.deform(rest, &posed);
    for v in (0..rest.len() as u32).step_by(3) {
        posed[v as usize] += DVec3::new(0.03, -0.02, 0.05) * f64::from(v % 5 + 1);
        operator.update_dofs(rest, &posed, &[v], &mut x);
        assert_eq!(x, operator.dofs(rest, &posed), "DOFs after moving {v}");
        let columns = operator.columns_of_moved_vertices(&[v]);
        let expected: Vec<u32> = std::iter::once(v)
            .chain(
                operator
                    .green_dofs()
                    .triangles()
                    .iter()
                    .enumerate()
                    .filter(|(_, t)| t.contains(&v))
                    .map(|(d, _)| (rest.len() + d) as u32),
            )
            .collect();
        assert_eq!(columns, expected, "columns of {v}");
        operator.apply_rows(&operator.rows_touched(&columns), &x, &mut followed);
    }
    let full = binding.deform(rest, &posed);
    let worst = followed
        .iter()
        .zip(&full)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f32::max);
    // The same f32 products, row by row: equal to the bit.
    assert!(worst == 0.0, "{worst}");
}

#[test]
fn f32_operator_matches_f64_evaluation() {
    for name in ["bumpy", "egg"] {
        let scene = demo_scene(name, 0.3).unwrap();
        let pose = scene.poses.values().next().unwrap().clone();
        let binding = StarBinding::bind_scene(&scene, &control()).unwrap();
        let fast = binding.deform(&scene.cages.vertices, &pose);
        let exact =
            evaluate_points(&scene, scene.mesh.welded_positions(), &pose, &control()).unwrap();
        let worst = fast
            .iter()
            .zip(&exact)
            .map(|(a, b)| (a.as_dvec3() - *b).length())
            .fold(0.0, f64::max);
        assert!(worst < 1e-5, "{name}: {worst}");
        assert!(binding.stats.operator_bytes > 0 && binding.stats.seconds_total > 0.0);
    }
}

/// A random grid of box cages (nx × ny × nz cells of size 1) with the given kinds.
pub(crate) fn grid_scene(dims: [usize; 3], kinds: &[CoordinateKind], policy: JoinPolicy) -> Scene {
    let [nx, ny, nz] = dims;
    let mut set = CageSet::default();
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                set.vertices.push(DVec3::new(i as f64, j as f64, k as f64));
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| (i + (nx + 1) * (j + (ny + 1) * k)) as u32;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let cell = i + nx * (j + ny * k);
                set.leaves.push(LeafCage {
                    name: format!("c{cell}"),
                    kind: kinds[cell % kinds.len()],
                    h: None,
                    border_h: Default::default(),
                    faces: box_faces(std::array::from_fn(|c| {
                        id(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2))
                    })),
                });
            }
        }
    }
    let mesh = box_mesh(
        DVec3::splat(0.1),
        DVec3::new(nx as f64, ny as f64, nz as f64) - 0.1,
        [4 * nx as u32, 4 * ny as u32, 4 * nz as u32],
    );
    let mut settings = SceneSettings {
        join_coordinates: policy,
        ..Default::default()
    };
    settings.harmonic.resolution = 16;
    Scene::new(MeshSource::Embedded, mesh, set, settings)
}

mod random_grids {
    use super::*;
    use proptest::prelude::*;

    fn kind() -> impl Strategy<Value = CoordinateKind> {
        prop_oneof![
            Just(CoordinateKind::MeanValue),
            Just(CoordinateKind::Green),
            Just(CoordinateKind::Harmonic)
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(6))]

        /// Similarities are reproduced by every mix of kinds; with no Green cage in the mix,
        /// any affine map is (HC within a tenth of its grid cell).
        #[test]
        fn mixed_kind_grids_reproduce_similarities(
            dims in (1usize..=3, 1usize..=2, 1usize..=2),
            kinds in prop::collection::vec(kind(), 1..4),
            angle in -1.0f64..1.0,
            scale in 0.5f64..2.0,
            shear in -0.3f64..0.3,
            auto_policy in any::<bool>(),
        ) {
            let policy = if auto_policy { JoinPolicy::Auto } else { JoinPolicy::Mvc };
            let scene = grid_scene([dims.0, dims.1, dims.2], &kinds, policy);
            let has_green = scene.cages.leaves.iter().any(|c| c.kind == CoordinateKind::Green);
            let linear = if has_green {
                DMat3::from_quat(DQuat::from_rotation_z(angle)) * scale
            } else {
                DMat3::from_quat(DQuat::from_rotation_z(angle)) * scale + DMat3::from_cols_array(&[0.0, shear, 0.0, 0.0, 0.0, shear, shear, 0.0, 0.0])
            };
            let map = |p: DVec3| linear * p + DVec3::new(0.2, -0.1, 0.3);
            let posed: Vec<DVec3> = scene.cages.vertices.iter().map(|&p| map(p)).collect();
            let points: Vec<DVec3> = scene.mesh.welded_positions().iter().step_by(7).copied().collect();
            let out = evaluate_points(&scene, &points, &posed, &control()).unwrap();
            let uses_hc = auto_policy || scene.cages.leaves.iter().any(|c| c.kind == CoordinateKind::Harmonic);
            let tolerance = if uses_hc { 0.1 * 3.0 / 16.0 * scale.max(1.0) } else { 1e-8 };
            let worst = points.iter().zip(&out).map(|(p, q)| (map(*p) - *q).length()).fold(0.0, f64::max);
            prop_assert!(worst < tolerance, "{dims:?} {kinds:?} {policy:?}: error {worst}");
        }

        /// The rest pose gives every point back (the displacement form) on random cages: a grid
        /// whose vertices are jittered (concave join cages included), every mix of kinds, every
        /// join policy, any h.
        #[test]
        fn random_cages_give_the_points_back_at_rest(
            dims in (1usize..=3, 1usize..=2, 1usize..=2),
            kinds in prop::collection::vec(kind(), 1..4),
            policy in prop_oneof![
                Just(JoinPolicy::Mvc),
                Just(JoinPolicy::Auto),
                Just(JoinPolicy::Hc),
                Just(JoinPolicy::Gc)
            ],
            h in 0.1f64..1.0,
            jitter in prop::collection::vec(-0.08f64..0.08, 54 * 3),
        ) {
            let mut scene = grid_scene([dims.0, dims.1, dims.2], &kinds, policy);
            scene.settings.default_h = h;
            scene.settings.harmonic.resolution = 16;
            for (v, d) in scene.cages.vertices.iter_mut().zip(jitter.chunks_exact(3)) {
                *v += DVec3::new(d[0], d[1], d[2]);
            }
            let points: Vec<DVec3> = scene.mesh.welded_positions().iter().step_by(5).copied().collect();
            let rest = scene.cages.vertices.clone();
            let out = evaluate_points(&scene, &points, &rest, &control()).unwrap();
            let worst = points.iter().zip(&out).map(|(p, q)| (*p - *q).length()).fold(0.0, f64::max);
            prop_assert!(worst < 1e-9, "{dims:?} {kinds:?} {policy:?} h {h}: error {worst}");
            // The f32 operator too.
            let binding = StarBinding::bind_scene(&scene, &control()).unwrap();
            let out = binding.deform(&rest, &rest);
            let worst = scene.mesh.welded_positions().iter().zip(&out)
                .map(|(p, q)| (*p - q.as_dvec3()).length()).fold(0.0, f64::max);
            prop_assert!(worst < 1e-5, "f32: {worst}");
        }
    }
}

#[test]
fn bumpy_gc_mvc_border_is_c1() {
    let scene = demo_scene("bumpy", 0.3).unwrap();
    let pose = scene.poses["lift"].clone();
    let posed: Vec<DVec3> = pose.iter().map(|&p| wavy(p)).collect();
    // The border between the middle (MVC) and right (GC) cages is the plane x = 0.5.
    let star = |p: DVec3| evaluate_points(&scene, &[p], &posed, &control()).unwrap()[0];
    let (y, z) = (0.1, 0.03);
    let gap = (star(DVec3::new(0.5 - 1e-9, y, z)) - star(DVec3::new(0.5 + 1e-9, y, z))).length();
    assert!(gap < 1e-6, "C0 gap {gap}");
    let (j1, j2) = (
        derivative_jump(star, 0.5, y, z, 1e-2),
        derivative_jump(star, 0.5, y, z, 1e-3),
    );
    assert!(j2 < 0.2 * j1 + 1e-5, "jump {j1} at 1e-2, {j2} at 1e-3");
}

#[test]
fn moving_any_cage_vertex_changes_nothing_beyond_its_join_cages() {
    let scene = demo_scene("egg", 0.3).unwrap();
    let binding = StarBinding::bind_scene(&scene, &control()).unwrap();
    let rest = &scene.cages.vertices;
    let before = binding.deform(rest, rest);
    let vertices_of: Vec<std::collections::BTreeSet<u32>> = scene
        .cages
        .leaves
        .iter()
        .map(|c| c.faces.iter().flatten().copied().collect())
        .collect();
    for u in 0..rest.len() as u32 {
        let mut posed = rest.clone();
        posed[u as usize] += DVec3::new(0.2, -0.1, 0.15);
        let after = binding.deform(rest, &posed);
        let containing: Vec<usize> = (0..vertices_of.len())
            .filter(|&c| vertices_of[c].contains(&u))
            .collect();
        for (i, (a, b)) in before.iter().zip(&after).enumerate() {
            let cage = binding.cage_of[i] as usize;
            let shares = containing
                .iter()
                .any(|&c| !vertices_of[c].is_disjoint(&vertices_of[cage]));
            let b_is_one = binding.boundary_weight[i] >= 1.0;
            if !shares || (b_is_one && !containing.contains(&cage)) {
                assert_eq!(a, b, "u = {u}: vertex {i} in cage {cage} moved");
            }
        }
    }
}

/// A border made by the rig operations (a box extruded along x, then cut across x) is C1 as
/// the demos' borders are, where plain piecewise T is only C0.
#[test]
fn borders_made_by_extrude_and_loop_cut_are_c1() {
    use starcages_core::rig::{RigOp, apply_rig_op};
    let mesh = box_mesh(
        DVec3::new(-0.9, -0.4, -0.4),
        DVec3::new(1.9, 0.4, 0.4),
        [14, 4, 4],
    );
    let mut scene = Scene::new(
        MeshSource::Embedded,
        mesh,
        CageSet::default(),
        SceneSettings {
            join_coordinates: JoinPolicy::Mvc,
            ..Default::default()
        },
    );
    apply_rig_op(
        &mut scene,
        &RigOp::parse("add-box left -1 -0.5 -0.5 0 0.5 0.5").unwrap(),
    )
    .unwrap();
    // The +x face of the box: extrude it 2 along x, then cut the new cage in half across x.
    let face = scene.cages.leaves[0]
        .faces
        .iter()
        .position(|f| f.iter().all(|&v| scene.cages.vertices[v as usize].x == 0.0))
        .unwrap();
    apply_rig_op(
        &mut scene,
        &RigOp::parse(&format!("extrude left {face} 2 right")).unwrap(),
    )
    .unwrap();
    apply_rig_op(&mut scene, &RigOp::parse("split right x 0.5 far").unwrap()).unwrap();
    let report = starcages_core::check::validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
    let posed: Vec<DVec3> = scene.cages.vertices.iter().map(|&p| wavy(p)).collect();
    let (y, z) = (0.13, -0.21);
    let star = |p: DVec3| evaluate_points(&scene, &[p], &posed, &control()).unwrap()[0];
    // The extruded border at x = 0 and the cut at x = 1.
    for (x0, near, beyond) in [(0.0, 0, 1), (1.0, 1, 2)] {
        let (j1, j2) = (
            derivative_jump(star, x0, y, z, 1e-2),
            derivative_jump(star, x0, y, z, 1e-3),
        );
        assert!(
            j2 < 0.2 * j1 + 1e-5,
            "x = {x0}: jump {j1} at 1e-2, {j2} at 1e-3"
        );
        let plain = |p: DVec3| plain_t(&scene, if p.x < x0 { near } else { beyond }, p, &posed);
        let p2 = derivative_jump(plain, x0, y, z, 1e-3);
        assert!(j2 < 0.1 * p2, "x = {x0}: *Cages jump {j2} vs plain {p2}");
    }
}

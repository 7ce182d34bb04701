//! Scene model and files: demos validate, files round-trip, every validation problem is
//! reported with its cage and element, bad files get clear errors, saves are atomic.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use glam::DVec3;
use starcages_core::check::validate_scene;
use starcages_core::coords::CoordinateKind;
use starcages_core::generate::demo::{box_mesh, demo_scene};
use starcages_core::generate::{AutocageOptions, autocage};
use starcages_core::scene::{
    CageSet, InternalCage, LeafCage, MeshSource, OutsidePolicy, Scene, SceneProblem, SceneSettings,
};

fn problems(scene: &Scene) -> Vec<SceneProblem> {
    validate_scene(scene).errors
}

#[test]
fn autocage_drops_empty_cells_and_shares_faces_exactly() {
    // An L-shaped mesh (a bar along x and a post along z): the cells beyond the L's corner are
    // outside its volume and stay empty; the cells inside it are kept.
    let bar = box_mesh(DVec3::ZERO, DVec3::new(3.0, 1.0, 1.0), [6, 2, 2]);
    let post = box_mesh(
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(1.0, 1.0, 3.0),
        [2, 2, 4],
    );
    let mut positions = bar.welded_positions().to_vec();
    let mut triangles = bar.welded_triangles().to_vec();
    let base = positions.len() as u32;
    positions.extend_from_slice(post.welded_positions());
    triangles.extend(post.welded_triangles().iter().map(|t| t.map(|v| v + base)));
    let mesh = starcages_core::mesh::Mesh::new(positions, triangles, None, None).unwrap();
    let set = autocage(
        &mesh,
        &AutocageOptions {
            grid: [3, 3, 3],
            ..Default::default()
        },
    );
    // The far corner (x > 2, z > 2) holds no vertex and lies outside the L: dropped.
    let names: Vec<&str> = set.leaves.iter().map(|c| c.name.as_str()).collect();
    assert!(set.leaves.len() < 27, "empty cells kept: {names:?}");
    assert!(!names.contains(&"cell_2_1_2"), "{names:?}");
    let scene = Scene::new(MeshSource::Embedded, mesh, set, SceneSettings::default());
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
    let adjacency = scene.cages.adjacency();
    assert!(!adjacency.is_empty());
    // Shared-vertex count: a 3x1x1 row in the middle layer shares 4 vertices per border.
    assert!(adjacency.iter().all(|a| !a.faces.is_empty()));
}

fn two_box_scene() -> Scene {
    demo_scene("bar", 0.3).unwrap()
}

/// One way to break the two-box scene, and what validation must say about it.
struct ValidationCase {
    /// What is broken.
    name: &'static str,
    /// Breaks the scene.
    break_it: fn(&mut Scene),
    /// Whether the problems name it (and say the fix).
    named: fn(&Scene, &[SceneProblem]) -> bool,
}

/// Moves the left cage's right face into the right cage (its own copies of the old border keep
/// both cages closed): the cages overlap.
fn overlap_the_cages(s: &mut Scene) {
    let mut shared: Vec<u32> = s.cages.leaves[0]
        .faces
        .iter()
        .flatten()
        .copied()
        .filter(|v| s.cages.vertices[*v as usize].x == 0.0)
        .collect();
    shared.sort_unstable();
    shared.dedup();
    let mut moved = s.cages.clone();
    for v in shared {
        // Into the right cage, strictly inside it (not on its edges).
        let p = &mut moved.vertices[v as usize];
        *p = DVec3::new(0.5, p.y * 0.9, p.z * 0.9);
    }
    let offset = moved.vertices.len() as u32;
    let border: Vec<u32> = (0..moved.vertices.len() as u32)
        .filter(|&v| moved.vertices[v as usize].x == 0.5)
        .collect();
    for &v in &border {
        let p = moved.vertices[v as usize];
        moved.vertices.push(DVec3::new(0.0, p.y / 0.9, p.z / 0.9));
    }
    for f in &mut moved.leaves[1].faces {
        for v in f.iter_mut() {
            if let Some(k) = border.iter().position(|b| b == v) {
                *v = offset + k as u32;
            }
        }
    }
    s.pose = moved.vertices.clone();
    s.poses.clear();
    s.cages = moved;
}

/// Shrinks the cages along x so that the mesh's ends stick out.
fn shrink_the_cages(s: &mut Scene) {
    for v in &mut s.cages.vertices {
        v.x *= 0.8;
    }
    s.pose = s.cages.vertices.clone();
    s.poses.clear();
}

/// Every case is checked and every failing one reported, not only the first.
#[test]
fn validation_names_cage_element_and_fix() {
    let cases = [
        ValidationCase {
            name: "an open cage",
            break_it: |s| drop(s.cages.leaves[0].faces.pop()),
            named: |_, p| {
                matches!(p.first(), Some(SceneProblem::Cage { cage, .. }) if cage == "cage_0_0_0")
                    && p[0].to_string().contains("not closed")
            },
        },
        ValidationCase {
            name: "an inward cage",
            break_it: |s| s.cages.leaves[1].faces.iter_mut().for_each(|f| f.reverse()),
            named: |_, p| p.iter().any(|e| e.to_string().contains("oriented inwards")),
        },
        ValidationCase {
            name: "a shared face run the same way by both cages",
            break_it: |s| s.cages.leaves[1].faces.iter_mut().for_each(|f| f.reverse()),
            named: |_, p| {
                p.iter()
                    .any(|e| matches!(e, SceneProblem::SharedFaceSameOrientation { .. }))
            },
        },
        ValidationCase {
            name: "a mesh vertex in two cages",
            break_it: overlap_the_cages,
            named: |_, p| {
                p.iter()
                    .any(|e| matches!(e, SceneProblem::MeshVertexInTwoCages { .. }))
            },
        },
        ValidationCase {
            name: "a cage vertex inside another cage",
            break_it: overlap_the_cages,
            named: |_, p| {
                p.iter()
                    .any(|e| matches!(e, SceneProblem::CageVertexInsideCage { .. }))
            },
        },
        ValidationCase {
            name: "mesh vertices outside every cage, named, with the fix",
            break_it: shrink_the_cages,
            named: |s, p| {
                let outside = p.iter().find_map(|e| match e {
                    SceneProblem::MeshOutside {
                        count, vertices, ..
                    } => Some((*count, vertices.clone())),
                    _ => None,
                });
                outside.is_some_and(|(count, vertices)| {
                    count > 0
                        && vertices
                            .iter()
                            .all(|&v| s.mesh.welded_positions()[v].x.abs() > 0.88 - 1e-9)
                }) && p.iter().any(|e| {
                    e.to_string()
                        .contains("set the scene's outside policy to 'nearest'")
                })
            },
        },
        ValidationCase {
            name: "h outside (0, 1]",
            break_it: |s| s.cages.leaves[0].h = Some(1.5),
            named: |_, p| {
                p.iter()
                    .any(|e| matches!(e, SceneProblem::InvalidH { h, .. } if *h == 1.5))
            },
        },
        ValidationCase {
            name: "a border h for a cage that does not exist",
            break_it: |s| {
                s.cages.leaves[0].border_h.insert("nobody".into(), 0.5);
            },
            named: |_, p| {
                p.iter().any(|e| {
                    matches!(e, SceneProblem::UnknownBorder { neighbour, .. } if neighbour == "nobody")
                })
            },
        },
        ValidationCase {
            name: "a default h outside (0, 1], printed short",
            break_it: |s| s.settings.default_h = 1e308,
            named: |_, p| {
                p.iter().any(|e| {
                    e.to_string()
                        == "settings: default_h = 1e308 is outside (0, 1]; choose a value in \
                            that range (0.5 is the default)"
                })
            },
        },
        ValidationCase {
            name: "two cages of one name",
            break_it: |s| s.cages.leaves[1].name = "cage_0_0_0".into(),
            named: |_, p| {
                p.iter()
                    .any(|e| matches!(e, SceneProblem::DuplicateName { .. }))
            },
        },
        ValidationCase {
            name: "a pose of the wrong length",
            break_it: |s| drop(s.poses.insert("short".into(), vec![DVec3::ZERO; 3])),
            named: |_, p| {
                p.iter().any(
                    |e| matches!(e, SceneProblem::PoseLength { pose, got: 3, .. } if pose == "short"),
                )
            },
        },
    ];
    let mut unnamed = Vec::new();
    for case in &cases {
        let mut scene = two_box_scene();
        (case.break_it)(&mut scene);
        let found = problems(&scene);
        if !(case.named)(&scene, &found) {
            unnamed.push(format!("{}: {found:?}", case.name));
        }
    }
    assert!(unnamed.is_empty(), "not named:\n{}", unnamed.join("\n"));
}

/// Mesh vertices outside every cage are a warning, not an error, under the 'nearest' policy.
#[test]
fn the_nearest_policy_makes_outside_vertices_a_warning() {
    let mut scene = two_box_scene();
    shrink_the_cages(&mut scene);
    scene.settings.outside = OutsidePolicy::Nearest;
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{:?}", report.errors);
    assert_eq!(report.warnings.len(), 1);
}

#[test]
fn hierarchy_problems() {
    let mut s = two_box_scene();
    let n = s.cages.vertices.len() as u32;
    // Two internal boxes, each around the whole bar, owning overlapping vertex sets.
    let add_box = |set: &mut CageSet, name: &str, owns: Vec<u32>| {
        let base = set.vertices.len() as u32;
        for c in 0..8u32 {
            let p = DVec3::new(
                if c & 1 == 0 { -2.0 } else { 2.0 },
                if c & 2 == 0 { -1.0 } else { 1.0 },
                if c & 4 == 0 { -1.0 } else { 1.0 },
            );
            set.vertices.push(p);
        }
        let faces = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        set.internals.push(InternalCage {
            name: name.into(),
            kind: CoordinateKind::MeanValue,
            faces: faces
                .iter()
                .map(|f| f.iter().map(|&c| base + c).collect())
                .collect(),
            owns,
            pivot: None,
            joint: Vec::new(),
        });
    };
    add_box(&mut s.cages, "upper", vec![0, 1, n + 8]);
    add_box(&mut s.cages, "lower", vec![1, n, 999]);
    s.pose = s.cages.vertices.clone();
    s.poses.clear();
    let p = problems(&s);
    assert!(
        p.iter()
            .any(|e| matches!(e, SceneProblem::OwnedTwice { vertex: 1, .. })),
        "{p:?}"
    );
    assert!(
        p.iter()
            .any(|e| matches!(e, SceneProblem::BadOwnedVertex { vertex: 999, .. })),
        "{p:?}"
    );
    assert!(
        p.iter()
            .any(|e| matches!(e, SceneProblem::HierarchyCycle { .. })),
        "{p:?}"
    );
}

#[test]
fn harmonic_settings_outside_their_limits_are_refused_before_any_work() {
    use starcages_core::coords::{BindControl, BindSettings, bind};
    for (resolution, tolerance, max_iterations, what) in [
        (0, 1e-8, 200, "resolution 0"),
        (3, 1e-8, 200, "resolution 3"),
        (100_000, 1e-8, 200, "resolution 100000"),
        (u32::MAX, 1e-8, 200, "resolution 4294967295"),
        (48, 0.0, 200, "tolerance 0"),
        (48, -1.0, 200, "tolerance -1"),
        (48, f64::NAN, 200, "tolerance NaN"),
        (48, 1e-8, 0, "max_iterations 0"),
        (48, 1e-8, u32::MAX, "max_iterations 4294967295"),
    ] {
        let mut scene = two_box_scene();
        scene.settings.harmonic.resolution = resolution;
        scene.settings.harmonic.tolerance = tolerance;
        scene.settings.harmonic.max_iterations = max_iterations;
        let report = validate_scene(&scene);
        let found = report
            .errors
            .iter()
            .find(|e| matches!(e, SceneProblem::Settings { .. }))
            .unwrap_or_else(|| panic!("{what}: not reported ({:?})", report.errors));
        let text = found.to_string();
        assert!(
            text.contains("out of range") && text.contains(" to "),
            "{what}: {text}"
        );
        // The coordinates refuse them too, at once (no grid is allocated).
        let cage = starcages_core::cage::shapes::cuboid(DVec3::ZERO, DVec3::ONE);
        let settings = BindSettings {
            harmonic: scene.settings.harmonic,
        };
        let error = bind(
            CoordinateKind::Harmonic,
            &cage,
            &[DVec3::splat(0.5)],
            &settings,
            &BindControl::default(),
        )
        .unwrap_err();
        assert!(
            error.to_string().contains("out of range"),
            "{what}: {error}"
        );
    }
    assert!(
        validate_scene(&two_box_scene()).is_valid(),
        "the defaults are in range"
    );
}

/// A scene of axis-aligned box leaf cages (each with its own eight vertices) around a small
/// box mesh at the origin.
fn boxes_scene(boxes: &[(DVec3, DVec3)]) -> Scene {
    let mut vertices = Vec::new();
    let mut leaves = Vec::new();
    for (i, &(lo, hi)) in boxes.iter().enumerate() {
        let base = vertices.len() as u32;
        let cage = starcages_core::cage::shapes::cuboid(lo, hi);
        vertices.extend_from_slice(cage.positions());
        let faces = cage
            .polygons()
            .iter()
            .map(|p| p.vertices.iter().map(|v| v + base).collect())
            .collect();
        leaves.push(LeafCage {
            name: format!("box_{i}"),
            kind: CoordinateKind::MeanValue,
            h: None,
            border_h: Default::default(),
            faces,
        });
    }
    let set = CageSet {
        vertices,
        leaves,
        internals: Vec::new(),
    };
    let mesh = box_mesh(DVec3::splat(-0.05), DVec3::splat(0.05), [1, 1, 1]);
    let settings = SceneSettings {
        outside: OutsidePolicy::Nearest,
        ..Default::default()
    };
    Scene::new(MeshSource::Embedded, mesh, set, settings)
}

#[test]
fn cages_through_each_other_t_junctions_and_self_intersections_are_refused() {
    // A plus sign: no vertex of either box lies inside the other, no mesh vertex in the overlap.
    let plus = boxes_scene(&[
        (DVec3::new(-1.0, -0.2, -0.2), DVec3::new(1.0, 0.2, 0.2)),
        (DVec3::new(-0.2, -1.0, -0.3), DVec3::new(0.2, 1.0, 0.3)),
    ]);
    let p = problems(&plus);
    let crossing = p
        .iter()
        .find(|e| matches!(e, SceneProblem::CagesCross { .. }))
        .unwrap_or_else(|| panic!("the plus sign passes validation: {p:?}"));
    assert!(crossing.to_string().contains("pass through each other"));
    // Negative control: the same boxes side by side are fine.
    let apart = boxes_scene(&[
        (DVec3::new(-1.0, -0.2, -0.2), DVec3::new(1.0, 0.2, 0.2)),
        (DVec3::new(-0.2, 0.5, -0.3), DVec3::new(0.2, 1.0, 0.3)),
    ]);
    assert!(validate_scene(&apart).is_valid(), "{:?}", problems(&apart));

    // A T-junction: a small box whose face lies inside a big box's face, corners on it.
    let t_junction = boxes_scene(&[
        (DVec3::splat(-1.0), DVec3::ONE),
        (DVec3::new(1.0, -0.5, -0.5), DVec3::new(2.0, 0.5, 0.5)),
    ]);
    let p = problems(&t_junction);
    assert!(
        p.iter().any(|e| matches!(e,
            SceneProblem::VertexOnCageSurface { cage, .. } if cage == "box_0")),
        "{p:?}"
    );
    assert!(p.iter().any(|e| e.to_string().contains("T-junction")));
    // Two neighbours with their own copies of the shared corners (not welded): the same.
    let unwelded = boxes_scene(&[
        (DVec3::splat(-1.0), DVec3::ONE),
        (DVec3::new(1.0, -1.0, -1.0), DVec3::new(3.0, 1.0, 1.0)),
    ]);
    // The small mesh lies in the first box only: the two touch, each on its own (a contact,
    // as the auto rig leaves two paws side by side).
    assert!(
        validate_scene(&unwelded).is_valid(),
        "{:?}",
        problems(&unwelded)
    );
    // A mesh across the seam would tear there: refused, with the fix.
    let mut across = unwelded.clone();
    across.mesh = box_mesh(
        DVec3::new(0.5, -0.2, -0.2),
        DVec3::new(1.5, 0.2, 0.2),
        [2, 1, 1],
    );
    let p = problems(&across);
    assert!(
        p.iter().any(|e| e.to_string().contains("weld the vertex")),
        "{p:?}"
    );

    // A cage pushed through itself is told so, not told to flip all its faces.
    let mut folded = boxes_scene(&[(DVec3::splat(-1.0), DVec3::ONE)]);
    let corner = folded
        .cages
        .vertices
        .iter()
        .position(|p| *p == DVec3::ONE)
        .unwrap();
    folded.cages.vertices[corner] = DVec3::new(-0.2, -0.1, -3.0);
    folded.pose = folded.cages.vertices.clone();
    let p = problems(&folded);
    let message = p
        .iter()
        .find_map(|e| match e {
            SceneProblem::Cage { problem, .. } => Some(problem.to_string()),
            _ => None,
        })
        .unwrap_or_else(|| panic!("a folded cage passes: {p:?}"));
    assert!(message.contains("passes through itself"), "{message}");
    assert!(!message.contains("flip all faces"), "{message}");

    // A cage saved without welding its vertices is told to weld them, not to close holes.
    let cube = starcages_core::cage::shapes::cuboid(DVec3::ZERO, DVec3::ONE);
    let mut positions = cube.positions().to_vec();
    let mut faces: Vec<Vec<u32>> = cube.polygons().iter().map(|p| p.vertices.clone()).collect();
    positions.push(positions[faces[0][0] as usize]);
    faces[0][0] = positions.len() as u32 - 1;
    let first = starcages_core::cage::Cage::from_polygons(positions, faces).unwrap_err();
    assert!(first.to_string().contains("weld"), "{first}");
}

/// Under the `nearest` policy, a mesh vertex outside every cage and beyond the range of its
/// nearest cage's mean value coordinates is an error of `validate`, as the bind refuses it; a
/// vertex just outside is only a warning.
#[test]
fn vertices_too_far_from_their_nearest_cage_fail_validation_as_the_bind_does() {
    let with_extra = |far: f64| {
        let mut scene = two_box_scene();
        scene.settings.outside = OutsidePolicy::Nearest;
        let mut positions = scene.mesh.positions().to_vec();
        let mut triangles = scene.mesh.triangles().to_vec();
        let base = positions.len() as u32;
        positions.extend([
            DVec3::new(far, 0.0, 0.0),
            DVec3::new(far + 0.1, 0.0, 0.0),
            DVec3::new(far, 0.1, 0.0),
        ]);
        triangles.push([base, base + 1, base + 2]);
        scene.mesh = starcages_core::mesh::Mesh::new(positions, triangles, None, None).unwrap();
        scene
    };
    let near = with_extra(1.5);
    let report = validate_scene(&near);
    assert!(report.is_valid(), "{:?}", report.errors);
    assert_eq!(report.warnings.len(), 1);
    let far = with_extra(1e5);
    let p = problems(&far);
    assert!(
        p.iter()
            .any(|e| matches!(e, SceneProblem::FarFromNearestCage { count: 3, .. })),
        "{p:?}"
    );
    let bound = starcages_core::star::StarBinding::bind_scene(
        &far,
        &starcages_core::BindControl::default(),
    );
    assert!(bound.is_err(), "the bind accepted what validate refuses");
}

//! The auto rig on generated shapes (an H, a Y, a five-armed star, two blobs, a figure with
//! legs close together): valid scenes, one piece of surface per cage, the same rig on any
//! number of threads; the 3×3×3 box grid as the negative control of the one-piece check.

use glam::DVec3;
use proptest::array::uniform3;
use proptest::prelude::*;
use starcages_core::BindControl;
use starcages_core::check::validate_scene;
use starcages_core::generate::{AutocageOptions, autocage};
use starcages_core::generate::{AutorigSettings, Mirror, autorig, surface_pieces_per_leaf};
use starcages_core::mesh::Mesh;
use starcages_core::scene::{CageSet, MeshSource, Scene, SceneSettings};
use starcages_core::surface_nets::surface_nets;

use crate::common::capsules;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

fn shape_h() -> Mesh {
    capsules(
        &[
            (v(-1.0, 0.0, -1.5), v(-1.0, 0.0, 1.5), 0.35),
            (v(1.0, 0.0, -1.5), v(1.0, 0.0, 1.5), 0.35),
            (v(-1.0, 0.0, 0.0), v(1.0, 0.0, 0.0), 0.3),
        ],
        0.06,
    )
}

fn shape_y() -> Mesh {
    capsules(
        &[
            (v(0.0, 0.0, -2.0), v(0.0, 0.0, 0.0), 0.35),
            (v(0.0, 0.0, 0.0), v(-1.2, 0.0, 1.5), 0.3),
            (v(0.0, 0.0, 0.0), v(1.2, 0.0, 1.5), 0.3),
        ],
        0.06,
    )
}

fn shape_star() -> Mesh {
    let mut parts = vec![(v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.01), 0.6)];
    for k in 0..5 {
        let angle = std::f64::consts::TAU * f64::from(k) / 5.0;
        parts.push((
            v(0.0, 0.0, 0.0),
            2.2 * v(angle.cos(), angle.sin(), 0.0),
            0.22,
        ));
    }
    capsules(&parts, 0.05)
}

fn two_blobs() -> Mesh {
    capsules(
        &[
            (v(-1.5, 0.0, 0.0), v(-1.0, 0.0, 0.2), 0.6),
            (v(1.2, 0.0, 0.0), v(1.6, 0.3, 0.0), 0.5),
        ],
        0.06,
    )
}

/// The capsules of a standing figure: a torso, a head, two arms out to the sides (left, right)
/// and two legs 0.3 apart (left, right).
fn figure_parts() -> Vec<(DVec3, DVec3, f64)> {
    vec![
        (v(0.0, 0.0, 0.2), v(0.0, 0.0, 1.2), 0.45),
        (v(0.0, 0.0, 1.8), v(0.0, 0.0, 1.85), 0.28),
        (v(-0.3, 0.0, 1.1), v(-1.5, 0.0, 0.9), 0.14),
        (v(0.3, 0.0, 1.1), v(1.5, 0.0, 0.9), 0.14),
        (v(-0.3, 0.0, 0.1), v(-0.3, 0.0, -1.6), 0.15),
        (v(0.3, 0.0, 0.1), v(0.3, 0.0, -1.6), 0.15),
    ]
}

/// A standing figure (see [`figure_parts`]).
fn figure() -> Mesh {
    capsules(&figure_parts(), 0.04)
}

/// A hand: a palm with four fingers whose sides lie closer than one cell of the auto rig's
/// grid, so that no grid-aligned cut can put them in cages of their own.
fn hand() -> Mesh {
    let mut parts = vec![(v(-0.25, 0.0, 0.0), v(0.25, 0.0, 0.0), 0.3)];
    for k in 0..4 {
        let x = -0.285 + 0.19 * f64::from(k);
        parts.push((v(x, 0.0, 0.2), v(x, 0.0, 1.6), 0.08));
    }
    capsules(&parts, 0.012)
}

fn rig(mesh: &Mesh, settings: &AutorigSettings) -> CageSet {
    autorig(mesh, settings, &BindControl::default())
        .unwrap()
        .cages
}

fn scene(mesh: &Mesh, cages: CageSet) -> Scene {
    Scene::new(
        MeshSource::Embedded,
        mesh.clone(),
        cages,
        SceneSettings::default(),
    )
}

/// The rig of `mesh` at `detail` with internal cages, checked valid.
fn rig_with_internal_cages(mesh: &Mesh, detail: u32) -> Scene {
    let settings = AutorigSettings {
        detail,
        controls: true,
        ..AutorigSettings::default()
    };
    let scene = scene(mesh, rig(mesh, &settings));
    assert!(validate_scene(&scene).is_valid());
    scene
}

/// The names of the internal cages.
fn internal_names(scene: &Scene) -> Vec<&str> {
    scene
        .cages
        .internals
        .iter()
        .map(|c| c.name.as_str())
        .collect()
}

/// The limbs with controls: one `<limb>.1` control each, at the limb's root.
fn limb_boxes(scene: &Scene) -> usize {
    scene
        .cages
        .internals
        .iter()
        .filter(|c| c.name.ends_with(".1"))
        .count()
}

/// Properties 1, 2 and 6 of the issue: a valid scene, one piece of surface in every leaf
/// cage, and the same rig on one thread as on many.
fn check_rig(name: &str, mesh: &Mesh, least_cages: usize) -> Scene {
    let cages = rig(mesh, &AutorigSettings::default());
    // Property 6: the same rig on one thread as on the test's pool.
    let on_one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| rig(mesh, &AutorigSettings::default()));
    assert!(cages == on_one_thread, "{name}: another rig on one thread");
    let scene = scene(mesh, cages);
    let report = validate_scene(&scene);
    assert!(report.is_valid(), "{name}: {:?}", report.errors);
    assert!(
        scene.cages.leaves.len() >= least_cages,
        "{name}: only {} leaf cages",
        scene.cages.leaves.len()
    );
    let pieces = surface_pieces_per_leaf(&scene);
    for (leaf, n) in scene.cages.leaves.iter().zip(&pieces) {
        assert_eq!(
            *n, 1,
            "{name}: cage '{}' holds {n} pieces of surface",
            leaf.name
        );
    }
    scene
}

#[test]
fn an_h_gets_a_valid_rig_with_one_piece_per_cage() {
    check_rig("H", &shape_h(), 5);
}

#[test]
fn a_y_gets_a_valid_rig_with_one_piece_per_cage() {
    check_rig("Y", &shape_y(), 4);
}

#[test]
fn a_five_armed_star_gets_a_chain_per_arm() {
    let scene = check_rig("star", &shape_star(), 6);
    let limbs: std::collections::BTreeSet<&str> = scene
        .cages
        .leaves
        .iter()
        .filter(|l| !l.name.starts_with("body"))
        .filter_map(|l| l.name.split('_').next())
        .collect();
    assert_eq!(
        limbs.len(),
        5,
        "one limb per arm: {:?}",
        scene
            .cages
            .leaves
            .iter()
            .map(|l| &l.name)
            .collect::<Vec<_>>()
    );
}

#[test]
fn two_blobs_get_cages_of_their_own() {
    check_rig("two blobs", &two_blobs(), 2);
}

/// The meshes of several shapes as one mesh of separate components.
fn components(meshes: &[Mesh]) -> Mesh {
    let (mut positions, mut triangles) = (Vec::new(), Vec::new());
    for part in meshes {
        let base = positions.len() as u32;
        positions.extend_from_slice(part.positions());
        triangles.extend(part.triangles().iter().map(|t| t.map(|i| i + base)));
    }
    Mesh::new(positions, triangles, None, None).unwrap()
}

/// Two separate bars closer than a cell of the detail's grid (letters of a word, the parts of
/// a kit) share cells there; each still gets cages of its own, by moving the faces between
/// two cages over the mesh vertices there (the decimation's sweep) or, failing that, on a
/// finer grid. Not one mesh vertex of either bar lies in a cage holding the other's, slivers
/// included (the pieces check allows those).
#[test]
fn separate_parts_closer_than_a_cell_get_cages_of_their_own() {
    let bar = |y: f64, r: f64| capsules(&[(v(-1.0, y, 0.0), v(1.0, y, 0.0), r)], 0.02);
    // Surfaces 0.07 apart (-0.02 and 0.05), off the grid's middle: about one cell of the
    // detail-3 grid, whose cells straddle the gap.
    let (first, second) = (bar(-0.17, 0.15), bar(0.05 + 0.1, 0.1));
    let first_count = first.positions().len();
    let mesh = components(&[first, second]);
    let made = autorig(&mesh, &AutorigSettings::default(), &BindControl::default()).unwrap();
    assert!(made.report.shared_cages.is_empty(), "{:?}", made.report);
    let scene = check_rig("two bars", &mesh, 2);
    let containment = crate::posable_rig::mesh_containment(&scene);
    let mut holds = vec![[false; 2]; scene.cages.leaves.len()];
    for (vertex, c) in containment.iter().enumerate() {
        let bar = usize::from(vertex >= first_count);
        for &leaf in c.inside.iter().chain(&c.on_surface) {
            holds[leaf][bar] = true;
        }
    }
    for (leaf, held) in scene.cages.leaves.iter().zip(&holds) {
        assert!(
            !(held[0] && held[1]),
            "cage '{}' holds both bars",
            leaf.name
        );
    }
}

/// A head with two eyes that are separate spheres set half into it (Suzanne's, a character's
/// eyeballs): no cage boundary can pass where the surfaces cross, so each eye is one piece with
/// the head around it, and every cage holds one piece.
#[test]
fn eyes_set_into_a_head_are_one_piece_with_it() {
    let head = capsules(&[(v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.6), 0.7)], 0.05);
    let eye = |x: f64| capsules(&[(v(x, -0.68, 0.45), v(x, -0.68, 0.47), 0.18)], 0.03);
    check_rig(
        "head and eyes",
        &components(&[head, eye(-0.25), eye(0.25)]),
        1,
    );
}

#[test]
fn a_figure_with_legs_close_together_keeps_them_apart_where_a_box_grid_does_not() {
    let mesh = figure();
    check_rig("figure", &mesh, 7);
    // Negative control: the 3x3x3 grid puts both legs in one cell.
    let grid = scene(&mesh, autocage(&mesh, &AutocageOptions::default()));
    assert!(validate_scene(&grid).is_valid());
    let pieces = surface_pieces_per_leaf(&grid);
    assert!(
        pieces.iter().any(|&n| n > 1),
        "the box grid should hold two legs in one cell: {pieces:?}"
    );
}

#[test]
fn fingers_closer_than_a_cell_share_their_palm_s_cage_rather_than_split_apart() {
    let mesh = hand();
    check_rig("hand", &mesh, 1);
    // Negative control: the fingers do lie in shared cells of the 3x3x3 grid too.
    let grid = scene(&mesh, autocage(&mesh, &AutocageOptions::default()));
    assert!(surface_pieces_per_leaf(&grid).iter().any(|&n| n > 1));
}

#[test]
fn a_mesh_lying_on_its_side_gets_a_valid_rig_too() {
    // The Y turned a quarter about x, as a Y-up file read without turning would be.
    let mesh = shape_y();
    let turned: Vec<DVec3> = mesh.positions().iter().map(|p| v(p.x, -p.z, p.y)).collect();
    let turned = Mesh::new(turned, mesh.triangles().to_vec(), None, None).unwrap();
    check_rig("Y on its side", &turned, 4);
}

#[test]
fn a_mesh_with_holes_is_filled_and_rigged() {
    // The H with a tenth of its triangles removed: open, yet inside by winding number.
    let mesh = shape_h();
    let kept: Vec<[u32; 3]> = mesh
        .triangles()
        .iter()
        .enumerate()
        .filter(|(i, _)| i % 10 != 3)
        .map(|(_, t)| *t)
        .collect();
    let open = Mesh::new(mesh.positions().to_vec(), kept, None, None).unwrap();
    let scene = scene(&open, rig(&open, &AutorigSettings::default()));
    assert!(validate_scene(&scene).is_valid());
}

#[test]
fn the_same_mesh_gives_the_same_rig_on_any_thread_count() {
    let mesh = shape_star();
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| rig(&mesh, &AutorigSettings::default()))
    };
    assert_eq!(on(1), on(3));
}

#[test]
fn internal_cages_drive_each_limb() {
    let mesh = shape_star();
    let scene = rig_with_internal_cages(&mesh, 3);
    let names = internal_names(&scene);
    assert_eq!(
        names.iter().filter(|n| n.ends_with(".1")).count(),
        5,
        "{names:?}"
    );
    assert!(names.contains(&"root"));
}

#[test]
fn bad_settings_and_flat_meshes_are_refused_with_the_reason() {
    let mesh = shape_y();
    let control = BindControl::default();
    let bad = AutorigSettings {
        detail: 9,
        ..AutorigSettings::default()
    };
    let e = autorig(&mesh, &bad, &control).unwrap_err().to_string();
    assert!(e.contains("detail 9"), "{e}");
    let flat = Mesh::new(
        vec![v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)],
        vec![[0, 1, 2]],
        None,
        None,
    )
    .unwrap();
    let e = autorig(&flat, &AutorigSettings::default(), &control)
        .unwrap_err()
        .to_string();
    assert!(e.contains("no volume"), "{e}");
}

/// Two legs joined below the body (a bar between the knees) are one connected limb region;
/// each leg still gets a limb of its own (and so its own internal cage), the bar following one.
#[test]
fn legs_joined_below_the_body_are_limbs_of_their_own() {
    let mesh = capsules(
        &[
            (v(-0.6, 0.0, 1.4), v(0.6, 0.0, 1.4), 0.5),
            (v(-0.6, 0.0, 1.0), v(-0.6, 0.0, -1.6), 0.16),
            (v(0.6, 0.0, 1.0), v(0.6, 0.0, -1.6), 0.16),
            (v(-0.6, 0.0, -0.4), v(0.6, 0.0, -0.4), 0.12),
        ],
        0.04,
    );
    let scene = rig_with_internal_cages(&mesh, 3);
    let names: Vec<&str> = scene.cages.leaves.iter().map(|l| l.name.as_str()).collect();
    // Root segments: one per leg, each of its own limb (no "limbL_1b").
    let roots: Vec<&&str> = names
        .iter()
        .filter(|n| !n.starts_with("body") && n.contains("_1"))
        .collect();
    assert!(
        roots.len() >= 2 && roots.iter().all(|n| n.ends_with("_1")),
        "{names:?}"
    );
    let limb_boxes = limb_boxes(&scene);
    assert!(limb_boxes >= 2, "{limb_boxes} limb boxes: {names:?}");
}

/// A neck that forks into two horns, and a tail beside two legs, all joined to each other
/// outside the body: each horn, leg and the tail is a limb of its own, and the horns' boxes are
/// driven by the neck's box (posing the neck carries the horns).
#[test]
fn a_limb_that_forks_gets_a_limb_per_branch_under_the_limb_it_grows_from() {
    let mesh = capsules(
        &[
            // Body, lying along x.
            (v(-1.0, 0.0, 0.0), v(1.0, 0.0, 0.0), 0.55),
            // Neck up from the front, forking into two horns.
            (v(1.0, 0.0, 0.3), v(1.4, 0.0, 1.3), 0.2),
            (v(1.4, 0.0, 1.3), v(1.0, -0.7, 2.3), 0.12),
            (v(1.4, 0.0, 1.3), v(1.0, 0.7, 2.3), 0.12),
        ],
        0.04,
    );
    let scene = rig_with_internal_cages(&mesh, 3);
    assert!(surface_pieces_per_leaf(&scene).iter().all(|&n| n <= 1));
    // The limb holding the horn tips (the highest cage vertices on either side of y = 0).
    let limb_at = |side: f64| -> String {
        let set = &scene.cages;
        let leaf = set
            .leaves
            .iter()
            .filter(|l| !l.name.starts_with("body"))
            .max_by(|a, b| {
                let top = |l: &starcages_core::scene::LeafCage| {
                    l.faces
                        .iter()
                        .flatten()
                        .map(|&i| set.vertices[i as usize])
                        .filter(|p| p.y * side > 0.3)
                        .map(|p| p.z)
                        .fold(f64::NEG_INFINITY, f64::max)
                };
                top(a).total_cmp(&top(b))
            })
            .unwrap();
        leaf.name.split('_').next().unwrap().to_owned()
    };
    let (left, right) = (limb_at(-1.0), limb_at(1.0));
    assert_ne!(left, right, "both horns in one limb");
    // Each horn's first control is carried by another limb's control (the neck's), not by
    // the root.
    let internals = &scene.cages.internals;
    let vertices_of = |name: &str| -> std::collections::BTreeSet<u32> {
        internals
            .iter()
            .find(|c| c.name == name)
            .unwrap()
            .faces
            .iter()
            .flatten()
            .copied()
            .collect()
    };
    for horn in [&left, &right] {
        let own = vertices_of(&format!("{horn}.1"));
        let owner = internals
            .iter()
            .find(|c| c.owns.iter().any(|v| own.contains(v)))
            .unwrap();
        assert!(
            owner.name != "root" && !owner.name.starts_with(horn.as_str()),
            "{horn}.1 is driven by {}",
            owner.name
        );
    }
}

/// A lumpy blob (as scans are: lumps reaching out less than half their thickness) is a body
/// at every detail: the lumps get no chain of cages and no internal box of their own.
#[test]
fn lumps_on_a_body_are_not_limbs() {
    let field = |p: DVec3| {
        p.length() - 0.8 + 0.05 * (9.0 * p.x).sin() * (9.0 * p.y).sin() * (9.0 * p.z).sin()
    };
    let (positions, triangles) = surface_nets(field, DVec3::splat(-1.0), DVec3::splat(1.0), 0.03);
    let mesh = Mesh::new(positions, triangles, None, None).unwrap();
    for detail in [3, 4] {
        let scene = rig_with_internal_cages(&mesh, detail);
        let names: Vec<&str> = scene.cages.leaves.iter().map(|l| l.name.as_str()).collect();
        assert!(
            names.iter().all(|n| n.starts_with("body")),
            "detail {detail}: {names:?}"
        );
        assert_eq!(internal_names(&scene), ["root"], "detail {detail}");
    }
}

/// The cage vertices of `set` with no mirror image across the plane `axis` = `centre` among
/// them (to 1e-9), and its leaf cages with no mirror twin.
fn asymmetry(set: &CageSet, axis: usize, centre: f64) -> (usize, usize) {
    let key = |p: DVec3| ((p * 1e9).round().as_i64vec3()).to_array();
    let leaf_vertices: std::collections::BTreeSet<u32> = set
        .leaves
        .iter()
        .flat_map(|l| l.faces.iter().flatten().copied())
        .collect();
    let at: std::collections::BTreeMap<[i64; 3], u32> = leaf_vertices
        .iter()
        .map(|&i| (key(set.vertices[i as usize]), i))
        .collect();
    let image = |i: u32| {
        let mut p = set.vertices[i as usize];
        p[axis] = 2.0 * centre - p[axis];
        at.get(&key(p)).copied()
    };
    let lonely = leaf_vertices
        .iter()
        .filter(|&&i| image(i).is_none())
        .count();
    type FaceSet = std::collections::BTreeSet<std::collections::BTreeSet<Option<u32>>>;
    let faces_of = |faces: &[Vec<u32>], map: &dyn Fn(u32) -> Option<u32>| -> FaceSet {
        faces
            .iter()
            .map(|f| f.iter().map(|&v| map(v)).collect())
            .collect()
    };
    let leaves: Vec<FaceSet> = set
        .leaves
        .iter()
        .map(|l| faces_of(&l.faces, &Some))
        .collect();
    let twinless = set
        .leaves
        .iter()
        .filter(|l| !leaves.contains(&faces_of(&l.faces, &image)))
        .count();
    (lonely, twinless)
}

/// `--mirror`: on a figure whose two sides differ (one arm lower, one foot out, one leg thicker),
/// the rig is a mirror image of itself across the plane through the mesh's centre: every leaf
/// vertex has its image among the leaf vertices and every leaf cage a mirror twin. Without the
/// option, the same figure's rig is not symmetric (the negative control).
#[test]
fn a_mirrored_rig_is_its_own_mirror_image_on_a_lopsided_figure() {
    let mut parts = figure_parts();
    parts[3] = (v(0.3, 0.0, 1.0), v(1.5, 0.0, 0.6), 0.14);
    parts[4].1 = v(-0.35, 0.0, -1.6);
    parts[5].2 = 0.19;
    let mesh = capsules(&parts, 0.04);
    let (lo, hi) = mesh.bounds();
    let centre = 0.5 * (lo.x + hi.x);
    for (mirror, symmetric) in [(Mirror::Axis(0), true), (Mirror::None, false)] {
        let settings = AutorigSettings {
            mirror,
            controls: true,
            ..AutorigSettings::default()
        };
        let scene = scene(&mesh, rig(&mesh, &settings));
        assert!(validate_scene(&scene).is_valid(), "{mirror:?}");
        let (lonely, twinless) = asymmetry(&scene.cages, 0, centre);
        if symmetric {
            assert_eq!((lonely, twinless), (0, 0));
            let pieces = surface_pieces_per_leaf(&scene);
            assert!(pieces.iter().all(|&n| n <= 1), "{pieces:?}");
            assert!(limb_boxes(&scene) >= 4, "two arms and two legs");
        } else {
            assert!(lonely > 0 && twinless > 0, "{lonely} {twinless}");
        }
    }
}

/// The plane a mirrored rig is symmetric about along an axis of bounds `lo`..`hi`: the origin
/// where the mesh is centred on it within 1 % of its width, else the centre (docs/autorig.md).
fn mirror_plane(lo: f64, hi: f64) -> f64 {
    let centre = 0.5 * (lo + hi);
    if centre.abs() <= 0.01 * (hi - lo) {
        0.0
    } else {
        centre
    }
}

/// Cases of the random-shape property: 6 in the test suite, more with
/// `STARCAGES_AUTORIG_CASES` (each case rigs a mesh of a few thousand triangles).
fn random_shape_cases() -> u32 {
    std::env::var("STARCAGES_AUTORIG_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(6)
}

fn mirror_choice() -> impl Strategy<Value = Mirror> {
    prop_oneof![
        Just(Mirror::None),
        Just(Mirror::Auto),
        (0usize..3).prop_map(Mirror::Axis),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(random_shape_cases()))]

    /// Random unions of capsules under random settings: the auto rig never panics; it gives a
    /// valid scene (or says why not), and with a mirror axis a rig that is its own mirror image.
    #[test]
    fn random_shapes_get_a_valid_rig_symmetric_when_asked(
        capsule_list in proptest::collection::vec(
            (uniform3(-1.0f64..1.0), uniform3(-1.0f64..1.0), 0.12f64..0.4),
            1..5,
        ),
        detail in 1u32..=3,
        mirror in mirror_choice(),
        internal in any::<bool>(),
    ) {
        let parts: Vec<(DVec3, DVec3, f64)> = capsule_list
            .iter()
            .map(|&(a, b, r)| (DVec3::from_array(a), DVec3::from_array(b), r))
            .collect();
        let mesh = capsules(&parts, 0.07);
        let settings = AutorigSettings { detail, mirror, controls: internal, ..AutorigSettings::default() };
        match autorig(&mesh, &settings, &BindControl::default()) {
            Ok(rig) => {
                let axis = rig.report.mirror_axis;
                let scene = scene(&mesh, rig.cages);
                let report = validate_scene(&scene);
                prop_assert!(report.is_valid(), "{:?}", report.errors);
                if let Some(axis) = axis {
                    let (lo, hi) = mesh.bounds();
                    let plane = mirror_plane(lo[axis], hi[axis]);
                    prop_assert_eq!(asymmetry(&scene.cages, axis, plane), (0, 0));
                }
            }
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}

/// A mesh whose triangles are repeated in place (a file of 400 copies of one shape's faces,
/// each with its own vertices) gets the rig of the shape itself: exact duplicates add nothing
/// to the shape and are dropped before the work that scales with triangles (issue 42, class 5;
/// before, each copy was rasterised again and the rig came out different: 400 copies are
/// enough for that, and 2,000 took 12 s of the suite).
#[test]
fn duplicated_triangles_give_the_rig_of_the_shape_once() {
    let shape = shape_y();
    let (positions, triangles) = (shape.welded_positions(), shape.welded_triangles());
    let copies = 400;
    let mut all_positions = Vec::with_capacity(positions.len() * copies);
    let mut all_triangles = Vec::with_capacity(triangles.len() * copies);
    for copy in 0..copies {
        let base = (copy * positions.len()) as u32;
        all_positions.extend_from_slice(positions);
        all_triangles.extend(triangles.iter().map(|t| t.map(|v| v + base)));
    }
    let stacked = Mesh::new(all_positions, all_triangles, None, None).unwrap();
    assert_eq!(stacked.welded_positions().len(), positions.len());
    let settings = AutorigSettings::default();
    let (stacked_rig, shape_rig) = (rig(&stacked, &settings), rig(&shape, &settings));
    assert!(
        stacked_rig == shape_rig,
        "the stacked copies get another rig: {} leaf cages, the shape {}",
        stacked_rig.leaves.len(),
        shape_rig.leaves.len()
    );
}

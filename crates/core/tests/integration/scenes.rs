//! Scene model and files: demos validate, files round-trip, every validation problem is
//! reported with its cage and element, bad files get clear errors, saves are atomic.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use glam::DVec3;
use starcages_core::coords::CoordinateKind;
use starcages_core::generate::demo::{DEMOS, box_mesh, demo_scene};
use starcages_core::generate::{AutocageOptions, autocage};
use starcages_core::io::read_mesh;
use starcages_core::scene::{
    CageSet, InternalCage, LeafCage, MeshSource, OutsidePolicy, Scene, SceneFileError,
    SceneProblem, SceneSettings, UpAxis, load_scene, save_scene, validate_scene,
};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("starcages-scenes-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn problems(scene: &Scene) -> Vec<SceneProblem> {
    validate_scene(scene).errors
}

#[test]
fn every_demo_validates_and_round_trips() {
    let dir = scratch("demos");
    for (name, _) in DEMOS {
        let scene = demo_scene(name, 0.5).unwrap();
        let report = validate_scene(&scene);
        assert!(report.is_valid(), "{name}: {:?}", report.errors);
        let path = dir.join(format!("{name}.json"));
        save_scene(&scene, &path).unwrap();
        let back = load_scene(&path).unwrap();
        // Compare without printing whole scenes on failure.
        assert!(
            back == scene,
            "{name}: the scene changed in a save/load round trip"
        );
        // Saving the loaded scene gives the same bytes.
        let again = dir.join(format!("{name}-again.json"));
        save_scene(&back, &again).unwrap();
        assert_eq!(
            std::fs::read(&path).unwrap(),
            std::fs::read(&again).unwrap()
        );
    }
    let egg = demo_scene("egg", 0.5).unwrap();
    assert_eq!(egg.cages.leaves.len(), 12);
    assert!(demo_scene("nope", 1.0).is_none());
}

#[test]
fn mesh_files_are_referenced_relative_to_the_scene() {
    let dir = scratch("relative");
    let mesh = box_mesh(DVec3::splat(-1.0), DVec3::splat(1.0), [2, 2, 2]);
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    let mesh_path = dir.join("meshes").join("box.obj");
    starcages_core::io::write_mesh(&mesh_path, &mesh, mesh.positions()).unwrap();
    let mesh = read_mesh(&mesh_path).unwrap();
    let cages = autocage(&mesh, &AutocageOptions::default());
    let scene = Scene::new(
        MeshSource::File(mesh_path.clone()),
        mesh,
        cages,
        SceneSettings::default(),
    );
    let path = dir.join("scene.json");
    save_scene(&scene, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"path\": \"meshes/box.obj\""), "{text}");
    let back = load_scene(&path).unwrap();
    assert_eq!(back.cages, scene.cages);
    assert_eq!(back.mesh, scene.mesh);
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

#[test]
fn validation_names_cage_element_and_fix() {
    // Open cage.
    let mut s = two_box_scene();
    s.cages.leaves[0].faces.pop();
    let p = problems(&s);
    assert!(
        matches!(&p[0], SceneProblem::Cage { cage, .. } if cage == "cage_0_0_0"),
        "{p:?}"
    );
    assert!(p[0].to_string().contains("not closed"), "{}", p[0]);

    // Inward cage: also runs the shared face the same way as its neighbour.
    let mut s = two_box_scene();
    for f in &mut s.cages.leaves[1].faces {
        f.reverse();
    }
    let p = problems(&s);
    assert!(
        p.iter().any(|e| e.to_string().contains("oriented inwards")),
        "{p:?}"
    );
    assert!(
        p.iter()
            .any(|e| matches!(e, SceneProblem::SharedFaceSameOrientation { .. })),
        "{p:?}"
    );

    // Overlap: move the left cage's right face into the right cage.
    let mut s = two_box_scene();
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
        *p = glam::DVec3::new(0.5, p.y * 0.9, p.z * 0.9);
    }
    // Give the right cage its own copies of the old border so both cages stay closed.
    let offset = moved.vertices.len() as u32;
    let border: Vec<u32> = (0..moved.vertices.len() as u32)
        .filter(|&v| moved.vertices[v as usize].x == 0.5)
        .collect();
    for &v in &border {
        let p = moved.vertices[v as usize];
        moved
            .vertices
            .push(glam::DVec3::new(0.0, p.y / 0.9, p.z / 0.9));
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
    let p = problems(&s);
    assert!(
        p.iter()
            .any(|e| matches!(e, SceneProblem::MeshVertexInTwoCages { .. })),
        "{p:?}"
    );
    assert!(
        p.iter()
            .any(|e| matches!(e, SceneProblem::CageVertexInsideCage { .. })),
        "{p:?}"
    );

    // Mesh outside every cage: error by default, warning with the 'nearest' policy.
    let mut s = two_box_scene();
    for v in &mut s.cages.vertices {
        v.x *= 0.8;
    }
    s.pose = s.cages.vertices.clone();
    s.poses.clear();
    let p = problems(&s);
    let outside = p.iter().find_map(|e| match e {
        SceneProblem::MeshOutside {
            count, vertices, ..
        } => Some((*count, vertices.clone())),
        _ => None,
    });
    let (count, vertices) = outside.expect("outside vertices reported");
    assert!(
        count > 0
            && vertices
                .iter()
                .all(|&v| s.mesh.welded_positions()[v].x.abs() > 0.88 - 1e-9)
    );
    assert!(p.iter().any(|e| {
        e.to_string()
            .contains("set the scene's outside policy to 'nearest'")
    }));
    s.settings.outside = OutsidePolicy::Nearest;
    let report = validate_scene(&s);
    assert!(report.is_valid(), "{:?}", report.errors);
    assert_eq!(report.warnings.len(), 1);

    // Bad h values, unknown border, duplicate names, pose length.
    let mut s = two_box_scene();
    s.cages.leaves[0].h = Some(1.5);
    s.cages.leaves[0].border_h.insert("nobody".into(), 0.5);
    s.cages.leaves[1].name = "cage_0_0_0".into();
    s.poses.insert("short".into(), vec![DVec3::ZERO; 3]);
    let p = problems(&s);
    assert!(
        p.iter()
            .any(|e| matches!(e, SceneProblem::InvalidH { h, .. } if *h == 1.5)),
        "{p:?}"
    );
    assert!(p.iter().any(
        |e| matches!(e, SceneProblem::UnknownBorder { neighbour, .. } if neighbour == "nobody")
    ));
    // The scene's default h is a setting, and an extreme value prints short.
    let mut d = two_box_scene();
    d.settings.default_h = 1e308;
    let default_problems = problems(&d);
    assert!(
        default_problems.iter().any(|e| e.to_string()
            == "settings: default_h = 1e308 is outside (0, 1]; choose a value in that range \
                (0.5 is the default)"),
        "{default_problems:?}"
    );
    assert!(
        p.iter()
            .any(|e| matches!(e, SceneProblem::DuplicateName { .. }))
    );
    assert!(
        p.iter()
            .any(|e| matches!(e, SceneProblem::PoseLength { pose, got: 3, .. } if pose == "short"))
    );
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

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn bad_scene_files_get_clear_errors() {
    let dir = scratch("bad-files");
    let good = dir.join("good.json");
    save_scene(&two_box_scene(), &good).unwrap();
    let text = std::fs::read_to_string(&good).unwrap();

    let truncated = write(&dir, "truncated.json", &text[..text.len() / 2]);
    let e = load_scene(&truncated).unwrap_err().to_string();
    assert!(
        e.contains("truncated.json: not a valid scene file") && e.contains("line"),
        "{e}"
    );

    let garbled = write(
        &dir,
        "garbled.json",
        &text.replacen("\"cages\"", "\"cagez\"", 1),
    );
    let e = load_scene(&garbled).unwrap_err().to_string();
    assert!(e.contains("cagez") || e.contains("cages"), "{e}");

    let nan = write(&dir, "nan.json", &text.replacen("-1.1", "NaN", 1));
    assert!(matches!(
        load_scene(&nan),
        Err(SceneFileError::Syntax { .. })
    ));

    let newer = write(
        &dir,
        "newer.json",
        &text.replacen("\"version\": 3", "\"version\": 7", 1),
    );
    let e = load_scene(&newer).unwrap_err().to_string();
    assert!(
        e.contains("newer StarCages") && e.contains("version 7"),
        "{e}"
    );

    let other = write(
        &dir,
        "other.json",
        "{\"format\": \"blender\", \"version\": 1}",
    );
    let e = load_scene(&other).unwrap_err().to_string();
    assert!(e.contains("not a StarCages scene"), "{e}");

    let missing_mesh = write(
        &dir,
        "missing-mesh.json",
        &text.replacen(
            &text[text.find("\"mesh\"").unwrap()..text.rfind('}').unwrap()],
            "\"mesh\": {\"path\": \"nowhere/mesh.obj\"}\n",
            1,
        ),
    );
    let e = load_scene(&missing_mesh).unwrap_err().to_string();
    assert!(e.contains("nowhere/mesh.obj: cannot read"), "{e}");

    let nan_mesh = write(&dir, "nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
    let e = read_mesh(&nan_mesh).unwrap_err().to_string();
    assert!(e.contains("nan.obj"), "{e}");
}

#[test]
fn failed_save_keeps_the_old_file_and_says_why() {
    let dir = scratch("failed-save");
    // The temporary file's name (".NAME.XXXXXX.starcages-tmp") is longer than the file's own:
    // with a name near the file-system limit the temporary file cannot be made, for root too.
    let path = dir.join(format!("{}.json", "s".repeat(236)));
    std::fs::write(&path, b"the old scene").unwrap();
    let before = std::fs::read(&path).unwrap();
    let mut changed = two_box_scene();
    changed.cages.leaves[0].h = Some(0.3);
    let e = save_scene(&changed, &path).unwrap_err().to_string();
    assert!(e.contains("cannot save") && e.contains("unchanged"), "{e}");
    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        1,
        "no temporary file left"
    );
    // A read-only folder, where permissions apply (not for root).
    let readonly = scratch("readonly");
    let target = readonly.join("scene.json");
    save_scene(&two_box_scene(), &target).unwrap();
    let original = std::fs::read(&target).unwrap();
    set_readonly(&readonly, true);
    let result = save_scene(&changed, &target);
    set_readonly(&readonly, false);
    if let Err(e) = result {
        assert!(e.to_string().contains("cannot save"), "{e}");
        assert_eq!(std::fs::read(&target).unwrap(), original);
    }
}

#[cfg(unix)]
fn set_readonly(dir: &Path, readonly: bool) {
    use std::os::unix::fs::PermissionsExt as _;
    std::fs::set_permissions(
        dir,
        std::fs::Permissions::from_mode(if readonly { 0o555 } else { 0o755 }),
    )
    .unwrap();
}

#[cfg(not(unix))]
fn set_readonly(dir: &Path, readonly: bool) {
    let mut p = std::fs::metadata(dir).unwrap().permissions();
    p.set_readonly(readonly);
    std::fs::set_permissions(dir, p).unwrap();
}

#[test]
fn leaf_cage_settings_survive_a_round_trip() {
    let dir = scratch("settings");
    let mut s = two_box_scene();
    s.cages.leaves[0].h = Some(0.25);
    s.cages.leaves[0].border_h.insert("cage_1_0_0".into(), 0.75);
    s.cages.leaves[1].kind = CoordinateKind::Harmonic;
    s.settings.default_h = 0.4;
    s.pose[0].y += 0.1;
    let _: &LeafCage = &s.cages.leaves[0];
    let path = dir.join("s.json");
    save_scene(&s, &path).unwrap();
    assert!(
        load_scene(&path).unwrap() == s,
        "settings changed in a round trip"
    );
    assert!(
        validate_scene(&s).is_valid(),
        "{:?}",
        validate_scene(&s).errors
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

#[test]
fn huge_or_non_finite_coordinates_are_refused_and_never_written() {
    for value in [1e100, f64::INFINITY, f64::NAN, -2e9] {
        let mut scene = two_box_scene();
        scene.pose[3].y = value;
        let report = validate_scene(&scene);
        assert!(
            report.errors.iter().any(|e| matches!(
                e,
                SceneProblem::CoordinateOutOfRange { vertex: 3, pose } if pose == "the current pose"
            )),
            "{value}: {:?}",
            report.errors
        );
        let mut scene = two_box_scene();
        scene.poses.insert("far".into(), scene.pose.clone());
        scene.poses.get_mut("far").unwrap()[0].x = value;
        let text = validate_scene(&scene).errors[0].to_string();
        assert!(
            text.contains("pose 'far'") && text.contains("vertex 0"),
            "{text}"
        );
    }
    // A mesh with an infinite vertex is not written at all.
    let dir = scratch("non-finite");
    let scene = two_box_scene();
    let mut positions = scene.mesh.positions().to_vec();
    positions[1].z = f64::INFINITY;
    for name in ["out.obj", "out.glb"] {
        let path = dir.join(name);
        let error = starcages_core::io::write_mesh(&path, &scene.mesh, &positions)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("non-finite") && error.contains("vertex 1"),
            "{error}"
        );
        assert!(!path.exists());
    }
}

#[test]
fn text_files_with_a_bom_read_whole_and_cut_obj_files_name_their_line() {
    let dir = scratch("obj-lines");
    let bom = write(
        &dir,
        "bom.obj",
        "\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let mesh = read_mesh(&bom).unwrap();
    assert_eq!(
        mesh.positions().len(),
        3,
        "the first vertex is not lost to the BOM"
    );
    let cut = write(
        &dir,
        "cut.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1/1 2",
    );
    let error = read_mesh(&cut).unwrap_err().to_string();
    assert!(
        error.contains("cut.obj:6:") && error.contains("2 corner(s)"),
        "{error}"
    );
    let nan_uv = write(
        &dir,
        "uv.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt nan 0\nf 1/1 2/1 3/1\n",
    );
    let error = read_mesh(&nan_uv).unwrap_err().to_string();
    assert!(
        error.contains("uv.obj:4:") && error.contains("not finite"),
        "{error}"
    );
    // A mesh coordinate of 1e308 is named as such (it made cages of that size, which then
    // failed validation with messages about cages).
    let huge = write(
        &dir,
        "huge.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1e308 1 1\nf 1 2 3\nf 1 2 4\n",
    );
    let error = read_mesh(&huge).unwrap_err().to_string();
    assert!(
        error.contains("huge.obj") && error.contains("magnitude 1e308, beyond ±1e9"),
        "{error}"
    );
    // Every text reader drops a byte-order mark: cage OBJ, points, scene JSON.
    let cage = write(
        &dir,
        "bom-cage.obj",
        "\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    );
    let cage = starcages_core::io::read_cage_obj(&cage).unwrap();
    assert_eq!(cage.vertex_count(), 4);
    let points = write(&dir, "bom-points.txt", "\u{feff}0.5 0.25 0\n");
    assert_eq!(
        starcages_core::io::read_points(&points).unwrap(),
        vec![DVec3::new(0.5, 0.25, 0.0)]
    );
    let scene_path = dir.join("bom-scene.json");
    save_scene(&demo_scene("bar", 0.3).unwrap(), &scene_path).unwrap();
    let text = std::fs::read_to_string(&scene_path).unwrap();
    std::fs::write(&scene_path, format!("\u{feff}{text}")).unwrap();
    load_scene(&scene_path).unwrap();
}

#[test]
fn scene_version_zero_is_refused() {
    let dir = scratch("version-zero");
    let path = dir.join("scene.json");
    save_scene(&two_box_scene(), &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"version\": 3"));
    std::fs::write(&path, text.replace("\"version\": 3", "\"version\": 0")).unwrap();
    let error = load_scene(&path).unwrap_err().to_string();
    assert!(
        error.contains("scene.json") && error.contains("start at 1"),
        "{error}"
    );
}

#[cfg(unix)]
#[test]
fn devices_and_folders_are_refused_as_inputs_without_reading_them() {
    let dir = scratch("devices");
    let link = dir.join("zero.obj");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let gltf_link = dir.join("zero.gltf");
    std::os::unix::fs::symlink("/dev/zero", &gltf_link).unwrap();
    let error = read_mesh(&gltf_link).unwrap_err().to_string();
    assert!(error.contains("not a regular file"), "{error}");
    let error = read_mesh(&link).unwrap_err().to_string();
    assert!(error.contains("not a regular file"), "{error}");
    let folder = dir.join("folder.obj");
    std::fs::create_dir_all(&folder).unwrap();
    let error = read_mesh(&folder).unwrap_err().to_string();
    assert!(error.contains("not a regular file"), "{error}");
    // Reading a device would never end: the run's time limit is the guard, not a clock here.
}

#[test]
fn scene_shape_errors_name_the_line_and_the_field() {
    let dir = scratch("shape-errors");
    let path = dir.join("scene.json");
    save_scene(&two_box_scene(), &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let cases = [
        (
            text.replacen("\"default_h\": 0.5", "\"default_h\": \"x\"", 1),
            "field 'settings.default_h'",
            "invalid type",
        ),
        (
            text.replacen("\"faces\"", "\"facez\"", 1),
            "field 'cages[0]",
            "",
        ),
        (
            text.replacen("\"kind\": \"mvc\"", "\"kind\": 5", 1),
            "field 'cages[0].kind'",
            "expected a name in quotes here (such as \"mvc\"",
        ),
    ];
    for (broken, field, reason) in cases {
        assert_ne!(broken, text, "the test edits the file");
        std::fs::write(&path, &broken).unwrap();
        let error = load_scene(&path).unwrap_err().to_string();
        assert!(
            error.contains("scene.json:") && error.contains(field),
            "{error}"
        );
        assert!(error.contains(reason), "{error}");
        // The line named holds the offending text or follows it.
        let line: usize = error
            .split("scene.json:")
            .nth(1)
            .and_then(|rest| rest.split(':').next())
            .and_then(|n| n.parse().ok())
            .unwrap();
        assert!(line >= 1 && line <= broken.lines().count(), "{error}");
    }
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
    let p = problems(&unwelded);
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

/// A deformed OBJ export is a copy of the source OBJ: the same `v` list (count and order, so
/// it works as a shape key), texture coordinates with their seams, normals' layout, groups,
/// material references and comments; at rest its positions are the source's.
#[test]
fn obj_exports_keep_the_source_layout_and_rest_is_the_source() {
    let dir = scratch("faithful-obj");
    // A Y-up box with a UV seam (corner 1 has two texture coordinates), per-face normals,
    // two groups, a material library and a comment.
    let source = "# made by hand\nmtllib box.mtl\no box\n\
        v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n\
        vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n\
        g bottom\nusemtl red\nf 1/1/1 3/2/1 4/3/1 2/4/1\nf 5/5/2 6/2/2 8/3/2 7/4/2\n\
        g sides\nusemtl blue\nf 1/1/3 2/2/3 6/3/3 5/4/3\nf 3/1/4 7/2/4 8/3/4 4/4/4\n\
        f 1/5/5 5/2/5 7/3/5 3/4/5\nf 2/1/6 4/2/6 8/3/6 6/4/6\n";
    let mesh_path = write(&dir, "box.obj", source);
    let mesh = starcages_core::io::read_mesh_as(&mesh_path, UpAxis::Y).unwrap();
    let cages = autocage(&mesh, &AutocageOptions::default());
    let mut scene = Scene::new(
        MeshSource::File(mesh_path.clone()),
        mesh,
        cages,
        SceneSettings::default(),
    );
    scene.mesh_up = UpAxis::Y;
    let binding = starcages_core::star::StarBinding::bind_scene(
        &scene,
        &starcages_core::BindControl::default(),
    )
    .unwrap();
    let deform = |pose: &[DVec3]| -> Vec<DVec3> {
        binding
            .deform(&scene.cages.vertices, pose)
            .iter()
            .map(|p| p.as_dvec3())
            .collect()
    };
    let is_data = |l: &&str| l.starts_with("v ") || l.starts_with("vn ");
    // At rest: the source, numbers to float precision.
    let rest = dir.join("rest.obj");
    starcages_core::scene::write_deformed_mesh(&rest, &scene, &deform(&scene.pose)).unwrap();
    let written = std::fs::read_to_string(&rest).unwrap();
    let (src_lines, out_lines): (Vec<&str>, Vec<&str>) =
        (source.lines().collect(), written.lines().collect());
    assert_eq!(src_lines.len(), out_lines.len());
    for (a, b) in src_lines.iter().zip(&out_lines) {
        if is_data(a) {
            let numbers = |l: &str| -> Vec<f64> {
                l.split_whitespace()
                    .skip(1)
                    .map(|x| x.parse().unwrap())
                    .collect()
            };
            for (x, y) in numbers(a).iter().zip(numbers(b)) {
                assert!((x - y).abs() < 1e-5, "{a} vs {b}");
            }
        } else {
            assert_eq!(a, b, "a line that is not data changed");
        }
    }
    // Posed: positions move, everything else stays; the file reads back with the same counts.
    let mut pose = scene.pose.clone();
    for p in &mut pose {
        p.z *= 1.5;
    }
    let posed = dir.join("posed.obj");
    starcages_core::scene::write_deformed_mesh(&posed, &scene, &deform(&pose)).unwrap();
    let written = std::fs::read_to_string(&posed).unwrap();
    let kept: Vec<&str> = written.lines().filter(|l| !is_data(l)).collect();
    let original: Vec<&str> = source.lines().filter(|l| !is_data(l)).collect();
    assert_eq!(kept, original);
    let tall = written
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|rest| {
            rest.split_whitespace()
                .nth(1)
                .unwrap()
                .parse::<f64>()
                .unwrap()
        })
        .fold(f64::MIN, f64::max);
    // Scene z is the file's y: the box is stretched along the file's up axis.
    assert!(tall > 1.2, "the pose did not reach the file: {tall}");
    let back = read_mesh(&posed).unwrap();
    assert_eq!(
        back.positions().len(),
        read_mesh(&mesh_path).unwrap().positions().len()
    );
    // The source changed on disk: refused with the reason, nothing written.
    std::fs::write(&mesh_path, source.replace("v 1 1 1\n", "v 1 1 2\n")).unwrap();
    let stale = dir.join("stale.obj");
    let error = starcages_core::scene::write_deformed_mesh(&stale, &scene, &deform(&pose))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("changed since the scene was opened"),
        "{error}"
    );
    assert!(!stale.exists());
}

/// Version-1 scenes read their mesh files as they are (they were made that way): migrated with
/// "z", their mesh stays where their cages are; new scenes record the file's axis.
#[test]
fn version_1_scenes_keep_their_mesh_as_is_and_new_ones_record_the_up_axis() {
    let dir = scratch("up-axis-migration");
    let mesh_path = write(
        &dir,
        "tall.obj",
        "v 0 0 0\nv 1 0 0\nv 0 4 0\nv 1 4 0\nv 0 0 1\nv 1 0 1\nv 0 4 1\nv 1 4 1\n\
         f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n",
    );
    let mesh = starcages_core::io::read_mesh_as(&mesh_path, UpAxis::Y).unwrap();
    assert!(
        (mesh.bounds().1.z - 4.0).abs() < 1e-12,
        "Y-up turned to Z-up"
    );
    let cages = autocage(&mesh, &AutocageOptions::default());
    let mut scene = Scene::new(
        MeshSource::File(mesh_path.clone()),
        mesh,
        cages,
        SceneSettings::default(),
    );
    scene.mesh_up = UpAxis::Y;
    let path = dir.join("tall.json");
    save_scene(&scene, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"mesh_up_axis\": \"y\""), "{text}");
    let back = load_scene(&path).unwrap();
    assert_eq!(back.mesh_up, UpAxis::Y);
    assert_eq!(back.mesh.bounds(), scene.mesh.bounds());
    // The same file as version 1 wrote it: no axis, version 1.
    let v1: String = text
        .lines()
        .filter(|l| !l.contains("mesh_up_axis"))
        .collect::<Vec<_>>()
        .join("\n")
        .replace("\"version\": 3", "\"version\": 1");
    std::fs::write(&path, v1).unwrap();
    let old = load_scene(&path).unwrap();
    assert_eq!(old.mesh_up, UpAxis::Z);
    assert!(
        (old.mesh.bounds().1.y - 4.0).abs() < 1e-12,
        "a version-1 mesh was turned"
    );
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

/// A glTF source (Y-up by specification) with a UV seam: its rest export is the source's
/// vertices, count and order, to float precision, turned back to Y-up.
#[test]
fn glb_exports_keep_the_source_vertex_order_and_axes() {
    let dir = scratch("glb-round-trip");
    // A Y-up square pyramid: the apex is duplicated with two UVs (a seam).
    let positions = [
        DVec3::new(-1.0, 0.0, -1.0),
        DVec3::new(1.0, 0.0, -1.0),
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::new(-1.0, 0.0, 1.0),
        DVec3::new(0.0, 2.0, 0.0),
        DVec3::new(0.0, 2.0, 0.0),
    ];
    let triangles = [
        [0, 1, 2],
        [0, 2, 3],
        [0, 4, 1],
        [1, 4, 2],
        [2, 5, 3],
        [3, 5, 0],
    ];
    let normals = [glam::Vec3::Y; 6];
    let uvs = [
        glam::Vec2::new(0.0, 0.0),
        glam::Vec2::new(1.0, 0.0),
        glam::Vec2::new(1.0, 1.0),
        glam::Vec2::new(0.0, 1.0),
        glam::Vec2::new(0.5, 0.5),
        glam::Vec2::new(0.25, 0.75),
    ];
    let source = dir.join("pyramid.glb");
    let bytes = starcages_core::io::glb_bytes(&positions, &triangles, &normals, Some(&uvs));
    std::fs::write(&source, bytes).unwrap();
    let mesh = starcages_core::io::read_mesh_as(&source, UpAxis::Y).unwrap();
    assert!(
        (mesh.bounds().1.z - 2.0).abs() < 1e-12,
        "the apex points up along Z"
    );
    assert_eq!(
        mesh.welded_positions().len(),
        5,
        "the seam's two apex vertices weld"
    );
    let cages = autocage(&mesh, &AutocageOptions::default());
    let scene = Scene::from_mesh_file(
        source.clone(),
        UpAxis::Y,
        mesh,
        cages,
        SceneSettings::default(),
    );
    let binding = starcages_core::star::StarBinding::bind_scene(
        &scene,
        &starcages_core::BindControl::default(),
    )
    .unwrap();
    let rest: Vec<DVec3> = binding
        .deform(&scene.cages.vertices, &scene.pose)
        .iter()
        .map(|p| p.as_dvec3())
        .collect();
    let out = dir.join("rest.glb");
    starcages_core::scene::write_deformed_mesh(&out, &scene, &rest).unwrap();
    let back = read_mesh(&out).unwrap();
    assert_eq!(back.positions().len(), positions.len());
    for (a, b) in positions.iter().zip(back.positions()) {
        assert!(a.distance(*b) < 1e-5, "{a} vs {b}");
    }
    assert_eq!(back.uvs().unwrap(), &uvs[..], "UVs and the seam kept");
}

/// One frame convention for written files (issue 26): an embedded mesh's files follow the axes
/// the scene declares for it (`mesh_up_axis`), a demo declares Y-up, and GLB is Y-up whatever
/// the scene says, also for a mesh read from a Z-up OBJ.
#[test]
fn written_meshes_follow_the_declared_axes_and_glb_is_always_y_up() {
    let dir = scratch("declared-axes");
    // A box taller along scene z than along x and y.
    let mesh = box_mesh(
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 3.0),
        [1, 1, 1],
    );
    let mut scene = demo_scene("bar", 0.2).unwrap();
    assert_eq!(scene.export_up(), UpAxis::Y, "demos declare Y-up");
    scene.mesh = mesh.clone();
    let welded = mesh.welded_positions().to_vec();
    let tallest_axis = |path: &Path| {
        let m = read_mesh(path).unwrap();
        let (lo, hi) = m.bounds();
        (hi - lo)
            .to_array()
            .iter()
            .copied()
            .enumerate()
            .fold(
                (0, 0.0),
                |best, (k, e)| {
                    if e > best.1 { (k, e) } else { best }
                },
            )
            .0
    };
    for (up, obj_axis) in [(UpAxis::Z, 2), (UpAxis::Y, 1)] {
        scene.mesh_up = up;
        let obj = dir.join(format!("{}.obj", up.name()));
        starcages_core::scene::write_deformed_mesh(&obj, &scene, &welded).unwrap();
        // read_mesh reads the OBJ's numbers as they are: the tall side is the declared up.
        assert_eq!(
            tallest_axis(&obj),
            obj_axis,
            "OBJ of a scene declaring {up:?}"
        );
        let glb = dir.join(format!("{}.glb", up.name()));
        starcages_core::scene::write_deformed_mesh(&glb, &scene, &welded).unwrap();
        // read_mesh reads a GLB as it is too: Y-up whatever the scene declares.
        assert_eq!(tallest_axis(&glb), 1, "GLB of a scene declaring {up:?}");
    }
}

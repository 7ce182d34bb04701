//! End-to-end tests of the scene commands: demo, validate, info, autocage, autorig, new, cages.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use crate::common;

use common::{BOX_OBJ, cli, dir, ok, s, stderr, stdout};

#[test]
fn demos_are_listed_written_valid_and_described() {
    let out = dir("demo");
    let list = cli(&["demo", "--list"]);
    assert!(list.status.success());
    for name in ["bar", "prism", "egg", "bumpy"] {
        assert!(stdout(&list).contains(name));
    }
    let written = cli(&["demo", "all", "--out", s(&out), "--detail", "0.3"]);
    assert!(written.status.success(), "{}", stderr(&written));
    for name in ["bar", "prism", "egg", "bumpy"] {
        let scene = out.join(format!("{name}.json"));
        let v = cli(&["validate", s(&scene)]);
        assert!(v.status.success(), "{name}: {}", stderr(&v));
    }
    let info = cli(&["info", s(&out.join("egg.json")), "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(json["cages"].as_array().unwrap().len(), 12);
    assert_eq!(json["cages"][2]["kind"], "gc");
    assert_eq!(json["cages"][0]["level"], "leaf");
    assert_eq!(json["cage_vertices"], 36);
    assert!(json["mesh"]["triangles"].as_u64().unwrap() > 100);
    let unknown = cli(&["demo", "nope", "--out", s(&out)]);
    assert_eq!(unknown.status.code(), Some(2));
    assert!(stderr(&unknown).contains("unknown demo 'nope'"));
}

#[test]
fn autocage_new_and_cages_round_trip() {
    let d = dir("autocage");
    // A mesh file to cage: the bar demo's mesh, exported through `cages`-like OBJ writing.
    let mesh = d.join("box.obj");
    std::fs::write(&mesh, BOX_OBJ).unwrap();
    let scene = d.join("auto.json");
    let auto = cli(&[
        "autocage",
        s(&mesh),
        "--grid",
        "2",
        "1",
        "1",
        "--kind",
        "gc",
        "--out",
        s(&scene),
    ]);
    assert!(auto.status.success(), "{}", stderr(&auto));
    assert!(
        std::fs::read_to_string(&scene)
            .unwrap()
            .contains("\"path\": \"box.obj\"")
    );
    assert!(cli(&["validate", s(&scene)]).status.success());

    // Cages out, then back in through `new`.
    let cages = d.join("cages.obj");
    assert!(
        cli(&["cages", s(&scene), "--out", s(&cages)])
            .status
            .success()
    );
    let rebuilt = d.join("rebuilt.json");
    let new = cli(&[
        "new",
        s(&mesh),
        "--cages",
        s(&cages),
        "--kind",
        "hc",
        "--out",
        s(&rebuilt),
    ]);
    assert!(new.status.success(), "{}", stderr(&new));
    let info = cli(&["info", s(&rebuilt), "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(json["cages"].as_array().unwrap().len(), 2);
    assert_eq!(json["cages"][1]["kind"], "hc");
    assert_eq!(json["cage_vertices"], 12);

    let missing = cli(&["cages", s(&scene), "--pose", "nope", "--out", s(&cages)]);
    assert_eq!(missing.status.code(), Some(2));
    assert!(
        stderr(&missing).contains("no pose named 'nope'"),
        "{}",
        stderr(&missing)
    );
}

#[test]
fn invalid_scenes_and_files_exit_with_status_2() {
    let d = dir("invalid");
    let mesh = d.join("box.obj");
    std::fs::write(&mesh, BOX_OBJ).unwrap();
    // A cage too small for the mesh: the scene is written, but does not validate.
    let small = d.join("small.obj");
    std::fs::write(
        &small,
        "o tiny\nv 0 0 0\nv .5 0 0\nv 0 .5 0\nv .5 .5 0\nv 0 0 .5\nv .5 0 .5\nv 0 .5 .5\nv .5 .5 .5\n\
         f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n",
    )
    .unwrap();
    let scene = d.join("small.json");
    let new = cli(&["new", s(&mesh), "--cages", s(&small), "--out", s(&scene)]);
    assert_eq!(new.status.code(), Some(2));
    assert!(
        stderr(&new).contains("mesh vertices lie outside every leaf cage"),
        "{}",
        stderr(&new)
    );
    let validate = cli(&["validate", s(&scene)]);
    assert_eq!(validate.status.code(), Some(2));
    let nearest = d.join("nearest.json");
    let ok = cli(&[
        "new",
        s(&mesh),
        "--cages",
        s(&small),
        "--outside",
        "nearest",
        "--out",
        s(&nearest),
    ]);
    assert!(ok.status.success(), "{}", stderr(&ok));
    assert!(stderr(&ok).contains("warning"));

    let newer = d.join("newer.json");
    let text =
        std::fs::read_to_string(&nearest)
            .unwrap()
            .replacen("\"version\": 3", "\"version\": 99", 1);
    std::fs::write(&newer, text).unwrap();
    let refused = cli(&["info", s(&newer)]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(
        stderr(&refused).contains("newer StarCages"),
        "{}",
        stderr(&refused)
    );

    let garbage = d.join("garbage.json");
    std::fs::write(
        &garbage,
        "{\"format\": \"starcages-scene\", \"version\": 1, \"cages\": [",
    )
    .unwrap();
    let bad = cli(&["validate", s(&garbage)]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        stderr(&bad).contains("garbage.json: not a valid scene file"),
        "{}",
        stderr(&bad)
    );
}

/// `v` lines of an OBJ file as numbers, in file order.
fn obj_positions(path: &std::path::Path) -> Vec<[f64; 3]> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|rest| {
            let n: Vec<f64> = rest
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            [n[0], n[1], n[2]]
        })
        .collect()
}

/// An OBJ file is Y-up: a tower tall along Y stands up along the scene's Z, the scene records
/// the axis, and every file written back (deformed mesh at rest, cages) is in the file's axes:
/// a round trip is the identity.
#[test]
fn y_up_obj_files_stand_up_and_round_trip_unchanged() {
    let d = dir("up-axis");
    let tower = d.join("tower.obj");
    // A box 1 wide, 4 tall along Y, 1 deep.
    let text = "v 0 0 0\nv 1 0 0\nv 0 4 0\nv 1 4 0\nv 0 0 1\nv 1 0 1\nv 0 4 1\nv 1 4 1\n\
                f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    std::fs::write(&tower, text).unwrap();
    let scene = d.join("tower.json");
    // No --grid: the one default grid.
    ok(&cli(&["autocage", s(&tower), "--out", s(&scene)]));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    assert_eq!(json["mesh_up_axis"], "y");
    assert_eq!(json["version"], 3);
    let info = cli(&["info", s(&scene), "--json"]);
    let info: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    let (lo, hi) = (&info["mesh"]["bounds_min"], &info["mesh"]["bounds_max"]);
    let height = hi[2].as_f64().unwrap() - lo[2].as_f64().unwrap();
    let depth = hi[1].as_f64().unwrap() - lo[1].as_f64().unwrap();
    assert!(
        (height - 4.0).abs() < 1e-9 && (depth - 1.0).abs() < 1e-9,
        "the tower lies down: {info}"
    );
    // The rest pose written back is the source file, vertex for vertex.
    let rest = d.join("rest.obj");
    ok(&cli(&["deform", s(&scene), "--out", s(&rest)]));
    let (source, written) = (obj_positions(&tower), obj_positions(&rest));
    assert_eq!(source.len(), written.len());
    for (a, b) in source.iter().zip(&written) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() < 1e-6, "{a:?} vs {b:?}");
        }
    }
    // Cages come out in the file's axes too (tall along Y), and go back in as a pose.
    let cages = d.join("cages.obj");
    ok(&cli(&["cages", s(&scene), "--out", s(&cages)]));
    let cage_positions = obj_positions(&cages);
    let span = |k: usize| {
        let values = cage_positions.iter().map(|p| p[k]);
        values.clone().fold(f64::MIN, f64::max) - values.fold(f64::MAX, f64::min)
    };
    assert!(
        span(1) > 4.0 && span(2) < 2.0,
        "cages not in the file's axes"
    );
    let posed = d.join("posed.obj");
    ok(&cli(&[
        "deform",
        s(&scene),
        "--pose-file",
        s(&cages),
        "--out",
        s(&posed),
    ]));
    for (a, b) in source.iter().zip(&obj_positions(&posed)) {
        for k in 0..3 {
            assert!(
                (a[k] - b[k]).abs() < 1e-6,
                "pose file not turned back: {a:?} vs {b:?}"
            );
        }
    }
    // --up z reads the file as it is; glTF cannot be told to be Z-up.
    let as_is = d.join("as-is.json");
    ok(&cli(&[
        "autocage",
        s(&tower),
        "--up",
        "z",
        "--out",
        s(&as_is),
    ]));
    let info = cli(&["info", s(&as_is), "--json"]);
    let info: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert!((info["mesh"]["bounds_max"][1].as_f64().unwrap() - 4.0).abs() < 1e-9);
    let glb = d.join("tower.glb");
    std::fs::write(&glb, b"glTF").unwrap();
    let refused = cli(&["autocage", s(&glb), "--up", "z", "--out", s(&as_is)]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(stderr(&refused).contains("Y-up by specification"));
    // FBX declares its axes too; a file that is not one is refused naming it.
    let fbx = d.join("tower.fbx");
    std::fs::write(&fbx, b"Kaydara FBX Binary").unwrap();
    let refused = cli(&["autocage", s(&fbx), "--up", "z", "--out", s(&as_is)]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(stderr(&refused).contains("declares its own axes"));
    let refused = cli(&["autorig", s(&fbx), "--out", s(&as_is)]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(stderr(&refused).contains("tower.fbx: not a readable FBX file"));
}

/// `edit` builds a rig from nothing around a mesh with a script of operations, validates and
/// deforms it; an operation that cannot apply names itself and writes nothing.
#[test]
fn edit_builds_a_rig_from_nothing_and_refuses_a_bad_op_writing_nothing() {
    let d = dir("edit");
    let tower = write_tower(&d);
    let scene = d.join("rig.json");
    // Face 1 of an add-box is its top.
    ok(&cli(&[
        "edit",
        s(&tower),
        "--up",
        "z",
        "--out",
        s(&scene),
        "--op",
        "add-box body 0 0 0 1 1 1",
        "--op",
        "extrude body 1 1 top",
        "--op",
        "rest top: scale 1.1",
    ]));
    let info = cli(&["info", s(&scene), "--json"]);
    let info: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    let names: Vec<&str> = info["cages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["body", "top"], "the extrusion took the name given");
    ok(&cli(&["validate", s(&scene)]));
    let out = d.join("deformed.obj");
    let stats = cli(&["deform", s(&scene), "--out", s(&out), "--stats"]);
    ok(&stats);
    // --stats breaks the weights down per leaf cage.
    let per_leaf: Vec<String> = stderr(&stats)
        .lines()
        .skip_while(|l| !l.starts_with("leaf cage"))
        .skip(1)
        .map(|l| l.split_whitespace().next().unwrap_or_default().to_owned())
        .collect();
    assert_eq!(per_leaf, ["body", "top"], "{}", stderr(&stats));
    // A bad op: named, status 2, nothing written.
    let other = d.join("other.json");
    let refused = cli(&[
        "edit",
        s(&scene),
        "--out",
        s(&other),
        "--op",
        "delete body",
        "--op",
        "extrude nobody 0 1",
    ]);
    assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
    assert!(
        stderr(&refused).contains("--op 2 'extrude nobody 0 1'")
            && stderr(&refused).contains("no leaf cage 'nobody'"),
        "{}",
        stderr(&refused)
    );
    assert!(!other.exists());
}

/// `edit --script` runs a file of operations (comments allowed) before the `--op` ones; a bad
/// line is named by file and line and nothing is written.
#[test]
fn edit_runs_a_script_file_and_names_a_bad_line() {
    let d = dir("edit-script");
    let tower = write_tower(&d);
    let script = d.join("rig.ops");
    std::fs::write(
        &script,
        "# a tower in two cages\nadd-box body 0 0 0 1 1 1\ninset body +z 0.05\n\nextrude body +z 1 top # up\nkind top gc\n",
    )
    .unwrap();
    let scene = d.join("rig.json");
    ok(&cli(&[
        "edit",
        s(&tower),
        "--up",
        "z",
        "--out",
        s(&scene),
        "--script",
        s(&script),
        "--op",
        "subdivide",
    ]));
    let info = cli(&["info", s(&scene), "--json"]);
    let info: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    let cages = info["cages"].as_array().unwrap();
    assert_eq!(cages.len(), 2);
    assert_eq!(cages[1]["kind"], "gc");
    assert_eq!(cages[1]["faces"], 24, "subdivided after the script");
    assert_eq!(
        cages[0]["faces"], 40,
        "the inset's ten faces, subdivided: the top grew from its inner face"
    );
    // A bad line: named by file and line; nothing written.
    std::fs::write(
        &script,
        "add-box body 0 0 0 1 1 1\nextrude body sideways 1\n",
    )
    .unwrap();
    let other = d.join("other.json");
    let refused = cli(&[
        "edit",
        s(&tower),
        "--up",
        "z",
        "--out",
        s(&other),
        "--script",
        s(&script),
    ]);
    assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
    assert!(
        stderr(&refused).contains("rig.ops: line 2:"),
        "{}",
        stderr(&refused)
    );
    assert!(!other.exists());
}

/// A Z-up tower mesh, 0.8 wide and 1.8 tall, as `tower.obj` in `d`.
fn write_tower(d: &std::path::Path) -> std::path::PathBuf {
    let tower = d.join("tower.obj");
    std::fs::write(
        &tower,
        "v 0.1 0.1 0.1\nv 0.9 0.1 0.1\nv 0.1 0.9 0.1\nv 0.9 0.9 0.1\nv 0.1 0.1 1.9\nv 0.9 0.1 1.9\n\
         v 0.1 0.9 1.9\nv 0.9 0.9 1.9\nf 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n",
    )
    .unwrap();
    tower
}

/// The auto rig (`rig.json` in `d`) of [`write_body_with_arm`]'s mesh, read Z-up; the mesh
/// and the scene.
fn rig_body_with_arm(d: &std::path::Path) -> (std::path::PathBuf, std::path::PathBuf) {
    let mesh = write_body_with_arm(d);
    let scene = d.join("rig.json");
    ok(&cli(&[
        "autorig",
        s(&mesh),
        "--up",
        "z",
        "--out",
        s(&scene),
    ]));
    (mesh, scene)
}

/// An OBJ of two overlapping closed boxes: a body and a long arm out along +x, towards the
/// front (a body symmetric front to back would have its one arm on its plane of symmetry, the
/// figure's middle, and the arm no side).
fn write_body_with_arm(d: &std::path::Path) -> std::path::PathBuf {
    let path = d.join("body_arm.obj");
    let mut text = String::new();
    for (k, (lo, hi)) in [
        ([0.0, 0.0, 0.0], [1.0, 1.0, 1.5]),
        ([0.8, 0.3, 0.6], [3.2, 0.6, 0.9]),
    ]
    .iter()
    .enumerate()
    {
        for c in 0..8 {
            let p = [
                if c & 1 == 0 { lo[0] } else { hi[0] },
                if c & 2 == 0 { lo[1] } else { hi[1] },
                if c & 4 == 0 { lo[2] } else { hi[2] },
            ];
            text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
        }
        let b = 8 * k + 1;
        for f in [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ] {
            text += &format!("f {} {} {} {}\n", b + f[0], b + f[1], b + f[2], b + f[3]);
        }
    }
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn autorig_adds_controls_that_turn_about_their_joints_unless_told_not_to() {
    let d = dir("autorig-controls");
    let (mesh, scene) = rig_body_with_arm(&d);
    let info = cli(&["info", s(&scene), "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    let controls = json["controls"].as_array().unwrap();
    let limb_control = controls
        .iter()
        .find(|c| c["name"] != "root")
        .expect("a control per limb segment");
    assert_eq!(limb_control["parent"], "root", "{limb_control}");
    assert_eq!(limb_control["pivot"].as_array().unwrap().len(), 3);
    // The arm stands out along +X of an upright body: Blender's left.
    assert_eq!(limb_control["limb"], "arm.L", "{limb_control}");
    assert_eq!(limb_control["side"], "L", "{limb_control}");
    // A control turns about its pivot from the command line.
    let name = limb_control["name"].as_str().unwrap();
    let posed = d.join("posed.obj");
    let turned = cli(&[
        "deform",
        s(&scene),
        "--apply",
        &format!("{name}: rotate 1 0 0 30"),
        "--out",
        s(&posed),
    ]);
    assert!(turned.status.success(), "{}", stderr(&turned));
    let rest = d.join("rest.obj");
    ok(&cli(&["deform", s(&scene), "--out", s(&rest)]));
    assert_ne!(
        std::fs::read(&posed).unwrap(),
        std::fs::read(&rest).unwrap(),
        "the arm turned"
    );
    // --no-controls: the bare leaf rig.
    let bare = d.join("bare.json");
    ok(&cli(&[
        "autorig",
        s(&mesh),
        "--up",
        "z",
        "--no-controls",
        "--out",
        s(&bare),
    ]));
    let info = cli(&["info", s(&bare), "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert!(json["controls"].as_array().unwrap().is_empty());
}

/// Signed volume of the quads and triangles of an OBJ's faces at `positions`.
fn obj_volume(path: &std::path::Path, positions: &[[f64; 3]]) -> f64 {
    let text = std::fs::read_to_string(path).unwrap();
    let mut volume = 0.0;
    for face in text.lines().filter_map(|l| l.strip_prefix("f ")) {
        let corners: Vec<usize> = face
            .split_whitespace()
            .map(|c| c.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
            .collect();
        let p = |k: usize| glam::DVec3::from_array(positions[corners[k]]);
        for k in 1..corners.len() - 1 {
            volume += p(0).dot(p(k).cross(p(k + 1))) / 6.0;
        }
    }
    volume
}

/// A bent joint keeps the mesh's volume through `deform --apply` (the mitre alone loses 2.5 %
/// of the two boxes' volume at this turn of the arm's last joint), and `eval --apply` on the
/// mesh's own vertices gives the same positions, so both settle the pose alike.
#[test]
fn a_turned_control_keeps_the_volume_at_its_joint_in_deform_and_eval() {
    let d = dir("autorig-volume");
    let (mesh, scene) = rig_body_with_arm(&d);
    let edit = "arm.L.6: rotate 0 0 1 60";
    let posed = d.join("posed.obj");
    ok(&cli(&[
        "deform",
        s(&scene),
        "--apply",
        edit,
        "--out",
        s(&posed),
    ]));
    let rest = obj_positions(&mesh);
    let moved = obj_positions(&posed);
    let change = obj_volume(&mesh, &moved) / obj_volume(&mesh, &rest) - 1.0;
    // Issue 41's 2 %: the mitre alone loses 2.5 % here. The arm's mesh has no vertex near the
    // joint: its ring widens to the bound of its scale (4 times its radius on the outer side),
    // where the triangles it moves are within 0.2 % of their volume and the whole mesh 1.9 %
    // short (each sweep widening on top of the last reached 0.0 %, but spiked real meshes).
    assert!(
        change.abs() < 0.02,
        "the mesh's volume changed by {:.2} %",
        100.0 * change
    );
    assert!(moved != rest, "the arm turned");
    let points = d.join("points.txt");
    let lines: Vec<String> = rest
        .iter()
        .map(|p| format!("{} {} {}", p[0], p[1], p[2]))
        .collect();
    std::fs::write(&points, lines.join("\n")).unwrap();
    let evaluated = cli(&["eval", s(&scene), "--points", s(&points), "--apply", edit]);
    ok(&evaluated);
    let json: serde_json::Value = serde_json::from_slice(&evaluated.stdout).unwrap();
    let evaluated: Vec<[f64; 3]> = serde_json::from_value(json["points"].clone()).unwrap();
    for (a, b) in evaluated.iter().zip(&moved) {
        let apart = (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max);
        assert!(apart < 1e-5, "eval {a:?} against deform {b:?}");
    }
}

#[test]
fn autorig_writes_a_valid_shape_following_rig_and_refuses_what_it_cannot_rig() {
    let d = dir("autorig");
    // The bar demo's mesh as an OBJ: a long bar, so a body and a chain along it.
    ok(&cli(&["demo", "bar", "--out", s(&d), "--detail", "0.3"]));
    let mesh = d.join("bar.obj");
    ok(&cli(&["deform", s(&d.join("bar.json")), "--out", s(&mesh)]));
    let scene = d.join("rig.json");
    let rig = cli(&[
        "autorig",
        s(&mesh),
        "--detail",
        "2",
        "--mirror",
        "auto",
        "--out",
        s(&scene),
    ]);
    assert!(rig.status.success(), "{}", stderr(&rig));
    assert!(stdout(&rig).contains("leaf cages"), "{}", stdout(&rig));
    assert!(cli(&["validate", s(&scene)]).status.success());
    let info = cli(&["info", s(&scene), "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    let cages = json["cages"].as_array().unwrap();
    assert!(
        cages
            .iter()
            .any(|c| c["name"] == "root" && c["level"] == "internal")
    );
    // Leaf cages are named `<body or limb>_<n>`; controls list their limb, parent and pivot.
    assert!(
        cages
            .iter()
            .filter(|c| c["level"] == "leaf")
            .all(|c| c["name"].as_str().unwrap().contains('_'))
    );
    // A flat mesh, a detail out of range, the mesh as the output: exit 2, nothing written.
    let flat = d.join("flat.obj");
    std::fs::write(&flat, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = d.join("never.json");
    let refused = cli(&["autorig", s(&flat), "--out", s(&out)]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(
        stderr(&refused).contains("no volume"),
        "{}",
        stderr(&refused)
    );
    let refused = cli(&["autorig", s(&mesh), "--detail", "9", "--out", s(&out)]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(
        stderr(&refused).contains("'9' for '--detail <DETAIL>': 9 is not in 1..=5"),
        "{}",
        stderr(&refused)
    );
    let refused = cli(&["autorig", s(&mesh), "--mirror", "w", "--out", s(&out)]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(!out.exists());
    let onto_input = cli(&["autorig", s(&mesh), "--out", s(&mesh)]);
    assert_eq!(onto_input.status.code(), Some(2));
}

/// PLY, STL and OFF meshes come in wherever OBJ does: a scene around each, deformed back out
/// in the file's layout (an STL keeps its three corners per triangle).
#[test]
fn ply_stl_and_off_meshes_make_scenes_and_deform_out_in_their_layout() {
    let d = dir("formats");
    let corners = "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n";
    let quads = "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
    let ply = format!(
        "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n\
         property float z\nelement face 6\nproperty list uchar int vertex_indices\nend_header\n\
         {corners}{quads}"
    );
    let off = format!("OFF\n8 6 0\n{corners}{quads}");
    let mut stl = String::from("solid c\n");
    let p: Vec<[&str; 3]> = corners
        .lines()
        .map(|l| {
            let t: Vec<&str> = l.split(' ').collect();
            [t[0], t[1], t[2]]
        })
        .collect();
    for q in quads.lines() {
        let i: Vec<usize> = q.split(' ').skip(1).map(|t| t.parse().unwrap()).collect();
        for t in [[i[0], i[1], i[2]], [i[0], i[2], i[3]]] {
            stl += "facet normal 0 0 0\nouter loop\n";
            for k in t {
                stl += &format!("vertex {} {} {}\n", p[k][0], p[k][1], p[k][2]);
            }
            stl += "endloop\nendfacet\n";
        }
    }
    stl += "endsolid c\n";
    for (name, text, vertices) in [("c.ply", ply, 8), ("c.off", off, 8), ("c.stl", stl, 36)] {
        let mesh = d.join(name);
        std::fs::write(&mesh, text).unwrap();
        let scene = d.join(format!("{name}.json"));
        ok(&cli(&[
            "autocage",
            s(&mesh),
            "--grid",
            "1",
            "1",
            "1",
            "--out",
            s(&scene),
        ]));
        let out = d.join(format!("{name}.obj"));
        ok(&cli(&["deform", s(&scene), "--out", s(&out)]));
        let written = std::fs::read_to_string(&out).unwrap();
        let count = written.lines().filter(|l| l.starts_with("v ")).count();
        assert_eq!(count, vertices, "{name}");
    }
}

/// A scene with thousands of problems prints a capped list and a count, not thousands of lines.
#[test]
fn thousands_of_problems_print_a_capped_list_and_a_count() {
    let d = dir("many-problems");
    ok(&cli(&["demo", "critter", "--out", s(&d)]));
    let scene = d.join("critter.json");
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    let owns = json["internal_cages"][0]["owns"].as_array_mut().unwrap();
    owns.extend((0..5000).map(|k| serde_json::json!(1_000_000 + k)));
    std::fs::write(&scene, json.to_string()).unwrap();
    let o = cli(&["validate", s(&scene)]);
    assert_eq!(o.status.code(), Some(2));
    let text = stderr(&o);
    let lines = text.lines().filter(|l| l.starts_with("error:")).count();
    assert!(lines <= 52, "{lines} lines");
    assert!(
        text.contains("more (50") || text.contains("in all"),
        "{text}"
    );
    assert!(
        text.contains("5000") || text.contains("problem(s)"),
        "{text}"
    );
}

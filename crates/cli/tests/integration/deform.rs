//! End-to-end tests of deform and eval: outputs, baselines, poses from files, the cache.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use crate::common;

use common::{BOX_OBJ, cli, dir, ok, s, stderr, stdout};

#[test]
fn deform_eval_baselines_pose_files_and_cache() {
    let d = dir("all");
    let p = |name: &str| d.join(name).to_str().unwrap().to_owned();
    ok(&cli(&["demo", "bar", "--out", &p(""), "--detail", "0.4"]));
    let scene = p("bar.json");
    // OBJ and GLB outputs, *Cages and a baseline.
    ok(&cli(&[
        "deform",
        &scene,
        "--pose",
        "bend",
        "--out",
        &p("bent.obj"),
        "--stats",
    ]));
    ok(&cli(&[
        "deform",
        &scene,
        "--pose",
        "bend",
        "--single-cage",
        "gc",
        "--out",
        &p("bent.glb"),
    ]));
    let obj = std::fs::read_to_string(p("bent.obj")).unwrap();
    assert!(obj.lines().any(|l| l.starts_with("vn ")) && obj.lines().any(|l| l.starts_with("f ")));
    assert!(std::fs::read(p("bent.glb")).unwrap().starts_with(b"glTF"));

    // eval: the rest pose is the identity; a pose file round trip gives the named pose's result.
    std::fs::write(p("points.txt"), "0 0 0\n0.5 0.1 -0.1\n").unwrap();
    let rest = cli(&["eval", &scene, "--points", &p("points.txt")]);
    ok(&rest);
    let json: serde_json::Value = serde_json::from_slice(&rest.stdout).unwrap();
    let first: Vec<f64> = serde_json::from_value(json["points"][1].clone()).unwrap();
    assert!(
        (first[0] - 0.5).abs() < 1e-9
            && (first[1] - 0.1).abs() < 1e-9
            && (first[2] + 0.1).abs() < 1e-9
    );
    ok(&cli(&[
        "cages",
        &scene,
        "--pose",
        "bend",
        "--out",
        &p("bend.obj"),
    ]));
    let named = cli(&[
        "eval",
        &scene,
        "--points",
        &p("points.txt"),
        "--pose",
        "bend",
    ]);
    let from_file = cli(&[
        "eval",
        &scene,
        "--points",
        &p("points.txt"),
        "--pose-file",
        &p("bend.obj"),
    ]);
    ok(&named);
    assert_eq!(named.stdout, from_file.stdout);

    // A pose file with another vertex count is a clear error.
    std::fs::write(p("short.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let bad = cli(&[
        "deform",
        &scene,
        "--pose-file",
        &p("short.obj"),
        "--out",
        &p("x.obj"),
    ]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&bad.stderr)
            .contains("has 3 vertices but the scene's cages have 12")
    );

    // The cache: written, then read.
    ok(&cli(&[
        "deform",
        &scene,
        "--pose",
        "bend",
        "--cache",
        "--out",
        &p("c1.obj"),
    ]));
    assert!(d.join("bar.json.bind").exists());
    let again = cli(&[
        "deform",
        &scene,
        "--pose",
        "bend",
        "--cache",
        "--out",
        &p("c2.obj"),
    ]);
    ok(&again);
    assert!(String::from_utf8_lossy(&again.stderr).contains("binding read from its cache"));
    assert_eq!(
        std::fs::read(p("c1.obj")).unwrap(),
        std::fs::read(p("c2.obj")).unwrap()
    );
}

/// `--apply` edits propagate down the hierarchy: translating the critter's root moves every
/// point by exactly that vector, and an unknown cage or a bad edit is an input error.
#[test]
fn apply_edits_and_internal_cages() {
    let d = dir("apply");
    ok(&cli(&[
        "demo",
        "critter",
        "--detail",
        "0.3",
        "--out",
        s(&d),
    ]));
    let scene = d.join("critter.json");
    let points = d.join("points.txt");
    // In the mesh file's axes: a demo's are Y-up (scene points (x, y, z) are (x, z, -y)).
    std::fs::write(&points, "0 0 0\n0.3 0.2 0.5\n-0.4 1.5 -0.6\n").unwrap();
    let eval = |extra: &[&str]| -> Vec<Vec<f64>> {
        let mut args = vec!["eval", s(&scene), "--points", s(&points)];
        args.extend_from_slice(extra);
        let out = cli(&args);
        ok(&out);
        let json: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
        serde_json::from_value(json["points"].clone()).unwrap()
    };
    let rest = eval(&[]);
    let moved = eval(&[
        "--apply",
        "head: translate 0.5 0 -1",
        "--apply",
        "head: scale 1",
    ]);
    // --apply moves in StarCages' Z-up frame (as the editor shows the scene): (0.5, 0, -1)
    // there is (0.5, -1, 0) in the file's Y-up axes.
    for (a, b) in rest.iter().zip(&moved) {
        let shift = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        for (got, want) in shift.iter().zip([0.5, -1.0, 0.0]) {
            assert!((got - want).abs() < 1e-6, "{shift:?}");
        }
    }
    // A leaf edit under the same root move is carried along.
    let both = eval(&[
        "--pose",
        "fig13",
        "--apply",
        "ear_left: translate 0 0 0.3",
        "--apply",
        "head: rotate 0 0 1 10",
    ]);
    assert!(both.iter().flatten().all(|x| x.is_finite()));
    let out = cli(&[
        "eval",
        s(&scene),
        "--points",
        s(&points),
        "--apply",
        "nose: scale 2",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("the cages are:"), "{}", stderr(&out));
    let out = cli(&[
        "eval",
        s(&scene),
        "--points",
        s(&points),
        "--apply",
        "head scale 2",
    ]);
    assert_eq!(out.status.code(), Some(2));
    // A new internal cage over the bar's right cage, then posed through it.
    ok(&cli(&["demo", "bar", "--out", s(&d)]));
    let bar = d.join("bar.json");
    let boxed = d.join("boxed.json");
    ok(&cli(&[
        "internal-cage",
        s(&bar),
        "--name",
        "end",
        "--cages",
        "cage_1_0_0",
        "--kind",
        "hc",
        "--cells",
        "1",
        "2",
        "2",
        "--out",
        s(&boxed),
    ]));
    let mesh = d.join("bent.obj");
    ok(&cli(&[
        "deform",
        s(&boxed),
        "--apply",
        "end: rotate 0 1 0 30",
        "--out",
        s(&mesh),
    ]));
    let out = cli(&[
        "internal-cage",
        s(&boxed),
        "--name",
        "twice",
        "--vertices",
        "1",
        "--out",
        s(&boxed),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("already owned"), "{}", stderr(&out));
}

/// `internal-cage --from CAGES.obj`: each cage of the file becomes an internal cage owning the
/// free cage vertices inside it; one holding nothing free is an input error naming the file.
#[test]
fn internal_cages_imported_from_an_obj() {
    let d = dir("internal-from");
    ok(&cli(&["demo", "bar", "--detail", "0.3", "--out", s(&d)]));
    let bar = d.join("bar.json");
    // A box around the whole bar (symmetric in y and z, so the same in either up axis).
    let (lo, hi) = ([-1.5, -0.6, -0.6], [1.5, 0.6, 0.6]);
    let mut text = String::from("o whole\n");
    for c in 0..8usize {
        let at = |axis: usize| {
            if c >> axis & 1 == 0 {
                lo[axis]
            } else {
                hi[axis]
            }
        };
        text += &format!("v {} {} {}\n", at(0), at(1), at(2));
    }
    for f in starcages_core::cage::shapes::BOX_FACES {
        let corners: Vec<String> = f.iter().map(|v| (v + 1).to_string()).collect();
        text += &format!("f {}\n", corners.join(" "));
    }
    let cages = d.join("whole.obj");
    std::fs::write(&cages, text).unwrap();
    let out_path = d.join("driven.json");
    let args = [
        "internal-cage",
        s(&bar),
        "--from",
        s(&cages),
        "--kind",
        "hc",
        "--out",
        s(&out_path),
    ];
    let out = cli(&args);
    ok(&out);
    assert!(
        stdout(&out).contains("'whole' owns 12 vertices"),
        "{}",
        stdout(&out)
    );
    ok(&cli(&["validate", s(&out_path)]));
    // Again on the result: nothing inside is free any more.
    let again = d.join("again.json");
    let out = cli(&[
        "internal-cage",
        s(&out_path),
        "--from",
        s(&cages),
        "--out",
        s(&again),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("whole.obj") && stderr(&out).contains("no cage vertex"));
    assert!(!again.exists(), "nothing is written");
}

/// Poses pushed past ±1e9 by a pose file or `--apply` are refused naming the vertex and where
/// the pose came from; nothing is written (meshes came out at 1e19–1e30 before).
#[test]
fn poses_beyond_the_coordinate_limit_are_refused_before_writing() {
    let d = crate::common::dir("far-poses");
    crate::common::ok(&crate::common::cli(&[
        "demo",
        "critter",
        "--out",
        crate::common::s(&d),
    ]));
    let scene = d.join("critter.json");
    let out = d.join("far.obj");
    let s = crate::common::s;
    for edits in [
        vec!["--apply", "head: translate 1e12 0 0"],
        vec!["--apply", "head_0_0_0: scale 1e15"],
    ] {
        let mut args = vec!["deform", s(&scene), "--out", s(&out)];
        args.extend(edits.iter().copied());
        let o = crate::common::cli(&args);
        assert_eq!(
            o.status.code(),
            Some(2),
            "{edits:?}: {}",
            crate::common::stderr(&o)
        );
        assert!(
            crate::common::stderr(&o).contains("--apply edits"),
            "{}",
            crate::common::stderr(&o)
        );
        assert!(!out.exists(), "nothing written");
    }
    let cages = d.join("cages.obj");
    crate::common::ok(&crate::common::cli(&[
        "cages",
        s(&scene),
        "--out",
        s(&cages),
    ]));
    let far = std::fs::read_to_string(&cages)
        .unwrap()
        .replacen("v ", "v 1e20 ", 1);
    // The first vertex line gets an x of 1e20 in front (its old x becomes y, and so on).
    let far_file = d.join("far_cages.obj");
    std::fs::write(&far_file, far).unwrap();
    let o = crate::common::cli(&[
        "deform",
        s(&scene),
        "--pose-file",
        s(&far_file),
        "--out",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", crate::common::stderr(&o));
    assert!(
        crate::common::stderr(&o).contains("pose file"),
        "{}",
        crate::common::stderr(&o)
    );
    assert!(!out.exists(), "nothing written");
}

/// `eval` reads and writes points in the mesh file's axes, as `cages` and `--pose-file` do: a
/// Y-up OBJ's rig moved up its file's Y moves the points up Y (they were taken in StarCages'
/// Z-up frame, and moved along the file's Z).
#[test]
fn eval_points_are_in_the_mesh_files_axes() {
    let d = dir("eval-axes");
    let mesh = d.join("box.obj");
    std::fs::write(&mesh, BOX_OBJ).unwrap();
    let scene = d.join("box.json");
    ok(&cli(&["autocage", s(&mesh), "--out", s(&scene)]));
    let cages = d.join("cages.obj");
    ok(&cli(&["cages", s(&scene), "--out", s(&cages)]));
    let moved: String = std::fs::read_to_string(&cages)
        .unwrap()
        .lines()
        .map(|line| match line.strip_prefix("v ") {
            Some(rest) => {
                let v: Vec<f64> = rest
                    .split_whitespace()
                    .map(|x| x.parse().unwrap())
                    .collect();
                format!("v {} {} {}\n", v[0], v[1] + 1.0, v[2])
            }
            None => format!("{line}\n"),
        })
        .collect();
    let pose = d.join("up.obj");
    std::fs::write(&pose, moved).unwrap();
    let points = d.join("points.txt");
    std::fs::write(&points, "0.3 0.7 -0.2\n").unwrap();
    let out = cli(&[
        "eval",
        s(&scene),
        "--points",
        s(&points),
        "--pose-file",
        s(&pose),
    ]);
    ok(&out);
    let json: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    let p: Vec<f64> = serde_json::from_value(json["points"][0].clone()).unwrap();
    for (got, want) in p.iter().zip([0.3, 1.7, -0.2]) {
        assert!((got - want).abs() < 1e-6, "{p:?}");
    }
}

//! End-to-end tests of deform and eval: outputs, baselines, poses from files, the cache.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

mod common;

use common::{cli, dir, ok};

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

//! `deform --frame`, `bake` and `cages` to point caches, end to end: every baked sample equals
//! the mesh `deform --frame` writes, a cage cache written by `cages` drives the rig back to
//! the same result, and bad caches or scenes are refused without writing.

use std::path::Path;

use starcages_io::read_point_cache;

use crate::common::{cli, dir, ok, s, stderr};

/// The `v` lines of an OBJ file.
fn obj_vertices(path: &Path) -> Vec<[f32; 3]> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f32> = l
                .split_whitespace()
                .take(3)
                .map(|t| t.parse().unwrap())
                .collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

fn largest_difference(a: &[[f32; 3]], b: &[glam::Vec3]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| (glam::Vec3::from_array(*p) - *q).abs().max_element())
        .fold(0.0, f32::max)
}

#[test]
fn baked_caches_equal_deform_at_each_frame_and_cage_caches_drive_the_rig() {
    let d = dir("bake");
    ok(&cli(&["demo", "critter", "--out", s(&d)]));
    let scene = d.join("critter.json");
    let at = |frame: &str| {
        let out = d.join(format!("frame{frame}.obj"));
        ok(&cli(&[
            "deform",
            s(&scene),
            "--frame",
            frame,
            "--out",
            s(&out),
            "--cache",
        ]));
        obj_vertices(&out)
    };
    let (frame1, frame7) = (at("1"), at("7"));
    for name in ["walk.pc2", "walk.mdd"] {
        let out = d.join(name);
        ok(&cli(&["bake", s(&scene), "--out", s(&out), "--cache"]));
        let cache = read_point_cache(&out, Some(frame1.len()), 24.0).unwrap();
        assert_eq!(cache.samples.len(), 24, "{name}: frames 1..24");
        assert!((cache.start_frame - 1.0).abs() < 1e-4, "{name}");
        assert_eq!(
            largest_difference(&frame1, &cache.samples[0]),
            0.0,
            "{name}"
        );
        assert_eq!(
            largest_difference(&frame7, &cache.samples[6]),
            0.0,
            "{name}"
        );
    }
    // A range, resampled at twice the rate: frames 5, 5.5, …, 7.
    let range = d.join("range.pc2");
    ok(&cli(&[
        "bake",
        s(&scene),
        "--out",
        s(&range),
        "--frames",
        "5..7",
        "--fps",
        "48",
        "--cache",
    ]));
    let cache = read_point_cache(&range, None, 24.0).unwrap();
    assert_eq!(cache.samples.len(), 5);
    assert_eq!((cache.start_frame, cache.frame_step), (5.0, 0.5));
    assert_eq!(largest_difference(&frame7, &cache.samples[4]), 0.0);
    // The cages' own animation out, and back in as the driver of the same rig.
    let cages = d.join("cages.mdd");
    ok(&cli(&["cages", s(&scene), "--out", s(&cages)]));
    let driven = d.join("driven.pc2");
    ok(&cli(&[
        "bake",
        s(&scene),
        "--cage-cache",
        s(&cages),
        "--out",
        s(&driven),
        "--cache",
    ]));
    let driven = read_point_cache(&driven, None, 24.0).unwrap();
    assert_eq!(driven.samples.len(), 24);
    assert!(largest_difference(&frame7, &driven.samples[6]) < 1e-5);
    // glTF bakes open as the rest mesh in our own reader (their layout is tested in core).
    let glb = d.join("walk.glb");
    ok(&cli(&[
        "bake",
        s(&scene),
        "--out",
        s(&glb),
        "--frames",
        "1..4",
        "--cache",
    ]));
    assert!(starcages_io::read_mesh(&glb).is_ok());
}

#[test]
fn caches_of_a_mesh_read_from_obj_follow_its_vertex_lines() {
    let d = dir("bake-obj");
    // A box with a vertex no face uses, first: the cache keeps it, in file order.
    let mesh = d.join("box.obj");
    let vertices: String = crate::common::BOX_OBJ
        .lines()
        .filter(|l| l.starts_with("v "))
        .map(|l| format!("{l}\n"))
        .collect();
    let faces = "f 2 4 5 3\nf 6 7 9 8\nf 2 3 7 6\nf 4 8 9 5\nf 2 6 8 4\nf 3 5 9 7\n";
    std::fs::write(&mesh, format!("v 9 9 9\n{vertices}{faces}")).unwrap();
    let scene = d.join("box.json");
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
    // Key the current pose and a stretched one.
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    let rest = json["cage_vertices"].clone();
    let stretched: Vec<serde_json::Value> = rest
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let p: Vec<f64> = p
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_f64().unwrap())
                .collect();
            serde_json::json!([p[0] * 1.5, p[1], p[2]])
        })
        .collect();
    json["poses"] = serde_json::json!({"rest": rest, "wide": stretched});
    json["animation"] = serde_json::json!({"fps": 24, "frame_start": 1, "frame_end": 10,
        "keys": [{"frame": 1, "pose": "rest", "interpolation": "linear"},
                 {"frame": 10, "pose": "wide"}]});
    std::fs::write(&scene, json.to_string()).unwrap();
    let obj = d.join("f4.obj");
    ok(&cli(&[
        "deform",
        s(&scene),
        "--frame",
        "4",
        "--out",
        s(&obj),
    ]));
    let expected = obj_vertices(&obj);
    assert_eq!(expected.len(), 9);
    assert_eq!(expected[0], [9.0, 9.0, 9.0], "the unused line is kept");
    let pc2 = d.join("box.pc2");
    ok(&cli(&["bake", s(&scene), "--out", s(&pc2)]));
    let cache = read_point_cache(&pc2, Some(9), 24.0).unwrap();
    assert_eq!(largest_difference(&expected, &cache.samples[3]), 0.0);
    // Frame 4 of 1..10 is a third of the way: x grows by 1/6 (linear key).
    assert!(
        (expected[1][0] - (-1.0 - 1.0 / 6.0)).abs() < 1e-5,
        "{:?}",
        expected[1]
    );
}

#[test]
fn bad_caches_and_unanimated_scenes_are_refused_without_writing() {
    let d = dir("bake-bad");
    ok(&cli(&["demo", "critter", "--out", s(&d)]));
    ok(&cli(&["demo", "bar", "--out", s(&d)]));
    let (critter, bar) = (d.join("critter.json"), d.join("bar.json"));
    let out = d.join("out.pc2");
    std::fs::write(&out, b"previous").unwrap();
    let refused = |args: &[&str], says: &str| {
        let o = cli(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(says), "{says:?} not in {}", stderr(&o));
        assert_eq!(std::fs::read(&out).unwrap(), b"previous", "{args:?}");
    };
    refused(&["bake", s(&bar), "--out", s(&out)], "no animation keys");
    refused(
        &[
            "deform",
            s(&bar),
            "--frame",
            "3",
            "--out",
            s(&d.join("x.obj")),
        ],
        "no animation keys",
    );
    // A cage cache of the wrong scene, a truncated one, one with a forged header.
    let cages = d.join("cages.pc2");
    ok(&cli(&["cages", s(&critter), "--out", s(&cages)]));
    let bytes = std::fs::read(&cages).unwrap();
    let truncated = d.join("truncated.pc2");
    std::fs::write(&truncated, &bytes[..bytes.len() - 7]).unwrap();
    refused(
        &[
            "bake",
            s(&critter),
            "--cage-cache",
            s(&truncated),
            "--out",
            s(&out),
        ],
        "truncated.pc2",
    );
    let mut forged = bytes.clone();
    forged[28..32].copy_from_slice(&i32::MAX.to_le_bytes());
    let forged_path = d.join("forged.pc2");
    std::fs::write(&forged_path, &forged).unwrap();
    refused(
        &[
            "bake",
            s(&critter),
            "--cage-cache",
            s(&forged_path),
            "--out",
            s(&out),
        ],
        "announces",
    );
    refused(
        &["cages", s(&bar), "--out", s(&d.join("bar.pc2"))],
        "no animation keys",
    );
    refused(
        &["bake", s(&bar), "--cage-cache", s(&cages), "--out", s(&out)],
        "are needed here",
    );
    // The cage cache may not be the output, nor the scene.
    refused(&["bake", s(&critter), "--out", s(&critter)], "--out");
    refused(
        &["bake", s(&critter), "--frames", "9..2", "--out", s(&out)],
        "first frame comes after the last",
    );
}

/// At a keyed frame the edits go on from the key's hierarchy state, as in the editor and as
/// with the key's pose by name; before the posing engine `--frame` started from rest.
#[test]
fn deform_at_a_keyed_frame_with_edits_equals_the_key_pose_with_the_same_edits() {
    let d = dir("frame-edits");
    ok(&cli(&["demo", "critter", "--out", s(&d)]));
    let scene = d.join("critter.json");
    let (at_frame, by_name) = (d.join("frame.obj"), d.join("name.obj"));
    let edit = "head: rotate 0 0 1 10";
    ok(&cli(&[
        "deform",
        s(&scene),
        "--frame",
        "12",
        "--apply",
        edit,
        "--out",
        s(&at_frame),
    ]));
    ok(&cli(&[
        "deform",
        s(&scene),
        "--pose",
        "ears_back",
        "--apply",
        edit,
        "--out",
        s(&by_name),
    ]));
    let by_name: Vec<glam::Vec3> = obj_vertices(&by_name)
        .into_iter()
        .map(glam::Vec3::from_array)
        .collect();
    assert_eq!(largest_difference(&obj_vertices(&at_frame), &by_name), 0.0);
}

/// A point cache that does not start at frame 0 says the one Blender setting that lines it up
/// (Mesh Cache's Frame Start); one from frame 0 needs none.
#[test]
fn a_cache_from_frame_one_names_the_mesh_cache_frame_start_to_set() {
    let d = dir("mesh-cache-note");
    ok(&cli(&["demo", "critter", "--out", s(&d)]));
    let scene = d.join("critter.json");
    let from_one = cli(&["bake", s(&scene), "--out", s(&d.join("a.pc2"))]);
    ok(&from_one);
    assert!(
        stderr(&from_one).contains("set Frame Start to 1"),
        "{}",
        stderr(&from_one)
    );
    let from_zero = cli(&[
        "bake",
        s(&scene),
        "--frames",
        "0..4",
        "--out",
        s(&d.join("b.mdd")),
    ]);
    ok(&from_zero);
    assert!(
        !stderr(&from_zero).contains("Frame Start"),
        "{}",
        stderr(&from_zero)
    );
}

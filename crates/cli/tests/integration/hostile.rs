//! Hostile input at the command line (issue 42's classes): negative numbers reach the range
//! checks that name the allowed range, and the scene's own values are blamed as the scene's.

use crate::common::{BOX_OBJ, cli, dir, ok, s, stderr};

/// Runs `args`, expects status 2 with every one of `messages` on standard error and none of
/// clap's "unexpected argument" with its tip to write `-- -1`.
fn refused(args: &[&str], messages: &[&str]) {
    let out = cli(args);
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {text}");
    assert!(!text.contains("unexpected argument"), "{args:?}: {text}");
    for message in messages {
        assert!(text.contains(message), "{args:?}: {text}");
    }
}

#[test]
fn negative_numbers_reach_the_range_checks() {
    let d = dir("negative-numbers");
    let mesh = d.join("box.obj");
    std::fs::write(&mesh, BOX_OBJ).unwrap();
    let out = d.join("rig.json");
    let (mesh, out) = (s(&mesh), s(&out));
    refused(
        &["autorig", mesh, "--detail", "-1", "--out", out],
        &["--detail", "1..=5"],
    );
    refused(
        &["autorig", mesh, "--margin", "-1", "--out", out],
        &["margin -1", "[0, 0.25]"],
    );
    refused(
        &["autocage", mesh, "--grid", "2", "-1", "1", "--out", out],
        &["--grid", "1..=64"],
    );
    ok(&cli(&["demo", "critter", "--out", s(&d)]));
    let scene = d.join("critter.json");
    let png = d.join("x.png");
    refused(
        &["render", s(&scene), "--size", "-5x5", "--png", s(&png)],
        &["16 to 8192"],
    );
    // A range of negative frames is a range: this one holds no keyed motion but bakes (the
    // poses hold before the first key).
    let cache = d.join("early.pc2");
    ok(&cli(&[
        "bake",
        s(&scene),
        "--frames",
        "-10..-5",
        "--out",
        s(&cache),
    ]));
    let read = starcages_io::read_point_cache(&cache, None, 24.0).unwrap();
    assert_eq!(read.samples.len(), 6);
    assert_eq!(read.start_frame, -10.0);
}

/// What we would write and then refuse is refused on the way in (issue 42, class 2), and a
/// scene's own values are blamed as the scene's, not as a flag the user never gave (class 3):
/// a cage cache putting a vertex at 1e20 (a pose file is held to ±1e9 the same way), a scene
/// whose fps would make every MDD time infinite, a key beyond Blender's last frame.
#[test]
fn bakes_refuse_what_their_files_could_not_hold() {
    let d = dir("bake-limits");
    ok(&cli(&["demo", "critter", "--out", s(&d)]));
    let scene = d.join("critter.json");
    let cages = d.join("cages.pc2");
    ok(&cli(&["cages", s(&scene), "--out", s(&cages)]));
    let mut bytes = std::fs::read(&cages).unwrap();
    // Sample 0, vertex 3, y (after the 32-byte header).
    let at = 32 + 3 * 12 + 4;
    bytes[at..at + 4].copy_from_slice(&1e20f32.to_le_bytes());
    let far = d.join("far.pc2");
    std::fs::write(&far, &bytes).unwrap();
    let out = d.join("out.pc2");
    refused(
        &["bake", s(&scene), "--cage-cache", s(&far), "--out", s(&out)],
        &["far.pc2", "sample 0 puts cage vertex 3 at", "beyond ±1e9"],
    );
    assert!(!out.exists());

    let text = std::fs::read_to_string(&scene).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    for (fps, shown) in [(1e-300, "1e-300"), (1e308, "1e308")] {
        json["animation"]["fps"] = serde_json::json!(fps);
        let odd = d.join("odd-fps.json");
        std::fs::write(&odd, serde_json::to_string(&json).unwrap()).unwrap();
        let o = cli(&["validate", s(&odd)]);
        let text = stderr(&o) + &crate::common::stdout(&o);
        assert!(!o.status.success(), "{text}");
        assert!(
            text.contains(&format!("fps = {shown} is outside 0.01 to 1000"))
                && !text.contains("--fps"),
            "{text}"
        );
        for name in ["walk.mdd", "walk.pc2"] {
            let out = d.join(name);
            refused(&["bake", s(&odd), "--out", s(&out)], &["does not validate"]);
            assert!(!out.exists());
        }
    }
    json["animation"]["fps"] = serde_json::json!(24.0);
    json["animation"]["keys"][0]["frame"] = serde_json::json!(-2e7);
    let odd = d.join("far-key.json");
    std::fs::write(&odd, serde_json::to_string(&json).unwrap()).unwrap();
    let o = cli(&["validate", s(&odd)]);
    let text = stderr(&o) + &crate::common::stdout(&o);
    assert!(
        text.contains("key 0 has frame -20000000") && text.contains("1048574"),
        "{text}"
    );
    // Resampling at --fps far from frame 0, where MDD's 32-bit times would collide: refused
    // before writing, naming the sample.
    let resampled = d.join("resampled.mdd");
    refused(
        &[
            "bake",
            s(&scene),
            "--frames",
            "1048000..1048002",
            "--fps",
            "1000",
            "--out",
            s(&resampled),
        ],
        &["not written", "32-bit float"],
    );
    assert!(!resampled.exists());
}

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
    let read = starcages_core::io::read_point_cache(&cache, None, 24.0).unwrap();
    assert_eq!(read.samples.len(), 6);
    assert_eq!(read.start_frame, -10.0);
}

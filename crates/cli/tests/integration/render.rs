//! End-to-end tests of `render`: PNG images of demo scenes (software Vulkan in CI).

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use crate::common;

use common::{cli, dir, ok, s, stderr};

#[test]
fn renders_pngs_with_maps_and_refuses_bad_options() {
    let d = dir("render");
    ok(&cli(&["demo", "bumpy", "--detail", "0.3", "--out", s(&d)]));
    let scene = d.join("bumpy.json");
    let png = d.join("b.png");
    ok(&cli(&[
        "render",
        s(&scene),
        "--pose",
        "lift",
        "--influence",
        "all",
        "--size",
        "120x90",
        "--png",
        s(&png),
    ]));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    // Width and height from the IHDR chunk.
    let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let height = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    assert_eq!((width, height), (120, 90));
    let out = cli(&[
        "render",
        s(&scene),
        "--difference",
        "mvc",
        "--size",
        "64x48",
        "--png",
        s(&d.join("d.png")),
    ]);
    ok(&out);
    assert!(stderr(&out).contains("RMS"), "{}", stderr(&out));
    let out = cli(&["render", s(&scene), "--size", "12", "--png", s(&png)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("WIDTHxHEIGHT"));
    let out = cli(&["render", s(&scene), "--influence", "nose", "--png", s(&png)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no leaf cage named 'nose'"));
}

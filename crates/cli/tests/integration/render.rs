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

/// `--shading textured` reads the mesh file's materials (the checker sphere's GLB): red checker
/// pixels appear that Solid does not draw; a broken image is a note naming it and the image is
/// still written; `--shading matcap --matcap metal` renders.
#[test]
fn renders_the_mesh_file_s_materials_and_names_a_broken_image() {
    let d = dir("render-textured");
    let samples = starcages_io::sample_files::write_textured_samples(&d).unwrap();
    let scene = d.join("sphere.json");
    ok(&cli(&["autocage", s(&samples.obj), "--out", s(&scene)]));
    let render = |shading: &[&str], png: &str| {
        let png = d.join(png);
        let mut args = vec!["render", s(&scene), "--size", "160x120", "--no-cages"];
        args.extend_from_slice(shading);
        args.extend(["--png", s(&png)]);
        let out = cli(&args);
        ok(&out);
        (image::open(&png).unwrap().to_rgba8(), stderr(&out))
    };
    let red = |image: &image::RgbaImage| {
        image
            .pixels()
            .filter(|p| p.0[0] > 150 && p.0[1] < 90 && p.0[2] < 90)
            .count()
    };
    let (solid, _) = render(&[], "solid.png");
    let (textured, notes) = render(&["--shading", "textured"], "textured.png");
    assert!(notes.is_empty() || !notes.contains("checker"), "{notes}");
    assert_eq!(red(&solid), 0);
    assert!(red(&textured) > 200, "{} red pixels", red(&textured));
    let (metal, _) = render(&["--shading", "matcap", "--matcap", "metal"], "metal.png");
    assert_ne!(metal, solid);
    std::fs::write(&samples.png, b"not an image").unwrap();
    let (broken, notes) = render(&["--shading", "textured"], "broken.png");
    assert!(notes.contains("checker.png"), "{notes}");
    assert_eq!(red(&broken), 0);
}

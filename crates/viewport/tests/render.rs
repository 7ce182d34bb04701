//! Offscreen rendering on the software Vulkan driver (lavapipe): snapshots of the demo scenes
//! (plain, influence map, wireframe, selection) with pixel checks of what must be visible, and
//! GPU deformation against the CPU operator.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::sync::LazyLock;

use glam::{DVec3, Vec3};
use image::RgbaImage;
use starcages_core::BindControl;
use starcages_core::generate::demo::demo_scene;
use starcages_core::scene::Scene;
use starcages_core::star::StarBinding;
use starcages_viewport::colors;
use starcages_viewport::gpu::{GpuContext, OFFSCREEN_FORMAT, SceneRenderer};
use starcages_viewport::influence;
use starcages_viewport::layers::CageStyle;
use starcages_viewport::offscreen::download;
use starcages_viewport::{Layers, RenderOptions, framing_camera, render_to_image};

/// One device for the whole test binary.
static GPU: LazyLock<GpuContext> = LazyLock::new(|| {
    let gpu = GpuContext::headless().unwrap_or_else(|e| panic!("{e}"));
    eprintln!("adapter: {:?}", gpu.adapter_info);
    gpu
});

fn bound(name: &str, detail: f64) -> (Scene, StarBinding) {
    let scene = demo_scene(name, detail).unwrap();
    let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
    (scene, binding)
}

fn options() -> RenderOptions {
    // No MSAA: sample placement differs between rasterisers.
    RenderOptions {
        width: 256,
        height: 192,
        msaa: false,
        ..RenderOptions::default()
    }
}

fn snapshot_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots")
}

/// Compares with the stored snapshot: a pixel fails when a channel differs by more than 24
/// (lavapipe JIT differences stay far below), and at most 0.5 % of pixels may fail. A missing
/// snapshot is written as `NAME.new.png` and fails, unless UPDATE_SNAPSHOTS=1 stores it.
fn check_snapshot(name: &str, image: &RgbaImage) {
    let dir = snapshot_dir();
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.png"));
    if std::env::var_os("UPDATE_SNAPSHOTS").is_some() {
        image.save(&path).unwrap();
        return;
    }
    let Ok(stored) = image::open(&path) else {
        image.save(dir.join(format!("{name}.new.png"))).unwrap();
        panic!(
            "missing snapshot {}: run with UPDATE_SNAPSHOTS=1 after looking at {name}.new.png",
            path.display()
        );
    };
    let stored = stored.to_rgba8();
    assert_eq!(
        stored.dimensions(),
        image.dimensions(),
        "{name}: size changed"
    );
    let failing = stored
        .pixels()
        .zip(image.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 24))
        .count();
    let allowed = (image.width() * image.height()) as usize / 200;
    if failing > allowed {
        image.save(dir.join(format!("{name}.new.png"))).unwrap();
        panic!(
            "{name}: {failing} pixels differ from the snapshot (at most {allowed}); see {name}.new.png"
        );
    }
}

/// Pixels close to `colour` (each channel within `tolerance`).
fn count_near(image: &RgbaImage, colour: [u8; 4], tolerance: u8) -> usize {
    image
        .pixels()
        .filter(|p| {
            p.0[..3]
                .iter()
                .zip(&colour[..3])
                .all(|(a, b)| a.abs_diff(*b) <= tolerance)
        })
        .count()
}

/// Distinct colours, a blank-image check.
fn distinct(image: &RgbaImage) -> usize {
    let mut colours: Vec<[u8; 4]> = image.pixels().map(|p| p.0).collect();
    colours.sort_unstable();
    colours.dedup();
    colours.len()
}

/// Pixels that are clearly reddish / bluish (influence-map ends, after lighting).
fn reddish(image: &RgbaImage) -> usize {
    image
        .pixels()
        .filter(|p| {
            let [r, g, b, _] = p.0.map(u16::from);
            r > 120 && r > 2 * b && r > g + 40
        })
        .count()
}

fn bluish(image: &RgbaImage) -> usize {
    image
        .pixels()
        .filter(|p| {
            let [r, _, b, _] = p.0.map(u16::from);
            b > 120 && b > 2 * r
        })
        .count()
}

fn render(
    scene: &Scene,
    binding: &StarBinding,
    pose: &[DVec3],
    options: &RenderOptions,
) -> RgbaImage {
    let camera = framing_camera(scene, pose);
    render_to_image(&GPU, scene, binding, pose, &camera, options).unwrap()
}

/// Keeps a copy of every rendered image for looking at (target/tmp).
fn keep(name: &str, image: &RgbaImage) {
    image
        .save(Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}.png")))
        .unwrap();
}

#[test]
fn plain_demo_scene() {
    let (scene, binding) = bound("bar", 0.5);
    let pose = &scene.poses["bend"];
    let image = render(&scene, &binding, pose, &options());
    keep("bar_bend", &image);
    assert!(distinct(&image) > 50, "blank image");
    // The clay mesh covers a good part of the view; cage lines in MVC blue are drawn.
    let clay = image
        .pixels()
        .filter(|p| p.0[0] > 90 && p.0[0].abs_diff(p.0[1]) < 25 && p.0[2] < p.0[0])
        .count();
    assert!(clay > 2000, "{clay} clay pixels");
    let mvc = colors::to_u8(colors::kind(
        starcages_core::coords::CoordinateKind::MeanValue,
    ));
    assert!(count_near(&image, mvc, 30) > 50, "no blue cage lines");
    check_snapshot("bar_bend", &image);
}

#[test]
fn influence_map_has_both_ends() {
    let (scene, binding) = bound("bumpy", 0.4);
    let map = influence::boundary(&binding, None);
    let image = render(
        &scene,
        &binding,
        &scene.poses["lift"],
        &RenderOptions {
            map: Some(map),
            layers: Layers {
                cages: false,
                vertices: false,
                ..Layers::default()
            },
            ..options()
        },
    );
    keep("bumpy_b_map", &image);
    assert!(
        reddish(&image) > 300,
        "no red (T) in the b map: {}",
        reddish(&image)
    );
    assert!(
        bluish(&image) > 300,
        "no blue (join) in the b map: {}",
        bluish(&image)
    );
    check_snapshot("bumpy_b_map", &image);
}

#[test]
fn wireframe_and_flat_shading() {
    let (scene, binding) = bound("bumpy", 0.25);
    let plain = render(
        &scene,
        &binding,
        &scene.poses["lift"],
        &RenderOptions {
            layers: Layers {
                cages: false,
                vertices: false,
                ..Layers::default()
            },
            ..options()
        },
    );
    let wire = render(
        &scene,
        &binding,
        &scene.poses["lift"],
        &RenderOptions {
            layers: Layers {
                cages: false,
                vertices: false,
                wireframe: true,
                flat: true,
                ..Layers::default()
            },
            ..options()
        },
    );
    keep("bumpy_plain", &plain);
    keep("bumpy_wireframe", &wire);
    let dark = |image: &RgbaImage| {
        image
            .pixels()
            .filter(|p| p.0[..3].iter().all(|&c| c < 60))
            .count()
    };
    assert!(
        dark(&wire) > dark(&plain) + 200,
        "wireframe not drawn: {} vs {}",
        dark(&wire),
        dark(&plain)
    );
    check_snapshot("bumpy_wireframe", &wire);
}

#[test]
fn selection_is_highlighted() {
    let (scene, binding) = bound("critter", 0.5);
    let ears = scene.cages.cage_vertices("ears").unwrap();
    let style = CageStyle {
        selected: ears.iter().copied().collect(),
        hovered: Some(0),
        focus_level: Some(1),
        ..CageStyle::default()
    };
    let pose = &scene.poses["fig13"];
    let image = render(
        &scene,
        &binding,
        pose,
        &RenderOptions { style, ..options() },
    );
    keep("critter_selection", &image);
    let orange = count_near(&image, colors::to_u8(colors::SELECTED), 40);
    assert!(orange > 100, "{orange} selected-vertex pixels");
    check_snapshot("critter_selection", &image);
}

#[test]
fn gpu_deformation_matches_the_cpu_operator() {
    let (scene, binding) = bound("prism", 0.5);
    if !GPU.compute {
        eprintln!("no compute shaders on this adapter: the CPU path is used");
        return;
    }
    let rest: Vec<Vec3> = scene.mesh.welded_positions_f32();
    let mut renderer = SceneRenderer::new(&GPU, OFFSCREEN_FORMAT, 1);
    renderer.set_mesh(
        &GPU,
        &rest,
        scene.mesh.welded_triangles(),
        Some(&binding.operator),
    );
    assert!(renderer.deforms_on_gpu());
    let pose = &scene.poses["twist"];
    let mut encoder = GPU.device.create_command_encoder(&Default::default());
    let dofs = binding.operator.dofs(&scene.cages.vertices, pose);
    assert!(renderer.deform_on_gpu(&GPU, &mut encoder, &dofs));
    GPU.queue.submit([encoder.finish()]);
    let bytes = download(&GPU, renderer.position_buffer().unwrap()).unwrap();
    let gpu: &[Vec3] = bytemuck::cast_slice(&bytes[..rest.len() * 12]);
    let cpu = binding.deform(&scene.cages.vertices, pose);
    let (lo, hi) = scene.mesh.bounds();
    let diagonal = (hi - lo).length() as f32;
    let worst = gpu
        .iter()
        .zip(&cpu)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f32::max);
    assert!(
        worst <= 1e-5 * diagonal,
        "GPU and CPU differ by {worst} (diagonal {diagonal})"
    );
}

/// X-ray draws the mesh translucent and the cages over it: cage vertices and edges behind the
/// mesh show (more dark vertex pixels and blue edge pixels than without), the mesh is still
/// there; a low cage opacity fades the cages. Snapshots of both.
#[test]
fn xray_shows_the_cages_through_the_mesh_and_cage_opacity_fades_them() {
    let (scene, binding) = bound("critter", 0.3);
    let pose = &scene.poses["fig13"];
    let with = |layers: Layers| {
        render(
            &scene,
            &binding,
            pose,
            &RenderOptions {
                layers,
                ..options()
            },
        )
    };
    let plain = with(Layers::default());
    let xray = with(Layers {
        xray: true,
        ..Layers::default()
    });
    let faded = with(Layers {
        cage_opacity: 0.15,
        ..Layers::default()
    });
    keep("critter_plain", &plain);
    keep("critter_xray", &xray);
    keep("critter_faded_cages", &faded);
    let vertex = colors::to_u8(colors::VERTEX);
    let mvc = colors::to_u8(colors::kind(
        starcages_core::coords::CoordinateKind::MeanValue,
    ));
    let cage_pixels =
        |image: &RgbaImage| count_near(image, vertex, 12) + count_near(image, mvc, 30);
    let clay = |image: &RgbaImage| {
        image
            .pixels()
            .filter(|p| p.0[0] > 90 && p.0[0].abs_diff(p.0[1]) < 25 && p.0[2] < p.0[0])
            .count()
    };
    assert!(
        cage_pixels(&xray) > cage_pixels(&plain) + 40,
        "x-ray shows the cages behind the mesh: {} vs {}",
        cage_pixels(&xray),
        cage_pixels(&plain)
    );
    assert!(
        clay(&xray) > 300,
        "the mesh is still drawn in x-ray: {}",
        clay(&xray)
    );
    assert!(clay(&xray) < clay(&plain), "x-ray's mesh is translucent");
    // Faded edges blend into the background (faded vertices would look like it too).
    let edges = |image: &RgbaImage| count_near(image, mvc, 30);
    assert!(
        edges(&faded) * 3 < edges(&plain),
        "faded cage edges: {} vs {}",
        edges(&faded),
        edges(&plain)
    );
    check_snapshot("critter_xray", &xray);
    check_snapshot("critter_plain_cages", &plain);
}

/// The textured sphere (`starcages_io::sample_files`) as a scene in a grid of cages, with its
/// loaded look.
fn textured_sphere(
    folder: &Path,
    obj: bool,
) -> (
    Scene,
    StarBinding,
    std::sync::Arc<starcages_core::mesh::look::LoadedLook>,
) {
    let samples = starcages_io::sample_files::write_textured_samples(folder).unwrap();
    let path = if obj { samples.obj } else { samples.glb };
    let (mesh, look) = starcages_io::read_mesh_look(&path).unwrap();
    let up = starcages_core::scene::UpAxis::Y;
    let mesh = up.mesh_to_scene(mesh);
    let cages = starcages_core::generate::autocage(
        &mesh,
        &starcages_core::generate::AutocageOptions {
            grid: [1, 1, 1],
            ..Default::default()
        },
    );
    let scene = Scene::from_mesh_file(path, up, mesh, cages, Default::default());
    let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
    let loaded = starcages_io::load_look_images(look);
    assert!(loaded.problems.is_empty(), "{:?}", loaded.problems);
    (scene, binding, std::sync::Arc::new(loaded))
}

fn greenish(image: &RgbaImage) -> usize {
    image
        .pixels()
        .filter(|p| {
            let [r, g, b, _] = p.0.map(u16::from);
            g > 90 && g > r + 40 && g > b + 40
        })
        .count()
}

/// Textured shading draws each material: the checker's red squares on the northern half (the
/// image's top half: its orientation is kept), the green factor on the southern half, the
/// same from the GLB (UV origin at the top) and the OBJ + MTL (at the bottom); Solid and
/// MatCap draw no material colour. Snapshots of each mode, looked at.
#[test]
fn each_shading_mode_on_a_textured_mesh() {
    use starcages_viewport::{Matcap, Shading};
    let folder = tempfile::tempdir().unwrap();
    let (scene, binding, look) = textured_sphere(folder.path(), false);
    let pose = scene.cages.vertices.clone();
    let with = |scene: &Scene, binding: &StarBinding, look, shading| {
        render(
            scene,
            binding,
            &pose,
            &RenderOptions {
                layers: Layers {
                    shading,
                    cages: false,
                    vertices: false,
                    ..Layers::default()
                },
                look,
                ..options()
            },
        )
    };
    let textured = with(&scene, &binding, Some(look.clone()), Shading::Textured);
    let solid = with(&scene, &binding, Some(look.clone()), Shading::Solid);
    let clay = with(
        &scene,
        &binding,
        Some(look.clone()),
        Shading::MatCap(Matcap::Clay),
    );
    let metal = with(&scene, &binding, None, Shading::MatCap(Matcap::Metal));
    let unlooked = with(&scene, &binding, None, Shading::Textured);
    for (name, image) in [
        ("sphere_textured", &textured),
        ("sphere_solid", &solid),
        ("sphere_matcap_clay", &clay),
        ("sphere_matcap_metal", &metal),
    ] {
        keep(name, image);
        check_snapshot(name, image);
    }
    // Red squares above, green below.
    let mean_row = |keep: &dyn Fn(&image::Rgba<u8>) -> bool| {
        let rows: Vec<u32> = textured
            .enumerate_pixels()
            .filter(|(_, _, p)| keep(p))
            .map(|(_, y, _)| y)
            .collect();
        rows.iter().map(|&y| f64::from(y)).sum::<f64>() / rows.len().max(1) as f64
    };
    let red = |p: &image::Rgba<u8>| {
        let [r, g, b, _] = p.0.map(u16::from);
        r > 120 && r > 2 * b && r > g + 40
    };
    let green = |p: &image::Rgba<u8>| {
        let [r, g, b, _] = p.0.map(u16::from);
        g > 90 && g > r + 40 && g > b + 40
    };
    assert!(reddish(&textured) > 300, "no checker");
    assert!(greenish(&textured) > 300, "no green");
    assert!(
        mean_row(&red) + 10.0 < mean_row(&green),
        "checker not above the green"
    );
    assert!(
        bluish(&textured) < reddish(&textured) / 4,
        "image upside down"
    );
    for (name, image) in [("solid", &solid), ("matcap", &clay), ("no look", &unlooked)] {
        assert_eq!(
            reddish(image) + greenish(image),
            0,
            "{name} shows materials"
        );
    }
    // The OBJ draws as the GLB (its v counts from the bottom row).
    let (obj_scene, obj_binding, obj_look) = textured_sphere(folder.path(), true);
    let from_obj = with(&obj_scene, &obj_binding, Some(obj_look), Shading::Textured);
    keep("sphere_textured_obj", &from_obj);
    let differing = from_obj
        .pixels()
        .zip(textured.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 24))
        .count();
    assert!(
        differing < 100,
        "{differing} pixels differ between GLB and OBJ"
    );
}

/// Ghosts: at frame 8 of the critter's ear fold (ears up at 1, back at 12), frames 2 and 14
/// drawn translucent in their tints over the mesh; without ghosts neither tint shows.
#[test]
fn ghosts_show_the_frames_around_the_ear_fold() {
    let (scene, binding) = bound("critter", 0.3);
    let at = |frame: f64| {
        starcages_core::posing::PoseRequest::frame(frame)
            .resolve(&scene)
            .unwrap()
            .cages
    };
    let pose = at(8.0);
    let before = [0.95, 0.35, 0.25, 0.45];
    let after = [0.25, 0.55, 0.95, 0.45];
    // The mesh framed, the cages hidden: the ghosts are what is looked at.
    let (lo, hi) = scene.mesh.bounds();
    let mut camera = starcages_viewport::OrbitCamera::default();
    camera.frame(lo.as_vec3(), hi.as_vec3());
    let with = |ghosts| {
        let options = RenderOptions {
            ghosts,
            layers: Layers {
                cages: false,
                vertices: false,
                ..Layers::default()
            },
            ..options()
        };
        render_to_image(&GPU, &scene, &binding, &pose, &camera, &options).unwrap()
    };
    let plain = with(Vec::new());
    let ghosted = with(vec![(at(2.0), before), (at(14.0), after)]);
    keep("critter_ghosts", &ghosted);
    check_snapshot("critter_ghosts", &ghosted);
    let changed = plain
        .pixels()
        .zip(ghosted.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 24))
        .count();
    assert!(changed > 200, "ghosts changed only {changed} pixels");
    let tinted = |image: &RgbaImage, blue: bool| {
        image
            .pixels()
            .filter(|p| {
                let [r, g, b, _] = p.0.map(i32::from);
                if blue {
                    b > r + 25 && b > g
                } else {
                    r > b + 25 && r > g + 10
                }
            })
            .count()
    };
    assert!(
        tinted(&ghosted, true) > tinted(&plain, true) + 100,
        "no blue ghost"
    );
    assert!(
        tinted(&ghosted, false) > tinted(&plain, false) + 100,
        "no red ghost"
    );
}

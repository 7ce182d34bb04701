//! Every file we write, our readers read back (issue 42, class 2): any animation that
//! validates, sampled as `bake` and `cages --out` sample it, goes through every writer (PC2,
//! MDD, animated glTF) to files that `read_point_cache` and the glTF readers accept with the
//! same samples; any mesh goes through the deform writers (OBJ, GLB) to files that read back
//! with the same triangles. The validation bounds (fps, frames) are what make this hold: the negative
//! controls show the writers refusing what validation refuses, and the reader refusing the
//! header a writer without those checks wrote.

use starcages_core::anim::SampleTimes;
use std::path::Path;

use glam::{DVec3, Vec3};
use proptest::prelude::*;
use starcages_core::anim::sampling::{animation_samples, gltf_seconds};
use starcages_core::anim::{Animation, Interpolation, Key};
use starcages_core::mesh::Mesh;
use starcages_io::{
    MorphAnimation, PointCacheFormat, PointCacheWriter, read_mesh, read_point_cache,
};

use starcages_test_support::Scratch;

fn scratch() -> Scratch {
    Scratch::new("written-files")
}

fn tetrahedron() -> Mesh {
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    Mesh::new(
        positions,
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        None,
        None,
    )
    .unwrap()
}

/// One key per frame in `keys`, all on pose "a".
fn animation(fps: f64, start: i64, end: i64, keys: &[f64]) -> Animation {
    Animation {
        fps,
        frame_start: start,
        frame_end: end,
        keys: keys
            .iter()
            .map(|&frame| Key {
                frame,
                pose: "a".into(),
                interpolation: Interpolation::Bezier,
                h: Default::default(),
            })
            .collect(),
    }
}

fn validates(animation: &Animation) -> bool {
    let poses = [("a".to_owned(), vec![DVec3::ZERO])].into_iter().collect();
    animation.problems(&poses, std::iter::empty()).is_empty()
}

/// What a writer did with a bake.
#[derive(Debug)]
enum Written {
    /// Every writer wrote, and every file read back with its samples.
    ReadBack,
    /// A writer refused before writing (the file is not there), with this reason.
    Refused(String),
}

/// Writes `frames` at `times` through the three writers; an error when a file was written that
/// our readers then refuse (or read back wrong).
fn bake_and_read_back(name: &str, frames: &[f64], times: SampleTimes) -> Result<Written, String> {
    let dir = scratch();
    let points = [Vec3::new(1.0, -2.0, 1e9), Vec3::new(-1e9, 0.5, 0.0)];
    for (format, extension) in [
        (PointCacheFormat::Pc2, "pc2"),
        (PointCacheFormat::Mdd, "mdd"),
    ] {
        let path = dir.join(format!("{name}.{extension}"));
        let mut writer =
            match PointCacheWriter::create(&path, format, points.len(), frames.len(), times) {
                Ok(writer) => writer,
                Err(e) if !path.exists() => return Ok(Written::Refused(e.to_string())),
                Err(e) => return Err(format!("refused, yet the file is there: {e}")),
            };
        for _ in frames {
            writer.write_sample(&points).map_err(|e| e.to_string())?;
        }
        writer.finish().map_err(|e| e.to_string())?;
        let cache = read_point_cache(&path, Some(points.len()), times.fps)
            .map_err(|e| format!("written, then refused: {e}"))?;
        if cache.samples.len() != frames.len() {
            return Err(format!(
                "{extension}: {} samples read back",
                cache.samples.len()
            ));
        }
        // The frames come back (MDD through 32-bit seconds: to a part in 10⁶ of the time).
        let first = cache.start_frame;
        let tolerance = 1e-3 * (1.0 + frames[0].abs() * 1e-3);
        if (first - frames[0]).abs() > tolerance {
            return Err(format!(
                "{extension}: starts at frame {first}, not {}",
                frames[0]
            ));
        }
    }
    // An animated glTF holds one morph target per frame, up to 4096: longer bakes are
    // refused before anything is written (docs/cli.md), which is not a file we then refuse.
    if frames.len() > 4096 {
        return Ok(Written::ReadBack);
    }
    let mesh = tetrahedron();
    let path = dir.join(format!("{name}.glb"));
    let mut gltf =
        MorphAnimation::new(&path, &mesh, mesh.positions().to_vec()).map_err(|e| e.to_string())?;
    for (frame, seconds) in frames.iter().zip(gltf_seconds(frames, times.fps)) {
        gltf.push_frame(&mesh, mesh.positions(), seconds, format!("frame {frame}"))
            .map_err(|e| e.to_string())?;
    }
    gltf.write(&mesh).map_err(|e| e.to_string())?;
    read_mesh(&path).map_err(|e| format!("written, then refused: {e}"))?;
    let document = gltf::Gltf::open(&path).map_err(|e| format!("gltf crate: {e}"))?;
    for animation in document.animations() {
        for sampler in animation.samplers() {
            let input = sampler.input();
            let bounds = [input.min(), input.max()];
            if bounds.iter().any(|b| {
                b.as_ref()
                    .and_then(|v| v.as_array()?.first()?.as_f64())
                    .is_none_or(|t| !t.is_finite())
            }) {
                return Err(format!("glTF: times {bounds:?}"));
            }
        }
    }
    Ok(Written::ReadBack)
}

/// A frame rate: ordinary, at the bounds, or absurd.
fn any_fps() -> impl Strategy<Value = f64> {
    prop_oneof![
        0.5f64..240.0,
        Just(0.01),
        Just(1000.0),
        Just(1e-300),
        Just(1e308),
        Just(0.0),
        Just(-24.0),
        1e-4f64..5000.0,
    ]
}

/// A first frame: ordinary, at Blender's limit, or far beyond it.
fn any_start() -> impl Strategy<Value = i64> {
    prop_oneof![
        -100i64..100,
        Just(-1_048_574),
        Just(1_048_574 - 40),
        Just(20_000_000),
        -3_000_000i64..3_000_000,
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(crate::fuzz_readers::fuzz_cases()))]

    #[test]
    fn every_animation_that_validates_bakes_to_files_we_read_back(
        fps in any_fps(),
        start in any_start(),
        length in 0i64..40,
        keys in prop::collection::vec(-2e6f64..2e6, 1..3),
        rate in prop::option::of(any_fps()),
        range in prop::option::of((any_start(), 0i64..40)),
        case in 0u32..1_000_000,
    ) {
        let mut keys = keys;
        keys.sort_by(f64::total_cmp);
        keys.dedup();
        let animation = animation(fps, start, start.saturating_add(length), &keys);
        let range = range.map(|(first, length)| (first, first.saturating_add(length)));
        let sampled = animation_samples(&animation, range, rate);
        if !validates(&animation) {
            // Nothing is sampled from an animation whose rate validation refuses.
            if !starcages_core::anim::FPS_RANGE.contains(&fps) {
                prop_assert!(sampled.is_err());
            }
            return Ok(());
        }
        if range.is_none() && rate.is_none() {
            prop_assert!(sampled.is_ok(), "a valid animation's own range: {sampled:?}");
        }
        let Ok((frames, times)) = sampled else {
            return Ok(());
        };
        // Millions of samples (0.01 fps resampled at 1000) take too long to write here; their
        // headers are the same code.
        if frames.len() > 20_000 {
            return Ok(());
        }
        let written = bake_and_read_back(&format!("case{case}"), &frames, times);
        match &written {
            Ok(Written::ReadBack) => {}
            // The animation's own frames at its own rate always fit the formats; resampled at
            // another rate far from frame 0, MDD's 32-bit times may collide: refused, naming
            // the sample, before anything is written.
            Ok(Written::Refused(why)) => prop_assert!(
                rate.is_some() && why.contains("not written"),
                "{fps} fps, {range:?} at {rate:?}: {why}"
            ),
            Err(why) => prop_assert!(false, "{fps} fps, {range:?} at {rate:?}: {why}"),
        }
    }
}

/// The negative controls: what validation refuses, the writers refuse too (before writing);
/// a header written without those checks is one the reader refuses.
#[test]
fn what_validation_refuses_is_never_written() {
    let dir = scratch();
    for fps in [1e-300, 1e308] {
        let animation = animation(fps, 1, 48, &[1.0, 24.0]);
        assert!(!validates(&animation), "{fps}");
        assert!(animation_samples(&animation, None, None).is_err(), "{fps}");
    }
    assert!(!validates(&animation(24.0, 20_000_000, 20_000_010, &[1.0])));
    // Times that overflow or collide in 32 bits: refused by the writer, nothing written.
    let cases = [
        (
            PointCacheFormat::Mdd,
            SampleTimes {
                start_frame: 1.0,
                frame_step: 1.0,
                fps: 1e-300,
            },
        ),
        (
            PointCacheFormat::Mdd,
            SampleTimes {
                start_frame: 2e7,
                frame_step: 1.0,
                fps: 24.0,
            },
        ),
        (
            PointCacheFormat::Pc2,
            SampleTimes {
                start_frame: 1.0,
                frame_step: 1e300,
                fps: 24.0,
            },
        ),
        (
            PointCacheFormat::Pc2,
            SampleTimes {
                start_frame: 1e300,
                frame_step: 1.0,
                fps: 24.0,
            },
        ),
    ];
    for (k, (format, times)) in cases.into_iter().enumerate() {
        let path = dir.join(format!("refused{k}.cache"));
        let path = path.with_extension(if format == PointCacheFormat::Pc2 {
            "pc2"
        } else {
            "mdd"
        });
        let error = match PointCacheWriter::create(&path, format, 1, 10, times) {
            Ok(_) => panic!("{k}: {times:?} was accepted"),
            Err(e) => e.to_string(),
        };
        assert!(
            error.contains("not written") && error.contains("32-bit float"),
            "{k}: {error}"
        );
        assert!(!path.exists(), "{k}");
    }
    // Without the writer's check: a PC2 whose sampling is infinite, as such a writer wrote it.
    let mut bytes = b"POINTCACHE2\0".to_vec();
    for field in [1i32.to_le_bytes(), 1i32.to_le_bytes()] {
        bytes.extend(field);
    }
    bytes.extend(1.0f32.to_le_bytes());
    bytes.extend(f32::INFINITY.to_le_bytes());
    bytes.extend(1i32.to_le_bytes());
    bytes.extend([0u8; 12]);
    let path = dir.join("unchecked.pc2");
    std::fs::write(&path, &bytes).unwrap();
    let error = read_point_cache(&path, None, 24.0).unwrap_err().to_string();
    assert!(error.contains("sampling inf"), "{error}");
    assert!(Path::new(&path).exists());
}

/// A coordinate: ordinary, tiny, or at the edge of the supported range.
fn any_coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        -10.0f64..10.0,
        -1e9f64..1e9,
        -1e-30f64..1e-30,
        Just(1e9),
        Just(-1e9),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(crate::fuzz_readers::fuzz_cases()))]

    /// Every mesh the deform and export paths write (OBJ, GLB) reads back with its vertices
    /// and triangles, wherever in the supported range its coordinates lie.
    #[test]
    fn every_mesh_we_write_reads_back(
        points in prop::collection::vec(prop::array::uniform3(any_coordinate()), 3..24),
        corners in prop::collection::vec(prop::array::uniform3(0usize..24), 1..30),
        with_uvs in any::<bool>(),
        case in 0u32..1_000_000,
    ) {
        let positions: Vec<DVec3> = points.iter().map(|p| DVec3::from_array(*p)).collect();
        let n = positions.len();
        let triangles: Vec<[u32; 3]> = corners
            .iter()
            .map(|t| t.map(|i| (i % n) as u32))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
        let uvs = with_uvs.then(|| (0..n).map(|i| glam::Vec2::new(i as f32 * 0.1, 0.5)).collect());
        let Ok(mesh) = Mesh::new(positions.clone(), triangles, None, uvs) else {
            return Ok(());
        };
        let dir = scratch();
        for extension in ["obj", "glb"] {
            let path = dir.join(format!("mesh{case}.{extension}"));
            starcages_io::write_mesh(&path, &mesh, mesh.positions())
                .map_err(|e| TestCaseError::fail(format!("{extension}: not written: {e}")))?;
            let read = read_mesh(&path)
                .map_err(|e| TestCaseError::fail(format!("{extension}: written, then refused: {e}")))?;
            prop_assert_eq!(read.triangles().len(), mesh.triangles().len(), "{}", extension);
            // Each triangle's corners where they were (an OBJ reader lays vertices out in the
            // order the faces first use them); GLB holds 32-bit floats.
            let corner = |m: &Mesh, t: usize, k: usize| m.positions()[m.triangles()[t][k] as usize];
            for t in 0..mesh.triangles().len() {
                for k in 0..3 {
                    let (a, b) = (corner(&read, t, k), corner(&mesh, t, k));
                    let tolerance = 1e-6 * b.abs().max_element().max(1e-30);
                    prop_assert!(
                        (a - b).abs().max_element() <= tolerance,
                        "{}: triangle {}: {} for {}", extension, t, a, b
                    );
                }
            }
        }
    }
}

//! Animation: curve properties (interpolation at keys, no overshoot, C1 at smooth keys with a
//! linear negative control), poses and h at frames, validation, scene files, point caches
//! against their specifications (and forged ones), and baked glTF read back by the `gltf`
//! crate.

use std::collections::BTreeMap;
use std::path::PathBuf;

use glam::{DVec3, Vec3};
use proptest::prelude::*;
use starcages_core::anim::curve::{self, Interpolation};
use starcages_core::anim::{Animation, AnimationProblem, Key};
use starcages_core::generate::demo::demo_scene;
use starcages_core::io::{
    MorphAnimation, PointCacheFormat, PointCacheWriter, SampleTimes, parse_point_cache,
    read_point_cache,
};
use starcages_core::scene::{SceneProblem, load_scene, save_scene, validate_scene};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("starcages-anim-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Strictly increasing key times and a value per key.
fn channel() -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    prop::collection::vec((0.5f64..12.0, -5.0f64..5.0), 2..7).prop_map(|pairs| {
        let mut t = 0.0;
        let times = pairs
            .iter()
            .map(|(gap, _)| {
                t += gap;
                t
            })
            .collect();
        (times, pairs.iter().map(|p| p.1).collect())
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Every mode passes through its keys and holds outside them; constant holds a key's
    /// value; linear and smooth segments never leave the range of their two keys (Blender's
    /// auto-clamped handles do not overshoot).
    #[test]
    fn channels_interpolate_their_keys_and_never_overshoot(
        (times, values) in channel(),
        mode in prop::sample::select(Interpolation::ALL.to_vec()),
    ) {
        let modes = vec![mode; times.len()];
        for (t, v) in times.iter().zip(&values) {
            prop_assert!((curve::evaluate(&times, &values, &modes, *t) - v).abs() < 1e-12);
        }
        let last = times.len() - 1;
        prop_assert_eq!(curve::evaluate(&times, &values, &modes, times[0] - 3.0), values[0]);
        prop_assert_eq!(curve::evaluate(&times, &values, &modes, times[last] + 3.0), values[last]);
        for k in 0..last {
            let (lo, hi) = (values[k].min(values[k + 1]), values[k].max(values[k + 1]));
            for step in 1..20 {
                let t = times[k] + (times[k + 1] - times[k]) * step as f64 / 20.0;
                let v = curve::evaluate(&times, &values, &modes, t);
                prop_assert!(v >= lo - 1e-9 && v <= hi + 1e-9, "{v} outside [{lo}, {hi}] at {t}");
                if mode == Interpolation::Constant {
                    prop_assert_eq!(v, values[k]);
                }
            }
        }
    }

    /// Smooth curves are C1 at interior keys: the slopes on both sides agree (finite
    /// differences); linear ones are not where the key is not on the line of its neighbours
    /// (the negative control: the test can see a kink).
    #[test]
    fn smooth_channels_are_c1_at_keys_and_linear_ones_kink(
        (times, values) in channel().prop_filter("three keys", |(t, _)| t.len() >= 3),
    ) {
        let eps = 1e-6;
        let slopes = |mode: Interpolation, k: usize| {
            let modes = vec![mode; times.len()];
            let at = |t: f64| curve::evaluate(&times, &values, &modes, t);
            let t = times[k];
            // Second-order one-sided differences: the first-order ones differ by the
            // curvature times eps at a flat extremum (1.01e-4 at a key of -4.2 between two
            // keys of 0, half a second apart), which read as a kink.
            (
                (3.0 * at(t) - 4.0 * at(t - eps) + at(t - 2.0 * eps)) / (2.0 * eps),
                (-3.0 * at(t) + 4.0 * at(t + eps) - at(t + 2.0 * eps)) / (2.0 * eps),
            )
        };
        for k in 1..times.len() - 1 {
            let (left, right) = slopes(Interpolation::Bezier, k);
            prop_assert!((left - right).abs() < 1e-4 * (1.0 + left.abs()), "{left} vs {right}");
            let secant_before = (values[k] - values[k - 1]) / (times[k] - times[k - 1]);
            let secant_after = (values[k + 1] - values[k]) / (times[k + 1] - times[k]);
            if (secant_before - secant_after).abs() > 1e-2 {
                let (left, right) = slopes(Interpolation::Linear, k);
                prop_assert!((left - right).abs() > 1e-3, "linear shows no kink at key {k}");
            }
        }
    }
}

fn key(frame: f64, pose: &str) -> Key {
    Key {
        frame,
        pose: pose.into(),
        interpolation: Interpolation::Bezier,
        h: BTreeMap::new(),
    }
}

#[test]
fn poses_and_h_at_frames_follow_their_own_keys() {
    let mut poses = BTreeMap::new();
    poses.insert("a".to_owned(), vec![DVec3::ZERO, DVec3::X]);
    poses.insert("b".to_owned(), vec![DVec3::ONE, DVec3::Y]);
    let mut first = key(1.0, "a");
    first.interpolation = Interpolation::Linear;
    first.h.insert("left".into(), 0.2);
    let mut middle = key(5.0, "b");
    middle.interpolation = Interpolation::Constant;
    let mut last = key(9.0, "a");
    last.h.insert("left".into(), 0.6);
    let animation = Animation {
        keys: vec![first, middle, last],
        ..Animation::default()
    };
    // Linear from a to b; constant b until the last key.
    let at3 = animation.pose_at(&poses, 3.0).unwrap();
    assert_eq!(at3, vec![DVec3::splat(0.5), DVec3::new(0.5, 0.5, 0.0)]);
    assert_eq!(animation.pose_at(&poses, 8.9).unwrap(), poses["b"]);
    assert_eq!(animation.pose_at(&poses, 9.0).unwrap(), poses["a"]);
    assert_eq!(animation.pose_at(&poses, -4.0).unwrap(), poses["a"]);
    // h of "left" runs through the two keys that set it (linear: the first key's mode).
    let h = animation.h_at(5.0);
    assert!((h["left"] - 0.4).abs() < 1e-12, "{h:?}");
    assert_eq!(animation.h_at(20.0)["left"], 0.6);
    // A key naming a missing pose gives nothing rather than a wrong pose.
    let mut broken = animation.clone();
    broken.keys[1].pose = "gone".into();
    assert_eq!(broken.pose_at(&poses, 3.0), None);
}

#[test]
fn validation_names_each_animation_problem() {
    let mut scene = demo_scene("bar", 0.3).unwrap();
    let rest = scene.cages.vertices.clone();
    scene.poses.insert("up".into(), rest.clone());
    let cage = scene.cages.leaves[0].name.clone();
    let mut bad_h = key(30.0, "up");
    bad_h.h.insert(cage.clone(), 1.5);
    bad_h.h.insert("nobody".into(), 0.5);
    scene.animation = Animation {
        fps: 0.0,
        frame_start: 10,
        frame_end: 5,
        keys: vec![
            key(10.0, "up"),
            key(4.0, "up"),
            key(f64::NAN, "up"),
            key(20.0, "missing"),
            bad_h,
        ],
    };
    let problems: Vec<AnimationProblem> = validate_scene(&scene)
        .errors
        .into_iter()
        .filter_map(|p| match p {
            SceneProblem::Animation(a) => Some(a),
            _ => None,
        })
        .collect();
    let text: Vec<String> = problems.iter().map(ToString::to_string).collect();
    assert!(
        matches!(problems[0], AnimationProblem::Fps { .. }),
        "{text:?}"
    );
    assert!(
        problems.contains(&AnimationProblem::Range {
            start: 10,
            end: 5,
            why: "empty"
        }),
        "{text:?}"
    );
    assert!(
        problems.iter().any(|p| matches!(
            p,
            AnimationProblem::KeyOrder {
                key: 1,
                previous: 0,
                ..
            }
        )),
        "{text:?}"
    );
    assert!(
        problems
            .iter()
            .any(|p| matches!(p, AnimationProblem::KeyFrame { key: 2, .. })),
        "{text:?}"
    );
    assert!(
        text.iter()
            .any(|t| t.contains("key 3") && t.contains("'missing'") && t.contains("up")),
        "{text:?}"
    );
    assert!(
        problems
            .iter()
            .any(|p| matches!(p, AnimationProblem::KeyH { cage: c, .. } if *c == cage)),
        "{text:?}"
    );
    assert!(
        problems
            .iter()
            .any(|p| matches!(p, AnimationProblem::UnknownCage { cage, .. } if cage == "nobody")),
        "{text:?}"
    );
    // The same scene with its animation repaired validates.
    scene.animation = Animation {
        keys: vec![key(1.0, "up"), key(10.0, "up")],
        ..Animation::default()
    };
    assert!(validate_scene(&scene).is_valid());
}

#[test]
fn animations_round_trip_through_scene_files_and_version_2_files_migrate() {
    let dir = scratch("files");
    let scene = demo_scene("critter", 0.3).unwrap();
    assert!(scene.animation.keys.len() >= 3, "the critter ships keys");
    let path = dir.join("critter.json");
    save_scene(&scene, &path).unwrap();
    let back = load_scene(&path).unwrap();
    assert_eq!(back.animation, scene.animation);
    // A version-2 file has no animation: it opens with the default one.
    let mut plain = demo_scene("bar", 0.3).unwrap();
    plain.animation = Animation::default();
    save_scene(&plain, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        !text.contains("animation"),
        "a default animation is not written"
    );
    std::fs::write(&path, text.replace("\"version\": 3", "\"version\": 2")).unwrap();
    assert_eq!(load_scene(&path).unwrap().animation, Animation::default());
}

#[test]
fn the_creature_walks_with_four_legs_tail_and_head_for_two_seconds() {
    let scene = starcages_core::generate::creature::creature(0.25);
    let animation = &scene.animation;
    let seconds = (animation.frame_end - animation.frame_start + 1) as f64 / animation.fps;
    assert!(seconds >= 2.0, "{seconds} s");
    assert!(validate_scene(&scene).is_valid());
    // Every leg's foot, the tail and the head move during the cycle, and the cycle loops.
    let first = animation.pose_at(&scene.poses, 1.0).unwrap();
    let looped = animation.pose_at(&scene.poses, 49.0).unwrap();
    assert_eq!(first, looped);
    for cage in [
        "shin_front_left",
        "shin_front_right",
        "shin_rear_left",
        "shin_rear_right",
        "tail",
        "head",
    ] {
        let vertices = scene.cages.cage_vertices(cage).unwrap();
        let travel = (1..=48)
            .map(|f| animation.pose_at(&scene.poses, f as f64).unwrap())
            .map(|pose| {
                vertices
                    .iter()
                    .map(|&v| pose[v as usize].distance(first[v as usize]))
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max);
        assert!(travel > 0.05, "{cage} moves only {travel}");
    }
}

fn times() -> SampleTimes {
    SampleTimes {
        start_frame: 3.0,
        frame_step: 1.0,
        fps: 24.0,
    }
}

fn samples() -> Vec<Vec<Vec3>> {
    (0..4)
        .map(|s| {
            (0..5)
                .map(|p| Vec3::new(s as f32, p as f32 * 0.5, -(s as f32) * 0.25 + 1.0))
                .collect()
        })
        .collect()
}

/// Writes a cache and returns its bytes.
fn written(dir: &std::path::Path, name: &str) -> Vec<u8> {
    let path = dir.join(name);
    let format = PointCacheFormat::of(&path).unwrap();
    let mut writer = PointCacheWriter::create(&path, format, 5, 4, times()).unwrap();
    for sample in samples() {
        writer.write_sample(&sample).unwrap();
    }
    writer.finish().unwrap();
    std::fs::read(&path).unwrap()
}

#[test]
fn point_caches_follow_their_specifications_and_read_back() {
    let dir = scratch("caches");
    // PC2: the 32-byte little-endian header, then x y z per point per sample.
    let pc2 = written(&dir, "a.pc2");
    assert_eq!(&pc2[..12], b"POINTCACHE2\0");
    let int = |at: usize| i32::from_le_bytes(pc2[at..at + 4].try_into().unwrap());
    let float = |at: usize| f32::from_le_bytes(pc2[at..at + 4].try_into().unwrap());
    assert_eq!((int(12), int(16), int(28)), (1, 5, 4));
    assert_eq!((float(20), float(24)), (3.0, 1.0));
    assert_eq!(pc2.len(), 32 + 4 * 5 * 12);
    // Sample 2, point 3, y.
    assert_eq!(float(32 + (2 * 5 + 3) * 12 + 4), 1.5);
    // MDD: big-endian counts, one time in seconds per frame, then the frames.
    let mdd = written(&dir, "a.mdd");
    let be_int = |at: usize| i32::from_be_bytes(mdd[at..at + 4].try_into().unwrap());
    let be_float = |at: usize| f32::from_be_bytes(mdd[at..at + 4].try_into().unwrap());
    assert_eq!((be_int(0), be_int(4)), (4, 5));
    assert_eq!(be_float(8), 3.0 / 24.0);
    assert_eq!(be_float(8 + 12), 6.0 / 24.0);
    assert_eq!(mdd.len(), 8 + 4 * 4 + 4 * 5 * 12);
    assert_eq!(be_float(8 + 16 + (2 * 5 + 3) * 12 + 4), 1.5);
    for name in ["a.pc2", "a.mdd"] {
        let cache = read_point_cache(&dir.join(name), Some(5), 24.0).unwrap();
        assert_eq!(cache.samples, samples(), "{name}");
        assert!((cache.start_frame - 3.0).abs() < 1e-5, "{name}");
        assert!((cache.frame_step - 1.0).abs() < 1e-5, "{name}");
    }
}

#[test]
fn forged_and_truncated_caches_are_refused_with_the_reason() {
    let dir = scratch("forged");
    let pc2 = written(&dir, "good.pc2");
    let mdd = written(&dir, "good.mdd");
    let refuse = |format: PointCacheFormat, bytes: &[u8], expected: Option<usize>, says: &str| {
        let error = parse_point_cache(&dir.join("x"), format, bytes, expected, 24.0)
            .unwrap_err()
            .to_string();
        assert!(error.contains(says), "{says:?} not in {error}");
    };
    use PointCacheFormat::{Mdd, Pc2};
    refuse(Pc2, &pc2[..20], None, "32-byte header");
    refuse(Pc2, &pc2[..pc2.len() - 1], None, "truncated");
    refuse(
        Pc2,
        b"POINTCACHE3\0aaaaaaaaaaaaaaaaaaaa",
        None,
        "POINTCACHE2",
    );
    let patch = |bytes: &[u8], at: usize, value: [u8; 4]| {
        let mut copy = bytes.to_vec();
        copy[at..at + 4].copy_from_slice(&value);
        copy
    };
    refuse(
        Pc2,
        &patch(&pc2, 28, (-3i32).to_le_bytes()),
        None,
        "at least 1",
    );
    // A huge header: refused from the file's length, before anything is allocated.
    refuse(
        Pc2,
        &patch(&pc2, 16, i32::MAX.to_le_bytes()),
        None,
        "announces",
    );
    refuse(
        Pc2,
        &patch(&pc2, 24, f32::NAN.to_le_bytes()),
        None,
        "sampling",
    );
    refuse(
        Pc2,
        &patch(&pc2, 40, f32::NAN.to_le_bytes()),
        None,
        "not finite",
    );
    refuse(Pc2, &pc2, Some(6), "6 are needed");
    refuse(Mdd, &mdd[..6], None, "8-byte header");
    refuse(
        Mdd,
        &patch(&mdd, 0, (-1i32).to_be_bytes()),
        None,
        "at least 1",
    );
    refuse(
        Mdd,
        &patch(&mdd, 4, i32::MAX.to_be_bytes()),
        None,
        "announces",
    );
    refuse(
        Mdd,
        &patch(&mdd, 12, 0f32.to_be_bytes()),
        None,
        "times must increase",
    );
    let mut extra = mdd.clone();
    extra.extend(std::iter::repeat_n(0u8, 5 * 12));
    refuse(Mdd, &extra, None, "rest pose");
}

#[test]
fn an_unfinished_or_refused_cache_leaves_the_old_file() {
    let dir = scratch("atomic");
    let path = dir.join("keep.pc2");
    std::fs::write(&path, b"old").unwrap();
    let mut writer = PointCacheWriter::create(&path, PointCacheFormat::Pc2, 2, 2, times()).unwrap();
    writer.write_sample(&[Vec3::ZERO, Vec3::ONE]).unwrap();
    assert!(writer.write_sample(&[Vec3::ZERO]).is_err(), "wrong size");
    assert!(
        writer
            .write_sample(&[Vec3::ZERO, Vec3::splat(f32::NAN)])
            .is_err(),
        "NaN"
    );
    assert!(writer.finish().is_err(), "one sample short");
    assert_eq!(std::fs::read(&path).unwrap(), b"old");
    let leftovers = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(leftovers, 1, "the temporary file is gone");
}

#[test]
fn baked_gltf_holds_one_morph_target_per_frame_and_plays_them_in_order() {
    let dir = scratch("gltf");
    let scene = demo_scene("bar", 0.3).unwrap();
    let mesh = &scene.mesh;
    let rest: Vec<DVec3> = mesh.positions().to_vec();
    let frame = |k: usize| -> Vec<DVec3> {
        rest.iter()
            .map(|p| *p + DVec3::new(0.1 * k as f64 * p.z, 0.0, 0.05 * k as f64))
            .collect()
    };
    for name in ["bake.glb", "bake.gltf"] {
        let path = dir.join(name);
        let mut animation = MorphAnimation::new(&path, mesh, rest.clone()).unwrap();
        for k in 0..3 {
            animation
                .push_frame(mesh, &frame(k), k as f64 / 24.0, format!("frame {k}"))
                .unwrap();
        }
        animation.write(mesh).unwrap();
        let (document, buffers) = open_gltf(&path);
        let gltf_mesh = document.meshes().next().unwrap();
        let primitive = gltf_mesh.primitives().next().unwrap();
        let reader = primitive.reader(|b| Some(&buffers[b.index()]));
        let base: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        assert_eq!(base.len(), rest.len(), "{name}");
        assert!(reader.read_normals().is_some() && reader.read_tex_coords(0).is_none());
        let targets: Vec<_> = reader.read_morph_targets().collect();
        assert_eq!(targets.len(), 3, "{name}");
        for (k, (positions, normals, _)) in targets.into_iter().enumerate() {
            let offsets: Vec<[f32; 3]> = positions.unwrap().collect();
            assert!(normals.is_some());
            for ((b, o), expected) in base.iter().zip(&offsets).zip(frame(k)) {
                let p = Vec3::from_array(*b) + Vec3::from_array(*o);
                assert!((p - expected.as_vec3()).length() < 1e-5, "{name} frame {k}");
            }
        }
        let animation = document.animations().next().unwrap();
        let channel = animation.channels().next().unwrap();
        assert_eq!(
            channel.target().property(),
            gltf::animation::Property::MorphTargetWeights
        );
        let reader = channel.reader(|b| Some(&buffers[b.index()]));
        let times: Vec<f32> = reader.read_inputs().unwrap().collect();
        assert_eq!(times, vec![0.0, 1.0 / 24.0, 2.0 / 24.0]);
        let weights: Vec<f32> = match reader.read_outputs().unwrap() {
            gltf::animation::util::ReadOutputs::MorphTargetWeights(w) => w.into_f32().collect(),
            _ => panic!("weights expected"),
        };
        // At each frame's time its own target, alone.
        assert_eq!(weights, vec![1., 0., 0., 0., 1., 0., 0., 0., 1.]);
        // Our own reader opens the file as the rest mesh.
        let back = starcages_core::io::read_mesh(&path).unwrap();
        assert_eq!(back.positions().len(), rest.len());
    }
}

/// A glTF document and its one buffer: a GLB's BIN chunk, or a .gltf's data URI.
fn open_gltf(path: &std::path::Path) -> (gltf::Document, Vec<Vec<u8>>) {
    use base64::Engine as _;
    let gltf = gltf::Gltf::from_slice(&std::fs::read(path).unwrap()).unwrap();
    let buffer = match gltf.blob.clone() {
        Some(blob) => blob,
        None => {
            let buffer = gltf.document.buffers().next().unwrap();
            let gltf::buffer::Source::Uri(uri) = buffer.source() else {
                panic!("a .gltf bake embeds its buffer")
            };
            let data = uri
                .strip_prefix("data:application/octet-stream;base64,")
                .unwrap();
            base64::engine::general_purpose::STANDARD
                .decode(data)
                .unwrap()
        }
    };
    (gltf.document, vec![buffer])
}

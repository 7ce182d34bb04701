//! Animation: curve properties (interpolation at keys, no overshoot, C1 at smooth keys with a
//! linear negative control), poses and h at frames, validation, scene files, point caches
//! against their specifications (and forged ones), and baked glTF read back by the `gltf`
//! crate.

use starcages_core::anim::SampleTimes;

use glam::{DVec3, Vec3};
use starcages_core::anim::Animation;
use starcages_core::generate::demo::demo_scene;
use starcages_io::{
    MorphAnimation, PointCacheFormat, PointCacheWriter, parse_point_cache, read_point_cache,
};
use starcages_io::{load_scene, save_scene};

use starcages_test_support::Scratch;

fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("anim-{name}"))
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
        let back = starcages_io::read_mesh(&path).unwrap();
        assert_eq!(back.positions().len(), rest.len());
    }
}

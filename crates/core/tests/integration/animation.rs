//! Animation: curve properties (interpolation at keys, no overshoot, C1 at smooth keys with a
//! linear negative control), poses and h at frames, validation, scene files, point caches
//! against their specifications (and forged ones), and baked glTF read back by the `gltf`
//! crate.

use std::collections::BTreeMap;

use glam::DVec3;
use proptest::prelude::*;
use starcages_core::anim::curve::{self, Interpolation};
use starcages_core::anim::{Animation, AnimationProblem, Key};
use starcages_core::check::validate_scene;
use starcages_core::generate::demo::demo_scene;
use starcages_core::scene::SceneProblem;

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

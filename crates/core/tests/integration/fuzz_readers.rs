//! No panic on arbitrary input: the scene, mesh OBJ, cage OBJ and point readers on random bytes
//! and on randomly damaged valid files (a proptest harness; run longer with
//! `PROPTEST_CASES=20000 cargo test --release -p starcages-core --test integration fuzz_readers`).

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use proptest::prelude::*;
use starcages_core::io::{parse_obj_cages, parse_points, read_cage_obj, read_mesh};
use starcages_core::scene::demo::demo_scene;
use starcages_core::scene::{load_scene, save_scene};

fn scratch() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("starcages-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn valid_scene_text() -> String {
    let path = scratch().join("valid.json");
    save_scene(&demo_scene("bar", 0.2).unwrap(), &path).unwrap();
    std::fs::read_to_string(path).unwrap()
}

const CUBE_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\no a\n\
f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

fn damage(text: &str, cuts: &[(usize, u8)]) -> Vec<u8> {
    let mut bytes = text.as_bytes().to_vec();
    for &(at, b) in cuts {
        if bytes.is_empty() {
            break;
        }
        let i = at % bytes.len();
        match b % 3 {
            0 => bytes[i] = b,
            1 => {
                bytes.remove(i);
            }
            _ => bytes.truncate(i),
        }
    }
    bytes
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn scene_reader_never_panics(cuts in prop::collection::vec((any::<usize>(), any::<u8>()), 1..6), raw in prop::collection::vec(any::<u8>(), 0..200)) {
        let dir = scratch();
        let text = valid_scene_text();
        for (name, bytes) in [("damaged.json", damage(&text, &cuts)), ("raw.json", raw)] {
            let path = dir.join(format!("{}-{name}", std::process::id()));
            std::fs::write(&path, &bytes).unwrap();
            let _ = load_scene(&path);
        }
    }

    #[test]
    fn obj_readers_never_panic(cuts in prop::collection::vec((any::<usize>(), any::<u8>()), 1..6), raw in prop::collection::vec(any::<u8>(), 0..200)) {
        let dir = scratch();
        for (name, bytes) in [("damaged.obj", damage(CUBE_OBJ, &cuts)), ("raw.obj", raw)] {
            let path = dir.join(name);
            std::fs::write(&path, &bytes).unwrap();
            let _ = read_mesh(&path);
            let _ = read_cage_obj(&path);
            let text = String::from_utf8_lossy(&bytes);
            let _ = parse_obj_cages(&text, &path);
            let _ = parse_points(&text, &path);
        }
    }
}

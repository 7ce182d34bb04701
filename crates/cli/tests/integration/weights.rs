//! End-to-end tests of `starcages-cli weights`: JSON shape and values, and one-line errors
//! with exit status 2 for bad input.

// Tests may unwrap: a panic is the failure report (clippy.toml allows it in #[test] fns).
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;
use std::process::{Command, Output};

const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

fn scratch_dir(name: &str) -> starcages_test_support::Scratch {
    crate::common::dir(name)
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write test file");
    path
}

fn weights(cage: &std::path::Path, points: &std::path::Path, kind: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_starcages-cli"))
        .args(["weights", "--cage"])
        .arg(cage)
        .arg("--points")
        .arg(points)
        .args(["--coords", kind, "--resolution", "16"])
        .output()
        .expect("run starcages-cli")
}

#[test]
fn prints_weights_as_json_for_each_kind() {
    let dir = scratch_dir("json");
    let cage = write(&dir, "cube.obj", CUBE);
    let points = write(
        &dir,
        "points.txt",
        "# comment\n0.5 0.5 0.5\n\n0.2 0.3 0.7 # inline\n",
    );
    for kind in ["mvc", "hc", "gc"] {
        let out = weights(&cage, &points, kind);
        assert!(
            out.status.success(),
            "{kind}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("valid JSON");
        assert_eq!(json["kind"], kind);
        assert_eq!(json["vertices"], 8);
        assert_eq!(json["faces"], 12);
        assert_eq!(json["polygons"], 6);
        let rows = json["points"].as_array().expect("points array");
        assert_eq!(rows.len(), 2);
        let p = [[0.5, 0.5, 0.5], [0.2, 0.3, 0.7]];
        let corners: Vec<[f64; 3]> = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64])
            .collect();
        for (row, p) in rows.iter().zip(p) {
            let key = if kind == "gc" { "phi" } else { "w" };
            let w: Vec<f64> = serde_json::from_value(row[key].clone()).expect("numbers");
            assert_eq!(w.len(), 8);
            let sum: f64 = w.iter().sum();
            assert!((sum - 1.0).abs() < 1e-9, "{kind}: sum {sum}");
            if kind == "gc" {
                let psi: Vec<f64> = serde_json::from_value(row["psi"].clone()).expect("numbers");
                assert_eq!(psi.len(), 12);
            } else {
                for axis in 0..3 {
                    let x: f64 = w.iter().zip(&corners).map(|(w, c)| w * c[axis]).sum();
                    assert!((x - p[axis]).abs() < 1e-6, "{kind}: {x} vs {}", p[axis]);
                }
            }
        }
    }
}

fn assert_input_error(out: &Output, expected: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert!(
        stderr.contains(expected),
        "expected '{expected}' in: {stderr}"
    );
    assert_eq!(
        stderr.trim_end().lines().count(),
        1,
        "one-line error: {stderr}"
    );
}

#[test]
fn bad_input_gets_a_one_line_error_and_status_2() {
    let dir = scratch_dir("errors");
    let cage = write(&dir, "cube.obj", CUBE);
    let good = write(&dir, "good.txt", "0.5 0.5 0.5\n");

    let short = write(&dir, "short.txt", "0.5 0.5 0.5\n1 2\n");
    assert_input_error(
        &weights(&cage, &short, "mvc"),
        "short.txt:2: expected 3 numbers",
    );

    let nan = write(&dir, "nan.txt", "0.5 nan 0.5\n");
    assert_input_error(
        &weights(&cage, &nan, "gc"),
        "nan.txt:1: y 'nan' is not finite",
    );

    let outside = write(&dir, "outside.txt", "0.5 0.5 0.5\n3 3 3\n");
    assert_input_error(&weights(&cage, &outside, "hc"), "outside the cage");
    // 1e5 cube diagonals away: MVC would not reproduce it, so it is refused; GC is accurate.
    let far = write(
        &dir,
        "far.txt",
        "0.5 0.5 0.5
1e5 3e4 -2e4
",
    );
    assert_input_error(
        &weights(&cage, &far, "mvc"),
        "far.txt: 1 point(s) lie more than 1000 cage diagonals",
    );
    assert_eq!(weights(&cage, &far, "gc").status.code(), Some(0));

    let open = write(&dir, "open.obj", &CUBE[..CUBE.rfind("f ").expect("a face")]);
    assert_input_error(
        &weights(&open, &good, "mvc"),
        "open.obj: invalid cage: cage is not closed",
    );

    let garbled = write(&dir, "garbled.obj", "v 0 0 0\nv 1 0 zero\n");
    assert_input_error(
        &weights(&garbled, &good, "mvc"),
        "garbled.obj:2: z 'zero' is not a number",
    );

    let inward: String = CUBE
        .lines()
        .map(|l| match l.strip_prefix("f ") {
            Some(rest) => format!(
                "f {}\n",
                rest.split(' ').rev().collect::<Vec<_>>().join(" ")
            ),
            None => format!("{l}\n"),
        })
        .collect();
    let inward = write(&dir, "inward.obj", &inward);
    assert_input_error(&weights(&inward, &good, "mvc"), "oriented inwards");

    // A 1e308 coordinate is named as such (not as duplicate vertices or degenerate faces,
    // which is what its huge diagonal made every other check say).
    let huge = write(
        &dir,
        "huge.obj",
        &CUBE.replacen("v 1 1 1", "v 1 1 1e308", 1),
    );
    assert!(
        CUBE.contains("v 1 1 1"),
        "the cube has the corner to replace"
    );
    assert_input_error(
        &weights(&huge, &good, "mvc"),
        "coordinate of magnitude 1e308, beyond ±1e9",
    );

    let missing = dir.join("missing.obj");
    assert_input_error(&weights(&missing, &good, "mvc"), "missing.obj: cannot read");
}

#[test]
fn resolutions_outside_the_limits_exit_with_status_2_not_a_panic() {
    let dir = scratch_dir("resolution");
    let cage = write(&dir, "cube.obj", CUBE);
    let points = write(&dir, "points.txt", "0.5 0.5 0.5\n");
    for resolution in ["0", "3", "129", "4294967295"] {
        let out = Command::new(env!("CARGO_BIN_EXE_starcages-cli"))
            .args(["weights", "--cage"])
            .arg(&cage)
            .arg("--points")
            .arg(&points)
            .args(["--coords", "hc", "--resolution", resolution])
            .output()
            .expect("run starcages-cli");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{resolution}: {stderr}");
        assert!(
            stderr.contains("out of range") && stderr.contains("4 to 128"),
            "{stderr}"
        );
    }
}

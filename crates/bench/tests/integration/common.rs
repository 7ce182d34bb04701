//! Helpers shared by the benchmarks' end-to-end tests.
#![allow(dead_code, clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `starcages-bench` with `args`.
pub fn bench(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_starcages-bench"))
        .args(args)
        .output()
        .expect("run starcages-bench")
}

/// A fresh scratch folder for one test, removed when dropped.
pub fn dir(name: &str) -> starcages_test_support::Scratch {
    starcages_test_support::Scratch::new(&format!("bench-test-{name}"))
}

/// Writes demo `name` at `detail` into `dir` as NAME.json; returns its path.
pub fn demo(name: &str, detail: f64, dir: &Path) -> PathBuf {
    let scene = starcages_core::generate::demo::demo_scene(name, detail).unwrap();
    let path = dir.join(format!("{name}.json"));
    starcages_io::save_scene(&scene, &path).unwrap();
    path
}

/// A path as a command-line argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Standard output as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts the command succeeded, showing its error output otherwise.
pub fn ok(o: &Output) {
    assert!(o.status.success(), "{}", stderr(o));
}

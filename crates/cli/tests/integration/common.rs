//! Helpers shared by the CLI's end-to-end tests.
#![allow(dead_code, clippy::unwrap_used)]

use std::path::Path;
use std::process::{Command, Output};

/// A closed box as OBJ (8 vertices, 12 triangles).
pub const BOX_OBJ: &str = "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

/// Runs `starcages-cli` with `args`.
pub fn cli(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_starcages-cli"))
        .args(args)
        .output()
        .expect("run starcages-cli")
}

/// A fresh scratch folder for one test, removed when dropped.
pub fn dir(name: &str) -> starcages_test_support::Scratch {
    starcages_test_support::Scratch::new(&format!("cli-test-{name}"))
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

//! The core's layout: no two source files reach each other through explicit module paths
//! (`super::fit::…`, `crate::rig::vocabulary::…`), directly or around a longer circle. A
//! folder's `mod.rs` re-exports its files' items and is left out (every file uses its parent's
//! names); so is test code (`#[cfg(test)]` onwards), which may use the demos.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`, as (module path, non-test source).
fn modules(root: &Path, dir: &Path, out: &mut BTreeMap<String, String>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            modules(root, &path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let relative = path.strip_prefix(root).unwrap().with_extension("");
            let mut name = relative.to_string_lossy().replace('/', "::");
            if let Some(parent) = name.strip_suffix("::mod") {
                name = parent.to_owned();
            }
            if name == "lib" {
                name = String::new();
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let code = text.split("#[cfg(test)]").next().unwrap_or("").to_owned();
            out.insert(name, code);
        }
    }
}

/// The files (not `mod.rs`) each file names through an explicit module path.
fn edges(root: &Path, files: &BTreeMap<String, String>) -> BTreeMap<String, BTreeSet<String>> {
    let is_folder =
        |m: &str| root.join(m.replace("::", "/")).join("mod.rs").exists() || m.is_empty();
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (from, code) in files {
        let own: Vec<&str> = if from.is_empty() {
            vec![]
        } else {
            from.split("::").collect()
        };
        let bytes = code.as_bytes();
        let mut i = 0;
        while i < code.len() {
            if !code.is_char_boundary(i) {
                i += 1;
                continue;
            }
            let rest = &code[i..];
            let start = ["crate::", "super::", "self::"]
                .iter()
                .find(|p| rest.starts_with(**p));
            let boundary = i == 0
                || !(bytes[i - 1].is_ascii_alphanumeric()
                    || bytes[i - 1] == b'_'
                    || bytes[i - 1] == b':');
            let Some(prefix) = start.filter(|_| boundary) else {
                i += 1;
                continue;
            };
            let path: Vec<&str> = rest
                .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':'))
                .next()
                .unwrap_or("")
                .split("::")
                .filter(|s| !s.is_empty())
                .collect();
            let (mut base, mut segments): (Vec<&str>, &[&str]) = match *prefix {
                "crate::" => (vec![], &path[1..]),
                _ => {
                    let mut base = own.clone();
                    let mut segments = &path[1..];
                    if *prefix == "super::" {
                        base.pop();
                        while segments.first() == Some(&"super") {
                            base.pop();
                            segments = &segments[1..];
                        }
                    }
                    (base, segments)
                }
            };
            let mut target = None;
            while let Some((first, more)) = segments.split_first() {
                base.push(first);
                let name = base.join("::");
                if files.contains_key(&name) && !is_folder(&name) {
                    target = Some(name);
                }
                segments = more;
            }
            if let Some(target) = target.filter(|t| t != from) {
                out.entry(from.clone()).or_default().insert(target);
            }
            i += prefix.len();
        }
    }
    out
}

#[test]
fn no_two_core_files_import_each_other_around_a_circle() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = BTreeMap::new();
    modules(&root, &root, &mut files);
    let edges = edges(&root, &files);
    assert!(
        edges
            .get("rig::fit")
            .is_some_and(|e| e.contains("rig::vocabulary")),
        "the scan reads `super::` paths: {edges:?}"
    );
    // Depth-first search for a path back to where it started.
    fn visit(
        node: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(node.to_owned(), 1);
        path.push(node.to_owned());
        for next in edges.get(node).into_iter().flatten() {
            match state.get(next) {
                Some(1) => {
                    let at = path.iter().position(|p| p == next).unwrap_or(0);
                    let mut circle = path[at..].to_vec();
                    circle.push(next.clone());
                    return Some(circle);
                }
                Some(_) => {}
                None => {
                    if let Some(circle) = visit(next, edges, state, path) {
                        return Some(circle);
                    }
                }
            }
        }
        path.pop();
        state.insert(node.to_owned(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for node in files.keys() {
        if !state.contains_key(node) {
            let circle = visit(node, &edges, &mut state, &mut Vec::new());
            assert!(
                circle.is_none(),
                "files import each other: {}",
                circle.unwrap().join(" -> ")
            );
        }
    }
}

/// Rig operations live one per file in `rig/`, over its vocabulary: no operation's file names
/// another's (only the dispatcher, `rig/mod.rs`, names them all); generators live in
/// `generate/`, and `scene/` keeps the model, its files and validation.
#[test]
fn rig_operations_import_only_their_vocabulary_and_generators_live_apart() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = BTreeMap::new();
    modules(&root, &root, &mut files);
    let edges = edges(&root, &files);
    for op in [
        "add_box", "extrude", "delete", "merge", "split", "mirror", "rest", "fit", "inset",
    ] {
        let name = format!("rig::{op}");
        assert!(files.contains_key(&name), "{name} is missing");
        let within: Vec<&String> = edges
            .get(&name)
            .into_iter()
            .flatten()
            .filter(|t| t.starts_with("rig::") && *t != "rig::vocabulary")
            .collect();
        assert!(within.is_empty(), "{name} imports {within:?}");
    }
    for generator in ["generate::autocage", "generate::demo", "generate::creature"] {
        assert!(files.contains_key(generator), "{generator} is missing");
    }
    let scene: Vec<&String> = files.keys().filter(|m| m.starts_with("scene::")).collect();
    for stray in [
        "rig_edit",
        "fit",
        "inset",
        "weld",
        "subdivide",
        "demo",
        "creature",
        "autocage",
    ] {
        assert!(
            !scene.iter().any(|m| m.ends_with(&format!("::{stray}"))),
            "scene::{stray} belongs in rig/ or generate/: {scene:?}"
        );
    }
}

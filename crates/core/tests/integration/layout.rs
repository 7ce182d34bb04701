//! The core's layout, read from its sources: no two files reach each other through explicit
//! module paths (`super::fit::…`, `crate::rig::vocabulary::…`) around a circle, and no two
//! top-level folders either — a `mod.rs` counts as its folder — and the folder graph is the
//! one `docs/ARCHITECTURE.md` draws. Test items (`#[cfg(test)]` and what it marks) are left
//! out wherever they stand in a file, since tests may use anything; the code after them is read.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`, as (module path, source without its test items).
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
            out.insert(name, without_test_items(&text));
        }
    }
}

/// Where the string, character literal or comment starting at byte `i` of `code` ends (the
/// byte after it), or `None` when none starts there.
fn skip_literal(code: &[u8], i: usize) -> Option<usize> {
    let at = |k: usize| code.get(k).copied();
    match (at(i)?, at(i + 1)) {
        (b'/', Some(b'/')) => Some(
            code[i..]
                .iter()
                .position(|&c| c == b'\n')
                .map_or(code.len(), |n| i + n),
        ),
        (b'/', Some(b'*')) => Some(
            code[i + 2..]
                .windows(2)
                .position(|w| w == b"*/")
                .map_or(code.len(), |n| i + 2 + n + 2),
        ),
        (b'r', Some(b'"' | b'#')) if i == 0 || !is_ident(code[i - 1]) => {
            let hashes = code[i + 1..].iter().take_while(|&&c| c == b'#').count();
            if at(i + 1 + hashes) != Some(b'"') {
                return None;
            }
            let close: Vec<u8> = std::iter::once(b'"')
                .chain(std::iter::repeat_n(b'#', hashes))
                .collect();
            let body = i + 2 + hashes;
            Some(
                code[body..]
                    .windows(close.len())
                    .position(|w| w == close.as_slice())
                    .map_or(code.len(), |n| body + n + close.len()),
            )
        }
        (b'"', _) => {
            let mut k = i + 1;
            while k < code.len() && code[k] != b'"' {
                k += if code[k] == b'\\' { 2 } else { 1 };
            }
            Some((k + 1).min(code.len()))
        }
        // A character literal ('{', '\''), not a lifetime ('a).
        (b'\'', Some(b'\\')) => Some(
            code[i + 3..]
                .iter()
                .position(|&c| c == b'\'')
                .map_or(code.len(), |n| i + 3 + n + 1),
        ),
        (b'\'', Some(_)) if at(i + 2) == Some(b'\'') => Some(i + 3),
        _ => None,
    }
}

fn is_ident(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// `code` without each item marked `#[cfg(test)]`: the attribute, any attributes after it and
/// the item up to its `;` or its closing brace (strings, characters and comments skipped).
fn without_test_items(code: &str) -> String {
    const MARK: &str = "#[cfg(test)]";
    let bytes = code.as_bytes();
    let mut out = String::with_capacity(code.len());
    let mut kept_from = 0;
    let mut i = 0;
    while i < bytes.len() {
        if let Some(end) = skip_literal(bytes, i) {
            i = end;
            continue;
        }
        if !code[i..].starts_with(MARK) {
            i += 1;
            continue;
        }
        out.push_str(&code[kept_from..i]);
        // The item: to the first `;` outside braces, or the brace that closes its first `{`.
        let mut k = i + MARK.len();
        let mut depth = 0usize;
        while k < bytes.len() {
            if let Some(end) = skip_literal(bytes, k) {
                k = end;
                continue;
            }
            match bytes[k] {
                b'{' => depth += 1,
                b'}' => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        k += 1;
                        break;
                    }
                }
                b';' if depth == 0 => {
                    k += 1;
                    break;
                }
                _ => {}
            }
            k += 1;
        }
        i = k;
        kept_from = k;
    }
    out.push_str(&code[kept_from.min(code.len())..]);
    out
}

/// The module paths each file names through `crate::`, `super::` or `self::`, resolved to
/// absolute module paths (`crate::{a, b::c}` names both); whole paths, longest first cut by
/// the caller.
fn named_paths(from: &str, code: &str) -> Vec<Vec<String>> {
    let own: Vec<&str> = if from.is_empty() {
        vec![]
    } else {
        from.split("::").collect()
    };
    let bytes = code.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if let Some(end) = skip_literal(bytes, i) {
            i = end;
            continue;
        }
        let rest = &code[i..];
        let prefix = ["crate::", "super::", "self::"]
            .into_iter()
            .find(|p| rest.starts_with(*p));
        let boundary = i == 0 || !(is_ident(bytes[i - 1]) || bytes[i - 1] == b':');
        let Some(prefix) = prefix.filter(|_| boundary) else {
            i += 1;
            continue;
        };
        let mut base: Vec<String> = match prefix {
            "crate::" => vec![],
            _ => own.iter().map(|s| s.to_string()).collect(),
        };
        let mut tail = &rest[prefix.len()..];
        if prefix == "super::" {
            base.pop();
            while let Some(more) = tail.strip_prefix("super::") {
                base.pop();
                tail = more;
            }
        }
        for path in expand(tail) {
            let mut full = base.clone();
            full.extend(path);
            out.push(full);
        }
        i += prefix.len();
    }
    out
}

/// The paths a use-tree tail names: `a::b::C` is one, `a::{b, c::D}` two.
fn expand(tail: &str) -> Vec<Vec<String>> {
    let head: String = tail
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == ':')
        .collect();
    let segments: Vec<String> = head
        .split("::")
        .filter(|s| !s.is_empty())
        .map(str::to_owned)
        .collect();
    let after = &tail[head.len()..];
    if !(head.is_empty() || head.ends_with("::")) || !after.starts_with('{') {
        return vec![segments];
    }
    // A group: split its top level at commas.
    let mut paths = Vec::new();
    let mut depth = 0;
    let mut start = 1;
    for (k, c) in after.char_indices() {
        match c {
            '{' => depth += 1,
            '}' | ',' if depth == 1 => {
                for inner in expand(after[start..k].trim_start()) {
                    let mut path = segments.clone();
                    path.extend(inner);
                    paths.push(path);
                }
                start = k + 1;
                if c == '}' {
                    break;
                }
            }
            '}' => depth -= 1,
            _ => {}
        }
    }
    paths
}

/// For each file, the other files (not `mod.rs`) it names.
fn file_edges(root: &Path, files: &BTreeMap<String, String>) -> BTreeMap<String, BTreeSet<String>> {
    let is_folder =
        |m: &str| root.join(m.replace("::", "/")).join("mod.rs").exists() || m.is_empty();
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (from, code) in files {
        for path in named_paths(from, code) {
            let mut target = None;
            for k in 1..=path.len() {
                let name = path[..k].join("::");
                if files.contains_key(&name) && !is_folder(&name) {
                    target = Some(name);
                }
            }
            if let Some(target) = target.filter(|t| t != from) {
                out.entry(from.clone()).or_default().insert(target);
            }
        }
    }
    out
}

/// For each top-level module of the crate (a folder with its `mod.rs`, or a file), the other
/// top-level modules its code names. `lib.rs` is left out: it declares them all.
fn folder_edges(files: &BTreeMap<String, String>) -> BTreeMap<String, BTreeSet<String>> {
    let top = |m: &str| m.split("::").next().unwrap_or("").to_owned();
    let tops: BTreeSet<String> = files.keys().map(|m| top(m)).collect();
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (from, code) in files.iter().filter(|(m, _)| !m.is_empty()) {
        for path in named_paths(from, code) {
            let Some(first) = path.first() else { continue };
            if tops.contains(first) && *first != top(from) {
                out.entry(top(from)).or_default().insert(first.clone());
            }
        }
    }
    out
}

/// A circle in `edges`, if any, as the path around it.
fn circle(edges: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
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
    for node in edges.keys() {
        if !state.contains_key(node)
            && let Some(found) = visit(node, edges, &mut state, &mut Vec::new())
        {
            return Some(found);
        }
    }
    None
}

fn core_files() -> (PathBuf, BTreeMap<String, String>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = BTreeMap::new();
    modules(&root, &root, &mut files);
    (root, files)
}

#[test]
fn test_items_are_cut_where_they_stand_and_the_scan_finds_planted_circles() {
    // A test item in the middle of a file: only it goes, the code after it stays.
    let code = "use crate::a::x;\n#[cfg(test)]\n#[test]\nfn t() { let s = \"}\"; let c = '{'; \
                crate::b::y(); }\nuse super::c::z;\n#[cfg(test)]\nmod tests;\nfn after() {}\n";
    let kept = without_test_items(code);
    assert!(kept.contains("use crate::a::x;") && kept.contains("use super::c::z;"));
    assert!(
        kept.contains("fn after()") && !kept.contains("crate::b") && !kept.contains("mod tests")
    );
    // Groups name every member.
    let named = named_paths("d::e", "use crate::{a::X, b::{c::Y, Z}};\nuse super::f;");
    for path in [&["a", "X"][..], &["b", "c", "Y"], &["b", "Z"], &["d", "f"]] {
        assert!(named.iter().any(|p| p == path), "{path:?} in {named:?}");
    }
    // Negative control: a planted folder circle through a mod.rs and a group is found.
    let planted: BTreeMap<String, String> = [
        ("a".to_owned(), "pub use crate::{b::Thing, c};".to_owned()),
        (
            "b::inner".to_owned(),
            "use super::super::a::Other;".to_owned(),
        ),
        ("c".to_owned(), String::new()),
    ]
    .into();
    let edges = folder_edges(&planted);
    assert_eq!(
        circle(&edges),
        Some(vec!["a".into(), "b".into(), "a".into()])
    );
}

#[test]
fn no_two_core_files_import_each_other_around_a_circle() {
    let (root, files) = core_files();
    let edges = file_edges(&root, &files);
    assert!(
        edges
            .get("rig::fit")
            .is_some_and(|e| e.contains("rig::vocabulary")),
        "the scan reads `super::` paths: {edges:?}"
    );
    if let Some(circle) = circle(&edges) {
        panic!("files import each other: {}", circle.join(" -> "));
    }
}

/// The folder graph drawn in `docs/ARCHITECTURE.md`, as its lines `folder -> a, b, c`
/// between the markers.
fn documented_folder_graph() -> BTreeMap<String, BTreeSet<String>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/ARCHITECTURE.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let start = text
        .find("<!-- core folder graph -->")
        .expect("ARCHITECTURE.md marks the core folder graph");
    let block = &text[start + "<!-- core folder graph -->".len()..];
    let block = &block[..block.find("<!-- end core folder graph -->").unwrap()];
    let mut graph = BTreeMap::new();
    for line in block.lines() {
        let Some((from, to)) = line.split_once("->") else {
            continue;
        };
        let targets: BTreeSet<String> = to
            .split(',')
            .map(|t| t.trim().to_owned())
            .filter(|t| !t.is_empty() && t != "(none)")
            .collect();
        graph.insert(from.trim().to_owned(), targets);
    }
    graph
}

#[test]
fn core_folders_form_no_circle_and_match_the_architecture_diagram() {
    let (_, files) = core_files();
    let edges = folder_edges(&files);
    let tops: BTreeSet<String> = files
        .keys()
        .filter(|m| !m.is_empty())
        .map(|m| m.split("::").next().unwrap_or("").to_owned())
        .collect();
    let actual: BTreeMap<String, BTreeSet<String>> = tops
        .iter()
        .map(|t| (t.clone(), edges.get(t).cloned().unwrap_or_default()))
        .collect();
    let drawn = documented_folder_graph();
    let show = |g: &BTreeMap<String, BTreeSet<String>>| {
        g.iter()
            .map(|(from, to)| {
                let to: Vec<&str> = to.iter().map(String::as_str).collect();
                let to = if to.is_empty() {
                    "(none)".to_owned()
                } else {
                    to.join(", ")
                };
                format!("{from} -> {to}")
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(
        show(&drawn),
        show(&actual),
        "docs/ARCHITECTURE.md's core folder graph is not the code's; the code's is:\n{}",
        show(&actual)
    );
    if let Some(circle) = circle(&edges) {
        panic!("core folders import each other: {}", circle.join(" -> "));
    }
}

/// Rig operations live one per file in `rig/`, over its vocabulary: no operation's file names
/// another's (only the dispatcher, `rig/mod.rs`, names them all); generators live in
/// `generate/`, and `scene/` keeps the model and its validation.
#[test]
fn rig_operations_import_only_their_vocabulary_and_generators_live_apart() {
    let (root, files) = core_files();
    let edges = file_edges(&root, &files);
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

//! The editor's layers point one way — `state` ← `commands` ← `ui` ← `app` — and the state has
//! no egui types. Checked on the source text, so a cycle fails here before it lands.

use std::path::Path;

/// Every `.rs` file under `dir`, with its text.
fn sources(dir: &Path) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(sources(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&path).unwrap();
            out.push((path.display().to_string(), text));
        }
    }
    out
}

fn assert_layer_avoids(layer: &str, forbidden: &[&str]) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("src")
        .join(layer);
    let files = sources(&dir);
    assert!(!files.is_empty(), "no sources under {}", dir.display());
    for (file, text) in files {
        for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
            for word in forbidden {
                assert!(!line.contains(word), "{file}: `{line}` uses {word}");
            }
        }
    }
}

#[test]
fn the_state_has_no_egui_types_and_knows_no_higher_layer() {
    assert_layer_avoids(
        "state",
        &[
            "egui",
            "eframe",
            "crate::commands",
            "crate::ui",
            "crate::app",
        ],
    );
}

#[test]
fn commands_know_the_state_only() {
    assert_layer_avoids("commands", &["crate::ui", "crate::app"]);
}

#[test]
fn the_ui_never_reaches_the_app() {
    assert_layer_avoids("ui", &["crate::app", "&mut EditorState"]);
}

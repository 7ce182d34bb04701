//! Recently opened and saved scenes, kept in the user's configuration folder.

use std::path::{Path, PathBuf};

/// Where the list lives: `$XDG_CONFIG_HOME/starcages/recent.txt` (or `~/.config/...`).
pub fn default_file() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_CONFIG_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))?;
    Some(base.join("starcages").join("recent.txt"))
}

/// The recent files in `file`, newest first (empty when there is no list).
pub fn load(file: &Path) -> Vec<PathBuf> {
    std::fs::read_to_string(file)
        .map(|text| {
            text.lines()
                .filter(|l| !l.is_empty())
                .map(PathBuf::from)
                .collect()
        })
        .unwrap_or_default()
}

/// Stores the list in `file`; failures are ignored (the list is a convenience).
pub fn store(file: &Path, paths: &[PathBuf]) {
    if let Some(dir) = file.parent() {
        std::fs::create_dir_all(dir).ok();
    }
    let text: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    starcages_io::write_atomic(file, text.join("\n").as_bytes()).ok();
}

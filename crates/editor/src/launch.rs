//! The `starcages` command line: a file to open, or `--help` / `--version` answered on the
//! terminal (instead of opening a file called `--help`).

use std::ffi::OsString;
use std::path::PathBuf;

/// What the command line asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Launch {
    /// Open the editor on this file, or on the built-in demo.
    Open(Option<PathBuf>),
    /// Print [`usage`] and exit.
    Help,
    /// Print the version and exit.
    Version,
    /// A command line that means nothing: the message, for standard error (exit status 2).
    Invalid(String),
}

/// The usage text of `starcages --help`.
pub fn usage() -> String {
    format!(
        "starcages {} — the StarCages cage editor\n\n\
         Usage: starcages [FILE]\n\n\
         FILE  a scene (.json) to open, or a mesh (.obj, .gltf, .glb, .fbx, .ply, .stl, .off) to rig\n      \
         automatically: a chain of cages along each limb (OBJ, PLY, STL and OFF meshes are read\n      \
         Y-up and turned to Z-up); without\n      \
         FILE the built-in demo opens\n\n\
         Options:\n  -h, --help     print this help\n  -V, --version  print the version\n\n\
         Headless work (binding, deforming, benchmarks) is `starcages-cli --help`.",
        env!("CARGO_PKG_VERSION"),
    )
}

/// Reads the arguments after the program name.
pub fn parse(args: impl IntoIterator<Item = OsString>) -> Launch {
    let args: Vec<OsString> = args.into_iter().collect();
    let mut file = None;
    let mut options_ended = false;
    for arg in &args {
        match arg.to_str().filter(|_| !options_ended) {
            Some("-h" | "--help") => return Launch::Help,
            Some("-V" | "--version") => return Launch::Version,
            Some("--") => options_ended = true,
            Some(flag) if flag.starts_with('-') && flag.len() > 1 => {
                return Launch::Invalid(format!("unknown option '{flag}'; see starcages --help"));
            }
            _ if file.is_some() => {
                return Launch::Invalid(
                    "more than one file given; starcages opens one file (see --help)".into(),
                );
            }
            _ => file = Some(PathBuf::from(arg)),
        }
    }
    Launch::Open(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_str(args: &[&str]) -> Launch {
        parse(args.iter().map(OsString::from))
    }

    #[test]
    fn help_and_version_are_answered_and_files_are_opened() {
        assert_eq!(parse_str(&["--help"]), Launch::Help);
        assert_eq!(parse_str(&["-h"]), Launch::Help);
        assert_eq!(parse_str(&["scene.json", "--version"]), Launch::Version);
        assert_eq!(parse_str(&[]), Launch::Open(None));
        assert_eq!(
            parse_str(&["bunny.obj"]),
            Launch::Open(Some(PathBuf::from("bunny.obj")))
        );
        // A file whose name starts with a dash, after `--`.
        assert_eq!(
            parse_str(&["--", "-odd.json"]),
            Launch::Open(Some(PathBuf::from("-odd.json")))
        );
        assert!(
            matches!(parse_str(&["--frobnicate"]), Launch::Invalid(m) if m.contains("--frobnicate"))
        );
        assert!(matches!(
            parse_str(&["a.json", "b.json"]),
            Launch::Invalid(_)
        ));
        assert!(usage().contains("Usage: starcages [FILE]"));
    }
}

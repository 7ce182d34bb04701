//! Helpers shared by the StarCages crates' tests; a dev-dependency only, never shipped.

use std::path::Path;

/// A fresh folder for one test in the system's temporary folder, removed with everything in it
/// when dropped, so that test runs leave nothing behind (folders named by process piled up by
/// the thousand and once filled a CI machine's disk). Derefs to its [`Path`].
pub struct Scratch(tempfile::TempDir);

impl Scratch {
    /// A folder named `starcages-{name}-` and a random suffix.
    ///
    /// # Panics
    /// Where the system's temporary folder cannot be written: a test cannot run without it.
    pub fn new(name: &str) -> Self {
        let prefix = format!("starcages-{name}-");
        match tempfile::Builder::new().prefix(&prefix).tempdir() {
            Ok(dir) => Self(dir),
            Err(e) => panic!("cannot make a scratch folder {prefix}… for a test: {e}"),
        }
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;

    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scratch_folder_is_removed_with_its_files_when_dropped() {
        let scratch = Scratch::new("self-test");
        let path = scratch.to_path_buf();
        std::fs::create_dir_all(scratch.join("sub")).unwrap();
        std::fs::write(scratch.join("sub").join("a.txt"), "a").unwrap();
        assert!(path.is_dir());
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.starts_with("starcages-self-test-"), "{name}");
        // A second one is another folder.
        assert_ne!(Scratch::new("self-test").to_path_buf(), path);
        drop(scratch);
        assert!(!path.exists());
    }
}

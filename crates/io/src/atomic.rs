//! Atomic saves: write a temporary file in the target's folder, flush it to disk, then rename
//! it over the target. A failure at any step leaves the previous file untouched.
//!
//! The temporary file has an unpredictable name and is created exclusively (the `tempfile`
//! crate: `O_CREAT | O_EXCL`, so a symlink planted at its name is never followed), and it is
//! removed when the save fails. While a save runs its temporary file is listed, so that a
//! program stopped by Ctrl-C or SIGTERM can remove it ([`remove_unfinished_saves`], which the
//! binaries call from their signal handlers). Temporary files of ours that an earlier save left
//! behind (the process was killed outright, SIGKILL) are swept on the next save to the same file.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, SystemTime};

use super::FileError;

/// Suffix of our temporary files: `.NAME.XXXXXX.starcages-tmp` beside `NAME`.
const TEMP_SUFFIX: &str = ".starcages-tmp";

/// A temporary file this old was left by a save that did not finish; a running save is much
/// younger.
const STALE_AFTER: Duration = Duration::from_secs(10 * 60);

/// Temporary files of the saves running now.
static UNFINISHED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Lists a temporary file for the time of one save.
struct Unfinished(PathBuf);

impl Unfinished {
    fn new(path: &Path) -> Self {
        if let Ok(mut list) = UNFINISHED.lock() {
            list.push(path.to_path_buf());
        }
        Self(path.to_path_buf())
    }
}

impl Drop for Unfinished {
    fn drop(&mut self) {
        if let Ok(mut list) = UNFINISHED.lock()
            && let Some(i) = list.iter().position(|p| *p == self.0)
        {
            list.swap_remove(i);
        }
    }
}

/// Removes the temporary files of the saves running now, and returns how many it removed. For
/// a program that is about to exit on Ctrl-C or SIGTERM: the targets keep their old content.
/// A save that finishes meanwhile has renamed its file, which then is no longer there to remove.
pub fn remove_unfinished_saves() -> usize {
    let Ok(list) = UNFINISHED.lock() else {
        return 0;
    };
    list.iter()
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count()
}

/// Writes `bytes` to `path` atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), FileError> {
    let mut writer = AtomicWriter::create(path)?;
    writer.write(bytes)?;
    writer.commit()
}

/// A file written in pieces (a bake's frames) and put in place atomically by
/// [`AtomicWriter::commit`]; dropped without committing, it removes its temporary file and the
/// target keeps its old content.
pub struct AtomicWriter {
    target: PathBuf,
    folder: PathBuf,
    temp: std::io::BufWriter<tempfile::NamedTempFile>,
    _listed: Unfinished,
}

impl AtomicWriter {
    /// Creates the temporary file beside `path` (exclusively, with an unpredictable name).
    pub fn create(path: &Path) -> Result<Self, FileError> {
        let fail = |error: std::io::Error| FileError::Write {
            path: path.to_path_buf(),
            error,
        };
        let folder = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => std::path::PathBuf::from("."),
        };
        let name = path.file_name().ok_or_else(|| {
            fail(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "not a file path",
            ))
        })?;
        let prefix = format!(".{}.", name.to_string_lossy());
        sweep_stale(&folder, &prefix);
        let existing = std::fs::metadata(path).ok().map(|m| m.permissions());
        let mut builder = tempfile::Builder::new();
        builder.prefix(&prefix).suffix(TEMP_SUFFIX);
        // tempfile creates owner-only files; a saved file gets the permissions a plain new file
        // would (0o666 less the umask), or keeps those of the file it replaces.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt as _;
            builder.permissions(std::fs::Permissions::from_mode(0o666));
        }
        let temp = builder.tempfile_in(&folder).map_err(fail)?;
        if let Some(permissions) = existing {
            temp.as_file().set_permissions(permissions).map_err(fail)?;
        }
        let listed = Unfinished::new(temp.path());
        pause_for_interrupt_tests();
        Ok(Self {
            target: path.to_path_buf(),
            folder,
            temp: std::io::BufWriter::with_capacity(1 << 20, temp),
            _listed: listed,
        })
    }

    fn fail(&self, error: std::io::Error) -> FileError {
        FileError::Write {
            path: self.target.clone(),
            error,
        }
    }

    /// Appends `bytes`.
    pub fn write(&mut self, bytes: &[u8]) -> Result<(), FileError> {
        self.temp.write_all(bytes).map_err(|e| self.fail(e))
    }

    /// Flushes the file to disk and renames it over the target.
    pub fn commit(self) -> Result<(), FileError> {
        let target = self.target.clone();
        let fail = |error: std::io::Error| FileError::Write {
            path: target.clone(),
            error,
        };
        let temp = self.temp.into_inner().map_err(|e| fail(e.into_error()))?;
        temp.as_file().sync_all().map_err(fail)?;
        // On failure the temporary file is dropped, which removes it.
        temp.persist(&self.target).map_err(|e| fail(e.error))?;
        // Make the rename itself durable where the platform allows opening folders.
        if let Ok(dir) = std::fs::File::open(&self.folder) {
            dir.sync_all().ok();
        }
        Ok(())
    }
}

/// Debug builds only: waits `STARCAGES_TEST_SAVE_PAUSE_MS` milliseconds with the temporary
/// file created, so that a test can interrupt a save at a known point (a real large save is
/// too quick to hit reliably). Release builds do not read the variable.
fn pause_for_interrupt_tests() {
    #[cfg(debug_assertions)]
    if let Some(ms) = std::env::var("STARCAGES_TEST_SAVE_PAUSE_MS")
        .ok()
        .and_then(|v| v.parse::<u64>().ok())
    {
        std::thread::sleep(Duration::from_millis(ms.min(60_000)));
    }
}

/// Whether `a` and `b` name the same existing file, through symbolic and hard links (an
/// output that is one of a command's inputs would destroy it).
pub fn is_same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
    }
}

/// Removes our stale temporary files for one target (`prefix` = `.NAME.`) in `folder`. Only
/// regular files of our own naming and older than [`STALE_AFTER`] go; failures are ignored
/// (the sweep is housekeeping, never a reason to fail a save).
fn sweep_stale(folder: &Path, prefix: &str) {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return;
    };
    let now = SystemTime::now();
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let name = file_name.to_string_lossy();
        if !name.starts_with(prefix) || !name.ends_with(TEMP_SUFFIX) {
            continue;
        }
        // symlink_metadata: a symlink of that name is not ours and is left alone.
        let Ok(meta) = entry.path().symlink_metadata() else {
            continue;
        };
        let stale = meta
            .modified()
            .ok()
            .and_then(|m| now.duration_since(m).ok())
            .is_some_and(|age| age >= STALE_AFTER);
        if meta.is_file() && stale {
            std::fs::remove_file(entry.path()).ok();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh folder, removed when dropped.
    fn scratch(name: &str) -> tempfile::TempDir {
        tempfile::Builder::new()
            .prefix(&format!("starcages-atomic-{name}-"))
            .tempdir()
            .unwrap()
    }

    #[test]
    fn replaces_content_and_leaves_no_temp_file() {
        let scratch = scratch("replace");
        let dir = scratch.path();
        let path = dir.join("scene.json");
        write_atomic(&path, b"first").unwrap();
        write_atomic(&path, b"second").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"second");
        let leftovers: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .filter_map(Result::ok)
            .collect();
        assert_eq!(leftovers.len(), 1);
    }

    #[test]
    fn failure_keeps_the_old_file_and_says_why() {
        let scratch = scratch("missing");
        let dir = scratch.path();
        let path = dir.join("nested").join("scene.json");
        let error = write_atomic(&path, b"x").unwrap_err().to_string();
        assert!(
            error.contains("cannot save") && error.contains("unchanged"),
            "{error}"
        );
    }

    #[cfg(unix)]
    #[test]
    fn planted_symlinks_at_temp_names_are_never_followed() {
        let scratch = scratch("symlink");
        let dir = scratch.path();
        let victim = dir.join("victim.txt");
        std::fs::write(&victim, b"precious").unwrap();
        let path = dir.join("out.obj");
        // The names earlier versions used, and names of our current pattern.
        for planted in [
            format!(".out.obj.{}.tmp", std::process::id()),
            ".out.obj.AAAAAA.starcages-tmp".to_owned(),
        ] {
            std::os::unix::fs::symlink(&victim, dir.join(planted)).unwrap();
        }
        for _ in 0..20 {
            write_atomic(&path, b"mesh").unwrap();
        }
        assert_eq!(std::fs::read(&victim).unwrap(), b"precious");
        assert_eq!(std::fs::read(&path).unwrap(), b"mesh");
        // The planted links are not ours: the sweep leaves them alone too.
        assert!(
            dir.join(".out.obj.AAAAAA.starcages-tmp")
                .symlink_metadata()
                .is_ok()
        );
    }

    #[test]
    fn stale_temp_files_of_ours_are_swept_and_fresh_ones_kept() {
        let scratch = scratch("sweep");
        let dir = scratch.path();
        let path = dir.join("scene.json");
        let stale = dir.join(".scene.json.OLD123.starcages-tmp");
        let fresh = dir.join(".scene.json.NEW123.starcages-tmp");
        let other = dir.join(".other.json.OLD123.starcages-tmp");
        for p in [&stale, &fresh, &other] {
            std::fs::write(p, b"partial").unwrap();
        }
        let old = SystemTime::now() - Duration::from_secs(3600);
        for p in [&stale, &other] {
            std::fs::File::options()
                .write(true)
                .open(p)
                .unwrap()
                .set_modified(old)
                .unwrap();
        }
        write_atomic(&path, b"scene").unwrap();
        assert!(!stale.exists(), "a stale temp of this file is swept");
        assert!(fresh.exists(), "a save in progress elsewhere is left alone");
        assert!(
            other.exists(),
            "another file's temps are its own save's business"
        );
    }

    #[cfg(unix)]
    #[test]
    fn saved_files_are_readable_by_others_as_new_files_are_and_keep_replaced_permissions() {
        use std::os::unix::fs::PermissionsExt as _;
        let scratch = scratch("permissions");
        let dir = scratch.path();
        let plain = dir.join("plain.txt");
        std::fs::write(&plain, b"x").unwrap();
        let expected = plain.metadata().unwrap().permissions().mode() & 0o777;
        let saved = dir.join("saved.txt");
        write_atomic(&saved, b"x").unwrap();
        assert_eq!(
            saved.metadata().unwrap().permissions().mode() & 0o777,
            expected
        );
        // An existing file keeps its (here narrower) permissions.
        std::fs::set_permissions(&saved, std::fs::Permissions::from_mode(0o640)).unwrap();
        write_atomic(&saved, b"y").unwrap();
        assert_eq!(
            saved.metadata().unwrap().permissions().mode() & 0o777,
            0o640
        );
    }
}

//! The binding cache file: beside the scene (`SCENE.json.bind`), the compiled operator in
//! `starcages_core::star`'s cache bytes. A missing, stale or corrupt cache is ignored with a
//! reason and rebuilt; it is never trusted without both the key and the checksum matching.

use std::path::{Path, PathBuf};

use starcages_core::coords::BindControl;
use starcages_core::scene::Scene;
use starcages_core::star::{StarBinding, StarError, decode_binding_cache, encode_binding_cache};

use crate::{read_file_bytes, write_atomic};

/// What happened with the cache.
#[derive(Debug, Clone, PartialEq)]
pub enum CacheOutcome {
    /// The cache matched: no bind was needed.
    Hit,
    /// There was no cache; the scene was bound and the cache written.
    Written,
    /// The cache was stale or unreadable (the reason); the scene was bound and the cache
    /// rewritten.
    Replaced(String),
    /// The bind succeeded but the cache could not be written (the reason).
    NotWritten(String),
}

/// The cache file of a scene file.
pub fn cache_path(scene_path: &Path) -> PathBuf {
    let mut name = scene_path
        .file_name()
        .map(std::ffi::OsString::from)
        .unwrap_or_default();
    name.push(".bind");
    scene_path.with_file_name(name)
}

/// Binds the scene's mesh through the cache beside `scene_path`: a matching cache is used as
/// is; otherwise the scene is bound and the cache (re)written atomically.
pub fn bind_scene_cached(
    scene: &Scene,
    scene_path: &Path,
    control: &BindControl,
) -> Result<(StarBinding, CacheOutcome), StarError> {
    let path = cache_path(scene_path);
    let stale = match read_file_bytes(&path) {
        Ok(bytes) => match decode_binding_cache(&bytes, scene) {
            Ok(binding) => return Ok((binding, CacheOutcome::Hit)),
            Err(reason) => Some(reason),
        },
        Err(_) => None,
    };
    let binding = StarBinding::bind_scene(scene, control)?;
    let bytes = encode_binding_cache(scene, &binding);
    let outcome = match (write_atomic(&path, &bytes), stale) {
        (Err(e), _) => CacheOutcome::NotWritten(e.to_string()),
        (Ok(()), Some(reason)) => CacheOutcome::Replaced(format!(
            "{}: ignored the binding cache: {reason}",
            path.display()
        )),
        (Ok(()), None) => CacheOutcome::Written,
    };
    Ok((binding, outcome))
}

#[cfg(test)]
mod tests {
    use super::*;
    use starcages_core::generate::demo::demo_scene;

    #[test]
    fn cache_is_used_rebuilt_when_stale_and_never_trusted_when_corrupt() {
        let scratch = tempfile::tempdir().unwrap();
        let dir = scratch.path();
        let scene_path = dir.join("egg.json");
        let mut scene = demo_scene("egg", 0.2).unwrap();
        let control = BindControl::default();
        let (first, outcome) = bind_scene_cached(&scene, &scene_path, &control).unwrap();
        assert_eq!(outcome, CacheOutcome::Written);
        let (second, outcome) = bind_scene_cached(&scene, &scene_path, &control).unwrap();
        assert_eq!(outcome, CacheOutcome::Hit);
        assert_eq!(second.operator, first.operator);
        assert_eq!(second.join_weights, first.join_weights);
        assert!(!first.join_weights.vertex.is_empty());
        assert_eq!(second.boundary_weight, first.boundary_weight);
        // A changed setting makes the cache stale.
        scene.cages.leaves[0].h = Some(0.3);
        let (_, outcome) = bind_scene_cached(&scene, &scene_path, &control).unwrap();
        assert!(
            matches!(&outcome, CacheOutcome::Replaced(r) if r.contains("changed")),
            "{outcome:?}"
        );
        // Flipping one byte of the content is caught by the checksum.
        let cache = cache_path(&scene_path);
        let mut bytes = std::fs::read(&cache).unwrap();
        let last = bytes.len() - 5;
        bytes[last] ^= 0x40;
        std::fs::write(&cache, &bytes).unwrap();
        let (rebound, outcome) = bind_scene_cached(&scene, &scene_path, &control).unwrap();
        assert!(
            matches!(&outcome, CacheOutcome::Replaced(r) if r.contains("corrupt")),
            "{outcome:?}"
        );
        let fresh = StarBinding::bind_scene(&scene, &control).unwrap();
        assert_eq!(rebound.operator, fresh.operator);
        // Truncated and garbage files too.
        std::fs::write(&cache, &bytes[..bytes.len() / 2]).unwrap();
        assert!(matches!(
            bind_scene_cached(&scene, &scene_path, &control).unwrap().1,
            CacheOutcome::Replaced(_)
        ));
        std::fs::write(&cache, b"garbage").unwrap();
        assert!(matches!(
            bind_scene_cached(&scene, &scene_path, &control).unwrap().1,
            CacheOutcome::Replaced(_)
        ));
    }
}

//! `EXT_meshopt_compression` (gltfpack's `-cc` output): each compressed buffer view is decoded
//! by the meshoptimizer reference decoders (the `meshopt` crate) into the bytes the view
//! stands for, written where the view points (usually a "fallback" buffer that the file
//! declares without data). The accessors then read those bytes as any other.

use std::path::Path;

use serde_json::Value;

use super::FileError;

/// The extension's name.
pub(super) const MESHOPT: &str = "EXT_meshopt_compression";

/// Most bytes a fallback buffer may declare: at most this many times the file's size (the
/// codec compresses a few times; a tiny file claiming gigabytes is refused, not allocated).
const MAX_EXPANSION: usize = 256;

/// Whether buffer `index` is a fallback buffer of the extension (declared without data).
pub(super) fn is_fallback(root: &Value, index: usize) -> bool {
    root.pointer(&format!("/buffers/{index}/extensions/{MESHOPT}/fallback"))
        .and_then(Value::as_bool)
        .unwrap_or(false)
}

/// The zero bytes of fallback buffer `index` of `length` bytes, which the decoded views fill;
/// refused past [`MAX_EXPANSION`] × the file's `file_length`.
pub(super) fn fallback_bytes(
    path: &Path,
    index: usize,
    length: usize,
    file_length: usize,
) -> Result<Vec<u8>, FileError> {
    if length > file_length.saturating_mul(MAX_EXPANSION) {
        return Err(FileError::format(
            path,
            format!(
                "buffer {index} (the {MESHOPT} fallback) declares {length} bytes, more than \
                 {MAX_EXPANSION} times the file's {file_length}; the file is corrupt, re-export it"
            ),
        ));
    }
    Ok(vec![0; length])
}

/// One compressed view's description.
struct Compressed {
    source: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: String,
    filter: String,
}

/// Decodes every compressed buffer view of `root` into its place in `buffers`.
pub(super) fn decode_views(
    path: &Path,
    root: &Value,
    buffers: &mut [Vec<u8>],
) -> Result<(), FileError> {
    let Some(views) = root.get("bufferViews").and_then(Value::as_array) else {
        return Ok(());
    };
    for (index, view) in views.iter().enumerate() {
        let Some(ext) = view.pointer(&format!("/extensions/{MESHOPT}")) else {
            continue;
        };
        let fail = |why: String| {
            FileError::format(
                path,
                format!("buffer view {index} ({MESHOPT}): {why}; re-export the file"),
            )
        };
        let number = |v: &Value, key: &str, default: Option<usize>| {
            match v.get(key) {
                Some(x) => x.as_u64().and_then(|x| usize::try_from(x).ok()),
                None => default,
            }
            .ok_or_else(|| fail(format!("'{key}' is missing or not a count")))
        };
        let text = |key: &str, default: &str| {
            ext.get(key)
                .map_or(Some(default), Value::as_str)
                .map(str::to_owned)
                .ok_or_else(|| fail(format!("'{key}' is not a string")))
        };
        let c = Compressed {
            source: number(ext, "buffer", None)?,
            offset: number(ext, "byteOffset", Some(0))?,
            length: number(ext, "byteLength", None)?,
            stride: number(ext, "byteStride", None)?,
            count: number(ext, "count", None)?,
            mode: text("mode", "")?,
            filter: text("filter", "NONE")?,
        };
        let target = number(view, "buffer", None)?;
        let target_offset = number(view, "byteOffset", Some(0))?;
        let source = buffers
            .get(c.source)
            .and_then(|b| b.get(c.offset..c.offset.checked_add(c.length)?))
            .ok_or_else(|| fail(format!("its data lies outside buffer {}", c.source)))?;
        let decoded = decode(&c, source).map_err(fail)?;
        let place = buffers
            .get_mut(target)
            .and_then(|b| b.get_mut(target_offset..target_offset.checked_add(decoded.len())?))
            .ok_or_else(|| {
                fail(format!(
                    "its {} decoded bytes do not fit buffer {target} at offset {target_offset}",
                    decoded.len()
                ))
            })?;
        place.copy_from_slice(&decoded);
    }
    Ok(())
}

/// The decoded bytes of one view (`count` × `stride`), its filter undone.
fn decode(c: &Compressed, source: &[u8]) -> Result<Vec<u8>, String> {
    let size = c
        .count
        .checked_mul(c.stride)
        .filter(|&s| s <= source.len().saturating_mul(MAX_EXPANSION))
        .ok_or_else(|| {
            format!(
                "{} elements of {} bytes from {} compressed bytes is not possible",
                c.count,
                c.stride,
                source.len()
            )
        })?;
    let corrupt = |e: meshopt::Error| format!("the compressed data does not decode ({e:?})");
    let bytes = match (c.mode.as_str(), c.stride) {
        ("TRIANGLES", 2) if c.count.is_multiple_of(3) => {
            let indices = meshopt::decode_index_buffer::<u16>(source, c.count).map_err(corrupt)?;
            indices.iter().flat_map(|i| i.to_le_bytes()).collect()
        }
        ("TRIANGLES", 4) if c.count.is_multiple_of(3) => {
            let indices = meshopt::decode_index_buffer::<u32>(source, c.count).map_err(corrupt)?;
            indices.iter().flat_map(|i| i.to_le_bytes()).collect()
        }
        ("INDICES", 2) => {
            let indices =
                meshopt::decode_index_sequence::<u16>(source, c.count).map_err(corrupt)?;
            indices.iter().flat_map(|i| i.to_le_bytes()).collect()
        }
        ("INDICES", 4) => {
            let indices =
                meshopt::decode_index_sequence::<u32>(source, c.count).map_err(corrupt)?;
            indices.iter().flat_map(|i| i.to_le_bytes()).collect()
        }
        ("ATTRIBUTES", _) => attributes(c, source).map_err(|e| {
            e.unwrap_or_else(|| {
                format!(
                    "the compressed data does not decode as {} attributes",
                    c.count
                )
            })
        })?,
        (mode, stride) => {
            return Err(format!(
                "mode '{mode}' with byteStride {stride} (and count {}) is not a valid combination",
                c.count
            ));
        }
    };
    debug_assert_eq!(bytes.len(), size);
    Ok(bytes)
}

/// A vertex stream of `stride`-byte elements, with its filter undone. `Err(None)`: the data
/// does not decode; `Err(Some(why))`: an unsupported stride or filter.
fn attributes(c: &Compressed, source: &[u8]) -> Result<Vec<u8>, Option<String>> {
    let n = c.count;
    match (c.filter.as_str(), c.stride) {
        ("OCTAHEDRAL", 4) => {
            let mut v = meshopt::decode_vertex_buffer::<[i8; 4]>(source, n).map_err(|_| None)?;
            meshopt::decode_filter_oct(&mut v);
            Ok(v.iter().flatten().map(|&x| x as u8).collect())
        }
        ("OCTAHEDRAL", 8) => {
            let mut v = meshopt::decode_vertex_buffer::<[i16; 4]>(source, n).map_err(|_| None)?;
            meshopt::decode_filter_oct(&mut v);
            Ok(v.iter().flatten().flat_map(|x| x.to_le_bytes()).collect())
        }
        ("QUATERNION", 8) => {
            let mut v = meshopt::decode_vertex_buffer::<[i16; 4]>(source, n).map_err(|_| None)?;
            meshopt::decode_filter_quat(&mut v);
            Ok(v.iter().flatten().flat_map(|x| x.to_le_bytes()).collect())
        }
        ("NONE" | "EXPONENTIAL", stride) if stride % 4 == 0 && (4..=64).contains(&stride) => {
            words(c.filter == "EXPONENTIAL", stride / 4, source, n)
        }
        (filter, stride) => Err(Some(format!(
            "filter '{filter}' with byteStride {stride} is not supported (vertex streams of \
             4 to 64 bytes, octahedral normals of 4 or 8, quaternions of 8)"
        ))),
    }
}

/// Decodes `n` elements of `words` 32-bit words, undoing the exponential filter if asked.
fn words(
    exponential: bool,
    words: usize,
    source: &[u8],
    n: usize,
) -> Result<Vec<u8>, Option<String>> {
    fn decoded<const W: usize>(
        exponential: bool,
        source: &[u8],
        n: usize,
    ) -> Result<Vec<u8>, Option<String>> {
        /// `W` words: the element the decoder fills (its size is the stride).
        #[derive(Clone, Copy)]
        #[repr(transparent)]
        struct Words<const W: usize>([u32; W]);
        impl<const W: usize> Default for Words<W> {
            fn default() -> Self {
                Self([0; W])
            }
        }
        let decoded = meshopt::decode_vertex_buffer::<Words<W>>(source, n).map_err(|_| None)?;
        let mut v: Vec<[u32; W]> = decoded.into_iter().map(|w| w.0).collect();
        if exponential {
            meshopt::decode_filter_exp(&mut v);
        }
        Ok(v.iter().flatten().flat_map(|x| x.to_le_bytes()).collect())
    }
    macro_rules! by_width {
        ($($w:literal)*) => {
            match words {
                $($w => decoded::<$w>(exponential, source, n),)*
                _ => Err(Some(format!("a {}-byte stride is not supported", 4 * words))),
            }
        };
    }
    by_width!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

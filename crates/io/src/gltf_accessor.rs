//! A glTF accessor checked against its buffers before anything reads it, and its elements
//! decoded as f64 (floats, or the integer forms KHR_mesh_quantization allows): the readers of
//! meshes and skins share these.

use std::path::Path;

use super::FileError;

/// Checks an accessor before the `gltf` crate reads it (it panics on some malformed ones): a
/// component type and element type among `kinds`, no sparse storage, a buffer view, a stride at
/// least the element size, and every element inside the view and the view inside its buffer.
/// Returns the element count.
pub(super) fn check_accessor(
    path: &Path,
    accessor: &gltf::Accessor,
    buffers: &[Vec<u8>],
    kinds: &[(gltf::accessor::DataType, gltf::accessor::Dimensions)],
    what: &str,
) -> Result<usize, FileError> {
    let fail = |why: String| {
        FileError::format(
            path,
            format!(
                "{what} (accessor {}): {why}; re-export the file",
                accessor.index()
            ),
        )
    };
    let kind = (accessor.data_type(), accessor.dimensions());
    if !kinds.contains(&kind) {
        let expected: Vec<String> = kinds
            .iter()
            .map(|(t, d)| format!("{d:?} of {t:?}"))
            .collect();
        return Err(fail(format!(
            "holds {:?} of {:?}, expected {}",
            kind.1,
            kind.0,
            expected.join(" or ")
        )));
    }
    if accessor.sparse().is_some() {
        return Err(fail("uses sparse storage, which is not supported".into()));
    }
    let view = accessor
        .view()
        .ok_or_else(|| fail("has no buffer view".into()))?;
    let element = accessor.size();
    let stride = view.stride().unwrap_or(element);
    if stride < element {
        return Err(fail(format!(
            "byteStride {stride} is smaller than its {element}-byte elements"
        )));
    }
    let count = accessor.count();
    if count == 0 {
        return Err(fail("has no elements".into()));
    }
    let last = count
        .checked_sub(1)
        .and_then(|c| c.checked_mul(stride))
        .and_then(|x| x.checked_add(accessor.offset()))
        .and_then(|x| x.checked_add(element))
        .unwrap_or(accessor.offset());
    if last > view.length() {
        return Err(fail(format!(
            "{count} elements need {last} bytes of its buffer view, which has {}",
            view.length()
        )));
    }
    let buffer_length = buffers.get(view.buffer().index()).map_or(0, Vec::len);
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|end| end > buffer_length) {
        return Err(fail(format!(
            "buffer view {} ends past its buffer's {buffer_length} bytes",
            view.index()
        )));
    }
    Ok(count)
}

/// The `N`-component elements of an accessor that [`check_accessor`] passed, as f64: floats as
/// they are, integers as they are or, where the accessor is normalised, mapped to [0, 1]
/// (unsigned) or [−1, 1] (signed) as the glTF specification says; `normalized` also where the
/// core specification requires it without saying so (8- and 16-bit texture coordinates).
pub(super) fn read_elements<const N: usize>(
    accessor: &gltf::Accessor,
    buffers: &[Vec<u8>],
    normalized: bool,
) -> Vec<[f64; N]> {
    use gltf::accessor::DataType as T;
    let Some(view) = accessor.view() else {
        return Vec::new();
    };
    let Some(buffer) = buffers.get(view.buffer().index()) else {
        return Vec::new();
    };
    let size = accessor.data_type().size();
    let stride = view.stride().unwrap_or(size * N);
    let start = view.offset() + accessor.offset();
    let normalized = normalized || accessor.normalized();
    let component = |at: usize| -> f64 {
        let bytes = buffer.get(at..at + size).unwrap_or(&[0; 4][..size]);
        match accessor.data_type() {
            T::F32 => f64::from(f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])),
            T::I8 => {
                let v = f64::from(bytes[0] as i8);
                if normalized { (v / 127.0).max(-1.0) } else { v }
            }
            T::U8 => {
                let v = f64::from(bytes[0]);
                if normalized { v / 255.0 } else { v }
            }
            T::I16 => {
                let v = f64::from(i16::from_le_bytes([bytes[0], bytes[1]]));
                if normalized {
                    (v / 32767.0).max(-1.0)
                } else {
                    v
                }
            }
            T::U16 => {
                let v = f64::from(u16::from_le_bytes([bytes[0], bytes[1]]));
                if normalized { v / 65535.0 } else { v }
            }
            T::U32 => f64::from(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])),
        }
    };
    (0..accessor.count())
        .map(|k| std::array::from_fn(|c| component(start + k * stride + c * size)))
        .collect()
}

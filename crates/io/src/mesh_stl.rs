//! STL meshes (3D printing, CAD, Blender's STL export), binary and ASCII. Each triangle keeps
//! its own three corners, as the file has them (the layout an export writes back); the mesh
//! welds coincident corners for binding. Facet normals are not kept: normals are recomputed
//! from the surface.
//!
//! No crate for STL was at hand (the build is offline); a binary file must be exactly as long as
//! its triangle count says, so a forged count cannot make the reader allocate.

use std::path::Path;

use glam::DVec3;

use super::FileError;
use starcages_core::mesh::Mesh;

/// Reads an STL mesh, binary or ASCII.
pub(super) fn read_stl_mesh(path: &Path) -> Result<Mesh, FileError> {
    let bytes = super::read_file_bytes(path)?;
    parse_stl(path, &bytes)
}

/// Parses the bytes of an STL file (`path` names it in errors).
pub fn parse_stl(path: &Path, bytes: &[u8]) -> Result<Mesh, FileError> {
    let binary_count = bytes
        .get(80..84)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
    let is_binary = binary_count.is_some_and(|n| 84 + 50 * n as u128 == bytes.len() as u128);
    // An ASCII STL starts with `solid` and is text; a binary one may start with `solid` too
    // (some exporters write it into the 80-byte header), but its data is not text.
    let starts_solid = bytes.trim_ascii_start().starts_with(b"solid");
    let is_text = !bytes.contains(&0) && std::str::from_utf8(bytes).is_ok();
    let positions = if is_binary {
        binary(bytes)
    } else if starts_solid && is_text {
        ascii(path, bytes)?
    } else {
        let header_note = if starts_solid {
            " (its header starts with 'solid' as an ASCII STL does, but the rest is binary)"
        } else {
            ""
        };
        return Err(FileError::format(
            path,
            match binary_count {
                Some(n) => format!(
                    "a binary STL file{header_note} announcing {n} triangles is {} bytes long, \
                     but {} were expected (84 + 50 per triangle): it is truncated or its \
                     triangle count is wrong; export it again",
                    bytes.len(),
                    84 + 50 * n as u128
                ),
                None => "too short for an STL file (a binary one has an 84-byte header)".into(),
            },
        ));
    };
    if positions.is_empty() {
        return Err(FileError::format(path, "no triangles"));
    }
    if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
        return Err(FileError::format(
            path,
            format!(
                "triangle {} has a corner that is not finite (NaN or infinity); fix or remove \
                 it and export again",
                v / 3
            ),
        ));
    }
    let triangles = (0..positions.len() as u32 / 3)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    super::mesh_from_file(path, positions, triangles, None, None)
}

/// Corners of a binary STL: an 80-byte header, a u32 count, then per triangle a normal, three
/// corners (f32) and a 2-byte attribute.
fn binary(bytes: &[u8]) -> Vec<DVec3> {
    let f = |record: &[u8], at: usize| {
        f64::from(f32::from_le_bytes([
            record[at],
            record[at + 1],
            record[at + 2],
            record[at + 3],
        ]))
    };
    bytes
        .get(84..)
        .unwrap_or_default()
        .chunks_exact(50)
        .flat_map(|record| {
            // After the facet normal (12 bytes), three corners of 12 bytes.
            (0..3).map(move |c| {
                let at = 12 + 12 * c;
                DVec3::new(f(record, at), f(record, at + 4), f(record, at + 8))
            })
        })
        .collect()
}

/// Corners of an ASCII STL: `vertex x y z` lines, three per `facet`.
fn ascii(path: &Path, bytes: &[u8]) -> Result<Vec<DVec3>, FileError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|_| FileError::format(path, "an ASCII STL file that is not text"))?;
    let mut positions = Vec::new();
    let mut in_facet = 0usize;
    for (number, line) in text.lines().enumerate() {
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("vertex") => {
                let mut xyz = [0.0; 3];
                for (k, value) in xyz.iter_mut().enumerate() {
                    let token = tokens.next().unwrap_or("");
                    *value = super::parse_finite(token, ["x", "y", "z"][k])
                        .map_err(|why| FileError::parse(path, number + 1, why))?;
                }
                positions.push(DVec3::from_array(xyz));
                in_facet += 1;
            }
            Some("endfacet") => {
                if in_facet != 3 {
                    return Err(FileError::parse(
                        path,
                        number + 1,
                        format!("a facet with {in_facet} vertices; each facet has 3"),
                    ));
                }
                in_facet = 0;
            }
            _ => {}
        }
    }
    if in_facet != 0 {
        return Err(FileError::format(path, "the last facet is cut short"));
    }
    Ok(positions)
}

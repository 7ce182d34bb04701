//! A deformed mesh written as a copy of the OBJ file it was read from: every line kept as it is
//! (texture coordinates, faces, groups, objects, material references, comments) except the
//! `v` lines, which get the deformed position of each vertex in file order, and the `vn` lines,
//! recomputed from the deformed surface. The result has the source's vertex list, count and
//! order, so it works as a shape key / blend shape against the original.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use glam::DVec3;

use super::{FileError, parse_finite, read_text, write_atomic};
use starcages_core::mesh::Mesh;

/// What an OBJ export kept and changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ObjCopyReport {
    /// `v` lines written with deformed positions.
    pub moved_vertices: usize,
    /// `v` lines no face uses: not part of the mesh, written as they were.
    pub unused_vertices: usize,
    /// `vn` lines recomputed from the deformed surface.
    pub normals: usize,
}

/// Writes `mesh` deformed to `deformed` (welded positions, scene coordinates) as a copy of
/// `source`, the OBJ file it was read from; `to_file` and `to_scene` turn scene coordinates into
/// the file's and back (its up axis). Atomic, like every save.
pub fn write_obj_like_source(
    path: &Path,
    source: &Path,
    mesh: &Mesh,
    deformed: &[DVec3],
    to_scene: impl Fn(DVec3) -> DVec3,
    to_file: impl Fn(DVec3) -> DVec3,
) -> Result<ObjCopyReport, FileError> {
    if let Some(vertex) = deformed.iter().position(|p| !p.is_finite()) {
        return Err(FileError::NonFinite {
            path: path.to_path_buf(),
            vertex,
        });
    }
    let text = read_text(source)?;
    let vertex_of: Vec<Option<usize>> = source_vertex_list(&text, source, mesh, &to_scene)?
        .iter()
        .map(|v| v.welded)
        .collect();
    // Per `vn` line the area normals of the deformed faces that use it.
    let mut normal_sums: Vec<DVec3> = Vec::new();
    let mut vertices_read = 0usize;
    for (number, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("");
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("v") => vertices_read += 1,
            Some("vn") => normal_sums.push(DVec3::ZERO),
            Some("f") => {
                let corners = tokens
                    .map(|corner| corner_indices(corner, vertices_read, normal_sums.len()))
                    .collect::<Option<Vec<(usize, Option<usize>)>>>()
                    .ok_or_else(|| {
                        FileError::parse(
                            source,
                            number + 1,
                            "a face corner names a vertex or normal that does not exist",
                        )
                    })?;
                let points: Option<Vec<DVec3>> = corners
                    .iter()
                    .map(|&(v, _)| vertex_of.get(v).copied().flatten().map(|w| deformed[w]))
                    .collect();
                let Some(points) = points else { continue };
                let area = newell_normal(&points);
                for &(_, normal) in &corners {
                    if let Some(sum) = normal.and_then(|n| normal_sums.get_mut(n)) {
                        *sum += area;
                    }
                }
            }
            _ => {}
        }
    }
    // The copy.
    let newline = if text.contains("\r\n") { "\r\n" } else { "\n" };
    let mut out = String::with_capacity(text.len() + text.len() / 4);
    let (mut v, mut vn) = (0usize, 0usize);
    let mut report = ObjCopyReport {
        moved_vertices: 0,
        unused_vertices: 0,
        normals: 0,
    };
    for raw in text.lines() {
        let line = raw.split('#').next().unwrap_or("");
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("v") => {
                match vertex_of.get(v).copied().flatten() {
                    Some(w) => {
                        let p = to_file(deformed[w]);
                        // Anything after x y z (w, or vertex colours) stays.
                        let extra: Vec<&str> = tokens.skip(3).collect();
                        let _ = write!(out, "v {} {} {}", p.x, p.y, p.z);
                        for token in extra {
                            let _ = write!(out, " {token}");
                        }
                        report.moved_vertices += 1;
                    }
                    None => {
                        out.push_str(raw);
                        report.unused_vertices += 1;
                    }
                }
                v += 1;
            }
            Some("vn") => {
                match normal_sums
                    .get(vn)
                    .and_then(|n| n.try_normalize())
                    .map(&to_file)
                {
                    Some(n) => {
                        let _ = write!(out, "vn {} {} {}", n.x as f32, n.y as f32, n.z as f32);
                        report.normals += 1;
                    }
                    None => out.push_str(raw),
                }
                vn += 1;
            }
            _ => out.push_str(raw),
        }
        out.push_str(newline);
    }
    write_atomic(path, out.as_bytes())?;
    Ok(report)
}

/// One `v` line of an OBJ file: the welded mesh vertex at its position (none for a vertex no
/// face uses) and the position as the file has it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SourceVertex {
    /// The welded mesh vertex, if a face uses the line.
    pub welded: Option<usize>,
    /// The position in the file's axes.
    pub in_file: DVec3,
}

/// The `v` lines of the OBJ text `text` (read from `source`, the file `mesh` came from), in
/// file order: the vertex list, count and order that a deformed copy keeps. Refuses a file that
/// no longer holds every mesh vertex (it changed since the mesh was read).
pub fn source_vertex_list(
    text: &str,
    source: &Path,
    mesh: &Mesh,
    to_scene: impl Fn(DVec3) -> DVec3,
) -> Result<Vec<SourceVertex>, FileError> {
    // The welded vertex of each rest position (the mesh welded exactly equal positions).
    let welded: HashMap<[u64; 3], usize> = mesh
        .welded_positions()
        .iter()
        .enumerate()
        .map(|(i, p)| (key(*p), i))
        .collect();
    let mut list = Vec::new();
    for (number, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("");
        let mut tokens = line.split_whitespace();
        if tokens.next() != Some("v") {
            continue;
        }
        let mut xyz = [0.0; 3];
        for (k, value) in xyz.iter_mut().enumerate() {
            let token = tokens.next().unwrap_or("");
            *value = parse_finite(token, ["x", "y", "z"][k])
                .map_err(|why| FileError::parse(source, number + 1, why))?;
        }
        let in_file = DVec3::from_array(xyz);
        list.push(SourceVertex {
            welded: welded.get(&key(to_scene(in_file))).copied(),
            in_file,
        });
    }
    // Every vertex of the mesh must come from some `v` line, or the file is not the one the
    // mesh was read from (it changed on disk since).
    let mut reached = vec![false; mesh.welded_positions().len()];
    for w in list.iter().filter_map(|v| v.welded) {
        reached[w] = true;
    }
    if let Some(missing) = reached.iter().position(|r| !r) {
        return Err(FileError::format(
            source,
            format!(
                "no longer matches the scene's mesh (mesh vertex {missing} is not in it: the file \
                 changed since the scene was opened); reopen the scene, or export as .glb"
            ),
        ));
    }
    Ok(list)
}

/// The bit pattern of a position, −0 and +0 alike (as the mesh welds).
fn key(p: DVec3) -> [u64; 3] {
    (p + DVec3::ZERO).to_array().map(f64::to_bits)
}

/// (vertex, normal) indices, 0-based, of a face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`, with
/// OBJ's negative indices counting back from the last one read.
fn corner_indices(corner: &str, vertices: usize, normals: usize) -> Option<(usize, Option<usize>)> {
    let resolve = |token: &str, count: usize| -> Option<usize> {
        let i: i64 = token.parse().ok()?;
        let index = if i < 0 { count as i64 + i } else { i - 1 };
        usize::try_from(index).ok().filter(|&k| k < count)
    };
    let mut parts = corner.split('/');
    let vertex = resolve(parts.next()?, vertices)?;
    let normal = match parts.nth(1) {
        Some(token) if !token.is_empty() => Some(resolve(token, normals)?),
        _ => None,
    };
    Some((vertex, normal))
}

/// The area vector of a polygon (Newell's method: exact for planar polygons, a good average
/// for others).
fn newell_normal(points: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for (k, a) in points.iter().enumerate() {
        let b = points[(k + 1) % points.len()];
        n += a.cross(b);
    }
    0.5 * n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_resolve_positive_and_negative_indices() {
        assert_eq!(corner_indices("3", 5, 0), Some((2, None)));
        assert_eq!(corner_indices("3/1", 5, 0), Some((2, None)));
        assert_eq!(corner_indices("3//2", 5, 4), Some((2, Some(1))));
        assert_eq!(corner_indices("-1/2/-2", 5, 4), Some((4, Some(2))));
        assert_eq!(corner_indices("6", 5, 0), None);
        assert_eq!(corner_indices("0", 5, 0), None);
        assert_eq!(corner_indices("x", 5, 0), None);
    }

    #[test]
    fn a_unit_square_has_area_one_along_z() {
        let square = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        assert_eq!(newell_normal(&square), DVec3::Z);
    }
}

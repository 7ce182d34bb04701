//! OFF meshes (Geomview's Object File Format, common in geometry processing data sets): an
//! `OFF` line (or `COFF`, `NOFF`, `CNOFF`: colours and normals after the coordinates are
//! ignored), the vertex, face and edge counts, the vertices, then each face as its corner
//! count and indices (fanned into triangles; colours after them ignored). `#` starts a
//! comment.

use std::path::Path;

use glam::DVec3;

use super::FileError;
use crate::mesh::Mesh;

/// Reads an OFF mesh.
pub(super) fn read_off_mesh(path: &Path) -> Result<Mesh, FileError> {
    let text = super::read_text(path)?;
    parse_off(path, &text)
}

/// Parses the text of an OFF file (`path` names it in errors).
pub fn parse_off(path: &Path, text: &str) -> Result<Mesh, FileError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.split('#').next().unwrap_or("").trim()))
        .filter(|(_, l)| !l.is_empty());
    let Some((_, first)) = lines.next() else {
        return Err(FileError::format(path, "empty: not an OFF file"));
    };
    let keyword = first.split_whitespace().next().unwrap_or("");
    if !keyword.ends_with("OFF") || keyword.len() > 6 {
        return Err(FileError::parse(
            path,
            1,
            format!("starts with '{keyword}', not OFF: not an OFF file"),
        ));
    }
    // The counts may follow the keyword on its line.
    let rest: Vec<&str> = first.split_whitespace().skip(1).collect();
    let (count_line, counts): (usize, Vec<&str>) = if rest.is_empty() {
        let (n, l) = lines
            .next()
            .ok_or_else(|| FileError::format(path, "no counts line"))?;
        (n, l.split_whitespace().collect())
    } else {
        (1, rest)
    };
    let count = |k: usize, what: &str| -> Result<usize, FileError> {
        counts
            .get(k)
            .and_then(|t| t.parse::<usize>().ok())
            .ok_or_else(|| {
                FileError::parse(
                    path,
                    count_line,
                    format!("the {what} count is missing or not a count"),
                )
            })
    };
    let (vertices, faces) = (count(0, "vertex")?, count(1, "face")?);
    // Every vertex and face takes a line: counts beyond the file's lines are forged.
    let line_count = text.lines().count();
    if vertices.saturating_add(faces) > line_count {
        return Err(FileError::parse(
            path,
            count_line,
            format!(
                "{vertices} vertices and {faces} faces announced, but the file has {line_count} \
                 lines: it is truncated or the counts are wrong"
            ),
        ));
    }
    let mut positions = Vec::with_capacity(vertices);
    for v in 0..vertices {
        let (number, line) = lines.next().ok_or_else(|| {
            FileError::format(path, format!("the file ends at vertex {v} of {vertices}"))
        })?;
        let mut tokens = line.split_whitespace();
        let mut xyz = [0.0; 3];
        for (k, value) in xyz.iter_mut().enumerate() {
            let token = tokens.next().unwrap_or("");
            *value = super::parse_finite(token, ["x", "y", "z"][k])
                .map_err(|why| FileError::parse(path, number, why))?;
        }
        positions.push(DVec3::from_array(xyz));
    }
    let mut triangles = Vec::new();
    for f in 0..faces {
        let (number, line) = lines.next().ok_or_else(|| {
            FileError::format(path, format!("the file ends at face {f} of {faces}"))
        })?;
        let mut tokens = line.split_whitespace();
        let n: usize = tokens
            .next()
            .and_then(|t| t.parse().ok())
            .filter(|&n| n >= 3)
            .ok_or_else(|| {
                FileError::parse(
                    path,
                    number,
                    "a face starts with its corner count, at least 3",
                )
            })?;
        let corners: Vec<u32> = (0..n)
            .map(|_| {
                tokens
                    .next()
                    .and_then(|t| t.parse::<usize>().ok())
                    .filter(|&i| i < vertices)
                    .map(|i| i as u32)
                    .ok_or_else(|| {
                        FileError::parse(
                            path,
                            number,
                            format!("face {f}: a corner is missing or not one of the {vertices} vertices"),
                        )
                    })
            })
            .collect::<Result<_, _>>()?;
        for t in 1..n - 1 {
            triangles.push([corners[0], corners[t], corners[t + 1]]);
        }
    }
    if triangles.is_empty() {
        return Err(FileError::format(path, "no faces: a mesh needs a surface"));
    }
    super::mesh_from_file(path, positions, triangles, None, None)
}

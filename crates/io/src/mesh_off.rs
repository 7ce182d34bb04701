//! OFF meshes (Geomview's Object File Format, common in geometry processing data sets): an
//! `OFF` line (or `COFF`, `NOFF`, `CNOFF`, `STOFF`…: texture coordinates, colours and normals
//! after the coordinates are ignored; `nOFF` with dimension 3), the vertex, face and edge
//! counts, the vertices, then each face as its corner count and indices (fanned into
//! triangles; colours after them ignored). `#` starts a comment. Refused with the reason, never
//! read as something else: 4-D vertices (`4OFF`, `nOFF` of another dimension) and binary OFF
//! (`OFF BINARY`).

use std::path::Path;

use glam::DVec3;

use super::FileError;
use starcages_core::mesh::Mesh;

/// Reads an OFF mesh.
pub(super) fn read_off_mesh(path: &Path) -> Result<Mesh, FileError> {
    let bytes = super::read_file_bytes(path)?;
    // A binary OFF is not text: say so before the text check blames its bytes.
    let first_line = bytes.split(|&b| b == b'\n').next().unwrap_or_default();
    if let Ok(first_line) = std::str::from_utf8(first_line) {
        check_not_binary(path, first_line)?;
    }
    let text = super::read_text(path)?;
    parse_off(path, &text)
}

/// Refuses a header line that announces binary data (`OFF BINARY`).
fn check_not_binary(path: &Path, first_line: &str) -> Result<(), FileError> {
    let line = first_line.split('#').next().unwrap_or("");
    if line.split_whitespace().nth(1) == Some("BINARY") {
        return Err(FileError::parse(
            path,
            1,
            "a binary OFF file ('OFF BINARY'), which StarCages does not read; save it as ASCII \
             OFF (or PLY, OBJ)",
        ));
    }
    Ok(())
}

/// What the header keyword's prefixes (`[ST][C][N][4][n]OFF`, Geomview's grammar) say of the
/// vertex lines: whether the dimension follows on the next token (`n`) and whether a 4th
/// (homogeneous or 4-D) coordinate is added (`4`).
struct Keyword {
    dimension_follows: bool,
    four: bool,
}

fn keyword(path: &Path, keyword: &str) -> Result<Keyword, FileError> {
    let not_off = || {
        FileError::parse(
            path,
            1,
            format!("starts with '{keyword}', not OFF: not an OFF file"),
        )
    };
    let mut rest = keyword.strip_suffix("OFF").ok_or_else(not_off)?;
    for prefix in ["ST", "C", "N"] {
        rest = rest.strip_prefix(prefix).unwrap_or(rest);
    }
    let four = rest.starts_with('4');
    rest = rest.strip_prefix('4').unwrap_or(rest);
    let dimension_follows = rest.starts_with('n');
    rest = rest.strip_prefix('n').unwrap_or(rest);
    if !rest.is_empty() {
        return Err(not_off());
    }
    Ok(Keyword {
        dimension_follows,
        four,
    })
}

/// Refuses vertices of any dimension but 3 (`4OFF`, `nOFF` with another dimension): the 4th
/// coordinate cannot be dropped without changing the mesh.
fn check_dimension(
    path: &Path,
    line: usize,
    keyword: &str,
    dimension: usize,
) -> Result<(), FileError> {
    if dimension == 3 {
        return Ok(());
    }
    Err(FileError::parse(
        path,
        line,
        format!(
            "'{keyword}' announces {dimension}-D vertices; StarCages deforms 3-D meshes: project \
             the mesh to 3-D and save it as plain OFF"
        ),
    ))
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
    check_not_binary(path, first)?;
    let word = first.split_whitespace().next().unwrap_or("");
    let header = keyword(path, word)?;
    // The counts (and nOFF's dimension) may follow the keyword on its line.
    let mut rest: Vec<&str> = first.split_whitespace().skip(1).collect();
    if header.dimension_follows {
        let (line, token) = if rest.is_empty() {
            let (n, l) = lines
                .next()
                .ok_or_else(|| FileError::format(path, "no dimension after 'nOFF'"))?;
            let mut tokens: Vec<&str> = l.split_whitespace().collect();
            let first = tokens.remove(0);
            rest = tokens;
            (n, first)
        } else {
            (1, rest.remove(0))
        };
        let dimension: usize = token.parse().map_err(|_| {
            FileError::parse(
                path,
                line,
                format!("'{token}' is not the dimension 'nOFF' needs"),
            )
        })?;
        check_dimension(path, line, word, dimension + usize::from(header.four))?;
    } else if header.four {
        check_dimension(path, 1, word, 4)?;
    }
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
    if let Some((number, _)) = lines.next() {
        return Err(FileError::parse(
            path,
            number,
            format!(
                "data after the {vertices} vertices and {faces} faces the counts announce: the \
                 counts are wrong (a mesh with more vertices or faces than it says?); export the \
                 file again"
            ),
        ));
    }
    if triangles.is_empty() {
        return Err(FileError::format(path, "no faces: a mesh needs a surface"));
    }
    super::mesh_from_file(path, positions, triangles, None, None)
}

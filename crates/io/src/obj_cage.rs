//! Cage OBJ files: `v` and `f` statements, each `o`/`g` group one cage.
//!
//! A small reader of our own rather than `tobj`: cage files are small, and we need the polygon
//! faces as written (tobj's triangulation loses the grouping we need for eq. 7 otherwise), the
//! `o`/`g` groups, and errors with the line of the offending statement.

use std::path::Path;

use glam::DVec3;

use super::{FileError, parse_finite, read_text};
use starcages_core::cage::Cage;

/// One `o`/`g` group of an OBJ file.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjCageGroup {
    /// Group name (`cage` for faces before any `o`/`g`; numbered when names repeat).
    pub name: String,
    /// Polygon faces as 0-based indices into [`ObjCages::positions`].
    pub faces: Vec<Vec<u32>>,
    /// 1-based line of each face, for error messages.
    pub face_lines: Vec<usize>,
}

/// The content of a cage OBJ file: one vertex list, faces grouped by `o`/`g`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ObjCages {
    /// Vertex positions in file order.
    pub positions: Vec<DVec3>,
    /// Non-empty groups in file order.
    pub groups: Vec<ObjCageGroup>,
}

/// Reads an OBJ file's vertices and grouped polygon faces.
pub fn read_obj_cages(path: &Path) -> Result<ObjCages, FileError> {
    parse_obj_cages(&read_text(path)?, path)
}

/// Reads an OBJ file as one cage: all faces of all groups, vertices in file order.
pub fn read_cage_obj(path: &Path) -> Result<Cage, FileError> {
    let obj = read_obj_cages(path)?;
    let faces: Vec<Vec<u32>> = obj.groups.into_iter().flat_map(|g| g.faces).collect();
    if faces.is_empty() {
        return Err(FileError::parse(
            path,
            1,
            "no faces ('f' lines) in the file; a cage needs faces",
        ));
    }
    Cage::from_polygons(obj.positions, faces).map_err(|problem| FileError::InvalidCage {
        path: path.to_path_buf(),
        problem,
    })
}

/// Parses OBJ text; `path` only names the source in errors.
pub fn parse_obj_cages(text: &str, path: &Path) -> Result<ObjCages, FileError> {
    let mut out = ObjCages::default();
    let mut current = ObjCageGroup {
        name: "cage".to_owned(),
        faces: Vec::new(),
        face_lines: Vec::new(),
    };
    for (line_no, keyword, tokens) in super::obj_statements(text) {
        let err = |reason: String| FileError::parse(path, line_no, reason);
        match keyword {
            "v" => {
                let coords: Vec<&str> = tokens.collect();
                if coords.len() < 3 {
                    return Err(err(format!(
                        "vertex needs 3 coordinates 'v x y z', found {}",
                        coords.len()
                    )));
                }
                let mut xyz = [0.0; 3];
                for k in 0..3 {
                    xyz[k] = parse_finite(coords[k], ["x", "y", "z"][k]).map_err(&err)?;
                }
                out.positions.push(DVec3::from_array(xyz));
            }
            "f" => {
                let mut face = Vec::new();
                for token in tokens {
                    let index_text = token.split('/').next().unwrap_or("");
                    let value: i64 = index_text
                        .parse()
                        .map_err(|_| err(format!("face corner '{token}' is not a vertex index")))?;
                    let count = out.positions.len() as i64;
                    let resolved = match value {
                        v if v > 0 => v - 1,
                        v if v < 0 => count + v,
                        _ => return Err(err("face corner 0: OBJ indices start at 1".to_owned())),
                    };
                    if resolved < 0 || resolved >= count {
                        return Err(err(format!(
                            "face corner {value} refers to a vertex not defined before this line ({count} so far)"
                        )));
                    }
                    face.push(resolved as u32);
                }
                if face.len() < 3 {
                    return Err(err(format!(
                        "face has {} corners; a face needs at least 3",
                        face.len()
                    )));
                }
                current.faces.push(face);
                current.face_lines.push(line_no);
            }
            "o" | "g" => {
                let name = tokens.collect::<Vec<_>>().join(" ");
                let finished = std::mem::replace(
                    &mut current,
                    ObjCageGroup {
                        name: if name.is_empty() {
                            format!("cage{}", out.groups.len())
                        } else {
                            name
                        },
                        faces: Vec::new(),
                        face_lines: Vec::new(),
                    },
                );
                if !finished.faces.is_empty() {
                    out.groups.push(finished);
                }
            }
            // Texture coordinates, normals, materials, smoothing groups, lines: not cage data.
            _ => {}
        }
    }
    if !current.faces.is_empty() {
        out.groups.push(current);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUBE: &str = "\
# unit cube, quads
v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1
o box
f 1 3 4 2\nf 5 6 8 7\nf 1//1 2//1 6//1 5//1\nf 3/1 7/1 8/1 4/1\nf 1 5 7 3\nf -7 -5 -1 -3
";

    #[test]
    fn parses_quads_groups_and_negative_indices() {
        let obj = parse_obj_cages(CUBE, Path::new("cube.obj")).unwrap();
        assert_eq!(obj.positions.len(), 8);
        assert_eq!(obj.groups.len(), 1);
        assert_eq!(obj.groups[0].name, "box");
        assert_eq!(obj.groups[0].faces[5], vec![1, 3, 7, 5]);
        let cage = Cage::from_polygons(obj.positions, obj.groups[0].faces.clone()).unwrap();
        assert_eq!(cage.triangles().len(), 12);
        assert!((cage.volume() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn errors_name_file_and_line() {
        let e = parse_obj_cages("v 0 0 0\nv 1 x 0\n", Path::new("c.obj")).unwrap_err();
        assert_eq!(e.to_string(), "c.obj:2: y 'x' is not a number");
        let e = parse_obj_cages("v 0 0 0\nf 1 2 3\n", Path::new("c.obj")).unwrap_err();
        assert!(
            e.to_string().starts_with("c.obj:2: face corner 2 refers"),
            "{e}"
        );
        let e = parse_obj_cages("v 0 0 0\nv 0 0 0\nf 1 2\n", Path::new("c.obj")).unwrap_err();
        assert!(e.to_string().contains("needs at least 3"), "{e}");
    }
}

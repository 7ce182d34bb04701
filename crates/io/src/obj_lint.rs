//! A line-by-line check of mesh OBJ text before `tobj` reads it: `tobj` silently drops what it
//! cannot use (a face with one or two corners, a file cut mid-face, a `vt nan 0`), so every
//! vertex, texture coordinate, normal and face line is checked here, and the error names the
//! line and the fix.

use std::path::Path;

use super::{FileError, parse_finite};

/// Checks every `v`, `vt`, `vn` and `f` line of `text` (read from `path`).
pub(super) fn check_obj_text(path: &Path, text: &str) -> Result<(), FileError> {
    let mut counts = [0usize; 3]; // v, vt, vn defined so far
    // One buffer for every line's tokens (one allocation per line was most of this pass on a
    // big mesh).
    let mut values: Vec<&str> = Vec::new();
    for (line_no, keyword, tokens) in super::obj_statements(text) {
        values.clear();
        values.extend(tokens);
        let values = &values;
        let err = |reason: String| FileError::parse(path, line_no, reason);
        let numbers = |names: &[&str], least: usize, most: usize, what: &str| {
            if values.len() < least || values.len() > most {
                return Err(err(format!(
                    "{what} needs {} number(s), found {}; the file may be cut short, re-export it",
                    if least == most {
                        least.to_string()
                    } else {
                        format!("{least} to {most}")
                    },
                    values.len()
                )));
            }
            for (k, token) in values.iter().enumerate() {
                let name = names.get(k).copied().unwrap_or("value");
                parse_finite(token, name).map_err(&err)?;
            }
            Ok(())
        };
        match keyword {
            // x y z, an optional w or an r g b colour.
            "v" => numbers(&["x", "y", "z", "w", "g", "b"], 3, 6, "a vertex 'v x y z'")?,
            "vt" => numbers(&["u", "v", "w"], 1, 3, "a texture coordinate 'vt u v'")?,
            "vn" => numbers(&["x", "y", "z"], 3, 3, "a normal 'vn x y z'")?,
            "f" => check_face(values, &counts).map_err(err)?,
            _ => {}
        }
        match keyword {
            "v" => counts[0] += 1,
            "vt" => counts[1] += 1,
            "vn" => counts[2] += 1,
            _ => {}
        }
    }
    Ok(())
}

/// A face's corners: at least three, all in one layout (`v`, `v/vt`, `v//vn` or `v/vt/vn`),
/// every index a non-zero integer naming an element defined above (negative: counted back).
fn check_face(corners: &[&str], counts: &[usize; 3]) -> Result<(), String> {
    if corners.len() < 3 {
        return Err(format!(
            "a face has {} corner(s); a face needs at least 3 (the file may be cut short: \
             re-export it, or delete the line)",
            corners.len()
        ));
    }
    let mut layout = None;
    for corner in corners {
        // Its parts (at most three; a fourth makes it malformed) and which are written.
        let mut parts = [""; 3];
        let mut count = 0;
        for part in corner.split('/') {
            if count == 3 {
                count = 4;
                break;
            }
            parts[count] = part;
            count += 1;
        }
        if count > 3 || parts[0].is_empty() {
            return Err(format!(
                "face corner '{corner}' is not v, v/vt, v//vn or v/vt/vn"
            ));
        }
        // The layout: how many parts, and which are written.
        let this = (count, parts.map(|p| !p.is_empty()));
        let parts = &parts[..count];
        if *layout.get_or_insert(this) != this {
            return Err(format!(
                "face corner '{corner}' is written differently from the face's first corner; \
                 write every corner of a face the same way"
            ));
        }
        for ((part, count), what) in
            parts
                .iter()
                .zip(counts)
                .zip(["vertex", "texture coordinate", "normal"])
        {
            if part.is_empty() {
                continue;
            }
            let i: i64 = part
                .parse()
                .map_err(|_| format!("face corner '{corner}': '{part}' is not a whole number"))?;
            let count = *count as i64;
            let valid = (1..=count).contains(&i) || (-count..=-1).contains(&i);
            if !valid {
                return Err(format!(
                    "face corner '{corner}' names {what} {i}, but {count} are defined above \
                     this line (indices start at 1)"
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(text: &str) -> Result<(), String> {
        check_obj_text(Path::new("m.obj"), text).map_err(|e| e.to_string())
    }

    #[test]
    fn well_formed_files_pass() {
        let text = "# a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0 1.0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
                    vn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf -4//1 -3//1 -2//1\nf 1 2 3\no x\nl 1 2\n";
        assert_eq!(check(text), Ok(()));
    }

    #[test]
    fn each_defect_names_its_line() {
        let base = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n";
        for (extra, line, why) in [
            ("f 1 2\n", 5, "2 corner(s)"),
            ("f 1\n", 5, "1 corner(s)"),
            ("f 1036/359 1\n", 5, "2 corner(s)"),
            ("f 1/1 2 3\n", 5, "written differently"),
            ("f 1 2 4\n", 5, "names vertex 4"),
            ("f 1 2 0\n", 5, "names vertex 0"),
            ("f 1/2 2/1 3/1\n", 5, "texture coordinate 2"),
            ("f 1 2 x\n", 5, "not a whole number"),
            ("f 1/1/1/1 2 3\n", 5, "is not v, v/vt, v//vn or v/vt/vn"),
            ("f /1 2/1 3/1\n", 5, "is not v, v/vt, v//vn or v/vt/vn"),
            ("f 1 2/1 3\n", 5, "written differently"),
            ("vt nan 0\n", 5, "not finite"),
            ("v 1e999 0 0\n", 5, "not finite"),
            ("v 1 2\n", 5, "cut short"),
            ("vn 0 0\n", 5, "a normal"),
        ] {
            let error = check(&format!("{base}{extra}")).unwrap_err();
            assert!(
                error.starts_with(&format!("m.obj:{line}:")),
                "{extra}: {error}"
            );
            assert!(error.contains(why), "{extra}: {error}");
        }
    }
}

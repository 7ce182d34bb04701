//! Point lists: one `x y z` per line; blank lines and `#` comments allowed.

use std::path::Path;

use glam::DVec3;

use super::{FileError, parse_finite, read_text};

/// Reads a point list file.
pub fn read_points(path: &Path) -> Result<Vec<DVec3>, FileError> {
    parse_points(&read_text(path)?, path)
}

/// Parses point list text; `path` only names the source in errors.
pub fn parse_points(text: &str, path: &Path) -> Result<Vec<DVec3>, FileError> {
    let mut points = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let tokens: Vec<&str> = line.split_whitespace().collect();
        if tokens.len() != 3 {
            return Err(FileError::parse(
                path,
                index + 1,
                format!("expected 3 numbers 'x y z', found {} fields", tokens.len()),
            ));
        }
        let mut xyz = [0.0; 3];
        for (k, token) in tokens.iter().enumerate() {
            xyz[k] = parse_finite(token, ["x", "y", "z"][k])
                .map_err(|reason| FileError::parse(path, index + 1, reason))?;
        }
        points.push(DVec3::from_array(xyz));
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_blank_lines_and_errors() {
        let p = Path::new("pts.txt");
        let pts = parse_points("# header\n\n1 2 3 # first\n  -4e-1\t5 6\n", p).unwrap();
        assert_eq!(
            pts,
            vec![DVec3::new(1.0, 2.0, 3.0), DVec3::new(-0.4, 5.0, 6.0)]
        );
        let e = parse_points("1 2 3\n1 2\n", p).unwrap_err().to_string();
        assert_eq!(e, "pts.txt:2: expected 3 numbers 'x y z', found 2 fields");
        let e = parse_points("1 nan 3\n", p).unwrap_err().to_string();
        assert!(e.starts_with("pts.txt:1: y 'nan' is not finite"), "{e}");
        let e = parse_points("1 2 abc\n", p).unwrap_err().to_string();
        assert!(e.contains("z 'abc' is not a number"), "{e}");
    }
}

//! Point lists: one `x y z` per line; blank lines and `#` comments allowed.

use std::path::Path;

use glam::DVec3;

use super::{FileError, parse_finite, read_text};
use starcages_core::cage::MAX_COORDINATE;

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
            let axis = ["x", "y", "z"][k];
            xyz[k] = parse_finite(token, axis)
                .map_err(|reason| FileError::parse(path, index + 1, reason))?;
            // The range every mesh and cage coordinate is held to: beyond it coordinates
            // overflow to infinity in their sums (GC printed null) or lose all precision in
            // the f32 output.
            if xyz[k].abs() > MAX_COORDINATE {
                return Err(FileError::parse(
                    path,
                    index + 1,
                    format!(
                        "{axis} = {:e} is beyond the supported range of ±{MAX_COORDINATE:e}; \
                         express the points (and the scene) in larger units",
                        xyz[k]
                    ),
                ));
            }
        }
        points.push(DVec3::from_array(xyz));
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points beyond ±1e9 are refused naming the line and the coordinate (GC weights of a
    /// point at 1e300 printed null).
    #[test]
    fn points_beyond_the_coordinate_range_are_refused() {
        let p = Path::new("pts.txt");
        assert!(parse_points("1e9 -1e9 0\n", p).is_ok());
        let error = parse_points("0 0 0\n1e300 0 0\n", p)
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with("pts.txt:2:") && error.contains("1e300"),
            "{error}"
        );
        assert!(error.contains("supported range"), "{error}");
    }

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

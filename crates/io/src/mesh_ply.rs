//! PLY meshes (Stanford polygon files: scanners, the Stanford repository, most geometry
//! processing data sets), ASCII and binary in either byte order. The `vertex` element's `x y z`
//! (any numeric type) and, when present, `nx ny nz` and `u v` (or `s t`, `texture_u
//! texture_v`) are read; the `face` element's index list (`vertex_indices` or `vertex_index`)
//! gives polygons, fanned into triangles. Other properties and elements are skipped.
//!
//! No crate for PLY was at hand (the build is offline); the reader checks every count against
//! the bytes left before it allocates, so a forged header cannot exhaust memory.

use std::path::Path;

use glam::{DVec3, Vec2, Vec3};

use super::FileError;
use starcages_core::mesh::Mesh;

/// The storage of a scalar property.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
}

/// A property: a scalar, or a list (count type, item type).
#[derive(Debug, Clone, PartialEq)]
struct Property {
    name: String,
    scalar: Scalar,
    list_count: Option<Scalar>,
}

#[derive(Debug, Clone, PartialEq)]
struct Element {
    name: String,
    /// The header line that declares it (1-based).
    line: usize,
    count: usize,
    properties: Vec<Property>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Little,
    Big,
}

/// Reads a PLY mesh.
pub(super) fn read_ply_mesh(path: &Path) -> Result<Mesh, FileError> {
    let bytes = super::read_file_bytes(path)?;
    parse_ply(path, &bytes)
}

/// Parses the bytes of a PLY file (`path` names it in errors).
pub fn parse_ply(path: &Path, bytes: &[u8]) -> Result<Mesh, FileError> {
    let (format, elements, body) = header(path, bytes)?;
    let data = &bytes[body..];
    let mut reader: Box<dyn Values + '_> = match format {
        Format::Ascii => {
            let text = std::str::from_utf8(data)
                .map_err(|_| FileError::format(path, "an ASCII PLY file whose data is not text"))?;
            Box::new(AsciiValues::new(text, header_lines(bytes, body)))
        }
        Format::Little | Format::Big => Box::new(BinaryValues {
            data,
            at: 0,
            big: format == Format::Big,
            offset: body,
        }),
    };
    let (mut positions, mut normals, mut uvs) = (Vec::new(), Vec::new(), Vec::new());
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut vertex_count = None;
    for element in &elements {
        // The smallest record: one byte per property (binary) or one token (text).
        let least = element.properties.len().max(1);
        if element.count.saturating_mul(least) > data.len() {
            return Err(FileError::format(
                path,
                format!(
                    "the header announces {} '{}' elements, more than the file's {} bytes of \
                     data can hold: the file is truncated or its header is wrong",
                    element.count,
                    element.name,
                    data.len()
                ),
            ));
        }
        let role = |name: &str| element.properties.iter().position(|p| p.name == name);
        match element.name.as_str() {
            "vertex" => {
                let (Some(x), Some(y), Some(z)) = (role("x"), role("y"), role("z")) else {
                    return Err(FileError::format(
                        path,
                        "the vertex element has no x, y and z properties; a mesh needs positions",
                    ));
                };
                let normal = match (role("nx"), role("ny"), role("nz")) {
                    (Some(a), Some(b), Some(c)) => Some([a, b, c]),
                    _ => None,
                };
                let uv = [("u", "v"), ("s", "t"), ("texture_u", "texture_v")]
                    .iter()
                    .find_map(|(u, v)| Some([role(u)?, role(v)?]));
                positions.reserve(element.count);
                let mut record = vec![0.0; element.properties.len()];
                for v in 0..element.count {
                    for (k, property) in element.properties.iter().enumerate() {
                        record[k] = match property.list_count {
                            None => reader.scalar(path, property.scalar)?,
                            Some(count) => {
                                reader.skip_list(path, count, property.scalar)?;
                                0.0
                            }
                        };
                    }
                    let p = DVec3::new(record[x], record[y], record[z]);
                    if !p.is_finite() {
                        return Err(FileError::format(
                            path,
                            format!(
                                "vertex {v} has a coordinate that is not finite (NaN or \
                                 infinity); fix or remove it and export again"
                            ),
                        ));
                    }
                    positions.push(p);
                    if let Some([a, b, c]) = normal {
                        normals.push(Vec3::new(
                            record[a] as f32,
                            record[b] as f32,
                            record[c] as f32,
                        ));
                    }
                    if let Some([a, b]) = uv {
                        uvs.push(Vec2::new(record[a] as f32, record[b] as f32));
                    }
                }
                vertex_count = Some(element.count);
            }
            "face" => {
                let list = element.properties.iter().position(|p| {
                    p.list_count.is_some()
                        && (p.name == "vertex_indices" || p.name == "vertex_index")
                });
                let Some(list) = list else {
                    return Err(FileError::format(
                        path,
                        "the face element has no vertex_indices list; a mesh needs faces",
                    ));
                };
                let Some(count) = vertex_count else {
                    return Err(FileError::format(
                        path,
                        "faces come before the vertices they index; write the vertex element first",
                    ));
                };
                for f in 0..element.count {
                    for (k, property) in element.properties.iter().enumerate() {
                        match property.list_count {
                            Some(count_type) if k == list => {
                                let n = reader.count(path, count_type)?;
                                if n < 3 {
                                    return Err(FileError::format(
                                        path,
                                        format!(
                                            "face {f} has {n} corners; a face needs at least 3"
                                        ),
                                    ));
                                }
                                let mut corners = Vec::with_capacity(n.min(64));
                                for _ in 0..n {
                                    let i = reader.scalar(path, property.scalar)?;
                                    if !(i >= 0.0 && i < count as f64 && i.fract() == 0.0) {
                                        return Err(FileError::format(
                                            path,
                                            format!(
                                                "face {f} names vertex {i}, but there are {count} \
                                                 vertices (numbered from 0); the file is \
                                                 damaged: export it again"
                                            ),
                                        ));
                                    }
                                    corners.push(i as u32);
                                }
                                for t in 1..corners.len() - 1 {
                                    triangles.push([corners[0], corners[t], corners[t + 1]]);
                                }
                            }
                            Some(count_type) => {
                                reader.skip_list(path, count_type, property.scalar)?
                            }
                            None => {
                                reader.scalar(path, property.scalar)?;
                            }
                        }
                    }
                }
            }
            _ => {
                for _ in 0..element.count {
                    for property in &element.properties {
                        match property.list_count {
                            Some(count) => reader.skip_list(path, count, property.scalar)?,
                            None => {
                                reader.scalar(path, property.scalar)?;
                            }
                        }
                    }
                }
            }
        }
    }
    if let Some(left) = reader.left_over() {
        return Err(FileError::format(
            path,
            format!(
                "{left} after the last element the header announces: its counts are wrong (a \
                 mesh with more vertices or faces than it says?); export the file again"
            ),
        ));
    }
    if triangles.is_empty() {
        return Err(FileError::format(
            path,
            "no faces: a point cloud is not a mesh (cages need a surface to deform)",
        ));
    }
    let n = positions.len();
    super::mesh_from_file(
        path,
        positions,
        triangles,
        (normals.len() == n).then_some(normals),
        (uvs.len() == n).then_some(uvs),
    )
}

/// The number of lines the header takes (for 1-based line numbers of ASCII data).
fn header_lines(bytes: &[u8], body: usize) -> usize {
    bytes[..body].iter().filter(|&&b| b == b'\n').count()
}

/// The header: format, elements, and where the data starts.
fn header(path: &Path, bytes: &[u8]) -> Result<(Format, Vec<Element>, usize), FileError> {
    if !bytes.starts_with(b"ply") {
        return Err(FileError::format(
            path,
            "does not start with \"ply\": not a PLY file",
        ));
    }
    let end = find(bytes, b"end_header").ok_or_else(|| {
        FileError::format(path, "no \"end_header\" line: the header is cut short")
    })?;
    let mut body = end + b"end_header".len();
    // The header ends with its line: "\n" or "\r\n".
    if bytes.get(body) == Some(&b'\r') {
        body += 1;
    }
    if bytes.get(body) == Some(&b'\n') {
        body += 1;
    }
    let text = std::str::from_utf8(&bytes[..end])
        .map_err(|_| FileError::format(path, "the header is not text"))?;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    for (number, line) in text.lines().enumerate().skip(1) {
        let line_no = number + 1;
        let tokens: Vec<&str> = line.split_whitespace().collect();
        let bad = |why: String| FileError::parse(path, line_no, why);
        match tokens.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", kind, version] => {
                if !version.starts_with('1') {
                    return Err(bad(format!("PLY version {version}; only 1.0 exists")));
                }
                format = Some(match *kind {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::Little,
                    "binary_big_endian" => Format::Big,
                    other => return Err(bad(format!("unknown format '{other}'"))),
                });
            }
            ["element", name, count] => {
                let count = count
                    .parse::<usize>()
                    .map_err(|_| bad(format!("element count '{count}' is not a count")))?;
                if matches!(*name, "vertex" | "face")
                    && let Some(first) = elements.iter().find(|e| e.name == *name)
                {
                    return Err(bad(format!(
                        "a second '{name}' element (the first is on line {}); a PLY mesh has \
                         one vertex and one face element: merge them and export again",
                        first.line
                    )));
                }
                elements.push(Element {
                    name: (*name).to_owned(),
                    line: line_no,
                    count,
                    properties: Vec::new(),
                });
            }
            ["property", "list", count, item, name] => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| bad("a property before any element".into()))?;
                let (Some(count), Some(item)) = (Scalar::parse(count), Scalar::parse(item)) else {
                    return Err(bad(format!(
                        "unknown type in 'property list {count} {item}'"
                    )));
                };
                if element.name == "vertex" && VERTEX_SCALARS.contains(name) {
                    return Err(bad(format!(
                        "vertex property '{name}' is declared as a list; a coordinate is one \
                         number per vertex: declare it as 'property float {name}'"
                    )));
                }
                push_property(&mut element.properties, name, item, Some(count)).map_err(bad)?;
            }
            ["property", kind, name] => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| bad("a property before any element".into()))?;
                let scalar =
                    Scalar::parse(kind).ok_or_else(|| bad(format!("unknown type '{kind}'")))?;
                push_property(&mut element.properties, name, scalar, None).map_err(bad)?;
            }
            _ => return Err(bad(format!("'{line}' is not a PLY header line"))),
        }
    }
    let format = format.ok_or_else(|| FileError::format(path, "the header has no format line"))?;
    Ok((format, elements, body))
}

/// The vertex properties read as one number per vertex: positions, normals, texture
/// coordinates.
const VERTEX_SCALARS: [&str; 12] = [
    "x",
    "y",
    "z",
    "nx",
    "ny",
    "nz",
    "u",
    "v",
    "s",
    "t",
    "texture_u",
    "texture_v",
];

/// Adds a property to an element's list, refusing a name it already has (which of the two
/// would be the coordinate?).
fn push_property(
    properties: &mut Vec<Property>,
    name: &str,
    scalar: Scalar,
    list_count: Option<Scalar>,
) -> Result<(), String> {
    if properties.iter().any(|p| p.name == name) {
        return Err(format!(
            "property '{name}' is declared twice in the same element; rename or remove one"
        ));
    }
    properties.push(Property {
        name: name.to_owned(),
        scalar,
        list_count,
    });
    Ok(())
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

/// The values of the data section, in order.
trait Values {
    /// The next scalar of type `scalar`.
    fn scalar(&mut self, path: &Path, scalar: Scalar) -> Result<f64, FileError>;

    /// A list's length.
    fn count(&mut self, path: &Path, scalar: Scalar) -> Result<usize, FileError> {
        let n = self.scalar(path, scalar)?;
        if n >= 0.0 && n.fract() == 0.0 && n <= 1e6 {
            Ok(n as usize)
        } else {
            Err(FileError::format(
                path,
                format!("a list has {n} items; expected a count up to a million"),
            ))
        }
    }

    /// What is left after the last element, described (`None` when nothing: the header's
    /// counts took the whole data).
    fn left_over(&mut self) -> Option<String>;

    /// Skips a list.
    fn skip_list(&mut self, path: &Path, count: Scalar, item: Scalar) -> Result<(), FileError> {
        let n = self.count(path, count)?;
        for _ in 0..n {
            self.scalar(path, item)?;
        }
        Ok(())
    }
}

struct BinaryValues<'a> {
    data: &'a [u8],
    at: usize,
    big: bool,
    /// Where the data starts in the file (for messages).
    offset: usize,
}

impl Values for BinaryValues<'_> {
    fn left_over(&mut self) -> Option<String> {
        let left = self.data.len().saturating_sub(self.at);
        (left > 0).then(|| format!("{left} bytes of data remain"))
    }

    fn scalar(&mut self, path: &Path, scalar: Scalar) -> Result<f64, FileError> {
        let size = scalar.size();
        let Some(raw) = self.data.get(self.at..self.at + size) else {
            return Err(FileError::format(
                path,
                format!(
                    "the data ends at byte {} before the header's elements do: the file is \
                     truncated",
                    self.offset + self.data.len()
                ),
            ));
        };
        self.at += size;
        let mut b = [0u8; 8];
        b[..size].copy_from_slice(raw);
        if self.big {
            b[..size].reverse();
        }
        Ok(match scalar {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }
}

struct AsciiValues<'a> {
    tokens: std::iter::Peekable<Box<dyn Iterator<Item = (usize, &'a str)> + 'a>>,
}

impl<'a> AsciiValues<'a> {
    fn new(text: &'a str, header_lines: usize) -> Self {
        let tokens: Box<dyn Iterator<Item = (usize, &'a str)> + 'a> =
            Box::new(text.lines().enumerate().flat_map(move |(i, l)| {
                l.split_whitespace().map(move |t| (header_lines + i + 1, t))
            }));
        Self {
            tokens: tokens.peekable(),
        }
    }
}

impl Values for AsciiValues<'_> {
    fn left_over(&mut self) -> Option<String> {
        let (line, token) = self.tokens.next()?;
        Some(format!("line {line} still holds data ('{token}')"))
    }

    fn scalar(&mut self, path: &Path, scalar: Scalar) -> Result<f64, FileError> {
        let Some((line, token)) = self.tokens.next() else {
            return Err(FileError::format(
                path,
                "the data ends before the header's elements do: the file is truncated",
            ));
        };
        let value: f64 = token
            .parse()
            .map_err(|_| FileError::parse(path, line, format!("'{token}' is not a number")))?;
        if matches!(scalar, Scalar::F32 | Scalar::F64) || value.fract() == 0.0 {
            Ok(value)
        } else {
            Err(FileError::parse(
                path,
                line,
                format!("'{token}' is not an integer, as the header's type says"),
            ))
        }
    }
}

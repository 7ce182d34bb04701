//! Reading rig operations: one as `starcages-cli edit --op` takes it, and scripts of them (one
//! per line, `#` comments).

use glam::DVec3;

use super::{FaceRef, RestTransform, RigEditError, RigOp};
use crate::coords::CoordinateKind;

impl RigOp {
    /// Reads an operation as `starcages-cli edit --op` takes it (see its help).
    pub fn parse(text: &str) -> Result<Self, RigEditError> {
        let syntax = |why: &str| RigEditError::Syntax {
            op: text.to_owned(),
            why: why.to_owned(),
        };
        let number = |token: &str| -> Result<f64, RigEditError> {
            token
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| syntax(&format!("'{token}' is not a finite number")))
        };
        if let Some((cage, rest)) = text.strip_prefix("rest ").and_then(|r| r.split_once(':')) {
            let words: Vec<&str> = rest.split_whitespace().collect();
            let transform = match words.as_slice() {
                ["translate", x, y, z] => {
                    RestTransform::Translate(DVec3::new(number(x)?, number(y)?, number(z)?))
                }
                ["rotate", x, y, z, degrees] => RestTransform::Rotate(
                    DVec3::new(number(x)?, number(y)?, number(z)?),
                    number(degrees)?,
                ),
                ["scale", s] => RestTransform::Scale(number(s)?),
                _ => {
                    return Err(syntax(
                        "expected 'rest CAGE: translate X Y Z', 'rotate AX AY AZ DEG' or 'scale S'",
                    ));
                }
            };
            return Ok(Self::Rest {
                cage: cage.trim().to_owned(),
                transform,
            });
        }
        let words: Vec<&str> = text.split_whitespace().collect();
        match words.as_slice() {
            ["add-box", name, coords @ ..] if coords.len() == 6 || coords.len() == 7 => {
                let c: Vec<f64> = coords[..6]
                    .iter()
                    .map(|t| number(t))
                    .collect::<Result<_, _>>()?;
                let kind = match coords.get(6) {
                    Some(k) => k.parse().map_err(|e: String| syntax(&e))?,
                    None => CoordinateKind::MeanValue,
                };
                Ok(Self::AddBox {
                    name: (*name).to_owned(),
                    min: DVec3::new(c[0], c[1], c[2]),
                    max: DVec3::new(c[3], c[4], c[5]),
                    kind,
                })
            }
            ["extrude", cage, face, distance, rest @ ..] if rest.len() <= 1 => {
                let face = FaceRef::parse(face).map_err(|why| syntax(&why))?;
                Ok(Self::Extrude {
                    cage: (*cage).to_owned(),
                    face,
                    distance: number(distance)?,
                    name: rest
                        .first()
                        .map_or_else(|| format!("{cage}_extruded"), |n| (*n).to_owned()),
                })
            }
            ["inset", cage, face, thickness] => Ok(Self::Inset {
                cage: (*cage).to_owned(),
                face: FaceRef::parse(face).map_err(|why| syntax(&why))?,
                thickness: number(thickness)?,
            }),
            ["kind", cage, kind] => Ok(Self::Kind {
                cage: (*cage).to_owned(),
                kind: kind.parse().map_err(|e: String| syntax(&e))?,
            }),
            ["subdivide"] => Ok(Self::Subdivide),
            ["weld"] => Ok(Self::Weld { distance: 0.0 }),
            ["weld", distance] => Ok(Self::Weld {
                distance: number(distance)?,
            }),
            ["h", cage, h] => Ok(Self::H {
                cage: (*cage).to_owned(),
                h: number(h)?,
            }),
            ["delete", cage] => Ok(Self::Delete {
                cage: (*cage).to_owned(),
            }),
            ["fit", cage, margin] => Ok(Self::Fit {
                cage: (*cage).to_owned(),
                margin: number(margin)?,
            }),
            ["merge", first, second] => Ok(Self::Merge {
                first: (*first).to_owned(),
                second: (*second).to_owned(),
            }),
            ["split", cage, axis, t, rest @ ..] if rest.len() <= 1 => {
                let axis = match *axis {
                    "x" | "X" => 0,
                    "y" | "Y" => 1,
                    "z" | "Z" => 2,
                    other => return Err(syntax(&format!("axis '{other}' is not x, y or z"))),
                };
                Ok(Self::Split {
                    cage: (*cage).to_owned(),
                    axis,
                    t: number(t)?,
                    name: rest
                        .first()
                        .map_or_else(|| format!("{cage}_cut"), |n| (*n).to_owned()),
                })
            }
            ["mirror", cage, rest @ ..] if rest.len() <= 1 => Ok(Self::Mirror {
                cage: (*cage).to_owned(),
                name: rest
                    .first()
                    .map_or_else(|| format!("{cage}_mirrored"), |n| (*n).to_owned()),
            }),
            _ => Err(syntax(
                "unknown operation; use add-box, extrude, inset, split, delete, merge, mirror, fit, kind, h, subdivide, weld or 'rest CAGE: …'",
            )),
        }
    }
}

/// The most operations one rig script may hold (each one copies the scene while it applies,
/// so a longer script is a mistake, not a rig).
pub const MAX_RIG_SCRIPT_OPS: usize = 10_000;

/// Reads a rig script: one operation per line as `--op` takes it; blank lines and text after
/// `#` are ignored. Returns each operation with its line (from 1), or the first line that
/// cannot be read.
pub fn parse_rig_script(text: &str) -> Result<Vec<(usize, RigOp)>, RigEditError> {
    let mut ops = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or_default().trim();
        if line.is_empty() {
            continue;
        }
        if ops.len() == MAX_RIG_SCRIPT_OPS {
            return Err(RigEditError::AtLine {
                line: i + 1,
                problem: Box::new(RigEditError::Value(format!(
                    "a rig script has at most {MAX_RIG_SCRIPT_OPS} operations; split it into \
                     several runs"
                ))),
            });
        }
        let op = RigOp::parse(line).map_err(|e| RigEditError::AtLine {
            line: i + 1,
            problem: Box::new(e),
        })?;
        ops.push((i + 1, op));
    }
    Ok(ops)
}

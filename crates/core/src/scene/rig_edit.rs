//! Building a rig: operations on the rest cages, each a function of the scene that either
//! applies whole or refuses with a reason (the scene is then unchanged). Poses follow rest
//! edits as displacements (a rest move moves every pose by the same amount); new vertices start
//! at rest in every pose. `starcages-cli edit` runs them from a script.

use std::collections::BTreeSet;

use glam::{DQuat, DVec3};

use super::rig_vocabulary::{RigEditError, face_key, move_rest_vertex};
use super::{LeafCage, Scene};
use crate::cage::shapes::box_faces;
use crate::coords::CoordinateKind;

/// One rig operation.
#[derive(Debug, Clone, PartialEq)]
pub enum RigOp {
    /// A new axis-aligned box leaf cage from `min` to `max` (corners at positions of existing
    /// vertices reuse them, so a box beside a cage shares its face).
    AddBox {
        /// Its name.
        name: String,
        /// One corner.
        min: DVec3,
        /// The opposite corner.
        max: DVec3,
        /// Its coordinates.
        kind: CoordinateKind,
    },
    /// A new leaf cage on a face of `cage`, pushed out `distance` along its outward normal; the
    /// new cage shares that face with `cage`.
    Extrude {
        /// The cage.
        cage: String,
        /// The face: by index or by the direction it faces.
        face: FaceRef,
        /// How far.
        distance: f64,
        /// The new cage's name.
        name: String,
    },
    /// Inset a face no other cage shares (Blender's Inset Faces): a smaller copy of it,
    /// `thickness` inside each of its edges in its plane, joined to its edges by a ring of
    /// quads. The cage keeps its shape; the inner face can then be extruded, so the new cage
    /// touches no vertex of the face's edges (and no cage beyond them).
    Inset {
        /// The cage.
        cage: String,
        /// The face: by index or by the direction it faces.
        face: FaceRef,
        /// Distance from each edge to the inner face's edge, in scene units.
        thickness: f64,
    },
    /// Remove a leaf cage; vertices no other cage uses go.
    Delete {
        /// The cage.
        cage: String,
    },
    /// A copy of `cage` mirrored across x = 0 (vertices on the plane are shared).
    Mirror {
        /// The cage.
        cage: String,
        /// The copy's name.
        name: String,
    },
    /// Join two neighbouring cages into the first (the faces they share dissolve).
    Merge {
        /// The cage that stays.
        first: String,
        /// The cage merged into it.
        second: String,
    },
    /// Loop cut: split a cage whose faces are two ends and a ring of quads between them (a box,
    /// an extruded cage) across the ring, at fraction `t` from the end facing −`axis`; the
    /// two parts share the new face.
    Split {
        /// The cage.
        cage: String,
        /// The world axis the cut goes across (0 x, 1 y, 2 z): the ends are the faces whose
        /// normals are most aligned with it.
        axis: usize,
        /// Where, in (0, 1).
        t: f64,
        /// The new part's name (the part beyond the cut).
        name: String,
    },
    /// Fit to mesh (a shrink-wrap): pull each of the cage's vertices that no other leaf cage
    /// shares toward the mesh vertex nearest to it, as far as keeps every mesh vertex it holds
    /// inside with `margin` (a fraction of the mesh's bounding box diagonal) between them and
    /// the cage; a mesh vertex already closer than that keeps the distance it has.
    Fit {
        /// The cage.
        cage: String,
        /// The margin, as a fraction of the mesh's diagonal.
        margin: f64,
    },
    /// Give a leaf cage other coordinates.
    Kind {
        /// The cage.
        cage: String,
        /// Its new coordinates.
        kind: CoordinateKind,
    },
    /// Set the blending parameter h (eq. 11) of one leaf cage, or with `cage` = `all` the
    /// scene's default h (cages without their own h use it).
    H {
        /// The cage, or `all`.
        cage: String,
        /// h in (0, 1].
        h: f64,
    },
    /// Subdivide every face of every leaf cage into quads (a vertex at each edge's midpoint and
    /// at each face's centre, Blender's Subdivide). Shared faces and edges are cut the same way
    /// on both sides, so the rig stays watertight; poses get the same midpoints of their own
    /// positions. Refused while internal cages drive leaf vertices (the new vertices would
    /// have no driver).
    Subdivide,
    /// Weld: merge cage vertices no farther apart than `distance` (0: only those at exactly
    /// the same position), so cages that touch there share their border (see `weld_vertices`).
    Weld {
        /// The distance, in scene units.
        distance: f64,
    },
    /// Move a cage's rest vertices (and every pose by the same amount).
    Rest {
        /// The cage.
        cage: String,
        /// How.
        transform: RestTransform,
    },
}

/// A face of a cage, named by its index in the cage's face list (0-based, as in the scene
/// file) or by the direction it faces (`+x`, `-z`, …: the face whose outward normal is most
/// aligned with that axis, so a script reads as what it builds; among coplanar faces the one
/// listed first, which after an inset is the inner face).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FaceRef {
    /// By index.
    Index(usize),
    /// By direction: the axis (0 x, 1 y, 2 z) and whether it is the positive one.
    Facing {
        /// The world axis.
        axis: usize,
        /// Towards +axis (true) or −axis.
        positive: bool,
    },
}

impl FaceRef {
    /// Reads a face number or a direction (`+x`, `-z`, …).
    pub fn parse(text: &str) -> Result<Self, String> {
        let direction = |axis: usize| match text.as_bytes().first() {
            Some(b'+') => Some(Self::Facing {
                axis,
                positive: true,
            }),
            Some(b'-') => Some(Self::Facing {
                axis,
                positive: false,
            }),
            _ => None,
        };
        match text.get(1..) {
            Some("x" | "X") => direction(0),
            Some("y" | "Y") => direction(1),
            Some("z" | "Z") => direction(2),
            _ => None,
        }
        .or_else(|| text.parse().ok().map(Self::Index))
        .ok_or_else(|| {
            format!(
                "face '{text}' is neither a face number nor a direction (+x, -x, +y, -y, +z, -z)"
            )
        })
    }
}

impl std::fmt::Display for FaceRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Index(i) => write!(f, "{i}"),
            Self::Facing { axis, positive } => write!(
                f,
                "{}{}",
                if *positive { '+' } else { '-' },
                ['x', 'y', 'z'][(*axis).min(2)]
            ),
        }
    }
}

/// A change of a cage's rest positions, about the centroid of its vertices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RestTransform {
    /// Move by this vector.
    Translate(DVec3),
    /// Turn about this axis by degrees.
    Rotate(DVec3, f64),
    /// Scale by this factor.
    Scale(f64),
}

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

/// Adds the leaf cages of `imported` (positions in scene coordinates) to `scene`: vertices at
/// the exact positions of existing ones are reused, so imported cages that meet the rig share
/// its faces; new vertices start at rest in every pose. Names already taken get a number.
pub fn import_leaf_cages(scene: &mut Scene, imported: &super::CageSet) {
    let map: Vec<u32> = imported
        .vertices
        .iter()
        .map(|&p| vertex_at(scene, p))
        .collect();
    for cage in &imported.leaves {
        let name = (1..)
            .map(|k| {
                if k == 1 {
                    cage.name.clone()
                } else {
                    format!("{}_{k}", cage.name)
                }
            })
            .find(|n| free_name(scene, n).is_ok())
            .unwrap_or_default();
        scene.cages.leaves.push(LeafCage {
            name,
            faces: cage
                .faces
                .iter()
                .map(|f| f.iter().map(|&v| map[v as usize]).collect())
                .collect(),
            ..cage.clone()
        });
    }
}

/// Applies `op` to `scene`, or refuses with the scene unchanged.
pub fn apply_rig_op(scene: &mut Scene, op: &RigOp) -> Result<(), RigEditError> {
    check_structure(scene)?;
    let mut edited = scene.clone();
    match op {
        RigOp::AddBox {
            name,
            min,
            max,
            kind,
        } => add_box(&mut edited, name, *min, *max, *kind)?,
        RigOp::Extrude {
            cage,
            face,
            distance,
            name,
        } => extrude(&mut edited, cage, *face, *distance, name)?,
        RigOp::Inset {
            cage,
            face,
            thickness,
        } => {
            let c = leaf(&edited, cage)?;
            let f = free_face(&edited, c, *face)?;
            super::inset::inset_face(&mut edited, c, f, *thickness)?;
        }
        RigOp::Delete { cage } => delete(&mut edited, cage)?,
        RigOp::Merge { first, second } => merge(&mut edited, first, second)?,
        RigOp::Split {
            cage,
            axis,
            t,
            name,
        } => split(&mut edited, cage, *axis, *t, name)?,
        RigOp::Mirror { cage, name } => mirror(&mut edited, cage, name)?,
        RigOp::Fit { cage, margin } => {
            let c = leaf(&edited, cage)?;
            super::fit::fit(&mut edited, c, *margin)?;
        }
        RigOp::Rest { cage, transform } => rest(&mut edited, cage, *transform)?,
        RigOp::Kind { cage, kind } => {
            let c = leaf(&edited, cage)?;
            edited.cages.leaves[c].kind = *kind;
        }
        RigOp::Subdivide => super::subdivide::subdivide_leaf_cages(&mut edited)?,
        RigOp::Weld { distance } => {
            super::weld::weld_vertices(&mut edited, *distance, None)?;
        }
        RigOp::H { cage, h } => {
            if !(*h > 0.0 && *h <= 1.0) {
                return Err(RigEditError::Value(format!(
                    "h {cage} {h}: h must be in (0, 1] (1 blends across the whole cage, small \
                     values only near its borders)"
                )));
            }
            if cage == "all" {
                edited.settings.default_h = *h;
            } else {
                let c = leaf(&edited, cage)?;
                edited.cages.leaves[c].h = Some(*h);
            }
        }
    }
    *scene = edited;
    Ok(())
}

/// The operations index vertices through the faces and the poses: a scene read from a file
/// that `validate` would refuse on those grounds is refused here rather than indexed.
fn check_structure(scene: &Scene) -> Result<(), RigEditError> {
    let count = scene.cages.vertices.len();
    let set = &scene.cages;
    let faces = set
        .leaves
        .iter()
        .map(|c| (&c.name, &c.faces))
        .chain(set.internals.iter().map(|c| (&c.name, &c.faces)));
    for (name, faces) in faces {
        if let Some(v) = faces.iter().flatten().find(|&&v| v as usize >= count) {
            return Err(RigEditError::Value(format!(
                "cage '{name}' refers to vertex {v}, but there are {count}; fix the scene first \
                 (starcages-cli validate lists its problems)"
            )));
        }
    }
    let poses = std::iter::once(&scene.pose).chain(scene.poses.values());
    if poses.into_iter().any(|p| p.len() != count) {
        return Err(RigEditError::Value(
            "a pose has another vertex count than the cages; fix the scene first (starcages-cli \
             validate lists its problems)"
                .into(),
        ));
    }
    Ok(())
}

fn leaf(scene: &Scene, name: &str) -> Result<usize, RigEditError> {
    scene
        .cages
        .leaf_index(name)
        .ok_or_else(|| RigEditError::NoSuchCage(name.to_owned()))
}

fn free_name(scene: &Scene, name: &str) -> Result<(), RigEditError> {
    let set = &scene.cages;
    let taken =
        set.leaves.iter().any(|c| c.name == name) || set.internals.iter().any(|c| c.name == name);
    if taken || name.is_empty() {
        Err(RigEditError::NameTaken(name.to_owned()))
    } else {
        Ok(())
    }
}

/// The vertex at exactly `p` (rest), or a new one there (at rest in every pose).
fn vertex_at(scene: &mut Scene, p: DVec3) -> u32 {
    if let Some(v) = scene.cages.vertices.iter().position(|q| *q == p) {
        return v as u32;
    }
    scene.cages.vertices.push(p);
    scene.pose.push(p);
    for pose in scene.poses.values_mut() {
        pose.push(p);
    }
    scene.cages.vertices.len() as u32 - 1
}

fn add_box(
    scene: &mut Scene,
    name: &str,
    min: DVec3,
    max: DVec3,
    kind: CoordinateKind,
) -> Result<(), RigEditError> {
    free_name(scene, name)?;
    let (lo, hi) = (min.min(max), min.max(max));
    if (hi - lo).min_element() <= 0.0 {
        return Err(RigEditError::Value(format!(
            "add-box {name}: the box is flat ({lo} .. {hi}); give it a size along every axis"
        )));
    }
    let corners: [u32; 8] = std::array::from_fn(|c| {
        let p = DVec3::new(
            if c & 1 == 0 { lo.x } else { hi.x },
            if c & 2 == 0 { lo.y } else { hi.y },
            if c & 4 == 0 { lo.z } else { hi.z },
        );
        vertex_at(scene, p)
    });
    scene.cages.leaves.push(LeafCage {
        name: name.to_owned(),
        kind,
        h: None,
        border_h: Default::default(),
        faces: box_faces(corners),
    });
    Ok(())
}

/// The index of the face `face` names in leaf cage `c`.
fn face_index(scene: &Scene, c: usize, face: FaceRef) -> Result<usize, RigEditError> {
    let cage = &scene.cages.leaves[c];
    match face {
        FaceRef::Index(i) => Ok(i),
        FaceRef::Facing { axis, positive } => {
            let mut toward = DVec3::ZERO;
            toward[axis.min(2)] = if positive { 1.0 } else { -1.0 };
            cage.faces
                .iter()
                .enumerate()
                .map(|(i, f)| (i, face_normal(scene, f).dot(toward)))
                .filter(|(_, alignment)| *alignment > 0.5)
                // Coplanar faces tie (an inset's ring around its inner face, a subdivided
                // face's quads): the lowest index wins, which after an inset is the inner face.
                .fold(
                    None,
                    |best: Option<(usize, f64)>, (i, alignment)| match best {
                        Some((_, b)) if alignment <= b + 1e-9 => best,
                        _ => Some((i, alignment)),
                    },
                )
                .map(|(i, _)| i)
                .ok_or_else(|| {
                    RigEditError::Value(format!(
                        "cage '{}' has no face facing {face}; name the face by its number",
                        cage.name
                    ))
                })
        }
    }
}

/// The index of the face `face` names in leaf cage `c`, checked to exist and to be shared
/// with no other leaf cage (extrude and inset work on the rig's outer surface).
fn free_face(scene: &Scene, c: usize, face: FaceRef) -> Result<usize, RigEditError> {
    let face = face_index(scene, c, face)?;
    let cage = &scene.cages.leaves[c];
    let Some(corners) = cage.faces.get(face) else {
        return Err(RigEditError::NoSuchFace {
            cage: cage.name.clone(),
            face,
            count: cage.faces.len(),
        });
    };
    let key = face_key(corners);
    let shared = scene
        .cages
        .leaves
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != c)
        .flat_map(|(_, l)| &l.faces)
        .any(|f| face_key(f) == key);
    if shared {
        return Err(RigEditError::FaceShared {
            cage: cage.name.clone(),
            face,
        });
    }
    Ok(face)
}

/// A face's unit outward normal (Newell's method: counter-clockwise seen from outside), zero
/// for a face without area.
fn face_normal(scene: &Scene, face: &[u32]) -> DVec3 {
    let points: Vec<DVec3> = face
        .iter()
        .filter_map(|&v| scene.cages.vertices.get(v as usize).copied())
        .collect();
    points
        .iter()
        .zip(points.iter().cycle().skip(1))
        .map(|(a, b)| a.cross(*b))
        .sum::<DVec3>()
        .normalize_or_zero()
}

fn extrude(
    scene: &mut Scene,
    cage: &str,
    face: FaceRef,
    distance: f64,
    name: &str,
) -> Result<(), RigEditError> {
    free_name(scene, name)?;
    let c = leaf(scene, cage)?;
    let face = free_face(scene, c, face)?;
    let corners = scene.cages.leaves[c].faces[face].clone();
    if distance.is_nan() || distance <= 0.0 {
        return Err(RigEditError::Value(format!(
            "extrude {cage} {face}: the distance {distance} must be positive"
        )));
    }
    let points: Vec<DVec3> = corners
        .iter()
        .map(|&v| scene.cages.vertices[v as usize])
        .collect();
    let normal = face_normal(scene, &corners);
    if normal == DVec3::ZERO {
        return Err(RigEditError::Value(format!(
            "face {face} of '{cage}' has no area to extrude"
        )));
    }
    let cap: Vec<u32> = points
        .iter()
        .map(|p| vertex_at(scene, *p + normal * distance))
        .collect();
    // The base is the shared face run the other way; the cap keeps the face's orientation
    // (it faces outwards, away from the old cage); the sides join edge (a, b) to (a', b').
    let mut new_faces = vec![
        corners.iter().rev().copied().collect::<Vec<u32>>(),
        cap.clone(),
    ];
    let k = corners.len();
    for i in 0..k {
        let j = (i + 1) % k;
        new_faces.push(vec![corners[i], corners[j], cap[j], cap[i]]);
    }
    let kind = scene.cages.leaves[c].kind;
    scene.cages.leaves.push(LeafCage {
        name: name.to_owned(),
        kind,
        h: None,
        border_h: Default::default(),
        faces: new_faces,
    });
    Ok(())
}

/// Removes the vertices of `gone` (a removed cage's faces) that no cage uses any more, with
/// their ownership and hierarchy records, renumbering every index.
fn drop_unused_vertices(scene: &mut Scene, gone: &[Vec<u32>]) {
    let used = scene.cages.used_vertices();
    let removed: BTreeSet<u32> = gone
        .iter()
        .flatten()
        .copied()
        .filter(|v| !used.contains(v))
        .collect();
    for internal in &mut scene.cages.internals {
        internal.owns.retain(|v| !removed.contains(v));
    }
    for state in std::iter::once(&mut scene.pose_state).chain(scene.pose_states.values_mut()) {
        crate::hierarchy::forget(state, &removed);
    }
    crate::hierarchy::renumber(scene, &removed);
}

fn delete(scene: &mut Scene, cage: &str) -> Result<(), RigEditError> {
    let c = leaf(scene, cage)?;
    let gone = scene.cages.leaves.remove(c);
    // Neighbours' per-border h for the gone cage go too.
    for other in &mut scene.cages.leaves {
        other.border_h.remove(cage);
    }
    drop_unused_vertices(scene, &gone.faces);
    Ok(())
}

fn merge(scene: &mut Scene, first: &str, second: &str) -> Result<(), RigEditError> {
    let (a, b) = (leaf(scene, first)?, leaf(scene, second)?);
    if a == b {
        return Err(RigEditError::Value(format!(
            "merge {first} {second}: the same cage twice"
        )));
    }
    let shared: BTreeSet<Vec<u32>> = {
        let of_b: BTreeSet<Vec<u32>> = scene.cages.leaves[b]
            .faces
            .iter()
            .map(|f| face_key(f))
            .collect();
        scene.cages.leaves[a]
            .faces
            .iter()
            .map(|f| face_key(f))
            .filter(|k| of_b.contains(k))
            .collect()
    };
    if shared.is_empty() {
        return Err(RigEditError::Value(format!(
            "merge {first} {second}: they share no face; only neighbours can be merged"
        )));
    }
    let keep = |faces: &[Vec<u32>]| -> Vec<Vec<u32>> {
        faces
            .iter()
            .filter(|f| !shared.contains(&face_key(f)))
            .cloned()
            .collect()
    };
    let mut faces = keep(&scene.cages.leaves[a].faces);
    faces.extend(keep(&scene.cages.leaves[b].faces));
    scene.cages.leaves[a].faces = faces;
    scene.cages.leaves[a].border_h.remove(second);
    let gone = scene.cages.leaves.remove(b);
    for other in &mut scene.cages.leaves {
        other.border_h.remove(&gone.name);
    }
    // The vertices only the dissolved faces used (none for two boxes) go.
    drop_unused_vertices(scene, &gone.faces);
    Ok(())
}

/// The ring a loop cut of leaf cage `cage` across world axis `axis` (0 x, 1 y, 2 z) goes
/// around: the cage's two ends (the faces most against and most along the axis) and, for each
/// corner of the start end in its order, the corner of the far end its side edge leads to. A cut
/// at fraction t puts a vertex on each of those edges at t from the start. Refused where the
/// cage is not two ends joined by a ring of quads, or a ring face is shared with a neighbour
/// (the cut would leave it a T-junction).
pub fn loop_cut_ring(scene: &Scene, cage: &str, axis: usize) -> Result<LoopCutRing, RigEditError> {
    let c = leaf(scene, cage)?;
    let faces = &scene.cages.leaves[c].faces;
    let axis = axis.min(2);
    let along = |f: &[u32]| face_normal(scene, f)[axis];
    let not_a_ring = || {
        RigEditError::Value(format!(
            "split {cage}: it is not two ends joined by a ring of quads across that axis (a box or an \
         extruded cage is); cut another cage or along another axis"
        ))
    };
    if faces.is_empty() {
        return Err(not_a_ring());
    }
    // The ends: the faces most against and most along the axis.
    let (low, high) = (0..faces.len()).fold((0, 0), |(lo, hi), f| {
        (
            if along(&faces[f]) < along(&faces[lo]) {
                f
            } else {
                lo
            },
            if along(&faces[f]) > along(&faces[hi]) {
                f
            } else {
                hi
            },
        )
    });
    let (start, end) = (&faces[low], &faces[high]);
    let k = start.len();
    if low == high || end.len() != k || faces.len() != k + 2 {
        return Err(not_a_ring());
    }
    // Each start vertex's partner on the end face: the other end of its side edge.
    let end_set: BTreeSet<u32> = end.iter().copied().collect();
    let mut partner = std::collections::BTreeMap::new();
    for (f, side) in faces.iter().enumerate() {
        if f == low || f == high {
            continue;
        }
        if side.len() != 4 {
            return Err(not_a_ring());
        }
        for i in 0..4 {
            let (a, b) = (side[i], side[(i + 1) % 4]);
            if start.contains(&a) && end_set.contains(&b) {
                partner.insert(a, b);
            } else if start.contains(&b) && end_set.contains(&a) {
                partner.insert(b, a);
            }
        }
    }
    if partner.len() != k {
        return Err(not_a_ring());
    }
    // A ring face shared with a neighbour would be cut on one side only (a T-junction).
    for (f, side) in faces.iter().enumerate() {
        if f == low || f == high {
            continue;
        }
        let key = face_key(side);
        if let Some(other) = scene
            .cages
            .leaves
            .iter()
            .enumerate()
            .find(|(i, l)| *i != c && l.faces.iter().any(|g| face_key(g) == key))
        {
            return Err(RigEditError::Value(format!(
                "split {cage}: ring face {f} is shared with '{}', which the cut would leave \
                 with a T-junction; cut along another axis",
                other.1.name
            )));
        }
    }
    Ok(LoopCutRing {
        start_face: low,
        end_face: high,
        edges: start.iter().map(|&a| (a, partner[&a])).collect(),
    })
}

/// Where a loop cut goes: see [`loop_cut_ring`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LoopCutRing {
    /// The end the cut fraction is measured from (index in the cage's faces).
    pub start_face: usize,
    /// The other end.
    pub end_face: usize,
    /// The side edges, (start corner, far corner), in the start face's order.
    pub edges: Vec<(u32, u32)>,
}

fn split(
    scene: &mut Scene,
    cage: &str,
    axis: usize,
    t: f64,
    name: &str,
) -> Result<(), RigEditError> {
    free_name(scene, name)?;
    let c = leaf(scene, cage)?;
    if !(t > 0.0 && t < 1.0) {
        return Err(RigEditError::Value(format!(
            "split {cage}: t = {t} must be inside (0, 1)"
        )));
    }
    let ring = loop_cut_ring(scene, cage, axis)?;
    let faces = scene.cages.leaves[c].faces.clone();
    let (low, high) = (ring.start_face, ring.end_face);
    let (start, end) = (&faces[low], &faces[high]);
    let end_set: BTreeSet<u32> = end.iter().copied().collect();
    let partner: std::collections::BTreeMap<u32, u32> = ring.edges.iter().copied().collect();
    // New vertices on the side edges, at t from the start end.
    let mut cut = std::collections::BTreeMap::new();
    for (&a, &b) in &partner {
        let (pa, pb) = (
            scene.cages.vertices[a as usize],
            scene.cages.vertices[b as usize],
        );
        cut.insert(a, vertex_at(scene, pa + (pb - pa) * t));
        // The end vertex maps to the same cut vertex.
        cut.insert(b, cut[&a]);
    }
    // The start part keeps the start face and the start halves of the sides; the far part
    // gets the end face and the far halves. A side quad's start-side corners stay, its
    // end-side corners become cut vertices (and the other way round for the far part).
    let mut near = vec![start.clone()];
    let mut far = vec![end.clone()];
    for (f, side) in faces.iter().enumerate() {
        if f == low || f == high {
            continue;
        }
        near.push(
            side.iter()
                .map(|v| if end_set.contains(v) { cut[v] } else { *v })
                .collect(),
        );
        far.push(
            side.iter()
                .map(|v| if end_set.contains(v) { *v } else { cut[v] })
                .collect(),
        );
    }
    // The new face: the start face moved to the cut, facing the far part from the near one
    // (its orientation is the end face's), and reversed for the far part.
    let cut_face: Vec<u32> = start.iter().rev().map(|v| cut[v]).collect();
    near.push(cut_face.clone());
    far.push(cut_face.iter().rev().copied().collect());
    let original = scene.cages.leaves[c].clone();
    scene.cages.leaves[c].faces = near;
    scene.cages.leaves.push(LeafCage {
        name: name.to_owned(),
        faces: far,
        border_h: Default::default(),
        ..original
    });
    Ok(())
}

fn mirror(scene: &mut Scene, cage: &str, name: &str) -> Result<(), RigEditError> {
    free_name(scene, name)?;
    let c = leaf(scene, cage)?;
    let source = scene.cages.leaves[c].clone();
    let mut map = std::collections::BTreeMap::new();
    for &v in source.faces.iter().flatten() {
        if map.contains_key(&v) {
            continue;
        }
        let p = scene.cages.vertices[v as usize];
        let mirrored = DVec3::new(-p.x, p.y, p.z);
        map.insert(v, vertex_at(scene, mirrored));
    }
    // A reflection turns orientation inside out: run every face the other way.
    let faces = source
        .faces
        .iter()
        .map(|f| f.iter().rev().map(|v| map[v]).collect())
        .collect();
    scene.cages.leaves.push(LeafCage {
        name: name.to_owned(),
        faces,
        border_h: Default::default(),
        ..source
    });
    Ok(())
}

fn rest(scene: &mut Scene, cage: &str, transform: RestTransform) -> Result<(), RigEditError> {
    let c = leaf(scene, cage)?;
    let vertices: BTreeSet<u32> = scene.cages.leaves[c]
        .faces
        .iter()
        .flatten()
        .copied()
        .collect();
    let centre = vertices
        .iter()
        .map(|&v| scene.cages.vertices[v as usize])
        .sum::<DVec3>()
        / vertices.len().max(1) as f64;
    let map: Box<dyn Fn(DVec3) -> DVec3> = match transform {
        RestTransform::Translate(d) => Box::new(move |p| p + d),
        RestTransform::Rotate(axis, degrees) => {
            let Some(axis) = axis.try_normalize() else {
                return Err(RigEditError::Value(format!(
                    "rest {cage}: rotate needs a non-zero axis"
                )));
            };
            let turn = DQuat::from_axis_angle(axis, degrees.to_radians());
            Box::new(move |p| centre + turn * (p - centre))
        }
        RestTransform::Scale(s) if s > 0.0 => Box::new(move |p| centre + (p - centre) * s),
        RestTransform::Scale(s) => {
            return Err(RigEditError::Value(format!(
                "rest {cage}: scale {s} must be positive"
            )));
        }
    };
    for &v in &vertices {
        let to = map(scene.cages.vertices[v as usize]);
        move_rest_vertex(scene, v, to);
    }
    Ok(())
}

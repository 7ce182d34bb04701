//! Whole-cage edits as text, the scripting form of what the editor does:
//! `"CAGE: translate X Y Z"`, `"CAGE: rotate AX AY AZ DEG"` (about the cage's centroid, or a
//! control's pivot) and `"CAGE: scale S"` (about the same point).

use std::str::FromStr;

use glam::{DQuat, DVec3};
use thiserror::Error;

use crate::scene::{CageSet, InternalCage};

/// A transformation of a whole cage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CageTransform {
    /// Move by a vector.
    Translate(DVec3),
    /// Turn about an axis through the centroid, by degrees (right-handed).
    Rotate {
        /// Axis (any length but zero).
        axis: DVec3,
        /// Angle in degrees.
        degrees: f64,
    },
    /// Scale uniformly about the centroid.
    Scale(f64),
}

/// An edit of one cage's vertices.
#[derive(Debug, Clone, PartialEq)]
pub struct CageEdit {
    /// The leaf or internal cage.
    pub cage: String,
    /// What to do to it.
    pub transform: CageTransform,
}

/// Why an edit could not be read or applied.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EditError {
    /// Not of the form `CAGE: OPERATION NUMBERS`.
    #[error(
        "edit '{text}': {reason}; write e.g. \"head: translate 0 0.1 0\", \"head: rotate 0 0 1 30\" \
         or \"head: scale 1.2\""
    )]
    Syntax {
        /// The edit as given.
        text: String,
        /// What is wrong.
        reason: String,
    },
    /// No cage of that name.
    #[error("edit of '{cage}': no cage has that name; the cages are: {known}")]
    UnknownCage {
        /// The name.
        cage: String,
        /// The scene's cage names.
        known: String,
    },
}

impl FromStr for CageEdit {
    type Err = EditError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let syntax = |reason: &str| EditError::Syntax {
            text: text.to_owned(),
            reason: reason.to_owned(),
        };
        let (cage, operation) = text
            .rsplit_once(':')
            .ok_or_else(|| syntax("no ':' after the cage name"))?;
        let cage = cage.trim();
        if cage.is_empty() {
            return Err(syntax("the cage name is empty"));
        }
        let mut words = operation.split_whitespace();
        let verb = words.next().ok_or_else(|| syntax("no operation"))?;
        let numbers = words
            .map(|w| w.parse::<f64>().ok().filter(|x| x.is_finite()))
            .collect::<Option<Vec<f64>>>()
            .ok_or_else(|| syntax("the operation's arguments must be finite numbers"))?;
        let transform = match (verb.to_ascii_lowercase().as_str(), &numbers[..]) {
            ("translate", &[x, y, z]) => CageTransform::Translate(DVec3::new(x, y, z)),
            ("rotate", &[x, y, z, degrees]) if DVec3::new(x, y, z).length() > 0.0 => {
                CageTransform::Rotate {
                    axis: DVec3::new(x, y, z),
                    degrees,
                }
            }
            ("scale", &[s]) => CageTransform::Scale(s),
            ("translate", _) => return Err(syntax("translate takes X Y Z")),
            ("rotate", _) => return Err(syntax("rotate takes a non-zero axis AX AY AZ and DEG")),
            ("scale", _) => return Err(syntax("scale takes one factor S")),
            _ => return Err(syntax("the operation is translate, rotate or scale")),
        };
        Ok(Self {
            cage: cage.to_owned(),
            transform,
        })
    }
}

impl CageTransform {
    /// The image of `p` for a cage with centroid `centre`.
    pub fn apply(&self, p: DVec3, centre: DVec3) -> DVec3 {
        match *self {
            Self::Translate(t) => p + t,
            Self::Rotate { axis, degrees } => {
                centre
                    + DQuat::from_axis_angle(axis.normalize(), degrees.to_radians()) * (p - centre)
            }
            Self::Scale(s) => centre + (p - centre) * s,
        }
    }
}

impl CageEdit {
    /// The hand moves this edit makes in `pose`: every vertex of the cage, transformed about
    /// the centroid of its vertices' current positions.
    pub fn moves(&self, set: &CageSet, pose: &[DVec3]) -> Result<Vec<(u32, DVec3)>, EditError> {
        let vertices = set
            .cage_vertices(&self.cage)
            .ok_or_else(|| EditError::UnknownCage {
                cage: self.cage.clone(),
                known: set.cage_names().join(", "),
            })?;
        let positions: Vec<DVec3> = vertices
            .iter()
            .filter_map(|&v| pose.get(v as usize).copied())
            .collect();
        let centre = set
            .internals
            .iter()
            .find(|c| c.name == self.cage)
            .and_then(|c| posed_pivot(set, c, pose))
            .unwrap_or_else(|| positions.iter().sum::<DVec3>() / positions.len().max(1) as f64);
        Ok(vertices
            .iter()
            .zip(positions)
            .map(|(&v, p)| (v, self.transform.apply(p, centre)))
            .collect())
    }
}

/// Where a control's pivot stands in `pose`: its rest pivot carried by the control's motion
/// from rest (the affine map its vertices moved by). None without a pivot, or for a control
/// flattened into a plane.
pub fn posed_pivot(set: &CageSet, cage: &InternalCage, pose: &[DVec3]) -> Option<DVec3> {
    let pivot = cage.pivot?;
    let vertices = set.cage_vertices(&cage.name)?;
    let rest: Vec<DVec3> = vertices
        .iter()
        .map(|&v| set.vertices.get(v as usize).copied())
        .collect::<Option<_>>()?;
    let now: Vec<DVec3> = vertices
        .iter()
        .map(|&v| pose.get(v as usize).copied())
        .collect::<Option<_>>()?;
    let at = super::affine_fit(&rest, &now)?.transform_point3(pivot);
    at.is_finite().then_some(at)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_three_operations() {
        let e: CageEdit = "ears: rotate 0 0 1 30".parse().unwrap();
        assert_eq!(e.cage, "ears");
        assert_eq!(
            e.transform,
            CageTransform::Rotate {
                axis: DVec3::Z,
                degrees: 30.0
            }
        );
        let e: CageEdit = " head :translate 1 2 3".parse().unwrap();
        assert_eq!(
            (e.cage.as_str(), e.transform),
            ("head", CageTransform::Translate(DVec3::new(1.0, 2.0, 3.0)))
        );
        assert!(matches!(
            "a: scale 2".parse::<CageEdit>().unwrap().transform,
            CageTransform::Scale(2.0)
        ));
        for bad in [
            "head translate 1 2 3",
            "head: move 1",
            "head: scale",
            "head: rotate 0 0 0 5",
            ": scale 2",
            "h: scale NaN",
        ] {
            let error = bad.parse::<CageEdit>().unwrap_err();
            assert!(error.to_string().contains("write e.g."), "{error}");
        }
    }
}

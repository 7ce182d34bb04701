//! Rebuilding followers from a saved [`HierarchyState`](crate::scene::HierarchyState): every
//! recorded point is bound again at its recorded parent shape, one bind per distinct shape.

use std::collections::BTreeMap;
use std::sync::Arc;

use glam::DVec3;

use super::follow::{Anchored, Follow, anchor_points};
use super::{HierarchyError, Level, cage_at};
use crate::coords::BindSettings;
use crate::scene::{AnchorRecord, FollowRecord, ReboundVertex};

/// A shape as exact bit patterns, to group records made at the same parent shape.
type ShapeKey = (usize, Vec<[u64; 3]>);

fn key(level: usize, shape: &[DVec3]) -> ShapeKey {
    (
        level,
        shape
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect(),
    )
}

/// Followers of the `records`, whose vertices sit at `slots` (level, owned slot).
pub(super) fn follows(
    levels: &[Level],
    slots: &[(usize, usize)],
    records: &[ReboundVertex],
    settings: &BindSettings,
) -> Result<Vec<Follow>, HierarchyError> {
    // Every anchor record, grouped by (level, shape).
    let mut groups: BTreeMap<ShapeKey, Vec<(usize, usize)>> = BTreeMap::new();
    let anchors_of = |r: &FollowRecord| -> Vec<AnchorRecord> {
        match r {
            FollowRecord::Coordinates(a) => vec![a.clone()],
            FollowRecord::Lambda { anchor, delta, .. } => vec![anchor.clone(), delta.clone()],
            FollowRecord::Offset { anchor, .. } => vec![anchor.clone()],
        }
    };
    let all: Vec<Vec<AnchorRecord>> = records.iter().map(|r| anchors_of(&r.follow)).collect();
    for (i, anchors) in all.iter().enumerate() {
        let (l, _) = slots[i];
        for (j, a) in anchors.iter().enumerate() {
            let level = &levels[l];
            if a.parent_shape.len() != level.global.len() || !a.point.is_finite() {
                return Err(HierarchyError::BadState {
                    vertex: records[i].vertex,
                    reason: format!(
                        "its record does not fit parent '{}' ({} vertices)",
                        level.name,
                        level.global.len()
                    ),
                });
            }
            groups
                .entry(key(l, &a.parent_shape))
                .or_default()
                .push((i, j));
        }
    }
    let mut bound: Vec<Vec<Option<Anchored>>> = all.iter().map(|a| vec![None; a.len()]).collect();
    for ((l, _), members) in groups {
        let level = &levels[l];
        let (i0, j0) = members[0];
        let shape = &all[i0][j0].parent_shape;
        let vertex = records[i0].vertex;
        let cage = cage_at(level, shape).map_err(|problem| HierarchyError::BadState {
            vertex,
            reason: format!("its recorded parent shape is not a valid cage: {problem}"),
        })?;
        let cage = Arc::new(cage);
        let points: Vec<DVec3> = members.iter().map(|&(i, j)| all[i][j].point).collect();
        let anchored = anchor_points(level.kind, &cage, &points, settings).map_err(|source| {
            HierarchyError::Coordinates {
                cage: level.name.clone(),
                source,
            }
        })?;
        for ((i, j), a) in members.into_iter().zip(anchored) {
            bound[i][j] = Some(a);
        }
    }
    records
        .iter()
        .zip(bound)
        .map(|(record, anchored)| {
            let mut anchored = anchored.into_iter().flatten();
            let mut next = || {
                anchored.next().ok_or_else(|| HierarchyError::BadState {
                    vertex: record.vertex,
                    reason: "incomplete record".into(),
                })
            };
            Ok(match &record.follow {
                FollowRecord::Coordinates(_) => Follow::Coordinates(next()?),
                FollowRecord::Lambda { lambda, .. } => Follow::Lambda {
                    anchor: next()?,
                    delta: next()?,
                    lambda: *lambda,
                },
                FollowRecord::Offset { offset, .. } => Follow::Offset {
                    anchor: next()?,
                    offset: *offset,
                },
            })
        })
        .collect()
}

//! The multi-level part of a pose (section 3.4): which owned cage vertices were moved by hand
//! since their parent last moved, and which follow their parent with coordinates computed at a
//! shape other than the rest shape. Positions alone do not say how a pose reacts to the next
//! parent move; this does, so saving and reopening a scene keeps hand edits alive.

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// How the hierarchy stands in one pose. Empty in the rest pose.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HierarchyState {
    /// Owned vertices moved by hand since their parent cage last moved: their coordinates are
    /// recomputed from their current position when the parent moves next.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hand_moved: Vec<u32>,
    /// Owned vertices whose coordinates were recomputed away from the rest shape.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rebound: Vec<ReboundVertex>,
}

impl HierarchyState {
    /// Whether this is the rest state (nothing moved by hand, nothing re-bound).
    pub fn is_rest(&self) -> bool {
        self.hand_moved.is_empty() && self.rebound.is_empty()
    }
}

/// One owned vertex re-bound to its parent.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReboundVertex {
    /// The owned vertex.
    pub vertex: u32,
    /// How it follows its parent.
    pub follow: FollowRecord,
}

/// A point with the parent cage's shape its coordinates were computed at.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnchorRecord {
    /// The point.
    pub point: DVec3,
    /// The parent cage's vertex positions then, in increasing shared-vertex order.
    pub parent_shape: Vec<DVec3>,
}

/// How an owned vertex follows its parent cage.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum FollowRecord {
    /// Coordinates of the vertex itself: v = T_c(v).
    Coordinates(AnchorRecord),
    /// The λ·ΔU scheme for coordinates undefined outside the cage (HC):
    /// v = T_c(a) + λ (T_c(Δv) − T_c(a)).
    Lambda {
        /// a: where the parent put the vertex before the hand edit.
        anchor: AnchorRecord,
        /// Δv = a + ΔU, inside the parent.
        delta: AnchorRecord,
        /// λ ≥ 1 with U = λ ΔU.
        lambda: f64,
    },
    /// The parent's shape was not a valid cage when the vertex was re-bound: it keeps a
    /// constant offset from its anchor.
    Offset {
        /// Where the parent put the vertex before the hand edit.
        anchor: AnchorRecord,
        /// The hand displacement.
        offset: DVec3,
    },
}

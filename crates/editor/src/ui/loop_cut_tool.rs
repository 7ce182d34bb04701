//! Ctrl+R in Rig mode: the loop cut of the inspected cage, slid with the mouse before it is
//! made, as Blender's. The cut ring is previewed where it would go; the pointer's position
//! along the cage (between its two ends, on screen) sets the fraction, or a typed number does;
//! Enter or a click makes the cut (one rig operation), Esc or a right click drops it.

use glam::{DVec3, Vec2};
use starcages_core::rig::{LoopCutRing, RigOp, loop_cut_ring};

use crate::state::{CageId, EditorState};

/// The fraction is kept this far from either end (a cut at an end would make a flat cage).
const END_MARGIN: f64 = 0.02;

/// A loop cut being placed.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopCutTool {
    /// The cage being cut.
    pub cage: String,
    /// The world axis the cut goes across.
    pub axis: usize,
    /// Where, as a fraction from the start end.
    pub t: f64,
    /// Digits typed, which override the pointer.
    pub typed: String,
    ring: LoopCutRing,
}

impl LoopCutTool {
    /// The cut of the inspected leaf cage across its longest side, at the middle; or why there
    /// is none.
    pub fn begin(state: &EditorState) -> Result<Self, String> {
        let Some(CageId::Leaf(c)) = state.selection.cage() else {
            return Err(
                "Ctrl+R (loop cut): inspect a leaf cage first (click it in the outliner)".into(),
            );
        };
        let scene = &state.doc.scene;
        let cage = scene
            .cages
            .leaves
            .get(c)
            .ok_or("the inspected cage is gone")?;
        let points: Vec<DVec3> = cage
            .faces
            .iter()
            .flatten()
            .filter_map(|&v| scene.cages.vertices.get(v as usize).copied())
            .collect();
        let (lo, hi) = starcages_core::cage::bounds_of(&points);
        let extent = hi - lo;
        let axis = (0..3).fold(0, |best, k| if extent[k] > extent[best] { k } else { best });
        let ring = loop_cut_ring(scene, &cage.name, axis).map_err(|e| e.to_string())?;
        Ok(Self {
            cage: cage.name.clone(),
            axis,
            t: 0.5,
            typed: String::new(),
            ring,
        })
    }

    /// The fraction: the typed number when there is one, otherwise the pointer's position
    /// along the segment between the two ends' centres on screen (`project` gives the pixel
    /// of a world point), kept off the ends.
    pub fn follow(
        &mut self,
        state: &EditorState,
        pointer_in_view: Vec2,
        project: impl Fn(DVec3) -> Option<Vec2>,
    ) {
        if let Ok(typed) = self.typed.parse::<f64>() {
            self.t = typed.clamp(END_MARGIN, 1.0 - END_MARGIN);
            return;
        }
        let rest = &state.doc.scene.cages.vertices;
        let centre = |pick: fn(&(u32, u32)) -> u32| {
            let sum: DVec3 = self
                .ring
                .edges
                .iter()
                .filter_map(|e| rest.get(pick(e) as usize))
                .sum();
            sum / self.ring.edges.len().max(1) as f64
        };
        let (Some(a), Some(b)) = (project(centre(|e| e.0)), project(centre(|e| e.1))) else {
            return;
        };
        let along = b - a;
        if along.length_squared() < 1.0 {
            return;
        }
        let t = f64::from((pointer_in_view - a).dot(along) / along.length_squared());
        self.t = t.clamp(END_MARGIN, 1.0 - END_MARGIN);
    }

    /// The cut ring at the current fraction, in rest positions, in order around the cage.
    pub fn ring_points(&self, state: &EditorState) -> Vec<DVec3> {
        let rest = &state.doc.scene.cages.vertices;
        self.ring
            .edges
            .iter()
            .filter_map(|&(a, b)| {
                let (pa, pb) = (rest.get(a as usize)?, rest.get(b as usize)?);
                Some(pa.lerp(*pb, self.t))
            })
            .collect()
    }

    /// The rig operation that makes the cut, with a fresh name for the new part.
    pub fn operation(&self, state: &EditorState) -> RigOp {
        let taken = state.doc.scene.cages.cage_names();
        let name = (1..)
            .map(|i| format!("{}_{i}", self.cage))
            .find(|n| !taken.contains(&n.as_str()))
            .unwrap_or_default();
        RigOp::Split {
            cage: self.cage.clone(),
            axis: self.axis,
            t: self.t,
            name,
        }
    }

    /// The header over the viewport.
    pub fn header(&self) -> String {
        let typed = if self.typed.is_empty() {
            String::new()
        } else {
            format!("  [typed {}]", self.typed)
        };
        format!(
            "Loop cut '{}' across {}: {:.2} of the way{typed}",
            self.cage,
            ["X", "Y", "Z"][self.axis.min(2)],
            self.t
        )
    }

    /// The status bar's hint.
    pub fn describe(&self) -> String {
        format!(
            "Loop cut at {:.2} — move the mouse along the cage or type a fraction, Enter or click to cut, Esc or right click to cancel",
            self.t
        )
    }
}

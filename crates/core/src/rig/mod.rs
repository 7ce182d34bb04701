//! Building a rig: operations on the rest cages, each a function of the scene that either
//! applies whole or refuses with a reason (the scene is then unchanged). Poses follow rest
//! edits as displacements (a rest move moves every pose by the same amount); new vertices start
//! at rest in every pose. `starcages-cli edit` runs them from a script.
//!
//! One file per operation over a small shared vocabulary (`vocabulary`: errors, face keys,
//! rest moves, lookups); the operations never import each other, only this dispatcher names
//! them all; `op` holds the operations as values and `parse` reads them from text.

mod add_box;
mod delete;
mod extrude;
pub mod fit;
mod import;
mod inset;
mod merge;
mod mirror;
mod op;
mod parse;
mod rest;
mod split;
mod subdivide;
mod vocabulary;
mod weld;

use crate::scene::Scene;

pub use import::import_leaf_cages;
pub use inset::InsetCorners;
pub use op::{FaceRef, RestTransform, RigOp};
pub use parse::{MAX_RIG_SCRIPT_OPS, parse_rig_script};
pub use split::{LoopCutRing, loop_cut_ring};
pub use subdivide::{MAX_SUBDIVIDED_VERTICES, subdivide_leaf_cages};
pub use vocabulary::RigEditError;
pub use weld::{WeldReport, weld_vertices};

/// Applies `op` to `scene`, or refuses with the scene unchanged.
pub fn apply_rig_op(scene: &mut Scene, op: &RigOp) -> Result<(), RigEditError> {
    vocabulary::check_structure(scene)?;
    let mut edited = scene.clone();
    match op {
        RigOp::AddBox {
            name,
            min,
            max,
            kind,
        } => add_box::add_box(&mut edited, name, *min, *max, *kind)?,
        RigOp::Extrude {
            cage,
            face,
            distance,
            name,
        } => extrude::extrude(&mut edited, cage, *face, *distance, name)?,
        RigOp::Inset {
            cage,
            face,
            thickness,
        } => {
            let c = vocabulary::leaf(&edited, cage)?;
            let f = vocabulary::free_face(&edited, c, *face)?;
            inset::inset_face(&mut edited, c, f, *thickness)?;
        }
        RigOp::Delete { cage } => delete::delete(&mut edited, cage)?,
        RigOp::Merge { first, second } => merge::merge(&mut edited, first, second)?,
        RigOp::Split {
            cage,
            axis,
            t,
            name,
        } => split::split(&mut edited, cage, *axis, *t, name)?,
        RigOp::Mirror { cage, name } => mirror::mirror(&mut edited, cage, name)?,
        RigOp::Fit { cage, margin } => {
            let c = vocabulary::leaf(&edited, cage)?;
            fit::fit(&mut edited, c, *margin)?;
        }
        RigOp::Rest { cage, transform } => rest::rest(&mut edited, cage, *transform)?,
        RigOp::Kind { cage, kind } => {
            let c = vocabulary::leaf(&edited, cage)?;
            edited.cages.leaves[c].kind = *kind;
        }
        RigOp::Subdivide => subdivide::subdivide_leaf_cages(&mut edited)?,
        RigOp::Weld { distance } => {
            weld::weld_vertices(&mut edited, *distance, None)?;
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
                let c = vocabulary::leaf(&edited, cage)?;
                edited.cages.leaves[c].h = Some(*h);
            }
        }
    }
    *scene = edited;
    Ok(())
}

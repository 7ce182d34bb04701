//! Moving, turning or scaling a leaf cage's rest positions (poses follow as displacements).

use std::collections::BTreeSet;

use glam::{DQuat, DVec3};

use super::vocabulary::{leaf, move_rest_vertex};
use super::{RestTransform, RigEditError};
use crate::scene::Scene;

pub(crate) fn rest(
    scene: &mut Scene,
    cage: &str,
    transform: RestTransform,
) -> Result<(), RigEditError> {
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

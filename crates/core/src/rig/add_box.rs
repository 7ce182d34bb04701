//! Adding a box cage: its corners shared with existing cage vertices at the same positions.

use glam::DVec3;

use super::RigEditError;
use super::vocabulary::{free_name, vertex_at};
use crate::cage::shapes::box_faces;
use crate::coords::CoordinateKind;
use crate::scene::{LeafCage, Scene};

pub(crate) fn add_box(
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

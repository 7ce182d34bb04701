//! Leaf cages for unit tests of the stages that read only which vertices the cages share and
//! where they are (the limb tree, naming).

use std::collections::BTreeMap;

use glam::DVec3;

use crate::coords::CoordinateKind;
use crate::scene::{CageSet, LeafCage};

/// One leaf cage per point set (a single polygon over its points), points shared by position.
pub(super) fn point_cages(cages: &[Vec<DVec3>]) -> CageSet {
    let mut vertices: Vec<DVec3> = Vec::new();
    let mut leaves = Vec::new();
    for (k, points) in cages.iter().enumerate() {
        let face = points
            .iter()
            .map(|&p| {
                let index = vertices
                    .iter()
                    .position(|q| (*q - p).length() < 1e-9)
                    .unwrap_or_else(|| {
                        vertices.push(p);
                        vertices.len() - 1
                    });
                index as u32
            })
            .collect();
        leaves.push(LeafCage {
            name: format!("cage{k}"),
            kind: CoordinateKind::MeanValue,
            h: None,
            border_h: BTreeMap::new(),
            faces: vec![face],
        });
    }
    CageSet {
        vertices,
        leaves,
        internals: Vec::new(),
    }
}

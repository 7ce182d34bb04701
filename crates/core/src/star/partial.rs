//! Re-binding only what a change affects: a leaf cage's kind, h or per-border h changes only
//! the rows of S of the mesh vertices placed in that cage (T_c and b_c, eqs. 2 and 11; join
//! cages and their weights do not depend on them). Those rows are bound again and spliced into
//! the existing operator; Green face columns are matched by triangle and new ones appended.

use std::time::Instant;

use super::bind::Row;
use super::{GreenDofs, JoinWeights, StarBinding, StarError, StarOperator};
use crate::coords::BindControl;
use crate::scene::Scene;

impl StarBinding {
    /// This binding with the rows of the mesh vertices placed in `leaves` bound again for
    /// `scene` (same mesh and cage geometry; only those cages' kinds, h or border h changed).
    pub fn rebind_leaves(
        &self,
        scene: &Scene,
        leaves: &[usize],
        control: &BindControl,
    ) -> Result<Self, StarError> {
        let start = Instant::now();
        let positions = scene.mesh.welded_positions();
        let rows: Vec<usize> = (0..self.cage_of.len())
            .filter(|&i| leaves.contains(&(self.cage_of[i] as usize)))
            .collect();
        let subset: Vec<_> = rows.iter().map(|&i| positions[i]).collect();
        let part = Self::bind_points(scene, &subset, control)?;
        // Green columns: keep ours, append the part's new triangles.
        let vertex_count = scene.cages.vertices.len() as u32;
        let mut triangles = self.operator.green_dofs().triangles().to_vec();
        let column_of: Vec<u32> = part
            .operator
            .green_dofs()
            .triangles()
            .iter()
            .map(|t| {
                let existing = triangles.iter().position(|u| u == t);
                let index = existing.unwrap_or_else(|| {
                    triangles.push(*t);
                    triangles.len() - 1
                });
                vertex_count + index as u32
            })
            .collect();
        let remap = |c: u32| {
            if c < vertex_count {
                c
            } else {
                column_of[(c - vertex_count) as usize]
            }
        };
        let mut replaced = vec![None; self.cage_of.len()];
        for (k, &i) in rows.iter().enumerate() {
            replaced[i] = Some(k);
        }
        let all_rows: Vec<Row> = (0..self.cage_of.len())
            .map(|i| match replaced[i] {
                Some(k) => part
                    .operator
                    .row(k)
                    .map(|(c, w)| (remap(c), f64::from(w)))
                    .collect(),
                None => self
                    .operator
                    .row(i)
                    .map(|(c, w)| (c, f64::from(w)))
                    .collect(),
            })
            .collect();
        let operator = StarOperator::from_rows(
            &all_rows,
            scene.cages.vertices.len(),
            GreenDofs::from_triangles(triangles),
        );
        let join_rows: Vec<Vec<(u32, f64)>> = (0..self.cage_of.len())
            .map(|i| {
                let (source, r) = match replaced[i] {
                    Some(k) => (&part.join_weights, k),
                    None => (&self.join_weights, i),
                };
                (source.row_start[r] as usize..source.row_start[r + 1] as usize)
                    .map(|e| (source.vertex[e], f64::from(source.weight[e])))
                    .collect()
            })
            .collect();
        let boundary_weight = (0..self.cage_of.len())
            .map(|i| match replaced[i] {
                Some(k) => part.boundary_weight[k],
                None => self.boundary_weight[i],
            })
            .collect();
        let mut stats = self.stats;
        stats.seconds_cage_coordinates = part.stats.seconds_cage_coordinates;
        stats.seconds_join_cages = part.stats.seconds_join_cages;
        stats.seconds_total = start.elapsed().as_secs_f64();
        stats.operator_bytes = operator.byte_size();
        stats.transpose_bytes = operator.transpose_byte_size();
        stats.nonzeros = operator.nonzeros();
        Ok(Self {
            operator,
            boundary_weight,
            cage_of: self.cage_of.clone(),
            join_weights: JoinWeights::from_rows(&join_rows),
            stats,
        })
    }
}

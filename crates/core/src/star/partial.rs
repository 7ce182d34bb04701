//! Re-binding only what a change affects. A leaf cage's kind, h or per-border h changes only
//! the rows of S of the mesh vertices placed in that cage (T_c and b_c, eqs. 2 and 11; join
//! cages and their weights do not depend on them). A rest-pose edit of cage vertices changes
//! the rows of the cages holding them and the rows that read a join cage holding them. Those
//! rows are bound again and spliced into the existing operator; Green face columns are matched
//! by triangle and new ones appended.

use std::collections::BTreeSet;
use std::time::Instant;

use glam::DVec3;

use super::topology::Topology;
use super::{GreenDofs, StarBinding, StarError};
use crate::coords::BindControl;
use crate::scene::ON_CAGE;
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
        let rows: Vec<usize> = (0..self.cage_of.len())
            .filter(|&i| leaves.contains(&(self.cage_of[i] as usize)))
            .collect();
        let topology = Topology::new(&scene.cages, scene.settings.join_coordinates)?;
        self.rebind_rows(scene, &topology, &rows, control)
    }

    /// This binding after a rest-pose edit: `scene` has new rest positions for the cage
    /// vertices `moved` (same mesh, cage topology, kinds and settings). Only the rows that can
    /// change are bound again (section 3: T_c and b depend on the point's own cage, L_v and Ω on
    /// jc(v)): mesh vertices placed in a cage with a moved vertex, or inside its new bounds (they
    /// may change cage), and mesh vertices with b < 1 whose cage has a border vertex v, or an
    /// interior neighbour u of one, whose join cage jc(v) or jc(u) holds a moved vertex. Only
    /// the join cages those rows use are solved. The result equals a full bind of `scene`.
    pub fn rebind_rest_edit(
        &self,
        scene: &Scene,
        moved: &[u32],
        control: &BindControl,
    ) -> Result<Self, StarError> {
        // One topology for finding the rows and binding them (on a rig with subdivided
        // borders it is a fifth of a small edit's time).
        let topology = Topology::new(&scene.cages, scene.settings.join_coordinates)?;
        let rows = self.rows_affected_by(scene, &topology, moved)?;
        self.rebind_rows(scene, &topology, &rows, control)
    }

    /// The rows [`Self::rebind_rest_edit`] binds again, in increasing order.
    pub fn rows_affected_by_rest_edit(
        &self,
        scene: &Scene,
        moved: &[u32],
    ) -> Result<Vec<usize>, StarError> {
        let topology = Topology::new(&scene.cages, scene.settings.join_coordinates)?;
        self.rows_affected_by(scene, &topology, moved)
    }

    /// [`Self::rows_affected_by_rest_edit`] with `scene`'s topology.
    fn rows_affected_by(
        &self,
        scene: &Scene,
        topology: &Topology,
        moved: &[u32],
    ) -> Result<Vec<usize>, StarError> {
        let set = &scene.cages;
        let moved: BTreeSet<u32> = moved.iter().copied().collect();
        let touched_leaves: BTreeSet<usize> = (0..set.leaves.len())
            .filter(|&c| topology.leaves[c].global.iter().any(|v| moved.contains(v)))
            .collect();
        let changed_joins: BTreeSet<u32> = topology
            .joins
            .iter()
            .filter(|(_, join)| join.local.global.iter().any(|v| moved.contains(v)))
            .map(|(&v, _)| v)
            .collect();
        // Cages whose points with b < 1 read a changed join cage.
        let reads_changed_join: Vec<bool> = (0..set.leaves.len())
            .map(|c| {
                topology.boundary[c].iter().any(|v| {
                    changed_joins.contains(v)
                        || topology
                            .interior_neighbours(*v)
                            .any(|u| changed_joins.contains(&u))
                })
            })
            .collect();
        let boxes: Vec<(DVec3, DVec3)> = touched_leaves
            .iter()
            .map(|&c| {
                let cage = &topology.leaves[c].cage;
                let (lo, hi) = cage.bounds();
                let tol = DVec3::splat(ON_CAGE * cage.diagonal());
                (lo - tol, hi + tol)
            })
            .collect();
        let positions = scene.mesh.welded_positions();
        if positions.len() != self.cage_of.len() {
            return Err(StarError::StaleBinding {
                rows: self.cage_of.len(),
                vertices: positions.len(),
            });
        }
        Ok((0..positions.len())
            .filter(|&i| {
                let c = self.cage_of[i] as usize;
                touched_leaves.contains(&c)
                    || (self.boundary_weight[i] < 1.0
                        && reads_changed_join.get(c).copied().unwrap_or(true))
                    || boxes.iter().any(|(lo, hi)| {
                        positions[i].cmpge(*lo).all() && positions[i].cmple(*hi).all()
                    })
            })
            .collect())
    }

    /// This binding with `rows` (increasing mesh vertex indices) bound again for `scene` and
    /// spliced in; every other row is kept bit for bit.
    fn rebind_rows(
        &self,
        scene: &Scene,
        topology: &Topology,
        rows: &[usize],
        control: &BindControl,
    ) -> Result<Self, StarError> {
        let start = Instant::now();
        let positions = scene.mesh.welded_positions();
        let subset: Vec<_> = rows.iter().map(|&i| positions[i]).collect();
        let part = Self::bind_points_with(scene, topology, &subset, control)?;
        let bound = start.elapsed().as_secs_f64();
        // Green columns: keep ours, append the part's new triangles.
        let vertex_count = scene.cages.vertices.len() as u32;
        let mut triangles = self.operator.green_dofs().triangles().to_vec();
        // Our triangles by corners, so each of the part's is matched in log time (a scan per
        // triangle was quadratic in a Green rig's faces).
        let mut index_of = std::collections::BTreeMap::new();
        for (i, t) in triangles.iter().enumerate() {
            index_of.entry(*t).or_insert(i);
        }
        let column_of: Vec<u32> = part
            .operator
            .green_dofs()
            .triangles()
            .iter()
            .map(|t| {
                let index = *index_of.entry(*t).or_insert_with(|| {
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
        let operator = self.operator.splice(
            rows,
            &part.operator,
            remap,
            GreenDofs::from_triangles(triangles),
        );
        let join_weights = self.join_weights.splice(rows, &part.join_weights);
        let boundary_weight = (0..self.cage_of.len())
            .map(|i| match replaced[i] {
                Some(k) => part.boundary_weight[k],
                None => self.boundary_weight[i],
            })
            .collect();
        let cage_of = (0..self.cage_of.len())
            .map(|i| match replaced[i] {
                Some(k) => part.cage_of[k],
                None => self.cage_of[i],
            })
            .collect();
        let mut stats = self.stats;
        stats.seconds_cage_coordinates = part.stats.seconds_cage_coordinates;
        stats.seconds_join_cages = part.stats.seconds_join_cages;
        stats.kernel_pairs = part.stats.kernel_pairs;
        stats.seconds_total = start.elapsed().as_secs_f64();
        stats.seconds_splice = stats.seconds_total - bound;
        stats.operator_bytes = operator.byte_size();
        stats.transpose_bytes = operator.transpose_byte_size();
        stats.nonzeros = operator.nonzeros();
        Ok(Self {
            operator,
            boundary_weight,
            cage_of,
            join_weights,
            stats,
        })
    }
}

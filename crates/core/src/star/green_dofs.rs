//! The Green face degrees of freedom of the compiled operator: every oriented cage triangle
//! that some Green-coordinate cage (leaf or join) uses, and their per-frame values s_t n'_t
//! (Lipman et al.'s stretch times the posed unit normal).

use std::collections::BTreeMap;

use glam::DVec3;

use crate::scene::LocalCage;

/// Registry of oriented triangles (shared vertex indices) used as Green face DOFs.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GreenDofs {
    triangles: Vec<[u32; 3]>,
    index: BTreeMap<[u32; 3], u32>,
}

impl GreenDofs {
    /// The DOF of each triangle of `local` (registering new ones), in its triangle order.
    pub fn register(&mut self, local: &LocalCage) -> Vec<u32> {
        local
            .cage
            .triangles()
            .iter()
            .map(|t| {
                let key = t.map(|v| local.global[v as usize]);
                *self.index.entry(key).or_insert_with(|| {
                    self.triangles.push(key);
                    self.triangles.len() as u32 - 1
                })
            })
            .collect()
    }

    /// A registry from stored triangles (a binding cache).
    pub(crate) fn from_triangles(triangles: Vec<[u32; 3]>) -> Self {
        let index = triangles
            .iter()
            .enumerate()
            .map(|(i, t)| (*t, i as u32))
            .collect();
        Self { triangles, index }
    }

    /// Number of DOFs.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// The oriented triangles, in DOF order.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// s_t n'_t per DOF for the posed vertices (Lipman et al. eq. 13 in 3D; see
    /// [`crate::coords::green_stretch`]).
    pub fn values(&self, rest: &[DVec3], posed: &[DVec3]) -> Vec<DVec3> {
        (0..self.triangles.len())
            .map(|d| self.value(d, rest, posed))
            .collect()
    }

    /// s_t n'_t of DOF `d` alone (see [`GreenDofs::values`]).
    pub fn value(&self, d: usize, rest: &[DVec3], posed: &[DVec3]) -> DVec3 {
        let t = self.triangles[d].map(|v| v as usize);
        let p = t.map(|v| posed[v]);
        let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        normal * crate::coords::triangle_stretch(t.map(|v| rest[v]), p)
    }
}

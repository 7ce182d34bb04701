//! Mean value coordinates of the same points in several cages built from one pool of
//! triangles: each triangle's terms are computed once and summed into every cage that has it.
//!
//! Ju et al.'s weights are sums over triangles of terms that depend only on the point and the
//! triangle (`mvc.rs`): w_i(p) ∝ Σ_{t ∋ i} n_i·m_t / ((x_0 − p)·N_t). A *Cages join cage is the
//! union of leaf cages less their shared faces (eq. 8's jc(v)), so the join cages a leaf cage's
//! points are weighed in are made of that cage's and its neighbours' faces, and the same
//! triangle recurs in several of them. Here each is evaluated once per point and the cages'
//! sums are read off the pool, in each cage's own triangle order: the rows are those of
//! [`super::mvc::MvcRows`] on each cage, bit for bit (the same terms added in the same order,
//! and the same lanes recomputed by the scalar routine).

use std::collections::HashMap;

use glam::DVec3;

use super::lanes::{LANES, Lane, LaneKernel, Vec3Lanes};
use super::mvc::{MvcCageTables, ON_VERTEX, edge_terms, mvc_point, triangle_terms};
use crate::cage::Cage;

/// Triangles of several cages over one numbering of their vertices, each triangle once.
pub(crate) struct TrianglePool {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    /// Per triangle, its edges (corner k to corner k + 1) in `edges`.
    triangle_edges: Vec<[u32; 3]>,
    /// Per edge (a, b), a < b.
    edges: Vec<[u32; 2]>,
    /// Per triangle, its area vector and corner signs (`mvc.rs`'s tables).
    tables: MvcCageTables,
}

/// One cage of a pool: its local vertices and triangles as pool indices.
pub(crate) struct PooledCage<'a> {
    pub cage: &'a Cage,
    /// Local vertex → pool vertex.
    vertex: Vec<u32>,
    /// Local triangle → pool triangle.
    triangle: Vec<u32>,
}

impl TrianglePool {
    /// The pool of `cages`, each given with its local → shared vertex numbering (`global`).
    /// A triangle is the same in two cages when its corners are the same shared vertices in
    /// the same order. The pool numbers the shared vertices in increasing order, so an edge's
    /// lower end is the same in the pool as in every cage (the edge terms depend on it).
    pub(crate) fn new<'a>(cages: &[(&'a Cage, &[u32])]) -> (Self, Vec<PooledCage<'a>>) {
        let mut shared: Vec<u32> = cages.iter().flat_map(|(_, g)| g.iter().copied()).collect();
        shared.sort_unstable();
        shared.dedup();
        let pool_of = |g: u32| shared.binary_search(&g).unwrap_or(0) as u32;
        let mut positions = vec![DVec3::ZERO; shared.len()];
        let mut triangle_of: HashMap<[u32; 3], u32> = HashMap::new();
        let mut triangles = Vec::new();
        let mut pooled = Vec::with_capacity(cages.len());
        for &(cage, global) in cages {
            let vertex: Vec<u32> = global.iter().map(|&g| pool_of(g)).collect();
            for (local, &p) in vertex.iter().enumerate() {
                positions[p as usize] = cage.positions()[local];
            }
            let triangle = cage
                .triangles()
                .iter()
                .map(|t| {
                    let corners = t.map(|k| vertex[k as usize]);
                    *triangle_of.entry(corners).or_insert_with(|| {
                        triangles.push(corners);
                        triangles.len() as u32 - 1
                    })
                })
                .collect();
            pooled.push(PooledCage {
                cage,
                vertex,
                triangle,
            });
        }
        let mut edge_of: HashMap<[u32; 2], u32> = HashMap::new();
        let mut edges = Vec::new();
        let triangle_edges = triangles
            .iter()
            .map(|t| {
                std::array::from_fn(|k| {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    let key = [a.min(b), a.max(b)];
                    *edge_of.entry(key).or_insert_with(|| {
                        edges.push(key);
                        edges.len() as u32 - 1
                    })
                })
            })
            .collect();
        let tables = MvcCageTables::of_triangles(&positions, &triangles);
        let pool = Self {
            positions,
            triangles,
            triangle_edges,
            edges,
            tables,
        };
        (pool, pooled)
    }

    /// Triangles in the pool (each evaluated once per point).
    pub(crate) fn triangle_count(&self) -> usize {
        self.triangles.len()
    }
}

/// MVC of `points` in every cage of a pool: `rows[c]` receives cage c's rows, row-major
/// (`points.len()` rows of its vertex count).
pub(crate) struct MvcPoolRows<'a, 'r> {
    pub pool: &'a TrianglePool,
    pub cages: &'a [PooledCage<'a>],
    pub points: &'a [DVec3],
    pub rows: &'r mut [Vec<f64>],
}

/// Per-pool-triangle terms of [`LANES`] points.
struct Terms<L> {
    w: Vec<[L; 3]>,
    /// Lanes that met a special case at the triangle.
    special: Vec<u32>,
}

impl LaneKernel for MvcPoolRows<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn run<L: Lane>(self) {
        let pool = self.pool;
        let one = L::splat(1.0);
        let mut offset: Vec<Vec3Lanes<L>> = Vec::with_capacity(pool.positions.len());
        let mut dist: Vec<L> = Vec::with_capacity(pool.positions.len());
        let mut inv_dist: Vec<L> = Vec::with_capacity(pool.positions.len());
        let mut edge: Vec<([L; 2], Vec3Lanes<L>)> = Vec::with_capacity(pool.edges.len());
        let mut terms = Terms::<L> {
            w: Vec::with_capacity(pool.triangles.len()),
            special: Vec::with_capacity(pool.triangles.len()),
        };
        let mut weights: Vec<L> = Vec::new();
        let mut scalar = super::mvc::MvcScratch::default();
        for (group, first) in self.points.chunks(LANES).zip((0..).step_by(LANES)) {
            let p: [DVec3; LANES] = std::array::from_fn(|l| group[l.min(group.len() - 1)]);
            offset.clear();
            dist.clear();
            inv_dist.clear();
            for &x in &pool.positions {
                let v = Vec3Lanes::<L>::from_minus(x, &p);
                let d = v.dot(&v).sqrt();
                offset.push(v);
                dist.push(d);
                inv_dist.push(one / d);
            }
            // The edges and triangles as `mvc_points4` computes them (see there).
            edge.clear();
            for &[a, b] in &pool.edges {
                let (a, b) = (a as usize, b as usize);
                let e = pool.positions[b] - pool.positions[a];
                edge.push(edge_terms(&offset[a], &offset[b], e));
            }
            terms.w.clear();
            terms.special.clear();
            for (t, (tri, edges)) in pool.triangles.iter().zip(&pool.triangle_edges).enumerate() {
                let idx = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
                let (area, sign) = pool.tables.of(t);
                let (w, irregular) = triangle_terms(
                    idx,
                    [
                        edge[edges[1] as usize],
                        edge[edges[2] as usize],
                        edge[edges[0] as usize],
                    ],
                    sign,
                    area,
                    &offset,
                    &inv_dist,
                );
                terms.w.push(w);
                terms.special.push(irregular);
            }
            // Each cage's sums, in its own triangle order (as `mvc_points4` adds them).
            for (cage, rows) in self.cages.iter().zip(self.rows.iter_mut()) {
                let n = cage.cage.vertex_count();
                let on_vertex = L::splat(ON_VERTEX * cage.cage.diagonal());
                let mut special = 0u32;
                for &v in &cage.vertex {
                    special |= L::bitmask(dist[v as usize].lt(on_vertex));
                }
                weights.clear();
                weights.resize(n, L::zero());
                let mut total = L::zero();
                for (tri, &t) in cage.cage.triangles().iter().zip(&cage.triangle) {
                    let [w0, w1, w2] = terms.w[t as usize];
                    special |= terms.special[t as usize];
                    weights[tri[0] as usize] += w0;
                    weights[tri[1] as usize] += w1;
                    weights[tri[2] as usize] += w2;
                    total += w0 + w1 + w2;
                }
                let total = total.to_array();
                let scale: [f64; LANES] = std::array::from_fn(|l| 1.0 / total[l]);
                let block = &mut rows[first * n..(first + group.len()) * n];
                for (i, acc) in weights.iter().enumerate() {
                    let acc = acc.to_array();
                    for l in 0..group.len() {
                        block[l * n + i] = acc[l] * scale[l];
                    }
                }
                for (l, row) in block.chunks_mut(n.max(1)).enumerate() {
                    if special & (1 << l) != 0 || total[l] == 0.0 || !total[l].is_finite() {
                        mvc_point(cage.cage, p[l], row, &mut scalar);
                    }
                }
            }
        }
    }
}

/// MVC of `points` in each of `cages` (each with its local → shared vertex numbering), the
/// triangles they share evaluated once per point: per cage, its weights (as
/// [`super::bind`] gives them for MVC, bit for bit). The points must lie within
/// [`super::MVC_RANGE_IN_DIAGONALS`] of every cage (*Cages: points inside a leaf cage that
/// each join cage holds). Chunks of points run in parallel; `control` can cancel them and
/// counts the point·triangle pairs of the pool.
pub(crate) fn bind_mean_value_pooled(
    cages: &[(&Cage, &[u32])],
    points: &[DVec3],
    control: &super::BindControl,
) -> Result<Vec<super::VertexWeights>, super::CoordError> {
    use rayon::prelude::*;
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(super::CoordError::NonFinitePoint { index });
    }
    let (pool, pooled) = TrianglePool::new(cages);
    control.add_kernel_pairs(points.len() as u64 * pool.triangle_count() as u64);
    // Each chunk's rows per cage, then each cage's rows end to end.
    let chunks: Vec<Vec<Vec<f64>>> = points
        .par_chunks(CHUNK)
        .map(|chunk| {
            control.check()?;
            let mut rows: Vec<Vec<f64>> = pooled
                .iter()
                .map(|c| vec![0.0; chunk.len() * c.cage.vertex_count()])
                .collect();
            super::lanes::run_kernel(MvcPoolRows {
                pool: &pool,
                cages: &pooled,
                points: chunk,
                rows: &mut rows,
            });
            Ok(rows)
        })
        .collect::<Result<_, super::CoordError>>()?;
    Ok(pooled
        .iter()
        .enumerate()
        .map(|(c, cage)| {
            let n = cage.cage.vertex_count();
            let mut weights = Vec::with_capacity(points.len() * n);
            for chunk in &chunks {
                weights.extend_from_slice(&chunk[c]);
            }
            super::VertexWeights {
                vertex_count: n,
                weights,
            }
        })
        .collect())
}

/// Points per parallel task (a multiple of [`LANES`]).
const CHUNK: usize = 64;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::shapes;
    use crate::coords::lanes::run_every_backend;
    use crate::coords::mvc::MvcRows;

    /// Both kernels on the same cages and points, with one backend.
    #[derive(Clone)]
    struct Both<'a> {
        cages: &'a [(Cage, Vec<u32>)],
        points: &'a [DVec3],
    }

    impl LaneKernel for Both<'_> {
        type Output = (Vec<Vec<f64>>, Vec<Vec<f64>>);
        fn run<L: Lane>(self) -> Self::Output {
            let listed: Vec<(&Cage, &[u32])> =
                self.cages.iter().map(|(c, g)| (c, g.as_slice())).collect();
            let (pool, pooled) = TrianglePool::new(&listed);
            let mut pooled_rows: Vec<Vec<f64>> = self
                .cages
                .iter()
                .map(|(c, _)| vec![0.0; self.points.len() * c.vertex_count()])
                .collect();
            MvcPoolRows {
                pool: &pool,
                cages: &pooled,
                points: self.points,
                rows: &mut pooled_rows,
            }
            .run::<L>();
            let alone = self
                .cages
                .iter()
                .map(|(cage, _)| {
                    let mut rows = vec![0.0; self.points.len() * cage.vertex_count()];
                    MvcRows {
                        cage,
                        points: self.points,
                        rows: &mut rows,
                    }
                    .run::<L>();
                    rows
                })
                .collect();
            (pooled_rows, alone)
        }
    }

    /// Two boxes side by side and their union (the shared face left out), as a *Cages rig's
    /// leaf and join cages are: every cage's rows from the pool are its rows alone, bit for
    /// bit, on every backend, at regular points, on a vertex, on a face, on the shared face
    /// and outside, with a last partial group of lanes.
    #[test]
    fn pooled_rows_are_each_cages_own_bit_for_bit() {
        let corners: Vec<DVec3> = (0..12)
            .map(|i| DVec3::new((i % 3) as f64, ((i / 3) % 2) as f64, (i / 6) as f64))
            .collect();
        let id = |x: u32, y: u32, z: u32| x + 3 * y + 6 * z;
        let box_at = |x: u32| {
            shapes::box_faces(std::array::from_fn(|c| {
                let c = c as u32;
                id(x + (c & 1), (c >> 1) & 1, c >> 2)
            }))
        };
        let (left, right) = (box_at(0), box_at(1));
        let key = |f: &Vec<u32>| {
            let mut k = f.clone();
            k.sort_unstable();
            k
        };
        let shared: Vec<Vec<u32>> = left
            .iter()
            .filter(|f| right.iter().any(|g| key(g) == key(f)))
            .map(key)
            .collect();
        let union: Vec<Vec<u32>> = left
            .iter()
            .chain(&right)
            .filter(|f| !shared.contains(&key(f)))
            .cloned()
            .collect();
        let cages: Vec<(Cage, Vec<u32>)> = [left, right, union]
            .iter()
            .map(|faces| {
                let local = crate::scene::LocalCage::new(&corners, faces).unwrap();
                (local.cage, local.global)
            })
            .collect();
        let points = [
            DVec3::new(0.3, 0.4, 0.6),
            DVec3::new(0.9, 0.5, 0.5),
            DVec3::new(1.0, 0.3, 0.7), // on the shared face
            corners[4],                // on a vertex
            DVec3::new(0.5, 0.0, 0.5), // on an outer face
            DVec3::new(1.7, 0.2, 0.1),
            DVec3::new(3.0, 2.0, -1.0), // outside
        ];
        for (backend, (pooled, alone)) in run_every_backend(Both {
            cages: &cages,
            points: &points,
        }) {
            for (c, (a, b)) in pooled.iter().zip(&alone).enumerate() {
                assert_eq!(a.len(), b.len());
                for (k, (x, y)) in a.iter().zip(b).enumerate() {
                    assert_eq!(x.to_bits(), y.to_bits(), "{backend}, cage {c}, entry {k}");
                }
            }
        }
    }
}

//! Mean Value Coordinates for closed triangle meshes (Ju, Schaefer & Warren 2005, "Mean value
//! coordinates for closed triangular meshes", the robust pseudocode of their Fig. 4).
//!
//! Defined inside and outside the cage. Special cases handled exactly: a point on a vertex
//! (that vertex's weight is 1), on a face or an edge (barycentric coordinates of that triangle,
//! which on an edge reduce to linear interpolation), and coplanar triangles (no contribution).
//!
//! Speed and accuracy: the mean vector form of the same formula (Ju et al. §3: the mean vector
//! m = ½ Σ θ_j n_j of a spherical triangle split as w_i = n_i·m / (n_i·p_i)), with every quantity
//! computed from differences of cage positions rather than from unit vectors seen from the point.
//! n_j, the normal of the plane through the point and a cage *edge*, is (x_a − p) × (x_b − x_a);
//! θ_j is the atan2 of its length and (x_a − p)·(x_b − p); n_i·p_i is the triple product
//! (x_0 − p)·N with the face's area vector N. Nothing then cancels except what the geometry
//! cancels, so the weights stay accurate far from the cage: 3e-11 of the distance at 100 cage
//! diagonals, where the textbook form (unit vectors, cosine rule) is off by 1e-5 to 1e-1
//! (`docs/math.md`). Each edge's θ and n are computed once per point and shared by the two
//! triangles on that edge.

use glam::DVec3;

use super::lanes::{ALL_LANES, LANES, Lane, LaneKernel, Vec3Lanes, math};
use crate::cage::Cage;

/// Relative distance (to the cage diagonal) under which a point is on a vertex.
pub(crate) const ON_VERTEX: f64 = 1e-12;
/// Threshold on sin θ and on the sine of the spherical angles (both scale-free) under which the
/// point is on the line of an edge or in the plane of a triangle: on it (barycentric
/// coordinates) or outside it (no contribution), Ju et al. Fig. 4.
const COPLANAR: f64 = 1e-12;

/// Per cage triangle, what does not depend on the point: its area vector (x_1 − x_0) × (x_2 − x_0)
/// and, per corner i, the sign that turns the stored normal of the opposite edge (computed for
/// the edge's lower-numbered end first) into the normal for the triangle's own direction
/// i+1 → i+2.
#[derive(Debug, Clone, Default)]
pub(crate) struct MvcCageTables {
    area: Vec<DVec3>,
    sign: Vec<[f64; 3]>,
}

impl MvcCageTables {
    pub(crate) fn new(cage: &Cage) -> Self {
        Self::of_triangles(cage.positions(), cage.triangles())
    }

    /// The tables of `triangles` over `x` (a cage's, or a pool's shared by several cages).
    pub(crate) fn of_triangles(x: &[DVec3], triangles: &[[u32; 3]]) -> Self {
        let area = triangles
            .iter()
            .map(|t| {
                (x[t[1] as usize] - x[t[0] as usize]).cross(x[t[2] as usize] - x[t[0] as usize])
            })
            .collect();
        let sign = triangles
            .iter()
            .map(|t| {
                std::array::from_fn(|i| {
                    if t[(i + 1) % 3] < t[(i + 2) % 3] {
                        1.0
                    } else {
                        -1.0
                    }
                })
            })
            .collect();
        Self { area, sign }
    }

    /// Triangle t's area vector (x_1 − x_0) × (x_2 − x_0) and corner signs.
    pub(crate) fn of(&self, t: usize) -> (DVec3, [f64; 3]) {
        (self.area[t], self.sign[t])
    }
}

/// Reusable per-thread buffers of one MVC evaluation.
#[derive(Debug, Default, Clone)]
pub(crate) struct MvcScratch {
    /// x_i − p.
    offset: Vec<DVec3>,
    dist: Vec<f64>,
    /// Per edge (a, b), a < b: θ, |(x_a − p) × (x_b − p)| and its unit vector.
    edge: Vec<(f64, f64, DVec3)>,
}

/// Writes the mean value coordinates of `p` with respect to `cage` into `out`
/// (`out.len() == cage.vertex_count()`); they sum to 1 and reproduce `p` (eq. 1 of *Cages).
pub(crate) fn mvc_point(cage: &Cage, p: DVec3, out: &mut [f64], scratch: &mut MvcScratch) {
    let positions = cage.positions();
    let n = positions.len();
    out.fill(0.0);
    scratch.offset.resize(n, DVec3::ZERO);
    scratch.dist.resize(n, 0.0);
    let on_vertex = ON_VERTEX * cage.diagonal();
    for (i, &x) in positions.iter().enumerate() {
        let v = x - p;
        let d = v.length();
        if d < on_vertex {
            out[i] = 1.0;
            return;
        }
        scratch.offset[i] = v;
        scratch.dist[i] = d;
    }
    let (offset, dist) = (&scratch.offset, &scratch.dist);
    scratch.edge.clear();
    scratch.edge.extend(cage.edges().iter().map(|&[a, b]| {
        let (a, b) = (a as usize, b as usize);
        let normal = offset[a].cross(positions[b] - positions[a]);
        let length = normal.length();
        let theta = length.atan2(offset[a].dot(offset[b]));
        (theta, length, normal / length)
    }));
    let edge = &scratch.edge;
    let mut total = 0.0;
    let tables = MvcCageTables::new(cage);
    for (t, (tri, edges)) in cage
        .triangles()
        .iter()
        .zip(cage.triangle_edges())
        .enumerate()
    {
        let idx = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        // Corner i's opposite edge (i+1, i+2) is edges[(i + 1) % 3].
        let e = [
            edge[edges[1] as usize],
            edge[edges[2] as usize],
            edge[edges[0] as usize],
        ];
        let sin_th: [f64; 3] =
            std::array::from_fn(|i| e[i].1 / (dist[idx[(i + 1) % 3]] * dist[idx[(i + 2) % 3]]));
        let (area, sign) = (tables.area[t], tables.sign[t]);
        let normal: [DVec3; 3] = std::array::from_fn(|i| e[i].2 * sign[i]);
        // cos of the spherical angle at u_i: the planes through p and the edges at x_i meet
        // there at A_i, and their inward normals at π − A_i.
        let cos_a: [f64; 3] =
            std::array::from_fn(|i| -normal[(i + 1) % 3].dot(normal[(i + 2) % 3]));
        if let Some(k) = (0..3).find(|&k| sin_th[k] < COPLANAR) {
            if e[k].0 > std::f64::consts::FRAC_PI_2 {
                // Two corners on opposite sides of p: p lies on an edge of this triangle.
                barycentric(idx, [e[0].1, e[1].1, e[2].1], out);
                return;
            }
            continue; // p on the line of an edge, outside it: degenerate, contributes 0
        }
        // n_i·p_i = (x_i − p)·((x_{i+1} − p) × (x_{i+2} − p)) / |…| = (x_0 − p)·N / |…|.
        let triple = offset[idx[0]].dot(area);
        let det = triple / (dist[idx[0]] * dist[idx[1]] * dist[idx[2]]);
        // sin A_i = det / (sin θ_{i+1} sin θ_{i+2}) (sine rule); the smallest flags a plane.
        let s_min = det.abs() * sin_th[0].min(sin_th[1]).min(sin_th[2])
            / (sin_th[0] * sin_th[1] * sin_th[2]);
        if s_min <= COPLANAR {
            if cos_a.iter().all(|&c| c < 0.0) {
                // Every spherical angle near π: p lies on this triangle (Ju et al.'s π − h < ε).
                barycentric(idx, [e[0].1, e[1].1, e[2].1], out);
                return;
            }
            continue; // p in the plane of the triangle, outside it: no contribution
        }
        // w_i = n_i·m / (n_i·p_i), m = ½ Σ_j θ_j n_j (Ju et al. §3; the MVC of *Cages eq. 1).
        // m as a vector, not through the cosines n_i·n_j: the λ_i then decompose the computed m
        // exactly (Σ λ_i p_i = m), so a face seen edge-on, whose n_i·p_i is tiny, does not
        // magnify rounding into the reproduced point.
        let m = 0.5 * (e[0].0 * normal[0] + e[1].0 * normal[1] + e[2].0 * normal[2]);
        let inv_triple = 1.0 / triple;
        for i in 0..3 {
            let w = normal[i].dot(m) * e[i].1 * inv_triple;
            out[idx[i]] += w;
            total += w;
        }
    }
    if total != 0.0 && total.is_finite() {
        let inv = 1.0 / total;
        out.iter_mut().for_each(|w| *w *= inv);
    }
}

/// p on triangle `idx`: 2D barycentric coordinates, w_i ∝ sin θ_i d_{i+1} d_{i+2} =
/// |(x_{i+1} − p) × (x_{i+2} − p)| (Ju et al. Fig. 4), from those lengths.
fn barycentric(idx: [usize; 3], opposite_cross: [f64; 3], out: &mut [f64]) {
    let sum = opposite_cross[0] + opposite_cross[1] + opposite_cross[2];
    out.fill(0.0);
    for k in 0..3 {
        out[idx[k]] = opposite_cross[k] / sum;
    }
}

/// Reusable buffers of a multi-point MVC evaluation.
#[derive(Debug, Clone)]
pub(crate) struct MvcLanesScratch<L> {
    /// x_i − p.
    offset: Vec<Vec3Lanes<L>>,
    inv_dist: Vec<L>,
    /// Per edge (a, b), a < b: θ / |n| and |n| for n = (x_a − p) × (x_b − p), and n.
    edge: Vec<([L; 2], Vec3Lanes<L>)>,
    weights: Vec<L>,
    scalar: MvcScratch,
}

impl<L> Default for MvcLanesScratch<L> {
    fn default() -> Self {
        Self {
            offset: Vec::new(),
            inv_dist: Vec::new(),
            edge: Vec::new(),
            weights: Vec::new(),
            scalar: MvcScratch::default(),
        }
    }
}

/// MVC of a run of points into their rows (`points.len()` rows of `cage.vertex_count()`
/// weights), [`LANES`] points at a time with the best SIMD backend.
pub(crate) struct MvcRows<'a> {
    /// The cage.
    pub cage: &'a Cage,
    /// The points.
    pub points: &'a [DVec3],
    /// Their rows, row-major.
    pub rows: &'a mut [f64],
}

impl LaneKernel for MvcRows<'_> {
    type Output = ();

    #[inline(always)]
    fn run<L: Lane>(self) {
        let n = self.cage.vertex_count();
        let tables = MvcCageTables::new(self.cage);
        let mut scratch = MvcLanesScratch::<L>::default();
        let mut padded = Vec::new();
        let groups = self
            .rows
            .chunks_mut(LANES * n.max(1))
            .zip(self.points.chunks(LANES));
        for (rows, group) in groups {
            let lane_points = std::array::from_fn(|l| group[l.min(group.len() - 1)]);
            if group.len() == LANES {
                mvc_points4(self.cage, &tables, lane_points, rows, &mut scratch);
            } else {
                padded.resize(LANES * n, 0.0);
                mvc_points4(self.cage, &tables, lane_points, &mut padded, &mut scratch);
                rows.copy_from_slice(&padded[..rows.len()]);
            }
        }
    }
}

/// MVC of LANES points at once into `rows` (LANES rows of `cage.vertex_count()` weights), with
/// the formulas of [`mvc_point`] in SIMD lanes. Lanes that meet a special case (a point on a
/// vertex, an edge's line or a face's plane) are recomputed by [`mvc_point`].
#[inline(always)]
pub(crate) fn mvc_points4<L: Lane>(
    cage: &Cage,
    tables: &MvcCageTables,
    p: [DVec3; LANES],
    rows: &mut [f64],
    scratch: &mut MvcLanesScratch<L>,
) {
    let positions = cage.positions();
    let n = positions.len();
    let on_vertex = L::splat(ON_VERTEX * cage.diagonal());
    let one = L::splat(1.0);
    let mut special = 0u32;
    scratch.offset.clear();
    scratch.inv_dist.clear();
    for &x in positions {
        let v = Vec3Lanes::<L>::from_minus(x, &p);
        let d = v.dot(&v).sqrt();
        special |= L::bitmask(d.lt(on_vertex));
        scratch.offset.push(v);
        scratch.inv_dist.push(one / d);
    }
    let offset = &scratch.offset;
    scratch.edge.clear();
    // A loop, not a closure: the kernel must be one function for `#[target_feature]`.
    for &[a, b] in cage.edges() {
        let (a, b) = (a as usize, b as usize);
        scratch.edge.push(edge_terms(
            &offset[a],
            &offset[b],
            positions[b] - positions[a],
        ));
    }
    let edge = &scratch.edge;
    let inv_dist = &scratch.inv_dist;
    scratch.weights.clear();
    scratch.weights.resize(n, L::zero());
    let weights = &mut scratch.weights;
    let mut total = L::zero();
    let triangles = cage.triangles().iter().zip(cage.triangle_edges());
    for (t, (tri, edges)) in triangles.enumerate() {
        let idx = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        let ([w0, w1, w2], irregular) = triangle_terms(
            idx,
            [
                edge[edges[1] as usize],
                edge[edges[2] as usize],
                edge[edges[0] as usize],
            ],
            tables.sign[t],
            tables.area[t],
            offset,
            inv_dist,
        );
        special |= irregular;
        weights[idx[0]] += w0;
        weights[idx[1]] += w1;
        weights[idx[2]] += w2;
        total += w0 + w1 + w2;
    }
    let total = total.to_array();
    let scale: [f64; LANES] = std::array::from_fn(|l| 1.0 / total[l]);
    for (i, acc) in weights.iter().enumerate() {
        let acc = acc.to_array();
        for l in 0..LANES {
            rows[l * n + i] = acc[l] * scale[l];
        }
    }
    for (l, row) in rows.chunks_mut(n).enumerate().take(LANES) {
        if special & (1 << l) != 0 || total[l] == 0.0 || !total[l].is_finite() {
            mvc_point(cage, p[l], row, &mut scratch.scalar);
        }
    }
}

/// The per-point terms of edge (a, b), a < b (`va`, `vb`: x_a − p and x_b − p per lane, `e`:
/// x_b − x_a): θ / |n| and |n| for n = (x_a − p) × (x_b − x_a), and n.
#[inline(always)]
pub(crate) fn edge_terms<L: Lane>(
    va: &Vec3Lanes<L>,
    vb: &Vec3Lanes<L>,
    e: DVec3,
) -> ([L; 2], Vec3Lanes<L>) {
    // (x_a − p) × (x_b − x_a): the edge vector is exact, so the normal keeps its digits
    // however far p is (see mvc_point).
    let normal = Vec3Lanes {
        x: va.y.mul_sub(L::splat(e.z), va.z * L::splat(e.y)),
        y: va.z.mul_sub(L::splat(e.x), va.x * L::splat(e.z)),
        z: va.x.mul_sub(L::splat(e.y), va.y * L::splat(e.x)),
    };
    let length = normal.dot(&normal).sqrt();
    let theta = math::atan2(length, va.dot(vb));
    // θ / |n| with n unnormalised: m = ½ Σ θ_j n_j / |n_j| and w_i = n_i·m / triple.
    ([theta / length, length], normal)
}

/// One triangle's unnormalised weights of its corners `idx` per lane, from the terms of the
/// edges opposite each corner (`opposite[i]`: edge (i+1, i+2)), its corner signs and area
/// vector; and the lanes that meet a special case there (on an edge's line or in its plane:
/// recomputed by [`mvc_point`]).
#[inline(always)]
pub(crate) fn triangle_terms<L: Lane>(
    idx: [usize; 3],
    opposite: [([L; 2], Vec3Lanes<L>); 3],
    sign: [f64; 3],
    area: DVec3,
    offset: &[Vec3Lanes<L>],
    inv_dist: &[L],
) -> ([L; 3], u32) {
    let one = L::splat(1.0);
    let coplanar = L::splat(COPLANAR);
    let [([th0, len0], n0), ([th1, len1], n1), ([th2, len2], n2)] = opposite;
    // The triangle's own edge directions: n_i = sign_i × the stored normal.
    let (g0, g1, g2) = (
        L::splat(0.5 * sign[0]) * th0,
        L::splat(0.5 * sign[1]) * th1,
        L::splat(0.5 * sign[2]) * th2,
    );
    // m = ½ Σ θ_j n̂_j as a vector (see mvc_point).
    let m = Vec3Lanes {
        x: g0.mul_add(n0.x, g1.mul_add(n1.x, g2 * n2.x)),
        y: g0.mul_add(n0.y, g1.mul_add(n1.y, g2 * n2.y)),
        z: g0.mul_add(n0.z, g1.mul_add(n1.z, g2 * n2.z)),
    };
    let triple = offset[idx[0]].dot_splat(area);
    let inv_triple = one / triple;
    // w_i = n̂_i·m / (n̂_i·p_i) = n_i·m / triple, n_i = (x_{i+1} − p) × (x_{i+2} − p).
    let w0 = n0.dot(&m) * L::splat(sign[0]) * inv_triple;
    let w1 = n1.dot(&m) * L::splat(sign[1]) * inv_triple;
    let w2 = n2.dot(&m) * L::splat(sign[2]) * inv_triple;
    // The scale-free tests of mvc_point: sin θ_i and the smallest sin A_i.
    let (d0, d1, d2) = (inv_dist[idx[0]], inv_dist[idx[1]], inv_dist[idx[2]]);
    let s0 = len0 * d1 * d2;
    let s1 = len1 * d2 * d0;
    let s2 = len2 * d0 * d1;
    let s_min = s0.min(s1).min(s2);
    let det = triple * d0 * d1 * d2;
    // Regular where both tests hold; NaN fails them, so it flags the lane too.
    let regular = s_min.ge(coplanar) & (det.abs() * s_min / (s0 * s1 * s2)).gt(coplanar);
    ([w0, w1, w2], !L::bitmask(regular) & ALL_LANES)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::shapes;

    /// The lane kernel on `points`, with one backend.
    #[derive(Clone)]
    struct Rows<'a>(&'a Cage, &'a [DVec3]);

    impl LaneKernel for Rows<'_> {
        type Output = Vec<f64>;
        fn run<L: Lane>(self) -> Vec<f64> {
            let mut rows = vec![0.0; self.1.len() * self.0.vertex_count()];
            MvcRows {
                cage: self.0,
                points: self.1,
                rows: &mut rows,
            }
            .run::<L>();
            rows
        }
    }

    #[test]
    fn lane_kernel_matches_scalar_routine_on_every_backend() {
        let cage = shapes::star_prism();
        // Regular points, a vertex, a face, a point outside, and a last partial group.
        let points = [
            DVec3::new(0.1, 0.2, 0.0),
            DVec3::new(-0.3, 0.1, 0.3),
            DVec3::new(0.0, -0.2, -0.1),
            DVec3::new(0.2, 0.0, 0.4),
            cage.positions()[3],
            DVec3::new(0.0, 0.0, 0.5),
            DVec3::new(3.0, 0.0, 0.5),
            DVec3::new(0.05, 0.05, 0.05),
            DVec3::new(-0.05, 0.15, -0.45),
        ];
        let n = cage.vertex_count();
        let mut scalar = MvcScratch::default();
        for (backend, rows) in crate::coords::lanes::run_every_backend(Rows(&cage, &points)) {
            for (i, p) in points.iter().enumerate() {
                let mut expected = vec![0.0; n];
                mvc_point(&cage, *p, &mut expected, &mut scalar);
                for (a, b) in rows[i * n..(i + 1) * n].iter().zip(&expected) {
                    assert!(
                        (a - b).abs() < 1e-12,
                        "{backend}, point {i} at {p}: {a} vs {b}"
                    );
                }
            }
        }
    }
}

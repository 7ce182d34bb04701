//! Mean Value Coordinates for closed triangle meshes (Ju, Schaefer & Warren 2005, "Mean value
//! coordinates for closed triangular meshes", the robust pseudocode of their Fig. 4).
//!
//! Defined inside and outside the cage. Special cases handled exactly: a point on a vertex
//! (that vertex's weight is 1), on a face or an edge (barycentric coordinates of that triangle,
//! which on an edge reduce to linear interpolation), and coplanar triangles (no contribution).
//!
//! Speed and accuracy: every angle θ of the spherical triangles belongs to a cage *edge*, so
//! it is computed once per edge and shared by the two triangles on that edge. The paper's
//! c_i (cosine of the spherical angle A_i) comes from the cosine rule and s_i = sign(det) sin A_i
//! from the sine rule, so no `sin` is called per face and, unlike sqrt(1 − c_i²), s_i keeps
//! full relative precision next to the cage's faces.

use glam::DVec3;

use super::lanes::{ALL_LANES, LANES, Lane, LaneKernel, Vec3Lanes, math};
use crate::cage::Cage;

/// Relative distance (to the cage diagonal) under which a point is on a vertex.
const ON_VERTEX: f64 = 1e-12;
/// Threshold on |s_i| and sin θ_i (both scale-free) under which the point is in the plane of
/// a triangle: on it (barycentric coordinates) or outside it (no contribution), Ju et al. Fig. 4.
const COPLANAR: f64 = 1e-12;

/// Reusable per-thread buffers of one MVC evaluation.
#[derive(Debug, Default, Clone)]
pub(crate) struct MvcScratch {
    unit: Vec<DVec3>,
    dist: Vec<f64>,
    inv_dist: Vec<f64>,
    /// Per edge: θ, sin(θ/2), cos(θ/2).
    theta: Vec<[f64; 3]>,
}

/// Writes the mean value coordinates of `p` with respect to `cage` into `out`
/// (`out.len() == cage.vertex_count()`); they sum to 1 and reproduce `p` (eq. 1 of *Cages).
pub(crate) fn mvc_point(cage: &Cage, p: DVec3, out: &mut [f64], scratch: &mut MvcScratch) {
    let positions = cage.positions();
    let n = positions.len();
    out.fill(0.0);
    scratch.unit.resize(n, DVec3::ZERO);
    scratch.dist.resize(n, 0.0);
    scratch.inv_dist.resize(n, 0.0);
    let on_vertex = ON_VERTEX * cage.diagonal();
    for (i, &x) in positions.iter().enumerate() {
        let v = x - p;
        let d = v.length();
        if d < on_vertex {
            out[i] = 1.0;
            return;
        }
        let inv = 1.0 / d;
        scratch.dist[i] = d;
        scratch.inv_dist[i] = inv;
        scratch.unit[i] = v * inv;
    }
    let unit = &scratch.unit;
    let dist = &scratch.dist;
    let inv_dist = &scratch.inv_dist;
    scratch.theta.clear();
    scratch.theta.extend(cage.edges().iter().map(|&[a, b]| {
        // The arc θ between u_a and u_b from sin(θ/2) = |u_a − u_b| / 2 and
        // cos(θ/2) = |u_a + u_b| / 2, both direct: sqrt(1 − sin²) would lose every digit
        // next to θ = π (a point on an edge), and asin near 1 likewise.
        let (ua, ub) = (unit[a as usize], unit[b as usize]);
        let (half_sin, half_cos) = (0.5 * (ua - ub).length(), 0.5 * (ua + ub).length());
        // θ/2 from both: atan2 is well conditioned everywhere, asin of either alone is not.
        [2.0 * half_sin.atan2(half_cos), half_sin, half_cos]
    }));
    let theta = &scratch.theta;
    let mut total = 0.0;
    for (tri, edges) in cage.triangles().iter().zip(cage.triangle_edges()) {
        let idx = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        // θ_i is the arc opposite corner i: edge (i+1, i+2), stored as edges[(i + 1) % 3].
        let e = [
            theta[edges[1] as usize],
            theta[edges[2] as usize],
            theta[edges[0] as usize],
        ];
        let th = [e[0][0], e[1][0], e[2][0]];
        let sin_th = [
            2.0 * e[0][1] * e[0][2],
            2.0 * e[1][1] * e[1][2],
            2.0 * e[2][1] * e[2][2],
        ];
        // cos θ = 1 − 2 sin²(θ/2), exact near 0 and π.
        let cos_th = [
            1.0 - 2.0 * e[0][1] * e[0][1],
            1.0 - 2.0 * e[1][1] * e[1][1],
            1.0 - 2.0 * e[2][1] * e[2][1],
        ];
        if sin_th.iter().any(|&s| s < COPLANAR) {
            if cos_th.iter().any(|&c| c < 0.0) {
                // Two corners on opposite sides of p: p lies on an edge of this triangle.
                barycentric(idx, sin_th, dist, out);
                return;
            }
            continue; // p on the line of an edge, outside it: degenerate, contributes 0
        }
        // c_i = cos A_i, A_i the spherical angle at u_i (Ju et al.'s c_i, by the cosine rule):
        // c_i = (cos θ_i − cos θ_{i+1} cos θ_{i−1}) / (sin θ_{i+1} sin θ_{i−1}).
        // s_i = sign(det[u]) sin A_i. Ju et al. take sqrt(1 − c_i²), which loses every digit
        // next to a face; the sine rule gives it directly: s_i = det[u] / (sin θ_{i+1} sin θ_{i−1}).
        // With P = sin θ_0 sin θ_1 sin θ_2, 1 / (sin θ_{i+1} sin θ_{i−1}) = sin θ_i / P.
        let inv_p = 1.0 / (sin_th[0] * sin_th[1] * sin_th[2]);
        let cc = [
            (cos_th[0] - cos_th[1] * cos_th[2]) * sin_th[0] * inv_p,
            (cos_th[1] - cos_th[2] * cos_th[0]) * sin_th[1] * inv_p,
            (cos_th[2] - cos_th[0] * cos_th[1]) * sin_th[2] * inv_p,
        ];
        let det = unit[idx[0]].dot(unit[idx[1]].cross(unit[idx[2]]));
        let s_min = det.abs() * sin_th[0].min(sin_th[1]).min(sin_th[2]) * inv_p;
        if s_min <= COPLANAR {
            if cc.iter().all(|&c| c < 0.0) {
                // Every spherical angle near π: p lies on this triangle (Ju et al.'s π − h < ε).
                barycentric(idx, sin_th, dist, out);
                return;
            }
            continue; // p in the plane of the triangle, outside it: no contribution
        }
        // w_i = (θ_i − c_{i+1} θ_{i−1} − c_{i−1} θ_{i+1}) / (d_i sin θ_{i+1} s_{i−1}); since
        // sin θ_{i+1} s_{i−1} = det / sin θ_i, w_i = (…) sin θ_i / (d_i det).
        let inv_det = 1.0 / det;
        for i in 0..3 {
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            let w = (th[i] - cc[i1] * th[i2] - cc[i2] * th[i1])
                * sin_th[i]
                * inv_det
                * inv_dist[idx[i]];
            out[idx[i]] += w;
            total += w;
        }
    }
    if total != 0.0 && total.is_finite() {
        let inv = 1.0 / total;
        out.iter_mut().for_each(|w| *w *= inv);
    }
}

/// p on triangle `idx`: 2D barycentric coordinates, w_i ∝ sin θ_i d_{i−1} d_{i+1}
/// (Ju et al. Fig. 4).
fn barycentric(idx: [usize; 3], sin_th: [f64; 3], dist: &[f64], out: &mut [f64]) {
    let w = [
        sin_th[0] * dist[idx[1]] * dist[idx[2]],
        sin_th[1] * dist[idx[2]] * dist[idx[0]],
        sin_th[2] * dist[idx[0]] * dist[idx[1]],
    ];
    let sum = w[0] + w[1] + w[2];
    out.fill(0.0);
    for k in 0..3 {
        out[idx[k]] = w[k] / sum;
    }
}

/// Reusable buffers of a multi-point MVC evaluation.
#[derive(Debug, Clone)]
pub(crate) struct MvcLanesScratch<L> {
    unit: Vec<Vec3Lanes<L>>,
    inv_dist: Vec<L>,
    /// Per edge: θ, sin θ, cos θ.
    theta: Vec<[L; 3]>,
    weights: Vec<L>,
    scalar: MvcScratch,
}

impl<L> Default for MvcLanesScratch<L> {
    fn default() -> Self {
        Self {
            unit: Vec::new(),
            inv_dist: Vec::new(),
            theta: Vec::new(),
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
        let mut scratch = MvcLanesScratch::<L>::default();
        let mut padded = Vec::new();
        let groups = self
            .rows
            .chunks_mut(LANES * n.max(1))
            .zip(self.points.chunks(LANES));
        for (rows, group) in groups {
            let lane_points = std::array::from_fn(|l| group[l.min(group.len() - 1)]);
            if group.len() == LANES {
                mvc_points4(self.cage, lane_points, rows, &mut scratch);
            } else {
                padded.resize(LANES * n, 0.0);
                mvc_points4(self.cage, lane_points, &mut padded, &mut scratch);
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
    p: [DVec3; LANES],
    rows: &mut [f64],
    scratch: &mut MvcLanesScratch<L>,
) {
    let positions = cage.positions();
    let n = positions.len();
    let on_vertex = L::splat(ON_VERTEX * cage.diagonal());
    let coplanar = L::splat(COPLANAR);
    let (one, half, two) = (L::splat(1.0), L::splat(0.5), L::splat(2.0));
    let mut special = 0u32;
    scratch.unit.clear();
    scratch.inv_dist.clear();
    for &x in positions {
        let v = Vec3Lanes::<L>::from_minus(x, &p);
        let d = v.dot(&v).sqrt();
        special |= L::bitmask(d.lt(on_vertex));
        let inv = one / d;
        scratch.unit.push(v.scale(inv));
        scratch.inv_dist.push(inv);
    }
    let unit = &scratch.unit;
    scratch.theta.clear();
    // A loop, not a closure: the kernel must be one function for `#[target_feature]`.
    for &[a, b] in cage.edges() {
        let (ua, ub) = (&unit[a as usize], &unit[b as usize]);
        // sin(θ/2) = |u_a − u_b| / 2 and cos(θ/2) = |u_a + u_b| / 2, both direct (see
        // mvc_point); θ/2 = atan2 of the two; sin θ = 2 sin(θ/2) cos(θ/2),
        // cos θ = 1 − 2 sin²(θ/2).
        let (dx, dy, dz) = (ua.x - ub.x, ua.y - ub.y, ua.z - ub.z);
        let (sx, sy, sz) = (ua.x + ub.x, ua.y + ub.y, ua.z + ub.z);
        let half_sin = half * dx.mul_add(dx, dy.mul_add(dy, dz * dz)).sqrt();
        let half_cos = half * sx.mul_add(sx, sy.mul_add(sy, sz * sz)).sqrt();
        let half_angle = math::atan2_nonnegative(half_sin, half_cos);
        scratch.theta.push([
            two * half_angle,
            two * half_sin * half_cos,
            (-two * half_sin).mul_add(half_sin, one),
        ]);
    }
    let theta = &scratch.theta;
    let inv_dist = &scratch.inv_dist;
    scratch.weights.clear();
    scratch.weights.resize(n, L::zero());
    let weights = &mut scratch.weights;
    let mut total = L::zero();
    for (tri, edges) in cage.triangles().iter().zip(cage.triangle_edges()) {
        let idx = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        // θ_i is the arc opposite corner i: edge (i+1, i+2) is edges[(i + 1) % 3].
        let [th0, s0, c0] = theta[edges[1] as usize];
        let [th1, s1, c1] = theta[edges[2] as usize];
        let [th2, s2, c2] = theta[edges[0] as usize];
        let det = unit[idx[0]].dot(&unit[idx[1]].cross(&unit[idx[2]]));
        // The formulas of mvc_point, lane by lane.
        let inv_p = one / (s0 * s1 * s2);
        let cc0 = (c0 - c1 * c2) * s0 * inv_p;
        let cc1 = (c1 - c2 * c0) * s1 * inv_p;
        let cc2 = (c2 - c0 * c1) * s2 * inv_p;
        let inv_det = one / det;
        let w0 = (th0 - cc1 * th2 - cc2 * th1) * s0 * inv_det * inv_dist[idx[0]];
        let w1 = (th1 - cc2 * th0 - cc0 * th2) * s1 * inv_det * inv_dist[idx[1]];
        let w2 = (th2 - cc0 * th1 - cc1 * th0) * s2 * inv_det * inv_dist[idx[2]];
        let s_min = s0.min(s1).min(s2);
        // Regular where both tests hold; NaN fails them, so it flags the lane too.
        let regular = s_min.ge(coplanar) & (det.abs() * s_min * inv_p).gt(coplanar);
        special |= !L::bitmask(regular) & ALL_LANES;
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

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

use super::lanes::{ALL_LANES, LANES, Lane, Vec3Lanes, mask_bits};
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
        // θ/2 by asin of the smaller of the two (≤ 1/√2, where asin is well conditioned).
        let half = if half_sin <= half_cos {
            half_sin.asin()
        } else {
            std::f64::consts::FRAC_PI_2 - half_cos.asin()
        };
        [2.0 * half, half_sin, half_cos]
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

/// Reusable per-thread buffers of a multi-point MVC evaluation.
#[derive(Debug, Default, Clone)]
pub(crate) struct MvcLanesScratch {
    unit: Vec<Vec3Lanes>,
    inv_dist: Vec<Lane>,
    /// Per edge: θ, sin θ, cos θ.
    theta: Vec<[Lane; 3]>,
    weights: Vec<Lane>,
    scalar: MvcScratch,
}

/// MVC of LANES points at once into `rows` (LANES rows of `cage.vertex_count()` weights), with
/// the formulas of [`mvc_point`] in SIMD lanes. Lanes that meet a special case (a point on a
/// vertex, an edge's line or a face's plane) are recomputed by [`mvc_point`].
pub(crate) fn mvc_points4(
    cage: &Cage,
    p: [DVec3; LANES],
    rows: &mut [f64],
    scratch: &mut MvcLanesScratch,
) {
    let positions = cage.positions();
    let n = positions.len();
    let on_vertex = Lane::from(ON_VERTEX * cage.diagonal());
    let coplanar = Lane::from(COPLANAR);
    let (one, half, two) = (Lane::from(1.0), Lane::from(0.5), Lane::from(2.0));
    let quarter_turn = Lane::from(std::f64::consts::FRAC_PI_2);
    let mut special = 0u32;
    scratch.unit.clear();
    scratch.inv_dist.clear();
    for &x in positions {
        let v = Vec3Lanes::from_minus(x, &p);
        let d = v.dot(&v).sqrt();
        special |= mask_bits(d.simd_lt(on_vertex));
        let inv = one / d;
        scratch.unit.push(v.scale(inv));
        scratch.inv_dist.push(inv);
    }
    let unit = &scratch.unit;
    scratch.theta.clear();
    scratch.theta.extend(cage.edges().iter().map(|&[a, b]| {
        let (ua, ub) = (&unit[a as usize], &unit[b as usize]);
        // sin(θ/2) = |u_a − u_b| / 2 and cos(θ/2) = |u_a + u_b| / 2, both direct (see
        // mvc_point); θ, sin θ = 2 sin(θ/2) cos(θ/2), cos θ = 1 − 2 sin²(θ/2).
        let (dx, dy, dz) = (ua.x - ub.x, ua.y - ub.y, ua.z - ub.z);
        let (sx, sy, sz) = (ua.x + ub.x, ua.y + ub.y, ua.z + ub.z);
        let half_sin = half * (dx * dx + dy * dy + dz * dz).sqrt();
        let half_cos = half * (sx * sx + sy * sy + sz * sz).sqrt();
        // θ/2 = asin(min) or π/2 − asin(min): one asin, on an argument ≤ 1/√2.
        let small = half_sin.min(half_cos).asin();
        let reflect = half_sin.simd_gt(half_cos) & one;
        let half_angle = small + reflect * (quarter_turn - two * small);
        [
            two * half_angle,
            two * half_sin * half_cos,
            one - two * half_sin * half_sin,
        ]
    }));
    let theta = &scratch.theta;
    let inv_dist = &scratch.inv_dist;
    scratch.weights.clear();
    scratch.weights.resize(n, Lane::ZERO);
    let weights = &mut scratch.weights;
    let mut total = Lane::ZERO;
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
        let regular = s_min.simd_ge(coplanar) & (det.abs() * s_min * inv_p).simd_gt(coplanar);
        special |= !mask_bits(regular) & ALL_LANES;
        weights[idx[0]] += w0;
        weights[idx[1]] += w1;
        weights[idx[2]] += w2;
        total += w0 + w1 + w2;
    }
    let total = total.to_array();
    for (l, row) in rows.chunks_mut(n).enumerate().take(LANES) {
        if special & (1 << l) != 0 || total[l] == 0.0 || !total[l].is_finite() {
            mvc_point(cage, p[l], row, &mut scratch.scalar);
        } else {
            let inv = 1.0 / total[l];
            for (w, acc) in row.iter_mut().zip(weights.iter()) {
                *w = acc.as_array()[l] * inv;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::shapes;

    #[test]
    fn lane_kernel_matches_scalar_routine() {
        let cage = shapes::star_prism();
        let groups = [
            [
                DVec3::new(0.1, 0.2, 0.0),
                DVec3::new(-0.3, 0.1, 0.3),
                DVec3::new(0.0, -0.2, -0.1),
                DVec3::new(0.2, 0.0, 0.4),
            ],
            [
                cage.positions()[3],
                DVec3::new(0.0, 0.0, 0.5),
                DVec3::new(3.0, 0.0, 0.5),
                DVec3::new(0.05, 0.05, 0.05),
            ],
        ];
        let n = cage.vertex_count();
        let (mut lanes, mut scalar) = (MvcLanesScratch::default(), MvcScratch::default());
        for points in groups {
            let mut rows = vec![0.0; LANES * n];
            mvc_points4(&cage, points, &mut rows, &mut lanes);
            for (l, p) in points.iter().enumerate() {
                let mut expected = vec![0.0; n];
                mvc_point(&cage, *p, &mut expected, &mut scalar);
                for (a, b) in rows[l * n..(l + 1) * n].iter().zip(&expected) {
                    assert!((a - b).abs() < 1e-12, "lane {l} at {p}: {a} vs {b}");
                }
            }
        }
    }
}

//! Green Coordinates in 3D (Lipman, Levin & Cohen-Or 2008, "Green coordinates").
//!
//! For a point η, φ_i(η) = ∫ Γ_i ∂G/∂n dσ over the faces around vertex i (double layer, linear
//! hat density Γ_i) and ψ_j(η) = −∫_{t_j} G dσ (single layer), with G(ξ, η) = −1/(4π|ξ − η|),
//! so that η = Σ φ_i v_i + Σ ψ_j n_j inside the cage (Green's third identity), and the
//! deformation is f(η) = Σ φ_i v'_i + Σ ψ_j s_j n'_j (Lipman et al. eq. 12, stretch s_j below).
//!
//! Instead of the GCTriInt pseudocode (two numeric-friendly but costly integrals per edge and
//! side), we use the closed forms of both potentials over a flat triangle, in coordinates
//! centred at η, with n the face's unit normal, h = n·v_a its signed plane offset, Ω its signed
//! solid angle and, per edge e = (a, b) with in-plane outward normal ν_e,
//! L_e = ∫_e ds / |ξ| = ln((R_a + R_b + l) / (R_a + R_b − l)) and d_e = ν_e · v_a:
//!
//! * single layer: ∫_t dσ / |ξ| = Σ_e d_e L_e − h Ω  (so ψ_j = that / 4π);
//! * double layer: ∫_t h ξ / |ξ|³ dσ = h G with G = Ω n − Σ_e ν_e L_e; expanding ξ in the
//!   triangle's vertices gives φ_i's share m_i = G · (v_{i+1} × v_{i+2}) / (2A), A the area.
//!
//! The 0/0 case of GCTriInt (η on the line of an edge, inside the segment: L_e = ∞ while d_e
//! and ν_e·(v × v) vanish) is guarded by dropping the edge term, which is its limit.
//!
//! Outside the cage, Σ φ_i = 0 and the raw formula reproduces 0, not η. We use Lipman et al.'s
//! extension across a face (their §4.2): the coordinates are continued through the face t
//! nearest to η by adding the barycentric coordinates of η's projection on t's plane to the
//! φ of t's corners and η's height above t to ψ_t. This is C∞ across t; it jumps where the
//! nearest face changes, far from the cage, as in the paper.

use std::f64::consts::PI;

use glam::DVec3;

use super::lanes::{ALL_LANES, LANES, Lane, LaneKernel, Vec3Lanes};
use crate::cage::Cage;

/// Precomputed per-cage data for Green coordinates.
#[derive(Debug, Clone)]
pub(crate) struct GreenCage {
    normals: Vec<DVec3>,
    /// Per triangle, the in-plane outward unit normal of edges (i0,i1), (i1,i2), (i2,i0).
    edge_normals: Vec<[DVec3; 3]>,
    /// Per triangle, 1 / (2A · 4π).
    inv_scaled_double_area: Vec<f64>,
    edge_lengths: Vec<f64>,
}

impl GreenCage {
    pub(crate) fn new(cage: &Cage) -> Self {
        let p = cage.positions();
        let normals = cage.triangle_normals();
        let mut edge_normals = Vec::with_capacity(normals.len());
        let mut inv = Vec::with_capacity(normals.len());
        for (tri, n) in cage.triangles().iter().zip(&normals) {
            let x = [p[tri[0] as usize], p[tri[1] as usize], p[tri[2] as usize]];
            edge_normals.push([
                (x[1] - x[0]).cross(*n).normalize_or_zero(),
                (x[2] - x[1]).cross(*n).normalize_or_zero(),
                (x[0] - x[2]).cross(*n).normalize_or_zero(),
            ]);
            let double_area = (x[1] - x[0]).cross(x[2] - x[0]).length();
            inv.push(1.0 / (double_area * 4.0 * PI));
        }
        let edge_lengths = cage
            .edges()
            .iter()
            .map(|&[a, b]| p[a as usize].distance(p[b as usize]))
            .collect();
        Self {
            normals,
            edge_normals,
            inv_scaled_double_area: inv,
            edge_lengths,
        }
    }
}

/// Reusable per-thread buffers of one GC evaluation.
#[derive(Debug, Default, Clone)]
pub(crate) struct GreenScratch {
    rel: Vec<DVec3>,
    len: Vec<f64>,
    /// Per edge (a < b): L_e, v_a · v_b, v_a × v_b.
    edge: Vec<(f64, f64, DVec3)>,
}

/// Relative distance (to the cage diagonal) under which a point is on the cage.
const ON_CAGE: f64 = 1e-12;
/// How far (relative to the diagonal) a point on the cage is moved inside to take the inside
/// limit of the coordinates there.
const INSIDE_LIMIT_STEP: f64 = 1e-10;

/// Writes φ (per vertex) and ψ (per triangle) of `p` into `phi` and `psi`.
///
/// On the cage itself the potentials have edge singularities that cancel only in the limit;
/// there we return the limit from inside, evaluated 1e-10 diagonals inside along the summed
/// normals of the faces `p` touches.
pub(crate) fn green_point(
    cage: &Cage,
    gc: &GreenCage,
    p: DVec3,
    phi: &mut [f64],
    psi: &mut [f64],
    scratch: &mut GreenScratch,
) {
    let touching = green_point_raw(cage, gc, p, phi, psi, scratch);
    if touching != DVec3::ZERO {
        let inward = -touching.normalize_or_zero() * (INSIDE_LIMIT_STEP * cage.diagonal());
        green_point_raw(cage, gc, p + inward, phi, psi, scratch);
    }
}

/// GC at `p`; returns the sum of the normals of the faces `p` lies on (zero if none).
fn green_point_raw(
    cage: &Cage,
    gc: &GreenCage,
    p: DVec3,
    phi: &mut [f64],
    psi: &mut [f64],
    scratch: &mut GreenScratch,
) -> DVec3 {
    let on_cage = ON_CAGE * cage.diagonal();
    let mut touching = DVec3::ZERO;
    let positions = cage.positions();
    phi.fill(0.0);
    scratch.rel.clear();
    scratch.rel.extend(positions.iter().map(|&x| x - p));
    scratch.len.clear();
    scratch.len.extend(scratch.rel.iter().map(|v| v.length()));
    let (rel, len) = (&scratch.rel, &scratch.len);
    scratch.edge.clear();
    scratch.edge.extend(
        cage.edges()
            .iter()
            .zip(&gc.edge_lengths)
            .map(|(&[a, b], &l)| {
                let (va, vb) = (rel[a as usize], rel[b as usize]);
                let (ra, rb) = (len[a as usize], len[b as usize]);
                let dot = va.dot(vb);
                let sum = ra + rb;
                // R_a + R_b − l = 2 (R_a R_b + v_a·v_b) / (R_a + R_b + l), without cancellation.
                let near = 2.0 * (ra * rb + dot);
                let log = if near > 0.0 && sum > 0.0 {
                    ((sum + l) * (sum + l) / near).ln()
                } else {
                    0.0 // η on the edge segment: the 0/0 case, whose limit drops the term
                };
                (log, dot, va.cross(vb))
            }),
    );
    let edge = &scratch.edge;
    let mut winding = 0.0;
    for (t, (tri, tri_edges)) in cage
        .triangles()
        .iter()
        .zip(cage.triangle_edges())
        .enumerate()
    {
        let idx = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        let v = [rel[idx[0]], rel[idx[1]], rel[idx[2]]];
        let r = [len[idx[0]], len[idx[1]], len[idx[2]]];
        // Directed edge data: (i0,i1), (i1,i2), (i2,i0); the cross product v_i × v_j.
        let mut logs = [0.0; 3];
        let mut dots = [0.0; 3];
        let mut crosses = [DVec3::ZERO; 3];
        for k in 0..3 {
            let (log, dot, cross) = edge[tri_edges[k] as usize];
            logs[k] = log;
            dots[k] = dot;
            let forward = idx[k] < idx[(k + 1) % 3];
            crosses[k] = if forward { cross } else { -cross };
        }
        let n = gc.normals[t];
        let h = n.dot(v[0]);
        // Signed solid angle, Van Oosterom & Strackee: det(v0, v1, v2) = v0 · (v1 × v2).
        let det = v[0].dot(crosses[1]);
        let denom = r[0] * r[1] * r[2] + dots[0] * r[2] + dots[1] * r[0] + dots[2] * r[1];
        if h.abs() <= on_cage && denom <= 1e-9 * r[0] * r[1] * r[2] {
            touching += n; // on the closed triangle: the caller takes the inside limit
        }
        let omega = 2.0 * det.atan2(denom);
        winding += omega;
        let nu = gc.edge_normals[t];
        // ψ_t = (Σ_e d_e L_e − h Ω) / 4π, with d_e = ν_e · v (any point of the edge).
        let single =
            nu[0].dot(v[0]) * logs[0] + nu[1].dot(v[1]) * logs[1] + nu[2].dot(v[2]) * logs[2]
                - h * omega;
        psi[t] = single / (4.0 * PI);
        // G = Ω n − Σ_e ν_e L_e; m_i = G · (v_{i+1} × v_{i+2}) / 2A; φ_i += m_i / 4π.
        let g = n * omega - nu[0] * logs[0] - nu[1] * logs[1] - nu[2] * logs[2];
        let scale = gc.inv_scaled_double_area[t];
        phi[idx[0]] += g.dot(crosses[1]) * scale;
        phi[idx[1]] += g.dot(crosses[2]) * scale;
        phi[idx[2]] += g.dot(crosses[0]) * scale;
    }
    if winding < 2.0 * PI {
        extend_outside(cage, gc, p, phi, psi);
    }
    touching
}

/// Reusable buffers of a multi-point GC evaluation.
#[derive(Debug, Clone)]
pub(crate) struct GreenLanesScratch<L> {
    rel: Vec<Vec3Lanes<L>>,
    len: Vec<L>,
    /// Per edge (a < b): L_e, v_a · v_b, v_a × v_b.
    edge: Vec<(L, L, Vec3Lanes<L>)>,
    omega: Vec<L>,
    phi: Vec<L>,
    psi: Vec<L>,
    scalar: GreenScratch,
}

impl<L> Default for GreenLanesScratch<L> {
    fn default() -> Self {
        Self {
            rel: Vec::new(),
            len: Vec::new(),
            edge: Vec::new(),
            omega: Vec::new(),
            phi: Vec::new(),
            psi: Vec::new(),
            scalar: GreenScratch::default(),
        }
    }
}

/// GC of a run of points into their φ rows (`points.len()` × vertices) and ψ rows
/// (`points.len()` × triangles), [`LANES`] points at a time with the best SIMD backend.
pub(crate) struct GreenRows<'a> {
    /// The cage.
    pub cage: &'a Cage,
    /// Its precomputed data.
    pub gc: &'a GreenCage,
    /// The points.
    pub points: &'a [DVec3],
    /// φ rows, row-major.
    pub phi: &'a mut [f64],
    /// ψ rows, row-major.
    pub psi: &'a mut [f64],
}

impl LaneKernel for GreenRows<'_> {
    type Output = ();

    #[inline(always)]
    fn run<L: Lane>(self) {
        let (n, f) = (self.cage.vertex_count(), self.cage.triangles().len());
        let mut scratch = GreenLanesScratch::<L>::default();
        let (mut phi4, mut psi4) = (Vec::new(), Vec::new());
        let groups = self
            .phi
            .chunks_mut(LANES * n.max(1))
            .zip(self.psi.chunks_mut(LANES * f.max(1)))
            .zip(self.points.chunks(LANES));
        for ((phi, psi), group) in groups {
            let lane_points = std::array::from_fn(|l| group[l.min(group.len() - 1)]);
            if group.len() == LANES {
                green_points4(self.cage, self.gc, lane_points, phi, psi, &mut scratch);
            } else {
                phi4.resize(LANES * n, 0.0);
                psi4.resize(LANES * f, 0.0);
                green_points4(
                    self.cage,
                    self.gc,
                    lane_points,
                    &mut phi4,
                    &mut psi4,
                    &mut scratch,
                );
                phi.copy_from_slice(&phi4[..phi.len()]);
                psi.copy_from_slice(&psi4[..psi.len()]);
            }
        }
    }
}

/// GC of LANES points at once into `phi_rows` and `psi_rows` (LANES rows each), with the
/// formulas of [`green_point`] in SIMD lanes. Lanes on the cage (or meeting round-off trouble)
/// are recomputed by [`green_point`]; lanes outside get the exterior extension.
#[inline(always)]
pub(crate) fn green_points4<L: Lane>(
    cage: &Cage,
    gc: &GreenCage,
    p: [DVec3; LANES],
    phi_rows: &mut [f64],
    psi_rows: &mut [f64],
    scratch: &mut GreenLanesScratch<L>,
) {
    let positions = cage.positions();
    let (n, f) = (positions.len(), cage.triangles().len());
    let on_cage = L::splat(ON_CAGE * cage.diagonal());
    let (zero, two) = (L::zero(), L::splat(2.0));
    let largest = L::splat(f64::MAX);
    let mut special = 0u32;
    scratch.rel.clear();
    scratch.len.clear();
    for &x in positions {
        let v = Vec3Lanes::<L>::from_minus(x, &p);
        scratch.len.push(v.dot(&v).sqrt());
        scratch.rel.push(v);
    }
    let (rel, len) = (&scratch.rel, &scratch.len);
    scratch.edge.clear();
    for (&[a, b], &l) in cage.edges().iter().zip(&gc.edge_lengths) {
        let (va, vb) = (&rel[a as usize], &rel[b as usize]);
        let dot = va.dot(vb);
        let sum = len[a as usize] + len[b as usize];
        let l = L::splat(l);
        // L_e = ln((R_a + R_b + l) / (R_a + R_b − l)), the difference without cancellation:
        // (R_a + R_b − l)(R_a + R_b + l) = 2 (R_a R_b + v_a·v_b).
        let near = two * len[a as usize].mul_add(len[b as usize], dot);
        let far = sum + l;
        let ratio = far * far / near;
        // ln needs a positive finite argument: η on the edge (near ≤ 0) or so close that the
        // ratio overflows goes to the scalar routine.
        special |= !L::bitmask(near.gt(zero) & ratio.le(largest)) & ALL_LANES;
        scratch.edge.push((ratio.ln(), dot, va.cross(vb)));
    }
    let edge = &scratch.edge;
    scratch.phi.clear();
    scratch.phi.resize(n, zero);
    scratch.psi.clear();
    // Pass 1: solid angles (few live values, so no register spills on SSE2).
    let mut winding = zero;
    scratch.omega.clear();
    for (t, (tri, tri_edges)) in cage
        .triangles()
        .iter()
        .zip(cage.triangle_edges())
        .enumerate()
    {
        let idx = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        let r = [len[idx[0]], len[idx[1]], len[idx[2]]];
        let (_, d0, _) = edge[tri_edges[0] as usize];
        let (_, d1, c1) = edge[tri_edges[1] as usize];
        let (_, d2, _) = edge[tri_edges[2] as usize];
        let c1 = if idx[1] < idx[2] { c1 } else { c1.neg() };
        let det = rel[idx[0]].dot(&c1);
        let r01 = r[0] * r[1];
        // Van Oosterom & Strackee: tan(Ω/2) = det / (R0 R1 R2 + d01 R2 + d12 R0 + d20 R1).
        let denom = r01.mul_add(r[2], d0.mul_add(r[2], d1.mul_add(r[0], d2 * r[1])));
        let h = rel[idx[0]].dot_splat(gc.normals[t]);
        let touching = h.abs().le(on_cage) & denom.le(L::splat(1e-9) * r01 * r[2]);
        special |= L::bitmask(touching);
        let omega = two * det.atan2(denom);
        winding += omega;
        scratch.omega.push(omega);
    }
    // Pass 2: ψ (single layer) and φ (double layer) from Ω and the edge integrals.
    let inv_four_pi = L::splat(1.0 / (4.0 * PI));
    for (t, (tri, tri_edges)) in cage
        .triangles()
        .iter()
        .zip(cage.triangle_edges())
        .enumerate()
    {
        let idx = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        let v = [rel[idx[0]], rel[idx[1]], rel[idx[2]]];
        let (l0, c0) = directed_edge(edge, tri_edges, idx, 0);
        let (l1, c1) = directed_edge(edge, tri_edges, idx, 1);
        let (l2, c2) = directed_edge(edge, tri_edges, idx, 2);
        let n = gc.normals[t];
        let omega = scratch.omega[t];
        let h = v[0].dot_splat(n);
        let nu = gc.edge_normals[t];
        // ψ_t = (Σ_e d_e L_e − h Ω) / 4π.
        let single = v[0].dot_splat(nu[0]).mul_add(
            l0,
            v[1].dot_splat(nu[1])
                .mul_add(l1, v[2].dot_splat(nu[2]).mul_sub(l2, h * omega)),
        );
        scratch.psi.push(single * inv_four_pi);
        // G = Ω n − Σ_e ν_e L_e.
        let g = Vec3Lanes {
            x: omega.mul_sub(
                L::splat(n.x),
                l0.mul_add(
                    L::splat(nu[0].x),
                    l1.mul_add(L::splat(nu[1].x), l2 * L::splat(nu[2].x)),
                ),
            ),
            y: omega.mul_sub(
                L::splat(n.y),
                l0.mul_add(
                    L::splat(nu[0].y),
                    l1.mul_add(L::splat(nu[1].y), l2 * L::splat(nu[2].y)),
                ),
            ),
            z: omega.mul_sub(
                L::splat(n.z),
                l0.mul_add(
                    L::splat(nu[0].z),
                    l1.mul_add(L::splat(nu[1].z), l2 * L::splat(nu[2].z)),
                ),
            ),
        };
        let scale = L::splat(gc.inv_scaled_double_area[t]);
        scratch.phi[idx[0]] += g.dot(&c1) * scale;
        scratch.phi[idx[1]] += g.dot(&c2) * scale;
        scratch.phi[idx[2]] += g.dot(&c0) * scale;
    }
    // Transpose the lanes into rows; a lane whose φ is not finite goes to the scalar routine.
    let mut finite = L::bitmask(zero.le(zero));
    for (i, acc) in scratch.phi.iter().enumerate() {
        finite &= L::bitmask(acc.abs().le(largest));
        let acc = acc.to_array();
        for l in 0..LANES {
            phi_rows[l * n + i] = acc[l];
        }
    }
    for (t, acc) in scratch.psi.iter().enumerate() {
        let acc = acc.to_array();
        for l in 0..LANES {
            psi_rows[l * f + t] = acc[l];
        }
    }
    let winding = winding.to_array();
    for (l, (phi, psi)) in phi_rows
        .chunks_mut(n)
        .zip(psi_rows.chunks_mut(f))
        .enumerate()
        .take(LANES)
    {
        if special & (1 << l) != 0 || finite & (1 << l) == 0 {
            green_point(cage, gc, p[l], phi, psi, &mut scratch.scalar);
        } else if winding[l] < 2.0 * PI {
            extend_outside(cage, gc, p[l], phi, psi);
        }
    }
}

/// Edge `k` of a triangle (corners `idx`, edges `tri_edges`) from the per-edge table, directed
/// from corner k to corner k + 1: (L_e, v_k × v_{k+1}).
#[inline(always)]
fn directed_edge<L: Lane>(
    edge: &[(L, L, Vec3Lanes<L>)],
    tri_edges: &[u32; 3],
    idx: [usize; 3],
    k: usize,
) -> (L, Vec3Lanes<L>) {
    let (log, _, cross) = edge[tri_edges[k] as usize];
    let forward = idx[k] < idx[(k + 1) % 3];
    (log, if forward { cross } else { cross.neg() })
}

/// Lipman et al. §4.2: continue the coordinates through the nearest face so that the rest
/// cage reproduces η outside too.
fn extend_outside(cage: &Cage, gc: &GreenCage, p: DVec3, phi: &mut [f64], psi: &mut [f64]) {
    let (t, _, _) = cage.closest_point(p);
    let tri = cage.triangles()[t];
    let x = tri.map(|i| cage.positions()[i as usize]);
    let n = gc.normals[t];
    let height = n.dot(p - x[0]);
    let projected = p - n * height;
    let bary = barycentric_in_plane(projected, x[0], x[1], x[2]);
    for k in 0..3 {
        phi[tri[k] as usize] += bary[k];
    }
    psi[t] += height;
}

/// Barycentric coordinates of a point of the triangle's plane (affine, unclamped).
fn barycentric_in_plane(q: DVec3, a: DVec3, b: DVec3, c: DVec3) -> [f64; 3] {
    let normal = (b - a).cross(c - a);
    let inv = 1.0 / normal.length_squared();
    let wa = (c - b).cross(q - b).dot(normal) * inv;
    let wb = (a - c).cross(q - c).dot(normal) * inv;
    [wa, wb, 1.0 - wa - wb]
}

/// The per-face stretch factors s_j of Lipman et al. (eq. 13 in 3D): with u, v two edges of
/// t_j at rest and u', v' posed, s_j = sqrt(|u'|²|v|² − 2(u'·v')(u·v) + |v'|²|u|²) / (√8 A_j).
/// A similarity of scale σ gives s_j = σ for every face.
pub fn green_stretch(cage: &Cage, posed: &[DVec3]) -> Vec<f64> {
    let rest = cage.positions();
    cage.triangles()
        .iter()
        .map(|t| {
            let t = t.map(|v| v as usize);
            triangle_stretch(t.map(|v| rest[v]), t.map(|v| posed[v]))
        })
        .collect()
}

/// s_t of one triangle from its rest and posed corners (see [`green_stretch`]).
pub(crate) fn triangle_stretch(rest: [DVec3; 3], posed: [DVec3; 3]) -> f64 {
    let (u, v) = (rest[1] - rest[0], rest[2] - rest[0]);
    let (up, vp) = (posed[1] - posed[0], posed[2] - posed[0]);
    let area = 0.5 * u.cross(v).length();
    let num = up.length_squared() * v.length_squared() - 2.0 * up.dot(vp) * u.dot(v)
        + vp.length_squared() * u.length_squared();
    num.max(0.0).sqrt() / (8f64.sqrt() * area)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::shapes;

    /// The lane kernel on `points`, with one backend: (φ rows, ψ rows).
    #[derive(Clone)]
    struct Rows<'a>(&'a Cage, &'a [DVec3]);

    impl LaneKernel for Rows<'_> {
        type Output = (Vec<f64>, Vec<f64>);
        fn run<L: Lane>(self) -> (Vec<f64>, Vec<f64>) {
            let (cage, points) = (self.0, self.1);
            let mut phi = vec![0.0; points.len() * cage.vertex_count()];
            let mut psi = vec![0.0; points.len() * cage.triangles().len()];
            let gc = GreenCage::new(cage);
            GreenRows {
                cage,
                gc: &gc,
                points,
                phi: &mut phi,
                psi: &mut psi,
            }
            .run::<L>();
            (phi, psi)
        }
    }

    #[test]
    fn lane_kernel_matches_scalar_routine_on_every_backend() {
        let cage = shapes::l_prism();
        let gc = GreenCage::new(&cage);
        // Inside, a vertex, a face, outside, next to an edge, and a last partial group.
        let points = [
            DVec3::new(0.5, 0.5, 0.5),
            DVec3::new(1.5, 0.5, 0.2),
            DVec3::new(0.5, 1.5, 0.7),
            DVec3::new(0.2, 0.3, 0.9),
            cage.positions()[2],
            DVec3::new(0.5, 0.5, 1.0),
            DVec3::new(1.5, 1.5, 0.5),
            DVec3::new(-1.0, 0.5, 0.5),
            DVec3::new(1e-13, 0.5, 1e-13),
            DVec3::new(0.25, 1.75, 0.1),
        ];
        let (n, f) = (cage.vertex_count(), cage.triangles().len());
        let mut scalar = GreenScratch::default();
        for (backend, (phi, psi)) in crate::coords::lanes::run_every_backend(Rows(&cage, &points)) {
            for (i, p) in points.iter().enumerate() {
                let (mut phi1, mut psi1) = (vec![0.0; n], vec![0.0; f]);
                green_point(&cage, &gc, *p, &mut phi1, &mut psi1, &mut scalar);
                let lane = phi[i * n..(i + 1) * n]
                    .iter()
                    .chain(&psi[i * f..(i + 1) * f]);
                for (a, b) in lane.zip(phi1.iter().chain(&psi1)) {
                    assert!(
                        (a - b).abs() < 1e-12,
                        "{backend}, point {i} at {p}: {a} vs {b}"
                    );
                }
            }
        }
    }
}

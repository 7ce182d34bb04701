//! Multigrid-preconditioned conjugate gradients for the grid Laplace equation of harmonic
//! coordinates, solving `W` right-hand sides (cage vertices) at once: `K` (8), or 2 or 4 for
//! a cage's last few vertices.
//!
//! The unknowns of each level are numbered compactly in red-black order, `[red…, 0, black…, 0]`,
//! each block followed by a zero sentinel that stands for every non-unknown neighbour. A red
//! node's neighbours are all black and vice versa, so a Gauss–Seidel half-sweep reads one
//! block and writes the other: safe, parallel and cache friendly. Each node stores its `W`
//! values contiguously (`[f64; W]`), so the stencil works on whole rows.
//!
//! The fine operator is D − (sum of unknown neighbours), symmetric with D ≥ 6 (the ghost-value
//! boundary condition only raises the diagonal). The V-cycle (symmetric red-black
//! over-relaxed Gauss–Seidel, [`OMEGA`]; trilinear prolongation P, restriction ½ Pᵀ,
//! re-discretised 7-point Laplacians on injected coarse masks) is a symmetric positive definite
//! preconditioner, so CG converges even where coarse masks lose thin parts of the cage.

// Loops over the W right-hand-side columns index several rows at once; ranges read best.
#![allow(clippy::needless_range_loop)]

use glam::UVec3;
use rayon::prelude::*;

/// Number of right-hand sides solved together (the width of a stored field's rows).
pub(super) const K: usize = 8;
/// A row of `K` values.
pub(super) type Row = [f64; K];
const NONE: u32 = u32::MAX;
/// Unknown count under which a level is solved by plain smoothing.
const COARSEST: usize = 512;
const COARSE_SWEEPS: usize = 24;
const SMOOTHING_SWEEPS: usize = 2;
/// Over-relaxation of the red-black smoother (SOR). Pre- and post-smoothing sweep the colours
/// in opposite orders with the same ω, so the V-cycle stays symmetric for 0 < ω < 2; ω = 1.2
/// saves a CG iteration per batch over Gauss–Seidel (docs/performance.md, "Design
/// measurements").
const OMEGA: f64 = 1.2;
const OMEGA_F32: f32 = OMEGA as f32;

/// One level: grid dimensions, node → slot map, and the 6-neighbour table.
#[derive(Debug, Clone)]
struct Level {
    dims: UVec3,
    /// Grid node → slot in the compact vector (or NONE).
    slot_of_node: Vec<u32>,
    /// Slot → grid node (sentinel slots map to NONE).
    node_of_slot: Vec<u32>,
    red: usize,
    /// Per slot, the slots of its 6 neighbours (the other colour's sentinel where absent).
    neighbours: Vec<[u32; 6]>,
    /// Per slot, the diagonal of the operator (6 away from the cage; 1 sentinel).
    diagonal: Vec<f64>,
    /// Per slot, the diagonal in the V-cycle's single precision.
    diagonal_f32: Vec<f32>,
}

impl Level {
    fn len(&self) -> usize {
        self.node_of_slot.len()
    }

    fn black_start(&self) -> usize {
        self.red + 1
    }

    fn unknowns(&self) -> usize {
        self.len() - 2
    }

    fn is_sentinel(&self, slot: usize) -> bool {
        slot == self.red || slot == self.len() - 1
    }

    fn new(dims: UVec3, unknown: &[bool], node_diagonal: Option<&[f64]>) -> Self {
        let colour = |n: usize| {
            let n = n as u32;
            (n % dims.x + (n / dims.x) % dims.y + n / (dims.x * dims.y)) % 2
        };
        let mut node_of_slot: Vec<u32> = (0..unknown.len())
            .filter(|&n| unknown[n] && colour(n) == 0)
            .map(|n| n as u32)
            .collect();
        let red = node_of_slot.len();
        node_of_slot.push(NONE);
        node_of_slot.extend(
            (0..unknown.len())
                .filter(|&n| unknown[n] && colour(n) == 1)
                .map(|n| n as u32),
        );
        let black_sentinel = node_of_slot.len() as u32;
        node_of_slot.push(NONE);
        let mut slot_of_node = vec![NONE; unknown.len()];
        for (s, &n) in node_of_slot.iter().enumerate() {
            if n != NONE {
                slot_of_node[n as usize] = s as u32;
            }
        }
        let (sx, sy) = (1i64, dims.x as i64);
        let sz = sy * dims.y as i64;
        let neighbours = node_of_slot
            .iter()
            .enumerate()
            .map(|(s, &n)| {
                // Neighbours have the other colour; absent ones read its sentinel.
                let sentinel = if s < red { black_sentinel } else { red as u32 };
                if n == NONE {
                    return [sentinel; 6];
                }
                let n = n as i64;
                [n - sx, n + sx, n - sy, n + sy, n - sz, n + sz].map(|m| {
                    let slot = slot_of_node[m as usize];
                    if slot == NONE { sentinel } else { slot }
                })
            })
            .collect();
        let diagonal = node_of_slot
            .iter()
            .map(|&n| match (n, node_diagonal) {
                (NONE, _) => 1.0,
                (n, Some(d)) => d[n as usize],
                (_, None) => 6.0,
            })
            .collect::<Vec<f64>>();
        let diagonal_f32 = diagonal.iter().map(|&d| d as f32).collect();
        Self {
            dims,
            slot_of_node,
            node_of_slot,
            red,
            neighbours,
            diagonal,
            diagonal_f32,
        }
    }

    /// Injected coarse level: coarse node I is an unknown when fine node 2I is, away from
    /// the coarse border.
    fn coarsen(&self) -> Option<Self> {
        let d = (self.dims + UVec3::ONE) / 2;
        if d.min_element() < 3 {
            return None;
        }
        let mut unknown = vec![false; (d.x * d.y * d.z) as usize];
        for k in 1..d.z - 1 {
            for j in 1..d.y - 1 {
                for i in 1..d.x - 1 {
                    let fine = 2 * i + self.dims.x * (2 * j + self.dims.y * 2 * k);
                    unknown[(i + d.x * (j + d.y * k)) as usize] =
                        self.slot_of_node[fine as usize] != NONE;
                }
            }
        }
        if !unknown.iter().any(|&u| u) {
            return None;
        }
        Some(Self::new(d, &unknown, None))
    }
}

/// The hierarchy for one grid's unknown mask.
#[derive(Debug, Clone)]
pub(super) struct Hierarchy {
    levels: Vec<Level>,
}

/// Outcome of a solve, for diagnostics.
#[derive(Debug, Clone, Copy)]
pub(super) struct SolveReport {
    pub iterations: usize,
}

impl Hierarchy {
    /// Builds the levels from the finest unknown mask and the fine operator's diagonal per
    /// grid node (coarse levels use the plain 7-point Laplacian).
    pub fn new(dims: UVec3, unknown: &[bool], diagonal: &[f64]) -> Self {
        let mut levels = vec![Level::new(dims, unknown, Some(diagonal))];
        while levels.last().is_some_and(|l| l.unknowns() > COARSEST) {
            match levels.last().and_then(Level::coarsen) {
                Some(next) => levels.push(next),
                None => break,
            }
        }
        Self { levels }
    }

    /// Slot of a fine grid node, if it is an unknown.
    pub fn fine_slot(&self, node: usize) -> Option<usize> {
        let s = self.levels[0].slot_of_node[node];
        (s != NONE).then_some(s as usize)
    }

    /// Number of slots of the fine vector (unknowns plus two sentinels).
    pub fn fine_len(&self) -> usize {
        self.levels[0].len()
    }

    /// Solves `L x = b` (L = D − neighbours on the unknowns, D the diagonal) by MG-preconditioned CG, to a
    /// relative residual of `tolerance` per column. Returns the iterations used.
    pub fn solve<const W: usize>(
        &self,
        b: &[[f64; W]],
        x: &mut [[f64; W]],
        tolerance: f64,
        max_iterations: usize,
    ) -> SolveReport {
        let fine = &self.levels[0];
        let n = fine.len();
        x.fill([0.0; W]);
        let mut r = b.to_vec();
        let b_norm = norms(fine, b);
        let mut z = vec![[0.0; W]; n];
        let mut r_f32 = vec![[0.0f32; W]; n];
        let mut z_f32 = vec![[0.0f32; W]; n];
        let mut rz = self.precondition(&r, &mut r_f32, &mut z_f32, &mut z);
        let mut p = z.clone();
        let mut q = vec![[0.0; W]; n];
        for iteration in 0..max_iterations {
            // The products come with the passes that make their vectors (one read fewer each).
            let pq = apply_and_dot(fine, &p, &mut q);
            let alpha: [f64; W] =
                std::array::from_fn(|c| if pq[c] > 0.0 { rz[c] / pq[c] } else { 0.0 });
            let r_norm = step_and_norm(x, &mut r, &alpha, &p, &q).map(f64::sqrt);
            if (0..W).all(|c| r_norm[c] <= tolerance * b_norm[c]) {
                return SolveReport {
                    iterations: iteration + 1,
                };
            }
            let rz_new = self.precondition(&r, &mut r_f32, &mut z_f32, &mut z);
            let beta: [f64; W] =
                std::array::from_fn(|c| if rz[c] > 0.0 { rz_new[c] / rz[c] } else { 0.0 });
            rz = rz_new;
            p.par_iter_mut().zip(z.par_iter()).for_each(|(pi, zi)| {
                for c in 0..W {
                    pi[c] = zi[c] + beta[c] * pi[c];
                }
            });
            zero_sentinels(fine, &mut p);
        }
        SolveReport {
            iterations: max_iterations,
        }
    }

    /// z = M⁻¹ r by one V-cycle in single precision, and r·z per column.
    ///
    /// The preconditioner only has to approximate L⁻¹ to about three digits, which f32 does
    /// with half the memory traffic of f64; CG's own vectors, products and residual stay f64,
    /// so the tolerance still bounds the true residual. Rounding makes M⁻¹ symmetric only to
    /// about 1e-7 relative, which PCG absorbs (measured on the creature's harmonic thighs:
    /// the same 7–8 iterations per batch as the f64 V-cycle).
    fn precondition<const W: usize>(
        &self,
        r: &[[f64; W]],
        r_f32: &mut [[f32; W]],
        z_f32: &mut [[f32; W]],
        z: &mut [[f64; W]],
    ) -> [f64; W] {
        r_f32
            .par_iter_mut()
            .zip(r.par_iter())
            .with_min_len(4096)
            .for_each(|(a, b)| *a = b.map(|v| v as f32));
        self.v_cycle::<W>(0, r_f32, z_f32);
        z.par_iter_mut()
            .zip(z_f32.par_iter().zip(r.par_iter()))
            .with_min_len(4096)
            .fold(
                || [0.0; W],
                |mut dot, (zi, (zs, ri))| {
                    for c in 0..W {
                        zi[c] = f64::from(zs[c]);
                        dot[c] += zi[c] * ri[c];
                    }
                    dot
                },
            )
            .reduce(|| [0.0; W], add_rows)
    }

    /// One symmetric V-cycle from a zero initial guess: `x ≈ L⁻¹ b` on `level`.
    fn v_cycle<const W: usize>(&self, level: usize, b: &[[f32; W]], x: &mut [[f32; W]]) {
        let l = &self.levels[level];
        x.fill([0.0; W]);
        if level + 1 == self.levels.len() {
            for _ in 0..COARSE_SWEEPS {
                half_sweep(l, b, x, true);
                half_sweep(l, b, x, false);
            }
            for _ in 0..COARSE_SWEEPS {
                half_sweep(l, b, x, false);
                half_sweep(l, b, x, true);
            }
            return;
        }
        for _ in 0..SMOOTHING_SWEEPS {
            half_sweep(l, b, x, true);
            half_sweep(l, b, x, false);
        }
        let mut r = vec![[0.0f32; W]; l.len()];
        residual(l, b, x, &mut r);
        let coarse = &self.levels[level + 1];
        let bc = restrict(l, coarse, &r);
        let mut xc = vec![[0.0f32; W]; coarse.len()];
        self.v_cycle::<W>(level + 1, &bc, &mut xc);
        prolong_add(l, coarse, &xc, x);
        for _ in 0..SMOOTHING_SWEEPS {
            half_sweep(l, b, x, false);
            half_sweep(l, b, x, true);
        }
    }
}

/// Over-relaxed Gauss–Seidel on one colour: x_i ← (1 − ω) x_i + ω (b_i + Σ neighbours) / D_i.
fn half_sweep<const W: usize>(l: &Level, b: &[[f32; W]], x: &mut [[f32; W]], red: bool) {
    let split = l.black_start();
    let (red_part, black_part) = x.split_at_mut(split);
    let (written, read, offset, read_offset) = if red {
        (&mut red_part[..l.red], &*black_part, 0, split)
    } else {
        (&mut black_part[..l.len() - split - 1], &*red_part, split, 0)
    };
    written
        .par_iter_mut()
        .enumerate()
        .with_min_len(1024)
        .for_each(|(s, xi)| {
            let slot = s + offset;
            let nb = &l.neighbours[slot];
            let mut acc = b[slot];
            for &m in nb {
                let v = &read[m as usize - read_offset];
                for c in 0..W {
                    acc[c] += v[c];
                }
            }
            let inv = OMEGA_F32 / l.diagonal_f32[slot];
            for c in 0..W {
                xi[c] = (1.0 - OMEGA_F32) * xi[c] + acc[c] * inv;
            }
        });
}

/// r = b − L x in one pass (zero on the sentinels).
fn residual<const W: usize>(l: &Level, b: &[[f32; W]], x: &[[f32; W]], r: &mut [[f32; W]]) {
    r.par_iter_mut()
        .enumerate()
        .with_min_len(1024)
        .for_each(|(s, ri)| {
            if l.is_sentinel(s) {
                *ri = [0.0; W];
                return;
            }
            let d = l.diagonal_f32[s];
            let mut acc: [f32; W] = std::array::from_fn(|c| b[s][c] - d * x[s][c]);
            for &m in &l.neighbours[s] {
                let v = &x[m as usize];
                for c in 0..W {
                    acc[c] += v[c];
                }
            }
            *ri = acc;
        });
}

/// q = L p, and p·q per column in the same pass.
fn apply_and_dot<const W: usize>(l: &Level, p: &[[f64; W]], q: &mut [[f64; W]]) -> [f64; W] {
    q.par_iter_mut()
        .enumerate()
        .with_min_len(1024)
        .fold(
            || [0.0; W],
            |mut dot, (s, qi)| {
                if l.is_sentinel(s) {
                    *qi = [0.0; W];
                    return dot;
                }
                let d = l.diagonal[s];
                let mut acc = p[s].map(|v| d * v);
                for &m in &l.neighbours[s] {
                    let v = &p[m as usize];
                    for c in 0..W {
                        acc[c] -= v[c];
                    }
                }
                for c in 0..W {
                    dot[c] += p[s][c] * acc[c];
                }
                *qi = acc;
                dot
            },
        )
        .reduce(|| [0.0; W], add_rows)
}

/// The CG step x += α p, r −= α q, and r·r per column in the same pass.
fn step_and_norm<const W: usize>(
    x: &mut [[f64; W]],
    r: &mut [[f64; W]],
    alpha: &[f64; W],
    p: &[[f64; W]],
    q: &[[f64; W]],
) -> [f64; W] {
    x.par_iter_mut()
        .zip(r.par_iter_mut())
        .zip(p.par_iter().zip(q.par_iter()))
        .with_min_len(4096)
        .fold(
            || [0.0; W],
            |mut norm, ((xi, ri), (pi, qi))| {
                for c in 0..W {
                    xi[c] += alpha[c] * pi[c];
                    ri[c] -= alpha[c] * qi[c];
                    norm[c] += ri[c] * ri[c];
                }
                norm
            },
        )
        .reduce(|| [0.0; W], add_rows)
}

fn add_rows<const W: usize>(mut a: [f64; W], b: [f64; W]) -> [f64; W] {
    for c in 0..W {
        a[c] += b[c];
    }
    a
}

/// Restriction ½ Pᵀ r, gathered per coarse node from its 27 fine neighbours.
fn restrict<const W: usize>(fine: &Level, coarse: &Level, r: &[[f32; W]]) -> Vec<[f32; W]> {
    let fd = fine.dims;
    (0..coarse.len())
        .into_par_iter()
        .with_min_len(256)
        .map(|s| {
            let node = coarse.node_of_slot[s];
            let mut acc = [0.0; W];
            if node == NONE {
                return acc;
            }
            let cd = coarse.dims;
            let (i, j, k) = (node % cd.x, (node / cd.x) % cd.y, node / (cd.x * cd.y));
            for dk in 0..3u32 {
                for dj in 0..3u32 {
                    for di in 0..3u32 {
                        let (fi, fj, fk) = (2 * i + di - 1, 2 * j + dj - 1, 2 * k + dk - 1);
                        let fs = fine.slot_of_node[(fi + fd.x * (fj + fd.y * fk)) as usize];
                        if fs == NONE {
                            continue;
                        }
                        let w = 0.5 * weight(di) * weight(dj) * weight(dk);
                        for c in 0..W {
                            acc[c] += w * r[fs as usize][c];
                        }
                    }
                }
            }
            acc
        })
        .collect()
}

/// x += P xc: trilinear interpolation of the coarse correction onto fine unknowns.
fn prolong_add<const W: usize>(fine: &Level, coarse: &Level, xc: &[[f32; W]], x: &mut [[f32; W]]) {
    let cd = coarse.dims;
    let fd = fine.dims;
    x.par_iter_mut()
        .enumerate()
        .with_min_len(1024)
        .for_each(|(s, xi)| {
            let node = fine.node_of_slot[s];
            if node == NONE {
                return;
            }
            let (i, j, k) = (node % fd.x, (node / fd.x) % fd.y, node / (fd.x * fd.y));
            for (ci, wi) in parents(i) {
                for (cj, wj) in parents(j) {
                    for (ck, wk) in parents(k) {
                        if ci >= cd.x || cj >= cd.y || ck >= cd.z {
                            continue;
                        }
                        let cs = coarse.slot_of_node[(ci + cd.x * (cj + cd.y * ck)) as usize];
                        if cs == NONE {
                            continue;
                        }
                        let w = wi * wj * wk;
                        for c in 0..W {
                            xi[c] += w * xc[cs as usize][c];
                        }
                    }
                }
            }
        });
}

/// Coarse parents of fine index `i` along one axis with their weights.
fn parents(i: u32) -> impl Iterator<Item = (u32, f32)> {
    let even = i.is_multiple_of(2);
    let list = if even {
        [(i / 2, 1.0), (u32::MAX, 0.0)]
    } else {
        [(i / 2, 0.5), (i / 2 + 1, 0.5)]
    };
    list.into_iter().filter(|(c, _)| *c != u32::MAX)
}

/// Weight of fine offset `d − 1` ∈ {−1, 0, 1} in the transpose of trilinear prolongation.
fn weight(d: u32) -> f32 {
    if d == 1 { 1.0 } else { 0.5 }
}

fn zero_sentinels<const W: usize>(l: &Level, v: &mut [[f64; W]]) {
    v[l.red] = [0.0; W];
    let last = l.len() - 1;
    v[last] = [0.0; W];
}

fn dots<const W: usize>(l: &Level, a: &[[f64; W]], b: &[[f64; W]]) -> [f64; W] {
    let _ = l;
    a.par_iter()
        .zip(b.par_iter())
        .with_min_len(4096)
        .fold(
            || [0.0; W],
            |mut acc, (x, y)| {
                for c in 0..W {
                    acc[c] += x[c] * y[c];
                }
                acc
            },
        )
        .reduce(
            || [0.0; W],
            |mut s, t| {
                for c in 0..W {
                    s[c] += t[c];
                }
                s
            },
        )
}

fn norms<const W: usize>(l: &Level, a: &[[f64; W]]) -> [f64; W] {
    dots(l, a, a).map(f64::sqrt)
}

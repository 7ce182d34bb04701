//! The regular grid local to a cage on which harmonic coordinates are discretised: which
//! nodes are unknowns (strictly inside), where the grid lines between unknowns and the rest
//! cross the cage (for the ghost-value boundary condition), and which outside nodes carry
//! values for interpolation (the hat functions at their closest cage point).

use glam::{DVec3, UVec3};
use rayon::prelude::*;

use crate::cage::Cage;

/// Role of a grid node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum NodeRole {
    /// Far outside: never read.
    Unused,
    /// Strictly inside: an unknown of the Laplace system.
    Unknown,
    /// Dirichlet node, with its index into [`CageGrid::boundary`].
    Boundary(u32),
}

/// Dirichlet data of a boundary node: the hat functions at its closest cage point.
#[derive(Debug, Clone, Copy)]
pub(super) struct BoundaryValue {
    pub triangle: u32,
    pub bary: [f64; 3],
}

impl BoundaryValue {
    /// The hat function of cage vertex `vertex` here: its barycentric weight in the closest
    /// triangle (of `triangles`, the cage's), 0 where the triangle does not use it.
    pub fn hat(&self, triangles: &[[u32; 3]], vertex: usize) -> f64 {
        let tri = triangles[self.triangle as usize];
        (0..3)
            .filter(|&k| tri[k] as usize == vertex)
            .map(|k| self.bary[k])
            .sum()
    }
}

/// A cage's grid: geometry and node roles.
#[derive(Debug, Clone)]
pub(super) struct CageGrid {
    pub origin: DVec3,
    pub spacing: f64,
    pub dims: UVec3,
    pub roles: Vec<NodeRole>,
    pub boundary: Vec<BoundaryValue>,
    pub unknown_count: usize,
    /// Cage crossings between unknowns and their non-unknown neighbours (Gibou et al. 2002).
    pub interfaces: Vec<Interface>,
}

/// Where the segment from an unknown node to a non-unknown neighbour crosses the cage: at
/// θ·h from the unknown, with the hat functions' values there given by a triangle's
/// barycentric coordinates.
#[derive(Debug, Clone, Copy)]
pub(super) struct Interface {
    pub node: u32,
    pub theta: f64,
    pub value: BoundaryValue,
}

impl CageGrid {
    /// Linear index of node `(i, j, k)`.
    pub fn index(&self, i: u32, j: u32, k: u32) -> usize {
        (i + self.dims.x * (j + self.dims.y * k)) as usize
    }

    /// Grid with `resolution` cells along the cage's longest side, padded by at least two
    /// cells, centred on the cage's bounding box: a cage turned by a multiple of 90° or
    /// mirrored about its box's centre gets the same grid turned or mirrored, so congruent
    /// join cages can share one solve (`star::bind`).
    pub fn build(cage: &Cage, resolution: u32) -> Self {
        let (lo, hi) = cage.bounds();
        let extent = hi - lo;
        let spacing = extent.max_element() / resolution.max(2) as f64;
        let cells = (extent / spacing).ceil().as_uvec3() + UVec3::splat(4);
        let origin = 0.5 * (lo + hi) - 0.5 * cells.as_dvec3() * spacing;
        let dims = cells + UVec3::ONE;
        let lines = [0, 1, 2].map(|axis| axis_crossings(cage, origin, spacing, dims, axis));
        let mut inside = classify_inside(&lines[0], origin, spacing, dims);
        exclude_on_cage(&mut inside, &lines, origin, spacing, dims);
        let mut grid = Self {
            origin,
            spacing,
            dims,
            roles: vec![NodeRole::Unused; inside.len()],
            boundary: Vec::new(),
            unknown_count: 0,
            interfaces: Vec::new(),
        };
        // Unknowns: inside nodes (padding guarantees none on the grid border).
        for (role, &is_inside) in grid.roles.iter_mut().zip(&inside) {
            if is_inside {
                *role = NodeRole::Unknown;
            }
        }
        grid.unknown_count = inside.iter().filter(|&&b| b).count();
        // Dirichlet band: non-inside nodes in the 26-neighbourhood of an inside node (query
        // points' cell corners outside it are evaluated by the bind).
        let mut band = vec![false; inside.len()];
        let d = dims.as_ivec3();
        for k in 0..d.z {
            for j in 0..d.y {
                for i in 0..d.x {
                    if !inside[grid.index(i as u32, j as u32, k as u32)] {
                        continue;
                    }
                    for dk in -1..=1 {
                        for dj in -1..=1 {
                            for di in -1..=1 {
                                let n =
                                    grid.index((i + di) as u32, (j + dj) as u32, (k + dk) as u32);
                                band[n] |= !inside[n];
                            }
                        }
                    }
                }
            }
        }
        let band_nodes: Vec<usize> = (0..band.len()).filter(|&n| band[n]).collect();
        grid.boundary = band_nodes
            .par_iter()
            .map(|&n| {
                let (t, bary, _) = cage.closest_point(grid.position_of(n));
                BoundaryValue {
                    triangle: t as u32,
                    bary,
                }
            })
            .collect();
        for (b, &n) in band_nodes.iter().enumerate() {
            grid.roles[n] = NodeRole::Boundary(b as u32);
        }
        grid.interfaces = grid.find_interfaces(&lines, &inside);
        grid
    }

    /// For every unknown and each of its 6 neighbours that is not an unknown, the first cage
    /// crossing along the grid line between them.
    fn find_interfaces(&self, lines: &[Vec<Vec<Crossing>>; 3], inside: &[bool]) -> Vec<Interface> {
        let d = self.dims.to_array();
        let o = self.origin.to_array();
        let h = self.spacing;
        let unknowns: Vec<usize> = (0..inside.len()).filter(|&n| inside[n]).collect();
        unknowns
            .par_iter()
            .flat_map_iter(|&n| {
                let ijk = self.coords_of(n);
                let mut found = Vec::new();
                for axis in 0..3 {
                    let (b, c) = ((axis + 1) % 3, (axis + 2) % 3);
                    let line = &lines[axis][(ijk[b] + d[b] * ijk[c]) as usize];
                    let x = o[axis] + ijk[axis] as f64 * h;
                    for step in [-1i32, 1] {
                        let mut nb = ijk;
                        nb[axis] = (nb[axis] as i32 + step) as u32;
                        let m = self.index(nb[0], nb[1], nb[2]);
                        if inside[m] {
                            continue;
                        }
                        // First crossing from x towards the neighbour, within one cell.
                        let hit = if step > 0 {
                            line.iter().find(|cr| cr.at > x)
                        } else {
                            line.iter().rev().find(|cr| cr.at < x)
                        };
                        let interface = match hit {
                            Some(cr) if (cr.at - x).abs() <= h * (1.0 + NUDGE) => Interface {
                                node: n as u32,
                                theta: ((cr.at - x).abs() / h).clamp(MIN_THETA, 1.0),
                                value: BoundaryValue {
                                    triangle: cr.triangle,
                                    bary: cr.bary,
                                },
                            },
                            // Round-off disagreement between lines: use the neighbour itself.
                            _ => match self.roles[m] {
                                NodeRole::Boundary(bi) => Interface {
                                    node: n as u32,
                                    theta: 1.0,
                                    value: self.boundary[bi as usize],
                                },
                                _ => continue,
                            },
                        };
                        found.push(interface);
                    }
                }
                found
            })
            .collect()
    }

    /// Node indices `[i, j, k]` of node `n`.
    pub fn coords_of(&self, n: usize) -> [u32; 3] {
        let n = n as u32;
        [
            n % self.dims.x,
            (n / self.dims.x) % self.dims.y,
            n / (self.dims.x * self.dims.y),
        ]
    }

    /// Position of node `n`.
    pub fn position_of(&self, n: usize) -> DVec3 {
        self.origin + UVec3::from_array(self.coords_of(n)).as_dvec3() * self.spacing
    }

    /// The cell containing `p` (clamped into the grid) and `p`'s local coordinates in it.
    pub fn cell_of(&self, p: DVec3) -> (UVec3, DVec3) {
        let local = (p - self.origin) / self.spacing;
        let max_cell = (self.dims - UVec3::splat(2)).as_dvec3();
        let cell = local.floor().clamp(DVec3::ZERO, max_cell);
        let frac = (local - cell).clamp(DVec3::ZERO, DVec3::ONE);
        (cell.as_uvec3(), frac)
    }
}

/// Where a grid line crosses the cage.
#[derive(Debug, Clone, Copy)]
struct Crossing {
    /// Coordinate along the line's axis.
    at: f64,
    /// +1 entering the cage (going towards +axis), −1 leaving.
    entering: i32,
    triangle: u32,
    bary: [f64; 3],
}

/// Crossings of every grid line along `axis` (sorted), lines indexed by the node indices of the
/// two other axes (in cyclic order: for x, index j + ny·k). Lines are nudged by a tiny
/// irrational amount so they do not run exactly through edges of grid-aligned cages.
fn axis_crossings(
    cage: &Cage,
    origin: DVec3,
    spacing: f64,
    dims: UVec3,
    axis: usize,
) -> Vec<Vec<Crossing>> {
    let (b, c) = ((axis + 1) % 3, (axis + 2) % 3);
    let d = dims.to_array();
    let o = origin.to_array();
    let nudge = spacing * NUDGE;
    let positions = cage.positions();
    (0..d[b] * d[c])
        .into_par_iter()
        .map(|line| {
            let (ib, ic) = (line % d[b], line / d[b]);
            let (nudge_b, nudge_c) = (
                nudge * std::f64::consts::SQRT_2,
                nudge * std::f64::consts::PI,
            );
            let (y_exact, z_exact) = (o[b] + ib as f64 * spacing, o[c] + ic as f64 * spacing);
            let (y, z) = (y_exact + nudge_b, z_exact + nudge_c);
            let mut crossings = Vec::new();
            for (t, tri) in cage.triangles().iter().enumerate() {
                let [pa, pb, pc] = tri.map(|v| positions[v as usize].to_array());
                // Barycentric coordinates of (y, z) in the triangle's projection on (b, c).
                let det = (pb[b] - pa[b]) * (pc[c] - pa[c]) - (pc[b] - pa[b]) * (pb[c] - pa[c]);
                if det == 0.0 {
                    continue;
                }
                let wb = ((y - pa[b]) * (pc[c] - pa[c]) - (pc[b] - pa[b]) * (z - pa[c])) / det;
                let wc = ((pb[b] - pa[b]) * (z - pa[c]) - (y - pa[b]) * (pb[c] - pa[c])) / det;
                let wa = 1.0 - wb - wc;
                if wa < 0.0 || wb < 0.0 || wc < 0.0 {
                    continue;
                }
                // The nudged line decides which triangle is crossed. Where the exact line
                // crosses it too (on an edge or a vertex, say), the position and the hat values
                // are the exact line's, so that a mirrored cage gets mirrored values (the nudge
                // does not mirror) and symmetric cages can share solves. Elsewhere the exact
                // line misses the triangle, whose projection can be thin enough that its
                // barycentric coordinates there are far outside [0, 1]: the nudged line's stay.
                let (y, z) = (y_exact, z_exact);
                let wb_exact =
                    ((y - pa[b]) * (pc[c] - pa[c]) - (pc[b] - pa[b]) * (z - pa[c])) / det;
                let wc_exact =
                    ((pb[b] - pa[b]) * (z - pa[c]) - (y - pa[b]) * (pb[c] - pa[c])) / det;
                let wa_exact = 1.0 - wb_exact - wc_exact;
                let [wa, wb, wc] = if [wa_exact, wb_exact, wc_exact]
                    .iter()
                    .all(|&w| w >= -EXACT_LINE_SLACK)
                {
                    [wa_exact, wb_exact, wc_exact]
                } else {
                    [wa, wb, wc]
                };
                crossings.push(Crossing {
                    at: wa * pa[axis] + wb * pb[axis] + wc * pc[axis],
                    // det is the normal's component along the axis: entering where it is < 0.
                    entering: if det < 0.0 { 1 } else { -1 },
                    triangle: t as u32,
                    bary: [wa, wb, wc],
                });
            }
            crossings.sort_by(|p, q| p.at.total_cmp(&q.at));
            crossings
        })
        .collect()
}

/// Smallest fraction of a cell between an unknown and the cage: bounds the diagonal (1/θ) of
/// the ghost-value discretisation, at an error far below the discretisation's.
const MIN_THETA: f64 = 1e-3;

/// Nodes on the cage seen along y or z lines (faces parallel to x, which x lines never cross)
/// are not unknowns: they become Dirichlet nodes with their exact values.
fn exclude_on_cage(
    inside: &mut [bool],
    lines: &[Vec<Vec<Crossing>>; 3],
    origin: DVec3,
    spacing: f64,
    dims: UVec3,
) {
    let nudge = spacing * NUDGE * 4.0;
    let d = dims.to_array();
    let o = origin.to_array();
    inside.par_iter_mut().enumerate().for_each(|(n, flag)| {
        if !*flag {
            return;
        }
        let n = n as u32;
        let ijk = [n % d[0], (n / d[0]) % d[1], n / (d[0] * d[1])];
        for axis in 1..3 {
            let (b, c) = ((axis + 1) % 3, (axis + 2) % 3);
            let x = o[axis] + ijk[axis] as f64 * spacing;
            let line = &lines[axis][(ijk[b] + d[b] * ijk[c]) as usize];
            let k = line.partition_point(|cr| cr.at < x);
            let near = |i: usize| line.get(i).is_some_and(|cr| (cr.at - x).abs() < nudge);
            if near(k) || (k > 0 && near(k - 1)) {
                *flag = false;
                return;
            }
        }
    });
}

/// How far below 0 the exact line's barycentric coordinates in a triangle the nudged line
/// crosses may be and still count as crossing it (round-off where the line runs through an
/// edge or a vertex).
const EXACT_LINE_SLACK: f64 = 1e-12;

/// Relative nudge of grid lines and tolerance of "on the cage" along them.
const NUDGE: f64 = 1e-7;

/// Inside/outside of every node from the signed crossings of its x line; nodes on the cage
/// (within the nudge) count as outside: they are Dirichlet nodes with exact values.
fn classify_inside(
    x_lines: &[Vec<Crossing>],
    origin: DVec3,
    spacing: f64,
    dims: UVec3,
) -> Vec<bool> {
    let nudge = spacing * NUDGE;
    x_lines
        .par_iter()
        .flat_map_iter(|crossings| {
            let mut inside = vec![false; dims.x as usize];
            let mut winding = 0;
            let mut next = 0;
            for (i, flag) in inside.iter_mut().enumerate() {
                let x = origin.x + i as f64 * spacing;
                while next < crossings.len() && crossings[next].at <= x {
                    winding += crossings[next].entering;
                    next += 1;
                }
                let near_next = next < crossings.len() && crossings[next].at - x < nudge;
                let near_previous = next > 0 && x - crossings[next - 1].at < nudge;
                *flag = winding > 0 && !near_next && !near_previous;
            }
            inside
        })
        .collect()
}

//! The solved harmonic functions of one cage: its grid and, for every batch of `K` cage
//! vertices, each unknown node's values. They depend only on the cage and the settings, never
//! on the points bound, so a re-bind of other points of an unchanged cage (a rest edit nearby,
//! a change of h) reads them from [`cached_field`] instead of solving again.

use std::sync::{Arc, Mutex};

use glam::DVec3;

use super::HarmonicSettings;
use super::grid::{CageGrid, NodeRole};
use super::multigrid::{Hierarchy, K, Row};
use crate::cage::Cage;
use crate::coords::{BindControl, CoordError};

/// One cage's solution.
pub(super) struct HarmonicField {
    /// The grid (unknowns, and the Dirichlet band of their 26-neighbourhood).
    pub grid: CageGrid,
    /// Slot of each grid node in a batch (`u32::MAX` where the node is not an unknown).
    slot_of_node: Vec<u32>,
    /// Per batch of `K` vertices (vertex `K·batch + c` in column c), every slot's values.
    batches: Vec<Vec<Row>>,
}

impl HarmonicField {
    /// Values of the unknown `node` in `batch`, if it is an unknown.
    pub fn unknown_value(&self, batch: usize, node: usize) -> Option<Row> {
        let slot = *self.slot_of_node.get(node)?;
        (slot != u32::MAX).then(|| self.batches[batch][slot as usize])
    }

    /// Memory held, in bytes.
    fn bytes(&self) -> usize {
        self.slot_of_node.len() * 4
            + self.batches.iter().map(Vec::len).sum::<usize>() * std::mem::size_of::<Row>()
            + self.grid.roles.len() * std::mem::size_of::<NodeRole>()
            + self.grid.boundary.len() * 32
            + self.grid.interfaces.len() * 48
    }
}

/// Solves the harmonic functions of every vertex of `cage` (Joshi et al. 2007) on its grid,
/// batch by batch (multigrid-preconditioned CG).
fn solve_field(
    cage: &Cage,
    settings: &HarmonicSettings,
    control: &BindControl,
) -> Result<HarmonicField, CoordError> {
    let grid = CageGrid::build(cage, settings.resolution);
    control.check()?;
    let unknown: Vec<bool> = grid.roles.iter().map(|r| *r == NodeRole::Unknown).collect();
    // Gibou et al. 2002: a neighbour across the cage at θh is replaced by the ghost value
    // u_G = (u_Γ + (θ − 1) u_i) / θ, which changes the row of u_i to
    // (n_unknown + Σ 1/θ) u_i − Σ u_j = Σ u_Γ / θ: symmetric, and exact for linear functions.
    let mut diagonal: Vec<f64> = (0..unknown.len())
        .map(|n| {
            if unknown[n] {
                (6 - grid_boundary_neighbours(&grid, &unknown, n)) as f64
            } else {
                0.0
            }
        })
        .collect();
    for interface in &grid.interfaces {
        diagonal[interface.node as usize] += 1.0 / interface.theta;
    }
    let hierarchy = Hierarchy::new(grid.dims, &unknown, &diagonal);
    let triangles = cage.triangles();
    let hat_at = |value: &super::grid::BoundaryValue, vertex: usize| value.hat(triangles, vertex);
    let links: Vec<(usize, f64, &super::grid::BoundaryValue)> = grid
        .interfaces
        .iter()
        .filter_map(|i| {
            Some((
                hierarchy.fine_slot(i.node as usize)?,
                1.0 / i.theta,
                &i.value,
            ))
        })
        .collect();
    let n = cage.vertex_count();
    let mut batches = Vec::with_capacity(n.div_ceil(K));
    for first in (0..n).step_by(K) {
        control.check()?;
        let columns = (n - first).min(K);
        let batch = Batch {
            hierarchy: &hierarchy,
            links: &links,
            first,
            columns,
            hat_at: &hat_at,
        };
        // A last batch of few vertices is solved that narrow (the solve's cost follows its
        // width): 42 vertices were six batches of eight, the sixth for two.
        let x = match columns {
            1..=2 if !always_wide() => batch.solve::<2>(settings)?,
            3..=4 if !always_wide() => batch.solve::<4>(settings)?,
            _ => batch.solve::<K>(settings)?,
        };
        batches.push(x);
    }
    let slot_of_node = (0..grid.roles.len())
        .map(|node| hierarchy.fine_slot(node).map_or(u32::MAX, |s| s as u32))
        .collect();
    Ok(HarmonicField {
        grid,
        slot_of_node,
        batches,
    })
}

#[cfg(test)]
thread_local! {
    /// Tests solve every batch `K` wide on this thread, to compare with the narrow solves.
    static ALWAYS_WIDE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether every batch is solved `K` wide (only a test asks).
fn always_wide() -> bool {
    #[cfg(test)]
    return ALWAYS_WIDE.with(std::cell::Cell::get);
    #[cfg(not(test))]
    false
}

/// One batch of a field's solve: the cage vertices `first..first + columns`.
struct Batch<'a, H: Fn(&super::grid::BoundaryValue, usize) -> f64> {
    hierarchy: &'a Hierarchy,
    /// (fine slot, 1/θ, boundary value) of each interface node.
    links: &'a [(usize, f64, &'a super::grid::BoundaryValue)],
    first: usize,
    columns: usize,
    hat_at: &'a H,
}

impl<H: Fn(&super::grid::BoundaryValue, usize) -> f64> Batch<'_, H> {
    /// Solves the batch `W` right-hand sides wide (W ≥ columns) and returns its values in
    /// rows of `K` (columns past the batch's zero).
    fn solve<const W: usize>(&self, settings: &HarmonicSettings) -> Result<Vec<Row>, CoordError> {
        let len = self.hierarchy.fine_len();
        let mut b = vec![[0.0; W]; len];
        for &(slot, inv_theta, value) in self.links {
            for c in 0..self.columns.min(W) {
                b[slot][c] += inv_theta * (self.hat_at)(value, self.first + c);
            }
        }
        let mut x = vec![[0.0; W]; len];
        let report = self.hierarchy.solve(
            &b,
            &mut x,
            settings.tolerance,
            settings.max_iterations as usize,
        );
        if report.iterations >= settings.max_iterations as usize {
            return Err(CoordError::NotConverged {
                iterations: report.iterations,
            });
        }
        Ok(x.iter()
            .map(|v| std::array::from_fn(|c| v.get(c).copied().unwrap_or(0.0)))
            .collect())
    }
}

/// Number of the 6 neighbours of unknown `n` that are not unknowns.
fn grid_boundary_neighbours(grid: &CageGrid, unknown: &[bool], n: usize) -> usize {
    let (sx, sy) = (1usize, grid.dims.x as usize);
    let sz = sy * grid.dims.y as usize;
    [n - sx, n + sx, n - sy, n + sy, n - sz, n + sz]
        .iter()
        .filter(|&&m| !unknown[m])
        .count()
}

/// What a field is the solution for: the cage's positions and triangles, bit for bit, and the
/// settings.
#[derive(PartialEq)]
struct FieldKey {
    positions: Vec<[u64; 3]>,
    triangles: Vec<[u32; 3]>,
    resolution: u32,
    tolerance: u64,
    max_iterations: u32,
}

impl FieldKey {
    fn new(cage: &Cage, settings: &HarmonicSettings) -> Self {
        Self {
            positions: cage
                .positions()
                .iter()
                .map(|p: &DVec3| p.to_array().map(f64::to_bits))
                .collect(),
            triangles: cage.triangles().to_vec(),
            resolution: settings.resolution,
            tolerance: settings.tolerance.to_bits(),
            max_iterations: settings.max_iterations,
        }
    }
}

struct CacheEntry {
    key: FieldKey,
    field: Arc<HarmonicField>,
    bytes: usize,
    last_used: u64,
}

/// Solved fields kept for re-binds, least recently used dropped first beyond this many bytes.
const CACHE_BYTES: usize = 512 << 20;

struct Cache {
    entries: Vec<CacheEntry>,
    clock: u64,
    hits: u64,
}

static CACHE: Mutex<Cache> = Mutex::new(Cache {
    entries: Vec::new(),
    clock: 0,
    hits: 0,
});

/// The solved field of `cage` under `settings`: from the process's cache when this cage (bit
/// for bit) was solved under these settings before, else solved and kept (within
/// [`CACHE_BYTES`]). A solve that fails or is cancelled keeps nothing.
pub(super) fn cached_field(
    cage: &Cage,
    settings: &HarmonicSettings,
    control: &BindControl,
) -> Result<Arc<HarmonicField>, CoordError> {
    let key = FieldKey::new(cage, settings);
    {
        let mut cache = CACHE
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        cache.clock += 1;
        let now = cache.clock;
        if let Some(entry) = cache.entries.iter_mut().find(|e| e.key == key) {
            entry.last_used = now;
            let field = Arc::clone(&entry.field);
            cache.hits += 1;
            return Ok(field);
        }
    }
    let field = Arc::new(solve_field(cage, settings, control)?);
    #[cfg(test)]
    SOLVED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
        .push(FieldKey::new(cage, settings));
    let bytes = field.bytes();
    let mut cache = CACHE
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    cache.clock += 1;
    let now = cache.clock;
    if bytes <= CACHE_BYTES && !cache.entries.iter().any(|e| e.key == key) {
        while cache.entries.iter().map(|e| e.bytes).sum::<usize>() + bytes > CACHE_BYTES {
            let Some(oldest) = (0..cache.entries.len()).min_by_key(|&i| cache.entries[i].last_used)
            else {
                break;
            };
            cache.entries.swap_remove(oldest);
        }
        cache.entries.push(CacheEntry {
            key,
            field: Arc::clone(&field),
            bytes,
            last_used: now,
        });
    }
    Ok(field)
}

/// Drops every solved field (a benchmark times a bind from scratch after it).
pub(crate) fn clear_cache() {
    CACHE
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
        .entries
        .clear();
}

/// Fields served from the cache so far in this process (for tests).
#[cfg(test)]
pub(crate) fn cache_hits() -> u64 {
    CACHE
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
        .hits
}

/// Every field solved so far in this process (for tests).
#[cfg(test)]
static SOLVED: Mutex<Vec<FieldKey>> = Mutex::new(Vec::new());

/// How many times `cage`'s field under `settings` was solved in this process (for tests: a
/// test that counts picks settings no other test uses, since tests share the process).
#[cfg(test)]
pub(crate) fn solves_of(cage: &Cage, settings: &HarmonicSettings) -> usize {
    let key = FieldKey::new(cage, settings);
    SOLVED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
        .iter()
        .filter(|k| **k == key)
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A prism over a regular `n`-gon: 2n vertices.
    fn prism(n: usize) -> Cage {
        let ring = |z: f64| {
            (0..n).map(move |k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                DVec3::new(a.cos(), a.sin(), z)
            })
        };
        let positions: Vec<DVec3> = ring(0.0).chain(ring(1.5)).collect();
        let n32 = n as u32;
        let mut faces: Vec<Vec<u32>> = vec![(0..n32).rev().collect(), (n32..2 * n32).collect()];
        for k in 0..n32 {
            let j = (k + 1) % n32;
            faces.push(vec![k, j, j + n32, k + n32]);
        }
        Cage::from_polygons(positions, faces).unwrap()
    }

    /// A cage's last batch of two or four vertices, solved that narrow, gives the values of
    /// solving it eight wide, bit for bit (each column's CG is the same arithmetic).
    #[test]
    fn a_narrow_last_batch_gives_the_wide_batch_s_values() {
        let settings = HarmonicSettings {
            resolution: 14,
            ..HarmonicSettings::default()
        };
        let control = BindControl::default();
        for n in [5, 6] {
            let cage = prism(n); // 10 and 12 vertices: a last batch of 2 and of 4
            let narrow = solve_field(&cage, &settings, &control).unwrap();
            ALWAYS_WIDE.with(|wide| wide.set(true));
            let wide = solve_field(&cage, &settings, &control).unwrap();
            ALWAYS_WIDE.with(|wide| wide.set(false));
            assert_eq!(narrow.batches.len(), 2);
            assert_eq!(narrow.batches, wide.batches, "{n}-gon prism");
            assert!(narrow.batches[1].iter().any(|row| row[1] != 0.0));
        }
    }
}

//! The solved harmonic functions of one cage: its grid and, for every batch of `K` cage
//! vertices, each unknown node's values. They depend only on the cage and the settings, never
//! on the points bound, so a re-bind of other points of an unchanged cage (a rest edit nearby,
//! a change of h) reads them from [`cached_field`] instead of solving again.

use std::sync::{Arc, Mutex};

use glam::DVec3;
use rayon::prelude::*;

use super::HarmonicSettings;
use super::grid::{CageGrid, NodeRole};
use super::multigrid::{Hierarchy, K, Row};
use super::symmetry::Orbits;
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
    /// How many vertices' functions were solved; the others came from symmetries (read by
    /// the tests that count solves).
    #[cfg_attr(not(test), expect(dead_code))]
    solved_vertices: usize,
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
    let orbits = if use_symmetry() {
        Orbits::find(cage, &grid, &unknown, &diagonal)
    } else {
        Orbits::none(cage.vertex_count())
    };
    let mut solved = Vec::with_capacity(orbits.solved.len().div_ceil(K));
    for vertices in orbits.solved.chunks(K) {
        control.check()?;
        let batch = Batch {
            hierarchy: &hierarchy,
            links: &links,
            vertices,
            hat_at: &hat_at,
        };
        // A last batch of few vertices is solved that narrow (the solve's cost follows its
        // width): 42 vertices were six batches of eight, the sixth for two.
        let x = match vertices.len() {
            1..=2 if !always_wide() => batch.solve::<2>(settings)?,
            3..=4 if !always_wide() => batch.solve::<4>(settings)?,
            _ => batch.solve::<K>(settings)?,
        };
        solved.push(x);
    }
    let slot_of_node: Vec<u32> = (0..grid.roles.len())
        .map(|node| hierarchy.fine_slot(node).map_or(u32::MAX, |s| s as u32))
        .collect();
    let solved_vertices = orbits.solved.len();
    let batches = if orbits.is_trivial() {
        solved
    } else {
        derive_batches(&orbits, &solved, &grid, &slot_of_node, hierarchy.fine_len())
    };
    Ok(HarmonicField {
        grid,
        slot_of_node,
        batches,
        solved_vertices,
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

/// Every cage vertex's values, batch by batch in vertex order, from the solved vertices'
/// values and the symmetries that take them to the others.
fn derive_batches(
    orbits: &Orbits,
    solved: &[Vec<Row>],
    grid: &CageGrid,
    slot_of_node: &[u32],
    len: usize,
) -> Vec<Vec<Row>> {
    // Per symmetry, the slot each slot reads from.
    let mut preimage_slot: Vec<Vec<u32>> = (0..orbits.symmetry_count())
        .into_par_iter()
        .map(|g| {
            let mut from = vec![u32::MAX; len];
            for (node, &slot) in slot_of_node.iter().enumerate() {
                if let Some(entry) = from.get_mut(slot as usize) {
                    *entry = orbits
                        .preimage_node(g, grid.dims, node)
                        .and_then(|m| slot_of_node.get(m).copied())
                        .unwrap_or(u32::MAX);
                }
            }
            from
        })
        .collect();
    // The solved vertices read their own slots.
    preimage_slot.push((0..len as u32).collect());
    let identity = preimage_slot.len() - 1;
    let n = orbits.vertex_count();
    let sources: Vec<(usize, usize)> = (0..n)
        .map(|j| {
            orbits
                .source(j)
                .map_or((usize::MAX, identity), |(r, g)| (r, g.unwrap_or(identity)))
        })
        .collect();
    (0..n.div_ceil(K))
        .into_par_iter()
        .map(|batch| {
            let mut rows = vec![[0.0; K]; len];
            let columns = &sources[K * batch..(K * batch + K).min(n)];
            for (c, &(r, g)) in columns.iter().enumerate() {
                let (Some(values), Some(from)) = (solved.get(r / K), preimage_slot.get(g)) else {
                    continue;
                };
                for (row, &f) in rows.iter_mut().zip(from) {
                    row[c] = values.get(f as usize).map_or(0.0, |v| v[r % K]);
                }
            }
            rows
        })
        .collect()
}

/// Whether symmetries may stand in for solves (a test compares with solving every vertex).
fn use_symmetry() -> bool {
    #[cfg(test)]
    return !SOLVE_EVERY_VERTEX.with(std::cell::Cell::get);
    #[cfg(not(test))]
    true
}

#[cfg(test)]
thread_local! {
    /// Tests solve every vertex on this thread, to compare with the derived functions.
    static SOLVE_EVERY_VERTEX: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// One batch of a field's solve: the cage vertices `vertices` (at most `K`).
struct Batch<'a, H: Fn(&super::grid::BoundaryValue, usize) -> f64> {
    hierarchy: &'a Hierarchy,
    /// (fine slot, 1/θ, boundary value) of each interface node.
    links: &'a [(usize, f64, &'a super::grid::BoundaryValue)],
    vertices: &'a [usize],
    hat_at: &'a H,
}

impl<H: Fn(&super::grid::BoundaryValue, usize) -> f64> Batch<'_, H> {
    /// Solves the batch `W` right-hand sides wide (W ≥ columns) and returns its values in
    /// rows of `K` (columns past the batch's zero).
    fn solve<const W: usize>(&self, settings: &HarmonicSettings) -> Result<Vec<Row>, CoordError> {
        let len = self.hierarchy.fine_len();
        let mut b = vec![[0.0; W]; len];
        for &(slot, inv_theta, value) in self.links {
            for (c, &vertex) in self.vertices.iter().take(W).enumerate() {
                b[slot][c] += inv_theta * (self.hat_at)(value, vertex);
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
        .push((FieldKey::new(cage, settings), field.solved_vertices));
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

/// Every field solved so far in this process, with how many functions each solved (for tests).
#[cfg(test)]
static SOLVED: Mutex<Vec<(FieldKey, usize)>> = Mutex::new(Vec::new());

/// How many times `cage`'s field under `settings` was solved in this process (for tests: a
/// test that counts picks settings no other test uses, since tests share the process).
#[cfg(test)]
pub(crate) fn solves_of(cage: &Cage, settings: &HarmonicSettings) -> usize {
    let key = FieldKey::new(cage, settings);
    SOLVED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
        .iter()
        .filter(|(k, _)| *k == key)
        .count()
}

/// How many of `cage`'s functions its last solve under `settings` solved (the others came
/// from its symmetries), if it was solved in this process (for tests).
#[cfg(test)]
pub(crate) fn functions_solved_of(cage: &Cage, settings: &HarmonicSettings) -> Option<usize> {
    let key = FieldKey::new(cage, settings);
    SOLVED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
        .iter()
        .rev()
        .find(|(k, _)| *k == key)
        .map(|(_, solved)| *solved)
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
        SOLVE_EVERY_VERTEX.with(|every| every.set(true));
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
        SOLVE_EVERY_VERTEX.with(|every| every.set(false));
    }

    /// A box from `lo` to `hi` whose faces are fans of four triangles around a vertex at
    /// each face's centre (so its triangles have every symmetry of the box): 8 corners, then
    /// the 6 face centres.
    fn centred_box(lo: DVec3, hi: DVec3) -> Cage {
        let corners = crate::cage::shapes::cuboid(lo, hi);
        let mut positions = corners.positions().to_vec();
        let mut triangles = Vec::new();
        for face in crate::cage::shapes::BOX_FACES {
            let centre = face.iter().map(|&i| positions[i]).sum::<DVec3>() / 4.0;
            let c = positions.len() as u32;
            positions.push(centre);
            for k in 0..4 {
                triangles.push(vec![face[k] as u32, face[(k + 1) % 4] as u32, c]);
            }
        }
        Cage::from_polygons(positions, triangles).unwrap()
    }

    /// A cage with mirror (and, for a cube, turn) symmetries solves one function per orbit of
    /// its vertices and maps it to the others (u_σ(k)(g x) = u_k(x)); every vertex's values
    /// match a solve of every vertex to the solver's tolerance. Moving one face centre breaks
    /// the symmetries that involve it, and its orbit is solved again.
    #[test]
    fn a_symmetric_cage_solves_one_function_per_orbit_and_maps_the_rest() {
        let settings = HarmonicSettings {
            resolution: 13,
            ..HarmonicSettings::default()
        };
        let control = BindControl::default();
        let cuboid = centred_box(DVec3::new(-0.2, 0.1, 0.3), DVec3::new(0.9, 1.5, 1.0));
        let cube = centred_box(DVec3::ZERO, DVec3::ONE);
        let mut positions = cuboid.positions().to_vec();
        positions[8].x += 0.05; // a face centre off its face's middle
        let faces: Vec<Vec<u32>> = cuboid
            .polygons()
            .iter()
            .map(|f| f.vertices.clone())
            .collect();
        let lopsided = Cage::from_polygons(positions, faces).unwrap();
        // Solved: the box's corners are one orbit, its face centres three (a pair per axis);
        // the cube's face centres one. The lopsided box keeps only the mirror across y (the
        // centre moved along x on a face normal to z): its corners are four orbits (pairs),
        // its centres five (the two y faces' a pair, the others fixed).
        for (cage, solved) in [(&cuboid, 4), (&cube, 2), (&lopsided, 9)] {
            let derived = solve_field(cage, &settings, &control).unwrap();
            SOLVE_EVERY_VERTEX.with(|every| every.set(true));
            let direct = solve_field(cage, &settings, &control).unwrap();
            SOLVE_EVERY_VERTEX.with(|every| every.set(false));
            assert_eq!(derived.solved_vertices, solved);
            assert_eq!(direct.solved_vertices, cage.vertex_count());
            assert_eq!(derived.batches.len(), direct.batches.len());
            let mut largest = 0.0f64;
            for (a, b) in derived.batches.iter().zip(&direct.batches) {
                for (ra, rb) in a.iter().zip(b) {
                    for c in 0..K {
                        largest = largest.max((ra[c] - rb[c]).abs());
                    }
                }
            }
            assert!(largest < 1e-8, "derived and solved differ by {largest:e}");
        }
    }
}

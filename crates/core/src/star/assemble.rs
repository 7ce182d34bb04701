//! Row assembly (eqs. 3–10): each point's row of S_{c_i}(p) from the coordinate tables.
//!
//! Every point of a leaf cage c reads the same columns (c's vertices and Green faces, the join
//! cages of c's boundary vertices, the interior vertices of eq. 10), so a [`CagePlan`] maps
//! those columns once to slots of a dense accumulator. A point's row is then a sum of scaled
//! table rows into that accumulator, read out in column order: no per-point sort or merge.
//! Join cages over the same leaf cages (copies, whose tables are shared) are added once, with
//! the sum of their scales: Σ_v s_v T_{jc(v)}(p) = (Σ_v s_v) T_{jc}(p) when every jc(v) is
//! the same cage.

use std::collections::BTreeMap;
use std::sync::Arc;

use glam::DVec3;
use rayon::prelude::*;

use super::tables::{JoinData, Placement, Row, Table, merge};
use super::topology::Topology;
use crate::scene::{LocalCage, Smoothing};

/// Where the entries of one coordinate table's row go in a cage's accumulator.
struct Slots {
    /// Per local cage vertex.
    vertex: Vec<u32>,
    /// Per Green face term ψ (empty for vertex coordinates).
    psi: Vec<u32>,
}

impl Slots {
    fn new(local: &LocalCage, dofs: &[u32], vertex_count: u32, columns: &[u32]) -> Self {
        let slot = |c: u32| columns.binary_search(&c).unwrap_or(0) as u32;
        Self {
            vertex: local.global.iter().map(|&v| slot(v)).collect(),
            psi: dofs.iter().map(|&d| slot(vertex_count + d)).collect(),
        }
    }

    /// acc += scale × the table row `(w, ψ)`.
    fn add(&self, acc: &mut [f64], scale: f64, (w, psi): (&[f64], Option<&[f64]>)) {
        for (&s, &x) in self.vertex.iter().zip(w) {
            acc[s as usize] += scale * x;
        }
        if let Some(psi) = psi {
            for (&s, &x) in self.psi.iter().zip(psi) {
                acc[s as usize] += scale * x;
            }
        }
    }
}

/// One boundary vertex v of the cage: its weight W(v, p) (eqs. 5, 6, 8) and transformation
/// L_v (eqs. 9, 10).
struct Term {
    v: u32,
    /// Index of Ω(v, ·) in the plan's `omega_joins`.
    omega: usize,
    /// Per interior neighbour u of v: index of Ω(u, ·) and Ω(u, v), sorted by that index.
    interior_neighbours: Vec<(usize, f64)>,
    /// The table group of T_{jc(v)} (none where no point of the cage needed it).
    group: Option<usize>,
    /// For interior v: the slot of v and T_{jc(v)}(v) as (slot, weight) (eq. 10).
    interior: Option<(u32, Vec<(u32, f64)>)>,
}

/// Join cages sharing one table of T_{jc} (copies over the same leaf cages).
struct Group {
    table: Arc<Table>,
    slots: Slots,
}

/// What every row of one leaf cage's points reads, mapped to accumulator slots.
pub(super) struct CagePlan<'a> {
    /// The columns a row of this cage may hold, increasing.
    columns: Vec<u32>,
    leaf: Slots,
    /// How many Ω(u, p) the terms read (one per join vertex u).
    omega_count: usize,
    /// The indices of Ω(u, ·) of interior vertices u that some term reads in eq. 8's
    /// product, increasing.
    interior_omegas: Vec<usize>,
    /// Ω(u, ·) of interior u, or of a join cage without a shared table, evaluated alone
    /// (slot, data).
    omega_alone: Vec<(usize, &'a JoinData<'a>)>,
    /// Ω of non-interior join vertices whose join cages are one cage with one table.
    omega_shared: Vec<OmegaGroup<'a>>,
    terms: Vec<Term>,
    groups: Vec<Group>,
}

/// Join vertices whose join cages are copies of one cage (the same leaf cages) sharing one
/// table of interpolating weights: d_{jc}(t, p) is computed once per face and point. The
/// normalisers of non-interior members are 1 (eq. 6), so f(d_{jc}(t, p)) is shared too:
/// Ω(v, p) is the product over all faces divided by the factors of the faces at v. Interior
/// members take their own f(d(t, p) / d(t, u)).
struct OmegaGroup<'a> {
    data: &'a JoinData<'a>,
    /// Every face of the join cage, as local vertex lists end to end: face t is
    /// `face_vertices[face_start[t]..face_start[t + 1]]` (one allocation, read once per point).
    face_start: Vec<u32>,
    face_vertices: Vec<u32>,
    /// Per non-interior member: its Ω slot and the faces incident to it.
    members: Vec<(usize, Vec<usize>)>,
    /// Per interior member: its Ω slot and 1 / d(t, u) for every face t in order (no face
    /// holds an interior vertex, so all are far; its own normalisers: the factors cannot be
    /// shared, the sums d(t, p) are).
    interior: Vec<(usize, &'a [f64])>,
    /// Per face t, the least d(t, p) at which every interior member's factor is exactly 1
    /// (f(x) = 1 for x ≥ 1, eq. 6): faces at or past it are left out of their products. Most
    /// are (an auto rig's blend zone: 57 % of the faces, 69 % of the factors).
    all_one_from: Vec<f64>,
    /// Per vertex of the join cage (shared numbering), its faces, increasing.
    faces_at: BTreeMap<u32, Vec<usize>>,
}

/// Factors f(d) below this are set apart instead of divided out (no precision lost to
/// division, no underflow of the product).
const SMALL_FACTOR: f64 = 1e-3;

impl OmegaGroup<'_> {
    /// Ω(v, p) of every member into `omega`, from p's interpolating weights `w`.
    fn evaluate(&self, w: &[f64], smoothing: Smoothing, scratch: &mut Scratch) {
        let Scratch {
            distance,
            factor,
            small,
            omega,
            active,
            ..
        } = scratch;
        distance.clear();
        // d_{jc}(t, p) = 1 − Σ_{u ∈ V(t)} w(u, p)   (eq. 7)
        distance.extend(self.face_start.windows(2).map(|ends| {
            let face = &self.face_vertices[ends[0] as usize..ends[1] as usize];
            1.0 - face.iter().map(|&k| w[k as usize]).sum::<f64>()
        }));
        if !self.interior.is_empty() {
            active.clear();
            active.extend(
                distance
                    .iter()
                    .zip(&self.all_one_from)
                    .enumerate()
                    .filter(|(_, (d, from))| d < from)
                    .map(|(t, _)| t as u32),
            );
            for (slot, inverse) in &self.interior {
                // Ω(u, p) = Π_{t ∌ u} f(d(t, p) / d(t, u))   (eq. 6), over the faces whose
                // factor is not 1.
                factor.clear();
                factor.extend(
                    active
                        .iter()
                        .map(|&t| distance[t as usize] * inverse[t as usize]),
                );
                omega[*slot] = smoothing.product_of_unit_below_one(factor);
            }
        }
        if self.members.is_empty() {
            return;
        }
        factor.clear();
        factor.extend_from_slice(distance);
        smoothing.eval_unit_in_place(factor);
        small.clear();
        let mut product = 1.0;
        for (t, &f) in factor.iter().enumerate() {
            if f > SMALL_FACTOR {
                product *= f;
            } else {
                small.push((t, f));
            }
        }
        for (slot, incident) in &self.members {
            // One division per member: the product of its incident factors first.
            let mut divisor = 1.0;
            for &t in incident {
                if factor[t] > SMALL_FACTOR {
                    divisor *= factor[t];
                }
            }
            let mut value = product / divisor;
            for &(t, f) in small.iter() {
                if !incident.contains(&t) {
                    value *= f;
                }
            }
            omega[*slot] = value;
        }
    }
}

/// The join data of the table a point's L_v reads: its own kind's weights, else the
/// interpolating ones (the same when the kind interpolates).
fn transform_table(data: &JoinData) -> Option<Arc<Table>> {
    data.transform.clone().or_else(|| data.interp.clone())
}

impl<'a> CagePlan<'a> {
    /// The plan of leaf cage `c`.
    pub(super) fn new(
        c: usize,
        topology: &Topology,
        joins: &'a BTreeMap<u32, JoinData<'a>>,
        omega_at_vertex: &BTreeMap<(u32, u32), f64>,
        leaf_dofs: &[u32],
        vertex_count: u32,
        sharing: Sharing,
    ) -> Self {
        let local = &topology.leaves[c];
        let boundary = &topology.boundary[c];
        // Ω is read for each boundary vertex and its interior neighbours.
        let mut omega_index: BTreeMap<u32, usize> = BTreeMap::new();
        let mut omega_joins = Vec::new();
        let mut index_of = |u: u32| {
            *omega_index.entry(u).or_insert_with(|| {
                omega_joins.push(&joins[&u]);
                omega_joins.len() - 1
            })
        };
        let mut groups: Vec<(Arc<Table>, &JoinData)> = Vec::new();
        let mut terms = Vec::with_capacity(boundary.len());
        for &v in boundary {
            let omega = index_of(v);
            let mut interior_neighbours: Vec<(usize, f64)> = topology
                .interior_neighbours(v)
                .map(|u| (index_of(u), omega_at_vertex[&(u, v)]))
                .collect();
            interior_neighbours.sort_unstable_by_key(|&(u, _)| u);
            let data = &joins[&v];
            let group = transform_table(data).map(|table| {
                // Join cages over the same leaf cages share their `local` (topology.rs).
                let same = |(t, d): &(Arc<Table>, &JoinData)| {
                    Arc::ptr_eq(t, &table)
                        && (Arc::ptr_eq(&d.join.local, &data.join.local)
                            || d.join.local.global == data.join.local.global)
                        && d.dofs == data.dofs
                };
                let shared = groups
                    .iter()
                    .position(same)
                    .filter(|_| sharing == Sharing::Shared);
                shared.unwrap_or_else(|| {
                    groups.push((table, data));
                    groups.len() - 1
                })
            });
            let interior = data.join.interior.then(|| (v, data.vertex_row.clone()));
            terms.push((v, omega, interior_neighbours, group, interior));
        }
        // Every column a row can touch.
        let mut columns: Vec<u32> = local.global.clone();
        columns.extend(leaf_dofs.iter().map(|&d| vertex_count + d));
        for (_, data) in &groups {
            columns.extend(&data.join.local.global);
            columns.extend(data.dofs.iter().map(|&d| vertex_count + d));
        }
        for (_, _, _, _, interior) in &terms {
            if let Some((v, row)) = interior {
                columns.push(*v);
                columns.extend(row.iter().map(|&(col, _)| col));
            }
        }
        columns.sort_unstable();
        columns.dedup();
        let slot = |col: u32| columns.binary_search(&col).unwrap_or(0) as u32;
        let terms: Vec<Term> = terms
            .into_iter()
            .map(|(v, omega, interior_neighbours, group, interior)| Term {
                v,
                omega,
                interior_neighbours,
                group,
                interior: interior.map(|(v, row)| {
                    (
                        slot(v),
                        row.iter().map(|&(col, x)| (slot(col), x)).collect(),
                    )
                }),
            })
            .collect();
        let groups: Vec<Group> = groups
            .into_iter()
            .map(|(table, data)| Group {
                table,
                slots: Slots::new(&data.join.local, &data.dofs, vertex_count, &columns),
            })
            .collect();
        let (omega_alone, omega_shared) = match sharing {
            Sharing::Shared => omega_groups(&omega_joins),
            Sharing::Direct => (
                omega_joins.iter().copied().enumerate().collect(),
                Vec::new(),
            ),
        };
        let mut interior_omegas: Vec<usize> = terms
            .iter()
            .flat_map(|t| t.interior_neighbours.iter().map(|&(u, _)| u))
            .collect();
        interior_omegas.sort_unstable();
        interior_omegas.dedup();
        Self {
            leaf: Slots::new(local, leaf_dofs, vertex_count, &columns),
            columns,
            omega_count: omega_joins.len(),
            interior_omegas,
            omega_alone,
            omega_shared,
            terms,
            groups,
        }
    }
}

/// Splits the join vertices whose Ω a cage reads (by slot) into those evaluated alone and
/// groups of copies sharing their faces' factors.
fn omega_groups<'a>(
    omega_joins: &[&'a JoinData<'a>],
) -> (Vec<(usize, &'a JoinData<'a>)>, Vec<OmegaGroup<'a>>) {
    let mut alone = Vec::new();
    let mut shared: Vec<OmegaGroup> = Vec::new();
    for (slot, &data) in omega_joins.iter().enumerate() {
        let Some(table) = data.interp.as_ref() else {
            alone.push((slot, data));
            continue;
        };
        let v = data.join.vertex;
        let polygons = &data.join.polygons;
        let same = |group: &&mut OmegaGroup| {
            group
                .data
                .interp
                .as_ref()
                .is_some_and(|t| Arc::ptr_eq(t, table))
                && (Arc::ptr_eq(&group.data.join.polygons, polygons)
                    || group.data.join.polygons == *polygons)
                && (Arc::ptr_eq(&group.data.join.local, &data.join.local)
                    || group.data.join.local.global == data.join.local.global)
        };
        let index = match shared.iter_mut().position(|g| same(&g)) {
            Some(index) => index,
            None => {
                let local = &data.join.local;
                let mut faces_at: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
                for (t, f) in polygons.iter().enumerate() {
                    for &g in f {
                        faces_at.entry(g).or_default().push(t);
                    }
                }
                let mut face_start = vec![0];
                let mut face_vertices = Vec::new();
                for f in polygons.iter() {
                    face_vertices.extend(
                        f.iter()
                            .filter_map(|g| local.global.binary_search(g).ok())
                            .map(|k| k as u32),
                    );
                    face_start.push(face_vertices.len() as u32);
                }
                shared.push(OmegaGroup {
                    data,
                    face_start,
                    face_vertices,
                    members: Vec::new(),
                    interior: Vec::new(),
                    all_one_from: vec![f64::NEG_INFINITY; polygons.len()],
                    faces_at,
                });
                shared.len() - 1
            }
        };
        let group = &mut shared[index];
        if data.join.interior {
            // far_faces and their normalisers list the faces without v in polygon order: all
            // of them, v being on none.
            if data.inverse_normaliser.len() != polygons.len() {
                alone.push((slot, data));
                continue;
            }
            for (from, &one_from) in group.all_one_from.iter_mut().zip(&data.one_from) {
                *from = from.max(one_from);
            }
            group.interior.push((slot, &data.inverse_normaliser));
        } else {
            let incident = group.faces_at.get(&v).cloned().unwrap_or_default();
            group.members.push((slot, incident));
        }
    }
    (alone, shared)
}

/// Whether copies of a join cage share their terms (the bind), or every join vertex's Ω and
/// L_v is evaluated on its own (the direct reference the shared terms are tested against).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Sharing {
    Shared,
    #[cfg_attr(not(test), allow(dead_code))]
    Direct,
}

/// Per-thread scratch of [`assemble_rows`].
#[derive(Default)]
struct Scratch {
    /// Faces of an Ω group whose interior factors are not all 1 at the point.
    active: Vec<u32>,
    acc: Vec<f64>,
    omega: Vec<f64>,
    distance: Vec<f64>,
    factor: Vec<f64>,
    small: Vec<(usize, f64)>,
    weight: Vec<f64>,
    group_scale: Vec<f64>,
    /// Indices of the interior Ω(u, p) that are not zero at the point.
    live: Vec<usize>,
}

/// Everything a point's row is assembled from.
pub(super) struct Inputs<'a> {
    pub topology: &'a Topology,
    pub points: &'a [DVec3],
    pub placement: &'a [Placement],
    pub cage_t: &'a [Table],
    pub plans: &'a [CagePlan<'a>],
    pub boundary_weight: &'a [f64],
    pub smoothing: Smoothing,
}

/// The rows of S for the first `count` points, and their normalised join weights W_n(v, p).
pub(super) fn assemble_rows(inputs: &Inputs, count: usize) -> (Vec<Row>, Vec<Vec<(u32, f64)>>) {
    (0..count)
        .into_par_iter()
        .map_init(Scratch::default, |scratch, i| {
            assemble_row(inputs, scratch, i)
        })
        .unzip()
}

fn assemble_row(inputs: &Inputs, scratch: &mut Scratch, i: usize) -> (Row, Vec<(u32, f64)>) {
    let c = match inputs.placement[i] {
        Placement::Cage(c) | Placement::Nearest(c) => c,
    };
    let plan = &inputs.plans[c];
    let Some(t) = inputs.cage_t[c].get(i) else {
        // Outside an HC cage under the 'nearest' policy: follow the closest cage point
        // rigidly (translation with it).
        let local = &inputs.topology.leaves[c];
        let (t, bary, _) = local.cage.closest_point(inputs.points[i]);
        let tri = local.cage.triangles()[t];
        let row = (0..3)
            .map(|k| (local.global[tri[k] as usize], bary[k]))
            .collect();
        return (merge(row), Vec::new());
    };
    let b = inputs.boundary_weight[i];
    let weighs = b < 1.0 && joins_weigh(inputs, plan, scratch, i);
    let Scratch {
        acc,
        weight,
        group_scale,
        ..
    } = scratch;
    acc.clear();
    acc.resize(plan.columns.len(), 0.0);
    // b T_{c_i}(p): T of eq. 2 (or Lipman et al.'s GC map), b of eq. 11 (b = 1 where the point
    // is far from every border).
    plan.leaf.add(acc, if weighs { b } else { 1.0 }, t);
    // Sized once: growing these per point was a tenth of a large bind's time.
    let mut normalised = Vec::with_capacity(if weighs { plan.terms.len() } else { 0 });
    if weighs {
        let total: f64 = weight.iter().sum();
        group_scale.clear();
        group_scale.resize(plan.groups.len(), 0.0);
        for (term, &w) in plan.terms.iter().zip(weight.iter()) {
            if w == 0.0 {
                continue;
            }
            normalised.push((term.v, w / total));
            // (1 − b) W_n(v, p) L_v(p) of eq. 3, with L_v(p) = T_{jc(v)}(p) (eq. 9) …
            let scale = (1.0 - b) * w / total;
            let Some(g) = term.group else {
                continue;
            };
            group_scale[g] += scale;
            if let Some((v_slot, vertex_row)) = &term.interior {
                // … + W(v, p) (v' − T_{jc(v)}(v)) for interior v (eq. 10; the raw W,
                // docs/math.md, reading 5).
                acc[*v_slot as usize] += scale * w;
                for &(s, x) in vertex_row {
                    acc[s as usize] -= scale * w * x;
                }
            }
        }
        for (group, &scale) in plan.groups.iter().zip(group_scale.iter()) {
            if scale != 0.0
                && let Some(row) = group.table.get(i)
            {
                group.slots.add(acc, scale, row);
            }
        }
    }
    let mut row = Vec::with_capacity(acc.iter().filter(|x| **x != 0.0).count());
    row.extend(
        plan.columns
            .iter()
            .zip(acc.iter())
            .filter(|(_, x)| **x != 0.0)
            .map(|(&col, &x)| (col, x)),
    );
    (row, normalised)
}

/// The arguments (1 − Ω(u, p)) / (1 − Ω(u, v)) of eq. 8's factors, for the interior
/// neighbours u of v (`neighbours`: index of Ω(u, ·) and Ω(u, v), increasing) that are alive
/// at p (`live`: the indices with Ω(u, p) ≠ 0, increasing), in increasing index: each live
/// index looked up in v's list. For few live ones (a finely subdivided border: thousands of
/// neighbours, a few seen from p).
fn live_arguments_by_lookup(
    live: &[usize],
    neighbours: &[(usize, f64)],
    omega: &[f64],
    out: &mut Vec<f64>,
) {
    out.extend(live.iter().filter_map(|&u| {
        let k = neighbours.binary_search_by_key(&u, |&(x, _)| x).ok()?;
        Some((1.0 - omega[u]) / (1.0 - neighbours[k].1))
    }));
}

/// [`live_arguments_by_lookup`]'s list, the same values in the same order, read off v's list.
/// For many live ones (an auto rig's borders: most neighbours are, and the lookups were a
/// fifth of the bunny rig's bind).
fn live_arguments_by_scan(neighbours: &[(usize, f64)], omega: &[f64], out: &mut Vec<f64>) {
    out.extend(
        neighbours
            .iter()
            .filter(|&&(u, _)| omega[u] != 0.0)
            .map(|&(u, at_v)| (1.0 - omega[u]) / (1.0 - at_v)),
    );
}

/// W(v, p) = Ω(v, p) Π_u f((1 − Ω(u, p)) / (1 − Ω(u, v))) for each term (eqs. 5, 6, 8; h = 1,
/// see docs/math.md) into `scratch.weight`; false where they sum to nothing (far from every
/// boundary vertex: b = 1 to working precision).
fn joins_weigh(inputs: &Inputs, plan: &CagePlan, scratch: &mut Scratch, i: usize) -> bool {
    let smoothing = inputs.smoothing;
    scratch.omega.clear();
    scratch.omega.resize(plan.omega_count, 0.0);
    for &(slot, data) in &plan.omega_alone {
        scratch.omega[slot] = data
            .interp
            .as_ref()
            .and_then(|t| t.get(i))
            .map_or(0.0, |(w, _)| {
                data.omega_with(w, smoothing, &mut scratch.factor)
            });
    }
    for group in &plan.omega_shared {
        if let Some((w, _)) = group.data.interp.as_ref().and_then(|t| t.get(i)) {
            group.evaluate(w, smoothing, scratch);
        }
    }
    let Scratch {
        omega,
        live,
        weight,
        factor,
        ..
    } = scratch;
    // Where Ω(u, p) = 0 the factor of u is f(1 / (1 − Ω(u, v))) = 1 (Ω(u, v) ≤ 1): only the
    // interior vertices whose Ω is alive at p enter the products. On a finely subdivided
    // border every term has thousands of interior neighbours, of which a point sees a few.
    live.clear();
    live.extend(plan.interior_omegas.iter().filter(|&&u| omega[u] != 0.0));
    weight.clear();
    weight.extend(plan.terms.iter().map(|term| {
        let own = omega[term.omega];
        if own == 0.0 || live.is_empty() {
            return own;
        }
        // The factors' arguments first, then f of all of them in SIMD lanes (the same values
        // as one `eval` each), multiplied in the same order as before.
        factor.clear();
        let neighbours = &term.interior_neighbours;
        if live.len() * 4 < neighbours.len() {
            live_arguments_by_lookup(live, neighbours, omega, factor);
        } else {
            live_arguments_by_scan(neighbours, omega, factor);
        }
        own * smoothing.product_of_unit_below_one(factor)
    }));
    weight.iter().sum::<f64>() > 1e-14
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Eq. 8's arguments are the same values in the same order whether each live index
        /// is looked up in v's list or v's list is scanned, with few or most neighbours
        /// alive, and dead neighbours (Ω(u, p) = 0) give none (a scan that does not skip
        /// them fails: checked).
        #[test]
        fn eq_8_arguments_by_lookup_and_by_scan_agree(
            omega in proptest::collection::vec(
                prop_oneof![Just(0.0), 0.0f64..0.999], 1..200),
            neighbour_share in 0.0f64..1.0,
            at_v in proptest::collection::vec(0.0f64..0.999, 200),
        ) {
            let neighbours: Vec<(usize, f64)> = (0..omega.len())
                .filter(|&u| (u as f64 * 0.618_034).fract() < neighbour_share)
                .map(|u| (u, at_v[u]))
                .collect();
            let live: Vec<usize> = (0..omega.len()).filter(|&u| omega[u] != 0.0).collect();
            let (mut by_lookup, mut by_scan) = (Vec::new(), Vec::new());
            live_arguments_by_lookup(&live, &neighbours, &omega, &mut by_lookup);
            live_arguments_by_scan(&neighbours, &omega, &mut by_scan);
            let bits = |xs: &[f64]| xs.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            prop_assert_eq!(bits(&by_lookup), bits(&by_scan));
            let dead = neighbours.iter().filter(|&&(u, _)| omega[u] == 0.0).count();
            if dead > 0 {
                prop_assert_ne!(by_lookup.len(), neighbours.len());
            }
        }
    }
}

//! Binding (section 3): for every point, the linear row of S_{c_i}(p) (eq. 3) over the cage
//! degrees of freedom, with every coordinate computed in batches (per leaf cage, per join cage).
//!
//! S_{c_i}(p) = b T_{c_i}(p) + (1 − b) Σ_{v ∈ B_{c_i}} W_n(v, p) L_v(p), and T, L_v are linear in
//! the posed vertices and Green face terms (docs/math.md, reading 9), so the row is
//! b·row(T) + (1 − b)·Σ W_n(v, p)·row(L_v), with b, W, Ω and I from rest positions only.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;
use rayon::prelude::*;

use super::StarError;
use super::assemble::{CagePlan, Inputs, Sharing, assemble_rows};
use super::green_dofs::GreenDofs;
use super::pooled_joins::pooled_mean_value_tables;
use super::shape_class::{Placement as ShapePlacement, ShapeKey, shape_class};
pub use super::tables::Placement;
use super::tables::{JoinData, Row, Table, add_row};
use super::topology::{JoinCage, Topology};
use crate::coords::{BindControl, BindSettings, CageWeights, CoordinateKind, bind};
use crate::scene::{CageSet, LocalCage, SceneSettings};

/// Everything a bind produces before packing.
pub(crate) struct BoundRows {
    pub rows: Vec<Row>,
    pub boundary_weight: Vec<f64>,
    /// Per point, the normalised join weights W_n(v, p) of eq. 4 (empty where b = 1).
    pub join_weights: Vec<Vec<(u32, f64)>>,
    pub green: GreenDofs,
    pub seconds_cage: f64,
    pub seconds_join: f64,
}

/// Per join vertex, the points (increasing indices, each once) whose Ω or L_v needs its join
/// cage's coordinates.
pub(super) type Needs = BTreeMap<u32, Vec<usize>>;

/// The interpolating kind used for d (eq. 7) in a cage of kind `kind`: Green φ do not
/// interpolate (docs/math.md, reading 4), so Green cages use MVC there.
fn interpolating(kind: CoordinateKind) -> CoordinateKind {
    match kind {
        CoordinateKind::Green => CoordinateKind::MeanValue,
        other => other,
    }
}

/// What the binds of one scene's chunks of points share: the join cages' data at the cage
/// vertices, which depends on the cages alone. Each chunk computes what no chunk before it
/// needed and reads the rest from here, so the cage vertices are no longer bound as extra
/// points in every chunk (on the bunny's auto rig, eight chunks, that was a sixth of the bind).
#[derive(Default)]
pub(crate) struct JoinMemo {
    /// Whether a cage vertex lies in a join cage (by its leaf cages, then by vertex).
    within: BTreeMap<Vec<usize>, BTreeMap<u32, bool>>,
    /// Ω(u, v) (eqs. 6–7) of interior u at boundary vertex v inside jc(u), once computed.
    omega_at_vertex: BTreeMap<(u32, u32), f64>,
    /// Per interior join vertex v: d(t, v) per far face (eq. 6) and the row of T_{jc(v)}(v)
    /// (eq. 10), from v's own coordinates in jc(v).
    interior: BTreeMap<u32, (Vec<f64>, Row)>,
    /// Per join vertex v, the faces of jc(v) not incident to v (F(jc(v), v) in eq. 6).
    far_faces: BTreeMap<u32, Arc<Vec<Vec<usize>>>>,
}

/// Binds `points` placed by `placement` to the leaf cages of `set`.
pub(crate) fn bind_rows(
    set: &CageSet,
    topology: &Topology,
    settings: &SceneSettings,
    points: &[DVec3],
    placement: &[Placement],
    control: &BindControl,
    memo: &mut JoinMemo,
) -> Result<BoundRows, StarError> {
    bind_rows_by(
        set,
        topology,
        settings,
        points,
        placement,
        control,
        Sharing::Shared,
        memo,
    )
}

/// [`bind_rows`], assembling the rows with or without the terms copies of a join cage share.
#[allow(clippy::too_many_arguments)]
fn bind_rows_by(
    set: &CageSet,
    topology: &Topology,
    settings: &SceneSettings,
    points: &[DVec3],
    placement: &[Placement],
    control: &BindControl,
    sharing: Sharing,
    memo: &mut JoinMemo,
) -> Result<BoundRows, StarError> {
    let cx = BindContext {
        set,
        topology,
        settings,
        coord_settings: BindSettings {
            harmonic: settings.harmonic,
        },
        placement,
        control,
    };
    let start = Instant::now();
    let mut green = GreenDofs::default();
    let leaves = leaf_tables(&cx, points, &mut green)?;
    let seconds_cage = start.elapsed().as_secs_f64();
    let boundary_weight = boundary_weights(&cx, points.len(), &leaves);

    let join_start = Instant::now();
    let needs = join_needs(&cx, points, &boundary_weight, memo)?;
    let offset = points.len();
    let tables = join_cage_tables(&cx, &needs)?;
    let joins = join_data(&cx, tables, offset, &mut green, memo)?;
    let omega_at_vertex = omega_at_vertices(&cx, &joins, offset, memo)?;
    let seconds_join = join_start.elapsed().as_secs_f64();

    // Assemble every row (eqs. 3–10), one plan of columns per leaf cage.
    let plans: Vec<CagePlan> = (0..set.leaves.len())
        .into_par_iter()
        .map(|c| {
            CagePlan::new(
                c,
                topology,
                &joins,
                &omega_at_vertex,
                &leaves.dofs[c],
                set.vertices.len() as u32,
                sharing,
            )
        })
        .collect();
    let (rows, join_weights) = assemble_rows(
        &Inputs {
            topology,
            points: &needs.points,
            placement,
            cage_t: &leaves.t,
            plans: &plans,
            boundary_weight: &boundary_weight,
            smoothing: settings.smoothing,
        },
        offset,
    );
    Ok(BoundRows {
        rows,
        boundary_weight,
        join_weights,
        green,
        seconds_cage,
        seconds_join,
    })
}

/// What every phase of a bind reads.
struct BindContext<'a> {
    set: &'a CageSet,
    topology: &'a Topology,
    settings: &'a SceneSettings,
    coord_settings: BindSettings,
    placement: &'a [Placement],
    control: &'a BindControl,
}

/// Each leaf cage's coordinate tables of the points placed in it.
struct LeafTables {
    /// T_{c_i}(p) (eq. 3): coordinates of the cage's own kind.
    t: Vec<Table>,
    /// Interpolating weights for b (eq. 11) where the cage's kind does not interpolate (Green).
    w: Vec<Option<Table>>,
    /// The Green face degrees of freedom of each Green cage (empty for the others).
    dofs: Vec<Vec<u32>>,
}

/// Phase 1, the leaf cages: T_{c_i} of the points each holds (eq. 3), and the interpolating
/// weights b is made of (eq. 11; docs/math.md, reading 4). Congruent harmonic leaves (a rig's
/// mirrored limbs) share one solve.
fn leaf_tables(
    cx: &BindContext,
    points: &[DVec3],
    green: &mut GreenDofs,
) -> Result<LeafTables, StarError> {
    let (set, topology, placement, control) = (cx.set, cx.topology, cx.placement, cx.control);
    let n_cages = set.leaves.len();
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); n_cages];
    for (i, p) in placement.iter().enumerate() {
        match *p {
            Placement::Cage(c) => members[c].push(i),
            // A harmonic cage has no coordinates outside: such points follow it rigidly.
            Placement::Nearest(c) if set.leaves[c].kind == CoordinateKind::Harmonic => {}
            Placement::Nearest(c) => members[c].push(i),
        }
    }
    let mut shared_leaves =
        shared_leaf_tables(set, topology, &members, points, &cx.coord_settings, control)?;
    let mut tables = LeafTables {
        t: Vec::with_capacity(n_cages),
        w: Vec::with_capacity(n_cages),
        dofs: Vec::with_capacity(n_cages),
    };
    for (c, list) in members.iter().enumerate() {
        control.check().map_err(|_| StarError::Cancelled)?;
        let kind = set.leaves[c].kind;
        let local = &topology.leaves[c];
        let name = format!("leaf cage '{}'", set.leaves[c].name);
        tables.dofs.push(if kind == CoordinateKind::Green {
            green.register(local)
        } else {
            Vec::new()
        });
        let t = match shared_leaves.remove(&c) {
            Some(shared) => shared,
            None => Table::compute(
                kind,
                local,
                points,
                list.clone(),
                &cx.coord_settings,
                control,
                &name,
            )?,
        };
        // Interpolating weights for b of the points inside (nearest ones keep b = 1).
        let inside: Vec<usize> = list
            .iter()
            .copied()
            .filter(|&i| placement[i] == Placement::Cage(c))
            .collect();
        let w = if interpolating(kind) == kind {
            None
        } else {
            Some(Table::compute(
                interpolating(kind),
                local,
                points,
                inside,
                &cx.coord_settings,
                control,
                &name,
            )?)
        };
        tables.t.push(t);
        tables.w.push(w);
    }
    Ok(tables)
}

/// Phase 2, b per point (eq. 11): f_h of the product over the cage's borders of
/// 1 − Σ_{v ∈ B_{c_i c_j}} w_{c_i}(v, p), from the interpolating weights of its cage (with a
/// border's own h, each border's factor smoothed alone). 1 for points outside every cage and
/// in cages with no neighbour (section 3.2).
fn boundary_weights(cx: &BindContext, point_count: usize, leaves: &LeafTables) -> Vec<f64> {
    let (set, topology) = (cx.set, cx.topology);
    let smoothing = cx.settings.smoothing;
    let border_local: Vec<Vec<(usize, Vec<usize>, f64)>> = (0..set.leaves.len())
        .map(|c| {
            let local = &topology.leaves[c];
            let cage = &set.leaves[c];
            topology.borders[c]
                .iter()
                .map(|border| {
                    let locals = border
                        .vertices
                        .iter()
                        .filter_map(|v| local.global.binary_search(v).ok())
                        .collect();
                    let neighbour = &set.leaves[border.other].name;
                    let h = cage.border_h.get(neighbour).copied().unwrap_or(f64::NAN);
                    (border.other, locals, h)
                })
                .collect()
        })
        .collect();
    (0..point_count)
        .into_par_iter()
        .map(|i| {
            let Placement::Cage(c) = cx.placement[i] else {
                return 1.0;
            };
            if border_local[c].is_empty() {
                return 1.0; // no neighbour: b = 1 (section 3.2)
            }
            let table = leaves.w[c].as_ref().unwrap_or(&leaves.t[c]);
            let Some((w, _)) = table.get(i) else {
                return 1.0;
            };
            let h = set.leaves[c].h.unwrap_or(cx.settings.default_h);
            // 1 − Σ_{v ∈ B_{c_i c_j}} w_{c_i}(v, p) per border.
            let factors = border_local[c]
                .iter()
                .map(|(_, locals, hb)| (1.0 - locals.iter().map(|&k| w[k]).sum::<f64>(), *hb));
            if border_local[c].iter().any(|(_, _, hb)| hb.is_finite()) {
                // Per-border overrides: each border's factor smoothed with its own h.
                factors
                    .map(|(x, hb)| smoothing.eval(x, if hb.is_finite() { hb } else { h }))
                    .product()
            } else {
                smoothing.eval(factors.map(|(x, _)| x).product(), h)
            }
        })
        .collect()
}

/// The points each join cage must be evaluated at.
struct JoinNeeds {
    /// Per boundary vertex v, the points that need L_v (eq. 10).
    transform: Needs,
    /// Per join vertex u, the points that need Ω(u, ·) (eqs. 6–8).
    omega: Needs,
    /// The mesh points, then the cage vertices as extra points (index `offset + v`).
    points: Vec<DVec3>,
}

/// Phase 3, which join cages each point needs: every point with b < 1 reads L_v and Ω(v, ·)
/// of its cage's boundary vertices, and Ω(u, ·) of their interior neighbours u whose join cage
/// holds the cage (Ω(u, ·) vanishes outside jc(u), the union of the cages incident at u:
/// docs/math.md, reading 6). Cage vertices become extra points: an interior vertex's own
/// coordinates in its join cage (d(t, v) and T_{jc(v)}(v), eqs. 6 and 10), and each boundary
/// vertex v inside jc(u) of an interior neighbour u (Ω(u, v) in eq. 8), except where an
/// earlier chunk left their values in `memo`. Only the join cages the points use are listed,
/// so a partial bind solves only those near its rows.
fn join_needs(
    cx: &BindContext,
    points: &[DVec3],
    boundary_weight: &[f64],
    memo: &mut JoinMemo,
) -> Result<JoinNeeds, StarError> {
    let (set, topology) = (cx.set, cx.topology);
    let mut need_transform = Needs::new();
    let mut need_omega = Needs::new();
    // The same for every point of a cage, so listed once per cage.
    let omega_of_cage: Vec<Vec<u32>> = (0..topology.leaves.len())
        .map(|c| {
            let mut list: BTreeSet<u32> = topology.boundary[c].iter().copied().collect();
            // Boundary vertices with the same incident cages share one list: read it once.
            let mut read: Vec<&Arc<[u32]>> = Vec::new();
            for v in &topology.boundary[c] {
                let Some(near) = topology.interior_near.get(v) else {
                    continue;
                };
                if read.iter().any(|r| Arc::ptr_eq(r, near)) {
                    continue;
                }
                read.push(near);
                list.extend(near.iter().filter(|u| topology.joins[u].cages.contains(&c)));
            }
            list.into_iter().collect()
        })
        .collect();
    for (i, &b) in boundary_weight.iter().enumerate() {
        let Placement::Cage(c) = cx.placement[i] else {
            continue;
        };
        if b >= 1.0 {
            continue;
        }
        for v in &topology.boundary[c] {
            need_transform.entry(*v).or_default().push(i);
        }
        for u in &omega_of_cage[c] {
            need_omega.entry(*u).or_default().push(i);
        }
    }
    let offset = points.len();
    let mut all_points = points.to_vec();
    all_points.extend_from_slice(&set.vertices);
    let used_boundary: BTreeSet<u32> = need_transform.keys().copied().collect();
    check_omega_work(topology, set, &need_omega, &used_boundary)?;
    // Whether v lies in jc(u), once per join cage: interior vertices over the same leaf cages
    // (a subdivided shared face holds thousands) have the same join cage.
    for &v in &used_boundary {
        // Ω(u, v) is read only for boundary vertices of the points' cages.
        for u in topology.interior_neighbours(v) {
            let join = &topology.joins[&u];
            let known = memo
                .within
                .get(join.cages.as_slice())
                .and_then(|m| m.get(&v).copied());
            let inside = known.unwrap_or_else(|| {
                let cage = &join.local.cage;
                let x = set.vertices[v as usize];
                // A vertex of jc(u)'s faces is on it, so within (no winding number needed:
                // those were a tenth of an auto rig's bind).
                let inside = join.local.global.binary_search(&v).is_ok()
                    || cage.winding_number(x) > 0.5
                    || cage.is_within(x, 1e-9 * cage.diagonal());
                memo.within
                    .entry(join.cages.clone())
                    .or_default()
                    .insert(v, inside);
                inside
            });
            if inside && !memo.omega_at_vertex.contains_key(&(u, v)) {
                need_omega.entry(u).or_default().push(offset + v as usize);
            }
        }
    }
    for (&v, join) in &topology.joins {
        if join.interior && need_omega.contains_key(&v) && !memo.interior.contains_key(&v) {
            need_omega.entry(v).or_default().push(offset + v as usize);
        }
    }
    for list in need_omega.values_mut() {
        list.sort_unstable();
        list.dedup();
    }
    Ok(JoinNeeds {
        transform: need_transform,
        omega: need_omega,
        points: all_points,
    })
}

/// Phase 4, the join cages' coordinate tables at the points that need them. Harmonic join
/// cages congruent up to translation, quarter turns and mirrors share one solve (returned
/// apart, by vertex); join cages over the same leaf cages are one cage (jc(v) is the union of
/// the cages incident at v, eq. 8), its tables computed once for every point any copy needs.
fn join_cage_tables(cx: &BindContext, needs: &JoinNeeds) -> Result<JoinCageTables, StarError> {
    let topology = cx.topology;
    let classes = harmonic_classes(topology, &needs.omega);
    let in_a_class: BTreeSet<u32> = classes
        .iter()
        .flat_map(|class| &class.members)
        .map(|(v, _)| *v)
        .collect();
    let mut copies: BTreeMap<(&[usize], bool), Vec<u32>> = BTreeMap::new();
    for (&v, join) in &topology.joins {
        copies
            .entry((join.cages.as_slice(), in_a_class.contains(&v)))
            .or_default()
            .push(v);
    }
    let copies: Vec<_> = copies.into_iter().collect();
    let union_of = |members: &[u32], need: &Needs| -> Vec<usize> {
        let mut union: Vec<usize> = members
            .iter()
            .filter_map(|v| need.get(v))
            .flatten()
            .copied()
            .collect();
        union.sort_unstable();
        union.dedup();
        union
    };
    let join_tables_of = |members: &[u32], shared_interp: bool| {
        let v = members[0];
        join_tables(
            v,
            &topology.joins[&v],
            shared_interp,
            union_of(members, &needs.omega),
            union_of(members, &needs.transform),
            &needs.points,
            &cx.coord_settings,
            cx.control,
        )
    };
    // The class solves (in parallel with each other), then every other join cage's tables
    // (in parallel). Running both pools at once was slower: two grid solves at a time fight
    // over the caches.
    let shared = solve_harmonic_classes(
        &classes,
        topology,
        &needs.omega,
        &needs.points,
        &cx.coord_settings,
        cx.control,
    );
    // MVC join cages (interpolating, so one table each) from their leaf cages' pools of
    // triangles; the others each alone.
    let pooled = |members: &[u32], in_class: bool| {
        !in_class && topology.joins[&members[0]].kind == CoordinateKind::MeanValue
    };
    let (by_pool, alone): (Vec<_>, Vec<_>) = copies
        .iter()
        .partition(|((_, in_class), members)| pooled(members, *in_class));
    // Those no point needs get no table, as `join_tables` leaves them.
    let (needed, unneeded): (Vec<_>, Vec<_>) = by_pool
        .iter()
        .map(|(_, members)| (members, union_of(members, &needs.omega)))
        .partition(|(_, points)| !points.is_empty());
    let pool_members: Vec<&Vec<u32>> = needed.iter().map(|(members, _)| *members).collect();
    let pool_joins: Vec<(&JoinCage, Vec<usize>)> = needed
        .into_iter()
        .map(|(members, points)| (&topology.joins[&members[0]], points))
        .collect();
    let pool_tables = pooled_mean_value_tables(
        &pool_joins,
        &needs.points,
        cx.placement,
        &cx.coord_settings,
        cx.control,
    );
    let tables = alone
        .par_iter()
        .map(|((_, in_class), members)| {
            join_tables_of(members, *in_class)
                .map(|t| members.iter().map(|&v| (v, t.clone())).collect::<Vec<_>>())
        })
        .collect::<Result<Vec<Vec<(u32, JoinTables)>>, StarError>>();
    let (shared, tables, pool_tables) = (shared?, tables?, pool_tables?);
    let mut tables: BTreeMap<u32, JoinTables> = tables.into_iter().flatten().collect();
    for (members, table) in pool_members.into_iter().zip(pool_tables) {
        let table = Arc::new(table);
        tables.extend(
            members
                .iter()
                .map(|&v| (v, (Some(Arc::clone(&table)), None))),
        );
    }
    for (members, _) in unneeded {
        tables.extend(members.iter().map(|&v| (v, (None, None))));
    }
    // Members of a class whose shared solve failed bind alone.
    for &v in in_a_class.iter().filter(|v| !shared.contains_key(v)) {
        let (interp, _) = join_tables_of(&[v], false)?;
        if let Some(entry) = tables.get_mut(&v) {
            entry.0 = interp;
        }
    }
    Ok(JoinCageTables { tables, shared })
}

/// Every join cage's tables (phase 4).
struct JoinCageTables {
    /// By join vertex, its interpolating and own-kind tables.
    tables: BTreeMap<u32, JoinTables>,
    /// Interpolating tables of congruent harmonic join cages from their shared solve.
    shared: BTreeMap<u32, Table>,
}

/// Phase 5, each join cage's data (eqs. 6 and 10): its far faces F(jc(v), v), and for an
/// interior v the normalisers d(t, v) and the row of T_{jc(v)}(v) from v's own coordinates in
/// jc(v) (docs/math.md, reading 1), or from `memo` where an earlier chunk computed them; 1
/// and no row for a boundary vertex of its join cage.
fn join_data<'t>(
    cx: &BindContext<'t>,
    JoinCageTables {
        mut tables,
        mut shared,
    }: JoinCageTables,
    offset: usize,
    green: &mut GreenDofs,
    memo: &mut JoinMemo,
) -> Result<BTreeMap<u32, JoinData<'t>>, StarError> {
    let (set, topology, control) = (cx.set, cx.topology, cx.control);
    let vertex_count = set.vertices.len() as u32;
    let mut joins: BTreeMap<u32, JoinData> = BTreeMap::new();
    for (&v, join) in &topology.joins {
        control.check().map_err(|_| StarError::Cancelled)?;
        let local = &join.local;
        let far_faces = memo
            .far_faces
            .entry(v)
            .or_insert_with(|| {
                Arc::new(
                    join.polygons
                        .iter()
                        .filter(|f| !f.contains(&v))
                        .map(|f| {
                            f.iter()
                                .filter_map(|g| local.global.binary_search(g).ok())
                                .collect()
                        })
                        .collect(),
                )
            })
            .clone();
        let what = format!("join cage of vertex {v}");
        let interp_kind = interpolating(join.kind);
        let dofs = if join.kind == CoordinateKind::Green {
            green.register(local)
        } else {
            Vec::new()
        };
        let (interp, transform) = tables.remove(&v).unwrap_or_default();
        let interp = interp.or_else(|| shared.remove(&v).map(Arc::new));
        // Interior v: its own coordinates in jc(v) give the normalisers d(t, v) and T_{jc(v)}(v).
        let own = interp.as_ref().and_then(|t| t.get(offset + v as usize));
        let known = memo.interior.get(&v).filter(|_| join.interior);
        let (normaliser, vertex_row) = match (join.interior, own, known) {
            (_, _, Some((normaliser, row))) => (normaliser.clone(), row.clone()),
            (true, Some((w0, _)), None) => {
                let normaliser: Vec<f64> = far_faces
                    .iter()
                    .map(|f| 1.0 - f.iter().map(|&k| w0[k]).sum::<f64>())
                    .collect();
                let mut row = Vec::new();
                if join.kind == interp_kind {
                    add_row(&mut row, 1.0, (w0, None), local, &dofs, vertex_count);
                } else {
                    let x = [set.vertices[v as usize]];
                    let t = bind(join.kind, &local.cage, &x, &cx.coord_settings, control).map_err(
                        |source| StarError::Coordinates {
                            what: what.clone(),
                            source,
                        },
                    )?;
                    let t_row = match &t {
                        CageWeights::Vertex { weights, .. } => (weights.row(0), None),
                        CageWeights::Green(g) => (g.phi_row(0), Some(g.psi_row(0))),
                    };
                    add_row(&mut row, 1.0, t_row, local, &dofs, vertex_count);
                }
                memo.interior.insert(v, (normaliser.clone(), row.clone()));
                (normaliser, row)
            }
            _ => (vec![1.0; far_faces.len()], Vec::new()),
        };
        let (inverse_normaliser, one_from) = if join.interior {
            JoinData::interior_factors(&normaliser)
        } else {
            (Vec::new(), Vec::new())
        };
        joins.insert(
            v,
            JoinData {
                join,
                far_faces,
                normaliser,
                interp,
                transform,
                vertex_row,
                dofs,
                inverse_normaliser,
                one_from,
            },
        );
    }
    Ok(joins)
}

/// Phase 6, Ω(u, v) (eqs. 6–7) for interior u at each boundary vertex v that has u as an
/// interior neighbour: the values eq. 8's I(v, p) multiplies (0 where v lies outside jc(u),
/// or where no point of this chunk reads it). Those in `memo` are read, the others computed
/// and remembered there.
fn omega_at_vertices(
    cx: &BindContext,
    joins: &BTreeMap<u32, JoinData>,
    offset: usize,
    memo: &mut JoinMemo,
) -> Result<BTreeMap<(u32, u32), f64>, StarError> {
    let topology = cx.topology;
    let smoothing = cx.settings.smoothing;
    let pairs: Vec<(u32, u32)> = topology
        .interior_near
        .keys()
        .flat_map(|&v| topology.interior_neighbours(v).map(move |u| (u, v)))
        .collect();
    let known = &memo.omega_at_vertex;
    let values: Vec<Option<f64>> = pairs
        .par_iter()
        .with_min_len(64)
        .map(|&(u, v)| {
            if known.contains_key(&(u, v)) {
                return None;
            }
            let data = &joins[&u];
            data.interp
                .as_ref()
                .and_then(|t| t.get(offset + v as usize))
                .map(|(w, _)| data.omega(w, smoothing))
        })
        .collect();
    cx.control.check().map_err(|_| StarError::Cancelled)?;
    for (&pair, value) in pairs.iter().zip(values) {
        if let Some(value) = value {
            memo.omega_at_vertex.insert(pair, value);
        }
    }
    let known = &memo.omega_at_vertex;
    Ok(pairs
        .into_iter()
        .map(|pair| (pair, known.get(&pair).copied().unwrap_or(0.0)))
        .collect())
}

/// A join cage's tables: interpolating weights (for Ω) and weights of its own kind (for L_v),
/// shared by the join cages over the same leaf cages.
type JoinTables = (Option<Arc<Table>>, Option<Arc<Table>>);

/// The coordinate tables of join cage `join` (of vertex `v`): interpolating weights of
/// `omega_points` (the points that need Ω(v, ·); none where a shared solve provides them), and
/// weights of its own kind for `transform_points` (those that need L_v) when that kind does not
/// interpolate.
#[allow(clippy::too_many_arguments)]
fn join_tables(
    v: u32,
    join: &JoinCage,
    shared_interp: bool,
    omega_points: Vec<usize>,
    transform_points: Vec<usize>,
    points: &[DVec3],
    settings: &BindSettings,
    control: &BindControl,
) -> Result<JoinTables, StarError> {
    let what = format!("join cage of vertex {v}");
    let interp_kind = interpolating(join.kind);
    let interp = if omega_points.is_empty() || shared_interp {
        None
    } else {
        let local = &join.local;
        Some(Arc::new(Table::compute(
            interp_kind,
            local,
            points,
            omega_points,
            settings,
            control,
            &what,
        )?))
    };
    let transform = if transform_points.is_empty() || interp_kind == join.kind {
        None
    } else {
        Some(Arc::new(Table::compute(
            join.kind,
            &join.local,
            points,
            transform_points,
            settings,
            control,
            &what,
        )?))
    };
    Ok((interp, transform))
}

/// A class of congruent harmonic cages in one chunk of a bind: the frame its one solve is made
/// in, the first cage of the class over the whole rig (so that every chunk of a streamed bind
/// reads the same cached solve), and the members with points to bind in this chunk.
pub(super) struct HarmonicClass<K> {
    pub frame: (K, ShapePlacement),
    pub members: Vec<(K, ShapePlacement)>,
}

/// Classes of congruent cages from `(cage, placement, has points)` in rig order: classes of one
/// cage over the whole rig, and classes with no point to bind, are left out.
fn classes_by_shape<K: Copy>(
    cages: impl Iterator<Item = (K, (ShapeKey, ShapePlacement), bool)>,
) -> Vec<HarmonicClass<K>> {
    let mut classes: BTreeMap<ShapeKey, Vec<(K, ShapePlacement, bool)>> = BTreeMap::new();
    for (k, (key, placement), has_points) in cages {
        classes
            .entry(key)
            .or_default()
            .push((k, placement, has_points));
    }
    classes
        .into_values()
        .filter(|class| class.len() > 1)
        .filter_map(|class| {
            let frame = class
                .first()
                .map(|(k, placement, _)| (*k, placement.clone()))?;
            let members: Vec<_> = class
                .into_iter()
                .filter(|(_, _, has_points)| *has_points)
                .map(|(k, placement, _)| (k, placement))
                .collect();
            (!members.is_empty()).then_some(HarmonicClass { frame, members })
        })
        .collect()
}

/// Harmonic join cages (those whose interpolating coordinates are HC) grouped by shape up to
/// translation, turns by multiples of 90° and mirrors ([`super::shape_class`]); classes of
/// one are left out. Each class is solved once: every needing member's points, mapped into
/// the class's frame, are bound together and the rows are mapped back through the canonical
/// vertex order.
pub(super) fn harmonic_classes(topology: &Topology, need_omega: &Needs) -> Vec<HarmonicClass<u32>> {
    classes_by_shape(
        topology
            .joins
            .iter()
            .filter(|(_, join)| interpolating(join.kind) == CoordinateKind::Harmonic)
            .map(|(&v, join)| {
                let needed = need_omega.get(&v).is_some_and(|n| !n.is_empty());
                (v, shape_class(&join.local.cage), needed)
            }),
    )
}

/// The tables of [`harmonic_classes`]' classes, one solve each, in parallel.
fn solve_harmonic_classes(
    classes: &[HarmonicClass<u32>],
    topology: &Topology,
    need_omega: &Needs,
    points: &[DVec3],
    settings: &BindSettings,
    control: &BindControl,
) -> Result<BTreeMap<u32, Table>, StarError> {
    let solved: Vec<Vec<(u32, Table)>> = classes
        .par_iter()
        .map(|class| shared_class(topology, need_omega, points, settings, control, class))
        .collect::<Result<_, _>>()?;
    Ok(solved.into_iter().flatten().collect())
}

/// One solve for a class of congruent join cages: each member's table, or none when the
/// shared bind failed (round-off put a point outside, say: each member then binds alone).
fn shared_class(
    topology: &Topology,
    need_omega: &Needs,
    points: &[DVec3],
    settings: &BindSettings,
    control: &BindControl,
    class: &HarmonicClass<u32>,
) -> Result<Vec<(u32, Table)>, StarError> {
    let frame = Congruent {
        cage: &topology.joins[&class.frame.0].local,
        placement: &class.frame.1,
        points: Vec::new(),
    };
    let congruent: Vec<Congruent> = class
        .members
        .iter()
        .map(|(v, placement)| Congruent {
            cage: &topology.joins[v].local,
            placement,
            points: need_omega.get(v).cloned().unwrap_or_default(),
        })
        .collect();
    let tables = solve_congruent(&frame, &congruent, points, settings, control)?;
    Ok(class.members.iter().map(|(v, _)| *v).zip(tables).collect())
}

/// A member of a class of congruent harmonic cages, with the points it needs.
struct Congruent<'a> {
    cage: &'a LocalCage,
    placement: &'a ShapePlacement,
    points: Vec<usize>,
}

/// Steps of eq. 8 (one factor f(d(t, ·) / d(t, u)) each) a bind may take: about two
/// minutes on two cores.
const MAX_OMEGA_STEPS: f64 = 5e10;

/// Seconds one step of eq. 8 takes on one core (measured on a finely subdivided border).
const SECONDS_PER_OMEGA_STEP: f64 = 5e-9;

/// Refuses a bind whose interior vertices' Ω (eq. 6, each over every face of its join cage not
/// incident to it) at the points and cage vertices that need them would exceed
/// [`MAX_OMEGA_STEPS`], naming the border with the most interior vertices. Their number grows
/// with the square of a border's subdivision, the work with its fourth power.
fn check_omega_work(
    topology: &Topology,
    set: &CageSet,
    need_omega: &BTreeMap<u32, Vec<usize>>,
    used_boundary: &BTreeSet<u32>,
) -> Result<(), StarError> {
    // Points per interior vertex u: the mesh points listed so far, and (at most) every used
    // boundary vertex that has u as an interior neighbour, counted once per shared list.
    let mut readers: BTreeMap<u32, f64> = need_omega
        .iter()
        .map(|(&u, list)| (u, list.len() as f64))
        .collect();
    let mut by_list: Vec<(&Arc<[u32]>, f64)> = Vec::new();
    for v in used_boundary {
        let Some(near) = topology.interior_near.get(v) else {
            continue;
        };
        match by_list.iter_mut().find(|(list, _)| Arc::ptr_eq(list, near)) {
            Some((_, count)) => *count += 1.0,
            None => by_list.push((near, 1.0)),
        }
    }
    for (list, count) in by_list {
        for &u in list.iter() {
            *readers.entry(u).or_insert(0.0) += count;
        }
    }
    let steps: f64 = readers
        .iter()
        .filter_map(|(u, count)| {
            let join = topology.joins.get(u).filter(|j| j.interior)?;
            Some(count * join.local.cage.triangles().len() as f64)
        })
        .sum();
    if steps <= MAX_OMEGA_STEPS {
        return Ok(());
    }
    let mut interior_by_border: BTreeMap<&[usize], usize> = BTreeMap::new();
    for join in topology.joins.values().filter(|j| j.interior) {
        *interior_by_border.entry(join.cages.as_slice()).or_insert(0) += 1;
    }
    let Some((cages, interior)) = interior_by_border
        .into_iter()
        .max_by_key(|&(cages, n)| (n, std::cmp::Reverse(cages)))
    else {
        return Ok(());
    };
    let faces = topology
        .joins
        .values()
        .find(|j| j.cages.as_slice() == cages)
        .map_or(0, |j| j.local.cage.triangles().len());
    let names: Vec<String> = cages
        .iter()
        .filter_map(|&c| set.leaves.get(c))
        .map(|l| format!("'{}'", l.name))
        .collect();
    let seconds = steps * SECONDS_PER_OMEGA_STEP / rayon::current_num_threads().max(1) as f64;
    Err(StarError::TooMuchWork {
        cages: names.join(" and "),
        interior,
        faces,
        estimate: duration_in_words(seconds),
    })
}

/// A duration for a person: seconds, minutes, hours or days, rounded.
fn duration_in_words(seconds: f64) -> String {
    match seconds {
        s if s < 120.0 => format!("{s:.0} seconds"),
        s if s < 7_200.0 => format!("{:.0} minutes", s / 60.0),
        s if s < 172_800.0 => format!("{:.0} hours", s / 3_600.0),
        s => format!("{:.0} days", s / 86_400.0),
    }
}

/// One harmonic solve for a class of congruent cages (the same shape up to translation, quarter
/// turns and mirrors, [`super::shape_class`]): every member's points, mapped into the first
/// member's frame, are bound together and the rows are mapped back through the canonical
/// vertex order. Each member's table in order, or none when the shared bind failed.
fn solve_congruent(
    first: &Congruent,
    members: &[Congruent],
    points: &[DVec3],
    settings: &BindSettings,
    control: &BindControl,
) -> Result<Vec<Table>, StarError> {
    control.check().map_err(|_| StarError::Cancelled)?;
    let mut by_rank = vec![0usize; first.placement.rank.len()];
    for (k, &r) in first.placement.rank.iter().enumerate() {
        by_rank[r] = k;
    }
    let mapped: Vec<DVec3> = members
        .iter()
        .flat_map(|member| {
            member.points.iter().map(move |&i| {
                let canonical = member.placement.canonical_from_join(points[i]);
                first.placement.join_from_canonical(canonical)
            })
        })
        .collect();
    let result = bind(
        CoordinateKind::Harmonic,
        &first.cage.cage,
        &mapped,
        settings,
        control,
    );
    let Ok(CageWeights::Vertex { weights, .. }) = result else {
        control.check().map_err(|_| StarError::Cancelled)?;
        return Ok(Vec::new());
    };
    let n = weights.vertex_count;
    let mut row_index = 0;
    let mut tables = Vec::with_capacity(members.len());
    for member in members {
        let mut rows = Vec::with_capacity(member.points.len() * n);
        for _ in &member.points {
            let row = weights.row(row_index);
            row_index += 1;
            rows.extend(member.placement.rank.iter().map(|&r| row[by_rank[r]]));
        }
        tables.push(Table::new(
            member.points.clone(),
            CageWeights::Vertex {
                kind: CoordinateKind::Harmonic,
                weights: crate::coords::VertexWeights {
                    vertex_count: n,
                    weights: rows,
                },
            },
        ));
    }
    Ok(tables)
}

/// Harmonic leaf cages, grouped by shape as the join cages are; each class of two or more is
/// solved once, in the frame of its first cage whether or not that cage has points in this
/// chunk, so that every chunk of a streamed bind reads the same cached solve. The tables by leaf
/// cage (a class whose shared solve failed is left out: its members bind alone).
fn shared_leaf_tables(
    set: &CageSet,
    topology: &Topology,
    members: &[Vec<usize>],
    points: &[DVec3],
    settings: &BindSettings,
    control: &BindControl,
) -> Result<BTreeMap<usize, Table>, StarError> {
    let classes = classes_by_shape(
        (0..members.len())
            .filter(|&c| set.leaves[c].kind == CoordinateKind::Harmonic)
            .map(|c| {
                (
                    c,
                    shape_class(&topology.leaves[c].cage),
                    !members[c].is_empty(),
                )
            }),
    );
    let solved = classes
        .par_iter()
        .map(|class| {
            let frame = Congruent {
                cage: &topology.leaves[class.frame.0],
                placement: &class.frame.1,
                points: Vec::new(),
            };
            let congruent: Vec<Congruent> = class
                .members
                .iter()
                .map(|(c, placement)| Congruent {
                    cage: &topology.leaves[*c],
                    placement,
                    points: members[*c].clone(),
                })
                .collect();
            let tables = solve_congruent(&frame, &congruent, points, settings, control)?;
            Ok(class
                .members
                .iter()
                .map(|(c, _)| *c)
                .zip(tables)
                .collect::<Vec<_>>())
        })
        .collect::<Result<Vec<_>, StarError>>()?;
    Ok(solved.into_iter().flatten().collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::demo::demo_scene;
    use crate::scene::JoinPolicy;

    /// The bind's shared terms (Ω of copies of a join cage from one set of face factors, L_v of
    /// copies added once with the sum of their scales) give the rows and join weights of
    /// evaluating every join vertex alone, to 1e-12, on rigs with interior vertices (egg),
    /// Green leaves (bumpy), many copies (critter) and every join policy.
    #[test]
    fn shared_join_terms_equal_evaluating_each_join_vertex_alone() {
        for (name, policy) in [
            ("egg", JoinPolicy::Mvc),
            ("egg", JoinPolicy::Gc),
            ("bumpy", JoinPolicy::Auto),
            ("critter", JoinPolicy::Mvc),
            ("critter", JoinPolicy::Hc),
            ("prism", JoinPolicy::Gc),
        ] {
            let mut scene = demo_scene(name, 0.25).unwrap();
            scene.settings.join_coordinates = policy;
            scene.settings.harmonic.resolution = 12;
            let topology = Topology::new(&scene.cages, policy).unwrap();
            let points = scene.mesh.welded_positions();
            let placement = super::super::place(&scene, &topology, points).unwrap();
            let control = BindControl::default();
            let [shared, direct] = [Sharing::Shared, Sharing::Direct].map(|sharing| {
                bind_rows_by(
                    &scene.cages,
                    &topology,
                    &scene.settings,
                    points,
                    &placement,
                    &control,
                    sharing,
                    &mut JoinMemo::default(),
                )
                .unwrap()
            });
            let mut blended = 0;
            for i in 0..points.len() {
                let dense = |row: &Row| row.iter().copied().collect::<BTreeMap<u32, f64>>();
                let (a, b) = (dense(&shared.rows[i]), dense(&direct.rows[i]));
                for column in a.keys().chain(b.keys()) {
                    let (x, y) = (a.get(column), b.get(column));
                    let difference = (x.unwrap_or(&0.0) - y.unwrap_or(&0.0)).abs();
                    assert!(
                        difference <= 1e-12,
                        "{name} {policy:?} point {i}: {difference:e}"
                    );
                }
                let (a, b) = (&shared.join_weights[i], &direct.join_weights[i]);
                assert_eq!(a.len(), b.len(), "{name} point {i}");
                for ((va, wa), (vb, wb)) in a.iter().zip(b) {
                    assert_eq!(va, vb);
                    assert!((wa - wb).abs() <= 1e-12, "{name} point {i}: W_n");
                }
                blended += usize::from(!a.is_empty());
            }
            assert!(blended > 0, "{name}: some points blend join cages");
        }
    }

    #[test]
    fn translated_harmonic_join_cages_share_one_solve_with_the_same_weights() {
        let mut scene = demo_scene("prism", 0.2).unwrap();
        scene.settings.harmonic.resolution = 16;
        assert!(shared_tables_equal_solving_alone(&scene) >= 4);
    }

    /// On a box grid around an egg, join cages that are turned or mirrored copies of each
    /// other share a solve too, and give the same rows as solving each alone.
    #[test]
    fn turned_and_mirrored_harmonic_join_cages_share_one_solve_with_the_same_weights() {
        let mut scene = demo_scene("egg", 0.3).unwrap();
        scene.cages = crate::generate::autocage(
            &scene.mesh,
            &crate::generate::AutocageOptions {
                grid: [4, 4, 4],
                ..Default::default()
            },
        );
        scene.settings.harmonic.resolution = 12;
        let topology = Topology::new(&scene.cages, JoinPolicy::Hc).unwrap();
        let classes: BTreeMap<ShapeKey, Vec<ShapePlacement>> =
            topology
                .joins
                .values()
                .fold(BTreeMap::new(), |mut classes, join| {
                    let (key, placement) = shape_class(&join.local.cage);
                    classes.entry(key).or_default().push(placement);
                    classes
                });
        let turned = classes.values().any(|members| {
            members
                .iter()
                .any(|m| m.turned_or_mirrored_from(&members[0]))
        });
        assert!(turned, "a class holds turned or mirrored copies");
        assert!(shared_tables_equal_solving_alone(&scene) >= 8);
    }

    /// The creature's four harmonic thighs (mirrored left and right) bind in shared solves,
    /// with the rows each gets alone.
    #[test]
    fn congruent_harmonic_leaves_share_one_solve_with_the_same_weights() {
        let mut scene = demo_scene("creature", 0.2).unwrap();
        scene.settings.harmonic.resolution = 16;
        let topology = Topology::new(&scene.cages, scene.settings.join_coordinates).unwrap();
        let points = scene.mesh.welded_positions();
        let placement = super::super::place(&scene, &topology, points).unwrap();
        let mut members = vec![Vec::new(); scene.cages.leaves.len()];
        for (i, p) in placement.iter().enumerate() {
            if let Placement::Cage(c) = p {
                members[*c].push(i);
            }
        }
        let settings = BindSettings {
            harmonic: scene.settings.harmonic,
        };
        let control = BindControl::default();
        let shared = shared_leaf_tables(
            &scene.cages,
            &topology,
            &members,
            points,
            &settings,
            &control,
        )
        .unwrap();
        assert!(shared.len() >= 4, "{} thighs shared a solve", shared.len());
        for (c, table) in &shared {
            assert_equals_solving_alone(table, &topology.leaves[*c], points, &settings, 7);
        }
    }

    /// Asserts that `table` (from a shared solve) gives every `step`-th of its points the
    /// harmonic rows of solving `cage` alone, to 1e-6.
    fn assert_equals_solving_alone(
        table: &Table,
        cage: &LocalCage,
        points: &[DVec3],
        settings: &BindSettings,
        step: usize,
    ) {
        let control = BindControl::default();
        let alone = Table::compute(
            CoordinateKind::Harmonic,
            cage,
            points,
            table.points.clone(),
            settings,
            &control,
            "test",
        )
        .unwrap();
        for &i in table.points.iter().step_by(step) {
            let (a, b) = (table.get(i).unwrap().0, alone.get(i).unwrap().0);
            let worst = a
                .iter()
                .zip(b)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(worst < 1e-6, "point {i}: {worst}");
        }
    }

    /// Binds every join cage's points through the shared solves and each shared join cage
    /// alone; asserts their rows agree and returns how many join cages were shared.
    fn shared_tables_equal_solving_alone(scene: &crate::scene::Scene) -> usize {
        let topology = Topology::new(&scene.cages, JoinPolicy::Hc).unwrap();
        let points = scene.mesh.welded_positions();
        // Every join cage's points: those inside its incident cages.
        let containment = crate::scene::leaf_containment(&topology.leaves, points);
        let need: Needs = topology
            .joins
            .iter()
            .map(|(&v, join)| {
                let inside = (0..points.len())
                    .filter(|&i| {
                        containment[i]
                            .inside
                            .iter()
                            .chain(&containment[i].on_surface)
                            .any(|c| join.cages.contains(c))
                    })
                    .collect();
                (v, inside)
            })
            .collect();
        let settings = BindSettings {
            harmonic: scene.settings.harmonic,
        };
        let control = BindControl::default();
        let classes = harmonic_classes(&topology, &need);
        let shared =
            solve_harmonic_classes(&classes, &topology, &need, points, &settings, &control)
                .unwrap();
        for (v, table) in &shared {
            assert_equals_solving_alone(table, &topology.joins[v].local, points, &settings, 5);
        }
        shared.len()
    }
}

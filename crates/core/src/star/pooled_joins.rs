//! MVC join cages' tables from each leaf cage's pool of triangles (phase 4 of the bind).
//!
//! A point of leaf cage c with b < 1 is weighed in every join cage of c's boundary vertices
//! (eqs. 6–10), each the union of c and some of its neighbours less their shared faces. Those
//! join cages are made of the faces of c and its neighbours, so the triangle terms of MVC are
//! computed once per point over their pool and summed per join cage
//! ([`crate::coords::bind_mean_value_pooled`]): the same tables as binding each join cage alone,
//! bit for bit, at a fraction of the work (an auto rig's body cage reads seven to nine join
//! cages that repeat its own faces and its neighbours'). Cage vertices bound as extra points
//! (eqs. 6 and 10) are bound in each join cage alone.

use std::collections::BTreeMap;

use glam::DVec3;
use rayon::prelude::*;

use super::StarError;
use super::tables::{Placement, Table};
use super::topology::JoinCage;
use crate::coords::{
    BindControl, BindSettings, CageWeights, CoordinateKind, VertexWeights, bind,
    bind_mean_value_pooled,
};

/// One leaf cage's points in one join cage: the join cage (its index), the points and their
/// rows end to end.
struct Block {
    join: usize,
    points: Vec<usize>,
    rows: Vec<f64>,
}

/// The interpolating (MVC) table of each join cage in `joins` at its `points` (sorted; mesh
/// points below `placement.len()`, cage vertices as extra points above), in `joins`' order.
pub(super) fn pooled_mean_value_tables(
    joins: &[(&JoinCage, Vec<usize>)],
    all_points: &[DVec3],
    placement: &[Placement],
    settings: &BindSettings,
    control: &BindControl,
) -> Result<Vec<Table>, StarError> {
    let offset = placement.len();
    // Per leaf cage, the join cages its points need and which of its points each needs.
    let mut by_cage: BTreeMap<usize, BTreeMap<usize, Vec<usize>>> = BTreeMap::new();
    for (g, (_, points)) in joins.iter().enumerate() {
        for &i in points.iter().take_while(|&&i| i < offset) {
            let (Placement::Cage(c) | Placement::Nearest(c)) = placement[i];
            by_cage.entry(c).or_default().entry(g).or_default().push(i);
        }
    }
    let what = |g: usize| format!("join cage of vertex {}", joins[g].0.vertex);
    // Each leaf cage's points in all its join cages at once: per join cage, its points in
    // this leaf cage and their rows.
    let per_cage: Vec<Vec<Block>> = by_cage
        .par_iter()
        .map(|(_, needs)| {
            let mut points: Vec<usize> = needs.values().flatten().copied().collect();
            points.sort_unstable();
            points.dedup();
            let cages: Vec<_> = needs
                .keys()
                .map(|&g| {
                    let local = &joins[g].0.local;
                    (&local.cage, local.global.as_slice())
                })
                .collect();
            let positions: Vec<DVec3> = points.iter().map(|&i| all_points[i]).collect();
            let weights =
                bind_mean_value_pooled(&cages, &positions, control).map_err(|source| {
                    StarError::Coordinates {
                        what: what(needs.keys().next().copied().unwrap_or_default()),
                        source,
                    }
                })?;
            Ok(needs
                .iter()
                .zip(weights)
                .map(|((&g, wanted), weights)| {
                    if *wanted == points {
                        return Block {
                            join: g,
                            points: points.clone(),
                            rows: weights.weights,
                        };
                    }
                    // Only some of the cage's points need this join cage: their rows.
                    let mut rows = Vec::with_capacity(wanted.len() * weights.vertex_count);
                    for i in wanted {
                        if let Ok(k) = points.binary_search(i) {
                            rows.extend_from_slice(weights.row(k));
                        }
                    }
                    Block {
                        join: g,
                        points: wanted.clone(),
                        rows,
                    }
                })
                .collect())
        })
        .collect::<Result<_, StarError>>()?;
    let mut blocks_of: Vec<Vec<(Vec<usize>, Vec<f64>)>> = vec![Vec::new(); joins.len()];
    for Block {
        join: g,
        points,
        rows,
    } in per_cage.into_iter().flatten()
    {
        blocks_of[g].push((points, rows));
    }
    joins
        .par_iter()
        .zip(blocks_of)
        .enumerate()
        .map(|(g, ((join, points), mut blocks))| {
            let local = &join.local;
            let n = local.cage.vertex_count();
            // The cage vertices among the points, bound alone.
            let extra: Vec<usize> = points.iter().copied().filter(|&i| i >= offset).collect();
            if !extra.is_empty() {
                let positions: Vec<DVec3> = extra.iter().map(|&i| all_points[i]).collect();
                let alone = bind(
                    CoordinateKind::MeanValue,
                    &local.cage,
                    &positions,
                    settings,
                    control,
                )
                .map_err(|source| StarError::Coordinates {
                    what: what(g),
                    source,
                })?;
                if let CageWeights::Vertex { weights, .. } = alone {
                    blocks.push((extra, weights.weights));
                }
            }
            // The blocks end to end (a table's rows need not follow its points' order).
            let (points, weights) = if blocks.len() == 1 {
                blocks.pop().unwrap_or_default()
            } else {
                let count = blocks.iter().map(|(p, _)| p.len()).sum();
                let mut points = Vec::with_capacity(count);
                let mut weights = Vec::with_capacity(count * n);
                for (p, w) in blocks {
                    points.extend(p);
                    weights.extend(w);
                }
                (points, weights)
            };
            Ok(Table::new(
                points,
                CageWeights::Vertex {
                    kind: CoordinateKind::MeanValue,
                    weights: VertexWeights {
                        vertex_count: n,
                        weights,
                    },
                },
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::demo::demo_scene;
    use crate::scene::JoinPolicy;
    use crate::star::topology::Topology;

    /// Every join cage's table from the pools is the table of binding it alone, bit for bit:
    /// the egg's join cages (two to eight boxes each, two with an interior vertex) at the
    /// mesh points inside their boxes, some wanted by only a few of their cages, and at cage
    /// vertices as extra points.
    #[test]
    fn pooled_join_tables_are_each_join_cages_own_bit_for_bit() {
        let scene = demo_scene("egg", 0.25).unwrap();
        let topology = Topology::new(&scene.cages, JoinPolicy::Mvc).unwrap();
        let mesh = scene.mesh.welded_positions();
        let placement = crate::star::place(&scene, &topology, mesh).unwrap();
        let offset = mesh.len();
        let mut all_points = mesh.to_vec();
        all_points.extend_from_slice(&scene.cages.vertices);
        let mut seen = std::collections::BTreeSet::new();
        let joins: Vec<(&JoinCage, Vec<usize>)> = topology
            .joins
            .values()
            .filter(|join| seen.insert(join.cages.clone()))
            .enumerate()
            .map(|(k, join)| {
                let mut points: Vec<usize> = (0..offset)
                    .filter(|&i| match placement[i] {
                        Placement::Cage(c) => join.cages.contains(&c),
                        Placement::Nearest(_) => false,
                    })
                    // Every other join cage leaves out some of its points.
                    .filter(|&i| k % 2 == 0 || i % 3 != 0)
                    .collect();
                points.push(offset + join.vertex as usize);
                (join, points)
            })
            .collect();
        assert!(joins.iter().any(|(j, _)| j.cages.len() == 8));
        let settings = BindSettings::default();
        let control = BindControl::default();
        let pooled =
            pooled_mean_value_tables(&joins, &all_points, &placement, &settings, &control).unwrap();
        for ((join, points), table) in joins.iter().zip(&pooled) {
            let alone = Table::compute(
                CoordinateKind::MeanValue,
                &join.local,
                &all_points,
                points.clone(),
                &settings,
                &control,
                "test",
            )
            .unwrap();
            for &i in points {
                let (a, b) = (table.get(i).unwrap().0, alone.get(i).unwrap().0);
                let bits = |row: &[f64]| row.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(a), bits(b), "join cage of {}, point {i}", join.vertex);
            }
        }
    }
}

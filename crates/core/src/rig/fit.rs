//! Fit to mesh, a shrink-wrap: each vertex of a leaf cage that no other leaf cage shares is
//! pulled toward the mesh vertex nearest to it, as far as keeps every mesh vertex the cage
//! holds inside, a margin from the cage's unshared faces.
//!
//! Moving one vertex changes only the triangles around it, so for each vertex the winding
//! numbers and face distances of the other triangles are summed once, and each step of the
//! bisection evaluates the few triangles that move (in parallel over the mesh vertices).

use std::collections::BTreeSet;

use glam::DVec3;
use rayon::prelude::*;

use super::vocabulary::{RigEditError, face_key, move_rest_vertex};
use crate::cage::Cage;
use crate::geometry::{closest_point_on_triangle, solid_angle};
use crate::scene::{LocalCage, Scene, leaf_containment};

/// The furthest a fit moves a vertex: this fraction of the way to the mesh vertex nearest to it
/// (the margin stops it sooner wherever the mesh is in the way).
const FIT_FURTHEST: f64 = 0.9;

/// The least distance a fit leaves between two vertices of the cage, as a fraction of the
/// cage's diagonal (a cage folded onto one point is valid alone but not inside a join cage).
const FIT_SEPARATION: f64 = 0.02;

/// Bisection steps per vertex and rounds over the vertices (a later round lets a vertex go
/// further once its neighbours have moved).
const STEPS: usize = 20;
const ROUNDS: usize = 3;

/// A held mesh vertex with what the triangles that do not move contribute to its checks.
#[derive(Clone, Copy)]
struct Fixed {
    /// Sum of the solid angles of the triangles that do not move.
    solid_angle: f64,
    /// Distance to the nearest unshared triangle that does not move.
    distance: f64,
}

/// Fits leaf cage `c` of `scene` (see the module) with `margin` a fraction of the mesh's
/// bounding-box diagonal. Poses follow as displacements.
pub fn fit(scene: &mut Scene, c: usize, margin: f64) -> Result<(), RigEditError> {
    let problem = FitProblem::new(scene, c, margin)?;
    let mut positions = problem.start.clone();
    for _ in 0..ROUNDS {
        for &l in &problem.free {
            positions[l] = problem.furthest_fit(&mut positions, l);
            move_rest_vertex(scene, problem.global[l], positions[l]);
        }
    }
    Ok(())
}

/// What a fit of one cage works with, owned so that the scene can change as vertices move.
struct FitProblem {
    /// The cage's vertices as it starts (local numbering) and their scene indices.
    start: Vec<DVec3>,
    global: Vec<u32>,
    /// Its polygons in local numbering (a moved cage must still be a valid cage).
    local_faces: Vec<Vec<u32>>,
    /// Its triangles, each with whether it lies on a face no other cage shares (the margin is
    /// kept from those only: mesh vertices may lie on a border).
    triangles: Vec<([u32; 3], bool)>,
    /// The mesh vertices it holds (they must stay inside) and the clearance each must keep.
    held: Vec<DVec3>,
    clearance: Vec<f64>,
    /// The least distance between two of its vertices.
    separation: f64,
    /// The local vertices no other leaf cage shares: the ones that move.
    free: Vec<usize>,
}

impl FitProblem {
    /// The fit of cage `c`, refused with the reason where the margin is out of range, the cage
    /// is not valid to start with, or it holds no mesh vertex.
    fn new(scene: &Scene, c: usize, margin: f64) -> Result<Self, RigEditError> {
        let name = &scene.cages.leaves[c].name;
        if !(0.0..=0.5).contains(&margin) {
            return Err(RigEditError::Value(format!(
                "fit {name}: margin {margin} must be in [0, 0.5] (a fraction of the mesh's diagonal)"
            )));
        }
        let (lo, hi) = scene.mesh.bounds();
        let gap = margin * (hi - lo).length();
        let faces = &scene.cages.leaves[c].faces;
        let start = LocalCage::new(&scene.cages.vertices, faces).map_err(|e| {
            RigEditError::Value(format!(
                "fit {name}: the cage is not valid to start with: {e}"
            ))
        })?;
        let points = scene.mesh.welded_positions();
        let held: Vec<DVec3> = leaf_containment(std::slice::from_ref(&start), points)
            .iter()
            .zip(points)
            .filter(|(c, _)| c.is_covered())
            .map(|(_, p)| *p)
            .collect();
        if held.is_empty() {
            return Err(RigEditError::Value(format!(
                "fit {name}: it holds no mesh vertex to fit to"
            )));
        }
        let others = |f: &Vec<u32>| {
            let key = face_key(f);
            scene
                .cages
                .leaves
                .iter()
                .enumerate()
                .any(|(i, l)| i != c && l.faces.iter().any(|g| face_key(g) == key))
        };
        let shared_face: Vec<bool> = faces.iter().map(others).collect();
        let shared: BTreeSet<u32> = scene
            .cages
            .leaves
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != c)
            .flat_map(|(_, l)| l.faces.iter().flatten().copied())
            .collect();
        let global = start.global.clone();
        let local_faces: Vec<Vec<u32>> = faces
            .iter()
            .map(|f| {
                f.iter()
                    .map(|v| global.binary_search(v).map_or(0, |i| i as u32))
                    .collect()
            })
            .collect();
        let triangles: Vec<([u32; 3], bool)> = start
            .cage
            .triangles()
            .iter()
            .zip(start.cage.triangle_polygon())
            .map(|(t, poly)| (*t, !shared_face[*poly as usize]))
            .collect();
        let positions = start.cage.positions().to_vec();
        // Each held vertex keeps the margin, or, where it starts closer than the margin (a tip
        // against an end face), at least the distance it has: it must not freeze every other
        // vertex of the cage.
        let clearance: Vec<f64> = held
            .par_iter()
            .map(|&p| {
                let nearest = triangles
                    .iter()
                    .filter(|(_, free)| *free)
                    .map(|(t, _)| distance_to(&positions, *t, p))
                    .fold(f64::INFINITY, f64::min);
                gap.min(nearest * (1.0 - 1e-9))
            })
            .collect();
        let free = (0..global.len())
            .filter(|&l| !shared.contains(&global[l]))
            .collect();
        Ok(Self {
            separation: FIT_SEPARATION * start.cage.diagonal(),
            start: positions,
            global,
            local_faces,
            triangles,
            held,
            clearance,
            free,
        })
    }

    /// How far local vertex `l` can go toward the held mesh vertex nearest to it (at most
    /// [`FIT_FURTHEST`] of the way) with the cage still valid, its vertices apart and every
    /// held vertex inside and clear: a bisection over the fraction. `positions` is scratch
    /// space holding the cage as it is (vertex `l` is left anywhere).
    fn furthest_fit(&self, positions: &mut [DVec3], l: usize) -> DVec3 {
        let (moving, still): (Vec<_>, Vec<_>) = self
            .triangles
            .iter()
            .copied()
            .partition(|(t, _)| t.contains(&(l as u32)));
        // What the triangles that do not move contribute, summed once.
        let fixed: Vec<Fixed> = self
            .held
            .par_iter()
            .map(|&p| Fixed {
                solid_angle: still.iter().map(|(t, _)| angle_of(positions, *t, p)).sum(),
                distance: still
                    .iter()
                    .filter(|(_, free)| *free)
                    .map(|(t, _)| distance_to(positions, *t, p))
                    .fold(f64::INFINITY, f64::min),
            })
            .collect();
        let from = positions[l];
        let target = self
            .held
            .iter()
            .copied()
            .min_by(|a, b| {
                a.distance_squared(from)
                    .total_cmp(&b.distance_squared(from))
            })
            .unwrap_or(from);
        let (mut ok, mut bad) = (0.0f64, FIT_FURTHEST);
        for _ in 0..STEPS {
            let t = 0.5 * (ok + bad);
            positions[l] = from + (target - from) * t;
            if self.fits(positions, l, &moving, &fixed) {
                ok = t;
            } else {
                bad = t;
            }
        }
        from + (target - from) * ok
    }

    /// Whether the cage at `positions` (vertex `l` moved; `moving` its triangles, `fixed` the
    /// others' sums per held vertex) is valid, keeps its vertices apart, and holds every held
    /// vertex inside (winding number above ½) and clear of its unshared faces.
    fn fits(
        &self,
        positions: &[DVec3],
        l: usize,
        moving: &[([u32; 3], bool)],
        fixed: &[Fixed],
    ) -> bool {
        let at = positions[l];
        let crowded = positions
            .iter()
            .enumerate()
            .any(|(k, q)| k != l && q.distance(at) < self.separation);
        !crowded
            && Cage::from_polygons(positions.to_vec(), self.local_faces.clone()).is_ok()
            && self
                .held
                .par_iter()
                .zip(fixed)
                .zip(&self.clearance)
                .all(|((&p, fixed), &least)| {
                    let angle = fixed.solid_angle
                        + moving
                            .iter()
                            .map(|(t, _)| angle_of(positions, *t, p))
                            .sum::<f64>();
                    let distance = moving
                        .iter()
                        .filter(|(_, free)| *free)
                        .map(|(t, _)| distance_to(positions, *t, p))
                        .fold(fixed.distance, f64::min);
                    angle / (4.0 * std::f64::consts::PI) > 0.5 && distance >= least
                })
    }
}

/// Distance from `p` to triangle `t` of the cage at `positions`.
fn distance_to(positions: &[DVec3], t: [u32; 3], p: DVec3) -> f64 {
    let [a, b, c] = t.map(|v| positions[v as usize]);
    closest_point_on_triangle(p, a, b, c).0.distance(p)
}

/// Solid angle triangle `t` of the cage at `positions` subtends at `p`.
fn angle_of(positions: &[DVec3], t: [u32; 3], p: DVec3) -> f64 {
    let [a, b, c] = t.map(|v| positions[v as usize] - p);
    solid_angle(a, b, c)
}

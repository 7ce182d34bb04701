//! A drag's deformation as an affine function of the few vertices it moves by hand.
//!
//! Dragging an internal cage moves many leaf-cage vertices (section 3.4), so the mesh rows it
//! reaches are most of a big mesh and each update costs a whole sparse product. But with MVC
//! or HC leaves and internal cages, every leaf vertex is a fixed linear combination of the
//! dragged vertices d_m while the hierarchy's follows stay as they are, and so is every mesh
//! row: row_r = row_r⁰ + Σ_m K_rm (d_m − d_m⁰), K = S·A with S the compiled operator and A
//! the hierarchy's sensitivities ([`crate::hierarchy::Hierarchy::driver_sensitivity`]). K has
//! one column per dragged vertex (8 for a box) instead of the operator's ~150 weights per row.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::StarOperator;
use crate::hierarchy::MAX_DRIVERS;

/// f32 lanes summed together when the map is built.
const LANES: usize = 8;
const _: () = assert!(MAX_DRIVERS.is_multiple_of(LANES));

/// The most coefficients (rows × drivers) a map holds: 128 MB of `f32`.
const MAX_COEFFICIENTS: usize = 32 << 20;

/// Mesh rows as an affine function of a drag's driving vertices, from the state it was built
/// in.
#[derive(Debug, Clone)]
pub struct DriverMap {
    drivers: Vec<u32>,
    driver_start: Vec<DVec3>,
    /// Every cage vertex's position when the map was made.
    posed_start: Vec<DVec3>,
    /// Per cage vertex, its row of derivatives per driver, for followers.
    follows: Vec<Option<Vec<f64>>>,
    rows: Vec<u32>,
    row_start: Vec<Vec3>,
    /// K, rows × drivers, row-major.
    coefficients: Vec<f32>,
}

impl DriverMap {
    /// The map for `drivers` from `sensitivity` (every vertex that follows them, with its
    /// derivative per driver, as [`crate::hierarchy::Hierarchy::driver_sensitivity`] gives it),
    /// the cage vertices `posed` now and the `deformed` mesh they give (the operator's product
    /// for them). None where the mesh is not linear in the followers (a Green leaf cage has one
    /// among its vertices: its DOFs are scaled normals) or the map would be too large.
    pub fn new(
        operator: &StarOperator,
        drivers: &[u32],
        sensitivity: &[(u32, Vec<f64>)],
        posed: &[DVec3],
        deformed: &[Vec3],
    ) -> Option<Self> {
        let m = drivers.len();
        let vertex_count = posed.len();
        let followers: Vec<u32> = sensitivity.iter().map(|(v, _)| *v).collect();
        if m == 0
            || m > MAX_DRIVERS
            || deformed.len() != operator.row_count()
            || followers.iter().any(|&v| v as usize >= vertex_count)
            || sensitivity.iter().any(|(_, s)| s.len() != m)
        {
            return None;
        }
        let columns = operator.columns_of_moved_vertices(&followers);
        if columns.iter().any(|&c| c as usize >= vertex_count) {
            return None; // a Green DOF moves: not linear
        }
        // Every row when the followers hold most weights (an internal cage over the whole
        // mesh): reading the transpose to find them cost more than the pass below.
        let rows: Vec<u32> = if operator.holds_most_weights(&columns) {
            (0..operator.row_count() as u32).collect()
        } else {
            operator.rows_touched(&columns)
        };
        if rows.len().saturating_mul(m) > MAX_COEFFICIENTS {
            return None;
        }
        let mut follows: Vec<Option<Vec<f64>>> = vec![None; vertex_count];
        // The derivatives flat in blocks of eight f32 lanes per follower (zero-padded), and
        // each column's follower (u32::MAX: none): the pass over the rows reads two arrays,
        // allocates nothing, and adds w × a block in one vector operation (or two).
        let blocks = m.div_ceil(LANES);
        let mut follower_of = vec![u32::MAX; vertex_count];
        let mut flat: Vec<[f32; LANES]> = vec![[0.0; LANES]; sensitivity.len() * blocks];
        for (k, (v, s)) in sensitivity.iter().enumerate() {
            follows[*v as usize] = Some(s.clone());
            follower_of[*v as usize] = k as u32;
            for (j, value) in s.iter().enumerate() {
                flat[k * blocks + j / LANES][j % LANES] = *value as f32;
            }
        }
        let mut coefficients = vec![0.0f32; rows.len() * m];
        coefficients
            .par_chunks_mut(m)
            .zip(rows.par_iter())
            .with_min_len(1024)
            .for_each(|(out, &r)| {
                let mut sum = [[0.0f32; LANES]; MAX_DRIVERS / LANES];
                let sum = &mut sum[..blocks];
                for (c, w) in operator.row(r as usize) {
                    let Some(&k) = follower_of.get(c as usize) else {
                        continue;
                    };
                    if k == u32::MAX {
                        continue;
                    }
                    let s = &flat[k as usize * blocks..(k as usize + 1) * blocks];
                    for (acc, s) in sum.iter_mut().zip(s) {
                        for lane in 0..LANES {
                            acc[lane] += w * s[lane];
                        }
                    }
                }
                for (j, o) in out.iter_mut().enumerate() {
                    *o = sum[j / LANES][j % LANES];
                }
            });
        // Rows whose coefficients are all zero do not move: drop them.
        let moves = |k: &[f32]| k.iter().any(|&k| k != 0.0);
        let rows: Vec<u32> = rows
            .iter()
            .zip(coefficients.chunks(m))
            .filter(|(_, k)| moves(k))
            .map(|(&r, _)| r)
            .collect();
        coefficients = coefficients
            .chunks(m)
            .filter(|k| moves(k))
            .flatten()
            .copied()
            .collect();
        Some(Self {
            drivers: drivers.to_vec(),
            driver_start: drivers.iter().map(|&d| posed[d as usize]).collect(),
            posed_start: posed.to_vec(),
            follows,
            row_start: rows.iter().map(|&r| deformed[r as usize]).collect(),
            rows,
            coefficients,
        })
    }

    /// The driving vertices, in the order of the map's columns.
    pub fn drivers(&self) -> &[u32] {
        &self.drivers
    }

    /// Mesh rows the drivers move.
    pub fn row_count(&self) -> usize {
        self.rows.len()
    }

    /// Whether `posed` is a pose the map describes: the followers where the drivers' moves
    /// put them (to 1e-9 of their distance from the origin and their move), every other cage
    /// vertex where it was. False after anything else changed the pose or the hierarchy's
    /// follows (a vertex moved by hand re-bound when its parent moved).
    pub fn describes(&self, posed: &[DVec3]) -> bool {
        if posed.len() != self.posed_start.len() {
            return false;
        }
        let delta: Vec<DVec3> = self
            .drivers
            .iter()
            .zip(&self.driver_start)
            .map(|(&d, start)| posed[d as usize] - *start)
            .collect();
        posed
            .iter()
            .zip(&self.posed_start)
            .zip(&self.follows)
            .all(|((now, start), follows)| match follows {
                None => now == start,
                Some(row) => {
                    let moved: DVec3 = row.iter().zip(&delta).map(|(k, d)| *d * *k).sum();
                    let tolerance = 1e-9 * (1.0 + start.length() + moved.length());
                    (*now - (*start + moved)).length() <= tolerance
                }
            })
    }

    /// Sets the rows the drivers move to their positions for `posed` (the whole pose, indexed
    /// by cage vertex), when the map [`DriverMap::describes`] it; the other rows of `out` are
    /// left as they are. False, leaving `out` alone, when it does not.
    pub fn apply(&self, posed: &[DVec3], out: &mut [Vec3]) -> bool {
        if !self.describes(posed) {
            return false;
        }
        let delta: Vec<Vec3> = self
            .drivers
            .iter()
            .zip(&self.driver_start)
            .map(|(&d, start)| (posed[d as usize] - *start).as_vec3())
            .collect();
        let m = delta.len();
        let values: Vec<Vec3> = self
            .coefficients
            .par_chunks(m)
            .zip(self.row_start.par_iter())
            .with_min_len(4096)
            .map(|(k, start)| {
                k.iter()
                    .zip(&delta)
                    .fold(*start, |acc, (&k, &d)| acc + d * k)
            })
            .collect();
        for (&r, v) in self.rows.iter().zip(values) {
            if let Some(slot) = out.get_mut(r as usize) {
                *slot = v;
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coords::{BindControl, CoordinateKind};
    use crate::generate::demo::demo_scene;
    use crate::hierarchy::Hierarchy;
    use crate::scene::Scene;
    use crate::star::StarBinding;
    use glam::DQuat;

    /// The critter's head cage (MVC, over the ears' HC cage and the leaves): its vertices.
    fn head_drivers(scene: &Scene) -> Vec<u32> {
        scene.cages.cage_vertices("head").unwrap()
    }

    /// Moves `drivers` by `motion` about their centre through the hierarchy.
    fn drag(
        hierarchy: &mut Hierarchy,
        pose: &mut [DVec3],
        drivers: &[u32],
        motion: impl Fn(DVec3) -> DVec3,
    ) {
        let centre =
            drivers.iter().map(|&d| pose[d as usize]).sum::<DVec3>() / drivers.len() as f64;
        let moves: Vec<(u32, DVec3)> = drivers
            .iter()
            .map(|&d| (d, centre + motion(pose[d as usize] - centre)))
            .collect();
        hierarchy.apply(pose, &moves).unwrap();
    }

    fn largest_difference(a: &[Vec3], b: &[Vec3]) -> f32 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (*x - *y).length())
            .fold(0.0, f32::max)
    }

    /// Dragging the critter's head cage (turned, scaled, moved: every leaf vertex follows
    /// through the ears' HC cage or the head's MVC cage) gives through the map what the whole
    /// sparse product gives, to f32 rounding, from a map built mid-drag.
    #[test]
    fn a_drag_through_the_driver_map_equals_the_full_product() {
        let mut scene = demo_scene("critter", 0.5).unwrap();
        // Its right ear is Green (the other test): mean value, as the rest.
        for leaf in &mut scene.cages.leaves {
            leaf.kind = CoordinateKind::MeanValue;
        }
        let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
        let mut hierarchy = Hierarchy::bind(&scene).unwrap();
        let rest = &scene.cages.vertices;
        let drivers = head_drivers(&scene);
        let mut pose = scene.pose.clone();
        drag(&mut hierarchy, &mut pose, &drivers, |d| {
            d + DVec3::new(0.05, 0.0, 0.02)
        });
        let deformed = binding.deform(rest, &pose);
        let sensitivity = hierarchy.driver_sensitivity(&drivers).unwrap();
        assert!(
            sensitivity.len() > drivers.len() + 20,
            "leaf vertices follow"
        );
        let map =
            DriverMap::new(&binding.operator, &drivers, &sensitivity, &pose, &deformed).unwrap();
        assert!(
            map.row_count() > deformed.len() / 2,
            "{} rows",
            map.row_count()
        );
        let rebound = hierarchy.stats().rebound;
        let turn = DQuat::from_rotation_z(0.4) * DQuat::from_rotation_x(-0.2);
        drag(&mut hierarchy, &mut pose, &drivers, |d| {
            turn * (d * 1.2) + DVec3::new(-0.1, 0.2, 0.05)
        });
        assert_eq!(hierarchy.stats().rebound, rebound, "no follow was re-bound");
        let full = binding.deform(rest, &pose);
        let mut through_map = deformed.clone();
        assert!(map.apply(&pose, &mut through_map));
        let (lo, hi) = scene.mesh.bounds();
        let size = (hi - lo).length() as f32;
        let error = largest_difference(&full, &through_map);
        assert!(error <= 1e-5 * size, "map off by {error} (diagonal {size})");
        // The control: the drag moved the mesh far beyond that tolerance.
        let moved = largest_difference(&full, &deformed);
        assert!(moved > 1e-2 * size, "the drag moved the mesh by {moved}");
        // A pose the map does not describe is refused: another vertex moved too.
        let mut other = pose.clone();
        other[0] += DVec3::splat(1e-3);
        let mut untouched = full.clone();
        assert!(!map.apply(&other, &mut untouched));
        assert_eq!(untouched, full);
    }

    /// A Green leaf cage among the followers (the critter's right ear) makes the mesh
    /// nonlinear in them: no map.
    #[test]
    fn there_is_no_driver_map_over_a_green_leaf() {
        let scene = demo_scene("critter", 0.5).unwrap();
        assert!(
            scene
                .cages
                .leaves
                .iter()
                .any(|l| l.kind == CoordinateKind::Green)
        );
        let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
        let hierarchy = Hierarchy::bind(&scene).unwrap();
        let drivers = head_drivers(&scene);
        let sensitivity = hierarchy.driver_sensitivity(&drivers).unwrap();
        let deformed = binding.deform(&scene.cages.vertices, &scene.pose);
        let map = DriverMap::new(
            &binding.operator,
            &drivers,
            &sensitivity,
            &scene.pose,
            &deformed,
        );
        assert!(map.is_none());
    }
}

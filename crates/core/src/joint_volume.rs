//! Volume-keeping joints: after the posing engine has mitred a bent joint's ring
//! (`hierarchy::joint`), the ring is widened or narrowed by the one amount that gives the mesh
//! around the joint back its rest volume. The mitre keeps the *cages'* volume, but the mesh
//! inside them loses 3–6 % at a 90° knee and gains up to 12 % at an elbow, by amounts that
//! differ between meshes and even between the two sides of one rig: no rule on the cage alone
//! brings every limb within 2 % (docs/math.md, "Joints"). So the amount is measured on the
//! mesh itself, through the binding.
//!
//! Per joint, the *region* is the closed surface made of the mesh triangles that have a corner
//! whose row reads a ring vertex (the rows the ring moves), closed by a fan over each loop of
//! its border. Its enclosed volume does not depend on where it is measured from, and a rigid
//! motion of either side leaves it as it was, so it changes only by what the bend does to the
//! mesh. A bent joint's ring is scaled by one scalar `s` across the mitre plane's normal (the
//! bisector of the two sides' axes), solved by the secant method so that the region's volume
//! is its rest volume:
//! - `s < 0` (the bend gained volume): the ring narrows evenly towards its centre;
//! - `s > 0` (it lost volume): the ring widens on the outer side of the bend only, as a knee
//!   cap or an elbow stands out, blended towards an even widening for a joint that twists
//!   rather than swings (swing under 20°); pushing the inner side out as well would fold the
//!   crease.
//!
//! The mesh is linear in the ring for mean value and harmonic cages, so the volume is a cubic
//! in `s`; the secant method takes three to five evaluations of the region's rows. A joint at
//! rest relative to its parent is left as the mitre put it, so the rest pose stays exact.

use std::sync::atomic::{AtomicU64, Ordering};

use glam::{DAffine3, DVec3, Vec3};

use crate::hierarchy::affine_fit;
use crate::scene::CageSet;
use crate::star::StarOperator;

/// A region's volume change (as a share of its rest volume) below which its joint is left as
/// the mitre put it: a settled pose settled again does not move.
const SETTLED: f64 = 1e-3;

/// The share the secant method stops at.
const SOLVED: f64 = 1e-4;

/// The regions' triangles, all joints together, as a multiple of the mesh's: an auto rig's
/// hold 2.6–4.6 (the shared meshes; a body-rooted ring's region is most of the body).
const REGION_BUDGET: usize = 16;

/// Sweeps over the bent joints, at most.
const MAX_SWEEPS: usize = 4;

/// Evaluations of the region per joint and sweep, at most.
const MAX_EVALUATIONS: usize = 10;

/// The range of the ring's scale: a ring narrowed by more than 40 % pinches the limb, and one
/// widened by more than 80 % of its radius on the outer side is a lump; a region whose volume
/// needs more is left at the bound.
const S_MIN: f64 = -0.4;
const S_MAX: f64 = 0.8;

/// The swing (radians) from which a widening is on the outer side only; below it, blended
/// towards an even widening (a twist has no outer side).
const FULL_SWING: f64 = 20.0 * std::f64::consts::PI / 180.0;

/// One control's joint and the part of the mesh its ring moves.
#[derive(Debug, Clone)]
struct JointRegion {
    /// The control's cage vertices and their rest positions, for its motion.
    control: Vec<u32>,
    control_rest: Vec<DVec3>,
    /// The parent control's.
    parent: Vec<u32>,
    parent_rest: Vec<DVec3>,
    /// Unit direction along the limb at rest, from the pivot towards the control.
    axis: DVec3,
    /// The ring's cage vertices.
    ring: Vec<u32>,
    /// Welded triangles with a corner in a row that reads the ring.
    triangles: Vec<[u32; 3]>,
    /// The border loops of `triangles`: each loop's vertices and its border edges, directed
    /// as the triangles run them.
    loops: Vec<(Vec<u32>, Vec<[u32; 2]>)>,
    /// The ring's vertices, sorted.
    ring_sorted: Vec<u32>,
    /// Every row `triangles` use, sorted.
    rows: Vec<u32>,
    /// The region's volume at rest.
    rest_volume: f64,
    /// Its place among the scene's joints (for its hint).
    index: usize,
}

/// The joints of a bound scene with the regions their rings move, built once per binding.
#[derive(Debug, Default)]
pub struct JointVolumes {
    joints: Vec<JointRegion>,
    /// Per joint, the scale its last settle found (f64 bits): where the next one starts, so a
    /// drag's step costs two or three evaluations of the region rather than four or five.
    hints: Vec<AtomicU64>,
    /// Rest cage positions the binding was made for.
    rest: Vec<DVec3>,
}

impl JointVolumes {
    /// The joints of `set`'s controls (an internal cage with a pivot and a ring owned by its
    /// parent control), with their regions in the mesh of `triangles` bound by `operator`.
    pub fn new(set: &CageSet, triangles: &[[u32; 3]], operator: &StarOperator) -> Self {
        Self::with_budget(set, triangles, operator, REGION_BUDGET)
    }

    /// [`JointVolumes::new`] holding at most `budget` times the mesh's triangles in all
    /// regions together, joints in the scene's order: past it a joint keeps the mitre alone. A scene file with hundreds of rings around one cage that holds the whole
    /// mesh would otherwise hold the mesh once per ring.
    pub fn with_budget(
        set: &CageSet,
        triangles: &[[u32; 3]],
        operator: &StarOperator,
        budget: usize,
    ) -> Self {
        let rest_dofs = operator.dofs(&set.vertices, &set.vertices);
        let mut rest_mesh = vec![Vec3::ZERO; operator.row_count()];
        operator.apply(&rest_dofs, &mut rest_mesh);
        let around = TrianglesOfRow::new(triangles, operator.row_count());
        let mut taken = vec![false; triangles.len()];
        let budget = budget.saturating_mul(triangles.len());
        let mut held = 0;
        let mut joints = Vec::new();
        for cage in &set.internals {
            let (Some(pivot), false) = (cage.pivot, cage.joint.is_empty()) else {
                continue;
            };
            let Some(parent) = set
                .internals
                .iter()
                .find(|p| p.owns.contains(&cage.joint[0]))
            else {
                continue;
            };
            let corners = |faces: &[Vec<u32>]| {
                let mut v: Vec<u32> = faces.iter().flatten().copied().collect();
                v.sort_unstable();
                v.dedup();
                v
            };
            let (control, parent) = (corners(&cage.faces), corners(&parent.faces));
            let at_rest = |vs: &[u32]| -> Option<Vec<DVec3>> {
                vs.iter()
                    .map(|&v| set.vertices.get(v as usize).copied())
                    .collect()
            };
            let (Some(control_rest), Some(parent_rest)) = (at_rest(&control), at_rest(&parent))
            else {
                continue;
            };
            let centroid = control_rest.iter().sum::<DVec3>() / control_rest.len().max(1) as f64;
            let Some(axis) = (centroid - pivot).try_normalize() else {
                continue;
            };
            if cage.joint.iter().any(|&v| v as usize >= set.vertices.len()) {
                continue;
            }
            let columns = operator.columns_of_moved_vertices(&cage.joint);
            let touched = operator.rows_touched(&columns);
            let region = Region::of_rows(&touched, triangles, &around, &mut taken);
            held += region.triangles.len();
            if region.triangles.is_empty() || held > budget {
                continue;
            }
            let rest_volume = region_volume(&rest_mesh, &region.triangles, &region.loops);
            if !(rest_volume.is_finite() && rest_volume.abs() > 0.0) {
                continue;
            }
            joints.push(JointRegion {
                control,
                control_rest,
                parent,
                parent_rest,
                axis,
                ring: cage.joint.clone(),
                ring_sorted: {
                    let mut ring = cage.joint.clone();
                    ring.sort_unstable();
                    ring
                },
                triangles: region.triangles,
                loops: region.loops,
                rows: region.rows,
                rest_volume,
                index: joints.len(),
            });
        }
        Self {
            hints: joints.iter().map(|_| AtomicU64::new(0)).collect(),
            joints,
            rest: set.vertices.clone(),
        }
    }

    /// Whether the scene has no joint with a ring.
    pub fn is_empty(&self) -> bool {
        self.joints.is_empty()
    }

    /// The joints whose volume is kept.
    pub fn len(&self) -> usize {
        self.joints.len()
    }

    /// Settles every bent joint of `pose` (cage positions for the binding's scene): its ring
    /// scaled so that its region has its rest volume. With `moved` (sorted: the vertices the
    /// posing engine just moved; a live rig's path), only the joints whose ring it moved, so
    /// that a hand move of a leaf vertex near a joint is not undone, each solve starting from
    /// where the joint's last one ended; without, every bent joint from scratch, so the result
    /// depends on the pose alone. A ring holding a vertex for which `keep` is true (moved by
    /// hand) is left alone. Returns the ring vertices it moved, sorted.
    pub fn settle(
        &self,
        operator: &StarOperator,
        pose: &mut [DVec3],
        moved: Option<&[u32]>,
        keep: &dyn Fn(u32) -> bool,
    ) -> Vec<u32> {
        if self.joints.is_empty() || pose.len() != self.rest.len() {
            return Vec::new();
        }
        let mut dofs: Option<Vec<Vec3>> = None;
        let mut mesh: Vec<Vec3> = Vec::new();
        let mut settled = Vec::new();
        let bent: Vec<(&JointRegion, Bend)> = self
            .joints
            .iter()
            .filter(|joint| {
                moved.is_none_or(|m| intersects(m, &joint.ring_sorted))
                    && !joint.ring.iter().any(|&v| keep(v))
            })
            .filter_map(|joint| Some((joint, Bend::of(joint, pose)?)))
            .collect();
        if bent.is_empty() {
            return settled;
        }
        let x = dofs.get_or_insert_with(|| operator.dofs(&self.rest, pose));
        mesh.resize(operator.row_count(), Vec3::ZERO);
        // Gauss–Seidel: neighbouring joints share a segment's rows (a hip's region and its
        // knee's both hold the thigh), so a sweep is repeated until no ring moves.
        for sweep in 0..MAX_SWEEPS {
            let mut any = false;
            for (joint, bend) in &bent {
                let base: Vec<DVec3> = joint.ring.iter().map(|&v| pose[v as usize]).collect();
                let mut volume_at = |s: f64, pose: &mut [DVec3]| -> f64 {
                    for (&v, p) in joint.ring.iter().zip(bend.bulged(&base, s)) {
                        pose[v as usize] = p;
                    }
                    operator.update_dofs(&self.rest, pose, &joint.ring, x);
                    operator.apply_rows(&joint.rows, x, &mut mesh);
                    region_volume(&mesh, &joint.triangles, &joint.loops) - joint.rest_volume
                };
                // In a live rig's first sweep, from where this joint's last settle ended (a
                // drag's previous step); a whole settle starts from 0, so that a pose settles
                // to the same cages whatever was settled before (a bake against its frames
                // shown one by one).
                let hint = &self.hints[joint.index];
                let start = if sweep == 0 && moved.is_some() {
                    f64::from_bits(hint.load(Ordering::Relaxed))
                } else {
                    0.0
                };
                let solved = solve(|s| volume_at(s, pose), joint.rest_volume, start);
                if sweep == 0 {
                    hint.store(solved.scale.to_bits(), Ordering::Relaxed);
                }
                // Leave the ring at the solution (it is where the last evaluation left it, or
                // as it was when nothing needed doing).
                if solved.scale != solved.last {
                    volume_at(solved.scale, pose);
                }
                if solved.scale != 0.0 {
                    any = true;
                    settled.extend_from_slice(&joint.ring);
                }
            }
            if !any {
                break;
            }
        }
        settled.sort_unstable();
        settled.dedup();
        settled
    }
}

/// What [`solve`] found: the scale, and the last one it evaluated (where the ring was left).
struct Solved {
    scale: f64,
    last: f64,
}

/// The scale `s` at which `excess(s)` (the region's volume less its rest volume) vanishes, by
/// the secant method from 0 and `start` (a previous solution, when it widens or narrows as
/// this one must; else ±0.05) within [`S_MIN`, `S_MAX`]; 0 when the region is settled
/// already, the best evaluated otherwise.
fn solve(mut excess: impl FnMut(f64) -> f64, rest_volume: f64, start: f64) -> Solved {
    let e0 = excess(0.0);
    let size = rest_volume.abs();
    if !e0.is_finite() || e0.abs() <= SETTLED * size {
        return Solved {
            scale: 0.0,
            last: 0.0,
        };
    }
    // Lost volume (a change against the region's orientation): widen; gained: narrow.
    let widen = e0 * rest_volume < 0.0;
    let (mut s0, mut e_prev) = (0.0, e0);
    let mut s1 = match (widen, start) {
        (true, s) if s > 0.0 && s <= S_MAX => s,
        (false, s) if (S_MIN..0.0).contains(&s) => s,
        (true, _) => 0.05,
        (false, _) => -0.05,
    };
    let mut e1 = excess(s1);
    let mut best = (0.0, e0.abs());
    for _ in 2..MAX_EVALUATIONS {
        if e1.is_finite() && e1.abs() < best.1 {
            best = (s1, e1.abs());
        }
        if !e1.is_finite() || e1.abs() <= SOLVED * size {
            break;
        }
        let slope = (e1 - e_prev) / (s1 - s0);
        if !(slope.is_finite() && slope != 0.0) {
            break;
        }
        let s2 = (s1 - e1 / slope).clamp(S_MIN, S_MAX);
        if s2 == s1 {
            break;
        }
        (s0, e_prev, s1) = (s1, e1, s2);
        e1 = excess(s1);
    }
    if e1.is_finite() && e1.abs() < best.1 {
        best = (s1, e1.abs());
    }
    Solved {
        scale: best.0,
        last: s1,
    }
}

/// A joint's bend in a pose: the mitre plane's normal and the outer side of the bend.
struct Bend {
    /// The bisector of the two sides' axes (the ring's normal).
    normal: DVec3,
    /// Across the normal, away from where the control swings (zero without a swing).
    outer: DVec3,
    /// 0 for a pure twist, 1 from [`FULL_SWING`]: how much of a widening is one-sided.
    one_sided: f64,
}

impl Bend {
    /// The bend of `joint` in `pose`; None where the control has not moved relative to its
    /// parent (or either is flat).
    fn of(joint: &JointRegion, pose: &[DVec3]) -> Option<Self> {
        let now = |vs: &[u32]| -> Option<Vec<DVec3>> {
            vs.iter().map(|&v| pose.get(v as usize).copied()).collect()
        };
        let control: DAffine3 = affine_fit(&joint.control_rest, &now(&joint.control)?)?;
        let parent: DAffine3 = affine_fit(&joint.parent_rest, &now(&joint.parent)?)?;
        let size = joint
            .control_rest
            .iter()
            .map(|p| (*p - joint.control_rest[0]).length())
            .fold(0.0, f64::max);
        let apart = joint
            .control_rest
            .iter()
            .map(|&p| (control.transform_point3(p) - parent.transform_point3(p)).length())
            .fold(0.0, f64::max);
        if apart <= 1e-9 * size.max(f64::MIN_POSITIVE) {
            return None;
        }
        let along_control = control.transform_vector3(joint.axis).try_normalize()?;
        let along_parent = parent.transform_vector3(joint.axis).try_normalize()?;
        let normal = (along_control + along_parent).try_normalize()?;
        let away = along_parent - along_control;
        let outer = (away - away.dot(normal) * normal).normalize_or_zero();
        let swing = along_control.angle_between(along_parent);
        let t = (swing / FULL_SWING).clamp(0.0, 1.0);
        Some(Self {
            normal,
            outer,
            one_sided: t * t * (3.0 - 2.0 * t),
        })
    }

    /// The ring `base` scaled by `s` across the normal about its centre: evenly when
    /// narrowing, on the outer side (blended by `one_sided`) when widening.
    fn bulged<'a>(&'a self, base: &'a [DVec3], s: f64) -> impl Iterator<Item = DVec3> + 'a {
        let centre = base.iter().sum::<DVec3>() / base.len().max(1) as f64;
        let normal = ring_normal(base, centre, self.normal);
        base.iter().map(move |&p| {
            let d = p - centre;
            let across = d - d.dot(normal) * normal;
            let even = across;
            let outer = d.dot(self.outer).max(0.0) * self.outer;
            let direction = if s < 0.0 {
                even
            } else {
                (1.0 - self.one_sided) * even + self.one_sided * outer
            };
            p + s * direction
        })
    }
}

/// The normal of the ring's least-squares plane (the covariance's least eigenvector, by
/// inverse iteration from `guess`): a ring laid across the limb at a slant is scaled in its
/// own plane. `guess` where the ring is a line or a point.
fn ring_normal(ring: &[DVec3], centre: DVec3, guess: DVec3) -> DVec3 {
    let mut spread = glam::DMat3::ZERO;
    for &p in ring {
        let d = p - centre;
        spread += glam::DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    let trace = spread.x_axis.x + spread.y_axis.y + spread.z_axis.z;
    let shifted = spread + glam::DMat3::from_diagonal(DVec3::splat(1e-9 * trace));
    if trace.is_nan() || trace <= 0.0 || shifted.determinant().abs() <= f64::MIN_POSITIVE {
        return guess;
    }
    let inverse = shifted.inverse();
    let mut normal = guess;
    for _ in 0..8 {
        match (inverse * normal).try_normalize() {
            Some(n) => normal = n,
            None => return guess,
        }
    }
    if normal.dot(guess) < 0.0 {
        -normal
    } else {
        normal
    }
}

/// The triangles of a region and what closes them.
struct Region {
    triangles: Vec<[u32; 3]>,
    loops: Vec<(Vec<u32>, Vec<[u32; 2]>)>,
    rows: Vec<u32>,
}

/// The triangles around each mesh row (CSR), to gather a region from its rows.
struct TrianglesOfRow {
    start: Vec<u32>,
    triangle: Vec<u32>,
}

impl TrianglesOfRow {
    /// The index of `triangles` (those with a corner beyond `row_count` left out).
    fn new(triangles: &[[u32; 3]], row_count: usize) -> Self {
        let valid = |t: &[u32; 3]| t.iter().all(|&c| (c as usize) < row_count);
        let mut start = vec![0u32; row_count + 1];
        for t in triangles.iter().filter(|t| valid(t)) {
            for &c in t {
                start[c as usize + 1] += 1;
            }
        }
        for r in 0..row_count {
            start[r + 1] += start[r];
        }
        let mut next = start.clone();
        let mut triangle = vec![0u32; start[row_count] as usize];
        for (i, t) in triangles.iter().enumerate().filter(|(_, t)| valid(t)) {
            for &c in t {
                triangle[next[c as usize] as usize] = i as u32;
                next[c as usize] += 1;
            }
        }
        Self { start, triangle }
    }

    fn of(&self, row: u32) -> &[u32] {
        let (a, b) = (self.start[row as usize], self.start[row as usize + 1]);
        &self.triangle[a as usize..b as usize]
    }
}

impl Region {
    /// The triangles with a corner in `touched` (rows below the mesh's row count), their
    /// border loops and rows; `taken` marks triangles (all false on entry and on return).
    fn of_rows(
        touched: &[u32],
        triangles: &[[u32; 3]],
        around: &TrianglesOfRow,
        taken: &mut [bool],
    ) -> Self {
        let mut picked: Vec<u32> = Vec::new();
        for &r in touched
            .iter()
            .filter(|&&r| (r as usize) + 1 < around.start.len())
        {
            for &t in around.of(r) {
                if !std::mem::replace(&mut taken[t as usize], true) {
                    picked.push(t);
                }
            }
        }
        picked.sort_unstable();
        for &t in &picked {
            taken[t as usize] = false;
        }
        let triangles: Vec<[u32; 3]> = picked.iter().map(|&t| triangles[t as usize]).collect();
        // Each edge once, undirected, with +1 for each triangle running it from its smaller
        // end and −1 the other way: where the sum is not 0 it is on the border.
        let mut edges: Vec<(u64, i32)> = triangles
            .iter()
            .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
            .map(|[a, b]| {
                let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
                (key, if a < b { 1 } else { -1 })
            })
            .collect();
        edges.sort_unstable_by_key(|&(key, _)| key);
        let mut border = Vec::new();
        for run in edges.chunk_by(|x, y| x.0 == y.0) {
            let sum: i32 = run.iter().map(|&(_, d)| d).sum();
            let (low, high) = ((run[0].0 >> 32) as u32, run[0].0 as u32);
            match sum.signum() {
                1 => border.push([low, high]),
                -1 => border.push([high, low]),
                _ => {}
            }
        }
        let mut rows: Vec<u32> = triangles.iter().flatten().copied().collect();
        rows.sort_unstable();
        rows.dedup();
        Self {
            loops: border_loops(&border, &rows),
            triangles,
            rows,
        }
    }
}

/// Border edges grouped by connected loop (union-find over their vertices), each with its
/// vertices.
fn border_loops(border: &[[u32; 2]], rows: &[u32]) -> Vec<(Vec<u32>, Vec<[u32; 2]>)> {
    let index = |v: u32| rows.binary_search(&v).unwrap_or(0);
    let mut root: Vec<usize> = (0..rows.len()).collect();
    fn find(root: &mut [usize], mut i: usize) -> usize {
        while root[i] != i {
            root[i] = root[root[i]];
            i = root[i];
        }
        i
    }
    for &[a, b] in border {
        let (ra, rb) = (find(&mut root, index(a)), find(&mut root, index(b)));
        root[ra] = rb;
    }
    let mut by_root: std::collections::BTreeMap<usize, (Vec<u32>, Vec<[u32; 2]>)> =
        std::collections::BTreeMap::new();
    for &[a, b] in border {
        let r = find(&mut root, index(a));
        let entry = by_root.entry(r).or_default();
        entry.0.extend([a, b]);
        entry.1.push([a, b]);
    }
    by_root
        .into_values()
        .map(|(mut vertices, edges)| {
            vertices.sort_unstable();
            vertices.dedup();
            (vertices, edges)
        })
        .collect()
}

/// The volume enclosed by `triangles` closed by a fan from each border loop's centroid: the
/// sum of signed tetrahedra from one apex, which does not matter for a closed surface.
fn region_volume(
    mesh: &[Vec3],
    triangles: &[[u32; 3]],
    loops: &[(Vec<u32>, Vec<[u32; 2]>)],
) -> f64 {
    let at = |v: u32| mesh[v as usize].as_dvec3();
    let Some(&[first, ..]) = triangles.first() else {
        return 0.0;
    };
    let apex = at(first);
    let tetra = |a: DVec3, b: DVec3, c: DVec3| (a - apex).dot((b - apex).cross(c - apex)) / 6.0;
    let mut volume: f64 = triangles
        .iter()
        .map(|&[a, b, c]| tetra(at(a), at(b), at(c)))
        .sum();
    for (vertices, edges) in loops {
        let centre = vertices.iter().map(|&v| at(v)).sum::<DVec3>() / vertices.len() as f64;
        // The cap runs each border edge backwards to close the surface.
        volume += edges
            .iter()
            .map(|&[a, b]| tetra(at(b), at(a), centre))
            .sum::<f64>();
    }
    volume
}

/// Whether two sorted lists share an element.
fn intersects(a: &[u32], b: &[u32]) -> bool {
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => return true,
        }
    }
    false
}

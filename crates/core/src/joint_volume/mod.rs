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
//!   crease. It stops where an edge around the joint would be [`MAX_WIDENING_STRETCH`] times
//!   as long as the mitre made it (or as at rest, if longer): a mesh that barely follows its
//!   ring keeps a dent rather than grow a spike.
//!
//! The mesh is linear in the ring for mean value and harmonic cages, so the volume is a cubic
//! in `s`; the secant method takes three to five evaluations of the region's rows. A joint at
//! rest relative to its parent is left as the mitre put it, so the rest pose stays exact; one
//! barely bent (a turn of a few degrees) takes a share of its scale that grows smoothly with
//! the turn, so that the settle is continuous in the pose.

mod bend;
mod region;
mod solve;

use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::{DVec3, Vec3};

use crate::scene::CageSet;
use crate::star::StarOperator;
use bend::Bend;
use region::{Region, TrianglesOfRow, edge_lengths, most_stretch, region_volume};
use solve::solve;

/// The regions' triangles, all joints together, as a multiple of the mesh's: an auto rig's
/// hold 2.6–4.6 (the shared meshes; a body-rooted ring's region is most of the body).
const REGION_BUDGET: usize = 16;

/// Sweeps over the bent joints, at most.
const MAX_SWEEPS: usize = 4;

/// How much longer than the mitre made it (or than at rest, where the mitre shortened it) a
/// widening may make any edge of a joint's region: past it the ring stops and the region stays
/// short of its volume. A widening that keeps the volume at any cost spikes a joint whose mesh
/// barely follows its ring (the armadillo's wrist bent 90° backwards: 544 edges over twice
/// their rest length, the worst 6.6 times; with this bound 14 edges and 3.1 times, the hand
/// 22 % short of its volume, most of it lost to the mitre's folds). 1.5 left the beast's hip
/// at 45° 1.9 % short and 1.25 its knee at 90° 3.7 %; measured from the mitre's length alone,
/// the horse's hind knee, whose mitre shortens edges on the outer side, kept 10 % less
/// (docs/math.md, "Volume-keeping joints").
pub const MAX_WIDENING_STRETCH: f32 = 1.75;

/// A change of a ring's scale between sweeps below which it has settled (the secant method
/// stops at a share of the volume, so a ring solved again moves by a little).
const SCALE_SETTLED: f64 = 1e-3;

/// Halvings towards the widest scale within [`MAX_WIDENING_STRETCH`].
const WIDENING_HALVINGS: usize = 6;

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
    /// Their edges, each once.
    edges: Vec<[u32; 2]>,
    /// The edges' lengths at rest.
    rest_lengths: Vec<f32>,
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
#[derive(Debug)]
pub struct JointVolumes {
    joints: Vec<JointRegion>,
    /// Per joint, the scale its last settle found (f64 bits): where the next one starts, so a
    /// drag's step costs two or three evaluations of the region rather than four or five.
    hints: Vec<AtomicU64>,
    /// Rest cage positions the binding was made for.
    rest: Vec<DVec3>,
    /// How much longer than the mitre made it (or than at rest) a widening may make an edge
    /// of a region.
    max_widening_stretch: f32,
}

impl Default for JointVolumes {
    fn default() -> Self {
        Self {
            joints: Vec::new(),
            hints: Vec::new(),
            rest: Vec::new(),
            max_widening_stretch: MAX_WIDENING_STRETCH,
        }
    }
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
                rest_lengths: edge_lengths(&rest_mesh, &region.edges),
                edges: region.edges,
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
            max_widening_stretch: MAX_WIDENING_STRETCH,
        }
    }

    /// The same joints with widenings bounded by `limit` (how much longer than the mitre made
    /// it, or than at rest, a widening may make an edge around the joint; default
    /// [`MAX_WIDENING_STRETCH`], infinite for the volume at any cost), to compare the
    /// trade-off.
    pub fn with_max_widening_stretch(mut self, limit: f32) -> Self {
        self.max_widening_stretch = limit;
        self
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
            .filter_map(|joint| {
                let control = (joint.control.as_slice(), joint.control_rest.as_slice());
                let parent = (joint.parent.as_slice(), joint.parent_rest.as_slice());
                Some((joint, Bend::of(control, parent, joint.axis, pose)?))
            })
            .collect();
        if bent.is_empty() {
            return settled;
        }
        let x = dofs.get_or_insert_with(|| operator.dofs(&self.rest, pose));
        mesh.resize(operator.row_count(), Vec3::ZERO);
        // Every sweep scales a ring from where the mitre put it, so a ring is scaled once by
        // the amount that suits its neighbours as they now are, not again on top of its last
        // sweep (which widened a joint that could not regain its volume by the bound in every
        // sweep: the armadillo's wrist 4.7 times over on its outer side).
        let mitred: Vec<Vec<DVec3>> = bent
            .iter()
            .map(|(joint, _)| joint.ring.iter().map(|&v| pose[v as usize]).collect())
            .collect();
        // Per joint, each region edge's length with the ring at the mitre (taken at the first
        // sweep's first evaluation, its neighbours as the sweep has left them so far) or at
        // rest, whichever is longer: an edge the mitre shortened may first regain its length.
        let mut mitre_lengths: Vec<Vec<f32>> = vec![Vec::new(); bent.len()];
        let mut scales = vec![0.0; bent.len()];
        // Gauss–Seidel: neighbouring joints share a segment's rows (a hip's region and its
        // knee's both hold the thigh), so a sweep is repeated until no ring's scale changes.
        for sweep in 0..MAX_SWEEPS {
            let mut any = false;
            for (k, (joint, bend)) in bent.iter().enumerate() {
                let (base, lengths) = (&mitred[k], &mut mitre_lengths[k]);
                // The most a region edge is stretched beyond the mitre, at the last scale
                // evaluated and at 0.
                let (stretch, stretch_at_mitre) = (Cell::new(1.0f32), Cell::new(1.0f32));
                // The ring at scale `s` in the pose and the DOFs; with `measure`, the region's
                // volume change there (else 0: the ring only placed, its rows not evaluated).
                let mut ring_at = |s: f64, pose: &mut [DVec3], measure: bool| -> f64 {
                    for (&v, p) in joint.ring.iter().zip(bend.bulged(base, s)) {
                        pose[v as usize] = p;
                    }
                    operator.update_dofs(&self.rest, pose, &joint.ring, x);
                    if !measure {
                        return 0.0;
                    }
                    operator.apply_rows(&joint.rows, x, &mut mesh);
                    if s == 0.0 && lengths.is_empty() {
                        *lengths = edge_lengths(&mesh, &joint.edges);
                        for (length, rest) in lengths.iter_mut().zip(&joint.rest_lengths) {
                            *length = length.max(*rest);
                        }
                    }
                    // Only a widening is bounded by the stretch.
                    if s >= 0.0 {
                        stretch.set(most_stretch(&mesh, &joint.edges, lengths));
                    }
                    if s == 0.0 {
                        stretch_at_mitre.set(stretch.get());
                    }
                    region_volume(&mesh, &joint.triangles, &joint.loops) - joint.rest_volume
                };
                // In a live rig's first sweep, from where this joint's last settle ended (a
                // drag's previous step); a whole settle starts from 0, so that a pose settles
                // to the same cages whatever was settled before (a bake against its frames
                // shown one by one); later sweeps from the last sweep's scale.
                let start = match (sweep, moved) {
                    (0, Some(_)) => f64::from_bits(self.hints[joint.index].load(Ordering::Relaxed)),
                    (0, None) => 0.0,
                    _ => scales[k],
                };
                let solved = solve(|s| ring_at(s, pose, true), joint.rest_volume, start);
                let (mut scale, mut last) = (solved.scale, solved.last);

                // A widening stops where it would stretch an edge around the joint past
                // `max_widening_stretch` times its mitred (or rest) length, times what the
                // neighbours' rings already stretched it; the volume then stays short.
                if scale > 0.0 {
                    if last != scale {
                        ring_at(scale, pose, true);
                        last = scale;
                    }
                    let allowed = self.max_widening_stretch * stretch_at_mitre.get();
                    if stretch.get() > allowed {
                        let (mut within, mut beyond) = (0.0, scale);
                        for _ in 0..WIDENING_HALVINGS {
                            last = 0.5 * (within + beyond);
                            ring_at(last, pose, true);
                            if stretch.get() > allowed {
                                beyond = last;
                            } else {
                                within = last;
                            }
                        }
                        scale = within;
                    }
                }
                // A joint barely bent takes a share of it: the settle stays continuous where
                // the joint starts to count as bent (`Bend::weight`).
                scale *= bend.weight;
                // Leave the ring at the solution (it is where the last evaluation left it, or
                // as it was when nothing needed doing). Its rows are not needed there: the
                // next joint evaluates its own from the DOFs.
                if scale != last {
                    ring_at(scale, pose, false);
                }
                any |= (scale - scales[k]).abs() > SCALE_SETTLED;
                scales[k] = scale;
            }
            // One joint has no neighbour to wait for.
            if !any || bent.len() == 1 {
                break;
            }
        }
        for (k, (joint, _)) in bent.iter().enumerate() {
            self.hints[joint.index].store(scales[k].to_bits(), Ordering::Relaxed);
            if scales[k] != 0.0 {
                settled.extend_from_slice(&joint.ring);
            }
        }
        settled.sort_unstable();
        settled.dedup();
        settled
    }
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

//! The solid's cells split into parts that follow the shape: in each connected piece of the
//! solid, a body (the union of the balls inscribed at its thickest cells) cut into slabs across
//! its longest axis, and limbs (what is left: arms, legs, tails, ears, fingers), each cut into
//! a chain of segments by geodesic distance from the body (by grid layer where the limb runs
//! along a grid axis, so the joints between its segments are flat).

use std::cmp::Reverse;
use std::collections::{BTreeMap, BTreeSet, BinaryHeap};

use glam::{DVec3, IVec3};

use super::branches::branches;
use super::joint_bodies::fold_joint_bodies;
use super::narrowings::{self, SamplesByCell};
use super::saddles::split_at_saddles;
use super::straight::{Layers, STRAIGHT_SLACK};
use super::voxels::{FACE_STEPS, Grid, component_cells, components};

/// What a part is, for its name and for the internal cages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Role {
    /// Slab `slab` of body `body`.
    Body {
        /// The body (one per thick region).
        body: usize,
        /// Position along the body's axis.
        slab: usize,
    },
    /// Segment `segment` (0 at the body) of limb `limb`.
    Limb {
        /// The limb.
        limb: usize,
        /// Position along the limb, from its root.
        segment: usize,
    },
}

/// The parts: a label per cell (None where the cell is empty) and each part's role.
#[derive(Debug, Clone)]
pub(super) struct Parts {
    /// Part of each cell.
    pub label: Vec<Option<u32>>,
    /// Role of each part.
    pub roles: Vec<Role>,
    /// The limb each branching limb grows from (an ear from the head top, a leg from the hip
    /// band it shares with the other leg); limbs growing from a body are not listed.
    pub parent_limb: BTreeMap<usize, usize>,
    /// The bodies split off as heads (above the shoulders or on a neck): never the main body,
    /// though a head may be the largest (Cheburashka's).
    pub heads: BTreeSet<usize>,
    /// The heads that are a crown: the top [`HEAD_LAYERS`] of a standing body that narrows
    /// nowhere lower ([`split_heads_above_shoulders`]).
    pub crowns: BTreeSet<usize>,
    /// Body slabs halved between two legs, by the low half's role (below the plane across the
    /// legs).
    pub halved: BTreeMap<Role, Halved>,
    /// Limbs cut as a pair into as many segments ([`paired_segment_counts`]), by limb number.
    pub pairs: Vec<(usize, usize)>,
}

/// A body slab halved between two legs ([`Parts::halved`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Halved {
    /// The high half's role.
    pub high: Role,
    /// The horizontal grid axis across the legs.
    pub axis: usize,
    /// The grid plane between the legs: cells at or above it along `axis` are the high half.
    /// On a mirrored grid it is the mirror's plane, and the high half the low half's image.
    pub plane: i32,
}

impl Parts {
    /// Parts labelled `label` with roles `roles`, no branches, heads, halved slabs or pairs (a
    /// test's hand-made parts).
    #[cfg(test)]
    pub fn of_roles(label: Vec<Option<u32>>, roles: Vec<Role>) -> Self {
        Self {
            label,
            roles,
            parent_limb: BTreeMap::new(),
            heads: BTreeSet::new(),
            crowns: BTreeSet::new(),
            halved: BTreeMap::new(),
            pairs: Vec::new(),
        }
    }

    /// The part of the grid cell holding point `p` (None outside the grid or in an empty cell).
    pub fn part_at(&self, grid: &Grid, p: DVec3) -> Option<u32> {
        grid.index(grid.cell_at(p))
            .and_then(|c| self.label.get(c).copied().flatten())
    }

    /// A limb number no part and no branch record uses, nor any above it.
    pub fn unused_limb(&self) -> usize {
        self.roles
            .iter()
            .filter_map(|r| match r {
                Role::Limb { limb, .. } => Some(limb + 1),
                Role::Body { .. } => None,
            })
            .chain(self.parent_limb.iter().map(|(c, p)| c.max(p) + 1))
            .max()
            .unwrap_or(0)
    }

    /// The limb parts, per limb and per segment, in label order.
    pub fn limb_segments(&self) -> BTreeMap<usize, BTreeMap<usize, Vec<u32>>> {
        let mut by_limb: BTreeMap<usize, BTreeMap<usize, Vec<u32>>> = BTreeMap::new();
        for (p, role) in self.roles.iter().enumerate() {
            if let Role::Limb { limb, segment } = *role {
                (by_limb.entry(limb).or_default().entry(segment).or_default()).push(p as u32);
            }
        }
        by_limb
    }

    /// Each cell's role (None where it is empty): what a later step compares its parts with.
    pub fn roles_by_cell(&self) -> Vec<Option<Role>> {
        (self.label.iter())
            .map(|l| l.and_then(|l| self.roles.get(l as usize).copied()))
            .collect()
    }

    /// Merges each part of `into`'s keys into the part it names (which keeps its role), then
    /// renumbers the parts ([`compact`]).
    pub fn merge_into(&mut self, into: &BTreeMap<u32, u32>) {
        for l in self.label.iter_mut().flatten() {
            if let Some(&target) = into.get(l) {
                *l = target;
            }
        }
        compact(self);
    }
}

/// How parts are cut.
#[derive(Debug, Clone, Copy)]
pub(super) struct Cutting {
    /// Cells at least this fraction of their piece's greatest thickness seed the body.
    pub body_fraction: f64,
    /// Segment length along a limb, in thicknesses (diameters) of the limb.
    pub segment_length: f64,
    /// Slab length across a body, in thicknesses of the body.
    pub slab_length: f64,
    /// Whether the figure stands on separate feet (its surface's lowest vertices fall in two
    /// pieces or more): a standing body reaching the ground is then looked at for a head on a
    /// neck (Cheburashka's feet are blobs under his body, which holds them).
    pub on_separate_feet: bool,
}

/// Splits the occupied cells into parts (see the module).
pub(super) fn cut_into_parts(
    grid: &Grid,
    occupied: &[bool],
    depth: &[f64],
    cutting: &Cutting,
    samples: &SamplesByCell,
) -> Parts {
    let parts = cut_halving_crotches(grid, occupied, depth, cutting, samples, true);
    // A halved slab whose half was a sliver merged into a neighbour (a leg's first segment,
    // whose ring then moved up into the body): cut again with the slab whole.
    let halves_kept = parts
        .halved
        .iter()
        .all(|(low, halved)| parts.roles.contains(low) && parts.roles.contains(&halved.high));
    if halves_kept {
        parts
    } else {
        cut_halving_crotches(grid, occupied, depth, cutting, samples, false)
    }
}

/// [`cut_into_parts`], halving the slab above two legs between them where `halve`.
fn cut_halving_crotches(
    grid: &Grid,
    occupied: &[bool],
    depth: &[f64],
    cutting: &Cutting,
    samples: &SamplesByCell,
    halve: bool,
) -> Parts {
    let (piece_of, pieces) = components(grid, |i| occupied[i]);
    let mut body = body_cells(grid, &piece_of, pieces, depth, cutting.body_fraction);
    legs_leave_the_body(grid, &piece_of, pieces, &mut body);
    let necked = split_at_necks(grid, &mut body);
    let (mut heads, crowns) =
        split_heads_above_shoulders(grid, occupied, &mut body, &necked, cutting.on_separate_feet);
    // A head on a thick neck (spot's) splits at the saddle of the body's thickness, and is one
    // slab as a head above the shoulders is.
    let split: Vec<bool> = necked.iter().zip(&heads).map(|(n, h)| *n || *h).collect();
    let ends = split_at_saddles(grid, depth, &mut body, &split);
    for (h, e) in heads.iter_mut().zip(ends) {
        *h |= e;
    }
    // A knee or a shoulder thick enough to be a body rejoins its limb.
    fold_joint_bodies(grid, occupied, &mut body, &heads);
    // Bodies: face-connected pieces of body cells; limbs: of the rest.
    let (body_of, bodies) = components(grid, |i| body[i]);
    let (limb_of, limbs) = components(grid, |i| occupied[i] && !body[i]);
    let mut group: Vec<Option<Role>> = vec![None; grid.len()];
    let mut halved = BTreeMap::new();
    // Slabs across each body's longest grid axis.
    for b in 0..bodies {
        let cells: Vec<usize> = (0..grid.len()).filter(|&i| body_of[i] == Some(b)).collect();
        let (lo, hi) = cell_bounds(grid, &cells);
        let extent = hi - lo + IVec3::ONE;
        let axis = longest_axis(extent);
        let thickness = 2.0 * mean_depth(depth, &cells);
        // A head split off above the shoulders is one slab: halved, neither half is a part.
        let count = if cells.iter().any(|&i| heads[i]) {
            1
        } else {
            slab_count(f64::from(extent[axis]), cutting.slab_length * thickness)
        };
        // The slab above two legs is halved between them, one half a slab of its own: both
        // hips' rings on one slab's cage moved each other.
        let crotch = if halve && axis == 2 && count >= 2 {
            // The limbs' cells in the layer under the body, within its footprint: the tops
            // of its legs.
            let tops: BTreeSet<usize> = (lo.y..=hi.y)
                .flat_map(|y| (lo.x..=hi.x).map(move |x| IVec3::new(x, y, lo.z - 1)))
                .filter_map(|c| grid.index(c))
                .filter(|&n| occupied[n] && !body[n])
                .collect();
            plane_between_legs(grid, &tops)
        } else {
            None
        };
        if let Some((across, plane)) = crotch {
            let high = Role::Body {
                body: b,
                slab: count,
            };
            halved.insert(
                Role::Body { body: b, slab: 0 },
                Halved {
                    high,
                    axis: across,
                    plane,
                },
            );
        }
        for &i in &cells {
            let cell = grid.cell_of(i);
            let along = f64::from(cell[axis] - lo[axis]) + 0.5;
            let slab = (((along / f64::from(extent[axis])) * count as f64) as usize).min(count - 1);
            let slab = match crotch {
                Some((across, plane)) if slab == 0 && cell[across] >= plane => count,
                _ => slab,
            };
            group[i] = Some(Role::Body { body: b, slab });
        }
    }
    // The trunk: the largest body that is not a head (Cheburashka's head is his largest).
    let mut body_size = vec![0usize; bodies];
    let mut head_body = vec![false; bodies];
    for (i, b) in body_of.iter().enumerate() {
        if let Some(b) = b {
            body_size[*b] += 1;
            head_body[*b] |= heads[i];
        }
    }
    let trunk = (0..bodies)
        .filter(|&b| !head_body[b])
        .max_by_key(|&b| body_size[b]);
    // Each limb region's branches (one per limb: legs joined at the hip, ears on a head top),
    // each cut into a chain of segments by geodesic distance from where it starts.
    let mut next_limb = 0;
    let mut parent_limb = BTreeMap::new();
    let mut limb_cuts: Vec<LimbCut> = Vec::new();
    for l in 0..limbs {
        let cells: Vec<usize> = (0..grid.len()).filter(|&i| limb_of[i] == Some(l)).collect();
        let distance = geodesic_from_body(grid, &cells, &limb_of, l, &body);
        let thickness = 2.0 * mean_depth(depth, &cells);
        let first = next_limb;
        if let Some(role) = stub_body(grid, &distance, thickness, &group) {
            for &i in &cells {
                group[i] = Some(role);
            }
            continue;
        }
        // The body the region touches most, by cell faces: whether it grows from the trunk.
        let mut contacts = vec![0usize; bodies];
        for &i in &cells {
            for n in grid.face_neighbours(i) {
                if let Some(b) = body_of[n] {
                    contacts[b] += 1;
                }
            }
        }
        let touched = (0..bodies)
            .filter(|&b| contacts[b] > 0)
            .max_by_key(|&b| contacts[b]);
        let region_from_trunk = touched.is_some() && touched == trunk;
        for branch in branches(grid, &cells, &distance, thickness) {
            let from_trunk = region_from_trunk && branch.parent.is_none();
            let limb = next_limb;
            next_limb += 1;
            if let Some(p) = branch.parent {
                parent_limb.insert(limb, first + p);
            }
            let own: Vec<usize> = branch.cells.iter().map(|&(i, _)| i).collect();
            let longest = branch.cells.iter().map(|&(_, d)| d).fold(0.0, f64::max);
            let thickness = 2.0 * mean_depth(depth, &own);
            let root = branch
                .cells
                .iter()
                .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
                .map_or(IVec3::ZERO, |&(i, _)| grid.cell_of(i));
            let bottom = (own.iter().map(|&i| grid.cell_of(i).z).min()).unwrap_or(root.z);
            limb_cuts.push(LimbCut {
                limb,
                cells: branch.cells,
                longest,
                thickness,
                from_trunk,
                root,
                bottom,
            });
        }
    }
    let ground = (0..grid.len())
        .filter(|&i| occupied[i])
        .map(|i| grid.cell_of(i).z)
        .min()
        .unwrap_or(0);
    let SegmentCounts {
        counts,
        kneed,
        pairs: paired,
    } = paired_segment_counts(&limb_cuts, cutting, ground);
    let branches: Vec<narrowings::Branch> = (limb_cuts.iter())
        .map(|c| narrowings::Branch {
            cells: &c.cells,
            longest: c.longest,
            from_trunk: c.from_trunk,
        })
        .collect();
    let joints = narrowings::narrowed_joints(grid, &branches, &counts, &paired, samples);
    let pairs = paired
        .iter()
        .map(|&(a, b)| (limb_cuts[a].limb, limb_cuts[b].limb))
        .collect();
    for (((cut, count), kneed), joints) in limb_cuts.iter().zip(counts).zip(kneed).zip(&joints) {
        let straight = straightened(grid, &cut.cells);
        let shares_of = if kneed {
            ShareOf::Layers
        } else {
            ShareOf::GeodesicLength
        };
        let segments = segments_of_cells(
            &cut.cells,
            straight.as_deref(),
            joints.as_deref(),
            (count, cut.from_trunk),
            shares_of,
        );
        for (&(i, _), segment) in cut.cells.iter().zip(segments) {
            group[i] = Some(Role::Limb {
                limb: cut.limb,
                segment,
            });
        }
    }
    // Parts: face-connected cells of one group.
    let (part_of, part_count) = components_within(grid, |i| group[i]);
    let mut roles = vec![Role::Body { body: 0, slab: 0 }; part_count];
    for (i, p) in part_of.iter().enumerate() {
        if let (Some(p), Some(role)) = (p, group[i]) {
            roles[*p as usize] = role;
        }
    }
    let head_bodies = (0..grid.len())
        .filter(|&i| heads[i])
        .filter_map(|i| body_of[i])
        .collect();
    let mut parts = Parts {
        label: part_of,
        roles,
        parent_limb,
        heads: head_bodies,
        crowns: (0..grid.len())
            .filter(|&i| crowns[i])
            .filter_map(|i| body_of[i])
            .collect(),
        halved,
        pairs,
    };
    merge_small_parts(grid, &mut parts);
    parts
}

/// One limb branch to cut into segments: its cells with their distance from where it starts,
/// its length and thickness in cells, whether it grows from the trunk, and its first cell.
struct LimbCut {
    limb: usize,
    cells: Vec<(usize, f64)>,
    longest: f64,
    thickness: f64,
    from_trunk: bool,
    root: IVec3,
    /// The height (grid layer) of its lowest cell.
    bottom: i32,
}

/// Each limb's segment count ([`slab_count`] of its length over `segment_length` of its
/// thicknesses). Two limbs from the trunk that are a pair (rooted at the same height within
/// [`PAIR_HEIGHT`] cells, their lengths within [`PAIR_LENGTH`] and their thicknesses within
/// [`PAIR_THICKNESS`] of each other: two legs, two arms) get one count, from their mean length
/// and thickness: the Ogre's legs, 5.6 and 7.0 cells long, had two segments and three, so
/// `leg.R.2` was its knee and `leg.L.2` its shin.
fn paired_segment_counts(cuts: &[LimbCut], cutting: &Cutting, ground: i32) -> SegmentCounts {
    // Each limb's own count by its length over its thickness, and the least it may have.
    let own: Vec<usize> = cuts.iter().map(|c| own_segment_count(c, cutting)).collect();
    let least: Vec<usize> = (cuts.iter())
        .map(|c| if kneed_leg(c, ground) { 2 } else { 1 })
        .collect();
    let mut counts: Vec<usize> = own.iter().zip(&least).map(|(&o, &l)| o.max(l)).collect();
    let alike = |a: &LimbCut, b: &LimbCut| {
        let ratio = |x: f64, y: f64| x.max(y) / x.min(y).max(1e-9);
        a.from_trunk
            && b.from_trunk
            && (a.root.z - b.root.z).abs() <= PAIR_HEIGHT
            && ratio(a.longest, b.longest) <= PAIR_LENGTH
            && ratio(a.thickness, b.thickness) <= PAIR_THICKNESS
    };
    let mut paired = vec![false; cuts.len()];
    let mut pairs = Vec::new();
    for a in 0..cuts.len() {
        if paired[a] {
            continue;
        }
        // Its likest partner: the nearest in length.
        let partner = (a + 1..cuts.len())
            .filter(|&b| !paired[b] && alike(&cuts[a], &cuts[b]))
            .min_by(|&x, &y| {
                let gap = |b: usize| (cuts[a].longest - cuts[b].longest).abs();
                gap(x).total_cmp(&gap(y))
            });
        if let Some(b) = partner {
            paired[a] = true;
            paired[b] = true;
            let longest = 0.5 * (cuts[a].longest + cuts[b].longest);
            let thickness = 0.5 * (cuts[a].thickness + cuts[b].thickness);
            let count = slab_count(longest, cutting.segment_length * thickness)
                .max(least[a])
                .max(least[b]);
            counts[a] = count;
            counts[b] = count;
            pairs.push((a, b));
        }
    }
    let kneed = (0..cuts.len())
        .map(|i| counts[i] == 2 && own[i] == 1 && least[i] == 2)
        .collect();
    SegmentCounts {
        counts,
        kneed,
        pairs,
    }
}

/// What [`paired_segment_counts`] gives, one entry per limb cut (indices into the cuts).
struct SegmentCounts {
    counts: Vec<usize>,
    /// Whether a limb's two segments are the knee [`kneed_leg`] asks for, its own length
    /// over its thickness giving one: such a knee halves it by its layers ([`ShareOf::Layers`]).
    kneed: Vec<bool>,
    /// Limbs that are a pair, one count for both.
    pairs: Vec<(usize, usize)>,
}

/// A limb's segment count by its length over its thickness alone ([`slab_count`]).
fn own_segment_count(cut: &LimbCut, cutting: &Cutting) -> usize {
    slab_count(cut.longest, cutting.segment_length * cut.thickness)
}

/// How many cells apart in height two limbs' roots may be for them to be a pair.
const PAIR_HEIGHT: i32 = 2;

/// Whether a limb is a leg long enough to need a knee, so at least two segments: it grows
/// from the trunk, hangs [`SHORTEST_KNEED_LEG`] cells or more down from its root, and reaches
/// the figure's lowest layer of cells (the `ground`) within a cell. By length over thickness
/// alone TOSCA's cat's hind legs (3.4 cells long, 2.0 thick) and spot's legs (4.2 and 2.7)
/// were one segment each at the default detail, and turned stiff from the body like table
/// legs; a knee bends them.
fn kneed_leg(cut: &LimbCut, ground: i32) -> bool {
    cut.from_trunk
        && cut.bottom <= ground + 1
        && f64::from(cut.root.z - cut.bottom) >= SHORTEST_KNEED_LEG - 1.0
        && cut.longest >= SHORTEST_KNEED_LEG
}

/// The shortest leg, in cells along it, given a knee (two segments of 1.5 cells or more).
const SHORTEST_KNEED_LEG: f64 = 3.0;

/// How many times longer than the other one of a pair of limbs may be.
const PAIR_LENGTH: f64 = 1.3;

/// How many times thicker than the other one of a pair of limbs may be.
const PAIR_THICKNESS: f64 = 1.15;

/// A limb region that reaches out from the body no further than it is thick ([`STUB_LENGTH`]
/// thicknesses; its reach in cells is its cells' greatest geodesic `distance` from the body,
/// plus the cell touching the body) is a bump of the body: a scan's lump, a shoulder blade.
/// The body slab it touches most takes it, so it gets no chain of cages and no internal cage
/// of its own. Returns that slab.
fn stub_body(
    grid: &Grid,
    distance: &BTreeMap<usize, f64>,
    thickness: f64,
    group: &[Option<Role>],
) -> Option<Role> {
    let longest = distance.values().copied().fold(0.0, f64::max);
    if longest + 1.0 > STUB_LENGTH * thickness {
        return None;
    }
    let mut contacts: BTreeMap<Role, usize> = BTreeMap::new();
    for &i in distance.keys() {
        let c = grid.cell_of(i);
        for s in FACE_STEPS {
            if let Some(n) = grid.index(c + s)
                && let Some(role @ Role::Body { .. }) = group[n]
            {
                *contacts.entry(role).or_insert(0) += 1;
            }
        }
    }
    contacts
        .into_iter()
        .max_by_key(|&(role, n)| (n, Reverse(role)))
        .map(|(role, _)| role)
}

/// A branch's distances along a grid axis, cell by cell, where it runs along one (None where
/// it does not): the geodesic distances' best affine fit over the cells' coordinates has a
/// gradient within `straight::STRAIGHT_COS` of a grid axis, so the branch's cross-sections are grid
/// layers and each joint between its segments one flat face rather than a front stepped over
/// several layers. The smallest equals the smallest geodesic distance.
fn straightened(grid: &Grid, cells: &[(usize, f64)]) -> Option<Vec<f64>> {
    let layers = Layers::of(grid, cells)?;
    Some(
        cells
            .iter()
            .map(|&(i, _)| layers.first + layers.layer_of(grid, i))
            .collect(),
    )
}

/// What a limb cut at even shares ([`segment_at`]) takes the shares of.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ShareOf {
    /// Its cells' greatest geodesic distance from the body.
    GeodesicLength,
    /// Its grid layers alone (a straight limb's; else its geodesic distances), each moved by
    /// the median of what they exceed the geodesic distances by ([`layers_on_distances`]).
    Layers,
}

/// A straight limb's layer distances (`straight`) moved to lie on its cells' geodesic
/// distances: less the median of what they exceed them by. A leg whose top is ragged (it
/// climbs the body's flank, its distance 0 across three layers) counts its layers from the
/// highest cell, so they ran three past its geodesic distances: mixed with them where the
/// two differ by more than [`STRAIGHT_SLACK`], a generated stocky quadruped's knee cut its
/// leg lengthwise into pieces, and the pieces became a third control with its pivot above
/// the second's.
fn layers_on_distances(cells: &[(usize, f64)], straight: &[f64]) -> Vec<f64> {
    let mut excess: Vec<f64> = (straight.iter().zip(cells))
        .map(|(&layer, &(_, d))| layer - d)
        .collect();
    excess.sort_by(f64::total_cmp);
    let median = excess.get(excess.len() / 2).copied().unwrap_or(0.0);
    straight.iter().map(|&layer| layer - median).collect()
}

/// Each of a limb's cells' segment (0 at the body): past the `joints`' distances where the
/// narrowings found them, else at even shares of its length ([`segment_at`]) in `count`
/// segments (`from_trunk`: whether it grows from the trunk). Along a straight limb the
/// cells are measured by their grid layer's distance (`straight`, [`straightened`]) where
/// it is within [`STRAIGHT_SLACK`] cells of their geodesic one, so the joints are flat faces.
/// The shares are of `shares_of`: a knee the two-segment minimum gives a leg
/// ([`kneed_leg`]) halves it by its layers alone ([`layers_on_distances`]), since one
/// ragged top cell adds a layer past its geodesic length (TOSCA's cat's left hind leg:
/// layers 0-5 against 3.4) and its first segment kept two cells against 24, a sliver the
/// merges fold away. Every other limb keeps the geodesic length: taken of the layers too,
/// the knees of Victoria and of the cat's front legs turned triangles over at 90 degrees
/// (docs/autorig.md, Limits).
fn segments_of_cells(
    cells: &[(usize, f64)],
    straight: Option<&[f64]>,
    joints: Option<&[f64]>,
    (count, from_trunk): (usize, bool),
    shares_of: ShareOf,
) -> Vec<usize> {
    let (along, length): (Vec<f64>, f64) = match (shares_of, straight) {
        (ShareOf::Layers, Some(straight)) if joints.is_none() && straight.len() == cells.len() => {
            let along = layers_on_distances(cells, straight);
            let length = along.iter().copied().fold(0.0, f64::max);
            (along, length)
        }
        _ => {
            let along = (cells.iter().enumerate())
                .map(|(k, &(_, d))| match straight.and_then(|s| s.get(k)) {
                    Some(&layer) if (layer - d).abs() <= STRAIGHT_SLACK => layer,
                    _ => d,
                })
                .collect();
            (along, cells.iter().map(|&(_, d)| d).fold(0.0, f64::max))
        }
    };
    along
        .iter()
        .map(|&d| {
            let segment = match joints {
                Some(joints) => joints.iter().filter(|&&joint| d >= joint).count(),
                None => segment_at(d / length.max(1e-9), count, from_trunk),
            };
            segment.min(count.max(1) - 1)
        })
        .collect()
}

/// Longest reach of a limb region that is a bump of the body, in thicknesses of the region.
const STUB_LENGTH: f64 = 1.0;

/// Face-connected components of cells with equal `key` (None: not a member).
fn components_within<K: PartialEq + Copy>(
    grid: &Grid,
    key: impl Fn(usize) -> Option<K>,
) -> (Vec<Option<u32>>, usize) {
    let mut label: Vec<Option<u32>> = vec![None; grid.len()];
    let mut count = 0u32;
    let mut stack = Vec::new();
    for start in 0..grid.len() {
        let Some(k) = key(start) else { continue };
        if label[start].is_some() {
            continue;
        }
        label[start] = Some(count);
        stack.push(start);
        while let Some(i) = stack.pop() {
            for n in grid.face_neighbours(i) {
                if label[n].is_none() && key(n) == Some(k) {
                    label[n] = Some(count);
                    stack.push(n);
                }
            }
        }
        count += 1;
    }
    (label, count as usize)
}

/// The body cells of each piece: cells within the ball inscribed at a cell whose depth is at
/// least `fraction` of the piece's greatest depth (a morphological opening of the thick part,
/// which reaches the surface where no limb leaves it).
fn body_cells(
    grid: &Grid,
    piece_of: &[Option<usize>],
    pieces: usize,
    depth: &[f64],
    fraction: f64,
) -> Vec<bool> {
    let mut deepest = vec![0.0f64; pieces];
    for (i, p) in piece_of.iter().enumerate() {
        if let Some(p) = *p {
            deepest[p] = deepest[p].max(depth[i]);
        }
    }
    // Radius left at each cell, grown from the seeds outward (largest first).
    let mut left = vec![0.0f64; grid.len()];
    let mut heap = BinaryHeap::new();
    for (i, p) in piece_of.iter().enumerate() {
        if let Some(p) = *p
            && depth[i] >= fraction * deepest[p]
        {
            left[i] = depth[i];
            heap.push((left[i].to_bits(), Reverse(i)));
        }
    }
    let steps = neighbour_steps();
    while let Some((bits, Reverse(i))) = heap.pop() {
        let r = f64::from_bits(bits);
        if r < left[i] {
            continue;
        }
        let c = grid.cell_of(i);
        for (s, w) in &steps {
            let Some(n) = grid.index(c + *s) else {
                continue;
            };
            if piece_of[n] != piece_of[i] {
                continue;
            }
            let rn = r - w;
            if rn > left[n] {
                left[n] = rn;
                heap.push((rn.to_bits(), Reverse(n)));
            }
        }
    }
    left.iter().map(|&r| r > 0.0).collect()
}

/// Legs as thick as the body (a humanoid's thighs are as deep as his torso is): where a
/// standing body (longest axis vertical) reaches the bottom of its piece of the solid, and its
/// layers from there up each hold two pieces or more of at least [`LEG_PIECE_SHARE`] of the
/// layer's largest (two legs, side by side; a grid with thin cells between legs closer than a
/// cell parts them) for at least [`LEGS_IN_BODY_SHARE`] of its height, those layers leave the
/// body: the legs are limbs hanging from the body above the crotch, and the body stands on
/// them.
fn legs_leave_the_body(grid: &Grid, piece_of: &[Option<usize>], pieces: usize, body: &mut [bool]) {
    let mut piece_bottom = vec![i32::MAX; pieces];
    let mut piece_top = vec![i32::MIN; pieces];
    for (i, p) in piece_of.iter().enumerate() {
        if let Some(p) = *p {
            piece_bottom[p] = piece_bottom[p].min(grid.cell_of(i).z);
            piece_top[p] = piece_top[p].max(grid.cell_of(i).z);
        }
    }
    for cells in component_cells(grid, |i| body[i]) {
        let (lo, hi) = cell_bounds(grid, &cells);
        let extent = hi - lo + IVec3::ONE;
        // On the ground; on a grid parting legs closer than a cell (thighs pressed together),
        // or on shins thinner than the thighs (they are not body cells): its bottom in the
        // piece's lowest layers. Legs further apart keep the rule (the beast's default rig lost
        // its head when its hips left the body).
        let on_ground = cells.first().and_then(|&i| piece_of[i]).is_some_and(|p| {
            let shins = match grid.band {
                Some(_) => SHINS_IN_PIECE_SHARE * f64::from(piece_top[p] - piece_bottom[p]),
                None => 0.0,
            };
            lo.z <= piece_bottom[p] + (shins as i32).max(1)
        });
        if longest_axis(extent) != 2 || !on_ground {
            continue;
        }
        let layers = extent.z as usize;
        let mut by_layer: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); layers];
        for &i in &cells {
            by_layer[(grid.cell_of(i).z - lo.z) as usize].insert(i);
        }
        // Layers from the bottom holding two pieces or more (a foot alone in the lowest
        // layer or two, one foot set lower than the other, does not end the run).
        let mut run = 0;
        for (k, layer) in by_layer.iter().enumerate() {
            if pieces_in_layer(grid, layer) >= 2 {
                run = k + 1;
            } else if k >= run + LOWEST_LAYERS_ALONE || run > 0 {
                break;
            }
        }
        if (run as f64) < LEGS_IN_BODY_SHARE * layers as f64 || run >= layers {
            continue;
        }
        for layer in by_layer.iter().take(run) {
            for &i in layer {
                body[i] = false;
            }
        }
    }
}

/// The grid plane between the two largest pieces of a layer (the tops of two legs), across the
/// horizontal axis along which their centres lie furthest apart, where they are at most
/// [`CLOSE_LEGS_GAP`] cells apart with two columns of cells or more between them: the grid
/// plane in the middle of those columns (between a band's two thin columns: the mirror's
/// plane on a mirrored grid, where the legs are each other's images).
fn plane_between_legs(grid: &Grid, layer: &BTreeSet<usize>) -> Option<(usize, i32)> {
    let mut pieces = layer_pieces(grid, layer);
    pieces.sort_by_key(|p| Reverse(p.len()));
    let [a, b, ..] = pieces.as_slice() else {
        return None;
    };
    let centre = |cells: &[usize]| {
        let sum = cells.iter().fold(glam::DVec3::ZERO, |s, &i| {
            s + grid.cell_of(i).as_dvec3() + glam::DVec3::splat(0.5)
        });
        sum / cells.len() as f64
    };
    let (ca, cb) = (centre(a), centre(b));
    let axis = if (ca.x - cb.x).abs() >= (ca.y - cb.y).abs() {
        0
    } else {
        1
    };
    // Legs further apart have rings far enough apart on the slab's cage that neither moves
    // the other (the armadillo's: 0.000 % of the diagonal).
    let span = |cells: &[usize]| {
        let along = cells.iter().map(|&i| grid.cell_of(i)[axis]);
        (along.clone().min().unwrap_or(0), along.max().unwrap_or(0))
    };
    let ((a_lo, a_hi), (b_lo, b_hi)) = (span(a), span(b));
    // From the far side of the lower piece's last cell to the near side of the other's first:
    // the cells between them, thin ones in a band counted by their width.
    let (first, last) = if a_hi < b_lo {
        (a_hi, b_lo)
    } else {
        (b_hi, a_lo)
    };
    let gap = grid.position_along(axis, f64::from(last))
        - grid.position_along(axis, f64::from(first + 1));
    // With one column between them, the plane would run along one leg's side, whose ring
    // would then hold vertices of both halves: its knee moved the other half (Homer's, 0.33 %
    // of the diagonal, when a band was one thin column). The plane runs between the middle
    // columns of the gap (a band's two thin columns; the mirror's plane).
    if gap > CLOSE_LEGS_GAP * grid.cell || last - first - 1 < 2 {
        return None;
    }
    let plane = (first + 1 + last) / 2;
    Some((axis, plane))
}

/// The widest gap between two legs' tops, in cells, for the slab above them to be halved
/// between them ([`plane_between_legs`]): Homer's, parted by a band of thin cells, have less
/// than a cell between them; the armadillo's three.
const CLOSE_LEGS_GAP: f64 = 1.0;

/// The face-connected pieces of one layer's cells holding at least [`LEG_PIECE_SHARE`] of the
/// largest piece's cells.
fn pieces_in_layer(grid: &Grid, layer: &BTreeSet<usize>) -> usize {
    layer_pieces(grid, layer).len()
}

/// The face-connected pieces of one layer's cells holding at least [`LEG_PIECE_SHARE`] of the
/// largest piece's cells, each as its cells.
fn layer_pieces(grid: &Grid, layer: &BTreeSet<usize>) -> Vec<Vec<usize>> {
    let mut seen: BTreeSet<usize> = BTreeSet::new();
    let mut pieces = Vec::new();
    for &start in layer {
        if !seen.insert(start) {
            continue;
        }
        let mut piece = Vec::new();
        let mut stack = vec![start];
        while let Some(i) = stack.pop() {
            piece.push(i);
            let c = grid.cell_of(i);
            // Within the layer: the x and y steps.
            for step in &FACE_STEPS[..4] {
                if let Some(n) = grid.index(c + *step)
                    && layer.contains(&n)
                    && seen.insert(n)
                {
                    stack.push(n);
                }
            }
        }
        pieces.push(piece);
    }
    let largest = pieces.iter().map(Vec::len).max().unwrap_or(0) as f64;
    pieces.retain(|p| p.len() as f64 >= LEG_PIECE_SHARE * largest);
    pieces
}

/// The least share of a standing body's height its legs ([`legs_leave_the_body`]) reach.
const LEGS_IN_BODY_SHARE: f64 = 0.15;

/// On a grid parting legs closer than a cell, a standing body's bottom lies in this share of
/// its piece's height from the piece's bottom ([`legs_leave_the_body`]): the shins and feet
/// under thick thighs pressed together are thinner than the body cells above them (TOSCA's
/// Victoria: her thighs' body cells begin at the knee, 27 % up).
const SHINS_IN_PIECE_SHARE: f64 = 0.35;

/// The least size of a leg's piece of a layer, as a share of the layer's largest piece.
const LEG_PIECE_SHARE: f64 = 0.25;

/// How many of a standing body's lowest layers may hold one foot alone before its legs start.
const LOWEST_LAYERS_ALONE: usize = 2;

/// A body that narrows to a neck between two thick ends (a head on a short neck, which the
/// balls of the head's and the torso's thickest cells join): the narrowest layer across its
/// longest axis, where it holds at most [`NECK_SHARE`] of the body cells of the thickest layer
/// on its thinner side, leaves the body, so that each end is a body of its own and the neck a
/// limb between them (a head gets a control). Ends of fewer than [`NECK_END_LAYERS`] layers
/// (a rounded tip) are not split off. Returns which cells are in a body split so.
fn split_at_necks(grid: &Grid, body: &mut [bool]) -> Vec<bool> {
    let mut split = vec![false; grid.len()];
    let members = component_cells(grid, |i| body[i]);
    for cells in members {
        let (lo, hi) = cell_bounds(grid, &cells);
        let axis = longest_axis(hi - lo + IVec3::ONE);
        let layers = (hi[axis] - lo[axis] + 1) as usize;
        let layer = |i: usize| (grid.cell_of(i)[axis] - lo[axis]) as usize;
        let mut count = vec![0usize; layers];
        for &i in &cells {
            count[layer(i)] += 1;
        }
        if let Some(k) = narrowest_between_ends(&count, NECK_END_LAYERS, NECK_SHARE) {
            for &i in &cells {
                if layer(i) == k {
                    body[i] = false;
                } else {
                    split[i] = true;
                }
            }
        }
    }
    split
}

/// A standing figure's head on a body that does not narrow to a neck first (a humanoid's head
/// on thick shoulders, the beast's, the Ogre's): where a standing body (longest axis
/// vertical) stands on legs (its piece of the solid reaches [`LEGS_SHARE`] of its height
/// below it), the narrowest layer above its thickest one in its upper half (the chest and
/// shoulders) that holds at most [`HEAD_SHARE`] of that thickest layer and leaves
/// [`NECK_END_LAYERS`] layers above it ([`HEAD_LAYERS`] where none does; where no layer there
/// is that narrow, the narrowest above the whole body's thickest layer that touches no limb
/// reaching below it: Homer's head column on a low belly, clear of his arms) leaves the body, as
/// [`split_at_necks`] does between two thick ends (`necked`: the bodies it split, not looked
/// at again); a lumpy sphere or a bust, on no legs, is not split. A standing body that
/// reaches the ground itself, on a figure standing on separate feet (`on_separate_feet`:
/// the grid held its feet in the body, Cheburashka's), is split at a waist between a thick
/// head and chest instead ([`neck_between_thick_ends`]). The head's skin, the limb
/// cells within [`HEAD_SKIN`] cells of it above that layer, joins its body. A standing body
/// on legs that narrows in none of these ways may carry a head jutting forward from its top
/// ([`head_in_front`]), which leaves it through a collar that holds no arm. Returns which
/// cells are heads, and which of them crowns (a head of [`HEAD_LAYERS`]): each becomes one slab (halved, each half was under a fifth of a body
/// slab and merged away, leaving the head no control).
fn split_heads_above_shoulders(
    grid: &Grid,
    occupied: &[bool],
    body: &mut [bool],
    necked: &[bool],
    on_separate_feet: bool,
) -> (Vec<bool>, Vec<bool>) {
    let mut heads = vec![false; grid.len()];
    let mut crowns = vec![false; grid.len()];
    let members = component_cells(grid, |i| body[i]);
    let (piece_of, pieces) = components(grid, |i| occupied[i]);
    let (limb_of, limbs) = components(grid, |i| occupied[i] && !body[i]);
    let mut limb_bottom = vec![i32::MAX; limbs];
    for (i, l) in limb_of.iter().enumerate() {
        if let Some(l) = *l {
            limb_bottom[l] = limb_bottom[l].min(grid.cell_of(i).z);
        }
    }
    let mut piece_bottom = vec![i32::MAX; pieces];
    let mut piece_top = vec![i32::MIN; pieces];
    for (i, p) in piece_of.iter().enumerate() {
        if let Some(p) = *p {
            piece_bottom[p] = piece_bottom[p].min(grid.cell_of(i).z);
            piece_top[p] = piece_top[p].max(grid.cell_of(i).z);
        }
    }
    for cells in members {
        let Some(bottom) = cells
            .first()
            .and_then(|&i| piece_of[i])
            .map(|p| piece_bottom[p])
        else {
            continue;
        };
        let (lo, hi) = cell_bounds(grid, &cells);
        let height = hi.z - lo.z + 1;
        let standing = longest_axis(hi - lo + IVec3::ONE) == 2;
        let on_legs = f64::from(lo.z - bottom) >= LEGS_SHARE * f64::from(height);
        if !standing || !(on_legs || on_separate_feet) || cells.iter().any(|&i| necked[i]) {
            continue;
        }
        let layers = height as usize;
        let layer = |i: usize| (grid.cell_of(i).z - lo.z) as usize;
        let mut count = vec![0usize; layers];
        for &i in &cells {
            count[layer(i)] += 1;
        }
        let neck = if on_legs {
            // A neck layer touching a limb region that reaches below it (an arm) would join
            // that limb once it leaves the body: the arms would hang from a neck.
            let touches_limb_below = |k: usize| {
                cells.iter().filter(|&&i| layer(i) == k).any(|&i| {
                    FACE_STEPS.iter().any(|&step| {
                        grid.index(grid.cell_of(i) + step)
                            .and_then(|n| limb_of[n])
                            .is_some_and(|l| limb_bottom[l] < lo.z + k as i32)
                    })
                })
            };
            // The narrowest layer above the thickest one from layer `first` up, holding at
            // most HEAD_SHARE of it and leaving `above` layers of head; above the whole body's
            // thickest layer (`first` 0), one that keeps off the arms.
            let neck_above_thickest = |first: usize, above: usize| {
                let peak =
                    (first..layers).max_by(|&a, &c| count[a].cmp(&count[c]).then(c.cmp(&a)))?;
                let thickest = count[peak] as f64;
                (peak + 1..layers.saturating_sub(above))
                    .filter(|&k| count[k] > 0 && count[k] as f64 <= HEAD_SHARE * thickest)
                    .filter(|&k| first > 0 || !touches_limb_below(k))
                    .min_by(|&a, &c| count[a].cmp(&count[c]).then(a.cmp(&c)))
            };
            // Above the chest and shoulders (the upper half's thickest layer); where no layer
            // there is narrow enough, above the whole body's thickest layer: a belly low on a
            // short torso, under a head column nearly as wide as its shoulders (Homer's). A
            // head of NECK_END_LAYERS, else of HEAD_LAYERS (a crown, where the head narrows
            // nowhere else).
            neck_above_thickest(layers / 2, NECK_END_LAYERS)
                .or_else(|| neck_above_thickest(0, NECK_END_LAYERS))
                .map(|k| (k, false))
                .or_else(|| {
                    neck_above_thickest(layers / 2, HEAD_LAYERS)
                        .or_else(|| neck_above_thickest(0, HEAD_LAYERS))
                        .map(|k| (k, true))
                })
        } else {
            neck_between_thick_ends(&count).map(|k| (k, false))
        };
        let split = match neck {
            Some((k, crown)) => {
                let cut = HeadCut {
                    axis: 2,
                    sign: 1,
                    at: lo.z + k as i32,
                    from_z: i32::MIN,
                    crown,
                };
                Some(split_head(grid, occupied, body, &cells, &cut))
            }
            // A body with another above it in its piece of the solid (a head on a neck) has
            // its head: what juts from it is not one (a backpack became a `hips` body).
            None if on_legs && !body_above(grid, body, &piece_of, cells[0], hi.z) => {
                // The upper half's thickest layer: the shoulders.
                let shoulders = (layers / 2..layers)
                    .max_by(|&a, &c| count[a].cmp(&count[c]).then(c.cmp(&a)))
                    .unwrap_or(0);
                head_in_front(grid, &cells, lo.z + shoulders as i32)
                    .iter()
                    .map(|cut| split_head(grid, occupied, body, &cells, cut))
                    .find(|split| !split.collar_holds_a_limb_of_the_torso(grid, &limb_of, body))
            }
            None => None,
        };
        if let Some(split) = split {
            for &i in &split.neck {
                body[i] = false;
            }
            for &i in &split.head {
                body[i] = true;
                heads[i] = true;
                crowns[i] = split.crown;
            }
        }
    }
    (heads, crowns)
}

/// Whether a body cell of the piece of the solid holding cell `of` lies above layer `top`.
fn body_above(grid: &Grid, body: &[bool], piece_of: &[Option<usize>], of: usize, top: i32) -> bool {
    let piece = piece_of[of];
    (0..grid.len()).any(|i| body[i] && piece_of[i] == piece && grid.cell_of(i).z > top)
}

/// A head split off a body: its cells (its core and skin), the cells leaving the body as its
/// neck, and whether it is a crown.
struct HeadSplit {
    head: Vec<usize>,
    neck: Vec<usize>,
    crown: bool,
}

impl HeadSplit {
    /// Whether a limb region (`limb_of`, before the split) touches both the neck and the rest
    /// of the body: an arm rooted beside a head jutting forward would join the neck and hang
    /// from it.
    fn collar_holds_a_limb_of_the_torso(
        &self,
        grid: &Grid,
        limb_of: &[Option<usize>],
        body: &[bool],
    ) -> bool {
        let head: BTreeSet<usize> = self.head.iter().copied().collect();
        let neck: BTreeSet<usize> = self.neck.iter().copied().collect();
        let touching = |cells: &mut dyn Iterator<Item = usize>| -> BTreeSet<usize> {
            cells
                .flat_map(|i| grid.face_neighbours(i))
                .filter(|n| !head.contains(n))
                .filter_map(|n| limb_of[n])
                .collect()
        };
        let at_neck = touching(&mut neck.iter().copied());
        let mut torso =
            (0..grid.len()).filter(|i| body[*i] && !head.contains(i) && !neck.contains(i));
        let at_torso = touching(&mut torso);
        at_neck.intersection(&at_torso).next().is_some()
    }
}

/// The head, skin included, and neck of a body (`cells`) cut by `cut`, the body's cells as
/// `body` marks them. The head's skin is the thin shell of limb cells around its core, past
/// the neck, within [`HEAD_SKIN`] cells of the core: left a limb region, the shoulders' slab
/// took it and wrapped the head, so the joint ring reached its crown. The neck, decided here
/// only: a head cut across the vertical axis leaves the torso through the neck layer (the
/// body's cells in the cut's plane); one cut across a horizontal axis through its collar (the
/// torso's cells touching the head or its skin).
fn split_head(
    grid: &Grid,
    occupied: &[bool],
    body: &[bool],
    cells: &[usize],
    cut: &HeadCut,
) -> HeadSplit {
    let mut head = head_core(grid, cells, cut);
    // The lowest layer of the head: its skin stays above it.
    let head_from_z = head
        .iter()
        .map(|&i| grid.cell_of(i).z)
        .min()
        .unwrap_or(i32::MAX);
    let mut front = head.clone();
    let mut seen: BTreeSet<usize> = head.iter().copied().collect();
    for _ in 0..HEAD_SKIN {
        let mut next = Vec::new();
        for &i in &front {
            let c = grid.cell_of(i);
            for step in FACE_STEPS {
                let Some(n) = grid.index(c + step) else {
                    continue;
                };
                let c = grid.cell_of(n);
                let past = c.z >= head_from_z && cut.past(c) > 0;
                if occupied[n] && !body[n] && past && seen.insert(n) {
                    next.push(n);
                }
            }
        }
        front = next;
        head.extend_from_slice(&front);
    }
    let neck = if cut.axis == 2 {
        (cells.iter().copied())
            .filter(|&i| cut.past(grid.cell_of(i)) == 0)
            .collect()
    } else {
        let member: BTreeSet<usize> = cells.iter().copied().collect();
        let collar: BTreeSet<usize> = head
            .iter()
            .flat_map(|&i| grid.face_neighbours(i))
            .filter(|n| member.contains(n) && !seen.contains(n))
            .collect();
        collar.into_iter().collect()
    };
    HeadSplit {
        head,
        neck,
        crown: cut.crown,
    }
}

/// Where a head leaves its body: the body cells at or above layer `from_z` past the neck layer
/// `at` across grid axis `axis`, on its side `sign` (+1 or -1); the neck layer's cells leave
/// the body (the limb between head and torso).
#[derive(Debug, Clone, Copy, PartialEq)]
struct HeadCut {
    axis: usize,
    sign: i32,
    at: i32,
    from_z: i32,
    /// A head of [`HEAD_LAYERS`] on a body that narrows nowhere lower.
    crown: bool,
}

impl HeadCut {
    /// How many layers past the neck's plane cell `c` lies (negative on the torso's side).
    fn past(&self, c: IVec3) -> i32 {
        self.sign * (c[self.axis] - self.at)
    }
}

/// The core of the head of a body (`cells`) cut by `cut`, before its skin ([`split_head`],
/// which also decides its neck). Across the vertical axis: the layers above the neck layer.
/// Across a horizontal one: the body cells past the plane that are face-connected, past it, to
/// those at or above `from_z`, at most [`HEAD_UNDER_LAYERS`] below it (the torso's front
/// further down is not the head: taken, a head turn moved the generated hunched figure's hips
/// by 2 %).
fn head_core(grid: &Grid, cells: &[usize], cut: &HeadCut) -> Vec<usize> {
    if cut.axis == 2 {
        return (cells.iter().copied())
            .filter(|&i| cut.past(grid.cell_of(i)) > 0)
            .collect();
    }
    let member: BTreeSet<usize> = cells.iter().copied().collect();
    let past = |i: usize| cut.past(grid.cell_of(i)) > 0;
    let mut head: BTreeSet<usize> = cells
        .iter()
        .copied()
        .filter(|&i| past(i) && grid.cell_of(i).z >= cut.from_z)
        .collect();
    let mut front: Vec<usize> = head.iter().copied().collect();
    while let Some(i) = front.pop() {
        for n in grid.face_neighbours(i) {
            let low_enough = grid.cell_of(n).z >= cut.from_z - HEAD_UNDER_LAYERS;
            if member.contains(&n) && past(n) && low_enough && head.insert(n) {
                front.push(n);
            }
        }
    }
    head.into_iter().collect()
}

/// A standing figure's head jutting forward from the top of a hunched body that tapers into
/// it with no narrower horizontal layer (the armadillo's: its shell's top holds 0.64 of the
/// shoulders' layer one layer under the head, the head sitting in front of the shell). Of the
/// body `cells` from `shoulders_z` (the upper half's thickest layer) up, the layers across
/// either horizontal axis from either end: the tip, then layers of about one cross-section
/// (within [`HEAD_GROWTH`] of the thinnest after the tip), each at most [`FRONT_HEAD_SHARE`]
/// of the thickest, at least [`NECK_END_LAYERS`] of them and under [`FRONT_HEAD_EXTENT`] of
/// the extent, are a head; the layer inside them is its neck. A round body's flanks keep
/// widening and are no head. Returns the cuts to try in order: the ends whose heads hold the
/// most cells first, each from its longest head to its shortest.
fn head_in_front(grid: &Grid, cells: &[usize], shoulders_z: i32) -> Vec<HeadCut> {
    let upper: Vec<IVec3> = cells
        .iter()
        .map(|&i| grid.cell_of(i))
        .filter(|c| c.z >= shoulders_z)
        .collect();
    // Per end: its head's cells and its cuts.
    let mut ends: Vec<(usize, Vec<HeadCut>)> = Vec::new();
    for axis in 0..2 {
        let (Some(lo), Some(hi)) = (
            upper.iter().map(|c| c[axis]).min(),
            upper.iter().map(|c| c[axis]).max(),
        ) else {
            continue;
        };
        let mut count = vec![0usize; (hi - lo + 1) as usize];
        for c in &upper {
            count[(c[axis] - lo) as usize] += 1;
        }
        let thickest = count.iter().copied().max().unwrap_or(0) as f64;
        let longest = (FRONT_HEAD_EXTENT * count.len() as f64).ceil() as usize;
        for sign in [1, -1] {
            // Layers from the end on this side, outermost first.
            let from_end: Vec<usize> = if sign > 0 {
                count.iter().rev().copied().collect()
            } else {
                count.clone()
            };
            let mut least = usize::MAX;
            let run = from_end
                .iter()
                .enumerate()
                .take_while(|&(k, &n)| {
                    if k > 0 {
                        least = least.min(n);
                    }
                    n as f64 <= FRONT_HEAD_SHARE * thickest
                        && (k == 0 || n as f64 <= HEAD_GROWTH * least as f64)
                })
                .count();
            if run < NECK_END_LAYERS || run >= longest {
                continue;
            }
            let cuts = (NECK_END_LAYERS..=run)
                .rev()
                .map(|layers| HeadCut {
                    axis,
                    sign,
                    at: if sign > 0 {
                        hi - layers as i32
                    } else {
                        lo + layers as i32
                    },
                    from_z: shoulders_z,
                    crown: false,
                })
                .collect();
            ends.push((from_end[..run].iter().sum(), cuts));
        }
    }
    ends.sort_by_key(|end| Reverse(end.0));
    ends.into_iter().flat_map(|(_, cuts)| cuts).collect()
}

/// The most body cells each layer of a head jutting in front of a hunched body's top holds,
/// as a share of that top's thickest layer across the same axis (the armadillo's head:
/// 34, 28, 25 and 5 cells against 76).
const FRONT_HEAD_SHARE: f64 = 0.6;

/// How many layers under the hunched body's shoulders a head jutting in front of it reaches
/// (the armadillo's two; lower down, the torso's front is not the head).
const HEAD_UNDER_LAYERS: i32 = 2;

/// How much wider than its thinnest layer behind the tip a head jutting in front of a hunched
/// body's top may grow (the armadillo's: 25, 28 and 34 cells; its flanks 21 then 38).
const HEAD_GROWTH: f64 = 1.4;

/// A head jutting in front of a hunched body's top is under this share of that top's extent
/// along the axis it juts along.
const FRONT_HEAD_EXTENT: f64 = 0.4;

/// The neck of a standing body that reaches the ground on separate feet (the grid holds the
/// feet in the body: Cheburashka's): [`narrowest_between_ends`] above its lowest third (a head
/// may be more than half the body, his nearly is), at most [`WAIST_SHARE`] of the thinner end
/// (a waist between a thick head and a thick chest). `count`: the body's cells per layer, from
/// the ground up.
fn neck_between_thick_ends(count: &[usize]) -> Option<usize> {
    narrowest_between_ends(count, count.len() / 3, WAIST_SHARE)
}

/// The layer from `first` on, below the last [`NECK_END_LAYERS`], holding the fewest of
/// `count`'s cells against the thinner of its two ends' thickest layers (the lowest such layer
/// on a tie), where that is at most `share`: a neck between two thick ends.
fn narrowest_between_ends(count: &[usize], first: usize, share: f64) -> Option<usize> {
    let layers = count.len();
    let mut below = vec![0usize; layers];
    let mut above = vec![0usize; layers];
    for k in 1..layers {
        below[k] = below[k - 1].max(count[k - 1]);
    }
    for k in (0..layers.saturating_sub(1)).rev() {
        above[k] = above[k + 1].max(count[k + 1]);
    }
    let ratio = |k: usize| count[k] as f64 / below[k].min(above[k]).max(1) as f64;
    (first..layers.saturating_sub(NECK_END_LAYERS))
        .filter(|&k| count[k] > 0 && ratio(k) <= share)
        .min_by(|&a, &b| ratio(a).total_cmp(&ratio(b)).then(a.cmp(&b)))
}

/// The most cells the neck of [`neck_between_thick_ends`] holds, as a share of the thinner
/// end's thickest layer (Cheburashka's: 59 cells against his chest's 98).
const WAIST_SHARE: f64 = 0.65;

/// How many cells of limb region around a head split off above the shoulders are its skin.
const HEAD_SKIN: usize = 2;

/// The fewest layers of body cells a head split off above the shoulders holds.
const HEAD_LAYERS: usize = 2;

/// The most body cells the layer under a standing body's head holds, as a share of the
/// body's thickest layer.
const HEAD_SHARE: f64 = 0.6;

/// How far below a standing body its figure reaches (its legs), as a share of the body's
/// height, for its top to be looked at for a head (the Ogre's legs reach 0.17).
const LEGS_SHARE: f64 = 0.15;

/// The most body cells a neck's layer holds, as a share of the thickest layer of its thinner
/// end.
const NECK_SHARE: f64 = 0.35;

/// The fewest layers each end of a body split at a neck has.
const NECK_END_LAYERS: usize = 3;

/// Geodesic distance (26-neighbour steps) inside limb `l` from its cells touching the body.
fn geodesic_from_body(
    grid: &Grid,
    cells: &[usize],
    limb_of: &[Option<usize>],
    l: usize,
    body: &[bool],
) -> BTreeMap<usize, f64> {
    let mut distance: BTreeMap<usize, f64> = BTreeMap::new();
    let mut heap = BinaryHeap::new();
    for &i in cells {
        if grid.face_neighbours(i).any(|n| body[n]) {
            distance.insert(i, 0.0);
            heap.push((Reverse(0u64), i));
        }
    }
    if heap.is_empty() {
        // A piece with no body (cannot happen: every piece has its deepest cell as a seed).
        if let Some(&first) = cells.first() {
            distance.insert(first, 0.0);
            heap.push((Reverse(0u64), first));
        }
    }
    let steps = neighbour_steps();
    while let Some((Reverse(bits), i)) = heap.pop() {
        let d = f64::from_bits(bits);
        if d > distance[&i] {
            continue;
        }
        let c = grid.cell_of(i);
        for (s, w) in &steps {
            let Some(n) = grid.index(c + *s) else {
                continue;
            };
            if limb_of[n] != Some(l) {
                continue;
            }
            let dn = d + w;
            if distance.get(&n).is_none_or(|&old| dn < old) {
                distance.insert(n, dn);
                heap.push((Reverse(dn.to_bits()), n));
            }
        }
    }
    // Cells reached only through other pieces (none in practice) sit at the root.
    for &i in cells {
        distance.entry(i).or_insert(0.0);
    }
    distance
}

/// Parts smaller than a fifth of the median part of their kind (body slabs or limb segments),
/// or than 4 cells, join the neighbour they share most faces with, so no sliver becomes a cage
/// of its own. The median is per kind: a limb is small beside a body slab and is not a sliver.
fn merge_small_parts(grid: &Grid, parts: &mut Parts) {
    loop {
        let count = parts.roles.len();
        let mut size = vec![0usize; count];
        for p in parts.label.iter().flatten() {
            size[*p as usize] += 1;
        }
        let is_limb = |p: usize| matches!(parts.roles[p], Role::Limb { .. });
        let small_of = |limb: bool| {
            let mut sorted: Vec<usize> = (0..count)
                .filter(|&p| size[p] > 0 && is_limb(p) == limb)
                .map(|p| size[p])
                .collect();
            sorted.sort_unstable();
            let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0);
            (median / 5).max(4)
        };
        let small = [small_of(false), small_of(true)];
        // The first small part with a neighbour (an isolated piece stays a part of its own).
        let Some((victim, into)) = (0..count)
            .filter(|&p| size[p] > 0 && size[p] < small[usize::from(is_limb(p))])
            .find_map(|p| {
                let contacts = contacts_of(grid, &parts.label, p as u32);
                let best = contacts.iter().max_by_key(|(q, n)| (**n, Reverse(**q)))?;
                Some((p, *best.0))
            })
        else {
            return;
        };
        for l in parts.label.iter_mut() {
            if *l == Some(victim as u32) {
                *l = Some(into);
            }
        }
        compact(parts);
    }
}

/// Gives each root segment of a limb its own limb, with the segments that grow from it: where
/// the solid joins two limbs outside the body (legs touching at the crotch, an arm resting on
/// a thigh), their cells form one limb whose segments split into pieces, and one internal cage
/// would drive both. Each later segment follows the earlier neighbour it shares most faces
/// with, so a hand's fingers stay in the hand's limb. Only roles change.
pub(super) fn one_limb_per_root(grid: &Grid, parts: &mut Parts) {
    let count = parts.roles.len();
    let mut next_limb = parts.unused_limb();
    let by_limb = parts.limb_segments();
    let mut new_limb: Vec<Option<usize>> = vec![None; count];
    for (limb, segments) in &by_limb {
        let Some(first) = segments.keys().next().copied() else {
            continue;
        };
        // The first root keeps the limb's number; each other root starts a new limb.
        for (k, &p) in segments[&first].iter().enumerate() {
            new_limb[p as usize] = Some(if k == 0 {
                *limb
            } else {
                next_limb += 1;
                // A second root of a branch grows from the same limb.
                if let Some(&parent) = parts.parent_limb.get(limb) {
                    parts.parent_limb.insert(next_limb - 1, parent);
                }
                next_limb - 1
            });
        }
        for (&segment, list) in segments.range(first + 1..) {
            for &p in list {
                let contacts = contacts_of(grid, &parts.label, p);
                let parent = contacts
                    .iter()
                    .filter(|(q, _)| {
                        matches!(parts.roles[**q as usize], Role::Limb { limb: l, segment: s }
                            if l == *limb && s < segment)
                            && new_limb[**q as usize].is_some()
                    })
                    .max_by_key(|(q, n)| (**n, Reverse(**q)));
                new_limb[p as usize] = Some(
                    parent
                        .and_then(|(q, _)| new_limb[*q as usize])
                        .unwrap_or(*limb),
                );
            }
        }
    }
    for (p, role) in parts.roles.iter_mut().enumerate() {
        if let (Role::Limb { limb, .. }, Some(l)) = (role, new_limb[p]) {
            *limb = l;
        }
    }
}

/// Faces part `p` shares with each other part.
pub(super) fn contacts_of(grid: &Grid, label: &[Option<u32>], p: u32) -> BTreeMap<u32, usize> {
    let mut contacts = BTreeMap::new();
    for (i, l) in label.iter().enumerate() {
        if *l != Some(p) {
            continue;
        }
        let c = grid.cell_of(i);
        for s in FACE_STEPS {
            if let Some(n) = grid.index(c + s)
                && let Some(q) = label[n]
                && q != p
            {
                *contacts.entry(q).or_insert(0) += 1;
            }
        }
    }
    contacts
}

/// Renumbers parts so that the numbers are 0..n without gaps, in order of first cell, and
/// splits every part that is not face-connected into one part per piece.
pub(super) fn compact(parts: &mut Parts) {
    let mut renumber: BTreeMap<u32, u32> = BTreeMap::new();
    let mut roles = Vec::new();
    for l in parts.label.iter_mut().flatten() {
        let next = renumber.len() as u32;
        let new = *renumber.entry(*l).or_insert_with(|| {
            roles.push(parts.roles[*l as usize]);
            next
        });
        *l = new;
    }
    parts.roles = roles;
}

/// Splits parts that are not face-connected into one part per piece (same role).
pub(super) fn split_disconnected(grid: &Grid, parts: &mut Parts) {
    let label = parts.label.clone();
    let (pieces, _) = components_within(grid, |i| label[i]);
    let mut roles = Vec::new();
    let mut seen: BTreeMap<u32, u32> = BTreeMap::new();
    for (i, piece) in pieces.iter().enumerate() {
        if let (Some(piece), Some(old)) = (piece, label[i]) {
            let next = seen.len() as u32;
            let new = *seen.entry(*piece).or_insert_with(|| {
                roles.push(parts.roles[old as usize]);
                next
            });
            parts.label[i] = Some(new);
        }
    }
    parts.roles = roles;
}

fn neighbour_steps() -> Vec<(IVec3, f64)> {
    (-1..=1)
        .flat_map(|z| (-1..=1).flat_map(move |y| (-1..=1).map(move |x| IVec3::new(x, y, z))))
        .filter(|s| *s != IVec3::ZERO)
        .map(|s| (s, s.as_dvec3().length()))
        .collect()
}

fn cell_bounds(grid: &Grid, cells: &[usize]) -> (IVec3, IVec3) {
    cells.iter().fold((IVec3::MAX, IVec3::MIN), |(lo, hi), &i| {
        let c = grid.cell_of(i);
        (lo.min(c), hi.max(c))
    })
}

fn longest_axis(extent: IVec3) -> usize {
    // Ties go to z, then y: bodies stand along z in StarCages' frame.
    [2, 1, 0]
        .into_iter()
        .max_by_key(|&a| (extent[a], a == 2, a == 1))
        .unwrap_or(2)
}

fn mean_depth(depth: &[f64], cells: &[usize]) -> f64 {
    if cells.is_empty() {
        return 1.0;
    }
    (cells.iter().map(|&i| depth[i]).sum::<f64>() / cells.len() as f64).max(0.5)
}

/// The segment (0 at the body) of a limb cut into `count` segments at `along`, the share of
/// its length from the body. The first segment is two segments long, a turn of the whole limb
/// shearing it most, but never more than half of a limb that grows from the trunk
/// (`from_trunk`): a whole leg or arm of two segments bends at its middle (the knee, the
/// elbow), not two thirds of the way out, between the knee and the ankle. A limb that grows
/// from another body (a shin below a knee thick enough to be a body of its own, the beast's;
/// an ear on a head) keeps its joint two thirds out (the ankle).
fn segment_at(along: f64, count: usize, from_trunk: bool) -> usize {
    let segment = if count == 2 && from_trunk {
        (along * 2.0) as usize
    } else {
        let unit = (along * (count + 1) as f64) as usize;
        unit.max(1) - 1
    };
    segment.min(count.max(1) - 1)
}

/// How many pieces of about `piece` a length is cut into (at least one).
fn slab_count(length: f64, piece: f64) -> usize {
    ((length / piece.max(1.0)).round() as usize).clamp(1, 64)
}

#[cfg(test)]
mod tests {
    use super::{
        Cutting, IVec3, LimbCut, ShareOf, paired_segment_counts, segment_at, segments_of_cells,
    };

    /// Where each segment of a limb cut into `count` starts, as a share of its length.
    fn starts(count: usize, from_trunk: bool) -> Vec<f64> {
        let steps = 1200;
        let mut starts = vec![0.0];
        for k in 1..=steps {
            let along = k as f64 / steps as f64;
            let before = segment_at((k - 1) as f64 / steps as f64, count, from_trunk);
            let here = segment_at(along, count, from_trunk);
            assert!(
                here == before || here == before + 1,
                "{count}: {before} -> {here}"
            );
            if here != before {
                starts.push(along);
            }
        }
        starts
    }

    #[test]
    fn a_limb_of_two_segments_from_the_trunk_bends_at_its_middle_else_two_thirds_out() {
        assert_eq!(starts(1, true), vec![0.0]);
        assert_eq!(starts(2, true), vec![0.0, 0.5]);
        let from_a_knee = starts(2, false);
        assert!((from_a_knee[1] - 2.0 / 3.0).abs() < 1e-2, "{from_a_knee:?}");
        // Longer limbs: the first segment two units of count + 1, at most half the limb,
        // every segment present.
        for count in 3..8 {
            for from_trunk in [true, false] {
                let starts = starts(count, from_trunk);
                assert_eq!(starts.len(), count, "{count}: {starts:?}");
                assert!((starts[1] - 2.0 / (count + 1) as f64).abs() < 1e-2);
            }
        }
    }

    fn limb(limb: usize, longest: f64, thickness: f64, root: IVec3) -> LimbCut {
        LimbCut {
            limb,
            cells: Vec::new(),
            longest,
            thickness,
            from_trunk: true,
            root,
            bottom: root.z,
        }
    }

    /// Off the ground: no cut below reaches it.
    const NO_GROUND: i32 = -100;

    #[test]
    fn a_pair_of_limbs_is_cut_into_as_many_segments_each() {
        let cutting = Cutting {
            body_fraction: 0.55,
            segment_length: 1.3,
            slab_length: 0.9,
            on_separate_feet: false,
        };
        // The Ogre's legs: alone, 2 segments and 3.
        let legs = [
            limb(0, 5.56, 2.17, IVec3::new(13, 4, 2)),
            limb(1, 6.97, 2.14, IVec3::new(23, 4, 2)),
        ];
        let alone: Vec<usize> = legs
            .iter()
            .map(|l| super::slab_count(l.longest, cutting.segment_length * l.thickness))
            .collect();
        assert_eq!(alone, [2, 3]);
        assert_eq!(
            paired_segment_counts(&legs, &cutting, NO_GROUND).counts,
            [2, 2]
        );
        // Rooted three cells apart in height, or one much longer, they are no pair.
        let apart = [
            limb(0, 5.56, 2.17, IVec3::new(13, 4, 2)),
            limb(1, 6.97, 2.14, IVec3::new(23, 4, 5)),
        ];
        assert_eq!(
            paired_segment_counts(&apart, &cutting, NO_GROUND).counts,
            [2, 3]
        );
        let longer = [
            limb(0, 5.56, 2.17, IVec3::new(13, 4, 2)),
            limb(1, 9.0, 2.14, IVec3::new(23, 4, 2)),
        ];
        assert_eq!(
            paired_segment_counts(&longer, &cutting, NO_GROUND).counts,
            [2, 3]
        );
        // Of three alike, the two nearest in length pair; the third keeps its own count.
        let three = [
            limb(0, 5.56, 2.17, IVec3::new(13, 4, 2)),
            limb(1, 6.97, 2.14, IVec3::new(23, 4, 2)),
            limb(2, 5.7, 2.17, IVec3::new(18, 9, 2)),
        ];
        assert_eq!(
            paired_segment_counts(&three, &cutting, NO_GROUND).counts,
            [2, 3, 2]
        );
    }

    /// A leg three cells long or more under the trunk, reaching the ground, has a knee (two
    /// segments) however thick it is: TOSCA's cat's hind legs, 3.4 cells long and 2.0
    /// thick, were one segment. Shorter, off the ground, or rooted less than two cells above
    /// its foot (a foot out from a body lying on the ground), it keeps its own count.
    #[test]
    fn a_leg_long_enough_for_a_knee_has_one() {
        let cutting = Cutting {
            body_fraction: 0.55,
            segment_length: 1.3,
            slab_length: 0.9,
            on_separate_feet: false,
        };
        let leg = |longest: f64, root_z: i32, bottom: i32| LimbCut {
            bottom,
            ..limb(0, longest, 2.0, IVec3::new(4, 18, root_z))
        };
        let ground = 0;
        let counts = |cuts: &[LimbCut]| paired_segment_counts(cuts, &cutting, ground).counts;
        assert_eq!(counts(&[leg(3.41, 5, 0)]), [2]);
        assert_eq!(counts(&[leg(3.41, 5, 0), leg(3.41, 5, 1)]), [2, 2]);
        assert_eq!(counts(&[leg(2.9, 5, 0)]), [1]);
        assert_eq!(counts(&[leg(3.41, 5, 2)]), [1]);
        assert_eq!(counts(&[leg(3.41, 1, 0)]), [1]);
        let hanging = LimbCut {
            from_trunk: false,
            ..leg(3.41, 5, 0)
        };
        assert_eq!(counts(std::slice::from_ref(&hanging)), [1]);
        // The minimum is what gives the short leg its knee, and only it.
        let kneed = |cuts: &[LimbCut]| paired_segment_counts(cuts, &cutting, ground).kneed;
        assert_eq!(kneed(&[leg(3.41, 5, 0), leg(2.9, 5, 0)]), [true, false]);
        assert_eq!(kneed(&[leg(3.41, 5, 2), hanging]), [false, false]);
        let long = leg(8.0, 9, 0);
        assert_eq!(counts(std::slice::from_ref(&long)), [3]);
        assert_eq!(kneed(&[long]), [false]);
    }

    /// A knee the two-segment minimum gives a straight leg halves it by its grid layers: they
    /// run six deep (0-5) where one ragged cell at its root leaves the geodesic length 3.4
    /// (TOSCA's cat's hind leg), and each segment holds half its cells. Taken of the
    /// geodesic length (as every other limb is cut), the first keeps the two top layers.
    #[test]
    fn a_knee_the_minimum_adds_halves_the_leg_by_its_layers() {
        let layers = 6;
        let per_layer = 4;
        let cells: Vec<(usize, f64)> = (0..layers * per_layer)
            .map(|i| (i, (0.7 * (i / per_layer) as f64).min(3.4)))
            .collect();
        let straight: Vec<f64> = (0..layers * per_layer)
            .map(|i| (i / per_layer) as f64)
            .collect();
        let cut = |straight: Option<&[f64]>, joints: Option<&[f64]>, shares_of| {
            segments_of_cells(&cells, straight, joints, (2, true), shares_of)
        };
        let firsts = |segments: &[usize]| segments.iter().filter(|&&s| s == 0).count();
        let halved = cut(Some(&straight), None, ShareOf::Layers);
        assert_eq!(firsts(&halved), layers * per_layer / 2, "{halved:?}");
        // Every cell's segment grows with its layer: the cut is one flat face.
        for (a, b) in halved.iter().zip(&halved[per_layer..]) {
            assert!(a <= b, "{halved:?}");
        }
        let by_length = cut(Some(&straight), None, ShareOf::GeodesicLength);
        assert_eq!(firsts(&by_length), 2 * per_layer, "{by_length:?}");
        // Without layers (a bent limb) the distances are cut at their own longest either way.
        for shares_of in [ShareOf::Layers, ShareOf::GeodesicLength] {
            assert_eq!(firsts(&cut(None, None, shares_of)), 3 * per_layer);
        }
        // Joints found by the narrowings cut where they are.
        let at = cut(Some(&straight), Some(&[1.0]), ShareOf::Layers);
        assert_eq!(firsts(&at), per_layer);
    }

    /// A leg climbing the body's flank (a generated stocky quadruped's): distance 0 across
    /// its three top layers, so its layers, counted from the highest cell, run three past
    /// its geodesic distances below. Its knee is still one flat face across it, between whole
    /// layers, with a part of the leg below the body on either side.
    #[test]
    fn a_knee_on_a_leg_with_a_ragged_top_is_one_face_across_it() {
        let layers = 7;
        let per_layer = 9;
        // Layer l's cells: distance 0 on the body's flank (layers 0-2), then l − 3 plus a
        // cell's diagonal step out from the leg's axis.
        let cells: Vec<(usize, f64)> = (0..layers * per_layer)
            .map(|i| {
                let (layer, k) = (i / per_layer, i % per_layer);
                let off_axis = if k == 4 {
                    0.0
                } else {
                    0.41 * (k % 2 + 1) as f64
                };
                (i, (layer as f64 - 3.0 + off_axis).max(0.0))
            })
            .collect();
        let straight: Vec<f64> = (0..layers * per_layer)
            .map(|i| (i / per_layer) as f64)
            .collect();
        let halved = segments_of_cells(&cells, Some(&straight), None, (2, true), ShareOf::Layers);
        let layer_segments: Vec<std::collections::BTreeSet<usize>> = (0..layers)
            .map(|l| {
                halved[l * per_layer..(l + 1) * per_layer]
                    .iter()
                    .copied()
                    .collect()
            })
            .collect();
        assert!(
            layer_segments.iter().all(|s| s.len() == 1),
            "{layer_segments:?}"
        );
        let knee = layer_segments.iter().position(|s| s.contains(&1));
        assert!(matches!(knee, Some(4..=5)), "{layer_segments:?}");
        // Mixing the layers with the distances where they differ by more than the slack, as
        // every other limb is cut, puts a layer of the flank in the second segment above
        // layers of the first: the second is in pieces.
        let mixed = segments_of_cells(
            &cells,
            Some(&straight),
            None,
            (2, true),
            ShareOf::GeodesicLength,
        );
        let farthest_in_first = (0..mixed.len()).rev().find(|&i| mixed[i] == 0);
        let nearest_in_second = (0..mixed.len()).find(|&i| mixed[i] == 1);
        assert!(nearest_in_second < farthest_in_first, "{mixed:?}");
    }
}

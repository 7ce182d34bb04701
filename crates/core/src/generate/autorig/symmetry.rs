//! Mirror symmetry of the auto rig: the grid is symmetric about a grid plane across one axis
//! (`Grid::around`), the solid is made symmetric (a cell is solid when it or its mirror image
//! is), and the parts on the low side of the plane decide the parts on the high side: each
//! part of the low side that reaches the plane continues across it as itself, every other
//! one gets a mirror-image partner (a left leg its right leg, with a limb of its own). The
//! cage faces and the decimation follow the low side too (`polycube`, `decimate`), so the
//! leaf cages are mirror images of each other to rounding.

use std::collections::{BTreeMap, BTreeSet};

use glam::IVec3;

use super::parts::{Parts, Role};
use super::union_find::find;
use super::voxels::Grid;

/// The grid plane the rig is symmetric about: `axis`, at grid coordinate `half` (cells below
/// it are the low side, their images at `2 half - 1 - c`; grid vertices at `2 half - v`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct MirrorPlane {
    /// The axis across which the rig is symmetric.
    pub axis: usize,
    /// The plane's grid coordinate along `axis` (half the grid's cells along it).
    pub half: i32,
}

impl MirrorPlane {
    /// The plane of a grid made symmetric across `axis`.
    pub fn of(grid: &Grid, axis: usize) -> Self {
        Self {
            axis,
            half: grid.dims[axis] / 2,
        }
    }

    /// The mirror image of a cell.
    pub fn cell(&self, mut c: IVec3) -> IVec3 {
        c[self.axis] = 2 * self.half - 1 - c[self.axis];
        c
    }

    /// The mirror image of a grid vertex.
    pub fn vertex(&self, mut v: IVec3) -> IVec3 {
        v[self.axis] = 2 * self.half - v[self.axis];
        v
    }

    /// Whether a cell lies on the low side.
    pub fn is_low_cell(&self, c: IVec3) -> bool {
        c[self.axis] < self.half
    }
}

/// The position of grid vertex `v`, measured from the plane so that a vertex and its image
/// lie at exactly opposite offsets from it.
pub(super) fn vertex_position(grid: &Grid, plane: &MirrorPlane, v: IVec3) -> glam::DVec3 {
    let a = plane.axis;
    let centre = grid.position_along(a, f64::from(plane.half));
    let k = v[a] - plane.half;
    // The offset from |k| alone, so that v and its image get it alike (a band of thin cells
    // across the plane included).
    let offset = match grid.band {
        Some(band) if band.axis == a => {
            grid.position_along(a, f64::from(plane.half + k.abs())) - centre
        }
        _ => f64::from(k.abs()) * grid.cell,
    };
    let mut p = grid.vertex(v);
    p[a] = centre + f64::from(k.signum()) * offset;
    p
}

/// Makes the solid symmetric: a cell is solid when it or its image is.
pub(super) fn symmetric_solid(grid: &Grid, plane: &MirrorPlane, occupied: &mut [bool]) {
    for i in 0..grid.len() {
        let c = grid.cell_of(i);
        if let Some(j) = grid.index(plane.cell(c))
            && plane.is_low_cell(c)
        {
            let either = occupied[i] || occupied[j];
            occupied[i] = either;
            occupied[j] = either;
        }
    }
}

/// The partner of each part: the part holding the images of its cells (itself for a part
/// that crosses the plane). Meaningful once [`mirror_parts`] has run.
pub(super) fn partners(grid: &Grid, plane: &MirrorPlane, parts: &Parts) -> Vec<u32> {
    let mut partner: Vec<u32> = (0..parts.roles.len() as u32).collect();
    for (i, label) in parts.label.iter().enumerate() {
        let Some(p) = *label else { continue };
        if let Some(j) = grid.index(plane.cell(grid.cell_of(i)))
            && let Some(q) = parts.label[j]
        {
            partner[p as usize] = q;
        }
    }
    partner
}

/// The low-side twin of each part: itself for a part with cells on the low side, its partner
/// for a part wholly on the high side. Meaningful once [`mirror_parts`] has run.
pub(super) fn low_twins(grid: &Grid, plane: &MirrorPlane, parts: &Parts) -> Vec<u32> {
    let partner = partners(grid, plane, parts);
    let mut low = vec![false; parts.roles.len()];
    for (i, label) in parts.label.iter().enumerate() {
        if let Some(p) = *label
            && plane.is_low_cell(grid.cell_of(i))
        {
            low[p as usize] = true;
        }
    }
    (0..parts.roles.len())
        .map(|p| if low[p] { p as u32 } else { partner[p] })
        .collect()
}

/// Relabels the high side as the mirror image of the low side (see the module). Limbs of the
/// low side that do not cross the plane get a new limb for their images, branching from the
/// image of the limb they branch from. Parts in `apart` reach the plane without crossing it
/// (their surface does not: a foot touching its twin) and get partners too.
pub(super) fn mirror_parts(
    grid: &Grid,
    plane: &MirrorPlane,
    parts: &mut Parts,
    apart: &BTreeSet<u32>,
) {
    let count = parts.roles.len();
    let mut low = vec![false; count];
    let mut crosses = vec![false; count];
    for (i, label) in parts.label.iter().enumerate() {
        let Some(p) = *label else { continue };
        let c = grid.cell_of(i);
        if plane.is_low_cell(c) {
            low[p as usize] = true;
            if c[plane.axis] == plane.half - 1 && !apart.contains(&p) {
                crosses[p as usize] = true;
            }
        }
    }
    // A limb crosses when any of its low parts does.
    let mut limb_crosses: BTreeMap<usize, bool> = BTreeMap::new();
    for (p, role) in parts.roles.iter().enumerate() {
        if let Role::Limb { limb, .. } = role
            && low[p]
        {
            *limb_crosses.entry(*limb).or_insert(false) |= crosses[p];
        }
    }
    let mut next_limb = parts.unused_limb();
    let mut limb_image: BTreeMap<usize, usize> = BTreeMap::new();
    for (&limb, &cross) in &limb_crosses {
        limb_image.insert(limb, if cross { limb } else { next_limb });
        if !cross {
            next_limb += 1;
        }
    }
    let mut roles = parts.roles.clone();
    let mut image: Vec<Option<u32>> = vec![None; count];
    for p in 0..count {
        if !low[p] {
            continue;
        }
        // The low half of a slab halved on the plane (between two legs) has the high half
        // as its image, a part of its own.
        let halved = parts
            .halved
            .get(&parts.roles[p])
            .filter(|h| h.axis == plane.axis && h.plane == plane.half);
        image[p] = Some(if let Some(h) = halved {
            roles.push(h.high);
            roles.len() as u32 - 1
        } else if crosses[p] {
            p as u32
        } else {
            let role = match parts.roles[p] {
                Role::Limb { limb, segment } => Role::Limb {
                    limb: limb_image.get(&limb).copied().unwrap_or(limb),
                    segment,
                },
                body => body,
            };
            roles.push(role);
            roles.len() as u32 - 1
        });
    }
    for i in 0..grid.len() {
        let c = grid.cell_of(i);
        if plane.is_low_cell(c) {
            continue;
        }
        let from = grid.index(plane.cell(c)).and_then(|j| parts.label[j]);
        parts.label[i] = from.and_then(|p| image[p as usize]);
    }
    let mut parent_limb = parts.parent_limb.clone();
    for (&child, &parent) in &parts.parent_limb {
        if let Some(&c) = limb_image.get(&child)
            && c != child
        {
            parent_limb.insert(c, limb_image.get(&parent).copied().unwrap_or(parent));
        }
    }
    parts.roles = roles;
    parts.parent_limb = parent_limb;
    super::parts::compact(parts);
}

/// Merges on the low side the twins of the parts that `merged` (the same parts after some
/// merges) joins: where a high-side part and its neighbour became one, their low twins become
/// one too, keeping the role nearest the body. Returns the number of parts merged away.
pub(super) fn merge_low_twins(
    grid: &Grid,
    plane: &MirrorPlane,
    parts: &mut Parts,
    merged: &Parts,
) -> usize {
    let count = parts.roles.len();
    let twins = low_twins(grid, plane, parts);
    let mut group_of: Vec<Option<u32>> = vec![None; count];
    for (i, label) in parts.label.iter().enumerate() {
        if let (Some(p), Some(g)) = (*label, merged.label[i]) {
            group_of[p as usize] = Some(g);
        }
    }
    let twin = |p: usize| twins[p] as usize;
    // Each merged group's low twins become the group's first.
    let mut into: Vec<usize> = (0..count).collect();
    let mut first_of: BTreeMap<u32, usize> = BTreeMap::new();
    for (p, group) in group_of.iter().enumerate() {
        let Some(g) = *group else { continue };
        let t = twin(p);
        let first = *first_of.entry(g).or_insert(t);
        let (a, b) = (find(&mut into, first), find(&mut into, t));
        if a != b {
            into[a.max(b)] = a.min(b);
        }
    }
    let mut merges = 0;
    let mut roles = parts.roles.clone();
    for p in 0..count {
        let r = find(&mut into, p);
        if r != p && twin(p) == p {
            roles[r] = roles[r].min(parts.roles[p]);
            merges += 1;
        }
    }
    for (i, label) in parts.label.iter_mut().enumerate() {
        if let Some(p) = label
            && plane.is_low_cell(grid.cell_of(i))
        {
            *p = find(&mut into, *p as usize) as u32;
        }
    }
    parts.roles = roles;
    super::parts::compact(parts);
    merges
}

//! The auto rig: leaf cages that follow a mesh's shape, one chain of cages per limb and a few
//! for each body, sharing faces exactly where they meet, with optional internal cages (one per
//! limb, one over everything) to pose a limb with one cage.
//!
//! The method (docs/autorig.md):
//! 1. the mesh's solid as cells of a regular grid (`voxels`): cells the surface passes
//!    through, and enclosed regions whose generalised winding number is above ½;
//! 2. parts (`parts`): in each connected piece, the body is the union of the balls inscribed
//!    at its thickest cells, cut into slabs across its longest axis; the rest are limbs: each
//!    region split into branches where it forks (`branches`: legs and a tail from one hip band,
//!    ears from a head top), each branch cut into a chain of segments by geodesic distance
//!    (by grid layer along a straight one, so its joints are flat);
//!    a region reaching out less than half its thickness is a bump of the body;
//!    a part holding two separate pieces of the surface is split between them, or merged with
//!    the parts that join them where they share cells (`pieces`);
//! 3. repairs (`repair`) until every part and every union of parts meeting at a grid vertex is
//!    a manifold solid (so each cage and each *Cages join cage is valid);
//! 4. cages (`polycube`): each part's surface as merged rectangles, shared rectangles run in
//!    opposite directions by the two parts;
//! 5. validation of the scene; parts named by a problem are merged and the cages rebuilt.
//!
//! With a mirror plane (`symmetry`), the solid is made symmetric and the low side's parts,
//! faces and collapses decide the high side's.

mod branches;
mod close_legs;
mod contacts;
mod controls;
mod crumbs;
mod decimate;
mod head_in_body;
mod head_over_legs;
mod joint_bodies;
mod limb_tree;
mod mirror_twins;
mod name_defects;
mod naming;
mod narrowings;
mod neck_head;
mod not_a_figure;
mod ownerless_limbs;
mod pair_segments;
mod parts;
mod pieces;
mod polycube;
mod repair;
mod saddles;
mod segment_boundary;
mod straight;
mod surface;
mod surface_pieces;
mod symmetry;
#[cfg(test)]
mod test_cages;
#[cfg(test)]
mod test_mirror;
mod twin_limbs;
mod union_find;
mod voxels;

use std::collections::{BTreeMap, BTreeSet};

use glam::{DVec3, IVec3};
use rayon::prelude::*;
use thiserror::Error;

use crate::check::validate_scene;
use crate::coords::{BindControl, CoordinateKind};
use crate::mesh::Mesh;
use crate::scene::{CageSet, LeafCage, MeshSource, Scene, SceneSettings};
use close_legs::{
    BETTER_LEG_REACH, CELL_IN_GAP, SHORT_BIPED_LEG_REACH, SHORT_LEG_REACH, gap_between_legs,
    has_head, leg_reach, on_two_legs, sided_legs, sided_other_limbs, stands_on_separate_feet,
    unpaired_legs, unsided_legs,
};
use decimate::{Held, SurfaceByPart, Sweep};
use name_defects::{name_defects, names_better};
use parts::{Parts, Role};
use surface::SurfaceMesh;
use symmetry::MirrorPlane;
use voxels::{BandAt, Grid};

/// The mirror plane the rig is made symmetric across.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Mirror {
    /// No symmetry.
    #[default]
    None,
    /// The axis (0 = x, 1 = y, 2 = z) across whose centre plane the mesh is most symmetric,
    /// if it is symmetric enough (otherwise none).
    Auto,
    /// The plane across this axis (0 = x, 1 = y, 2 = z, in the scene's Z-up frame) through the
    /// origin where the mesh is centred on it, else through the mesh's centre.
    Axis(usize),
}

impl Mirror {
    /// The mirror a user names: "auto", or "x", "y" or "z" in the axes of a mesh file whose
    /// up axis is `up` (a Y-up file's y is the scene's z and its z the scene's y).
    pub fn named(name: &str, up: crate::scene::UpAxis) -> Result<Self, String> {
        let file_axis = match name {
            "auto" => return Ok(Self::Auto),
            "x" => 0,
            "y" => 1,
            "z" => 2,
            other => return Err(format!("'{other}': expected x, y, z or auto")),
        };
        Ok(Self::Axis(match (up, file_axis) {
            (crate::scene::UpAxis::Y, 1) => 2,
            (crate::scene::UpAxis::Y, 2) => 1,
            (_, a) => a,
        }))
    }
}

/// Settings of [`autorig`], in the words an artist uses.
#[derive(Debug, Clone, PartialEq)]
pub struct AutorigSettings {
    /// How fine the rig is, 1 (few, coarse cages) to 5 (many, tight ones).
    pub detail: u32,
    /// Least distance from every mesh vertex to the cages' outer surface, as a fraction of the
    /// mesh's bounding-box diagonal (0: the cells the surface passes through are enough).
    pub margin: f64,
    /// A plane the rig is a mirror image of itself across (cage vertices and cages, to
    /// rounding); the cages then enclose the mesh and its mirror image.
    pub mirror: Mirror,
    /// Coordinates of every leaf cage.
    pub kind: CoordinateKind,
    /// Leaf cages whose name starts with one of these get Green coordinates ("keep shape").
    pub keep_shape: Vec<String>,
    /// Also make the controls: an internal box per limb segment turning about its joint and
    /// carrying the segments after it, and `root` over the whole rig (`controls` module).
    pub controls: bool,
}

impl Default for AutorigSettings {
    fn default() -> Self {
        Self {
            detail: 3,
            margin: 0.0,
            mirror: Mirror::None,
            kind: CoordinateKind::MeanValue,
            keep_shape: Vec::new(),
            controls: true,
        }
    }
}

/// Largest accepted [`AutorigSettings::detail`].
pub const MAX_DETAIL: u32 = 5;

/// Why no rig could be made.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AutorigError {
    /// A setting is out of range.
    #[error("auto rig: {0}")]
    Setting(String),
    /// The mesh has no extent to rig.
    #[error(
        "auto rig: the mesh has no volume to put cages around (its vertices lie in one plane, line \
         or point); open a mesh with a body, or give a flat one some thickness"
    )]
    NoVolume,
    /// The cages made are not a valid rig even after merging (a bug or a pathological mesh).
    #[error(
        "auto rig: no valid rig could be made for this mesh ({0}); try another detail, or build \
         the rig in Rig mode"
    )]
    Invalid(String),
    /// Cancelled through the control.
    #[error("auto rig cancelled")]
    Cancelled,
}

/// What the auto rig made, for a report.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AutorigReport {
    /// Grid cells along x, y and z.
    pub grid: [i32; 3],
    /// Cells of the solid.
    pub solid_cells: usize,
    /// Limbs found.
    pub limbs: usize,
    /// Leaf cages made.
    pub leaf_cages: usize,
    /// Cage vertices (leaf cages only).
    pub leaf_vertices: usize,
    /// Parts merged to repair pinches or problems.
    pub merges: usize,
    /// The mirror axis used, if any.
    pub mirror_axis: Option<usize>,
    /// Times the detail's grid was refined (by a quarter each) so that separate components
    /// closer than a cell fall in cages of their own (0: the detail's grid).
    pub refinements: u32,
    /// Leaf cages (indices) that hold more than one piece of the surface
    /// ([`surface_pieces_per_leaf`]): separate components that stay closer than a cell on the
    /// finest grid tried, or set into one another without crossing (teeth in a mouth).
    pub shared_cages: Vec<usize>,
    /// Each limb's name and the name of the limb it grows from (None: from a body).
    pub limb_parents: Vec<(String, Option<String>)>,
}

/// The rig and its report.
#[derive(Debug, Clone, PartialEq)]
pub struct Autorig {
    /// Leaf cages (and internal cages where asked) around the mesh.
    pub cages: CageSet,
    /// What was made.
    pub report: AutorigReport,
}

/// Grid resolution (cells along the longest side) and segment length per detail level.
fn resolution(detail: u32) -> (u32, f64) {
    match detail {
        1 => (20, 2.0),
        2 => (26, 1.6),
        3 => (32, 1.3),
        4 => (40, 1.1),
        _ => (52, 0.9),
    }
}

/// Length of a body slab as a share of a limb segment's (both in thicknesses).
const BODY_SLAB_SHARE: f64 = 0.7;

/// Steps reported through the control's progress.
const STEPS: usize = 6;

/// `mesh` without its exact duplicate triangles (the same three welded vertices, in the same
/// turn: a file that repeats its faces, or many copies of one part stacked in place), which
/// add nothing to the shape the rig follows but cost the voxelisation, the winding numbers and
/// the crossing test each their share (200,000 copies of a cube took minutes). The welded
/// vertices, and so every vertex index the rig reports, stay as they are. A triangle and its
/// reverse (a two-sided sheet) are both kept.
fn without_duplicate_triangles(mesh: &Mesh) -> std::borrow::Cow<'_, Mesh> {
    use std::borrow::Cow;
    let triangles = mesh.welded_triangles();
    // Each triangle as it reads from its least corner (the same triangle whichever corner it
    // starts from), sorted with its index: copies lie side by side, the first in the file
    // first. Sorted in parallel: a hash set of 1.25M triangles was 0.3 s of rigging a
    // 625k-vertex mesh.
    let mut keyed: Vec<([u32; 3], u32)> = triangles
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let first = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
            ([t[first], t[(first + 1) % 3], t[(first + 2) % 3]], i as u32)
        })
        .collect();
    keyed.par_sort_unstable();
    let mut copy = vec![false; triangles.len()];
    for pair in keyed.windows(2) {
        if pair[0].0 == pair[1].0 {
            copy[pair[1].1 as usize] = true;
        }
    }
    let unique: Vec<[u32; 3]> = triangles
        .iter()
        .zip(&copy)
        .filter(|(_, copy)| !**copy)
        .map(|(t, _)| *t)
        .collect();
    if unique.len() == triangles.len() {
        return Cow::Borrowed(mesh);
    }
    match Mesh::new(mesh.welded_positions().to_vec(), unique, None, None) {
        Ok(lean) if lean.welded_positions() == mesh.welded_positions() => Cow::Owned(lean),
        _ => Cow::Borrowed(mesh),
    }
}

/// Builds a shape-following rig around `mesh` (in the scene's Z-up frame). Deterministic: the
/// same mesh and settings give the same cages on any number of threads.
pub fn autorig(
    mesh: &Mesh,
    settings: &AutorigSettings,
    control: &BindControl,
) -> Result<Autorig, AutorigError> {
    if !(1..=MAX_DETAIL).contains(&settings.detail) {
        return Err(AutorigError::Setting(format!(
            "detail {} is outside 1..={MAX_DETAIL}",
            settings.detail
        )));
    }
    if !(0.0..=0.25).contains(&settings.margin) {
        return Err(AutorigError::Setting(format!(
            "margin {} is outside [0, 0.25] (a fraction of the mesh's diagonal)",
            settings.margin
        )));
    }
    if let Mirror::Axis(a) = settings.mirror
        && a > 2
    {
        return Err(AutorigError::Setting(format!(
            "mirror axis {a} is not 0, 1 or 2"
        )));
    }
    let (lo, hi) = mesh.bounds();
    let extent = hi - lo;
    let mut sorted = extent.to_array();
    sorted.sort_by(f64::total_cmp);
    let has_volume = sorted[0] > 1e-6 * sorted[2];
    if !has_volume || mesh.welded_positions().is_empty() {
        return Err(AutorigError::NoVolume);
    }
    // Separate components closer than a cell (letters of a word, parts of a kit) share cells,
    // so a cage may hold two of them: the grid is refined (at most three times, by a quarter) until
    // every cage holds one piece, else the rig with fewest such cages is kept. Parts of one
    // component are never the reason: their cells merge with what joins them (the palm).
    let deduplicated = without_duplicate_triangles(mesh);
    let mesh: &Mesh = &deduplicated;
    let (cells, _) = resolution(settings.detail);
    let surface = SurfaceMesh::new(mesh);
    let facts = MeshFacts {
        symmetry: symmetry_scores(mesh),
        on_separate_feet: stands_on_separate_feet(&surface),
    };
    let mut best: Option<Autorig> = None;
    let chosen = |mut rig: Autorig| {
        not_a_figure::limbs_unless_a_figure(&mut rig);
        Ok(rig)
    };
    for refinement in 0..=MAX_REFINEMENTS {
        let cells = (f64::from(cells) * REFINEMENT.powi(refinement as i32)).round() as u32;
        let detail = rig_with_legs_apart(&surface, settings, &facts, cells, refinement, control);
        let mut rig = match detail {
            Ok(rig) => rig,
            Err(e) if best.is_none() || matches!(e, AutorigError::Cancelled) => return Err(e),
            Err(_) => continue,
        };
        // Limbs the grid joined or confused (two legs as one, legs hanging from their joined
        // thighs, a second arm on one side) on a figure clearly symmetric across a horizontal
        // axis: rigged again mirrored across it, whose parts are alike on both sides (the
        // camel's legs, the elephant's ears and head), kept where its names show fewer.
        if settings.mirror == Mirror::None
            && let Some(axis) = horizontal_symmetry_axis(&facts.symmetry)
            && name_defects(&rig.report) > 0
        {
            let mirrored = AutorigSettings {
                mirror: Mirror::Axis(axis),
                ..settings.clone()
            };
            match rig_with_legs_apart(&surface, &mirrored, &facts, cells, refinement, control) {
                Ok(m) if names_better(&m.report, &rig.report) => rig = m,
                Err(AutorigError::Cancelled) => return Err(AutorigError::Cancelled),
                _ => {}
            }
        }
        let scene = Scene::new(
            MeshSource::Embedded,
            mesh.clone(),
            rig.cages.clone(),
            SceneSettings::default(),
        );
        rig.report.shared_cages = pieces_per_leaf(&scene, &surface.neighbours)
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 1)
            .map(|(leaf, _)| leaf)
            .collect();
        if rig.report.shared_cages.is_empty() {
            return chosen(rig);
        }
        let fewer = |best: &Autorig| rig.report.shared_cages.len() < best.report.shared_cages.len();
        if best.as_ref().is_none_or(fewer) {
            best = Some(rig);
        }
    }
    best.map_or(Err(AutorigError::Cancelled), chosen)
}

/// The rig on the detail's grid of `cells` (limbs apart at a mirror's plane where that makes
/// a valid rig), then, where it found fewer than two legs with a side, a leg without one, or
/// legs reaching little of the height (feet under legs it joined) on a figure standing on
/// separate feet, on the grids that part legs close together, keeping the better rig (more
/// legs with a side, or, for short legs alone, legs reaching higher with no limb lost). An
/// error only where the detail's grid makes no rig (or the job is cancelled).
fn rig_with_legs_apart(
    surface: &SurfaceMesh,
    settings: &AutorigSettings,
    facts: &MeshFacts,
    cells: u32,
    refinement: u32,
    control: &BindControl,
) -> Result<Autorig, AutorigError> {
    let mesh = surface.mesh;
    let on_grid = |cells: u32, choice: GridChoice| {
        rig_on_grid(surface, settings, facts, cells, refinement, choice, control)
    };
    // Limbs apart at the mirror plane where that makes a valid rig, else as before (Homer's
    // legs pressed together at detail 5: two limbs touching along the plane made a
    // non-manifold cage where they meet the body).
    let detail = on_grid(cells, GridChoice::DETAIL).or_else(|e| match e {
        AutorigError::Cancelled => Err(e),
        _ if settings.mirror == Mirror::None => Err(e),
        _ => on_grid(
            cells,
            GridChoice {
                limbs_apart: false,
                ..GridChoice::DETAIL
            },
        ),
    });
    let mut rig = detail?;
    // Legs closer than two cells share the cells between them, which join them into one
    // solid as thick as the body: one leg, or none, is found. A figure symmetric across a
    // horizontal plane standing on separate feet is rigged again on a grid with that plane
    // through the middle of a column of cells, which stays empty between legs more than a
    // cell apart, then with that column thinner than the gap between them; the grid that
    // finds more legs with a side is kept.
    // Also where the legs are feet under legs the grid joined (they reach little of the
    // height): [`retry_is_better`] weighs the retries.
    let wants_retry = |rig: &LegCounts| {
        let short = if rig.on_two_legs {
            SHORT_BIPED_LEG_REACH
        } else {
            SHORT_LEG_REACH
        };
        rig.sided_legs < 2 || rig.unsided_legs > 0 || rig.reach < short || rig.unpaired
    };
    let mut counts = LegCounts::of(&rig);
    if wants_retry(&counts) && facts.on_separate_feet {
        if settings.mirror == Mirror::None && symmetric_across_a_horizontal_plane(&facts.symmetry) {
            match on_grid(cells, GridChoice::CENTRED) {
                Ok(centred) => {
                    let centred_counts = LegCounts::of(&centred);
                    if retry_is_better(&centred_counts, &counts) {
                        (rig, counts) = (centred, centred_counts);
                    }
                }
                Err(AutorigError::Cancelled) => return Err(AutorigError::Cancelled),
                Err(_) => {}
            }
        }
        // Legs closer than a cell: two columns of cells thin enough to fit between them,
        // one either side of a grid plane (the mirror's, with a mirror), every other cell
        // the detail's. No finer grid is needed, so the rig costs what the detail's does
        // (a grid twice as fine made eight times the cells).
        if wants_retry(&counts)
            && let Some(band) = legs_band(mesh, settings.mirror, &facts.symmetry, cells)
        {
            let choice = GridChoice {
                centre_symmetry: settings.mirror == Mirror::None,
                band: Some(band),
                limbs_apart: true,
            };
            match on_grid(cells, choice) {
                Ok(parted) if retry_is_better(&LegCounts::of(&parted), &counts) => rig = parted,
                Err(AutorigError::Cancelled) => return Err(AutorigError::Cancelled),
                _ => {}
            }
        }
    }
    Ok(rig)
}

/// Whether a retry of [`rig_with_legs_apart`] (`retry`) is kept over the rig it retries
/// (`rig`). It must keep the head where the rig has one (the mirrored gorilla's retry traded
/// its head for four legs, kept out only by the count of its other sided limbs). Where the rig
/// asks for the retry only because its legs reach little of the height (two sided legs, none
/// without a side), the retry must keep every sided limb and leg, and find more sided legs or
/// legs reaching higher; else it must find more sided legs, or as many, fewer unsided,
/// reaching higher.
fn retry_is_better(retry: &LegCounts, rig: &LegCounts) -> bool {
    if rig.head && !retry.head {
        return false;
    }
    let keeps_limbs_reaching_higher = retry.sided_legs == rig.sided_legs
        && retry.sided_other_limbs >= rig.sided_other_limbs
        && retry.reach > rig.reach + BETTER_LEG_REACH;
    if rig.sided_legs >= 2 && rig.unsided_legs == 0 {
        retry.unsided_legs == 0
            && ((retry.sided_legs > rig.sided_legs
                && retry.sided_other_limbs >= rig.sided_other_limbs)
                || keeps_limbs_reaching_higher)
    } else {
        // Or as many with fewer unsided (the knight's centre `leg` on the ground between
        // its feet, mirrored at detail 3).
        retry.sided_legs > rig.sided_legs
            || (keeps_limbs_reaching_higher && retry.unsided_legs < rig.unsided_legs)
    }
}

/// What `rig_with_legs_apart` weighs a rig by, counted once per rig from its leaf names.
struct LegCounts {
    sided_legs: usize,
    unsided_legs: usize,
    sided_other_limbs: usize,
    /// [`leg_reach`]: the top of its legs as a share of the figure's height.
    reach: f64,
    /// [`on_two_legs`]: its legs are `leg.L` and `leg.R`.
    on_two_legs: bool,
    /// [`has_head`]: it has a `head` limb.
    head: bool,
    /// [`unpaired_legs`]: more legs on one side than on the other.
    unpaired: bool,
}

impl LegCounts {
    fn of(rig: &Autorig) -> Self {
        Self {
            sided_legs: sided_legs(rig),
            unsided_legs: unsided_legs(rig),
            sided_other_limbs: sided_other_limbs(rig),
            reach: leg_reach(rig),
            on_two_legs: on_two_legs(rig),
            head: has_head(rig),
            unpaired: unpaired_legs(rig),
        }
    }
}

/// Thin cells between legs closer than a cell of the detail's grid (`cells` along the longest
/// side): across the mirror's plane where the rig mirrors across a horizontal axis, else
/// across the centre plane of each horizontal axis the mesh is symmetric across (the widest
/// gap where both part legs), [`CELL_IN_GAP`] of the gap between the legs wide. None where no
/// plane has legs on either side ([`gap_between_legs`]) or their gap is wider than the two
/// cells the band replaces.
fn legs_band(mesh: &Mesh, mirror: Mirror, scores: &[f64; 3], cells: u32) -> Option<BandAt> {
    let (lo, hi) = mesh.bounds();
    let cell = (hi - lo).max_element() / f64::from(cells.max(1));
    let axes: Vec<(usize, f64)> = match mirror {
        Mirror::None => (0..2)
            .filter(|&a| scores[a] >= SYMMETRIC_SHARE)
            .map(|a| (a, 0.5 * (lo[a] + hi[a])))
            .collect(),
        Mirror::Axis(a) => vec![(a, mirror_plane(lo[a], hi[a]))],
        Mirror::Auto => most_symmetric_axis(scores)
            .map(|a| (a, mirror_plane(lo[a], hi[a])))
            .into_iter()
            .collect(),
    };
    axes.into_iter()
        .filter(|&(a, _)| a < 2)
        .filter_map(|(axis, plane)| {
            let width = CELL_IN_GAP * gap_between_legs(mesh, axis, plane)?;
            // Two columns, one either side of its plane.
            let columns = 2.0;
            (width < columns * cell).then_some(BandAt { axis, plane, width })
        })
        .max_by(|a, b| a.width.total_cmp(&b.width))
}

/// The parts of the cells within one cell of `point` (the cell it lies in and its 26
/// neighbours).
fn parts_around(grid: &Grid, parts: &Parts, point: DVec3) -> Vec<u32> {
    let centre = grid.cell_at(point);
    let mut around = Vec::new();
    for dz in -1..=1 {
        for dy in -1..=1 {
            for dx in -1..=1 {
                let label = grid
                    .index(centre + glam::IVec3::new(dx, dy, dz))
                    .and_then(|i| parts.label.get(i).copied().flatten());
                around.extend(label);
            }
        }
    }
    around.sort_unstable();
    around.dedup();
    around
}

/// Times the grid may be refined to give every cage one piece of surface, and by how much.
const MAX_REFINEMENTS: u32 = 3;
const REFINEMENT: f64 = 1.25;

/// What [`autorig`] measures of the mesh once, for every grid it rigs on.
struct MeshFacts {
    /// [`symmetry_scores`].
    symmetry: [f64; 3],
    /// [`stands_on_separate_feet`].
    on_separate_feet: bool,
}

/// How a grid is laid over the mesh, besides its cells along the longest side.
#[derive(Debug, Clone, Copy)]
struct GridChoice {
    /// Each horizontal plane the mesh is symmetric across through the middle of a column of
    /// cells (the retry for legs close together).
    centre_symmetry: bool,
    /// Thin cells between legs closer than a cell ([`legs_band`]).
    band: Option<BandAt>,
    /// Whether a mirrored rig mirrors limbs that touch their twins at the plane as limbs of
    /// their own ([`limbs_apart_at_plane`]); off for the retry where that made no valid rig.
    limbs_apart: bool,
}

impl GridChoice {
    /// The detail's grid, laid from the mesh's corner.
    const DETAIL: Self = Self {
        centre_symmetry: false,
        band: None,
        limbs_apart: true,
    };
    /// The detail's grid, centred on the planes of symmetry.
    const CENTRED: Self = Self {
        centre_symmetry: true,
        band: None,
        limbs_apart: true,
    };
}

/// [`autorig`] on a grid of `cells` along the mesh's longest side (`refinement`: how many
/// times the detail's grid was refined to reach it), laid as `choice` says.
fn rig_on_grid(
    surface: &SurfaceMesh,
    settings: &AutorigSettings,
    facts: &MeshFacts,
    cells: u32,
    refinement: u32,
    choice: GridChoice,
    control: &BindControl,
) -> Result<Autorig, AutorigError> {
    let GridChoice {
        centre_symmetry,
        band,
        limbs_apart,
    } = choice;
    let mesh = surface.mesh;
    let (lo, hi) = mesh.bounds();
    let extent = hi - lo;
    control.set_total(STEPS);

    let check = || {
        if control.is_cancelled() {
            Err(AutorigError::Cancelled)
        } else {
            Ok(())
        }
    };
    let (_, segment_length) = resolution(settings.detail);
    let mirror_axis = match settings.mirror {
        Mirror::None => None,
        Mirror::Axis(a) => Some(a),
        Mirror::Auto => most_symmetric_axis(&facts.symmetry),
    };
    // On a retry for legs close together ([`autorig`]), each horizontal plane of symmetry of
    // the mesh through the middle of a column of cells.
    let centred: Vec<(usize, f64)> = if centre_symmetry {
        (0..2)
            .filter(|&a| mirror_axis.is_none() && facts.symmetry[a] >= SYMMETRIC_SHARE)
            .map(|a| (a, 0.5 * (lo[a] + hi[a])))
            .collect()
    } else {
        Vec::new()
    };
    let grid = Grid::around(
        lo,
        hi,
        cells,
        mirror_axis.map(|a| (a, mirror_plane(lo[a], hi[a]))),
        &centred,
        band,
    );
    let mut occupied = voxels::solid_cells(&grid, mesh);
    if settings.margin > 0.0 {
        widen(
            &grid,
            &mut occupied,
            mesh,
            settings.margin * extent.length(),
        );
    }
    let mirror = mirror_axis.map(|a| MirrorPlane::of(&grid, a));
    if let Some(m) = &mirror {
        symmetry::symmetric_solid(&grid, m, &mut occupied);
    }
    control.advance();
    check()?;
    let depth = voxels::distance_to_outside(&grid, &occupied);
    let cutting = parts::Cutting {
        body_fraction: 0.55,
        segment_length,
        // Body slabs shorter than limb segments: a slab's neighbourhood (itself, the slabs
        // beside it and the limbs it carries) is then a smaller share of a long body, which
        // saves memory against single MVC (docs/performance.md, "Design measurements"); 0.5
        // made too many slabs.
        slab_length: BODY_SLAB_SHARE * segment_length,
        on_separate_feet: facts.on_separate_feet,
    };
    // Where the mesh narrows along a limb (a knee, an elbow), its joints move there.
    let samples = narrowings::samples_by_cell(&grid, mesh.welded_positions());
    let mut parts = parts::cut_into_parts(&grid, &occupied, &depth, &cutting, &samples);
    // A mirrored grid cuts a limb's twin as its mirror image (below); another may leave it
    // inside a larger limb.
    if mirror.is_none()
        && let Some(axis) = horizontal_symmetry_axis(&facts.symmetry)
    {
        mirror_twins::carve_missing_twins(&grid, &mut parts, axis, 0.5 * (lo[axis] + hi[axis]));
    }
    let cut_roles = parts.roles_by_cell();
    pieces::split_by_surface_pieces(&grid, &mut parts, surface);
    let mut merges = pieces::merge_inseparable_pieces(&grid, &mut parts, surface, mirror.as_ref());
    control.advance();
    check()?;
    // Repairs move cells between parts, which may leave a part two pieces again.
    merges += repair::make_manifold(&grid, &mut parts);
    merges += pieces::merge_inseparable_pieces(&grid, &mut parts, surface, mirror.as_ref());
    parts::one_limb_per_root(&grid, &mut parts);
    let crumbs = crumbs::merge_crumb_segments(&grid, &mut parts, surface);
    if crumbs > 0 {
        merges += crumbs + repair::make_manifold(&grid, &mut parts);
    }
    // A mirrored rig's pairs are mirror images (below); another's are made equal here.
    if mirror.is_none() {
        let equalised = pair_segments::equal_pair_segments(&grid, &mut parts, &cut_roles);
        if equalised > 0 {
            merges += equalised + repair::make_manifold(&grid, &mut parts);
        }
    }
    if let Some(m) = &mirror {
        merges += make_symmetric(&grid, m, &mut parts, surface, limbs_apart);
    }
    control.advance();
    check()?;
    // Build, validate, merge what a problem names, again.
    let mut rounds = 0;
    // Parts whose decimated cage did not validate keep their grid-stepped faces.
    let mut frozen: BTreeSet<u32> = BTreeSet::new();
    // Parts whose decimated cage did not validate with triangles across the band of thin
    // cells between legs: theirs cross none in the next round, before they are frozen.
    let mut off_band: BTreeSet<u32> = BTreeSet::new();
    // Parts where a collapse between two cages swept a piece of surface away from the rest
    // of the cage's: their faces sweep no mesh vertex in the next round.
    let mut no_sweep: BTreeSet<u32> = BTreeSet::new();
    // Parts left with a piece cut off where their collapses swept nothing: the sheets between
    // them spanned again from their rims sweep no mesh vertex in the next round either.
    let mut no_respan_sweep: BTreeSet<u32> = BTreeSet::new();
    let partners = |parts: &Parts, leaves: &[u32]| -> Vec<u32> {
        let partner = mirror.as_ref().map(|m| symmetry::partners(&grid, m, parts));
        leaves
            .iter()
            .filter_map(|&l| partner.as_ref()?.get(l as usize).copied())
            .collect()
    };
    let problem_of = |set: &CageSet| {
        let scene = Scene::new(
            MeshSource::Embedded,
            mesh.clone(),
            set.clone(),
            SceneSettings::default(),
        );
        validate_scene(&scene).errors.into_iter().next()
    };
    let cages = loop {
        // Decimated cages first; a cage named by a problem is kept grid-stepped and the rest
        // decimated again; all grid-stepped where that does not validate either.
        let label_by_cell: Vec<Option<u32>> = mesh
            .welded_positions()
            .iter()
            .map(|&p| parts.part_at(&grid, p))
            .collect();
        let (decimated, swept) = leaf_cages(
            &grid,
            &parts,
            settings,
            mirror.as_ref(),
            Some((
                mesh,
                Held {
                    frozen: &frozen,
                    off_band: &off_band,
                },
                Sweep {
                    refused: &no_sweep,
                    respan_refused: &no_respan_sweep,
                    surface: Some(SurfaceByPart {
                        label: &label_by_cell,
                        neighbours: &surface.neighbours,
                    }),
                },
            )),
        );
        let Some(problem) = problem_of(&decimated) else {
            let cut_off = leaves_cut_by_sweeps(&decimated, &grid, &parts, surface, &swept);
            // Each round refuses more parts, so this ends (at the latest with every part
            // refused: no sweep at all).
            if cut_off.iter().all(|l| no_respan_sweep.contains(l)) {
                break decimated;
            }
            // Collapses first; a part cut off again though they swept nothing in it was cut
            // by a respan.
            let (again, first): (Vec<u32>, Vec<u32>) =
                cut_off.iter().partition(|l| no_sweep.contains(l));
            for (refused, cut) in [(&mut no_respan_sweep, again), (&mut no_sweep, first)] {
                let images = partners(&parts, &cut);
                refused.extend(cut);
                refused.extend(images);
            }
            check()?;
            continue;
        };
        let elements = problem.elements(&decimated);
        let named: Vec<u32> = elements
            .leaf_cages
            .into_iter()
            .map(|l| l as u32)
            .filter(|l| !frozen.contains(l))
            .collect();
        // With a band of thin cells, the named cages' triangles first keep off its planes,
        // then every cage's, and only then are the named cages frozen. Where the problem names
        // no cage (a mesh vertex left outside), the parts of the cells around that vertex keep
        // off first: every cage kept off the band kept Homer's grid steps across his body and
        // head for one vertex at his crotch (358 cage vertices, 287 with the parts around it).
        let every_part: BTreeSet<u32> = (0..parts.roles.len() as u32).collect();
        let band = grid.band.is_some();
        if band && named.is_empty() && off_band != every_part {
            let points = mesh.welded_positions();
            let around: BTreeSet<u32> = elements
                .mesh_vertices
                .iter()
                .filter_map(|&v| points.get(v))
                .flat_map(|&p| parts_around(&grid, &parts, p))
                .filter(|l| !off_band.contains(l))
                .collect();
            if around.is_empty() {
                off_band = every_part;
            } else {
                let around: Vec<u32> = around.into_iter().collect();
                let images = partners(&parts, &around);
                off_band.extend(around);
                off_band.extend(images);
            }
            check()?;
            continue;
        }
        if !named.is_empty() {
            // A held cage's image is held with it.
            let images = partners(&parts, &named);
            if band && named.iter().all(|l| !off_band.contains(l)) {
                off_band.extend(named);
                off_band.extend(images);
            } else if band && off_band != every_part {
                off_band = every_part;
            } else {
                frozen.extend(named);
                frozen.extend(images);
            }
            check()?;
            continue;
        }
        let (set, _) = leaf_cages(&grid, &parts, settings, mirror.as_ref(), None);
        let Some(problem) = problem_of(&set) else {
            break set;
        };
        rounds += 1;
        let named = problem.elements(&set).leaf_cages;
        if rounds > 32 || named.len() < 2 {
            return Err(AutorigError::Invalid(problem.to_string()));
        }
        // With a mirror, the parts merge on the low side (the images follow).
        let twins = mirror
            .as_ref()
            .map(|m| symmetry::low_twins(&grid, m, &parts));
        let named: Vec<u32> = named
            .iter()
            .map(|&l| {
                twins
                    .as_ref()
                    .and_then(|t| t.get(l).copied())
                    .unwrap_or(l as u32)
            })
            .collect();
        let into = named[0];
        for l in parts.label.iter_mut().flatten() {
            if named.contains(l) {
                *l = into;
            }
        }
        parts::compact(&mut parts);
        merges += repair::make_manifold(&grid, &mut parts) + 1;
        if let Some(m) = &mirror {
            merges += make_symmetric(&grid, m, &mut parts, surface, limbs_apart);
        }
        frozen.clear();
        off_band.clear();
        no_sweep.clear();
        no_respan_sweep.clear();
        check()?;
    };
    control.advance();
    // Where two cages share faces the surface does not pass (two paws side by side), each
    // keeps its own vertices there, so that each limb's control carries its side.
    let plane = mirror_axis.map(|a| (a, mirror_plane(lo[a], hi[a])));
    let mut cages = match contacts::part_contacts(&cages, surface, plane) {
        Some((parted, _)) if problem_of(&parted).is_none() => parted,
        _ => cages,
    };
    // Without a mirror, the figure's sides are across the horizontal axis it is symmetric
    // across, where there is one.
    let lateral = plane
        .map(|(a, _)| a)
        .or_else(|| horizontal_symmetry_axis(&facts.symmetry));
    let leaf_roles = parts_of_leaves(&parts, &cages);
    let heads =
        head_over_legs::heads_over_legs(&cages, &leaf_roles, &parts.parent_limb, &parts.heads);
    let (mut roles, mut parent_limb, bodies) = limb_tree::bodies_as_limbs(
        &cages,
        &leaf_roles,
        &parts.parent_limb,
        lateral.filter(|&a| a < 2),
        &heads,
    );
    let mut names = naming::limb_names(
        &cages,
        &roles,
        &parent_limb,
        &bodies,
        plane,
        lateral,
        &heads,
    );
    ownerless_limbs::fold_ownerless_limbs(&mut cages, &mut roles, &mut parent_limb, &mut names);
    neck_head::head_off_neck(&cages, &mut roles, &mut parent_limb, &mut names);
    twin_limbs::merge_twin_limbs(&cages, &mut roles, &mut parent_limb, &mut names);
    head_in_body::head_out_of_body(&cages, &mut roles, &mut parent_limb, &mut names);
    naming::rename_limb_cages(&mut cages, &roles, &names);
    if settings.controls {
        controls::add_controls(&mut cages, &roles, &parent_limb, &names);
    }
    control.advance();
    let report = AutorigReport {
        grid: grid.dims.to_array(),
        solid_cells: occupied.iter().filter(|&&o| o).count(),
        limbs: parts
            .roles
            .iter()
            .filter_map(|r| match r {
                Role::Limb { limb, .. } => Some(*limb),
                Role::Body { .. } => None,
            })
            .collect::<BTreeSet<_>>()
            .len(),
        leaf_cages: cages.leaves.len(),
        leaf_vertices: cages
            .leaves
            .iter()
            .flat_map(|l| l.faces.iter().flatten())
            .collect::<BTreeSet<_>>()
            .len(),
        merges,
        mirror_axis,
        refinements: refinement,
        shared_cages: Vec::new(),
        limb_parents: names
            .iter()
            .map(|(limb, name)| {
                let parent = parent_limb.get(limb).and_then(|p| names.get(p)).cloned();
                (name.clone(), parent)
            })
            .collect(),
    };
    control.advance();
    Ok(Autorig { cages, report })
}

/// The leaf cages of the parts, named by role; decimated around the mesh where given, except
/// the held parts' faces (`decimate::Held`), with what the collapses swept into another cage
/// (nothing when not decimated).
fn leaf_cages(
    grid: &Grid,
    parts: &Parts,
    settings: &AutorigSettings,
    mirror: Option<&MirrorPlane>,
    decimate_around: Option<(&Mesh, Held<'_>, Sweep<'_>)>,
) -> (CageSet, decimate::Swept) {
    let faces = polycube::boundary_faces(grid, parts, mirror);
    let (vertices, faces) = polycube::indexed_faces(&faces);
    let (faces, swept) = match decimate_around {
        Some((mesh, held, sweep)) => {
            let decimated = decimate::decimate(
                grid,
                &vertices,
                &faces,
                mesh.welded_positions(),
                held,
                mirror,
                sweep,
            );
            let faces = decimated
                .triangles
                .into_iter()
                .map(|(corners, front, back)| (corners.to_vec(), front, back))
                .collect();
            (faces, decimated.swept)
        }
        None => (faces, decimate::Swept::default()),
    };
    let (vertices, per_part) = polycube::part_faces(&vertices, &faces, parts.roles.len());
    let names = part_names(&parts.roles);
    let leaves = per_part
        .into_iter()
        .zip(names)
        .map(|(faces, name)| {
            let keep = settings
                .keep_shape
                .iter()
                .any(|k| name.starts_with(k.as_str()));
            LeafCage {
                kind: if keep {
                    CoordinateKind::Green
                } else {
                    settings.kind
                },
                name,
                h: None,
                border_h: BTreeMap::new(),
                faces,
            }
        })
        .collect();
    let cages = CageSet {
        vertices: vertices
            .iter()
            .map(|&v| match mirror {
                Some(m) => symmetry::vertex_position(grid, m, v),
                None => grid.vertex(v),
            })
            .collect(),
        leaves,
        internals: Vec::new(),
    };
    (cages, swept)
}

/// Names by role: `body_K` along each body (`body2_K` for a second body), `limbL_K` from the
/// root of limb L; a part split into pieces gets a letter.
fn part_names(roles: &[Role]) -> Vec<String> {
    // Number bodies and limbs in order of appearance, segments in order along them.
    let mut bodies: BTreeMap<usize, usize> = BTreeMap::new();
    let mut limbs: BTreeMap<usize, usize> = BTreeMap::new();
    for role in roles {
        match *role {
            Role::Body { body, .. } => {
                let n = bodies.len();
                bodies.entry(body).or_insert(n);
            }
            Role::Limb { limb, .. } => {
                let n = limbs.len();
                limbs.entry(limb).or_insert(n);
            }
        }
    }
    let mut taken: BTreeMap<String, usize> = BTreeMap::new();
    roles
        .iter()
        .map(|role| {
            let base = match *role {
                Role::Body { body, slab } if bodies[&body] == 0 => format!("body_{}", slab + 1),
                Role::Body { body, slab } => format!("body{}_{}", bodies[&body] + 1, slab + 1),
                Role::Limb { limb, segment } => format!("limb{}_{}", limbs[&limb] + 1, segment + 1),
            };
            let n = taken.entry(base.clone()).or_insert(0);
            *n += 1;
            if *n == 1 {
                base
            } else {
                format!("{base}{}", char::from(b'a' + (*n as u8 - 1).min(25)))
            }
        })
        .collect()
}

/// Role of each leaf cage (parts and leaves are in the same order).
fn parts_of_leaves(parts: &Parts, cages: &CageSet) -> Vec<Role> {
    parts
        .roles
        .iter()
        .copied()
        .take(cages.leaves.len())
        .collect()
}

/// Where the mirror plane lies along its axis, given the mesh's bounds along it: at the mesh's
/// origin (0, where Blender's X-mirror and the editor's mirror editing put it) when the
/// bounds' centre lies within [`ORIGIN_TOLERANCE`] of their width from it, else at the centre.
fn mirror_plane(lo: f64, hi: f64) -> f64 {
    let centre = 0.5 * (lo + hi);
    if centre.abs() <= ORIGIN_TOLERANCE * (hi - lo) {
        0.0
    } else {
        centre
    }
}

/// See [`mirror_plane`].
const ORIGIN_TOLERANCE: f64 = 0.01;

/// Mirrors the low side's parts onto the high side and repairs, until the repairs leave the
/// parts symmetric (a few rounds; repairs across the plane are symmetric in practice). Where
/// the mesh is not symmetric, a high-side copy of a part may hold two pieces of the surface
/// that its low twin does not: the parts such pieces call to merge are merged on the low side
/// too (`symmetry::merge_low_twins`) and the whole mirrored again, kept only where that leaves
/// fewer extra pieces over the whole rig (on a lopsided figure it can join a leg to the body).
/// Returns the merges made.
fn make_symmetric(
    grid: &Grid,
    mirror: &MirrorPlane,
    parts: &mut Parts,
    surface: &SurfaceMesh,
    limbs_apart: bool,
) -> usize {
    let mirror_and_repair = |parts: &mut Parts| {
        let mut merges = 0;
        for _ in 0..4 {
            let apart = if limbs_apart {
                limbs_apart_at_plane(grid, mirror, parts, surface)
            } else {
                BTreeSet::new()
            };
            symmetry::mirror_parts(grid, mirror, parts, &apart);
            let before = parts.label.clone();
            merges += repair::make_manifold(grid, parts);
            if parts.label == before {
                break;
            }
        }
        merges
    };
    let mut merges = mirror_and_repair(parts);
    for _ in 0..4 {
        let extra = pieces::extra_pieces_total(grid, parts, surface);
        let mut trial = parts.clone();
        if extra == 0
            || pieces::merge_inseparable_pieces(grid, &mut trial, surface, Some(mirror)) == 0
        {
            break;
        }
        let mut candidate = parts.clone();
        let twins = symmetry::merge_low_twins(grid, mirror, &mut candidate, &trial);
        let repairs = mirror_and_repair(&mut candidate);
        if twins == 0 || pieces::extra_pieces_total(grid, &candidate, surface) >= extra {
            break;
        }
        *parts = candidate;
        merges += twins + repairs;
    }
    merges
}

/// The limb parts that reach the mirror plane without their surface crossing it
/// ([`pieces::limbs_stopping_at_plane`]) and that, mirrored as parts crossing the plane, would be
/// merged away with their limb: a foot touching its twin becomes one part holding both feet,
/// which the trunk joins into one piece (the mirrored Cheburashka had no legs). Limbs that
/// survive that merge (Homer's legs at detail 5, pressed together along their length) are
/// mirrored as before.
fn limbs_apart_at_plane(
    grid: &Grid,
    mirror: &MirrorPlane,
    parts: &Parts,
    surface: &SurfaceMesh,
) -> BTreeSet<u32> {
    let candidates = pieces::limbs_stopping_at_plane(grid, parts, surface, mirror);
    if candidates.is_empty() {
        return candidates;
    }
    let limbs_of = |parts: &Parts| -> BTreeSet<usize> {
        (parts.roles.iter())
            .filter_map(|r| match r {
                Role::Limb { limb, .. } => Some(*limb),
                Role::Body { .. } => None,
            })
            .collect()
    };
    let mut trial = parts.clone();
    symmetry::mirror_parts(grid, mirror, &mut trial, &BTreeSet::new());
    let before = limbs_of(&trial);
    pieces::merge_inseparable_pieces(grid, &mut trial, surface, Some(mirror));
    let erased: BTreeSet<usize> = before.difference(&limbs_of(&trial)).copied().collect();
    (candidates.into_iter())
        .filter(|&p| matches!(parts.roles[p as usize], Role::Limb { limb, .. } if erased.contains(&limb)))
        .collect()
}

/// Adds every cell within `distance` of a mesh vertex to the solid.
fn widen(grid: &Grid, occupied: &mut [bool], mesh: &Mesh, distance: f64) {
    for &p in mesh.welded_positions() {
        let lo = grid.cell_at(p - DVec3::splat(distance));
        let hi = grid.cell_at(p + DVec3::splat(distance));
        for z in lo.z..=hi.z {
            for y in lo.y..=hi.y {
                for x in lo.x..=hi.x {
                    if let Some(i) = grid.index(glam::IVec3::new(x, y, z)) {
                        occupied[i] = true;
                    }
                }
            }
        }
    }
}

/// The axis across whose centre plane the mesh's vertices are most symmetric, if their mirror
/// images land within 2 % of the diagonal of a vertex for at least 90 % of them (`scores`:
/// [`symmetry_scores`], sampled on a coarse grid of occupied cells).
fn most_symmetric_axis(scores: &[f64; 3]) -> Option<usize> {
    (0..3)
        .filter(|&a| scores[a] >= 0.9)
        .max_by(|&a, &b| scores[a].total_cmp(&scores[b]).then(b.cmp(&a)))
}

/// Whether the mesh is symmetric across the centre plane of X or Y ([`SYMMETRIC_SHARE`]).
fn symmetric_across_a_horizontal_plane(scores: &[f64; 3]) -> bool {
    scores[..2].iter().any(|&score| score >= SYMMETRIC_SHARE)
}

/// The share of a mesh's vertices whose mirror image lands on its surface
/// ([`symmetry_scores`]) for it to count as symmetric across that plane.
const SYMMETRIC_SHARE: f64 = 0.9;

/// The horizontal axis (X or Y) the mesh is clearly symmetric across: at least 90 % of its
/// vertices mirrored onto it, and 5 points more than across the other. A figure's left and
/// right are across it (a head deeper than it is wide included); None where both or neither
/// are (a cube, a lopsided shape).
fn horizontal_symmetry_axis(scores: &[f64; 3]) -> Option<usize> {
    let (x, y) = (scores[0], scores[1]);
    match () {
        _ if x >= SYMMETRIC_SHARE && x >= y + 0.05 => Some(0),
        _ if y >= SYMMETRIC_SHARE && y >= x + 0.05 => Some(1),
        _ => None,
    }
}

/// Per axis, the share of the mesh's vertices whose mirror image across the centre plane lands
/// within a cell (of 48 along the longest side) of a vertex.
fn symmetry_scores(mesh: &Mesh) -> [f64; 3] {
    let (lo, hi) = mesh.bounds();
    let n = 48.0;
    let cell = (hi - lo).max_element() / n;
    let key = |p: DVec3| ((p - lo) / cell).floor().as_ivec3();
    // The occupied cells as bits of a dense grid one cell wider on every side than the mesh's
    // (a mirrored point's neighbours may lie one cell out): a lookup per neighbour, where a
    // tree of cells made this a seventh of rigging a 625k-vertex mesh.
    let dims = key(hi) + IVec3::splat(3);
    let index = |c: IVec3| -> Option<usize> {
        let c = c + IVec3::ONE;
        (c.cmpge(IVec3::ZERO).all() && c.cmplt(dims).all())
            .then(|| ((c.z * dims.y + c.y) * dims.x + c.x) as usize)
    };
    let mut occupied = vec![false; (dims.x * dims.y * dims.z).max(0) as usize];
    for &p in mesh.welded_positions() {
        if let Some(slot) = index(key(p)).and_then(|i| occupied.get_mut(i)) {
            *slot = true;
        }
    }
    let centre = 0.5 * (lo + hi);
    let score = |axis: usize| -> f64 {
        let hits = mesh
            .welded_positions()
            .par_iter()
            .filter(|&&p| {
                let mut q = p;
                q[axis] = 2.0 * centre[axis] - p[axis];
                let c = key(q);
                (-1..=1).any(|dx| {
                    (-1..=1).any(|dy| {
                        (-1..=1).any(|dz| {
                            index(c + IVec3::new(dx, dy, dz))
                                .is_some_and(|i| occupied.get(i).copied().unwrap_or(false))
                        })
                    })
                })
            })
            .count();
        hits as f64 / mesh.welded_positions().len().max(1) as f64
    };
    [score(0), score(1), score(2)]
}

/// The scene settings an auto-rigged scene starts with: the defaults, with mean value join
/// cages (the paper's default join transformation). Its join cages are concave almost
/// everywhere, so the automatic policy would solve a harmonic grid for most of them: on the
/// armadillo that bind took minutes and gigabytes (docs/autorig.md).
pub fn autorig_settings() -> SceneSettings {
    SceneSettings {
        join_coordinates: crate::scene::JoinPolicy::Mvc,
        ..SceneSettings::default()
    }
}

/// Pieces of the surface smaller than this many mesh vertices (or than 1 % of a cage's
/// vertices) are slivers: they do not count as a part of their own.
pub const SLIVER_VERTICES: usize = 20;

/// For each leaf cage of `scene`, the number of connected pieces of the mesh surface among the
/// mesh vertices it holds (inside or on it), slivers left out (see [`SLIVER_VERTICES`]). A
/// rig that follows the shape has 1 everywhere: two legs, or an arm and the torso beside it,
/// never share a cage. Vertices are joined by mesh edges and where separate components pass
/// through each other (an eye set into its socket): those are one piece as a set of points.
pub fn surface_pieces_per_leaf(scene: &Scene) -> Vec<usize> {
    pieces_per_leaf(scene, &surface::surface_neighbours(&scene.mesh))
}

/// The leaf cages (by index, which is their part's label) a decimation's sweeps (`swept`: the
/// welded vertices a collapse moved into another cage, and the parts on either side of those
/// collapses) may have left wrong: a touched cage holding more than one piece of surface (a
/// sweep out of it cut its own surface, as at an ear's base, or swept most of a neighbour's
/// piece out and left a sliver of it) where its pieces off the largest are not slivers its
/// cells held before any sweep, untouched by sweeps, or any cage holding a piece made only of vertices swept
/// into it (the inner thigh of a leg close beside, cut off from the cage's own). No sliver
/// allowance, unlike [`pieces_per_leaf`]: one such vertex would move with the wrong limb.
///
/// A vertex no collapse swept is still in its grid cell's part (the decimation moves no face
/// over it), so only the swept ones are located in the cages: a few hundred point tests
/// instead of the whole mesh's (at 400k vertices the whole mesh's doubled the rig's time).
fn leaves_cut_by_sweeps(
    set: &CageSet,
    grid: &Grid,
    parts: &Parts,
    surface: &SurfaceMesh,
    swept: &decimate::Swept,
) -> Vec<u32> {
    if swept.parts.is_empty() {
        return Vec::new();
    }
    let points = surface.mesh.welded_positions();
    let is_swept = |v: usize| swept.points.get(v).copied().unwrap_or(false);
    let swept_vertices: Vec<usize> = (0..points.len()).filter(|&v| is_swept(v)).collect();
    let (valid, index_of) = valid_leaf_cages(set);
    let swept_points: Vec<DVec3> = swept_vertices.iter().map(|&v| points[v]).collect();
    let containment = crate::scene::leaf_containment(&valid, &swept_points);
    // The cages holding each vertex of a touched cage: a swept one's by its containment,
    // another's by its cell.
    let mut held: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    for (&v, c) in swept_vertices.iter().zip(&containment) {
        for &k in c.inside.iter().chain(&c.on_surface) {
            let leaf = index_of[k] as u32;
            if swept.parts.contains(&leaf) {
                held.entry(leaf).or_default().push(v);
            }
        }
    }
    let by_cell: Vec<Option<u32>> = points.iter().map(|&p| parts.part_at(grid, p)).collect();
    for (v, label) in by_cell.iter().enumerate() {
        if is_swept(v) {
            continue;
        }
        if let Some(label) = label.filter(|l| swept.parts.contains(l)) {
            held.entry(label).or_default().push(v);
        }
    }
    let mut member = vec![false; points.len()];
    let mut seen = vec![false; points.len()];
    let mut cut_off = Vec::new();
    for (&leaf, vertices) in &held {
        for &v in vertices {
            member[v] = true;
        }
        let (mut pieces, mut swept_only) = (Vec::<Vec<usize>>::new(), false);
        for &start in vertices {
            if seen[start] {
                continue;
            }
            let mut piece = Vec::new();
            walk_piece(start, &member, &mut seen, &surface.neighbours, |v| {
                piece.push(v);
            });
            swept_only |= piece.iter().all(|&v| is_swept(v));
            pieces.push(piece);
        }
        for &v in vertices {
            member[v] = false;
            seen[v] = false;
        }
        // Off the largest piece, only slivers the part's cells already held (the rule the
        // respans keep, `decimate::keeps_its_pieces`): no swept point, none of the largest
        // piece by cell.
        let cut = swept.parts.contains(&leaf) && pieces.len() > 1 && {
            let largest = (0..pieces.len())
                .max_by(|&a, &b| pieces[a].len().cmp(&pieces[b].len()).then(b.cmp(&a)));
            let cell = decimate::in_largest_piece(Some(leaf), &by_cell, &surface.neighbours);
            pieces
                .iter()
                .enumerate()
                .filter(|(k, _)| Some(*k) != largest)
                .flat_map(|(_, piece)| piece)
                .any(|&v| is_swept(v) || cell.get(v) != Some(&Some(false)))
        };
        if cut || swept_only {
            cut_off.push(leaf);
        }
    }
    cut_off
}

/// [`surface_pieces_per_leaf`] with the mesh's surface adjacency already found.
fn pieces_per_leaf(scene: &Scene, neighbours: &[Vec<u32>]) -> Vec<usize> {
    let set = &scene.cages;
    let (valid, index_of) = valid_leaf_cages(set);
    let points = scene.mesh.welded_positions();
    let containment = crate::scene::leaf_containment(&valid, points);
    let mut pieces = vec![0; set.leaves.len()];
    let mut member = vec![false; points.len()];
    let mut seen = vec![false; points.len()];
    for (k, &leaf) in index_of.iter().enumerate() {
        member.iter_mut().for_each(|m| *m = false);
        seen.iter_mut().for_each(|s| *s = false);
        let mut held = 0;
        for (v, c) in containment.iter().enumerate() {
            if c.inside.contains(&k) || c.on_surface.contains(&k) {
                member[v] = true;
                held += 1;
            }
        }
        let sliver = SLIVER_VERTICES.max(held / 100);
        let mut count = 0;
        for start in 0..points.len() {
            if !member[start] || seen[start] {
                continue;
            }
            let mut size = 0;
            walk_piece(start, &member, &mut seen, neighbours, |_| size += 1);
            if size >= sliver {
                count += 1;
            }
        }
        pieces[leaf] = count;
    }
    pieces
}

/// The leaf cages of `set` that are valid cages, and the leaf index of each.
fn valid_leaf_cages(set: &CageSet) -> (Vec<crate::scene::LocalCage>, Vec<usize>) {
    set.leaves
        .iter()
        .enumerate()
        .filter_map(|(i, l)| {
            Some((
                crate::scene::LocalCage::new(&set.vertices, &l.faces).ok()?,
                i,
            ))
        })
        .unzip()
}

/// Visits the piece of surface through `start` among the `member` vertices (joined by
/// `neighbours`), each vertex once, marking them in `seen`.
fn walk_piece(
    start: usize,
    member: &[bool],
    seen: &mut [bool],
    neighbours: &[Vec<u32>],
    mut visit: impl FnMut(usize),
) {
    seen[start] = true;
    let mut stack = vec![start];
    while let Some(v) = stack.pop() {
        visit(v);
        for &n in neighbours.get(v).into_iter().flatten() {
            let n = n as usize;
            if member.get(n) == Some(&true) && !seen[n] {
                seen[n] = true;
                stack.push(n);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_retry_finding_more_legs_is_kept_only_where_it_keeps_the_head() {
        // The mirrored gorilla: one sided leg and a head; the retry four sided legs, no head.
        let rig = LegCounts {
            sided_legs: 1,
            unsided_legs: 0,
            sided_other_limbs: 2,
            reach: 0.2,
            on_two_legs: true,
            head: true,
            unpaired: true,
        };
        let headless = LegCounts {
            sided_legs: 4,
            sided_other_limbs: 2,
            head: false,
            on_two_legs: false,
            ..rig
        };
        assert!(!retry_is_better(&headless, &rig));
        // The same retry with its head is better, and so is a headless retry of a headless
        // rig.
        let headed = LegCounts {
            head: true,
            ..headless
        };
        assert!(retry_is_better(&headed, &rig));
        let rig_without_head = LegCounts { head: false, ..rig };
        assert!(retry_is_better(&headless, &rig_without_head));
    }

    #[test]
    fn the_parts_around_a_point_are_those_of_its_cell_and_the_26_beside_it() {
        let grid = Grid::around(DVec3::ZERO, DVec3::splat(1.0), 10, None, &[], None);
        // Every cell its own part, numbered by cell.
        let parts = Parts::of_roles(
            (0..grid.len() as u32).map(Some).collect(),
            vec![Role::Body { body: 0, slab: 0 }; grid.len()],
        );
        let point = DVec3::splat(0.5);
        let centre = grid.cell_at(point);
        let around = parts_around(&grid, &parts, point);
        assert_eq!(around.len(), 27);
        for label in &around {
            let offset = grid.cell_of(*label as usize) - centre;
            assert!(offset.abs().max_element() <= 1, "{offset}");
        }
        // Empty cells name no part.
        let mut sparse = parts.clone();
        for (i, l) in sparse.label.iter_mut().enumerate() {
            if grid.cell_of(i).z != centre.z {
                *l = None;
            }
        }
        assert_eq!(parts_around(&grid, &sparse, point).len(), 9);
    }

    #[test]
    fn feet_touching_at_the_mirror_plane_and_joined_only_through_the_body_are_two_limbs() {
        // The body holds the layers from z = 3.2 up, the limb the low side's cells below them
        // from x = 1 to the plane x = 2.
        let (grid, plane, parts) = test_mirror::limb_at_the_plane(5.0, 3.2);
        let apart_in = |polylines: &[&[DVec3]]| {
            let mesh = test_mirror::ribbons(polylines);
            limbs_apart_at_plane(&grid, &plane, &parts, &SurfaceMesh::new(&mesh))
        };
        let (left, right) = (1.8, 2.2);
        // Two feet, one either side of the plane, joined only across the body (Cheburashka's):
        // mirrored as one part across the plane, it held both and merged into the body.
        let feet = [
            DVec3::new(left, 0.35, 0.5),
            DVec3::new(left, 0.35, 4.4),
            DVec3::new(right, 0.35, 4.4),
            DVec3::new(right, 0.35, 0.5),
        ];
        assert_eq!(apart_in(&[&feet]), BTreeSet::from([1]));
        // Joined below the body too (one loop through the limb across the plane): it crosses.
        let mut ring = feet.to_vec();
        ring.push(feet[0]);
        assert!(apart_in(&[&ring]).is_empty());
        // Not joined at all: two pieces no merge makes one, so the limb is not merged away
        // and is mirrored as before (Homer's legs pressed together at detail 5).
        let apart = apart_in(&[&feet[..2], &feet[2..]]);
        assert!(apart.is_empty(), "{apart:?}");
    }
}

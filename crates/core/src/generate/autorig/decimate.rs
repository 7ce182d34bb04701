//! Fewer cage vertices: the grid-stepped surfaces between parts (and between a part and the
//! outside) are decimated by collapsing vertices into a neighbour (Garland and Heckbert's
//! half-edge collapse, without the quadrics), all cages at once, so a face two cages share
//! stays one face of both.
//!
//! A vertex may go when all its triangles lie on one surface between the same two labels (a
//! sheet), or when it lies on a curve where three surfaces meet and slides along that curve;
//! corners stay. A collapse is refused when it would change the surface's topology (the link
//! condition), fold or flatten a triangle, move the surface further than a limit from the
//! vertex, or sweep over another cage vertex (so no cage vertex ends up on or inside a face it
//! did not touch). A collapse that moves the outer surface never sweeps over a mesh vertex
//! either (no mesh vertex leaves the cages' union); one that moves only faces between two cages
//! may, where the caller allows it for both cages ([`Sweep`]): the mesh vertices it sweeps change
//! cage, and are reported, so that the caller can refuse it where that leaves a piece of one
//! limb's surface in another's cage. All positions stay on grid vertices, so the tests are
//! exact in integers.

use std::cell::RefCell;
use std::collections::{BTreeMap, BTreeSet};

use glam::{DVec3, I64Vec3, IVec3};

use super::symmetry::MirrorPlane;
use super::voxels::Grid;

mod buckets;
mod respan;

use buckets::{TriangleBuckets, bounds};

pub(super) use respan::in_largest_piece;

/// The labels on the two sides of a triangle (a part, or None outside).
type Sides = (Option<u32>, Option<u32>);

/// A triangle of the complex: corners counter-clockwise seen from outside `front`.
#[derive(Debug, Clone, Copy)]
struct Triangle {
    corners: [u32; 3],
    front: Option<u32>,
    back: Option<u32>,
    alive: bool,
}

impl Triangle {
    /// The two labels it separates, in a fixed order.
    fn sheet(&self) -> Sides {
        (self.front.min(self.back), self.front.max(self.back))
    }
}

/// Largest distance (in cells) a collapse may move the surface away from the removed vertex,
/// on the outer surface and between two cages.
const OUTER_ERROR: f64 = 0.75;
const INNER_ERROR: f64 = 1.5;

/// Rounds of respans: whole sheets, then vertex stars until a round changes nothing.
const RESPAN_ROUNDS: usize = 6;

/// Which collapses of faces between two cages may sweep over mesh vertices: those between two
/// parts neither of which is listed (parts where a sweep left a piece of surface cut off from
/// the rest of the cage's).
#[derive(Debug, Clone, Copy)]
pub(super) struct Sweep<'a> {
    pub refused: &'a BTreeSet<u32>,
    /// Parts where a sheet spanned again from its rim left a piece of surface cut off all the
    /// same (in the cages, where its check by cells did not see it): their sheets sweep no mesh
    /// vertex in the next round.
    pub respan_refused: &'a BTreeSet<u32>,
    /// The mesh's surface by part, for the respans' check that each part keeps its pieces;
    /// without it, a respan sweeps no mesh point.
    pub surface: Option<SurfaceByPart<'a>>,
}

/// The mesh's surface with each point's part by its grid cell.
#[derive(Debug, Clone, Copy)]
pub(super) struct SurfaceByPart<'a> {
    /// Per mesh point: the part of its cell.
    pub label: &'a [Option<u32>],
    /// Per mesh point: the points it shares an edge with.
    pub neighbours: &'a [Vec<u32>],
}

impl Sweep<'_> {
    /// Whether a collapse moving only triangles between these labels may sweep mesh vertices.
    fn allows(&self, sheets: impl IntoIterator<Item = Sides>) -> bool {
        sheets.into_iter().all(|(a, b)| match (a, b) {
            (Some(a), Some(b)) => !self.refused.contains(&a) && !self.refused.contains(&b),
            _ => false,
        })
    }
}

/// The decimated complex and the mesh vertices whose cage it changed.
pub(super) struct Decimated {
    /// (corners, front, back) over the input's vertex numbering.
    pub triangles: Vec<([u32; 3], Option<u32>, Option<u32>)>,
    pub swept: Swept,
}

/// What the collapses swept over.
#[derive(Debug, Clone, Default)]
pub(super) struct Swept {
    /// Per mesh point: whether a collapse swept over it (it may now lie in another cage).
    pub points: Vec<bool>,
    /// The parts on either side of the faces that swept them.
    pub parts: BTreeSet<u32>,
}

/// Mesh points (and their mirror images) in grid units, bucketed by grid cell, each with its
/// mesh point's index (None for an image).
type PointsByCell = BTreeMap<(i32, i32, i32), Vec<(DVec3, Option<u32>)>>;

/// What a collapse must not sweep over: cage vertices (the live ones, which collapses change,
/// are passed beside it), and mesh points unless allowed.
struct Obstacles<'a> {
    /// Cage vertices in grid units.
    position: &'a [I64Vec3],
    points: &'a PointsByCell,
    sweep: Sweep<'a>,
    /// The grid planes bounding a band of thin cells (`Grid::band`): its axis and the two
    /// planes' coordinates. Grid units map to positions affinely on either side of each, so a
    /// triangle that crosses neither is as flat, and sweeps what it sweeps, in both; one of a
    /// part in `Held::off_band` that would cross one is not made.
    band: Option<(usize, [i64; 2])>,
    off_band: &'a BTreeSet<u32>,
    /// Per part a respan's sweep touched: each mesh point's place in the part's pieces by cell
    /// (`respan::in_largest_piece` over `sweep.surface`'s labels, which do not change during a
    /// decimation), found once.
    pieces_by_cell: &'a RefCell<BTreeMap<u32, Vec<Option<bool>>>>,
    /// Scratch of `respan::keeps_its_pieces_changed`: each mesh point's piece, unvisited
    /// between calls (allocated once: one per call was most of a big mesh's decimation).
    piece_scratch: &'a RefCell<Vec<u32>>,
}

impl Obstacles<'_> {
    /// Whether a triangle (corners in grid units) between these labels would cross a plane of
    /// the band while one of them must keep off it.
    fn crosses_band(&self, corners: [I64Vec3; 3], (front, back): Sides) -> bool {
        let Some((axis, planes)) = self.band else {
            return false;
        };
        if ![front, back]
            .iter()
            .flatten()
            .any(|part| self.off_band.contains(part))
        {
            return false;
        }
        let along = corners.map(|c| c[axis]);
        let (low, high) = (
            along[0].min(along[1]).min(along[2]),
            along[0].max(along[1]).max(along[2]),
        );
        planes.iter().any(|&plane| low < plane && plane < high)
    }
}

/// The parts whose decimated cages did not validate, held back from the decimation.
#[derive(Debug, Clone, Copy)]
pub(super) struct Held<'a> {
    /// Parts whose faces stay grid-stepped.
    pub frozen: &'a BTreeSet<u32>,
    /// Parts whose triangles cross no plane of the grid's band of thin cells (a triangle
    /// across the band is flat in grid units, not in positions: the cage it bounds may then
    /// leave a mesh vertex out). Tried before `frozen`, which costs far more cage vertices.
    pub off_band: &'a BTreeSet<u32>,
}

/// The decimated complex: the triangles of `faces` (polygons over `vertices`, each with the
/// part it bounds and the part behind it), with fewer vertices. Returns the triangles as
/// (corners, front, back) over the same vertex numbering; vertices no triangle uses are gone
/// from every triangle. The faces of the parts in `held.frozen` stay as they are (grid-stepped):
/// the auto rig freezes a cage whose decimated surface did not validate (after keeping its
/// triangles off the band's planes, `held.off_band`). `sweep` says where a
/// collapse between two cages may move mesh points from one to the other. Sheets between two
/// cages that keep inner vertices after the collapses are spanned again from their rims
/// ([`respan`]).
pub(super) fn decimate(
    grid: &Grid,
    vertices: &[IVec3],
    faces: &[(Vec<u32>, Option<u32>, Option<u32>)],
    mesh_points: &[DVec3],
    held: Held<'_>,
    mirror: Option<&MirrorPlane>,
    sweep: Sweep<'_>,
) -> Decimated {
    decimate_with(
        grid,
        vertices,
        faces,
        mesh_points,
        held,
        mirror,
        sweep,
        Respan::Sheets,
    )
}

/// Whether [`decimate`] spans sheets again from their rims (`Collapses`: only collapses, a
/// test's control).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Respan {
    Sheets,
    #[cfg_attr(not(test), allow(dead_code))]
    Collapses,
}

/// [`decimate`], with or without the respans.
#[allow(clippy::too_many_arguments)] // decimate's seven and the control
fn decimate_with(
    grid: &Grid,
    vertices: &[IVec3],
    faces: &[(Vec<u32>, Option<u32>, Option<u32>)],
    mesh_points: &[DVec3],
    held: Held<'_>,
    mirror: Option<&MirrorPlane>,
    sweep: Sweep<'_>,
    respan: Respan,
) -> Decimated {
    let Held { frozen, off_band } = held;
    let mut triangles: Vec<Triangle> = Vec::new();
    for (corners, front, back) in faces {
        for k in 1..corners.len().saturating_sub(1) {
            triangles.push(Triangle {
                corners: [corners[0], corners[k], corners[k + 1]],
                front: *front,
                back: *back,
                alive: true,
            });
        }
    }
    let position: Vec<I64Vec3> = vertices.iter().map(|v| v.as_i64vec3()).collect();
    let band = grid
        .band
        .map(|b| (b.axis, [i64::from(b.first), i64::from(b.last)]));
    let mut star: Vec<Vec<usize>> = vec![Vec::new(); vertices.len()];
    for (t, tri) in triangles.iter().enumerate() {
        for &c in &tri.corners {
            star[c as usize].push(t);
        }
    }
    let mut at: BTreeMap<(i32, i32, i32), u32> = vertices
        .iter()
        .enumerate()
        .map(|(i, v)| ((v.x, v.y, v.z), i as u32))
        .collect();
    // Mesh points in grid units, bucketed by cell.
    let mut points: PointsByCell = BTreeMap::new();
    for (index, &p) in mesh_points.iter().enumerate() {
        let q = grid.units_of(p);
        // With a mirror, the images of the mesh points too: no collapse sweeps over either.
        let image = mirror.map(|m| {
            let mut r = q;
            r[m.axis] = f64::from(2 * m.half) - r[m.axis];
            r
        });
        let real = std::iter::once((q, Some(index as u32)));
        for (q, index) in real.chain(image.map(|r| (r, None))) {
            let c = q.floor().as_ivec3();
            points.entry((c.x, c.y, c.z)).or_default().push((q, index));
        }
    }
    let index_of = at.clone();
    // What a collapse must not break, besides the live vertices (`at`, which collapses change).
    let pieces_by_cell = RefCell::new(BTreeMap::new());
    let piece_scratch = RefCell::new(Vec::new());
    let obstacles = Obstacles {
        position: &position,
        points: &points,
        sweep,
        band,
        off_band,
        pieces_by_cell: &pieces_by_cell,
        piece_scratch: &piece_scratch,
    };
    // The image of each vertex (itself on the plane), where it is a vertex.
    let image_of = |v: u32| -> Option<u32> {
        let m = mirror?;
        let c = m.vertex(vertices[v as usize]);
        index_of.get(&(c.x, c.y, c.z)).copied()
    };
    // Along the mirror axis: below the plane (-1), on it (0) or above (1).
    let side_of = |v: u32| mirror.map_or(-1, |m| (vertices[v as usize][m.axis] - m.half).signum());
    let mut removed = vec![false; vertices.len()];
    let mut buckets = TriangleBuckets::new();
    // Each mesh point's part as the collapses and respans leave it (its cell's to begin with).
    let mut label_now: Vec<Option<u32>> = sweep
        .surface
        .map_or_else(Vec::new, |surface| surface.label.to_vec());
    let mut swept = Swept {
        points: vec![false; mesh_points.len()],
        parts: BTreeSet::new(),
    };
    // Collapses, then the sheets that kept inner vertices spanned again from their rim, then
    // collapses again (a rim vertex may go once the sheet inside it is flat).
    for pass in 0..2 {
        for _round in 0..8 {
            let mut changed = false;
            for v in 0..vertices.len() as u32 {
                if removed[v as usize] {
                    continue;
                }
                // Here, where no collapse waits on its image's to be kept or taken back.
                buckets.refresh(&triangles, &position);
                let touches_frozen = star[v as usize].iter().any(|&t| {
                    let t = &triangles[t];
                    t.alive
                        && [t.front, t.back]
                            .iter()
                            .flatten()
                            .any(|p| frozen.contains(p))
                });
                if touches_frozen {
                    continue;
                }
                // With a mirror, the low side and the plane lead; each collapse is made with its
                // image or not at all, and a vertex on the plane stays on it.
                if side_of(v) > 0 {
                    continue;
                }
                let Some(targets) = targets_of(v, &triangles, &star) else {
                    continue;
                };
                for u in targets {
                    if mirror.is_some() && (side_of(u) > 0 || (side_of(v) == 0 && side_of(u) != 0))
                    {
                        continue;
                    }
                    let Some((undo, mut over)) = try_collapse(
                        v,
                        u,
                        &mut triangles,
                        &mut star,
                        &at,
                        &obstacles,
                        &mut buckets,
                    ) else {
                        continue;
                    };
                    let p = vertices[v as usize];
                    at.remove(&(p.x, p.y, p.z));
                    let image = match (mirror, image_of(v), image_of(u)) {
                        (None, _, _) => Some(None),
                        (Some(_), Some(mv), _) if mv == v => Some(None),
                        (Some(_), Some(mv), Some(mu)) if !removed[mv as usize] => try_collapse(
                            mv,
                            mu,
                            &mut triangles,
                            &mut star,
                            &at,
                            &obstacles,
                            &mut buckets,
                        )
                        .map(|(_, image_over)| {
                            for (i, sheet) in image_over.points {
                                over.points.entry(i).or_insert(sheet);
                            }
                            over.parts.extend(image_over.parts);
                            Some(mv)
                        }),
                        _ => None,
                    };
                    let Some(image) = image else {
                        undo.apply(&mut triangles, &mut star);
                        at.insert((p.x, p.y, p.z), v);
                        continue;
                    };
                    over.record(&mut swept, &mut label_now);
                    removed[v as usize] = true;
                    if let Some(mv) = image {
                        removed[mv as usize] = true;
                        let q = vertices[mv as usize];
                        at.remove(&(q.x, q.y, q.z));
                    }
                    changed = true;
                    break;
                }
            }
            if !changed {
                break;
            }
        }
        if pass == 1 || respan == Respan::Collapses {
            break;
        }
        let mut changed = false;
        // Whole sheets first, then the stars of the vertices left inside them, a few rounds
        // (neighbouring stars share triangles: one round takes every other).
        for round in 0..RESPAN_ROUNDS {
            let sheets = if round == 0 {
                respan::sheets_with_inner_vertices(&triangles, &star, frozen)
            } else {
                respan::vertex_stars(&triangles, &star, frozen)
            };
            let mut changed_now = false;
            for sheet in &sheets {
                // With a mirror, a sheet below the plane leads and its image follows.
                if !sheet.alive(&triangles) || sheet.inner.iter().any(|&v| side_of(v) >= 0) {
                    continue;
                }
                let Some(new) = respan::respanned(sheet, &triangles, &star, &position) else {
                    continue;
                };
                let Some((undo, over)) = respan::try_respan(
                    sheet,
                    &new,
                    (&mut triangles, &mut star),
                    &at,
                    &obstacles,
                    &label_now,
                ) else {
                    continue;
                };
                let mut gone = sheet.inner.clone();
                // Kept for the mirror image's respan to undo (a copy of every label).
                let labels_before = mirror.is_some().then(|| label_now.clone());
                over.flip(&mut label_now);
                if let Some(labels_before) = labels_before {
                    let image_done = respan::image_sheet(sheet, &new, &sheets, image_of).and_then(
                        |(image_sheet, mut mapped)| {
                            let facing = respan::area_vector(mapped.iter().copied(), &position);
                            if facing.dot(image_sheet.area_vector(&triangles, &position)) < 0.0 {
                                for t in &mut mapped {
                                    t.swap(1, 2);
                                }
                            }
                            respan::try_respan(
                                image_sheet,
                                &mapped,
                                (&mut triangles, &mut star),
                                &at,
                                &obstacles,
                                &label_now,
                            )
                            .map(|(_, image_over)| (image_sheet, image_over))
                        },
                    );
                    let Some((image_sheet, image_over)) = image_done else {
                        label_now = labels_before;
                        undo.apply(&mut triangles, &mut star);
                        continue;
                    };
                    image_over.record(&mut swept, &mut label_now);
                    gone.extend(&image_sheet.inner);
                }
                over.mark(&mut swept);
                for v in gone {
                    removed[v as usize] = true;
                    let p = vertices[v as usize];
                    at.remove(&(p.x, p.y, p.z));
                }
                changed_now = true;
            }
            changed |= changed_now;
            if round > 0 && !changed_now {
                break;
            }
        }
        if !changed {
            break;
        }
    }
    let triangles = triangles
        .into_iter()
        .filter(|t| t.alive)
        .map(|t| (t.corners, t.front, t.back))
        .collect();
    Decimated { triangles, swept }
}

/// The neighbours `v` may collapse into, nearest first: any neighbour for a sheet vertex, the
/// two neighbours along the curve for a curve vertex (unless its curve is a short closed
/// loop, a joint's ring); None for a corner.
fn targets_of(v: u32, triangles: &[Triangle], star: &[Vec<usize>]) -> Option<Vec<u32>> {
    match neighbourhood(v, triangles, star) {
        Neighbourhood::Sheet(neighbours) => Some(neighbours),
        Neighbourhood::Curve(curve) => {
            (!on_short_loop(v, &curve, triangles, star)).then_some(curve)
        }
        Neighbourhood::Corner => None,
    }
}

/// Where a vertex of the decimated surface lies.
enum Neighbourhood {
    /// Inside one sheet: all its neighbours.
    Sheet(Vec<u32>),
    /// On a simple curve where sheets meet: its two neighbours along the curve.
    Curve(Vec<u32>),
    /// Where curves meet or end, or on no live triangle.
    Corner,
}

fn neighbourhood(v: u32, triangles: &[Triangle], star: &[Vec<usize>]) -> Neighbourhood {
    let alive: Vec<&Triangle> = star[v as usize]
        .iter()
        .map(|&t| &triangles[t])
        .filter(|t| t.alive)
        .collect();
    if alive.is_empty() {
        return Neighbourhood::Corner;
    }
    // Sheets of the triangles around each edge from v.
    let mut edge_sheets: BTreeMap<u32, BTreeSet<Sides>> = BTreeMap::new();
    for t in &alive {
        for &c in &t.corners {
            if c != v {
                edge_sheets.entry(c).or_default().insert(t.sheet());
            }
        }
    }
    let sheets: BTreeSet<_> = alive.iter().map(|t| t.sheet()).collect();
    if sheets.len() == 1 {
        return Neighbourhood::Sheet(edge_sheets.keys().copied().collect());
    }
    let curve: Vec<u32> = edge_sheets
        .iter()
        .filter(|(_, s)| s.len() > 1)
        .map(|(u, _)| *u)
        .collect();
    // A simple curve vertex: two curve edges, each with every sheet of v around it.
    if curve.len() == 2 && curve.iter().all(|u| edge_sheets[u] == sheets) {
        Neighbourhood::Curve(curve)
    } else {
        Neighbourhood::Corner
    }
}

/// The fewest vertices a closed curve where three surfaces meet keeps (a joint's ring): a
/// triangle is no cross-section of a limb (TOSCA's cat's wrist ring, one corner over the toes).
const FEWEST_LOOP_VERTICES: usize = 4;

/// Whether the curve through `v` (its two neighbours along it, `curve`) closes on itself
/// through simple curve vertices within [`FEWEST_LOOP_VERTICES`] vertices.
fn on_short_loop(v: u32, curve: &[u32], triangles: &[Triangle], star: &[Vec<usize>]) -> bool {
    let Some(&first) = curve.first() else {
        return false;
    };
    let (mut previous, mut current) = (v, first);
    for _ in 1..FEWEST_LOOP_VERTICES {
        if current == v {
            return true;
        }
        let Neighbourhood::Curve(next) = neighbourhood(current, triangles, star) else {
            return false;
        };
        let Some(next) = next.into_iter().find(|&u| u != previous) else {
            return false;
        };
        (previous, current) = (current, next);
    }
    current == v
}

/// What a collapse changed, to take it back.
struct Undo {
    v: u32,
    u: u32,
    dying: Vec<usize>,
    moving: Vec<usize>,
    star_v: Vec<usize>,
    star_u_len: usize,
}

impl Undo {
    /// Takes the collapse back.
    fn apply(self, triangles: &mut [Triangle], star: &mut [Vec<usize>]) {
        for &t in &self.dying {
            triangles[t].alive = true;
        }
        for &t in &self.moving {
            for c in triangles[t].corners.iter_mut() {
                if *c == self.u {
                    *c = self.v;
                }
            }
        }
        star[self.u as usize].truncate(self.star_u_len);
        star[self.v as usize] = self.star_v;
    }
}

/// The mesh points one collapse swept over (each with the labels either side of the first face
/// that swept it: it changes from one to the other), and the parts either side of its faces
/// there.
#[derive(Debug, Default)]
struct SweptOver {
    points: BTreeMap<u32, Sides>,
    parts: BTreeSet<u32>,
}

impl SweptOver {
    /// Marks the points swept and moves each to the other side of the face that swept it.
    fn record(self, swept: &mut Swept, label_now: &mut [Option<u32>]) {
        self.flip(label_now);
        self.mark(swept);
    }

    /// Moves each point to the other side of the face that swept it.
    fn flip(&self, label_now: &mut [Option<u32>]) {
        for (&i, &(a, b)) in &self.points {
            if let Some(label) = label_now.get_mut(i as usize) {
                *label = if *label == a {
                    b
                } else if *label == b {
                    a
                } else {
                    *label
                };
            }
        }
    }

    /// Marks the points swept.
    fn mark(self, swept: &mut Swept) {
        for i in self.points.into_keys() {
            if let Some(s) = swept.points.get_mut(i as usize) {
                *s = true;
            }
        }
        swept.parts.extend(self.parts);
    }
}

/// Collapses `v` into `u` if every check passes (see the module); returns how to take it back
/// and the mesh points it swept over (where `obstacles.sweep` allowed it).
fn try_collapse(
    v: u32,
    u: u32,
    triangles: &mut [Triangle],
    star: &mut [Vec<usize>],
    at: &BTreeMap<(i32, i32, i32), u32>,
    obstacles: &Obstacles<'_>,
    buckets: &mut TriangleBuckets,
) -> Option<(Undo, SweptOver)> {
    let Obstacles {
        position,
        points,
        sweep,
        ..
    } = *obstacles;
    let around_v: Vec<usize> = star[v as usize]
        .iter()
        .copied()
        .filter(|&t| triangles[t].alive)
        .collect();
    let (dying, moving): (Vec<usize>, Vec<usize>) = around_v
        .iter()
        .partition(|&&t| triangles[t].corners.contains(&u));
    if dying.is_empty() {
        return None;
    }
    // Link condition: the vertices next to both u and v are the third corners of the
    // triangles on edge uv.
    let neighbours = |x: u32, star: &[Vec<usize>]| -> BTreeSet<u32> {
        star[x as usize]
            .iter()
            .filter(|&&t| triangles[t].alive)
            .flat_map(|&t| triangles[t].corners)
            .filter(|&c| c != x)
            .collect()
    };
    let (nv, nu) = (neighbours(v, star), neighbours(u, star));
    let common: BTreeSet<u32> = nv.intersection(&nu).copied().collect();
    let opposite: BTreeSet<u32> = dying
        .iter()
        .flat_map(|&t| triangles[t].corners)
        .filter(|&c| c != u && c != v)
        .collect();
    if common != opposite {
        return None;
    }
    let (pv, pu) = (position[v as usize], position[u as usize]);
    // Only faces between two cages move, both of which let mesh points change cage.
    let may_sweep = sweep.allows(dying.iter().chain(&moving).map(|&t| triangles[t].sheet()));
    let mut over = SweptOver::default();
    let limit = if dying.iter().chain(&moving).all(|&t| {
        let s = triangles[t].sheet();
        s.0.is_none() || s.1.is_none()
    }) {
        OUTER_ERROR
    } else {
        INNER_ERROR
    };
    for &t in &moving {
        let old = triangles[t].corners;
        let new = old.map(|c| if c == v { u } else { c });
        let [a, b, c] = old.map(|i| position[i as usize]);
        let [na, nb, nc] = new.map(|i| position[i as usize]);
        let n_old = (b - a).cross(c - a);
        let n_new = (nb - na).cross(nc - na);
        if n_new == I64Vec3::ZERO || n_old.dot(n_new) <= 0 {
            return None;
        }
        if obstacles.crosses_band([na, nb, nc], triangles[t].sheet()) {
            return None;
        }
        // How far the surface moves from v: v's distance to the new triangle's plane.
        let distance = ((pv - na).dot(n_new) as f64).abs() / n_new.as_dvec3().length();
        if distance > limit {
            return None;
        }
        // The tetrahedron the triangle sweeps must hold no other vertex and no mesh point.
        let others: Vec<I64Vec3> = old
            .iter()
            .filter(|&&i| i != v)
            .map(|&i| position[i as usize])
            .collect();
        let tetra = [pv, pu, others[0], others[1]];
        if orient(tetra[0], tetra[1], tetra[2], tetra[3]) == 0 {
            continue; // flat: the new triangle covers what the old ones did
        }
        let lo = tetra.iter().fold(I64Vec3::MAX, |m, p| m.min(*p));
        let hi = tetra.iter().fold(I64Vec3::MIN, |m, p| m.max(*p));
        for x in lo.x..=hi.x {
            for y in lo.y..=hi.y {
                for z in lo.z..=hi.z {
                    let q = I64Vec3::new(x, y, z);
                    if tetra.contains(&q) {
                        continue;
                    }
                    if at.contains_key(&(x as i32, y as i32, z as i32)) && in_tetra(q, &tetra) {
                        return None;
                    }
                }
            }
        }
        let tetra_f = tetra.map(|p| p.as_dvec3());
        for x in lo.x..hi.x.max(lo.x + 1) {
            for y in lo.y..hi.y.max(lo.y + 1) {
                for z in lo.z..hi.z.max(lo.z + 1) {
                    let Some(list) = points.get(&(x as i32, y as i32, z as i32)) else {
                        continue;
                    };
                    for &(p, index) in list {
                        if !in_tetra_f(p, &tetra_f) {
                            continue;
                        }
                        match index {
                            Some(i) if may_sweep => {
                                let sheet = triangles[t].sheet();
                                over.points.entry(i).or_insert(sheet);
                                over.parts.extend(sheet.0.into_iter().chain(sheet.1));
                            }
                            // An image only guards the mirror's collapse, made with its own.
                            None if may_sweep => {}
                            _ => return None,
                        }
                    }
                }
            }
        }
    }
    // The new triangles must not meet any other edge, and no edge the new triangles leave
    // around u may be pinched for a part or a union of parts (a join cage).
    let new_triangles: Vec<[u32; 3]> = moving
        .iter()
        .map(|&t| triangles[t].corners.map(|c| if c == v { u } else { c }))
        .collect();
    if new_triangles
        .iter()
        .any(|&tri| meets_other_edges(tri, v, triangles, position, buckets))
    {
        return None;
    }
    let mut around: BTreeMap<u32, Vec<Sides>> = BTreeMap::new();
    // u's star and the moving triangles, each once.
    let mut seen: BTreeSet<usize> = BTreeSet::new();
    for &t in star[u as usize].iter().chain(&moving) {
        if !seen.insert(t) || !triangles[t].alive || dying.contains(&t) {
            continue;
        }
        let tri = &triangles[t];
        let corners = tri.corners.map(|c| if c == v { u } else { c });
        for &w in corners.iter().filter(|&&w| w != u) {
            around.entry(w).or_default().push((tri.front, tri.back));
        }
    }
    if around.values().any(|sides| pinched(sides)) {
        return None;
    }
    let undo = Undo {
        v,
        u,
        star_v: star[v as usize].clone(),
        star_u_len: star[u as usize].len(),
        dying,
        moving,
    };
    for &t in &undo.dying {
        triangles[t].alive = false;
    }
    for &t in &undo.moving {
        for c in triangles[t].corners.iter_mut() {
            if *c == v {
                *c = u;
            }
        }
        star[u as usize].push(t);
        buckets.moved(t);
    }
    star[v as usize].clear();
    Some((undo, over))
}

/// Whether the triangles around one edge (each by the labels on its two sides) leave some part,
/// or some union of the parts there, with other than 0 or 2 faces on the edge.
fn pinched(sides: &[Sides]) -> bool {
    let mut labels: Vec<u32> = sides.iter().flat_map(|(a, b)| [*a, *b]).flatten().collect();
    labels.sort_unstable();
    labels.dedup();
    if labels.len() > 6 {
        return true;
    }
    (1u32..(1 << labels.len())).any(|subset| {
        let inside = |l: Option<u32>| {
            l.and_then(|l| labels.iter().position(|&x| x == l))
                .is_some_and(|k| subset & (1 << k) != 0)
        };
        let faces = sides
            .iter()
            .filter(|(a, b)| inside(*a) != inside(*b))
            .count();
        faces != 0 && faces != 2
    })
}

/// Whether triangle `tri` (which will replace triangles around the removed vertex `gone`)
/// meets an edge of an alive triangle that shares no corner with it, or holds one of their
/// corners (exact).
fn meets_other_edges(
    tri: [u32; 3],
    gone: u32,
    triangles: &[Triangle],
    position: &[I64Vec3],
    buckets: &mut TriangleBuckets,
) -> bool {
    let corners = tri.map(|i| position[i as usize]);
    let (lo, hi) = bounds(tri, position);
    let near = buckets.near(lo, hi, triangles.len());
    near.iter()
        .map(|&t| &triangles[t])
        .filter(|t| t.alive)
        .any(|t| {
            if t.corners.contains(&gone) {
                return false; // goes with the collapse
            }
            let (tlo, thi) = bounds(t.corners, position);
            if tlo.cmpgt(hi).any() || thi.cmplt(lo).any() {
                return false;
            }
            (0..3).any(|k| {
                let (p, q) = (t.corners[k], t.corners[(k + 1) % 3]);
                if tri.contains(&p) || tri.contains(&q) {
                    return false;
                }
                segment_meets_triangle(position[p as usize], position[q as usize], corners)
            })
        })
}

/// Whether segment pq touches triangle abc (exact; coplanar segments count when they touch).
fn segment_meets_triangle(p: I64Vec3, q: I64Vec3, [a, b, c]: [I64Vec3; 3]) -> bool {
    let (sp, sq) = (orient(a, b, c, p).signum(), orient(a, b, c, q).signum());
    if sp == sq && sp != 0 {
        return false;
    }
    if sp == 0 && sq == 0 {
        // Coplanar: in the plane's best 2D projection.
        let n = (b - a).cross(c - a).abs();
        let drop = if n.x >= n.y && n.x >= n.z {
            0
        } else if n.y >= n.z {
            1
        } else {
            2
        };
        let flat = |v: I64Vec3| {
            let k = [v.x, v.y, v.z];
            match drop {
                0 => (k[1], k[2]),
                1 => (k[2], k[0]),
                _ => (k[0], k[1]),
            }
        };
        let (p2, q2, a2, b2, c2) = (flat(p), flat(q), flat(a), flat(b), flat(c));
        let cross = |o: (i64, i64), x: (i64, i64), y: (i64, i64)| {
            (x.0 - o.0) * (y.1 - o.1) - (x.1 - o.1) * (y.0 - o.0)
        };
        let inside = |x: (i64, i64)| {
            let (d1, d2, d3) = (cross(a2, b2, x), cross(b2, c2, x), cross(c2, a2, x));
            (d1 >= 0 && d2 >= 0 && d3 >= 0) || (d1 <= 0 && d2 <= 0 && d3 <= 0)
        };
        let crosses = |e0: (i64, i64), e1: (i64, i64)| {
            let (d1, d2) = (cross(e0, e1, p2).signum(), cross(e0, e1, q2).signum());
            let (d3, d4) = (cross(p2, q2, e0).signum(), cross(p2, q2, e1).signum());
            d1 * d2 < 0 && d3 * d4 < 0
        };
        return inside(p2) || inside(q2) || crosses(a2, b2) || crosses(b2, c2) || crosses(c2, a2);
    }
    // The line pq passes through the triangle when pq sees its edges all on one side.
    let s1 = orient(p, q, a, b).signum();
    let s2 = orient(p, q, b, c).signum();
    let s3 = orient(p, q, c, a).signum();
    (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0)
}

/// Six times the signed volume of tetrahedron (a, b, c, d).
fn orient(a: I64Vec3, b: I64Vec3, c: I64Vec3, d: I64Vec3) -> i64 {
    (b - a).cross(c - a).dot(d - a)
}

/// Whether `q` lies inside or on tetrahedron `t` (exact).
fn in_tetra(q: I64Vec3, t: &[I64Vec3; 4]) -> bool {
    let whole = orient(t[0], t[1], t[2], t[3]).signum();
    let faces = [
        orient(q, t[1], t[2], t[3]),
        orient(t[0], q, t[2], t[3]),
        orient(t[0], t[1], q, t[3]),
        orient(t[0], t[1], t[2], q),
    ];
    faces.iter().all(|&f| f.signum() * whole >= 0)
}

/// Whether `q` lies inside or within a hair of tetrahedron `t`.
fn in_tetra_f(q: DVec3, t: &[DVec3; 4]) -> bool {
    let orient = |a: DVec3, b: DVec3, c: DVec3, d: DVec3| (b - a).cross(c - a).dot(d - a);
    let whole = orient(t[0], t[1], t[2], t[3]);
    let tolerance = 1e-9 * whole.abs();
    [
        orient(q, t[1], t[2], t[3]),
        orient(t[0], q, t[2], t[3]),
        orient(t[0], t[1], q, t[3]),
        orient(t[0], t[1], t[2], q),
    ]
    .iter()
    .all(|&f| f * whole.signum() >= -tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::autorig::voxels::BandAt;

    fn p(x: i64, y: i64, z: i64) -> I64Vec3 {
        I64Vec3::new(x, y, z)
    }

    #[test]
    fn segments_through_touching_and_beside_a_triangle() {
        let tri = [p(0, 0, 0), p(4, 0, 0), p(0, 4, 0)];
        assert!(segment_meets_triangle(p(1, 1, -1), p(1, 1, 1), tri));
        assert!(
            segment_meets_triangle(p(1, 1, 0), p(1, 1, 3), tri),
            "touching counts"
        );
        assert!(!segment_meets_triangle(p(5, 5, -1), p(5, 5, 1), tri));
        assert!(!segment_meets_triangle(p(1, 1, 1), p(2, 1, 3), tri));
        // Coplanar: crossing an edge, and lying beside it.
        assert!(segment_meets_triangle(p(1, -1, 0), p(1, 1, 0), tri));
        assert!(!segment_meets_triangle(p(5, 0, 0), p(6, 1, 0), tri));
    }

    /// A lattice point's vertex index in [`stacked_boxes`] `width` cells wide.
    fn lattice_id(width: i32, x: i32, y: i32, z: i32) -> u32 {
        (x + (width + 1) * (y + 2 * z)) as u32
    }

    /// Two boxes `width` × 1 × 1 of unit cells stacked along z, part 0 below part 1, their
    /// faces split into unit squares of two triangles each: the triangles and each vertex's
    /// star (vertices numbered by [`lattice_id`]).
    fn stacked_boxes(width: i32) -> (Vec<Triangle>, Vec<Vec<usize>>) {
        let id = |x: i32, y: i32, z: i32| lattice_id(width, x, y, z);
        let part_of = |x: i32, y: i32, z: i32| {
            ((0..width).contains(&x) && y == 0 && (0..2).contains(&z)).then_some(z as u32)
        };
        let mut triangles = Vec::new();
        for x in 0..width {
            for z in 0..2 {
                let here = part_of(x, 0, z);
                for axis in 0..3 {
                    for side in [0, 1] {
                        let mut step = [0; 3];
                        step[axis] = 2 * side - 1;
                        let there = part_of(x + step[0], step[1], z + step[2]);
                        // Each face between the parts once, from below.
                        if there.is_some() && (axis != 2 || side == 0) {
                            continue;
                        }
                        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
                        let corner = |a: i32, b: i32| {
                            let mut c = [x, 0, z];
                            c[axis] += side;
                            c[u] += a;
                            c[w] += b;
                            id(c[0], c[1], c[2])
                        };
                        let (a, b, c, d) = (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1));
                        for corners in [[a, b, c], [a, c, d]] {
                            triangles.push(Triangle {
                                corners,
                                front: here,
                                back: there,
                                alive: true,
                            });
                        }
                    }
                }
            }
        }
        let mut star = vec![Vec::new(); ((width + 1) * 2 * 3) as usize];
        for (t, triangle) in triangles.iter().enumerate() {
            for &c in &triangle.corners {
                star[c as usize].push(t);
            }
        }
        (triangles, star)
    }

    #[test]
    fn a_ring_of_four_vertices_keeps_them_and_a_longer_one_slides() {
        // One cell wide, the face the boxes share is bounded by a curve of 4 vertices, where
        // both boxes' sides meet it: a collapse would leave a triangle for a joint's ring.
        let (triangles, star) = stacked_boxes(1);
        assert_eq!(targets_of(lattice_id(1, 0, 0, 1), &triangles, &star), None);
        // Two cells wide, its curve has 6: a vertex may slide along it.
        let (triangles, star) = stacked_boxes(2);
        let id = |x, y, z| lattice_id(2, x, y, z);
        let targets = targets_of(id(1, 0, 1), &triangles, &star);
        assert_eq!(targets, Some(vec![id(0, 0, 1), id(2, 0, 1)]));
    }

    #[test]
    fn an_edge_with_four_faces_of_one_part_is_pinched() {
        let a = Some(0);
        let b = Some(1);
        assert!(!pinched(&[(a, None), (a, None)]));
        assert!(!pinched(&[(a, None), (b, None), (a, b)]));
        assert!(pinched(&[(a, None), (a, None), (a, None), (a, None)]));
        // Two parts meeting along the edge only: their union is pinched.
        assert!(pinched(&[(a, None), (a, None), (b, None), (b, None)]));
    }

    #[test]
    fn a_flat_sheet_loses_its_inner_vertices_and_keeps_its_corners() {
        // A 3x3 grid of unit squares on z = 0 with the outside below: 16 vertices, of which the
        // 4 inner ones can go; the border is a curve only where sheets meet, so here it is the
        // border of one sheet and its vertices have neighbours off it.
        let mut vertices = Vec::new();
        for y in 0..4 {
            for x in 0..4 {
                vertices.push(IVec3::new(x, y, 0));
            }
        }
        let id = |x: u32, y: u32| x + 4 * y;
        let mut faces = Vec::new();
        for y in 0..3 {
            for x in 0..3 {
                faces.push((
                    vec![id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)],
                    Some(0),
                    None,
                ));
            }
        }
        let grid = Grid::around(DVec3::ZERO, DVec3::splat(3.0), 3, None, &[], None);
        let triangles = decimate(
            &grid,
            &vertices,
            &faces,
            &[],
            Held {
                frozen: &BTreeSet::new(),
                off_band: &BTreeSet::new(),
            },
            None,
            Sweep {
                refused: &BTreeSet::new(),
                respan_refused: &BTreeSet::new(),
                surface: None,
            },
        )
        .triangles;
        let used: BTreeSet<u32> = triangles.iter().flat_map(|(c, _, _)| *c).collect();
        assert!(used.len() < 16, "{used:?}");
        for corner in [id(0, 0), id(3, 0), id(0, 3), id(3, 3)] {
            assert!(used.contains(&corner));
        }
        assert_eq!(
            twice_area_facing_z(&triangles, &vertices),
            2 * 9,
            "the sheet still covers its area, facing +z"
        );
    }

    /// Twice the area the triangles cover, measured facing +z (a sheet on z = 0).
    fn twice_area_facing_z(
        triangles: &[([u32; 3], Option<u32>, Option<u32>)],
        vertices: &[IVec3],
    ) -> i64 {
        triangles
            .iter()
            .map(|(c, _, _)| {
                let [a, b, c] = c.map(|i| vertices[i as usize].as_i64vec3());
                (b - a).cross(c - a).z
            })
            .sum()
    }

    #[test]
    fn an_off_band_part_s_triangles_cross_no_plane_of_the_band() {
        // A flat sheet of unit squares across a band of two thin columns: decimated freely,
        // its triangles span the band (flat in grid units, not in positions); held off the
        // band, none crosses either of its planes, and the sheet still covers its area.
        let band = BandAt {
            axis: 0,
            plane: 2.0,
            width: 0.1,
        };
        let grid = Grid::around(DVec3::ZERO, DVec3::splat(4.0), 4, None, &[], Some(band));
        let planes = grid.band.map(|b| [b.first, b.last]).unwrap();
        let (from, to) = (planes[0] - 3, planes[1] + 3);
        let mut vertices = Vec::new();
        for y in 0..4 {
            for x in from..=to {
                vertices.push(IVec3::new(x, y, 0));
            }
        }
        let row = (to - from + 1) as u32;
        let id = |x: i32, y: u32| (x - from) as u32 + row * y;
        let mut faces = Vec::new();
        for y in 0..3 {
            for x in from..to {
                let quad = vec![id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)];
                faces.push((quad, Some(0), None));
            }
        }
        let run = |off_band: &BTreeSet<u32>| {
            decimate(
                &grid,
                &vertices,
                &faces,
                &[],
                Held {
                    frozen: &BTreeSet::new(),
                    off_band,
                },
                None,
                Sweep {
                    refused: &BTreeSet::new(),
                    respan_refused: &BTreeSet::new(),
                    surface: None,
                },
            )
            .triangles
        };
        let crossing = |triangles: &[([u32; 3], Option<u32>, Option<u32>)]| {
            triangles
                .iter()
                .filter(|(c, _, _)| {
                    let x = c.map(|i| vertices[i as usize].x);
                    let (low, high) = (x.iter().min().unwrap(), x.iter().max().unwrap());
                    planes.iter().any(|p| low < p && p < high)
                })
                .count()
        };
        assert!(crossing(&run(&BTreeSet::new())) > 0);
        let held = run(&BTreeSet::from([0]));
        assert_eq!(crossing(&held), 0);
        assert_eq!(
            twice_area_facing_z(&held, &vertices),
            2 * 3 * i64::from(to - from)
        );
    }

    /// A bump in the sheet between parts 0 and 1 over a mesh point: flattening it moves the
    /// point from part 1 to part 0, done and reported where both parts allow it, refused where
    /// either does not.
    #[test]
    fn a_bump_between_two_cages_sweeps_a_mesh_point_only_where_both_allow_it() {
        // A 4x4 sheet of unit squares on z = 0, its middle vertex raised to z = 1.
        let mut vertices = Vec::new();
        for y in 0..5 {
            for x in 0..5 {
                vertices.push(IVec3::new(x, y, i32::from(x == 2 && y == 2)));
            }
        }
        let id = |x: u32, y: u32| x + 5 * y;
        let apex = id(2, 2);
        let mut faces = Vec::new();
        for y in 0..4 {
            for x in 0..4 {
                // Fanned from the apex where a square has it, so both triangles touch it.
                let quad = [id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)];
                let first = quad.iter().position(|&c| c == apex).unwrap_or(0);
                let turned: Vec<u32> = (0..4).map(|k| quad[(first + k) % 4]).collect();
                faces.push((turned, Some(0), Some(1)));
            }
        }
        let grid = Grid::around(DVec3::ZERO, DVec3::splat(4.0), 4, None, &[], None);
        // Under the apex, in grid units (2, 2, 0.5).
        let point = grid.origin + DVec3::new(2.0, 2.0, 0.5) * grid.cell;
        let run = |refused: &BTreeSet<u32>| {
            decimate(
                &grid,
                &vertices,
                &faces,
                &[point],
                Held {
                    frozen: &BTreeSet::new(),
                    off_band: &BTreeSet::new(),
                },
                None,
                Sweep {
                    refused,
                    respan_refused: &BTreeSet::new(),
                    surface: None,
                },
            )
        };
        let apex_kept = |d: &Decimated| d.triangles.iter().any(|(c, _, _)| c.contains(&apex));
        let allowed = run(&BTreeSet::new());
        assert!(!apex_kept(&allowed), "the bump is flattened");
        assert_eq!(allowed.swept.points, vec![true]);
        assert_eq!(allowed.swept.parts, BTreeSet::from([0, 1]));
        for refused in [BTreeSet::from([0]), BTreeSet::from([1])] {
            let kept = run(&refused);
            assert!(apex_kept(&kept), "refused {refused:?}: the bump stays");
            assert_eq!(kept.swept.points, vec![false]);
            assert!(kept.swept.parts.is_empty());
        }
    }

    /// A block of cells cut in two by a staircase that climbs along x and y (part 0 below,
    /// part 1 above), as polycube faces over a unit grid, with a mesh point at each cell's
    /// centre (its part by cell, linked to the points of the six cells beside it).
    struct Staircase {
        grid: Grid,
        vertices: Vec<IVec3>,
        faces: Vec<(Vec<u32>, Option<u32>, Option<u32>)>,
        points: Vec<DVec3>,
        label: Vec<Option<u32>>,
        neighbours: Vec<Vec<u32>>,
    }

    impl Staircase {
        /// Decimated with both parts refusing collapse sweeps.
        fn decimated(&self, respan: Respan, surface: Option<SurfaceByPart<'_>>) -> Decimated {
            decimate_with(
                &self.grid,
                &self.vertices,
                &self.faces,
                &self.points,
                Held {
                    frozen: &BTreeSet::new(),
                    off_band: &BTreeSet::new(),
                },
                None,
                Sweep {
                    refused: &BTreeSet::from([0, 1]),
                    respan_refused: &BTreeSet::new(),
                    surface,
                },
                respan,
            )
        }
    }

    fn staircase() -> Staircase {
        use super::super::parts::{Parts, Role};
        use super::super::polycube;
        let grid = Grid::around(DVec3::ZERO, DVec3::splat(10.0), 10, None, &[], None);
        let mut label = vec![None; grid.len()];
        let inside = |c: IVec3| c.cmpge(IVec3::ONE).all() && c.cmplt(IVec3::splat(9)).all();
        let mut point_of = BTreeMap::new();
        let mut points = Vec::new();
        let mut point_label = Vec::new();
        for x in 1..9 {
            for y in 1..9 {
                for z in 1..9 {
                    let part = Some(u32::from(z >= 2 + (x + y) / 3));
                    let cell = IVec3::new(x, y, z);
                    label[grid.index(cell).unwrap()] = part;
                    point_of.insert((x, y, z), points.len() as u32);
                    points.push(grid.origin + (cell.as_dvec3() + 0.5) * grid.cell);
                    point_label.push(part);
                }
            }
        }
        let mut neighbours = vec![Vec::new(); points.len()];
        for (&(x, y, z), &i) in &point_of {
            for step in [
                IVec3::X,
                IVec3::Y,
                IVec3::Z,
                -IVec3::X,
                -IVec3::Y,
                -IVec3::Z,
            ] {
                let c = IVec3::new(x, y, z) + step;
                if inside(c) {
                    neighbours[i as usize].push(point_of[&(c.x, c.y, c.z)]);
                }
            }
        }
        let parts = Parts::of_roles(
            label,
            vec![
                Role::Body { body: 0, slab: 0 },
                Role::Body { body: 0, slab: 1 },
            ],
        );
        let (vertices, faces) =
            polycube::indexed_faces(&polycube::boundary_faces(&grid, &parts, None));
        Staircase {
            grid,
            vertices,
            faces,
            points,
            label: point_label,
            neighbours,
        }
    }

    /// The vertices of the faces between parts 0 and 1 that lie on no outer face.
    fn inside_the_sheet(triangles: &[([u32; 3], Option<u32>, Option<u32>)]) -> BTreeSet<u32> {
        let outer: BTreeSet<u32> = triangles
            .iter()
            .filter(|(_, f, b)| f.is_none() || b.is_none())
            .flat_map(|(c, _, _)| *c)
            .collect();
        triangles
            .iter()
            .filter(|(_, f, b)| f.is_some() && b.is_some())
            .flat_map(|(c, _, _)| *c)
            .filter(|v| !outer.contains(v))
            .collect()
    }

    /// Each part's triangles (turned to face out of it) close a surface: every edge is walked
    /// once each way.
    fn closed_per_part(triangles: &[([u32; 3], Option<u32>, Option<u32>)], part: u32) -> bool {
        let mut edges: BTreeMap<(u32, u32), usize> = BTreeMap::new();
        for &([a, b, c], front, back) in triangles {
            let corners = if front == Some(part) {
                [a, b, c]
            } else if back == Some(part) {
                [a, c, b]
            } else {
                continue;
            };
            for k in 0..3 {
                *edges.entry((corners[k], corners[(k + 1) % 3])).or_default() += 1;
            }
        }
        edges
            .iter()
            .all(|(&(p, q), &n)| n == 1 && edges.get(&(q, p)) == Some(&1))
    }

    /// Mesh points fill a block cut by a staircase, and the collapses may sweep none (both
    /// parts refused, as the rig refuses parts where a collapse cut a piece off): the
    /// collapses leave vertices inside the sheet between the parts. The sheet spanned again
    /// from its rim has none, each part's cage is still closed, and the points it swept keep
    /// each part's in one piece.
    #[test]
    fn a_staircase_between_two_cages_is_spanned_again_from_its_rim_without_inner_vertices() {
        let s = staircase();
        let run = |respan: Respan, surface: Option<SurfaceByPart<'_>>| s.decimated(respan, surface);
        let surface = SurfaceByPart {
            label: &s.label,
            neighbours: &s.neighbours,
        };
        let collapsed = run(Respan::Collapses, Some(surface)).triangles;
        assert!(
            !inside_the_sheet(&collapsed).is_empty(),
            "the collapses alone leave vertices inside the staircase (the control)"
        );
        let respanned = run(Respan::Sheets, Some(surface));
        assert_eq!(inside_the_sheet(&respanned.triangles), BTreeSet::new());
        for part in [0, 1] {
            assert!(closed_per_part(&collapsed, part), "part {part}, collapsed");
            assert!(
                closed_per_part(&respanned.triangles, part),
                "part {part}, respanned"
            );
        }
        let used = |t: &[([u32; 3], Option<u32>, Option<u32>)]| {
            t.iter()
                .flat_map(|(c, _, _)| *c)
                .collect::<BTreeSet<u32>>()
                .len()
        };
        assert!(used(&respanned.triangles) < used(&collapsed));
        // The points swept changed part; each part's points are still one piece.
        let swept: Vec<usize> = (0..s.points.len())
            .filter(|&i| respanned.swept.points[i])
            .collect();
        assert!(!swept.is_empty(), "a staircase's corners are cut");
        assert_eq!(respanned.swept.parts, BTreeSet::from([0, 1]));
        let mut label = s.label.clone();
        for &i in &swept {
            label[i] = label[i].map(|l| 1 - l);
        }
        for part in [0, 1] {
            assert_eq!(respan::pieces_of(Some(part), &label, &s.neighbours), 1);
        }
        // Without the surface to check pieces on, a respan sweeps no point: the staircase
        // stays, but for stars whose hole is filled again without passing over a point.
        let kept = run(Respan::Sheets, None);
        assert!(kept.swept.points.iter().all(|&p| !p));
        let inside_kept = inside_the_sheet(&kept.triangles);
        assert!(!inside_kept.is_empty());
        assert!(inside_kept.is_subset(&inside_the_sheet(&collapsed)));
    }

    /// The stars offered for respanning one vertex at a time are those of the vertices inside
    /// the sheet between the two parts, each with its centre as its one inner vertex and its
    /// link as its rim.
    #[test]
    fn the_vertex_stars_respanned_are_those_of_the_vertices_inside_a_sheet() {
        let s = staircase();
        let collapsed = s.decimated(Respan::Collapses, None).triangles;
        let triangles: Vec<Triangle> = collapsed
            .iter()
            .map(|&(corners, front, back)| Triangle {
                corners,
                front,
                back,
                alive: true,
            })
            .collect();
        let mut star = vec![Vec::new(); s.vertices.len()];
        for (t, tri) in triangles.iter().enumerate() {
            for &c in &tri.corners {
                star[c as usize].push(t);
            }
        }
        let stars = respan::vertex_stars(&triangles, &star, &BTreeSet::new());
        let centres: BTreeSet<u32> = stars.iter().flat_map(|s| s.inner.clone()).collect();
        assert!(!centres.is_empty());
        assert_eq!(centres, inside_the_sheet(&collapsed));
        for sheet in &stars {
            let v = sheet.inner[0];
            let link: BTreeSet<u32> = star[v as usize]
                .iter()
                .flat_map(|&t| triangles[t].corners)
                .filter(|&c| c != v)
                .collect();
            assert_eq!(sheet.rim.iter().copied().collect::<BTreeSet<u32>>(), link);
        }
        // Frozen parts offer none.
        assert!(respan::vertex_stars(&triangles, &star, &BTreeSet::from([1])).is_empty());
    }
}

//! Contacts: two leaf cages that share faces where the surface does not pass between them (two
//! paws side by side, a hand resting on a hip) are parted there. Shared, such a face's vertices
//! belong to both cages, so the control that owns them is the cages' common ancestor (often
//! `root`) and turning one limb leaves a patch of it pinned to the other: the cat's front paw,
//! turned 45° at the shoulder, stayed 8–10 units short of a rigid turn and folded. Parted, each
//! cage gets its own copy of the vertices there and each limb's control carries its side.
//!
//! A contact is one connected patch of the faces two cages share that no mesh edge crosses and
//! that lies outside the surface. Its vertices are copied per group of cages still joined at
//! them by other shared faces. A patch stays shared where
//! - its two cages stay joined at one of its vertices (its rim touches cages joined to both,
//!   as two thighs pressed together up to the crotch): the join cage of that vertex would
//!   hold the two faces at one place, which is not a valid cage;
//! - parting it would cut cages off the rig's largest connected set (an ear that is its own
//!   piece of surface follows what it touches);
//! - the rig is mirrored and the patch's mirror image stays shared (both sides alike).
//!
//! Each cage keeps its own faces, renumbered only: every cage is the same polyhedron as before,
//! and the parted faces become outer faces that touch (docs/math.md, *Cages: "Two leaf cages
//! may touch").

use std::collections::{BTreeMap, BTreeSet, HashMap};

use glam::{DVec3, IVec3};

use super::surface::SurfaceMesh;
use super::union_find::find;
use crate::geometry::{segment_meets_triangle, winding_number};
use crate::scene::{Adjacency, CageSet};

/// Cells of the patch triangles' hash a mesh edge may cover before it is tested against every
/// patch triangle instead.
const MAX_EDGE_CELLS: i64 = 64;

/// A connected patch of the faces two cages share.
struct Patch {
    cages: [usize; 2],
    /// Faces, as (index in the first cage, index in the second).
    faces: Vec<(usize, usize)>,
}

/// `set` with its contacts parted, and how many patches were; `None` where there is none.
/// With a mirror plane (axis, position), a patch is parted only where its mirror image is too
/// (a mirrored rig's two sides stay alike though the mesh is not quite symmetric).
pub(super) fn part_contacts(
    set: &CageSet,
    surface: &SurfaceMesh,
    mirror: Option<(usize, f64)>,
) -> Option<(CageSet, usize)> {
    let adjacency = set.adjacency();
    let patches = patches_of(set, &adjacency);
    if patches.is_empty() {
        return None;
    }
    let crossed = crossed_patches(set, &patches, surface);
    let points = surface.mesh.welded_positions();
    let triangles = surface.mesh.welded_triangles();
    let mut parted: Vec<bool> = patches
        .iter()
        .zip(&crossed)
        .map(|(patch, &crossed)| {
            !crossed && outside_surface(set, patch, points, triangles).unwrap_or(false)
        })
        .collect();
    if !parted.contains(&true) {
        return None;
    }
    let images = mirror.map(|plane| mirror_images(set, &patches, plane));
    // Each rule keeps a patch shared that the others may have parted; they run until none
    // changes anything (each only ever keeps one more, so this ends).
    let copies = loop {
        if !parted.contains(&true) {
            return None;
        }
        // A patch whose two cages stay joined at one of its vertices (by a shared face that
        // stays shared) stays shared.
        let groups = groups_at_vertices(set, &patches, &parted);
        let joined = patches.iter().enumerate().find(|(p, patch)| {
            parted[*p]
                && patch_vertices(set, patch).iter().any(|v| {
                    groups
                        .get(v)
                        .is_some_and(|g| g.get(&patch.cages[0]) == g.get(&patch.cages[1]))
                })
        });
        if let Some((p, _)) = joined {
            parted[p] = false;
            continue;
        }
        // A cage the parting would cut off from the rig's largest connected set of cages (an
        // eye or an ear that is its own piece of surface) keeps its contacts: it follows them.
        let lost = cut_off(set.leaves.len(), &patches, &parted);
        if !lost.is_empty() {
            for p in lost {
                parted[p] = false;
            }
            continue;
        }
        if let Some(images) = &images {
            let lone = (0..patches.len())
                .find(|&p| parted[p] && images[p].is_some_and(|image| !parted[image]));
            if let Some(p) = lone {
                parted[p] = false;
                continue;
            }
        }
        break groups;
    };
    let count = parted.iter().filter(|&&p| p).count();
    Some((renumbered(set, &copies), count))
}

/// The parted patches with a cage outside the largest set of cages still connected by shared
/// faces: every contact of a cut-off set is kept (an ear that is its own piece of surface
/// follows all it touches, as it did shared).
fn cut_off(cages: usize, patches: &[Patch], parted: &[bool]) -> Vec<usize> {
    let mut into: Vec<usize> = (0..cages).collect();
    for (patch, _) in patches.iter().zip(parted).filter(|&(_, &p)| !p) {
        let [a, b] = patch.cages;
        if a < cages && b < cages {
            let (x, y) = (find(&mut into, a), find(&mut into, b));
            into[x.max(y)] = x.min(y);
        }
    }
    let mut size = vec![0usize; cages];
    for c in 0..cages {
        size[find(&mut into, c)] += 1;
    }
    let Some(largest) = (0..cages).max_by_key(|&c| (size[c], std::cmp::Reverse(c))) else {
        return Vec::new();
    };
    (0..patches.len())
        .filter(|&p| {
            parted[p]
                && patches[p]
                    .cages
                    .iter()
                    .any(|&c| c < cages && find(&mut into, c) != largest)
        })
        .collect()
}

/// Per patch, the patch at its mirror image across `(axis, position)`, where there is one
/// (a patch on the plane is its own).
fn mirror_images(set: &CageSet, patches: &[Patch], (axis, at): (usize, f64)) -> Vec<Option<usize>> {
    let (lo, hi) = crate::cage::bounds_of(&set.vertices);
    let step = 1e-9 * (hi - lo).length().max(f64::MIN_POSITIVE);
    let key = |p: DVec3| (p / step).round().as_i64vec3().to_array();
    let keys = |mirrored: bool| -> Vec<Vec<[i64; 3]>> {
        patches
            .iter()
            .map(|patch| {
                let mut k: Vec<[i64; 3]> = patch_vertices(set, patch)
                    .into_iter()
                    .filter_map(|v| set.vertices.get(v as usize).copied())
                    .map(|mut p| {
                        if mirrored {
                            p[axis] = 2.0 * at - p[axis];
                        }
                        key(p)
                    })
                    .collect();
                k.sort_unstable();
                k
            })
            .collect()
    };
    let by_key: HashMap<Vec<[i64; 3]>, usize> = keys(false)
        .into_iter()
        .enumerate()
        .map(|(p, k)| (k, p))
        .collect();
    keys(true).iter().map(|k| by_key.get(k).copied()).collect()
}

/// The connected patches (faces joined by an edge) of the faces each pair of cages shares.
fn patches_of(set: &CageSet, adjacency: &[Adjacency]) -> Vec<Patch> {
    let mut patches = Vec::new();
    for pair in adjacency {
        let Some(first) = set.leaves.get(pair.first) else {
            continue;
        };
        let face = |k: usize| first.faces.get(pair.faces[k].0).map_or(&[][..], |f| &f[..]);
        let mut into: Vec<usize> = (0..pair.faces.len()).collect();
        let mut by_edge: HashMap<(u32, u32), usize> = HashMap::new();
        for k in 0..pair.faces.len() {
            let f = face(k);
            for (i, &a) in f.iter().enumerate() {
                let b = f[(i + 1) % f.len()];
                if let Some(&other) = by_edge.get(&(a.min(b), a.max(b))) {
                    let (x, y) = (find(&mut into, k), find(&mut into, other));
                    into[x] = y;
                } else {
                    by_edge.insert((a.min(b), a.max(b)), k);
                }
            }
        }
        let mut members: BTreeMap<usize, Vec<(usize, usize)>> = BTreeMap::new();
        for (k, &faces) in pair.faces.iter().enumerate() {
            members.entry(find(&mut into, k)).or_default().push(faces);
        }
        patches.extend(members.into_values().map(|faces| Patch {
            cages: [pair.first, pair.second],
            faces,
        }));
    }
    patches
}

/// The patch's polygons, as the first cage has them.
fn patch_polygons<'a>(set: &'a CageSet, patch: &'a Patch) -> impl Iterator<Item = &'a [u32]> {
    let first = set.leaves.get(patch.cages[0]);
    patch
        .faces
        .iter()
        .filter_map(move |&(f, _)| first?.faces.get(f).map(|f| &f[..]))
}

fn patch_vertices(set: &CageSet, patch: &Patch) -> BTreeSet<u32> {
    patch_polygons(set, patch).flatten().copied().collect()
}

/// The patch's polygons as triangles (fans), by position.
fn patch_triangles(set: &CageSet, patch: &Patch) -> Vec<[DVec3; 3]> {
    let at = |v: u32| set.vertices.get(v as usize).copied();
    patch_polygons(set, patch)
        .flat_map(|f| {
            (1..f.len().saturating_sub(1))
                .filter_map(move |i| Some([at(f[0])?, at(f[i])?, at(f[i + 1])?]))
        })
        .collect()
}

/// Per patch, whether a mesh edge (or a link between crossing components, which
/// [`SurfaceMesh`] counts as edges) passes through it or touches it.
fn crossed_patches(set: &CageSet, patches: &[Patch], surface: &SurfaceMesh) -> Vec<bool> {
    let triangles: Vec<(usize, [DVec3; 3])> = patches
        .iter()
        .enumerate()
        .flat_map(|(p, patch)| patch_triangles(set, patch).into_iter().map(move |t| (p, t)))
        .collect();
    let mut crossed = vec![false; patches.len()];
    if triangles.is_empty() {
        return crossed;
    }
    let bounds = |t: &[DVec3; 3]| (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
    let cell = triangles
        .iter()
        .map(|(_, t)| {
            let (lo, hi) = bounds(t);
            (hi - lo).max_element()
        })
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let key = |p: DVec3| (p / cell).floor().as_ivec3();
    let mut in_cell: HashMap<IVec3, Vec<usize>> = HashMap::new();
    for (i, (_, t)) in triangles.iter().enumerate() {
        let (lo, hi) = bounds(t);
        let (l, h) = (key(lo), key(hi));
        for z in l.z..=h.z {
            for y in l.y..=h.y {
                for x in l.x..=h.x {
                    in_cell.entry(IVec3::new(x, y, z)).or_default().push(i);
                }
            }
        }
    }
    let points = surface.mesh.welded_positions();
    let every: Vec<usize> = (0..triangles.len()).collect();
    let mut near: Vec<usize> = Vec::new();
    for (a, ends) in surface.neighbours.iter().enumerate() {
        let Some(&p) = points.get(a) else { continue };
        for &b in ends.iter().filter(|&&b| b as usize > a) {
            let Some(&q) = points.get(b as usize) else {
                continue;
            };
            let (l, h) = (key(p.min(q)), key(p.max(q)));
            let span = (h - l + IVec3::ONE).as_i64vec3();
            let candidates: &[usize] = if span.x * span.y * span.z > MAX_EDGE_CELLS {
                &every
            } else {
                near.clear();
                for z in l.z..=h.z {
                    for y in l.y..=h.y {
                        for x in l.x..=h.x {
                            if let Some(members) = in_cell.get(&IVec3::new(x, y, z)) {
                                near.extend(members);
                            }
                        }
                    }
                }
                &near
            };
            for &i in candidates {
                let (patch, t) = triangles[i];
                if !crossed[patch] && segment_meets_triangle(p, q, t) {
                    crossed[patch] = true;
                }
            }
        }
    }
    crossed
}

/// Whether the patch lies outside the surface: the mesh's generalised winding number
/// (Jacobson et al. 2013) at the centroid of its first triangle is below a half.
fn outside_surface(
    set: &CageSet,
    patch: &Patch,
    points: &[DVec3],
    triangles: &[[u32; 3]],
) -> Option<bool> {
    let [a, b, c] = *patch_triangles(set, patch).first()?;
    Some(winding_number(points, triangles, (a + b + c) / 3.0) < 0.5)
}

/// At each vertex of a parted patch, each cage using it mapped to its group: cages joined there
/// by a shared face that is not parted are one group.
fn groups_at_vertices(
    set: &CageSet,
    patches: &[Patch],
    parted: &[bool],
) -> BTreeMap<u32, BTreeMap<usize, usize>> {
    let touched: BTreeSet<u32> = patches
        .iter()
        .zip(parted)
        .filter(|&(_, &p)| p)
        .flat_map(|(patch, _)| patch_vertices(set, patch))
        .collect();
    let mut cages_at: BTreeMap<u32, BTreeSet<usize>> = BTreeMap::new();
    for (c, leaf) in set.leaves.iter().enumerate() {
        for &v in leaf.faces.iter().flatten() {
            if touched.contains(&v) {
                cages_at.entry(v).or_default().insert(c);
            }
        }
    }
    let mut joins_at: BTreeMap<u32, Vec<[usize; 2]>> = BTreeMap::new();
    for (patch, _) in patches.iter().zip(parted).filter(|&(_, &p)| !p) {
        for v in patch_vertices(set, patch) {
            if touched.contains(&v) {
                joins_at.entry(v).or_default().push(patch.cages);
            }
        }
    }
    cages_at
        .into_iter()
        .map(|(v, cages)| {
            let cages: Vec<usize> = cages.into_iter().collect();
            let index = |c: usize| cages.binary_search(&c).ok();
            let mut into: Vec<usize> = (0..cages.len()).collect();
            for [a, b] in joins_at.get(&v).into_iter().flatten() {
                if let (Some(a), Some(b)) = (index(*a), index(*b)) {
                    let (x, y) = (find(&mut into, a), find(&mut into, b));
                    into[x.max(y)] = x.min(y);
                }
            }
            let groups = (0..cages.len())
                .map(|k| (cages[k], find(&mut into, k)))
                .collect();
            (v, groups)
        })
        .collect()
}

/// `set` with each vertex copied for every group but the first of the cages using it.
fn renumbered(set: &CageSet, groups: &BTreeMap<u32, BTreeMap<usize, usize>>) -> CageSet {
    let mut out = set.clone();
    let mut copy_of: HashMap<(usize, u32), u32> = HashMap::new();
    for (&v, by_cage) in groups {
        let Some(&position) = set.vertices.get(v as usize) else {
            continue;
        };
        let first = by_cage.values().copied().min();
        let mut copies: BTreeMap<usize, u32> = BTreeMap::new();
        for (&cage, &group) in by_cage {
            if Some(group) == first {
                continue;
            }
            let copy = *copies.entry(group).or_insert_with(|| {
                out.vertices.push(position);
                (out.vertices.len() - 1) as u32
            });
            copy_of.insert((cage, v), copy);
        }
    }
    for (c, leaf) in out.leaves.iter_mut().enumerate() {
        for v in leaf.faces.iter_mut().flatten() {
            if let Some(&copy) = copy_of.get(&(c, *v)) {
                *v = copy;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage::shapes::cuboid;
    use crate::check::validate_scene;
    use crate::coords::CoordinateKind;
    use crate::generate::demo::box_mesh;
    use crate::mesh::Mesh;
    use crate::scene::{LeafCage, MeshSource, Scene, SceneSettings};

    /// Unit boxes at the given (x, z) cells (y from 0 to 1), sharing their faces (welded by
    /// position).
    fn boxes_at(cells: &[(i32, i32)]) -> CageSet {
        let mut vertices: Vec<DVec3> = Vec::new();
        let mut leaves = Vec::new();
        for (k, &(x, z)) in cells.iter().enumerate() {
            let lo = DVec3::new(f64::from(x), 0.0, f64::from(z));
            let cage = cuboid(lo, lo + DVec3::ONE);
            let index = |p: DVec3, vertices: &mut Vec<DVec3>| {
                let found = vertices.iter().position(|q| *q == p);
                found.unwrap_or_else(|| {
                    vertices.push(p);
                    vertices.len() - 1
                }) as u32
            };
            let faces = cage
                .polygons()
                .iter()
                .map(|f| {
                    f.vertices
                        .iter()
                        .map(|&v| index(cage.positions()[v as usize], &mut vertices))
                        .collect()
                })
                .collect();
            leaves.push(LeafCage {
                name: format!("box{k}"),
                kind: CoordinateKind::MeanValue,
                h: None,
                border_h: BTreeMap::new(),
                faces,
            });
        }
        CageSet {
            vertices,
            leaves,
            internals: Vec::new(),
        }
    }

    /// One mesh of the given boxes, as (x, z) ranges, 0.3 to 0.7 in y (separate components,
    /// one piece where they pass through each other).
    fn bars_mesh(bars: &[([f64; 2], [f64; 2])]) -> Mesh {
        let (mut points, mut triangles) = (Vec::new(), Vec::new());
        for &([x0, x1], [z0, z1]) in bars {
            let one = box_mesh(DVec3::new(x0, 0.3, z0), DVec3::new(x1, 0.7, z1), [2, 2, 2]);
            let base = points.len() as u32;
            points.extend_from_slice(one.welded_positions());
            triangles.extend(one.welded_triangles().iter().map(|t| t.map(|v| v + base)));
        }
        Mesh::new(points, triangles, None, None).unwrap()
    }

    fn parted(set: &CageSet, mesh: &Mesh, mirror: Option<(usize, f64)>) -> Option<CageSet> {
        part_contacts(set, &SurfaceMesh::new(mesh), mirror).map(|(apart, count)| {
            assert_eq!(count, 1);
            apart
        })
    }

    /// A body of three cells over two legs: the left leg's foot turns right and touches the
    /// right leg's foot (cages 5 and 6); a bar of surface down each leg, across the body, and
    /// along the left foot.
    fn two_legs_touching_at_the_feet() -> (CageSet, Mesh) {
        let set = boxes_at(&[
            (0, 2),
            (1, 2),
            (2, 2),
            (0, 1),
            (2, 1),
            (0, 0),
            (1, 0),
            (2, 0),
        ]);
        let mesh = bars_mesh(&[
            ([0.3, 2.7], [2.3, 2.7]),
            ([0.3, 0.7], [0.3, 2.5]),
            ([0.5, 1.7], [0.3, 0.7]),
            ([2.3, 2.7], [0.3, 2.5]),
        ]);
        (set, mesh)
    }

    #[test]
    fn two_feet_the_surface_does_not_pass_between_are_parted_and_stay_valid() {
        let (set, mesh) = two_legs_touching_at_the_feet();
        let apart = parted(&set, &mesh, None).expect("the feet are parted");
        let pairs = |s: &CageSet| -> Vec<(usize, usize)> {
            s.adjacency().iter().map(|a| (a.first, a.second)).collect()
        };
        let mut kept = pairs(&set);
        kept.retain(|&p| p != (6, 7));
        assert_eq!(
            pairs(&apart),
            kept,
            "only the feet's face is no longer shared"
        );
        // The feet's square's four corners are copied; every cage keeps its faces.
        assert_eq!(apart.vertices.len(), set.vertices.len() + 4);
        for (before, after) in set.leaves.iter().zip(&apart.leaves) {
            assert_eq!(before.faces.len(), after.faces.len());
            for (f, g) in before.faces.iter().zip(&after.faces) {
                let at = |s: &CageSet, v: &u32| s.vertices[*v as usize];
                assert!(f.iter().zip(g).all(|(u, v)| at(&set, u) == at(&apart, v)));
            }
        }
        let scene = Scene::new(MeshSource::Embedded, mesh, apart, SceneSettings::default());
        let report = validate_scene(&scene);
        assert!(report.is_valid(), "{:?}", report.errors);
    }

    #[test]
    fn a_face_the_surface_crosses_or_that_lies_inside_it_stays_shared() {
        let (set, _) = two_legs_touching_at_the_feet();
        // The left foot's bar reaches into the right foot.
        let across = bars_mesh(&[
            ([0.3, 2.7], [2.3, 2.7]),
            ([0.3, 0.7], [0.3, 2.5]),
            ([0.5, 2.5], [0.3, 0.7]),
            ([2.3, 2.7], [0.3, 2.5]),
        ]);
        assert!(parted(&set, &across, None).is_none());
        // A surface around every cage passes no edge through the face, which lies inside it.
        let around = bars_mesh(&[([-1.0, 4.0], [-1.0, 4.0])]);
        assert!(parted(&set, &around, None).is_none());
    }

    #[test]
    fn legs_touching_up_to_the_body_stay_shared() {
        // Two legs side by side under a body of two cells, a bar of surface down each leg: the
        // legs' face reaches the body, whose cells join both legs at its top corners.
        let set = boxes_at(&[(0, 1), (1, 1), (0, 0), (1, 0)]);
        let mesh = bars_mesh(&[
            ([0.3, 1.7], [1.3, 1.7]),
            ([0.3, 0.7], [0.3, 1.5]),
            ([1.3, 1.7], [0.3, 1.5]),
        ]);
        assert!(parted(&set, &mesh, None).is_none());
    }

    #[test]
    fn a_cage_the_parting_would_cut_off_keeps_its_contacts() {
        // The right leg's surface is its own piece (an eye in its socket): parted, it would
        // follow nothing.
        let (set, _) = two_legs_touching_at_the_feet();
        let lone_leg = bars_mesh(&[
            ([0.3, 1.7], [2.3, 2.7]),
            ([0.3, 0.7], [0.3, 2.5]),
            ([0.5, 1.7], [0.3, 0.7]),
            ([2.3, 2.7], [0.3, 1.7]),
            ([2.3, 2.7], [2.3, 2.7]),
        ]);
        assert!(parted(&set, &lone_leg, None).is_none());
    }

    #[test]
    fn a_mirrored_rig_parts_a_contact_only_where_its_image_parts_too() {
        let (set, mesh) = two_legs_touching_at_the_feet();
        // Across x = 1.5 the feet's face is the left foot's inner face, which the surface
        // crosses.
        assert!(parted(&set, &mesh, Some((0, 1.5))).is_none());
        // Across a plane that maps no patch onto another, the feet part.
        assert!(parted(&set, &mesh, Some((1, 0.5))).is_some());
    }
}

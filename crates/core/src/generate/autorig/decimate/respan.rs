//! Sheets between two cages spanned again from their rim. A grid staircase between two parts
//! often keeps vertices inside it after the collapses: a half-edge collapse cannot flatten a
//! step without folding a triangle on the way, the link condition refuses others, and in parts
//! where a collapse's sweep once cut a piece of surface off (`Sweep::refused`) no collapse may
//! move a mesh point. Every such vertex is a boundary vertex of both cages, with a join cage
//! of its own that every blended point pays for in the bind (the paper's eqs. 6-10).
//!
//! Here a sheet that is a disk loses its inner vertices at once: its rim is triangulated afresh,
//! by the triangulation of least area among those whose projection (along the sheet's normal,
//! else a grid axis it faces) triangulates the rim's projection, each triangle meeting no other
//! face (Barequet and Sharir's dynamic programme). It is kept under the collapses' checks and
//! two more:
//! - the surface moves at most [`RESPAN_ERROR`] from a removed vertex;
//! - no triangle faces back, and no new triangle or edge meets another face;
//! - no cage vertex lies between the old sheet and the new;
//! - mesh points between them change part only where the surface is given
//!   (`Sweep::surface`), neither part is in `Sweep::respan_refused`, and each part's mesh points
//!   stay in one piece but for the slivers its cells held (`keeps_its_pieces`; the rig's own
//!   check after the decimation, `leaves_cut_by_sweeps`, asks the same of every part a sweep
//!   touched);
//! - both parts still bound a volume.

use std::collections::{BTreeMap, BTreeSet};

use glam::{DVec2, DVec3, I64Vec3};

use super::{Obstacles, SweptOver, Triangle, segment_meets_triangle};

/// Largest distance (in cells) from a removed inner vertex to the sheet spanned again: a little
/// more than one collapse may move a sheet (`INNER_ERROR`), since here many vertices go at once
/// where a chain of collapses would have moved it as far.
const RESPAN_ERROR: f64 = 2.0;

/// Longest rim spanned again (the triangulation takes time cubic in its length).
const LONGEST_RIM: usize = 240;

/// One sheet: connected triangles between the same two parts.
#[derive(Debug, Clone)]
pub(super) struct Sheet {
    /// Its triangles' indices.
    triangles: Vec<usize>,
    /// The lower and the higher label.
    labels: (u32, u32),
    /// Vertices on no other sheet (all go).
    pub inner: Vec<u32>,
    /// The boundary loop, in the direction the triangles run, seen from outside `labels.0`.
    pub rim: Vec<u32>,
}

/// The triangle's corners counter-clockwise seen from outside the lower of its two labels.
fn facing_out_of_lower(t: &Triangle) -> [u32; 3] {
    let [a, b, c] = t.corners;
    if t.front <= t.back {
        [a, b, c]
    } else {
        [a, c, b]
    }
}

/// The sheets between two parts (neither `frozen`) that are disks with vertices inside, each
/// with its rim.
pub(super) fn sheets_with_inner_vertices(
    triangles: &[Triangle],
    star: &[Vec<usize>],
    frozen: &BTreeSet<u32>,
) -> Vec<Sheet> {
    let mut on_edge: BTreeMap<(u32, u32), Vec<usize>> = BTreeMap::new();
    for (t, tri) in triangles.iter().enumerate().filter(|(_, t)| t.alive) {
        for k in 0..3 {
            let (a, b) = (tri.corners[k], tri.corners[(k + 1) % 3]);
            on_edge.entry((a.min(b), a.max(b))).or_default().push(t);
        }
    }
    let mut seen = vec![false; triangles.len()];
    let mut sheets = Vec::new();
    for (first, tri) in triangles.iter().enumerate() {
        let (Some(lo), Some(hi)) = tri.sheet() else {
            continue;
        };
        if !tri.alive || seen[first] || frozen.contains(&lo) || frozen.contains(&hi) {
            continue;
        }
        let sides = tri.sheet();
        seen[first] = true;
        let mut members = vec![first];
        let mut next = 0;
        while let Some(&t) = members.get(next) {
            next += 1;
            for k in 0..3 {
                let (a, b) = (triangles[t].corners[k], triangles[t].corners[(k + 1) % 3]);
                for &u in on_edge.get(&(a.min(b), a.max(b))).into_iter().flatten() {
                    if !seen[u] && triangles[u].sheet() == sides {
                        seen[u] = true;
                        members.push(u);
                    }
                }
            }
        }
        if let Some(sheet) = as_disk(triangles, star, members, (lo, hi)) {
            sheets.push(sheet);
        }
    }
    sheets
}

/// The stars of the vertices inside one sheet between two parts (neither `frozen`), each as
/// a sheet of its own whose one inner vertex is the centre: a sheet that cannot be spanned
/// again whole (its rim, seen along any direction tried, crosses itself) may still lose its
/// vertices one by one, each star's hole triangulated afresh where a collapse (a fan from one
/// neighbour) folded.
pub(super) fn vertex_stars(
    triangles: &[Triangle],
    star: &[Vec<usize>],
    frozen: &BTreeSet<u32>,
) -> Vec<Sheet> {
    (0..star.len() as u32)
        .filter_map(|v| {
            let members: Vec<usize> = star[v as usize]
                .iter()
                .copied()
                .filter(|&t| triangles[t].alive)
                .collect();
            let &first = members.first()?;
            let (Some(lo), Some(hi)) = triangles[first].sheet() else {
                return None;
            };
            let one_sheet = members
                .iter()
                .all(|&t| triangles[t].sheet() == (Some(lo), Some(hi)));
            if !one_sheet || frozen.contains(&lo) || frozen.contains(&hi) {
                return None;
            }
            as_disk(triangles, star, members, (lo, hi)).filter(|s| s.inner == [v])
        })
        .collect()
}

/// The sheet of these triangles if it is a disk with vertices inside, its rim one loop, and
/// every vertex off the rim on this sheet only.
fn as_disk(
    triangles: &[Triangle],
    star: &[Vec<usize>],
    members: Vec<usize>,
    labels: (u32, u32),
) -> Option<Sheet> {
    let member: BTreeSet<usize> = members.iter().copied().collect();
    let mut directed: BTreeMap<(u32, u32), usize> = BTreeMap::new();
    for &t in &members {
        let [a, b, c] = facing_out_of_lower(&triangles[t]);
        for (p, q) in [(a, b), (b, c), (c, a)] {
            *directed.entry((p, q)).or_default() += 1;
        }
    }
    if directed.values().any(|&n| n > 1) {
        return None; // folded over itself
    }
    let mut next_on_rim: BTreeMap<u32, u32> = BTreeMap::new();
    for &(p, q) in directed.keys() {
        if !directed.contains_key(&(q, p)) && next_on_rim.insert(p, q).is_some() {
            return None; // the rim passes twice through p
        }
    }
    let &start = next_on_rim.keys().next()?;
    let mut rim = vec![start];
    let mut at = next_on_rim[&start];
    while at != start {
        if rim.len() > next_on_rim.len() {
            return None;
        }
        rim.push(at);
        at = *next_on_rim.get(&at)?;
    }
    if rim.len() != next_on_rim.len() || rim.len() < 3 {
        return None; // more than one loop: not a disk
    }
    let vertices: BTreeSet<u32> = directed.keys().map(|&(p, _)| p).collect();
    let edges = directed
        .keys()
        .filter(|&&(p, q)| p < q || !directed.contains_key(&(q, p)))
        .count();
    if vertices.len() + members.len() != edges + 1 {
        return None; // Euler: a disk has V - E + F = 1
    }
    let on_rim: BTreeSet<u32> = rim.iter().copied().collect();
    let inner: Vec<u32> = vertices.difference(&on_rim).copied().collect();
    let only_here = |v: &u32| {
        star[*v as usize]
            .iter()
            .all(|t| !triangles[*t].alive || member.contains(t))
    };
    if inner.is_empty() || !inner.iter().all(only_here) {
        return None;
    }
    Some(Sheet {
        triangles: members,
        labels,
        inner,
        rim,
    })
}

/// The least-area triangulation of the rim whose projection along `normal` triangulates the
/// rim's projection, each triangle facing along `normal`; None where the projection is not a
/// simple polygon turning counter-clockwise, or no such triangulation exists. `joined(i, j)`
/// says rim vertices i and j are already joined by an edge off the sheet (a diagonal there would
/// give that edge more than two faces). Triangles as rim indices.
fn least_area_triangulation(
    rim: &[I64Vec3],
    normal: DVec3,
    joined: &impl Fn(usize, usize) -> bool,
    free: &impl Fn([usize; 3]) -> bool,
) -> Option<Vec<[usize; 3]>> {
    let n = rim.len();
    if !(3..=LONGEST_RIM).contains(&n) || normal.length_squared() == 0.0 {
        return None;
    }
    let axis = normal.normalize();
    let across = axis.any_orthonormal_vector();
    let up = axis.cross(across);
    let flat: Vec<DVec2> = rim
        .iter()
        .map(|p| {
            let p = p.as_dvec3();
            DVec2::new(p.dot(across), p.dot(up))
        })
        .collect();
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let twice_area: f64 = (0..n).map(|i| flat[i].perp_dot(flat[(i + 1) % n])).sum();
    let scale = flat
        .iter()
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()))
        .max(1.0);
    let tolerance = 1e-9 * scale * scale;
    if twice_area <= tolerance {
        return None;
    }
    // Whether segments ab and cd meet (touching counts).
    let meet = |a: DVec2, b: DVec2, c: DVec2, d: DVec2| {
        let (d1, d2) = (cross(a, b, c), cross(a, b, d));
        let (d3, d4) = (cross(c, d, a), cross(c, d, b));
        let on = |o: DVec2, e: DVec2, p: DVec2, s: f64| {
            s.abs() <= tolerance
                && p.x >= o.x.min(e.x) - 1e-12 * scale
                && p.x <= o.x.max(e.x) + 1e-12 * scale
                && p.y >= o.y.min(e.y) - 1e-12 * scale
                && p.y <= o.y.max(e.y) + 1e-12 * scale
        };
        (d1 * d2 < 0.0 && d3 * d4 < 0.0)
            || on(a, b, c, d1)
            || on(a, b, d, d2)
            || on(c, d, a, d3)
            || on(c, d, b, d4)
    };
    // A simple polygon: no two edges meet but neighbours at their shared corner.
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            if meet(flat[i], flat[(i + 1) % n], flat[j], flat[(j + 1) % n]) {
                return None;
            }
        }
    }
    // Diagonal i-j (i < j) inside the polygon: it leaves i into the polygon's inside, meets
    // no edge away from its ends, and joins no two vertices joined elsewhere.
    let inside_cone = |i: usize, j: usize| {
        let (prev, here, next) = (flat[(i + n - 1) % n], flat[i], flat[(i + 1) % n]);
        let to = flat[j];
        if cross(prev, here, next) >= 0.0 {
            cross(here, next, to) > tolerance && cross(prev, here, to) > tolerance
        } else {
            !(cross(here, next, to) <= tolerance && cross(prev, here, to) <= tolerance)
        }
    };
    let mut diagonal = vec![false; n * n];
    for i in 0..n {
        diagonal[i * n + (i + 1) % n] = true;
        diagonal[((i + 1) % n) * n + i] = true;
    }
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let ok = inside_cone(i, j)
                && inside_cone(j, i)
                && !joined(i, j)
                && (0..n).all(|k| {
                    let l = (k + 1) % n;
                    k == i
                        || k == j
                        || l == i
                        || l == j
                        || !meet(flat[i], flat[j], flat[k], flat[l])
                });
            diagonal[i * n + j] = ok;
            diagonal[j * n + i] = ok;
        }
    }
    // cost[i][j]: least area of a triangulation of rim[i..=j] closed by the diagonal ij.
    let mut cost = vec![f64::INFINITY; n * n];
    let mut best = vec![usize::MAX; n * n];
    for i in 0..n - 1 {
        cost[i * n + i + 1] = 0.0;
    }
    for span in 2..n {
        for i in 0..n - span {
            let j = i + span;
            if !diagonal[i * n + j] {
                continue;
            }
            for k in i + 1..j {
                let sub = cost[i * n + k] + cost[k * n + j];
                if !sub.is_finite() {
                    continue;
                }
                let facing = (rim[k] - rim[i]).cross(rim[j] - rim[i]);
                let along = facing.as_dvec3().dot(normal);
                if facing == I64Vec3::ZERO || along <= 0.0 {
                    continue;
                }
                let total = sub + 0.5 * facing.as_dvec3().length();
                if total < cost[i * n + j] && free([i, k, j]) {
                    cost[i * n + j] = total;
                    best[i * n + j] = k;
                }
            }
        }
    }
    if !cost[n - 1].is_finite() {
        return None;
    }
    let mut out = Vec::with_capacity(n - 2);
    let mut todo = vec![(0, n - 1)];
    while let Some((i, j)) = todo.pop() {
        if j <= i + 1 {
            continue;
        }
        let k = best[i * n + j];
        out.push([i, k, j]);
        todo.push((i, k));
        todo.push((k, j));
    }
    Some(out)
}

/// The sheet spanned again from its rim (triangles over the complex's vertex numbering, facing
/// out of the lower label), or None where its rim does not allow it.
pub(super) fn respanned(
    sheet: &Sheet,
    triangles: &[Triangle],
    star: &[Vec<usize>],
    position: &[I64Vec3],
) -> Option<Vec<[u32; 3]>> {
    let normal = sheet.area_vector(triangles, position);
    let member: BTreeSet<usize> = sheet.triangles.iter().copied().collect();
    let rim: Vec<I64Vec3> = sheet.rim.iter().map(|&v| position[v as usize]).collect();
    let joined = |i: usize, j: usize| {
        let (a, b) = (sheet.rim[i], sheet.rim[j]);
        star[a as usize].iter().any(|&t| {
            !member.contains(&t) && triangles[t].alive && triangles[t].corners.contains(&b)
        })
    };
    // The faces off the sheet near it, and whether a triangle over rim vertices meets one.
    let bounds = |c: [I64Vec3; 3]| (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]));
    let (low, high) = rim.iter().fold((I64Vec3::MAX, I64Vec3::MIN), |(l, h), p| {
        (l.min(*p), h.max(*p))
    });
    let nearby: Vec<usize> = (0..triangles.len())
        .filter(|&t| {
            let (l, h) = bounds(triangles[t].corners.map(|i| position[i as usize]));
            triangles[t].alive
                && !member.contains(&t)
                && !(l.cmpgt(high).any() || h.cmplt(low).any())
        })
        .collect();
    let free = |[i, k, j]: [usize; 3]| {
        let t = [sheet.rim[i], sheet.rim[k], sheet.rim[j]];
        let rim_edge = |a: usize, b: usize| a.abs_diff(b) == 1 || a.abs_diff(b) == rim.len() - 1;
        let diagonals: Vec<(u32, u32)> = [(i, k), (k, j), (i, j)]
            .into_iter()
            .filter(|&(a, b)| !rim_edge(a, b))
            .map(|(a, b)| (sheet.rim[a], sheet.rim[b]))
            .collect();
        !nearby
            .iter()
            .any(|&o| meets(t, &diagonals, &triangles[o].corners, position))
    };
    // Along the sheet's normal, else along the grid axes it faces (a staircase's rim may fold
    // over itself seen along the one and not the other): the least area found.
    let axes = [DVec3::X, DVec3::Y, DVec3::Z]
        .map(|axis| axis * normal.dot(axis).signum())
        .into_iter()
        .filter(|axis| axis.dot(normal) > 0.0);
    let area = |t: &Vec<[usize; 3]>| -> f64 {
        t.iter()
            .map(|&[i, k, j]| (rim[k] - rim[i]).cross(rim[j] - rim[i]).as_dvec3().length())
            .sum()
    };
    let spanned = std::iter::once(normal)
        .chain(axes)
        .filter_map(|along| least_area_triangulation(&rim, along, &joined, &free))
        .min_by(|a, b| area(a).total_cmp(&area(b)))?;
    Some(spanned.iter().map(|t| t.map(|k| sheet.rim[k])).collect())
}

/// Twice the area vector of these triangles (corners over the complex's numbering).
pub(super) fn area_vector(
    corners: impl IntoIterator<Item = [u32; 3]>,
    position: &[I64Vec3],
) -> DVec3 {
    corners
        .into_iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| position[i as usize]);
            (b - a).cross(c - a).as_dvec3()
        })
        .sum()
}

impl Sheet {
    /// Twice its area vector, facing out of its lower label.
    pub(super) fn area_vector(&self, triangles: &[Triangle], position: &[I64Vec3]) -> DVec3 {
        area_vector(
            self.triangles
                .iter()
                .map(|&t| facing_out_of_lower(&triangles[t])),
            position,
        )
    }

    /// Whether its triangles are all still there.
    pub(super) fn alive(&self, triangles: &[Triangle]) -> bool {
        self.triangles.iter().all(|&t| triangles[t].alive)
    }
}

/// Whether new triangle `t` (with these new edges, `diagonals`) meets triangle `other` of the
/// complex: an edge of `other` through `t`, or a new edge through `other` (each where the two
/// share no corner).
fn meets(t: [u32; 3], diagonals: &[(u32, u32)], other: &[u32; 3], position: &[I64Vec3]) -> bool {
    let at = |i: u32| position[i as usize];
    let (c, oc) = (t.map(at), other.map(at));
    let (low, high) = (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]));
    let (olow, ohigh) = (oc[0].min(oc[1]).min(oc[2]), oc[0].max(oc[1]).max(oc[2]));
    if olow.cmpgt(high).any() || ohigh.cmplt(low).any() {
        return false;
    }
    (0..3).any(|k| {
        let (p, q) = (other[k], other[(k + 1) % 3]);
        !t.contains(&p) && !t.contains(&q) && segment_meets_triangle(at(p), at(q), c)
    }) || diagonals.iter().any(|&(p, q)| {
        !other.contains(&p) && !other.contains(&q) && segment_meets_triangle(at(p), at(q), oc)
    })
}

/// What a respan changed, to take it back.
pub(super) struct RespanUndo {
    old: Vec<usize>,
    first_new: usize,
    rim: Vec<u32>,
}

impl RespanUndo {
    /// Takes the respan back.
    pub(super) fn apply(self, triangles: &mut Vec<Triangle>, star: &mut [Vec<usize>]) {
        for &t in &self.old {
            triangles[t].alive = true;
        }
        triangles.truncate(self.first_new);
        for &v in &self.rim {
            star[v as usize].retain(|&t| t < self.first_new);
        }
    }
}

/// Replaces the sheet's triangles by `new` (over the complex's numbering, facing out of the
/// lower label) if every check passes (see the module); returns how to take it back and the
/// mesh points it swept over (where `obstacles.sweep` allowed it).
pub(super) fn try_respan(
    sheet: &Sheet,
    new: &[[u32; 3]],
    (triangles, star): (&mut Vec<Triangle>, &mut [Vec<usize>]),
    at: &BTreeMap<(i32, i32, i32), u32>,
    obstacles: &Obstacles<'_>,
    label_now: &[Option<u32>],
) -> Option<(RespanUndo, SweptOver)> {
    let Obstacles {
        position,
        points,
        sweep,
        ..
    } = *obstacles;
    let (lo, hi) = sheet.labels;
    let corners_of = |t: &[u32; 3]| t.map(|i| position[i as usize]);
    // Off the band's planes, where either part must be.
    let labels = (Some(lo), Some(hi));
    if new
        .iter()
        .any(|t| obstacles.crosses_band(corners_of(t), labels))
    {
        return None;
    }
    // Close to every removed vertex.
    let far = sheet.inner.iter().any(|&v| {
        let p = position[v as usize].as_dvec3();
        new.iter()
            .map(|t| distance_to_triangle(p, corners_of(t).map(|c| c.as_dvec3())))
            .fold(f64::INFINITY, f64::min)
            > RESPAN_ERROR
    });
    if far {
        return None;
    }
    // No new triangle meets another face: another triangle's edge through a new triangle, or
    // a new diagonal through another triangle (sharing no corner with it).
    let member: BTreeSet<usize> = sheet.triangles.iter().copied().collect();
    let on_rim: BTreeSet<(u32, u32)> = (0..sheet.rim.len())
        .map(|k| {
            let (a, b) = (sheet.rim[k], sheet.rim[(k + 1) % sheet.rim.len()]);
            (a.min(b), a.max(b))
        })
        .collect();
    for t in new {
        let diagonals: Vec<(u32, u32)> = (0..3)
            .map(|k| (t[k], t[(k + 1) % 3]))
            .filter(|&(p, q)| !on_rim.contains(&(p.min(q), p.max(q))))
            .collect();
        let meets_one = triangles.iter().enumerate().any(|(o, other)| {
            other.alive && !member.contains(&o) && meets(*t, &diagonals, &other.corners, position)
        });
        if meets_one {
            return None;
        }
    }
    // Neither part's cage flattens: each still bounds a volume (a small part whose other
    // faces span the same rim would be left as two faces back to back).
    for (part, sign) in [(lo, 1), (hi, -1)] {
        let volume = |c: [I64Vec3; 3]| c[0].dot(c[1].cross(c[2]));
        let kept: i64 = triangles
            .iter()
            .enumerate()
            .filter(|(o, t)| t.alive && !member.contains(o))
            .map(|(_, t)| {
                let v = volume(corners_of(&t.corners));
                if t.front == Some(part) {
                    v
                } else if t.back == Some(part) {
                    -v
                } else {
                    0
                }
            })
            .sum();
        let spanned: i64 = new.iter().map(|t| sign * volume(corners_of(t))).sum();
        if kept + spanned <= 0 {
            return None;
        }
    }
    // Between the old sheet and the new: no cage vertex, and mesh points only where both parts
    // let them change cage. The old triangles and the new ones turned over close a surface;
    // its winding number is not zero between them.
    let mut closed: Vec<[DVec3; 3]> = sheet
        .triangles
        .iter()
        .map(|&t| corners_of(&facing_out_of_lower(&triangles[t])).map(|c| c.as_dvec3()))
        .collect();
    closed.extend(new.iter().map(|t| {
        let [a, b, c] = corners_of(t).map(|c| c.as_dvec3());
        [a, c, b]
    }));
    let between = |q: DVec3| winding_number(q, &closed).abs() > 0.25;
    let own: BTreeSet<u32> = sheet.rim.iter().chain(&sheet.inner).copied().collect();
    let (low, high) = sheet
        .rim
        .iter()
        .chain(&sheet.inner)
        .map(|&v| position[v as usize])
        .fold((I64Vec3::MAX, I64Vec3::MIN), |(l, h), p| {
            (l.min(p), h.max(p))
        });
    for x in low.x..=high.x {
        for y in low.y..=high.y {
            for z in low.z..=high.z {
                if let Some(v) = at.get(&(x as i32, y as i32, z as i32))
                    && !own.contains(v)
                    && between(I64Vec3::new(x, y, z).as_dvec3())
                {
                    return None;
                }
            }
        }
    }
    let may_sweep = sweep.surface.is_some()
        && !sweep.respan_refused.contains(&lo)
        && !sweep.respan_refused.contains(&hi);
    let mut over = SweptOver::default();
    for x in low.x..high.x.max(low.x + 1) {
        for y in low.y..high.y.max(low.y + 1) {
            for z in low.z..high.z.max(low.z + 1) {
                let Some(list) = points.get(&(x as i32, y as i32, z as i32)) else {
                    continue;
                };
                for &(p, index) in list {
                    if !between(p) {
                        continue;
                    }
                    match index {
                        Some(i) if may_sweep => {
                            over.points.insert(i, (Some(lo), Some(hi)));
                            over.parts.extend([lo, hi]);
                        }
                        None if may_sweep => {}
                        _ => return None,
                    }
                }
            }
        }
    }
    // Each part keeps its surface in one piece (the points swept change side), as the rig's
    // check after the decimation asks of every part a sweep touched.
    if let Some(surface) = sweep.surface
        && !over.points.is_empty()
    {
        // The labels after the sweep, as the changes to `label_now` (a copy of every label
        // per attempt was most of a big mesh's decimation).
        let mut changed = BTreeMap::new();
        for &i in over.points.keys() {
            let label = match *label_now.get(i as usize)? {
                l if l == Some(lo) => Some(hi),
                l if l == Some(hi) => Some(lo),
                _ => return None, // a third part's point between the two sheets
            };
            changed.insert(i, label);
        }
        let mut pieces_by_cell = obstacles.pieces_by_cell.borrow_mut();
        for part in [lo, hi] {
            let by_cell = pieces_by_cell
                .entry(part)
                .or_insert_with(|| in_largest_piece(Some(part), surface.label, surface.neighbours));
            let scratch = &mut obstacles.piece_scratch.borrow_mut();
            if !keeps_its_pieces_changed(
                part,
                (label_now, &changed),
                by_cell,
                surface.neighbours,
                scratch,
            ) {
                return None;
            }
        }
    }
    let undo = RespanUndo {
        old: sheet.triangles.clone(),
        first_new: triangles.len(),
        rim: sheet.rim.clone(),
    };
    for &t in &sheet.triangles {
        triangles[t].alive = false;
    }
    for t in new {
        let index = triangles.len();
        triangles.push(Triangle {
            corners: *t,
            front: Some(lo),
            back: Some(hi),
            alive: true,
        });
        for &c in t {
            star[c as usize].push(index);
        }
    }
    Some((undo, over))
}

/// How many pieces (connected by the surface's edges) the points labelled `part` make.
#[cfg(test)]
pub(super) fn pieces_of(
    part: Option<u32>,
    label: &[Option<u32>],
    neighbours: &[Vec<u32>],
) -> usize {
    piece_ids(part, label, neighbours).1
}

/// Each point's piece of `part` (None off it; connected by the surface's edges), and how many.
fn piece_ids(
    part: Option<u32>,
    label: &[Option<u32>],
    neighbours: &[Vec<u32>],
) -> (Vec<Option<u32>>, usize) {
    let mut piece: Vec<Option<u32>> = vec![None; label.len()];
    let mut pieces = 0;
    let mut todo = Vec::new();
    for start in 0..label.len() {
        if piece[start].is_some() || label[start] != part {
            continue;
        }
        let id = Some(pieces as u32);
        pieces += 1;
        piece[start] = id;
        todo.push(start);
        while let Some(v) = todo.pop() {
            for &u in neighbours.get(v).into_iter().flatten() {
                let u = u as usize;
                if label.get(u) == Some(&part) && piece.get(u) == Some(&None) {
                    piece[u] = id;
                    todo.push(u);
                }
            }
        }
    }
    (piece, pieces)
}

/// Each point's piece of `part` as in [`piece_ids`], and whether it is the largest piece (the
/// first found on a tie).
pub(crate) fn in_largest_piece(
    part: Option<u32>,
    label: &[Option<u32>],
    neighbours: &[Vec<u32>],
) -> Vec<Option<bool>> {
    let (piece, pieces) = piece_ids(part, label, neighbours);
    let mut size = vec![0usize; pieces];
    for p in piece.iter().flatten() {
        size[*p as usize] += 1;
    }
    let largest = (0..pieces).max_by(|&a, &b| size[a].cmp(&size[b]).then(b.cmp(&a)));
    piece
        .iter()
        .map(|p| p.map(|p| Some(p as usize) == largest))
        .collect()
}

/// Whether the points labelled `part` in `after` make one piece of surface, but for slivers
/// the part already held by cell (`by_cell`: each point's place in the part's pieces by cell,
/// [`in_largest_piece`]): every point of the part off its largest piece
/// lies, by cell, in the part but off its largest piece there. A sweep may then move points
/// into or out of a part whose cells hold a sliver of another side of the surface (five of the
/// bunny's parts), but neither cut a part nor add to its slivers, nor sweep its largest piece
/// away whole.
#[cfg(test)]
fn keeps_its_pieces(
    part: u32,
    after: &[Option<u32>],
    cell: &[Option<bool>],
    neighbours: &[Vec<u32>],
) -> bool {
    let scratch = &mut Vec::new();
    keeps_its_pieces_changed(part, (after, &BTreeMap::new()), cell, neighbours, scratch)
}

/// [`keeps_its_pieces`] with the labels after the sweep given as `label_now` with the labels
/// of the points in `changed` replaced. Reads only the points labelled `part` after the sweep
/// and their neighbours (and scans `label_now` and `cell` once), with the pieces numbered and
/// the largest chosen as [`in_largest_piece`] does (in the points' order, the first on a tie).
/// `scratch` holds each point's piece while it runs ([`UNVISITED`] before and after; piece
/// numbers stay below [`LEAVES`], a part having fewer points than that).
fn keeps_its_pieces_changed(
    part: u32,
    (label_now, changed): (&[Option<u32>], &BTreeMap<u32, Option<u32>>),
    cell: &[Option<bool>],
    neighbours: &[Vec<u32>],
    scratch: &mut Vec<u32>,
) -> bool {
    if scratch.len() < label_now.len() {
        scratch.resize(label_now.len(), UNVISITED);
    }
    // The points the sweep changed, marked as entering or leaving the part.
    for (&i, &label) in changed {
        if let Some(slot) = scratch.get_mut(i as usize) {
            *slot = if label == Some(part) { ENTERS } else { LEAVES };
        }
    }
    // A point not yet reached that is labelled `part` after the sweep.
    let unreached_member = |u: usize, scratch: &[u32]| match scratch.get(u) {
        Some(&ENTERS) => true,
        Some(&UNVISITED) => label_now.get(u) == Some(&Some(part)),
        _ => false,
    };
    let members: Vec<u32> = (0..label_now.len())
        .filter(|&i| unreached_member(i, scratch))
        .map(|i| i as u32)
        .collect();
    // Each member's piece (connected by the surface's edges among the members), numbered in
    // the members' order.
    let mut size: Vec<usize> = Vec::new();
    let mut todo = Vec::new();
    for &start in &members {
        if !unreached_member(start as usize, scratch) {
            continue;
        }
        let id = size.len() as u32;
        size.push(1);
        scratch[start as usize] = id;
        todo.push(start);
        while let Some(v) = todo.pop() {
            for &u in neighbours.get(v as usize).into_iter().flatten() {
                if unreached_member(u as usize, scratch) {
                    scratch[u as usize] = id;
                    size[id as usize] += 1;
                    todo.push(u);
                }
            }
        }
    }
    let largest = (0..size.len())
        .max_by(|&a, &b| size[a].cmp(&size[b]).then(b.cmp(&a)))
        .map(|p| p as u32);
    let piece_of: Vec<u32> = members.iter().map(|&v| scratch[v as usize]).collect();
    for &v in members.iter().chain(changed.keys()) {
        if let Some(slot) = scratch.get_mut(v as usize) {
            *slot = UNVISITED;
        }
    }
    let in_largest = |k: usize| Some(piece_of[k]) == largest;
    // The largest piece by cell is still there, in the largest now (a part swept empty, or
    // left with its sliver alone, holds none of its own surface) …
    let kept = !cell.contains(&Some(true))
        || members
            .iter()
            .enumerate()
            .any(|(k, &v)| in_largest(k) && cell.get(v as usize) == Some(&Some(true)));
    // … and nothing off it but slivers the cells held.
    kept && members
        .iter()
        .enumerate()
        .all(|(k, &v)| in_largest(k) || cell.get(v as usize) == Some(&Some(false)))
}

/// A point no piece has reached yet ([`keeps_its_pieces_changed`]'s scratch).
const UNVISITED: u32 = u32::MAX;

/// A point the sweep moves into the part, not yet reached ([`keeps_its_pieces_changed`]).
const ENTERS: u32 = u32::MAX - 1;

/// A point the sweep moves out of the part ([`keeps_its_pieces_changed`]).
const LEAVES: u32 = u32::MAX - 2;

/// The sheet that is `sheet`'s mirror image, with `new` (its triangles spanned again) mirrored
/// onto it; None where the image is not one of `sheets` or a rim vertex has none.
pub(super) fn image_sheet<'s>(
    sheet: &Sheet,
    new: &[[u32; 3]],
    sheets: &'s [Sheet],
    image_of: impl Fn(u32) -> Option<u32>,
) -> Option<(&'s Sheet, Vec<[u32; 3]>)> {
    let images: BTreeSet<u32> = sheet
        .inner
        .iter()
        .map(|&v| image_of(v))
        .collect::<Option<_>>()?;
    let image = sheets
        .iter()
        .find(|s| s.inner.len() == images.len() && s.inner.iter().all(|v| images.contains(v)))?;
    // A reflection turns a triangle over; its corners swapped turn it back.
    let mapped = new
        .iter()
        .map(|&[a, b, c]| Some([image_of(a)?, image_of(c)?, image_of(b)?]))
        .collect::<Option<_>>()?;
    Some((image, mapped))
}

/// The winding number of the closed triangle surface about `q` (the sum of the solid angles
/// its triangles subtend, over 4π; Van Oosterom and Strackee's formula).
fn winding_number(q: DVec3, closed: &[[DVec3; 3]]) -> f64 {
    let total: f64 = closed
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|p| p - q);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let numerator = a.dot(b.cross(c));
            let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
            2.0 * numerator.atan2(denominator)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}

/// The distance from `p` to the triangle (Ericson's closest point, *Real-Time Collision
/// Detection* 5.1.5).
fn distance_to_triangle(p: DVec3, [a, b, c]: [DVec3; 3]) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return p.distance(a);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return p.distance(b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return p.distance(a + ab * (d1 / (d1 - d3)));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return p.distance(c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return p.distance(a + ac * (d2 / (d2 - d6)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return p.distance(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    }
    let denominator = va + vb + vc;
    if denominator.abs() < f64::MIN_POSITIVE {
        return p.distance(a);
    }
    let (v, w) = (vb / denominator, vc / denominator);
    p.distance(a + ab * v + ac * w)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: i64, y: i64, z: i64) -> I64Vec3 {
        I64Vec3::new(x, y, z)
    }

    /// A sweep may move points of a part whose cells hold a sliver (another piece of the
    /// surface) as long as every point off its largest piece was off it by cell: points swept
    /// into the largest piece, or out of the part, pass; a cut of the largest piece, a point
    /// swept into the sliver, or the sliver swept out and the largest cut in two fail; a part
    /// one piece by cell must stay one piece.
    #[test]
    fn a_sweep_keeps_a_part_s_pieces_but_for_the_slivers_its_cells_held() {
        // Twelve points on a path 0 – 1 – … – 11.
        let neighbours: Vec<Vec<u32>> = (0..12u32)
            .map(|v| {
                [v.checked_sub(1), (v < 11).then_some(v + 1)]
                    .into_iter()
                    .flatten()
                    .collect()
            })
            .collect();
        let labels = |s: &str| -> Vec<Option<u32>> { s.chars().map(|c| c.to_digit(10)).collect() };
        // Part 0 by cell: a long piece 0–6 and a sliver 9–10.
        let by_cell = labels("000000011001");
        let by_cell_pieces = in_largest_piece(Some(0), &by_cell, &neighbours);
        let keeps = |after: &str| keeps_its_pieces(0, &labels(after), &by_cell_pieces, &neighbours);
        assert_eq!(pieces_of(Some(0), &by_cell, &neighbours), 2);
        assert!(keeps("000000011001"), "as it was by cell");
        assert!(
            keeps("000000001001"),
            "point 7 swept into the largest piece"
        );
        assert!(keeps("000001111001"), "points 5 and 6 swept out of it");
        assert!(keeps("000000011101"), "the sliver shrunk");
        assert!(!keeps("000100011001"), "the largest piece cut in two");
        assert!(!keeps("000000010001"), "point 8 swept into the sliver");
        assert!(
            !keeps("000100011111"),
            "the sliver swept out and the largest piece cut"
        );
        assert!(!keeps("111111111001"), "the largest piece swept away whole");
        assert!(!keeps("111111111111"), "the part swept empty");
        // Part 1 by cell is one piece (7–9): no second piece of it is allowed.
        let one = labels("000000011100");
        let one_pieces = in_largest_piece(Some(1), &one, &neighbours);
        let keeps_one = |after: &str| keeps_its_pieces(1, &labels(after), &one_pieces, &neighbours);
        assert!(keeps_one("000000111100"));
        assert!(!keeps_one("100000011100"), "a point of it swept far away");
    }

    /// The check before session 49, on a copy of every label after the sweep: the reference
    /// [`keeps_its_pieces_changed`] is compared with.
    fn keeps_its_pieces_by_copy(
        part: u32,
        after: &[Option<u32>],
        cell: &[Option<bool>],
        neighbours: &[Vec<u32>],
    ) -> bool {
        let now = in_largest_piece(Some(part), after, neighbours);
        let kept = !cell.contains(&Some(true))
            || now
                .iter()
                .zip(cell)
                .any(|(now, cell)| *now == Some(true) && *cell == Some(true));
        kept && now
            .iter()
            .enumerate()
            .all(|(v, largest)| *largest != Some(false) || cell.get(v) == Some(&Some(false)))
    }

    /// The sweep's labels given as changes to the labels before it decide as the labels after
    /// it do (the check on a copy of every label), on every assignment of three parts to six points of a ring and every set of
    /// points swept between parts 0 and 1, with one scratch for all calls (left clean).
    #[test]
    fn a_sweep_s_changes_decide_as_the_labels_after_it() {
        let n = 6u32;
        let neighbours: Vec<Vec<u32>> =
            (0..n).map(|v| vec![(v + n - 1) % n, (v + 1) % n]).collect();
        let mut scratch = Vec::new();
        let mut compared = 0;
        for code in 0..3u32.pow(n) {
            let before: Vec<Option<u32>> = (0..n).map(|k| Some(code / 3u32.pow(k) % 3)).collect();
            for swept in 0..1u32 << n {
                let mut after = before.clone();
                let mut changed = BTreeMap::new();
                for k in 0..n as usize {
                    if swept >> k & 1 == 1 && before[k] != Some(2) {
                        after[k] = before[k].map(|l| 1 - l);
                        changed.insert(k as u32, after[k]);
                    }
                }
                for part in [0, 1] {
                    let cell = in_largest_piece(Some(part), &before, &neighbours);
                    let dense = keeps_its_pieces_by_copy(part, &after, &cell, &neighbours);
                    let sparse = keeps_its_pieces_changed(
                        part,
                        (&before, &changed),
                        &cell,
                        &neighbours,
                        &mut scratch,
                    );
                    assert_eq!(dense, sparse, "{before:?} → {after:?}, part {part}");
                    assert!(scratch.iter().all(|&x| x == UNVISITED));
                    compared += 1;
                }
            }
        }
        assert_eq!(compared, 3usize.pow(n) * (1 << n) * 2);
    }

    /// Twice the area of the triangles over `rim`.
    fn twice_area(rim: &[I64Vec3], triangles: &[[usize; 3]]) -> f64 {
        triangles
            .iter()
            .map(|&[i, k, j]| (rim[k] - rim[i]).cross(rim[j] - rim[i]).as_dvec3().length())
            .sum()
    }

    #[test]
    fn a_flat_l_shaped_rim_is_covered_exactly_by_diagonals_inside_it() {
        // An L of area 3 on z = 0, counter-clockwise seen from +z; a diagonal from the outer
        // corner (2, 2) would leave the L.
        let rim = [
            p(0, 0, 0),
            p(2, 0, 0),
            p(2, 1, 0),
            p(1, 1, 0),
            p(1, 2, 0),
            p(0, 2, 0),
        ];
        let spanned = least_area_triangulation(&rim, DVec3::Z, &|_, _| false, &|_| true).unwrap();
        assert_eq!(spanned.len(), rim.len() - 2);
        assert!((twice_area(&rim, &spanned) - 6.0).abs() < 1e-9);
        // Seen from below it turns clockwise: refused.
        assert!(least_area_triangulation(&rim, -DVec3::Z, &|_, _| false, &|_| true).is_none());
        // Every diagonal from the inner corner (1, 1) joined elsewhere: none (a reflex
        // corner needs one); from the corner (2, 0), it goes without.
        let from = |corner: usize| move |i: usize, j: usize| i == corner || j == corner;
        assert!(least_area_triangulation(&rim, DVec3::Z, &from(3), &|_| true).is_none());
        let spanned = least_area_triangulation(&rim, DVec3::Z, &from(1), &|_| true).unwrap();
        assert!((twice_area(&rim, &spanned) - 6.0).abs() < 1e-9);
        assert!(spanned.contains(&[0, 1, 2]), "{spanned:?}");
        // No triangle allowed: none.
        assert!(least_area_triangulation(&rim, DVec3::Z, &|_, _| false, &|_| false).is_none());
    }

    #[test]
    fn a_saddle_rim_takes_the_lesser_of_its_two_diagonals() {
        // A square with two opposite corners raised by different heights: either diagonal
        // projects onto a triangulation of the square; the lesser area is taken.
        let rim = [p(0, 0, 0), p(4, 0, 3), p(4, 4, 0), p(0, 4, 1)];
        let spanned = least_area_triangulation(&rim, DVec3::Z, &|_, _| false, &|_| true).unwrap();
        let other = |d: [usize; 2]| -> Vec<[usize; 3]> {
            if d == [0, 2] {
                vec![[0, 1, 2], [0, 2, 3]]
            } else {
                vec![[0, 1, 3], [1, 2, 3]]
            }
        };
        let least = twice_area(&rim, &other([0, 2])).min(twice_area(&rim, &other([1, 3])));
        assert!((twice_area(&rim, &spanned) - least).abs() < 1e-9);
    }

    #[test]
    fn a_rim_that_crosses_itself_seen_along_the_normal_is_not_spanned() {
        // A bow tie seen from +z.
        let rim = [p(0, 0, 0), p(2, 2, 0), p(2, 0, 0), p(0, 2, 0)];
        assert!(least_area_triangulation(&rim, DVec3::Z, &|_, _| false, &|_| true).is_none());
    }

    #[test]
    fn the_winding_number_of_a_closed_surface_is_one_inside_and_zero_outside() {
        // A tetrahedron, faces counter-clockwise seen from outside.
        let [a, b, c, d] = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let closed = [[a, c, b], [a, b, d], [a, d, c], [b, c, d]];
        let inside = DVec3::splat(0.2);
        assert!((winding_number(inside, &closed) - 1.0).abs() < 1e-9);
        assert!(winding_number(DVec3::splat(2.0), &closed).abs() < 1e-9);
        assert!(winding_number(-DVec3::splat(0.1), &closed).abs() < 1e-9);
    }

    #[test]
    fn the_distance_to_a_triangle_is_to_its_face_edge_or_corner() {
        let t = [DVec3::ZERO, DVec3::X * 2.0, DVec3::Y * 2.0];
        assert!((distance_to_triangle(DVec3::new(0.5, 0.5, 3.0), t) - 3.0).abs() < 1e-12);
        assert!((distance_to_triangle(DVec3::new(-1.0, -1.0, 0.0), t) - 2f64.sqrt()).abs() < 1e-12);
        assert!((distance_to_triangle(DVec3::new(1.0, -2.0, 0.0), t) - 2.0).abs() < 1e-12);
        assert!((distance_to_triangle(DVec3::new(2.0, 2.0, 0.0), t) - 2f64.sqrt()).abs() < 1e-12);
    }
}

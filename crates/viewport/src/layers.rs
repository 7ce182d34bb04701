//! What to draw, as plain data: cage edges as coloured lines (kind colours, pink borders,
//! grey internal cages, other hierarchy levels dimmed), cage vertices as screen-space dots
//! (selection and hover highlighted), and the mesh's edges for the wireframe overlay.

use std::collections::BTreeSet;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use starcages_core::scene::CageSet;

use crate::colors::{self, Rgba};

/// One end of a line segment.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct LineVertex {
    /// World position.
    pub position: [f32; 3],
    /// RGBA colour, 8 bits each.
    pub color: [u8; 4],
}

/// A cage vertex drawn as a round dot of constant screen size.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Dot {
    /// World position.
    pub position: [f32; 3],
    /// RGBA colour, 8 bits each.
    pub color: [u8; 4],
    /// Diameter in pixels.
    pub size: f32,
}

/// A ground grid under the box `min..max` (the model): on the plane z = 0, or lower where the
/// model reaches below it, so the grid is a floor and never cuts through the model (lines are
/// seen through surfaces). It covers the box seen from above with half its size again on every
/// side, with lines every power of ten that gives about five to fifty cells across it, and the
/// X axis in red and the Y axis in green, as in Blender.
pub fn ground_grid(min: glam::Vec3, max: glam::Vec3) -> Vec<LineVertex> {
    let (lo, hi) = (min.min(glam::Vec3::ZERO), max.max(glam::Vec3::ZERO));
    let extent = (hi - lo).truncate().max_element().max(1e-6);
    let step = 10f32.powf((extent / 5.0).log10().floor());
    let margin = (extent * 0.5 / step).ceil();
    // Cell index range along x and y.
    let range = [0, 1].map(|k| {
        (
            (lo[k] / step).floor() - margin,
            (hi[k] / step).ceil() + margin,
        )
    });
    let z = min.z.min(0.0);
    let mut lines = Vec::new();
    // Lines across axis `k` (constant coordinate along it); the one through the origin is the
    // other axis's line: x = 0 is the Y axis (green), y = 0 the X axis (red).
    for (k, axis_color) in [(0, colors::Y_AXIS), (1, colors::X_AXIS)] {
        let (a0, a1) = range[k];
        let (b0, b1) = range[1 - k];
        for i in 0..=(a1 - a0).clamp(0.0, 400.0) as i32 {
            let a = (a0 + i as f32) * step;
            let color = colors::to_u8(if a.abs() < step * 0.5 {
                axis_color
            } else {
                colors::GRID
            });
            let mut start = [0.0, 0.0, z];
            let mut end = [0.0, 0.0, z];
            (start[k], end[k]) = (a, a);
            (start[1 - k], end[1 - k]) = (b0 * step, b1 * step);
            lines.push(LineVertex {
                position: start,
                color,
            });
            lines.push(LineVertex {
                position: end,
                color,
            });
        }
    }
    lines
}

/// How cages are shown.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CageStyle {
    /// Per cage (leaves, then internal cages): drawn or not. Missing entries are visible.
    pub hidden: BTreeSet<usize>,
    /// Selected cage vertices.
    pub selected: BTreeSet<u32>,
    /// The cage vertex under the cursor.
    pub hovered: Option<u32>,
    /// Show only this hierarchy level at full strength (0: leaf cages); others dimmed.
    pub focus_level: Option<usize>,
    /// Leaf cages with a problem (by index), drawn in the warning colour.
    pub warning_cages: BTreeSet<usize>,
    /// Cage vertices with a problem, drawn as large warning dots.
    pub warning_vertices: BTreeSet<u32>,
    /// Other points to mark (mesh vertices outside every cage), small warning dots.
    pub warning_points: Vec<glam::Vec3>,
    /// Selected points that are not cage vertices (mesh vertices), small dots in the
    /// selection colour.
    pub selected_points: Vec<glam::Vec3>,
    /// Cage vertices drawn small and faint (the leaf vertices under a rig's controls in Pose
    /// mode), unless selected, hovered or warned about.
    pub quiet_vertices: BTreeSet<u32>,
    /// Cage vertices not drawn at all, unless selected, hovered or warned about.
    pub hidden_vertices: BTreeSet<u32>,
    /// The 3D cursor, drawn as a large red dot.
    pub cursor: Option<glam::Vec3>,
}

/// Hierarchy level of every cage, leaves then internal cages: 0 for leaves, and for an
/// internal cage one more than the highest level among the cages holding vertices it owns.
pub fn cage_levels(set: &CageSet) -> Vec<usize> {
    let leaves = set.leaves.len();
    let mut level = vec![0usize; leaves + set.internals.len()];
    let vertices_of =
        |faces: &[Vec<u32>]| -> BTreeSet<u32> { faces.iter().flatten().copied().collect() };
    let all: Vec<BTreeSet<u32>> = set
        .leaves
        .iter()
        .map(|c| vertices_of(&c.faces))
        .chain(set.internals.iter().map(|c| vertices_of(&c.faces)))
        .collect();
    // Relax until stable: the hierarchy is acyclic, so this ends within #internal passes.
    for _ in 0..=set.internals.len() {
        let mut changed = false;
        for (i, cage) in set.internals.iter().enumerate() {
            let below = (0..all.len())
                .filter(|&j| j != leaves + i && cage.owns.iter().any(|v| all[j].contains(v)))
                .map(|j| level[j])
                .max()
                .unwrap_or(0);
            if level[leaves + i] != below + 1 {
                level[leaves + i] = below + 1;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    level
}

/// The unique edges of polygon faces, as sorted pairs.
fn polygon_edges(faces: &[Vec<u32>]) -> BTreeSet<(u32, u32)> {
    let mut edges = BTreeSet::new();
    for face in faces {
        for (k, &a) in face.iter().enumerate() {
            let b = face[(k + 1) % face.len()];
            edges.insert((a.min(b), a.max(b)));
        }
    }
    edges
}

/// Cage edges as line segments in `pose`.
pub fn cage_lines(set: &CageSet, pose: &[DVec3], style: &CageStyle) -> Vec<LineVertex> {
    let levels = cage_levels(set);
    let dim_for = |cage: usize| match style.focus_level {
        Some(level) if levels[cage] != level => 0.65,
        _ => 0.0,
    };
    // Edges of faces shared by two leaf cages are borders.
    let mut border_edges = BTreeSet::new();
    for sharing in set.faces_by_vertex_set().values() {
        if let [(c, f), _] = sharing[..] {
            border_edges.extend(polygon_edges(std::slice::from_ref(&set.leaves[c].faces[f])));
        }
    }
    let mut out = Vec::new();
    let mut push = |edges: BTreeSet<(u32, u32)>, colour: &dyn Fn((u32, u32)) -> Rgba| {
        for (a, b) in edges {
            let c = colors::to_u8(colour((a, b)));
            for v in [a, b] {
                if let Some(p) = pose.get(v as usize) {
                    out.push(LineVertex {
                        position: p.as_vec3().to_array(),
                        color: c,
                    });
                }
            }
        }
    };
    // An edge shared by neighbouring leaf cages is drawn once.
    let mut drawn = BTreeSet::new();
    for (i, cage) in set.leaves.iter().enumerate() {
        if style.hidden.contains(&i) {
            continue;
        }
        let base = if style.warning_cages.contains(&i) {
            colors::WARNING
        } else {
            colors::kind(cage.kind)
        };
        let warned = style.warning_cages.contains(&i);
        let dim = dim_for(i);
        let mut edges = polygon_edges(&cage.faces);
        edges.retain(|e| drawn.insert(*e));
        push(edges, &|e| {
            let c = if border_edges.contains(&e) && !warned {
                colors::BORDER
            } else {
                base
            };
            colors::dim(c, dim)
        });
    }
    let leaves = set.leaves.len();
    for (i, cage) in set.internals.iter().enumerate() {
        if style.hidden.contains(&(leaves + i)) {
            continue;
        }
        let c = colors::dim(colors::INTERNAL, dim_for(leaves + i));
        push(polygon_edges(&cage.faces), &|_| c);
    }
    out
}

/// The visible cages' edges that `pose` moves away from `rest`, in the faint ghost colour: Rig
/// mode draws the current pose this way over the rest cages it edits (edges the pose leaves in
/// place are not drawn twice).
pub fn ghost_lines(
    set: &CageSet,
    pose: &[DVec3],
    rest: &[DVec3],
    hidden: &BTreeSet<usize>,
) -> Vec<LineVertex> {
    let leaves = set.leaves.len();
    let faces = set
        .leaves
        .iter()
        .map(|c| &c.faces)
        .chain(set.internals.iter().map(|c| &c.faces))
        .enumerate()
        .filter(|(i, _)| !hidden.contains(i) && *i < leaves + set.internals.len())
        .flat_map(|(_, faces)| polygon_edges(faces));
    let edges: BTreeSet<(u32, u32)> = faces.collect();
    let moved = |v: u32| pose.get(v as usize) != rest.get(v as usize);
    let ghost = colors::to_u8(colors::GHOST);
    edges
        .into_iter()
        .filter(|&(a, b)| moved(a) || moved(b))
        .filter_map(|(a, b)| Some([pose.get(a as usize)?, pose.get(b as usize)?]))
        .flatten()
        .map(|p| LineVertex {
            position: p.as_vec3().to_array(),
            color: ghost,
        })
        .collect()
}

/// Cage vertices of visible cages as dots in `pose`: selected ones orange and larger, the
/// hovered one light yellow, ones with a problem large and yellow, vertices only on dimmed
/// levels faded; then the style's warning points as small yellow dots and its selected points
/// (mesh vertices) as small orange ones.
pub fn cage_dots(set: &CageSet, pose: &[DVec3], style: &CageStyle) -> Vec<Dot> {
    let levels = cage_levels(set);
    let leaves = set.leaves.len();
    let faces_of = |c: usize| {
        if c < leaves {
            &set.leaves[c].faces
        } else {
            &set.internals[c - leaves].faces
        }
    };
    // Per vertex: visible at all, and on the focused level.
    let mut visible = vec![false; pose.len()];
    let mut focused = vec![style.focus_level.is_none(); pose.len()];
    for (c, &level) in levels.iter().enumerate() {
        if style.hidden.contains(&c) {
            continue;
        }
        for &v in faces_of(c).iter().flatten() {
            if let Some(slot) = visible.get_mut(v as usize) {
                *slot = true;
                focused[v as usize] |= style.focus_level == Some(level);
            }
        }
    }
    let marked = |id: u32| {
        style.hovered == Some(id)
            || style.selected.contains(&id)
            || style.warning_vertices.contains(&id)
    };
    (0..pose.len())
        .filter(|&v| {
            visible[v] && (!style.hidden_vertices.contains(&(v as u32)) || marked(v as u32))
        })
        .map(|v| {
            let id = v as u32;
            let (colour, size) = if style.hovered == Some(id) {
                (colors::HOVERED, 10.0)
            } else if style.selected.contains(&id) {
                (colors::SELECTED, 9.0)
            } else if style.warning_vertices.contains(&id) {
                (colors::WARNING, 11.0)
            } else if style.quiet_vertices.contains(&id) {
                (colors::dim(colors::VERTEX, 0.6), 4.0)
            } else if focused[v] {
                (colors::VERTEX, 7.0)
            } else {
                (colors::dim(colors::VERTEX, 0.5), 5.0)
            };
            Dot {
                position: pose[v].as_vec3().to_array(),
                color: colors::to_u8(colour),
                size,
            }
        })
        .chain(style.warning_points.iter().map(|p| Dot {
            position: p.to_array(),
            color: colors::to_u8(colors::WARNING),
            size: 4.0,
        }))
        .chain(style.selected_points.iter().map(|p| Dot {
            position: p.to_array(),
            color: colors::to_u8(colors::SELECTED),
            size: 4.0,
        }))
        .chain(style.cursor.iter().map(|p| Dot {
            position: p.to_array(),
            color: colors::to_u8(colors::X_AXIS),
            size: 12.0,
        }))
        .collect()
}

/// The mesh's unique edges, as index pairs for the wireframe overlay.
pub fn mesh_edges(triangles: &[[u32; 3]]) -> Vec<u32> {
    let mut edges = BTreeSet::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges.insert((a.min(b), a.max(b)));
        }
    }
    edges.into_iter().flat_map(|(a, b)| [a, b]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use starcages_core::generate::demo::demo_scene;

    #[test]
    fn levels_follow_the_hierarchy() {
        let scene = demo_scene("critter", 0.2).unwrap();
        let levels = cage_levels(&scene.cages);
        let leaves = scene.cages.leaves.len();
        assert!(levels[..leaves].iter().all(|&l| l == 0));
        assert_eq!(levels[leaves..], [1, 2]); // ears, then head over the ears cage
    }

    #[test]
    fn borders_are_pink_and_kinds_keep_their_colours() {
        let scene = demo_scene("bumpy", 0.2).unwrap();
        let lines = cage_lines(&scene.cages, &scene.pose, &CageStyle::default());
        let colours: BTreeSet<[u8; 4]> = lines.iter().map(|l| l.color).collect();
        for c in [
            colors::BORDER,
            colors::kind(starcages_core::coords::CoordinateKind::MeanValue),
            colors::kind(starcages_core::coords::CoordinateKind::Green),
        ] {
            assert!(colours.contains(&colors::to_u8(c)));
        }
        // Three boxes in a row: 12 edges each, 4 shared per border, two borders.
        assert_eq!(lines.len(), 2 * (3 * 12 - 2 * 4));
    }

    #[test]
    fn dots_show_selection_hover_and_hidden_cages() {
        let scene = demo_scene("bar", 0.2).unwrap();
        let style = CageStyle {
            selected: [0, 1].into(),
            hovered: Some(3),
            hidden: [1].into(),
            ..CageStyle::default()
        };
        let dots = cage_dots(&scene.cages, &scene.pose, &style);
        // The right cage is hidden: only the left cage's 8 vertices remain.
        assert_eq!(dots.len(), 8);
        let selected = colors::to_u8(colors::SELECTED);
        assert_eq!(dots.iter().filter(|d| d.color == selected).count(), 2);
        assert!(
            dots.iter()
                .any(|d| d.color == colors::to_u8(colors::HOVERED))
        );
    }

    #[test]
    fn quiet_vertices_are_small_and_hidden_ones_go_unless_selected() {
        let scene = demo_scene("bar", 0.2).unwrap();
        let all = cage_dots(&scene.cages, &scene.pose, &CageStyle::default()).len();
        let style = CageStyle {
            quiet_vertices: [0, 1].into(),
            hidden_vertices: [2, 3, 4].into(),
            selected: [4].into(),
            ..CageStyle::default()
        };
        let dots = cage_dots(&scene.cages, &scene.pose, &style);
        assert_eq!(
            dots.len(),
            all - 2,
            "two hidden, the selected hidden one still shown"
        );
        assert_eq!(
            dots.iter().filter(|d| d.size == 4.0).count(),
            2,
            "two quiet"
        );
    }

    #[test]
    fn the_ground_grid_covers_the_scene_with_its_axes_coloured() {
        let lines = ground_grid(
            glam::Vec3::new(-0.3, -0.2, 0.1),
            glam::Vec3::new(0.5, 0.4, 1.0),
        );
        assert!(lines.len().is_multiple_of(2) && lines.len() > 8 && lines.len() < 400);
        assert!(lines.iter().all(|v| v.position[2] == 0.0));
        // A model reaching below z = 0 gets its floor under its lowest point.
        let under = ground_grid(glam::Vec3::new(-1.0, -1.0, -0.5), glam::Vec3::ONE);
        assert!(under.iter().all(|v| v.position[2] == -0.5));
        let xs = lines.iter().map(|v| v.position[0]);
        let (min_x, max_x) = xs.fold((f32::MAX, f32::MIN), |(a, b), x| (a.min(x), b.max(x)));
        assert!(min_x <= -0.3 && max_x >= 0.5, "{min_x} .. {max_x}");
        let red = colors::to_u8(colors::X_AXIS);
        let green = colors::to_u8(colors::Y_AXIS);
        assert!(lines.iter().any(|v| v.color == red && v.position[1] == 0.0));
        assert!(
            lines
                .iter()
                .any(|v| v.color == green && v.position[0] == 0.0)
        );
    }
}

//! What the user sees: camera, layers, hidden cages, the influence map, X mirroring, and where
//! the viewport is on screen.

use std::collections::BTreeMap;

use glam::Vec2;
use starcages_core::coords::CoordinateKind;
use starcages_core::scene::CageSet;
use starcages_viewport::layers::{CageStyle, cage_levels};
use starcages_viewport::{Layers, OrbitCamera};

use super::{CageId, Selection};

/// Which influence map is painted on the mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InfluenceChoice {
    /// None: the studio mesh.
    #[default]
    None,
    /// b (eq. 11) of the inspected leaf cage.
    SelectedCage,
    /// b of every leaf cage.
    AllCages,
    /// W(v, p) (eq. 4) of the one selected cage vertex.
    JoinWeight,
    /// Distance to the deformation by one cage of this kind around everything.
    Difference(CoordinateKind),
}

/// What R and S turn and scale about, as Blender's Transform Pivot Point. The origin of a
/// whole control (every vertex of an internal cage with a joint, as the auto rig makes them) is
/// its joint, as a bone's is its head; of another whole cage its centroid; of a loose vertex
/// itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PivotPoint {
    /// The mean of the selection's origins: one control turns about its joint, loose
    /// vertices about their centroid (Blender's default).
    #[default]
    MedianPoint,
    /// The centre of the box around the selection's origins.
    BoundingBoxCenter,
    /// Each selected control or cage about its own origin (loose vertices about their
    /// centroid): two legs selected bend each at its own hip.
    IndividualOrigins,
    /// The 3D cursor (Shift+right click on the mesh places it).
    Cursor,
    /// The active element's origin (the last vertex or control picked): a control's joint,
    /// another vertex itself.
    ActiveElement,
}

impl PivotPoint {
    /// All of them, in the order the menu lists them.
    pub const ALL: [Self; 5] = [
        Self::BoundingBoxCenter,
        Self::Cursor,
        Self::IndividualOrigins,
        Self::MedianPoint,
        Self::ActiveElement,
    ];

    /// The menu's label (Blender's words).
    pub fn label(self) -> &'static str {
        match self {
            Self::MedianPoint => "Median Point",
            Self::BoundingBoxCenter => "Bounding Box Center",
            Self::IndividualOrigins => "Individual Origins",
            Self::Cursor => "3D Cursor",
            Self::ActiveElement => "Active Element",
        }
    }
}

/// How Pose mode draws the leaf cage vertices of a rig with controls (internal cages): the
/// controls are what a person poses, the leaf vertices what Rig mode edits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LeafVertices {
    /// As every other vertex.
    Shown,
    /// Small and faint, still picked.
    #[default]
    Small,
    /// Not drawn and not picked (selected ones still show).
    Hidden,
}

impl LeafVertices {
    /// All of them, in the order the menu lists them.
    pub const ALL: [Self; 3] = [Self::Shown, Self::Small, Self::Hidden];

    /// The menu's label.
    pub fn label(self) -> &'static str {
        match self {
            Self::Shown => "Shown",
            Self::Small => "Small",
            Self::Hidden => "Hidden",
        }
    }
}

/// Ghosts of the animation (View ▸ Ghosts): the mesh at frames before and after the current
/// one, `step` frames apart, drawn translucent (before in red, after in blue) and following
/// key edits live.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GhostSettings {
    /// Drawn at all.
    pub shown: bool,
    /// Ghosts before the current frame.
    pub before: u32,
    /// Ghosts after it.
    pub after: u32,
    /// Frames between ghosts (at least 1).
    pub step: u32,
}

impl Default for GhostSettings {
    fn default() -> Self {
        Self {
            shown: false,
            before: 2,
            after: 2,
            step: 3,
        }
    }
}

impl GhostSettings {
    /// The most ghosts on either side.
    pub const MAX_PER_SIDE: u32 = 8;

    /// The ghosts' frames around `current` inside `range` (nearest first on each side), with
    /// whether each is before the current frame.
    pub fn frames(&self, current: f64, range: (f64, f64)) -> Vec<(f64, bool)> {
        if !self.shown {
            return Vec::new();
        }
        let step = f64::from(self.step.max(1));
        let side = |count: u32, sign: f64| {
            (1..=count.min(Self::MAX_PER_SIDE))
                .map(move |k| current + sign * step * f64::from(k))
                .filter(|f| (range.0..=range.1).contains(f))
        };
        side(self.before, -1.0)
            .map(|f| (f, true))
            .chain(side(self.after, 1.0).map(|f| (f, false)))
            .collect()
    }

    /// The tint (RGB) and opacity of the ghost `distance` steps from the current frame,
    /// before it or after: red before, blue after, fainter further away.
    pub fn tint(before: bool, distance: u32) -> [f32; 4] {
        let opacity = 0.5 / (1.0 + 0.35 * distance.saturating_sub(1) as f32);
        if before {
            [0.95, 0.38, 0.28, opacity]
        } else {
            [0.28, 0.55, 0.98, opacity]
        }
    }
}

/// The leaf cage vertices that belong to no internal cage: what a rig's controls move.
pub fn leaf_only_vertices(set: &CageSet) -> std::collections::BTreeSet<u32> {
    let internal: std::collections::BTreeSet<u32> = set
        .internals
        .iter()
        .flat_map(|c| c.faces.iter().flatten().copied())
        .collect();
    set.leaves
        .iter()
        .flat_map(|c| c.faces.iter().flatten().copied())
        .filter(|v| !internal.contains(v))
        .collect()
}

/// What clicks and region drags select in Rig mode (Pose mode always selects cage vertices).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SelectElement {
    /// Cage vertices.
    #[default]
    CageVertices,
    /// Faces of leaf cages (E extrudes them).
    CageFaces,
    /// Mesh vertices at rest (Shift+A puts a box around them).
    MeshVertices,
}

impl SelectElement {
    /// All of them, in the order the switch shows them.
    pub const ALL: [Self; 3] = [Self::CageVertices, Self::CageFaces, Self::MeshVertices];

    /// The switch's label.
    pub fn label(self) -> &'static str {
        match self {
            Self::CageVertices => "Vertex select",
            Self::CageFaces => "Face select",
            Self::MeshVertices => "Mesh select",
        }
    }

    /// The switch's tooltip.
    pub fn tooltip(self) -> &'static str {
        match self {
            Self::CageVertices => "Clicks and rectangles pick cage vertices",
            Self::CageFaces => {
                "Clicks pick faces of leaf cages (Shift adds), rectangles the faces inside them; \
                 E extrudes every selected face"
            }
            Self::MeshVertices => {
                "Rectangles (Ctrl+drag: lasso) pick mesh vertices at rest; Shift+A ▸ Box around \
                 the selected mesh vertices cages that region"
            }
        }
    }
}

/// A rectangle on screen in points (egui's logical pixels), top-left origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScreenRect {
    /// Top-left corner.
    pub min: Vec2,
    /// Width and height.
    pub size: Vec2,
}

impl ScreenRect {
    /// `pos_in_screen` relative to the rectangle's top-left corner.
    pub fn local(&self, pos_in_screen: Vec2) -> Vec2 {
        pos_in_screen - self.min
    }

    /// The centre.
    pub fn center(&self) -> Vec2 {
        self.min + self.size * 0.5
    }
}

impl Default for ScreenRect {
    fn default() -> Self {
        Self {
            min: Vec2::ZERO,
            size: Vec2::new(800.0, 600.0),
        }
    }
}

/// The view.
#[derive(Debug, Clone, Default)]
pub struct ViewState {
    /// The camera.
    pub camera: OrbitCamera,
    /// Layers and shading.
    pub layers: Layers,
    /// Cages not drawn (and not pickable), with their names: a name follows its cage when an
    /// edit renumbers the cages.
    hidden: BTreeMap<CageId, String>,
    /// The influence map.
    pub influence: InfluenceChoice,
    /// Moving a vertex moves its mirror partner across x = 0.
    pub mirror_x: bool,
    /// What clicks and region drags select in Rig mode.
    pub select_element: SelectElement,
    /// G snaps the selection onto the cage vertex under the pointer (Ctrl while moving does
    /// the opposite, as Blender's snapping toggle).
    pub snap_to_vertices: bool,
    /// What R and S turn and scale about.
    pub pivot_point: PivotPoint,
    /// How Pose mode draws the leaf vertices of a rig with controls.
    pub leaf_vertices: LeafVertices,
    /// The 3D cursor, where placed (scene coordinates); the origin until then.
    pub cursor: Option<glam::DVec3>,
    /// Ghosts of the animation.
    pub ghosts: GhostSettings,
    /// Where the 3D view was drawn last frame.
    pub viewport: ScreenRect,
}

impl ViewState {
    /// Whether `cage` is hidden.
    pub fn is_hidden(&self, cage: CageId) -> bool {
        self.hidden.contains_key(&cage)
    }

    /// Hides or shows `cage` (of `set`).
    pub fn set_hidden(&mut self, cage: CageId, hidden: bool, set: &CageSet) {
        match cage.name(set) {
            Some(name) if hidden => {
                self.hidden.insert(cage, name.to_owned());
            }
            _ => {
                self.hidden.remove(&cage);
            }
        }
    }

    /// Finds the hidden cages again by name after a change of the document; the ones gone
    /// are forgotten.
    pub fn revalidate(&mut self, set: &CageSet) {
        let names = std::mem::take(&mut self.hidden).into_values();
        self.hidden = names
            .filter_map(|name| Some((CageId::by_name(set, &name)?, name)))
            .collect();
    }

    /// Whether every hidden cage resolves in `set` under its name.
    pub fn is_valid_for(&self, set: &CageSet) -> bool {
        self.hidden
            .iter()
            .all(|(id, name)| id.name(set) == Some(name.as_str()))
    }

    /// Per cage vertex: whether it belongs to a drawn cage (what picking may hit).
    pub fn pickable(&self, set: &CageSet) -> Vec<bool> {
        let mut pickable = vec![false; set.vertices.len()];
        for id in CageId::all(set) {
            let internal_hidden = matches!(id, CageId::Internal(_)) && !self.layers.cages;
            if self.is_hidden(id) || internal_hidden {
                continue;
            }
            for &v in id.faces(set).unwrap_or_default().iter().flatten() {
                if let Some(p) = pickable.get_mut(v as usize) {
                    *p = true;
                }
            }
        }
        pickable
    }

    /// The viewport crate's cage style for this view and `selection`: the one place where
    /// [`CageId`]s become its flat per-cage indices.
    pub fn cage_style(&self, selection: &Selection, set: &CageSet) -> CageStyle {
        let focus_level = selection
            .cage()
            .filter(|c| c.exists(set))
            .and_then(|c| cage_levels(set).get(c.layer_index(set)).copied());
        CageStyle {
            hidden: self.hidden.keys().map(|c| c.layer_index(set)).collect(),
            selected: selection.vertices.clone(),
            hovered: selection.hovered,
            focus_level,
            ..CageStyle::default()
        }
    }
}

//! Blender's modal G / R / S: the selection follows the pointer (or a typed value) until Enter
//! or a click confirms it, Esc or a right click cancels it. X / Y / Z lock an axis.

use glam::{DQuat, DVec3, Vec2};
use starcages_viewport::OrbitCamera;

use crate::state::{EditorState, GestureId, PivotPoint, ScreenRect};

/// G, R or S.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Grab: move.
    Grab,
    /// Rotate about the selection's centre.
    Rotate,
    /// Scale about the selection's centre.
    Scale,
}

impl Mode {
    /// The undo label and status-bar name.
    pub fn label(self) -> &'static str {
        match self {
            Self::Grab => "grab",
            Self::Rotate => "rotate",
            Self::Scale => "scale",
        }
    }
}

/// An axis lock.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// X.
    X,
    /// Y.
    Y,
    /// Z.
    Z,
}

impl Axis {
    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        match self {
            Self::X => 0,
            Self::Y => 1,
            Self::Z => 2,
        }
    }

    /// The unit vector.
    pub fn vector(self) -> DVec3 {
        match self {
            Self::X => DVec3::X,
            Self::Y => DVec3::Y,
            Self::Z => DVec3::Z,
        }
    }

    /// `current` with `self` toggled: pressing the locked axis again unlocks it.
    pub fn toggle(self, current: Option<Self>) -> Option<Self> {
        (current != Some(self)).then_some(self)
    }
}

/// A modal transform of the selection, in progress.
#[derive(Debug)]
pub struct TransformTool {
    /// Grab, rotate or scale.
    pub mode: Mode,
    /// Axis lock.
    pub axis: Option<Axis>,
    /// A typed value (distance, degrees or factor) overriding the mouse.
    pub typed: String,
    /// The state's gesture this tool drives.
    pub gesture: GestureId,
    /// Grab only: the cage vertex the selection is snapped onto (index, position); the
    /// selected vertex nearest it lands exactly on it.
    pub snap: Option<(u32, DVec3)>,
    start_pointer: Vec2,
    /// The pivot the pointer's turn and stretch are measured around (and drawn).
    centre: DVec3,
    start: Vec<(u32, DVec3)>,
    /// Per vertex of `start`, the point it turns and scales about: `centre`, or with
    /// Individual Origins its own control's or cage's origin.
    origins: Vec<DVec3>,
}

/// How far a transform has gone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Amount {
    /// Grab: the displacement.
    Delta(DVec3),
    /// Rotate: the angle.
    Degrees(f64),
    /// Scale: the factor.
    Factor(f64),
}

/// The move that puts the vertex of `start` (index, position) nearest `at` exactly on `at`:
/// a snap onto the cage vertex there.
pub fn snap_delta(start: &[(u32, DVec3)], at: DVec3) -> DVec3 {
    start
        .iter()
        .map(|&(_, p)| p)
        .min_by(|a, b| a.distance_squared(at).total_cmp(&b.distance_squared(at)))
        .map_or(DVec3::ZERO, |nearest| at - nearest)
}

/// World displacement for a pointer move of `delta` points, in the view plane through `at`.
pub fn view_plane_delta(camera: &OrbitCamera, height: f32, at: DVec3, delta: Vec2) -> DVec3 {
    let (right, up) = camera.right_up();
    let depth = (at.as_vec3() - camera.eye())
        .dot(-camera.backward())
        .max(1e-4);
    let per_point = 2.0 * depth * (camera.fov_y * 0.5).tan() / height.max(1.0);
    ((right * delta.x - up * delta.y) * per_point).as_dvec3()
}

impl TransformTool {
    /// Starts `mode` on the current selection with the pointer at `pointer` (screen points);
    /// `None` without a selection.
    pub fn begin(
        state: &EditorState,
        mode: Mode,
        pointer: Vec2,
        gesture: GestureId,
    ) -> Option<Self> {
        let pose = state.shown_positions();
        let start: Vec<(u32, DVec3)> = state
            .selection
            .vertices
            .iter()
            .filter_map(|&v| pose.get(v as usize).map(|p| (v, *p)))
            .collect();
        if start.is_empty() {
            return None;
        }
        // A whole control selected (the auto rig's `leg.L.2`) turns and scales about its
        // joint, carried where its parents moved it; the pivot-point setting says how the
        // origins of several combine.
        let elements = selection_elements(state, pose, &start);
        // As Blender: a control counts by its joint (a bone by its head), anything else by
        // its vertices.
        let points: Vec<DVec3> = elements
            .iter()
            .flat_map(|e| match e.joint {
                true => vec![e.origin],
                false => e.members.iter().map(|&k| start[k].1).collect(),
            })
            .collect();
        let centre = match state.view.pivot_point {
            PivotPoint::BoundingBoxCenter => {
                let (lo, hi) = points.iter().fold(
                    (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                    |(lo, hi), &p| (lo.min(p), hi.max(p)),
                );
                (lo + hi) * 0.5
            }
            PivotPoint::MedianPoint | PivotPoint::IndividualOrigins => {
                points.iter().sum::<DVec3>() / points.len().max(1) as f64
            }
            PivotPoint::Cursor => state.view.cursor.unwrap_or(DVec3::ZERO),
            PivotPoint::ActiveElement => {
                // The active vertex's element: a control by its joint, else the vertex.
                let active = state.selection.active;
                let index = active.and_then(|a| start.iter().position(|&(v, _)| v == a));
                match index {
                    Some(k) => elements
                        .iter()
                        .find(|e| e.joint && e.members.contains(&k))
                        .map_or(start[k].1, |e| e.origin),
                    // Nothing active: the median, as Blender falls back to.
                    None => points.iter().sum::<DVec3>() / points.len().max(1) as f64,
                }
            }
        };
        let origins = match state.view.pivot_point {
            PivotPoint::IndividualOrigins => {
                let mut origins = vec![centre; start.len()];
                for element in &elements {
                    for &k in &element.members {
                        origins[k] = element.origin;
                    }
                }
                origins
            }
            _ => vec![centre; start.len()],
        };
        Some(Self {
            origins,
            mode,
            axis: None,
            typed: String::new(),
            gesture,
            snap: None,
            start_pointer: pointer,
            centre,
            start,
        })
    }

    fn typed_value(&self) -> Option<f64> {
        self.typed.parse::<f64>().ok().filter(|v| v.is_finite())
    }

    /// How far the tool has gone for the pointer at `pointer` (screen points) in the viewport
    /// `rect`: the typed value when there is one, else the mouse's.
    pub fn amount(&self, camera: &OrbitCamera, rect: ScreenRect, pointer: Vec2) -> Amount {
        let size = rect.size;
        let centre_in_viewport = camera
            .project(self.centre.as_vec3(), size)
            .map_or(size * 0.5, |(p, _)| p);
        let start_in_viewport = rect.local(self.start_pointer) - centre_in_viewport;
        let pointer_in_viewport = rect.local(pointer) - centre_in_viewport;
        match self.mode {
            Mode::Grab => {
                let mut delta = match (self.typed_value(), self.snap) {
                    (Some(v), _) => self.axis.unwrap_or(Axis::X).vector() * v,
                    (None, Some((_, at))) => snap_delta(&self.start, at),
                    (None, None) => {
                        view_plane_delta(camera, size.y, self.centre, pointer - self.start_pointer)
                    }
                };
                if let Some(axis) = self.axis {
                    delta = axis.vector() * delta.dot(axis.vector());
                }
                Amount::Delta(delta)
            }
            Mode::Rotate => Amount::Degrees(self.typed_value().unwrap_or_else(|| {
                let (a, b) = (start_in_viewport, pointer_in_viewport);
                // Screen y points down: counter-clockwise on screen is negative here.
                f64::from(-(a.x * b.y - a.y * b.x).atan2(a.dot(b))).to_degrees()
            })),
            Mode::Scale => Amount::Factor(self.typed_value().unwrap_or_else(|| {
                let a = start_in_viewport.length().max(1.0);
                f64::from(pointer_in_viewport.length() / a)
            })),
        }
    }

    /// The moves for the pointer at `pointer` (screen points) in the viewport `rect`.
    pub fn moves(
        &self,
        camera: &OrbitCamera,
        rect: ScreenRect,
        pointer: Vec2,
    ) -> Vec<(u32, DVec3)> {
        let map: Box<dyn Fn(DVec3, DVec3) -> DVec3> = match self.amount(camera, rect, pointer) {
            Amount::Delta(delta) => Box::new(move |p, _| p + delta),
            Amount::Degrees(degrees) => {
                let axis = self
                    .axis
                    .map_or_else(|| camera.backward().as_dvec3(), Axis::vector);
                let turn = DQuat::from_axis_angle(axis, degrees.to_radians());
                Box::new(move |p, origin| origin + turn * (p - origin))
            }
            Amount::Factor(factor) => {
                let axis = self.axis.map(Axis::vector);
                Box::new(move |p, origin| match axis {
                    Some(a) => p + a * (p - origin).dot(a) * (factor - 1.0),
                    None => origin + (p - origin) * factor,
                })
            }
        };
        self.start
            .iter()
            .zip(&self.origins)
            .map(|(&(v, p), &origin)| (v, map(p, origin)))
            .collect()
    }

    /// The vertices being moved, by index.
    pub fn moving(&self) -> impl Iterator<Item = u32> + '_ {
        self.start.iter().map(|&(v, _)| v)
    }

    /// The pivot: the centre of the vertices being transformed (world, rest of the gesture).
    pub fn pivot(&self) -> DVec3 {
        self.centre
    }

    /// The header shown over the viewport while the tool runs, as Blender's: the mode, the
    /// axis, and the live amount or the typed value ("Grab along Z: 0.300").
    pub fn header(&self, amount: Amount) -> String {
        let name = match self.mode {
            Mode::Grab => "Grab",
            Mode::Rotate => "Rotate",
            Mode::Scale => "Scale",
        };
        let axis = match (self.axis, self.mode) {
            (Some(a), Mode::Rotate) => format!(" about {a:?}"),
            (Some(a), _) => format!(" along {a:?}"),
            (None, _) => String::new(),
        };
        let value = match amount {
            Amount::Delta(d) => match self.axis {
                Some(a) => format!("{:.3}", d.dot(a.vector())),
                None => format!("({:.3}, {:.3}, {:.3}), {:.3}", d.x, d.y, d.z, d.length()),
            },
            Amount::Degrees(a) => format!("{a:.1}°"),
            Amount::Factor(f) => format!("{f:.3}"),
        };
        let typed = if self.typed.is_empty() {
            String::new()
        } else {
            format!("  [typed {}]", self.typed)
        };
        let snapped = match self.snap {
            Some((v, _)) if self.typed.is_empty() && self.mode == Mode::Grab => {
                format!("  snapped to vertex {v}")
            }
            _ => String::new(),
        };
        format!("{name}{axis}: {value}{typed}{snapped}")
    }

    /// A one-line description for the status bar.
    pub fn describe(&self) -> String {
        let name = match self.mode {
            Mode::Grab => "Grab",
            Mode::Rotate => "Rotate",
            Mode::Scale => "Scale",
        };
        let axis = self.axis.map_or(String::new(), |a| format!(" along {a:?}"));
        let typed = if self.typed.is_empty() {
            String::new()
        } else {
            format!(": {}", self.typed)
        };
        format!(
            "{name}{axis}{typed} — X/Y/Z lock, type a number, Ctrl snaps to a vertex, Enter or click to confirm, Esc or right click to cancel"
        )
    }
}

/// One thing the selection holds whole (a control, another cage) or its loose vertices: the
/// indices into the tool's `start` it covers and the point it turns about.
struct Element {
    members: Vec<usize>,
    origin: DVec3,
    /// The origin is a control's joint.
    joint: bool,
}

/// The selection as elements: every internal cage wholly selected (a control's origin is its
/// joint, carried where its parents moved it; another's its centroid), then every leaf cage
/// wholly selected among the vertices left (its centroid), then the loose vertices (their
/// centroid). A vertex belongs to the first element that takes it: a control owns the next
/// control's box, so each box is taken by its own control, smallest first.
fn selection_elements(state: &EditorState, pose: &[DVec3], start: &[(u32, DVec3)]) -> Vec<Element> {
    let set = &state.doc.scene.cages;
    let index_of: std::collections::HashMap<u32, usize> = start
        .iter()
        .enumerate()
        .map(|(k, &(v, _))| (v, k))
        .collect();
    let mut taken = vec![false; start.len()];
    let mut elements = Vec::new();
    let mut candidates: Vec<(Vec<u32>, Option<&starcages_core::scene::InternalCage>)> = set
        .internals
        .iter()
        .filter_map(|cage| Some((set.cage_vertices(&cage.name)?, Some(cage))))
        .chain(
            set.leaves
                .iter()
                .filter_map(|leaf| Some((set.cage_vertices(&leaf.name)?, None))),
        )
        .collect();
    // Internal cages first, each before the larger ones that may hold its box.
    candidates.sort_by_key(|(vertices, cage)| (cage.is_none(), vertices.len()));
    for (vertices, cage) in candidates {
        let Some(members) = vertices
            .iter()
            .map(|v| index_of.get(v).copied().filter(|&k| !taken[k]))
            .collect::<Option<Vec<usize>>>()
        else {
            continue;
        };
        if members.is_empty() {
            continue;
        }
        let centroid = members.iter().map(|&k| start[k].1).sum::<DVec3>() / members.len() as f64;
        let joint = cage
            .filter(|c| c.pivot.is_some())
            .and_then(|c| starcages_core::hierarchy::posed_pivot(set, c, pose));
        for &k in &members {
            taken[k] = true;
        }
        elements.push(Element {
            members,
            origin: joint.unwrap_or(centroid),
            joint: joint.is_some(),
        });
    }
    let loose: Vec<usize> = (0..start.len()).filter(|&k| !taken[k]).collect();
    if !loose.is_empty() {
        let origin = loose.iter().map(|&k| start[k].1).sum::<DVec3>() / loose.len() as f64;
        elements.push(Element {
            members: loose,
            origin,
            joint: false,
        });
    }
    elements
}

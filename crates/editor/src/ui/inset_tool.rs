//! I in Rig mode: the inset of the selected faces, sized with the mouse before it is made, as
//! Blender's. The inner faces are previewed where they would go; moving the pointer toward the
//! faces' centre on screen thickens the inset, away from it thins it, or a typed thickness (scene
//! units) sets it; Enter or a click makes it (one undo step), Esc or a right click drops it.

use glam::{DVec3, Vec2};
use starcages_core::rig::{FaceRef, InsetCorners, RigOp};

use crate::state::EditorState;

/// The thickness when I is pressed, as a share of each face's shortest side.
const START_SHARE: f64 = 0.2;
/// The share is kept within these (half the shortest side folds a rectangle's inner face).
const SHARE_RANGE: (f64, f64) = (0.01, 0.49);
/// The least pointer distance from the centre (points) the share is scaled by, so a pointer
/// that starts on the centre does not make the inset jump.
const LEAST_DISTANCE: f32 = 40.0;

/// One face being inset.
#[derive(Debug, Clone, PartialEq)]
struct Face {
    cage: String,
    index: usize,
    corners: Vec<DVec3>,
    shortest_side: f64,
}

/// An inset being sized.
#[derive(Debug, Clone, PartialEq)]
pub struct InsetTool {
    faces: Vec<Face>,
    /// The thickness as a share of each face's shortest side (from the pointer).
    pub share: f64,
    /// A thickness typed in scene units, which overrides the pointer.
    pub typed: String,
    /// The pointer's distance from the faces' centre on screen when I was pressed.
    start_distance: f32,
}

impl InsetTool {
    /// The inset of the selected faces at a fifth of each one's shortest side, with the pointer
    /// at `pointer_in_view`; or why there is none (no face selected, or one shared).
    pub fn begin(state: &EditorState, pointer_in_view: Vec2) -> Result<Self, String> {
        let scene = &state.doc.scene;
        let faces: Vec<Face> = super::rig_keys::free_selected_faces(state, "I (inset)")?
            .into_iter()
            .map(|(c, index, corners)| {
                let corners: Vec<DVec3> = corners
                    .iter()
                    .filter_map(|&v| scene.cages.vertices.get(v as usize).copied())
                    .collect();
                let k = corners.len();
                let shortest_side = (0..k)
                    .map(|i| corners[i].distance(corners[(i + 1) % k]))
                    .fold(f64::INFINITY, f64::min);
                Face {
                    cage: scene.cages.leaves[c].name.clone(),
                    index,
                    corners,
                    shortest_side,
                }
            })
            .collect();
        let mut tool = Self {
            faces,
            share: START_SHARE,
            typed: String::new(),
            start_distance: LEAST_DISTANCE,
        };
        if let Some(centre) = tool.centre_on_screen(state) {
            tool.start_distance = pointer_in_view.distance(centre).max(LEAST_DISTANCE);
        }
        Ok(tool)
    }

    /// The centre of the faces on screen (view pixels), if it is in front of the camera.
    fn centre_on_screen(&self, state: &EditorState) -> Option<Vec2> {
        let points: Vec<DVec3> = self.faces.iter().flat_map(|f| f.corners.clone()).collect();
        let centre = points.iter().sum::<DVec3>() / points.len().max(1) as f64;
        let camera = &state.view.camera;
        camera
            .project(centre.as_vec3(), state.view.viewport.size)
            .map(|(q, _)| q)
    }

    /// Follows the pointer (view pixels): the share grows as it nears the faces' centre.
    pub fn follow(&mut self, state: &EditorState, pointer_in_view: Vec2) {
        let Some(centre) = self.centre_on_screen(state) else {
            return;
        };
        let distance = pointer_in_view.distance(centre).max(1.0);
        self.share = (START_SHARE * f64::from(self.start_distance / distance))
            .clamp(SHARE_RANGE.0, SHARE_RANGE.1);
    }

    /// The thickness of one face: the typed one, or the share of its shortest side.
    fn thickness(&self, face: &Face) -> f64 {
        match self.typed.parse::<f64>() {
            Ok(typed) if typed > 0.0 => typed,
            _ => self.share * face.shortest_side,
        }
    }

    /// The inner faces as they would be (rest positions), one polygon per face that the
    /// thickness fits.
    pub fn inner_faces(&self) -> Vec<Vec<DVec3>> {
        self.faces
            .iter()
            .filter_map(|f| {
                let inset = InsetCorners::new(&f.corners, self.thickness(f)).ok()?;
                Some(inset.place(&f.corners))
            })
            .collect()
    }

    /// The rig operations that make the inset (applied together, one undo step).
    pub fn operations(&self) -> Vec<RigOp> {
        self.faces
            .iter()
            .map(|f| RigOp::Inset {
                cage: f.cage.clone(),
                face: FaceRef::Index(f.index),
                thickness: self.thickness(f),
            })
            .collect()
    }

    /// Whether every face it insets is still there (an undo or another edit may remove it).
    pub fn is_valid_for(&self, state: &EditorState) -> bool {
        let set = &state.doc.scene.cages;
        self.faces.iter().all(|f| {
            set.leaf_index(&f.cage)
                .and_then(|c| set.leaves[c].faces.get(f.index))
                .is_some()
        })
    }

    /// The header over the viewport.
    pub fn header(&self) -> String {
        let amount = match self.typed.parse::<f64>() {
            Ok(t) if t > 0.0 => format!("thickness {t}  [typed]"),
            _ => format!("{:.0} % of each face's shortest side", 100.0 * self.share),
        };
        let faces = match self.faces.len() {
            1 => "1 face".to_owned(),
            n => format!("{n} faces"),
        };
        format!("Inset {faces}: {amount}")
    }

    /// The status bar's hint.
    pub fn describe(&self) -> String {
        "Inset — move the mouse toward the faces to thicken it, away to thin it, or type a \
         thickness; Enter or click to inset, Esc or right click to cancel"
            .to_owned()
    }
}

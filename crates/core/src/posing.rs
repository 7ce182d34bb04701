//! The one posing engine: what cage positions, hierarchy state and keyed h a request for a
//! pose gives. The CLI (`--pose`, `--frame`, `--pose-file`, `--apply`), the bake and the
//! editor's timeline all pose through [`PoseRequest::resolve`], so a frame means the same
//! thing everywhere.

use std::collections::BTreeMap;

use glam::DVec3;

use crate::hierarchy::{CageEdit, EditError, Hierarchy, HierarchyError};
use crate::scene::{HierarchyState, MAX_COORDINATE, Scene};

/// Where a pose starts, before any edit.
#[derive(Debug, Clone, PartialEq)]
pub enum PoseSource {
    /// The rest cages.
    Rest,
    /// A pose stored in the scene by name; `None` is the current pose. Its stored hierarchy
    /// state comes with it.
    Named(Option<String>),
    /// The scene's animation at a frame (fractions allowed). On a key, the key's pose comes
    /// with its stored hierarchy state; between keys the interpolated cages start from the
    /// rest state. Keyed h comes with either.
    Frame(f64),
    /// Cage positions from outside the scene (a pose file), in scene coordinates and the
    /// scene's vertex order. Positions carry no hierarchy state: they start from rest.
    Positions(Vec<DVec3>),
}

/// A pose asked for: a source and hand edits on top, applied in order and propagated down the
/// cage hierarchy.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseRequest {
    /// Where the pose starts.
    pub source: PoseSource,
    /// Hand edits on top (`--apply`).
    pub edits: Vec<CageEdit>,
}

/// A resolved pose.
#[derive(Debug, Clone, PartialEq)]
pub struct Pose {
    /// Every cage vertex (leaf and internal), in scene coordinates.
    pub cages: Vec<DVec3>,
    /// The hierarchy state the cages were posed in (after the edits).
    pub state: HierarchyState,
    /// h per leaf cage name as keyed at the frame (empty for other sources): it shapes the
    /// operator, so a caller binds with it ([`Scene::apply_keyed_h`]).
    pub h: BTreeMap<String, f64>,
}

impl Pose {
    /// `cages` in the rest hierarchy state, with no keyed h.
    fn at_rest_state(cages: Vec<DVec3>) -> Self {
        Self {
            cages,
            state: HierarchyState::default(),
            h: BTreeMap::new(),
        }
    }
}

/// Why a request gives no pose.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PoseError {
    /// No stored pose has the name.
    #[error("no pose named '{name}'; known poses: {known}")]
    UnknownPose {
        /// The name asked for.
        name: String,
        /// The scene's pose names, comma-separated, or "none".
        known: String,
    },
    /// A frame that is not a number.
    #[error("frame {frame}: give a finite frame number")]
    NonFiniteFrame {
        /// The frame.
        frame: f64,
    },
    /// A frame asked of a scene without keys.
    #[error(
        "the scene has no animation keys; key poses in the editor (I on the timeline) or add \
         \"animation\" keys to the file (docs/scene-format.md)"
    )]
    NoKeys,
    /// Keys that name missing or malformed poses (a scene that does not validate).
    #[error("the animation's keys name missing or malformed poses; run `starcages-cli validate`")]
    BrokenKeys,
    /// Positions from outside with another vertex count.
    #[error("the pose has {found} cage vertices where the scene has {expected}")]
    VertexCount {
        /// The scene's cage vertex count.
        expected: usize,
        /// The pose's.
        found: usize,
    },
    /// An edit that names no cage or cannot be read.
    #[error(transparent)]
    Edit(#[from] EditError),
    /// The hierarchy could not be bound or refused the edit.
    #[error(transparent)]
    Hierarchy(#[from] HierarchyError),
    /// A cage vertex not finite or beyond ±[`MAX_COORDINATE`] (the deformation runs in 32-bit
    /// floats: beyond it a mesh comes out at 1e19 or worse).
    #[error(
        "{}",
        far_message(if *by_edits { "the edits" } else { "the pose" }, *vertex, *position)
    )]
    Far {
        /// The cage vertex.
        vertex: usize,
        /// Where it went.
        position: DVec3,
        /// Whether the edits put it there (else the pose itself).
        by_edits: bool,
    },
}

impl PoseRequest {
    /// A request without edits.
    pub fn new(source: PoseSource) -> Self {
        Self {
            source,
            edits: Vec::new(),
        }
    }

    /// The scene's animation at `frame`, without edits.
    pub fn frame(frame: f64) -> Self {
        Self::new(PoseSource::Frame(frame))
    }

    /// The cage positions, hierarchy state and keyed h this request gives for `scene`.
    pub fn resolve(&self, scene: &Scene) -> Result<Pose, PoseError> {
        self.resolve_with(scene, None)
    }

    /// [`PoseRequest::resolve`] with `scene`'s hierarchy already bound (validation's, in any
    /// state): edits go through a copy of it instead of a new bind.
    pub fn resolve_with(
        &self,
        scene: &Scene,
        bound: Option<&Hierarchy>,
    ) -> Result<Pose, PoseError> {
        let start = self.start(scene)?;
        within_range(&start.cages, false)?;
        if self.edits.is_empty() {
            return Ok(start);
        }
        let Pose {
            mut cages,
            state,
            h,
            ..
        } = start;
        let mut hierarchy = match bound {
            Some(bound) => {
                let mut hierarchy = bound.clone();
                hierarchy.restore(&state)?;
                hierarchy
            }
            None => Hierarchy::bind_in_state(scene, &state)?,
        };
        for edit in &self.edits {
            let moves = edit.moves(&scene.cages, &cages)?;
            hierarchy.apply(&mut cages, &moves)?;
        }
        within_range(&cages, true)?;
        Ok(Pose {
            cages,
            state: hierarchy.state(),
            h,
        })
    }

    /// The source's cages, hierarchy state and keyed h, before the edits.
    fn start(&self, scene: &Scene) -> Result<Pose, PoseError> {
        let expected = scene.cages.vertices.len();
        match &self.source {
            PoseSource::Rest => Ok(Pose::at_rest_state(scene.cages.vertices.clone())),
            PoseSource::Named(name) => {
                let cages = scene.pose_named(name.as_deref()).ok_or_else(|| {
                    let known: Vec<&str> = scene.poses.keys().map(String::as_str).collect();
                    PoseError::UnknownPose {
                        name: name.clone().unwrap_or_default(),
                        known: if known.is_empty() {
                            "none".to_owned()
                        } else {
                            known.join(", ")
                        },
                    }
                })?;
                Ok(Pose {
                    cages: cages.to_vec(),
                    state: scene.pose_state_named(name.as_deref()),
                    h: BTreeMap::new(),
                })
            }
            &PoseSource::Frame(frame) => {
                if !frame.is_finite() {
                    return Err(PoseError::NonFiniteFrame { frame });
                }
                let animation = &scene.animation;
                if animation.is_empty() {
                    return Err(PoseError::NoKeys);
                }
                let cages = animation
                    .pose_at(&scene.poses, frame)
                    .filter(|cages| cages.len() == expected)
                    .ok_or(PoseError::BrokenKeys)?;
                let state = animation
                    .key_at(frame)
                    .and_then(|k| animation.keys.get(k))
                    .and_then(|key| scene.pose_states.get(&key.pose))
                    .cloned()
                    .unwrap_or_default();
                Ok(Pose {
                    cages,
                    state,
                    h: animation.h_at(frame),
                })
            }
            PoseSource::Positions(cages) => {
                if cages.len() != expected {
                    return Err(PoseError::VertexCount {
                        expected,
                        found: cages.len(),
                    });
                }
                Ok(Pose::at_rest_state(cages.clone()))
            }
        }
    }
}

/// What [`PoseError::Far`] says, with `source` naming what put the vertex there ("the edits",
/// "the pose", or a caller's own words such as a file).
pub fn far_message(source: &str, vertex: usize, position: DVec3) -> String {
    format!(
        "{source} put cage vertex {vertex} at ({:e}, {:e}, {:e}), beyond ±{MAX_COORDINATE:e} \
         (the deformation runs in 32-bit floats); use a smaller move, scale or pose",
        position.x, position.y, position.z
    )
}

/// Refuses a cage vertex that is not finite or beyond ±[`MAX_COORDINATE`].
fn within_range(cages: &[DVec3], by_edits: bool) -> Result<(), PoseError> {
    match cages
        .iter()
        .position(|p| !(p.is_finite() && p.abs().max_element() <= MAX_COORDINATE))
    {
        Some(vertex) => Err(PoseError::Far {
            vertex,
            position: cages[vertex],
            by_edits,
        }),
        None => Ok(()),
    }
}

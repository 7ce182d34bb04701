//! Validation of a whole scene: the model's own rules ([`crate::scene::check_model`]) and the
//! dry runs of the engine that must succeed for a scene to deform: the *Cages topology built
//! (kept, so that the bind does not build it again) and the hierarchy bound and restored in
//! every stored state.

use std::sync::Arc;

use crate::coords::BindControl;
use crate::hierarchy::Hierarchy;
use crate::scene::{Scene, SceneProblem, ValidationReport, check_model};
use crate::star::{StarBinding, StarError, Topology};

/// A scene's validation and, when it is valid, the topology the bind needs.
#[derive(Debug, Clone)]
pub struct CheckedScene {
    /// Problems and warnings.
    pub report: ValidationReport,
    /// The scene's *Cages topology, built where the model's rules passed.
    pub topology: Option<Arc<Topology>>,
    /// The hierarchy as the dry run bound it (in the current pose's state), where the scene
    /// is valid: posing takes a copy instead of binding it again.
    pub hierarchy: Option<Hierarchy>,
}

impl CheckedScene {
    /// Whether the scene is valid.
    pub fn is_valid(&self) -> bool {
        self.report.is_valid()
    }

    /// Binds `scene` (the scene this checked) with the topology built here, or builds it when
    /// the check did not.
    pub fn bind(&self, scene: &Scene, control: &BindControl) -> Result<StarBinding, StarError> {
        match &self.topology {
            Some(topology) => StarBinding::bind_scene_with(scene, topology, control),
            None => StarBinding::bind_scene(scene, control),
        }
    }
}

/// Validates the whole scene: the model's rules, then the engine's dry runs.
pub fn check_scene(scene: &Scene) -> CheckedScene {
    let mut report = check_model(scene);
    let mut topology = None;
    if report.errors.is_empty() {
        match Topology::new(&scene.cages, scene.settings.join_coordinates) {
            Ok(built) => topology = Some(Arc::new(built)),
            Err(e) => report.errors.push(SceneProblem::Topology(e.to_string())),
        }
    }
    let mut hierarchy = None;
    if report.errors.is_empty() && !scene.cages.internals.is_empty() {
        hierarchy = check_pose_states(scene, &mut report.errors);
    }
    if !report.errors.is_empty() {
        topology = None;
        hierarchy = None;
    }
    CheckedScene {
        report,
        topology,
        hierarchy,
    }
}

/// Validates the whole scene: [`check_scene`]'s report.
pub fn validate_scene(scene: &Scene) -> ValidationReport {
    check_scene(scene).report
}

/// Binds the hierarchy and restores every stored hierarchy state, as `deform` and the editor
/// will: a record naming a vertex that has no parent, a parent shape of the wrong size or a
/// state that cannot be rebuilt is reported here rather than refused later.
fn check_pose_states(scene: &Scene, errors: &mut Vec<SceneProblem>) -> Option<Hierarchy> {
    // Binding restores the current pose's state: when that fails, bind at rest to tell a bad
    // state from a bad hierarchy.
    let mut hierarchy = match Hierarchy::bind(scene) {
        Ok(h) => h,
        Err(e) => {
            let (pose, rest) = match Hierarchy::bind_in_state(scene, &Default::default()) {
                Ok(h) => ("the current pose", Some(h)),
                Err(_) => ("every pose", None),
            };
            errors.push(SceneProblem::PoseState {
                pose: pose.into(),
                why: e.to_string(),
            });
            rest?
        }
    };
    let named = scene
        .pose_states
        .iter()
        .map(|(n, s)| (format!("pose '{n}'"), s));
    for (pose, state) in
        std::iter::once(("the current pose".to_owned(), &scene.pose_state)).chain(named)
    {
        if let Err(e) = hierarchy.restore(state) {
            errors.push(SceneProblem::PoseState {
                pose,
                why: e.to_string(),
            });
        }
    }
    // Kept in the current pose's state, as a fresh bind would be.
    hierarchy.restore(&scene.pose_state).ok()?;
    Some(hierarchy)
}

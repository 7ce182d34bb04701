//! Options shared by the commands that deform: which pose, which method.

use std::path::PathBuf;

use clap::Args;
use glam::DVec3;
use starcages_core::coords::CoordinateKind;
use starcages_core::hierarchy::{CageEdit, Hierarchy};
use starcages_core::io::read_pose_obj;
use starcages_core::scene::{HierarchyState, Scene};
use starcages_core::star::single_cage_scene;

use crate::InputError;

/// Pose and method options.
#[derive(Debug, Args)]
pub struct PoseArgs {
    /// A named pose stored in the scene (default: the scene's current pose).
    #[arg(long, conflicts_with = "pose_file")]
    pose: Option<String>,
    /// The scene's animation at this frame (fractions allowed): cage vertices and keyed h
    /// interpolated between its keys.
    #[arg(long, conflicts_with_all = ["pose", "pose_file"], allow_negative_numbers = true)]
    frame: Option<f64>,
    /// A cage OBJ with the scene's vertex order (as written by `starcages-cli cages`).
    #[arg(long)]
    pose_file: Option<PathBuf>,
    /// Deform with one cage (the union of the leaf cages) of this kind instead of *Cages: the
    /// single-cage baseline.
    #[arg(long, value_parser = |s: &str| s.parse::<CoordinateKind>())]
    single_cage: Option<CoordinateKind>,
    /// A hand edit on top of the pose, repeatable and applied in order, propagating down the
    /// cage hierarchy: "CAGE: translate X Y Z", "CAGE: rotate AX AY AZ DEG" (about the cage's
    /// centroid) or "CAGE: scale S" (about the centroid).
    #[arg(long = "apply", value_name = "EDIT", value_parser = |s: &str| s.parse::<CageEdit>())]
    edits: Vec<CageEdit>,
}

impl PoseArgs {
    /// The pose file given, if any (an input no output may overwrite).
    pub fn pose_file(&self) -> Option<&std::path::Path> {
        self.pose_file.as_deref()
    }

    /// Loads and validates the scene at `path` (problems printed, an input error if invalid),
    /// and returns the scene to bind, the posed cage vertices and the file's label.
    pub fn load_posed(
        &self,
        path: &std::path::Path,
    ) -> anyhow::Result<(Scene, Vec<DVec3>, String)> {
        let mut scene = super::load(path)?;
        let label = path.display().to_string();
        if !super::report(&scene, &label).is_valid() {
            return Err(InputError(format!(
                "{label}: the scene does not validate; see the problems above"
            ))
            .into());
        }
        if let Some(frame) = self.frame {
            // h keyed at this frame shapes the operator: the scene is bound with it.
            let h = scene.animation.h_at(frame);
            starcages_core::anim::bake::apply_keyed_h(&mut scene, &h);
        }
        let posed = self.positions(&scene, path)?;
        Ok((self.method_scene(scene), posed, label))
    }

    /// The scene to bind: the scene itself, or its single-cage baseline.
    pub fn method_scene(&self, scene: Scene) -> Scene {
        match self.single_cage {
            Some(kind) => single_cage_scene(&scene, kind),
            None => scene,
        }
    }

    /// Posed cage vertices: the chosen pose with the `--apply` edits on top. A pose file
    /// carries positions only, so its hierarchy starts from the rest state.
    pub fn positions(
        &self,
        scene: &Scene,
        scene_path: &std::path::Path,
    ) -> anyhow::Result<Vec<DVec3>> {
        let (mut pose, state) = match (&self.pose_file, self.frame) {
            (None, Some(frame)) => (
                frame_pose(scene, frame, scene_path)?,
                HierarchyState::default(),
            ),
            (Some(file), _) => (
                // Written by `cages` in the mesh file's axes: turned back to the scene's.
                read_pose_obj(file, scene.cages.vertices.len())?
                    .into_iter()
                    .map(|p| scene.export_up().to_scene(p))
                    .collect(),
                HierarchyState::default(),
            ),
            (None, None) => (
                named_pose(scene, self.pose.as_deref(), scene_path)?,
                scene.pose_state_named(self.pose.as_deref()),
            ),
        };
        if self.edits.is_empty() {
            return self.within_range(pose);
        }
        let label = scene_path.display();
        let mut posed = scene.clone();
        posed.pose_state = state;
        let mut hierarchy =
            Hierarchy::bind(&posed).map_err(|e| InputError(format!("{label}: {e}")))?;
        for edit in &self.edits {
            let moves = edit
                .moves(&scene.cages, &pose)
                .map_err(|e| InputError(format!("{label}: {e}")))?;
            hierarchy
                .apply(&mut pose, &moves)
                .map_err(|e| InputError(format!("{label}: {e}")))?;
        }
        self.within_range(pose)
    }

    /// `pose` when every coordinate is finite and within the documented ±1e9 (the deformation
    /// runs in 32-bit floats: beyond it a mesh comes out at 1e19 or worse), else an input
    /// error naming the vertex and where the pose came from.
    fn within_range(&self, pose: Vec<DVec3>) -> anyhow::Result<Vec<DVec3>> {
        use starcages_core::scene::MAX_COORDINATE;
        let far = pose
            .iter()
            .position(|p| !(p.is_finite() && p.abs().max_element() <= MAX_COORDINATE));
        let Some(vertex) = far else {
            return Ok(pose);
        };
        let source = match (&self.pose_file, self.edits.is_empty()) {
            (Some(file), true) => format!("the pose file {}", file.display()),
            (_, false) => "the --apply edits".to_owned(),
            (None, true) => "the pose".to_owned(),
        };
        Err(InputError(format!(
            "{source} put cage vertex {vertex} at ({:e}, {:e}, {:e}), beyond ±{MAX_COORDINATE:e} \
             (the deformation runs in 32-bit floats); use a smaller move, scale or pose",
            pose[vertex].x, pose[vertex].y, pose[vertex].z
        ))
        .into())
    }
}

/// The positions of pose `name` (the current pose for `None`), or an input error listing the
/// scene's poses.
pub fn named_pose(
    scene: &Scene,
    name: Option<&str>,
    scene_path: &std::path::Path,
) -> anyhow::Result<Vec<DVec3>> {
    let pose = scene.pose_named(name).ok_or_else(|| {
        let known: Vec<&str> = scene.poses.keys().map(String::as_str).collect();
        InputError(format!(
            "{}: no pose named '{}'; known poses: {}",
            scene_path.display(),
            name.unwrap_or_default(),
            if known.is_empty() {
                "none".to_owned()
            } else {
                known.join(", ")
            }
        ))
    })?;
    Ok(pose.to_vec())
}

/// The cage vertices at `frame` of the scene's animation, or an input error when it has no
/// keys.
pub fn frame_pose(
    scene: &Scene,
    frame: f64,
    scene_path: &std::path::Path,
) -> anyhow::Result<Vec<DVec3>> {
    if !frame.is_finite() {
        return Err(InputError(format!("--frame {frame}: give a finite frame number")).into());
    }
    if scene.animation.is_empty() {
        return Err(InputError(format!(
            "{}: the scene has no animation keys; key poses in the editor (I on the timeline) or \
             add \"animation\" keys to the file (docs/scene-format.md)",
            scene_path.display()
        ))
        .into());
    }
    scene.animation.pose_at(&scene.poses, frame).ok_or_else(|| {
        InputError(format!(
            "{}: the animation's keys name missing or malformed poses; run `starcages-cli \
                 validate`",
            scene_path.display()
        ))
        .into()
    })
}

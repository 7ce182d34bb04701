//! Options shared by the commands that deform: which pose, which method.

use std::path::PathBuf;

use clap::Args;
use glam::DVec3;
use starcages_core::coords::CoordinateKind;
use starcages_core::io::read_pose_obj;
use starcages_core::scene::Scene;
use starcages_core::star::single_cage_scene;

use crate::InputError;

/// Pose and method options.
#[derive(Debug, Args)]
pub struct PoseArgs {
    /// A named pose stored in the scene (default: the scene's current pose).
    #[arg(long, conflicts_with = "pose_file")]
    pose: Option<String>,
    /// A cage OBJ with the scene's vertex order (as written by `starcages-cli cages`).
    #[arg(long)]
    pose_file: Option<PathBuf>,
    /// Deform with one cage (the union of the leaf cages) of this kind instead of *Cages: the
    /// single-cage baseline.
    #[arg(long, value_parser = |s: &str| s.parse::<CoordinateKind>())]
    single_cage: Option<CoordinateKind>,
}

impl PoseArgs {
    /// The scene to bind: the scene itself, or its single-cage baseline.
    pub fn method_scene(&self, scene: Scene) -> Scene {
        match self.single_cage {
            Some(kind) => single_cage_scene(&scene, kind),
            None => scene,
        }
    }

    /// Posed cage vertices.
    pub fn positions(
        &self,
        scene: &Scene,
        scene_path: &std::path::Path,
    ) -> anyhow::Result<Vec<DVec3>> {
        if let Some(file) = &self.pose_file {
            return Ok(read_pose_obj(file, scene.cages.vertices.len())?);
        }
        named_pose(scene, self.pose.as_deref(), scene_path)
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

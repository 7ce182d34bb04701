//! Options shared by the commands that deform: which pose, which method.

use std::path::PathBuf;
use std::sync::Arc;

use clap::Args;
use glam::DVec3;
use starcages_core::coords::CoordinateKind;
use starcages_core::hierarchy::CageEdit;
use starcages_core::joint_volume::JointVolumes;
use starcages_core::posing::{Pose, PoseError, PoseRequest, PoseSource, far_message};
use starcages_core::scene::Scene;
use starcages_core::star::{StarBinding, Topology, single_cage_scene};
use starcages_io::read_pose_obj;

use crate::InputError;

/// A loaded, validated scene in the pose asked for.
pub struct PosedScene {
    /// The scene to bind (keyed h applied; the single-cage baseline where asked).
    pub scene: Scene,
    /// Posed cage vertices.
    pub cages: Vec<DVec3>,
    /// The scene file's name, for messages.
    pub label: String,
    /// The scene's topology as validation built it, for the bind.
    pub topology: Option<Arc<Topology>>,
    /// With `--apply` edits, the vertices moved by hand (which the joints' volume pass leaves
    /// alone); None for a pose taken as stored.
    pub edited: Option<Vec<u32>>,
}

/// An edited pose's bent joints settled to their rest volume through `binding` (the scene's
/// mesh binding, core's [`JointVolumes`]), the vertices in `hand_moved` (sorted) left alone. A
/// stored pose, a frame or a pose file is taken as it is: the editor settled its poses when
/// they were made.
pub fn keep_joint_volumes(
    scene: &Scene,
    binding: &StarBinding,
    posed: &mut [DVec3],
    hand_moved: &[u32],
) {
    let volumes = JointVolumes::new(
        &scene.cages,
        scene.mesh.welded_triangles(),
        &binding.operator,
    );
    volumes.settle(&binding.operator, posed, None, &|v| {
        hand_moved.binary_search(&v).is_ok()
    });
}

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
    /// centroid, or a control's pivot) or "CAGE: scale S" (about the same point); every joint
    /// the edits bend keeps its volume.
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
    pub fn load_posed(&self, path: &std::path::Path) -> anyhow::Result<PosedScene> {
        let mut scene = super::load(path)?;
        let label = path.display().to_string();
        let checked = super::report(&scene, &label);
        if !checked.is_valid() {
            return Err(InputError(format!(
                "{label}: the scene does not validate; see the problems above"
            ))
            .into());
        }
        let pose = self.resolve_with(&scene, checked.hierarchy.as_ref(), path)?;
        let edited = (!self.edits.is_empty()).then(|| pose.state.hand_moved.clone());
        // h keyed at a frame shapes the operator: the scene is bound with it.
        scene.apply_keyed_h(&pose.h);
        // The topology validation built is the bind's, unless the bind takes the single-cage
        // baseline instead (keyed h does not change it).
        let topology = checked.topology.filter(|_| self.single_cage.is_none());
        Ok(PosedScene {
            scene: self.method_scene(scene),
            cages: pose.cages,
            label,
            topology,
            edited,
        })
    }

    /// The scene to bind: the scene itself, or its single-cage baseline.
    pub fn method_scene(&self, scene: Scene) -> Scene {
        match self.single_cage {
            Some(kind) => single_cage_scene(&scene, kind),
            None => scene,
        }
    }

    /// Posed cage vertices: the chosen pose with the `--apply` edits on top, and with edits,
    /// the vertices moved by hand (as [`PosedScene::edited`]).
    pub fn positions(
        &self,
        scene: &Scene,
        scene_path: &std::path::Path,
    ) -> anyhow::Result<(Vec<DVec3>, Option<Vec<u32>>)> {
        let pose = self.resolve_with(scene, None, scene_path)?;
        let edited = (!self.edits.is_empty()).then_some(pose.state.hand_moved);
        Ok((pose.cages, edited))
    }

    /// The pose these options ask for, through core's posing engine. A pose file carries
    /// positions only, so its hierarchy starts from the rest state.
    fn resolve_with(
        &self,
        scene: &Scene,
        bound: Option<&starcages_core::hierarchy::Hierarchy>,
        scene_path: &std::path::Path,
    ) -> anyhow::Result<Pose> {
        let source = match (&self.pose_file, self.frame) {
            (Some(file), _) => PoseSource::Positions(
                // Written by `cages` in the mesh file's axes: turned back to the scene's.
                read_pose_obj(file, scene.cages.vertices.len())?
                    .into_iter()
                    .map(|p| scene.export_up().to_scene(p))
                    .collect(),
            ),
            (None, Some(frame)) => PoseSource::Frame(frame),
            (None, None) => PoseSource::Named(self.pose.clone()),
        };
        let request = PoseRequest {
            source,
            edits: self.edits.clone(),
        };
        request.resolve_with(scene, bound).map_err(|error| {
            let message = match (&error, &self.pose_file) {
                (
                    &PoseError::Far {
                        vertex,
                        position,
                        by_edits,
                    },
                    file,
                ) => {
                    let source = match (by_edits, file) {
                        (true, _) => "the --apply edits".to_owned(),
                        (false, Some(file)) => format!("the pose file {}", file.display()),
                        (false, None) => "the pose".to_owned(),
                    };
                    far_message(&source, vertex, position)
                }
                (PoseError::NonFiniteFrame { frame }, _) => {
                    format!("--frame {frame}: give a finite frame number")
                }
                _ => format!("{}: {error}", scene_path.display()),
            };
            InputError(message).into()
        })
    }
}

/// The pose `request` gives, or an input error naming the scene file.
pub fn resolve(
    scene: &Scene,
    request: &PoseRequest,
    scene_path: &std::path::Path,
) -> anyhow::Result<Pose> {
    request
        .resolve(scene)
        .map_err(|e| InputError(format!("{}: {e}", scene_path.display())).into())
}

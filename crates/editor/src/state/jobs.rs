//! Work off the UI thread: binding, the difference map's single-cage baseline, opening files.
//! Each runs on a worker thread with progress and cancel; dropping a [`Job`] cancels it, so a
//! job that became stale (a newer edit, a replaced document) stops using the cores.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::Instant;

use starcages_core::BindControl;
use starcages_core::coords::CoordinateKind;
use starcages_core::hierarchy::Hierarchy;
use starcages_core::joint_volume::JointVolumes;
use starcages_core::scene::{CageSet, JoinPolicy, Scene, SceneSettings};
use starcages_core::star::{StarBinding, Topology, single_cage_scene};

use super::{Document, EditorError};

/// Called from a worker when it finishes (the app asks egui to repaint).
pub type Waker = Arc<dyn Fn() + Send + Sync>;

/// A piece of work on a worker thread. Dropping it cancels the work.
pub struct Job<T> {
    control: Arc<BindControl>,
    receiver: Receiver<T>,
    /// What it does, for the status bar.
    pub label: String,
    /// When it started.
    pub started: Instant,
    what: &'static str,
}

impl<T> std::fmt::Debug for Job<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Job")
            .field("label", &self.label)
            .field("progress", &self.progress())
            .finish_non_exhaustive()
    }
}

impl<T: Send + 'static> Job<T> {
    /// Runs `work` on a new thread; it gets the job's progress-and-cancel control. `wake` is
    /// called when it ends. `what` names the worker in errors.
    pub fn spawn(
        what: &'static str,
        label: impl Into<String>,
        wake: Option<Waker>,
        work: impl FnOnce(&BindControl) -> T + Send + 'static,
    ) -> Self {
        let control = Arc::new(BindControl::default());
        let (sender, receiver) = channel();
        let worker_control = Arc::clone(&control);
        std::thread::spawn(move || {
            sender.send(work(&worker_control)).ok();
            if let Some(wake) = wake {
                wake();
            }
        });
        Self {
            control,
            receiver,
            label: label.into(),
            started: Instant::now(),
            what,
        }
    }
}

impl<T> Job<T> {
    /// Asks the worker to stop (a bind then ends with a cancellation error).
    pub fn cancel(&self) {
        self.control.cancel();
    }

    /// The job's progress-and-cancel control (to watch it after the job is gone).
    pub fn control(&self) -> Arc<BindControl> {
        Arc::clone(&self.control)
    }

    /// Whether cancel was asked for.
    pub fn is_cancelled(&self) -> bool {
        self.control.is_cancelled()
    }

    /// Fraction of the work done, in [0, 1].
    pub fn progress(&self) -> f64 {
        self.control.progress()
    }

    /// The result once the worker is done, without blocking.
    pub fn poll(&self) -> Option<Result<T, EditorError>> {
        match self.receiver.try_recv() {
            Ok(result) => Some(Ok(result)),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(EditorError::WorkerLost(self.what))),
        }
    }

    /// Blocks until the worker is done (tests and headless use).
    pub fn wait(&self) -> Result<T, EditorError> {
        self.receiver
            .recv()
            .map_err(|_| EditorError::WorkerLost(self.what))
    }
}

impl<T> Drop for Job<T> {
    fn drop(&mut self) {
        self.control.cancel();
    }
}

/// How much to bind again: core's [`starcages_core::live::RebindScope`], whose `Full` the
/// editor asks for itself.
pub use starcages_core::live::RebindScope as Scope;

/// What a finished bind delivers.
#[derive(Debug)]
pub struct Bound {
    /// The mesh binding.
    pub binding: Arc<StarBinding>,
    /// The internal-cage hierarchy.
    pub hierarchy: Hierarchy,
    /// Wall seconds of the whole bind.
    pub seconds: f64,
    /// The edit generation it was started for.
    pub generation: u64,
    /// The cages and settings it was bound for.
    pub bound_for: (CageSet, SceneSettings),
    /// A quick bind with mean value join cages where the scene's settings ask for harmonic
    /// ones, or with harmonic leaf cages at the preview resolution: usable at once, refined by
    /// a bind that follows.
    pub preview: bool,
    /// The leaf cages a quick leaf bind bound coarsely (empty for a join-cage preview): their
    /// rows are what the refinement binds again.
    pub coarse_leaves: Vec<usize>,
    /// The joints' regions in the bound mesh (built here, off the UI thread, where the scene
    /// has controls with joint rings), for the rig's volume-keeping joints.
    pub joint_volumes: Option<JointVolumes>,
}

/// What validation built for the scene being bound: a bind takes them instead of building them
/// again.
#[derive(Debug, Default)]
pub struct Checked<'a> {
    /// The scene's topology (a full or preview bind takes it).
    pub topology: Option<&'a Topology>,
    /// The scene's hierarchy, bound by validation's dry run.
    pub hierarchy: Option<Hierarchy>,
}

/// Binds `scene` as far as `scope` says (runs on a worker), with what validation built where
/// given (`checked`).
pub fn bind(
    scene: &Scene,
    checked: Checked<'_>,
    scope: Scope,
    generation: u64,
    control: &BindControl,
) -> Result<Bound, EditorError> {
    let start = Instant::now();
    let topology = checked.topology;
    let mut preview = matches!(scope, Scope::Preview) && has_harmonic_join_cages(scene, topology);
    let mut coarse_leaves = Vec::new();
    let binding = match scope {
        Scope::Preview if preview => {
            let mut quick = scene.clone();
            quick.settings.join_coordinates = JoinPolicy::Mvc;
            StarBinding::bind_scene(&quick, control).map(Arc::new)
        }
        Scope::Full | Scope::Preview => match topology {
            Some(topology) => StarBinding::bind_scene_with(scene, topology, control),
            None => StarBinding::bind_scene(scene, control),
        }
        .map(Arc::new),
        Scope::Leaves(old, leaves, quick) if quick && turns_harmonic(scene, &leaves) => {
            // A harmonic leaf at full resolution is one large grid solve: bind it coarsely
            // first, so the change shows at once.
            let mut coarse = scene.clone();
            coarse.settings.harmonic = scene.settings.harmonic.preview();
            preview = true;
            coarse_leaves = leaves.clone();
            old.rebind_leaves(&coarse, &leaves, control).map(Arc::new)
        }
        Scope::Leaves(old, leaves, _) => old.rebind_leaves(scene, &leaves, control).map(Arc::new),
        Scope::Hierarchy(old) => Ok(old),
        Scope::RestEdit(old, moved) => old.rebind_rest_edit(scene, &moved, control).map(Arc::new),
    }
    .map_err(EditorError::Bind)?;
    let hierarchy = match checked.hierarchy {
        Some(hierarchy) => hierarchy,
        None => Hierarchy::bind(scene).map_err(EditorError::Hierarchy)?,
    };
    let joint_volumes = scene
        .cages
        .internals
        .iter()
        .any(|c| !c.joint.is_empty())
        .then(|| {
            JointVolumes::new(
                &scene.cages,
                scene.mesh.welded_triangles(),
                &binding.operator,
            )
        });
    Ok(Bound {
        binding,
        hierarchy,
        seconds: start.elapsed().as_secs_f64(),
        generation,
        bound_for: (scene.cages.clone(), scene.settings),
        preview,
        coarse_leaves,
        joint_volumes,
    })
}

/// Whether some of `leaves` use harmonic coordinates at a resolution finer than the preview's.
fn turns_harmonic(scene: &Scene, leaves: &[usize]) -> bool {
    let settings = &scene.settings.harmonic;
    settings.preview() != *settings
        && leaves.iter().any(|&c| {
            scene
                .cages
                .leaves
                .get(c)
                .is_some_and(|cage| cage.kind == CoordinateKind::Harmonic)
        })
}

/// Whether binding `scene` solves harmonic coordinates in some join cage (its policy is
/// harmonic, or automatic with a concave join cage), read from `topology` (the scene's) or a
/// topology built here. One that cannot be built gives `false`: the bind itself then reports
/// why.
fn has_harmonic_join_cages(scene: &Scene, topology: Option<&Topology>) -> bool {
    let harmonic = |topology: &Topology| {
        topology
            .joins
            .values()
            .any(|join| join.kind == CoordinateKind::Harmonic)
    };
    match (scene.settings.join_coordinates, topology) {
        (JoinPolicy::Mvc, _) => false,
        (_, Some(topology)) => harmonic(topology),
        (policy, None) => Topology::new(&scene.cages, policy).is_ok_and(|t| harmonic(&t)),
    }
}

/// The difference map's baseline: the scene's mesh bound to one cage of `kind` around all.
pub fn bind_baseline(
    scene: &Scene,
    kind: CoordinateKind,
    control: &BindControl,
) -> Result<Arc<StarBinding>, EditorError> {
    let single = single_cage_scene(scene, kind);
    StarBinding::bind_scene(&single, control)
        .map(Arc::new)
        .map_err(EditorError::Baseline)
}

/// A bind job's result.
pub type BindResult = Result<Bound, EditorError>;
/// A load job's result.
pub type LoadResult = Result<Document, EditorError>;
/// A baseline job's result.
pub type BaselineResult = Result<Arc<StarBinding>, EditorError>;

/// Opening `path` on a worker.
pub fn load_demo(name: String, wake: Option<Waker>) -> Job<LoadResult> {
    let label = format!("generating the {name} demo");
    Job::spawn("loading", label, wake, move |_| Document::demo_named(&name))
}

/// Opens the file `path` on a worker.
pub fn load(path: PathBuf, wake: Option<Waker>) -> Job<LoadResult> {
    let label = format!("opening {}", path.display());
    Job::spawn("loading", label, wake, move |control| {
        Document::open(&path, control)
    })
}

/// Reads the mesh at `path` and puts the cages `options` ask for around it, on a worker (the
/// auto rig reports progress and can be cancelled).
pub fn new_from_mesh(
    path: PathBuf,
    options: super::NewMeshOptions,
    wake: Option<Waker>,
) -> Job<LoadResult> {
    let label = format!("rigging {}", path.display());
    Job::spawn("loading", label, wake, move |control| {
        let scene = super::document::scene_from_mesh(&path, &options, control)?;
        Ok(Document {
            scene,
            path: None,
            dirty: true,
        })
    })
}

/// The auto rig of `mesh` on a worker: the leaf cages (and internal cages where asked).
pub fn autorig(
    mesh: starcages_core::mesh::Mesh,
    settings: starcages_core::generate::AutorigSettings,
    wake: Option<Waker>,
) -> Job<Result<CageSet, EditorError>> {
    Job::spawn("auto rig", "auto rig", wake, move |control| {
        starcages_core::generate::autorig(&mesh, &settings, control)
            .map(|rig| rig.cages)
            .map_err(EditorError::AutoRig)
    })
}

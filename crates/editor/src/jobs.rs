//! Binding on a worker thread: the UI keeps drawing, shows progress and can cancel; the
//! previous binding stays in use until the new one arrives.

use std::sync::Arc;
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::Instant;

use starcages_core::BindControl;
use starcages_core::hierarchy::Hierarchy;
use starcages_core::scene::{CageSet, Scene, SceneSettings};
use starcages_core::star::StarBinding;

/// How much to bind again.
#[derive(Debug, Clone, PartialEq)]
pub enum Scope {
    /// Everything: the mesh and the hierarchy.
    Full,
    /// The mesh rows of these leaf cages (their kind or h changed), and the hierarchy.
    Leaves(Arc<StarBinding>, Vec<usize>),
    /// Only the hierarchy (internal cages changed); the mesh binding is kept.
    Hierarchy(Arc<StarBinding>),
}

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
}

/// A bind in progress.
#[derive(Debug)]
pub struct BindJob {
    control: Arc<BindControl>,
    receiver: Receiver<Result<Bound, String>>,
    /// When it started.
    pub started: Instant,
    /// What it binds, for the status line.
    pub label: String,
}

/// What polling a job found.
#[derive(Debug)]
pub enum Poll {
    /// Still working, with the fraction done.
    Running(f64),
    /// Finished.
    Done(Box<Result<Bound, String>>),
}

impl BindJob {
    /// Starts binding `scene` (as much as `scope` says) on a worker thread; `wake` is called
    /// when it ends (to repaint).
    pub fn start(
        scene: Scene,
        scope: Scope,
        generation: u64,
        label: &str,
        wake: impl Fn() + Send + 'static,
    ) -> Self {
        let control = Arc::new(BindControl::default());
        let (sender, receiver) = channel();
        let worker_control = Arc::clone(&control);
        std::thread::spawn(move || {
            let start = Instant::now();
            let binding = match scope {
                Scope::Full => StarBinding::bind_scene(&scene, &worker_control).map(Arc::new),
                Scope::Leaves(old, leaves) => old
                    .rebind_leaves(&scene, &leaves, &worker_control)
                    .map(Arc::new),
                Scope::Hierarchy(old) => Ok(old),
            };
            let result = binding.map_err(|e| e.to_string()).and_then(|binding| {
                let hierarchy = Hierarchy::bind(&scene).map_err(|e| e.to_string())?;
                Ok(Bound {
                    binding,
                    hierarchy,
                    seconds: start.elapsed().as_secs_f64(),
                    generation,
                    bound_for: (scene.cages.clone(), scene.settings),
                })
            });
            sender.send(result).ok();
            wake();
        });
        Self {
            control,
            receiver,
            started: Instant::now(),
            label: label.to_owned(),
        }
    }

    /// Asks the worker to stop; it then reports a cancellation error.
    pub fn cancel(&self) {
        self.control.cancel();
    }

    /// Fraction of the work done.
    pub fn progress(&self) -> f64 {
        self.control.progress()
    }

    /// Progress or the result, without blocking.
    pub fn poll(&self) -> Poll {
        match self.receiver.try_recv() {
            Ok(result) => Poll::Done(Box::new(result)),
            Err(TryRecvError::Empty) => Poll::Running(self.control.progress()),
            Err(TryRecvError::Disconnected) => Poll::Done(Box::new(Err(
                "the binding worker stopped unexpectedly".into(),
            ))),
        }
    }

    /// Blocks until the job ends (tests and headless use).
    pub fn wait(self) -> Result<Bound, String> {
        self.receiver
            .recv()
            .unwrap_or_else(|_| Err("the binding worker stopped unexpectedly".into()))
    }
}

/// Opening a file on a worker thread (big meshes take a while to read and weld).
#[derive(Debug)]
pub struct LoadJob {
    receiver: Receiver<Result<crate::document::Document, String>>,
    /// The file being opened.
    pub path: std::path::PathBuf,
    /// When it started.
    pub started: Instant,
}

impl LoadJob {
    /// Starts opening `path`; `wake` is called when it ends.
    pub fn start(path: std::path::PathBuf, wake: impl Fn() + Send + 'static) -> Self {
        let (sender, receiver) = channel();
        let worker_path = path.clone();
        std::thread::spawn(move || {
            sender
                .send(crate::document::Document::open(&worker_path))
                .ok();
            wake();
        });
        Self {
            receiver,
            path,
            started: Instant::now(),
        }
    }

    /// The opened document or the error, once done.
    pub fn poll(&self) -> Option<Result<crate::document::Document, String>> {
        match self.receiver.try_recv() {
            Ok(result) => Some(result),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => {
                Some(Err("the loading worker stopped unexpectedly".into()))
            }
        }
    }

    /// Blocks until done (tests).
    pub fn wait(self) -> Result<crate::document::Document, String> {
        self.receiver
            .recv()
            .unwrap_or_else(|_| Err("the loading worker stopped unexpectedly".into()))
    }
}

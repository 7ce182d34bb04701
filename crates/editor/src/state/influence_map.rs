//! The influence map painted on the mesh: its values and colours, recomputed only when what
//! they depend on changes. The difference map's single-cage baseline is bound in the
//! background like every bind; until it arrives the map says so instead of blocking a frame.

use std::sync::Arc;

use starcages_core::coords::CoordinateKind;
use starcages_core::star::StarBinding;
use starcages_viewport::influence::{self, MapValues};

use super::jobs::{BaselineResult, Job, bind_baseline};
use super::{CageId, EditorState, InfluenceChoice};

/// What a map depends on: the choice, the inspected cage, the one selected vertex, the document
/// and mesh binding, and (for difference maps) the deformation and the baseline.
#[derive(Debug, Clone, Copy, PartialEq)]
struct MapKey {
    choice: InfluenceChoice,
    cage: Option<CageId>,
    vertex: Option<u32>,
    document: u64,
    mesh: u64,
    deformation: u64,
    baseline_ready: bool,
}

/// The difference map's baseline binding and what it was bound for.
struct Baseline {
    kind: CoordinateKind,
    document: u64,
    mesh: u64,
    binding: Arc<StarBinding>,
}

/// A baseline bind in progress.
struct BaselineJob {
    kind: CoordinateKind,
    document: u64,
    mesh: u64,
    job: Job<BaselineResult>,
}

/// The painted map, its inputs and the baseline for difference maps.
#[derive(Default)]
pub struct InfluenceMap {
    key: Option<MapKey>,
    values: Option<MapValues>,
    colors: Option<(u64, Arc<Vec<[u8; 4]>>)>,
    baseline: Option<Baseline>,
    baseline_job: Option<BaselineJob>,
    /// Why no map is painted although one was chosen (shown in the view panel).
    pub note: Option<String>,
}

impl std::fmt::Debug for InfluenceMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("InfluenceMap")
            .field("key", &self.key)
            .field("note", &self.note)
            .finish_non_exhaustive()
    }
}

impl InfluenceMap {
    /// The painted map's values and legend, if any.
    pub fn values(&self) -> Option<&MapValues> {
        self.values.as_ref()
    }

    /// Per-vertex colours with their generation (changes whenever the colours do).
    pub fn colors(&self) -> Option<(u64, Arc<Vec<[u8; 4]>>)> {
        self.colors.clone()
    }

    /// The baseline bind in progress: its label and progress.
    pub fn baseline_progress(&self) -> Option<(&str, f64)> {
        self.baseline_job
            .as_ref()
            .map(|b| (b.job.label.as_str(), b.job.progress()))
    }

    /// Cancels the baseline bind (the map then stays empty until chosen again).
    pub fn cancel_baseline(&mut self) {
        self.baseline_job = None;
    }

    /// Blocks until the baseline bind ends (tests).
    pub(crate) fn wait_for_baseline(&mut self) -> Option<BaselineResult> {
        let job = self.baseline_job.as_ref()?;
        let result = job.job.wait().and_then(|r| r);
        Some(result)
    }
}

impl EditorState {
    /// Takes a finished baseline bind; returns an error to show, if it failed.
    pub(crate) fn poll_baseline(&mut self, wait: bool) {
        let map = &mut self.map;
        let Some(running) = &map.baseline_job else {
            return;
        };
        let result = if wait {
            map.wait_for_baseline()
        } else {
            running.job.poll().map(|r| r.and_then(|r| r))
        };
        let Some(result) = result else {
            return;
        };
        let Some(done) = map.baseline_job.take() else {
            return;
        };
        match result {
            Ok(binding) => {
                map.baseline = Some(Baseline {
                    kind: done.kind,
                    document: done.document,
                    mesh: done.mesh,
                    binding,
                });
            }
            Err(e) => {
                map.note = Some("the baseline could not be bound".into());
                self.error(e);
            }
        }
    }

    /// Recomputes the map when its inputs changed (cheap maps here, the baseline bind on a
    /// worker).
    pub(crate) fn refresh_map(&mut self) {
        let choice = self.view.influence;
        let difference_kind = match choice {
            InfluenceChoice::Difference(kind) => Some(kind),
            _ => None,
        };
        let (document, mesh) = (self.document_id, self.generations.mesh);
        let baseline_ready = difference_kind.is_some_and(|kind| {
            self.map
                .baseline
                .as_ref()
                .is_some_and(|b| b.kind == kind && b.document == document && b.mesh == mesh)
        });
        let key = MapKey {
            choice,
            cage: self.selection.cage(),
            // W of the one selected vertex, else of the vertex under the cursor.
            vertex: self.selection.single_vertex().or(self.selection.hovered),
            document,
            mesh,
            deformation: if difference_kind.is_some() {
                self.generations.deformation
            } else {
                0
            },
            baseline_ready,
        };
        if self.map.key == Some(key) {
            return;
        }
        if let Some(kind) = difference_kind
            && !baseline_ready
        {
            self.start_baseline(kind);
        }
        let Some(rig) = &self.rig else {
            return;
        };
        self.map.note = None;
        let values = match choice {
            InfluenceChoice::None => None,
            InfluenceChoice::AllCages => Some(influence::boundary(&rig.binding, None)),
            InfluenceChoice::SelectedCage => match self.selection.cage() {
                Some(CageId::Leaf(c)) => Some(influence::boundary(&rig.binding, Some(c))),
                _ => {
                    self.map.note = Some("select a leaf cage in the outliner".into());
                    None
                }
            },
            InfluenceChoice::JoinWeight => match key.vertex {
                Some(v) => Some(influence::join_weight(&rig.binding, v)),
                None => {
                    let selected = self.selection.vertices.len();
                    self.map.note = Some(if selected > 1 {
                        format!(
                            "W is shown for one cage vertex: {selected} are selected; hover one \
                             or select just one"
                        )
                    } else {
                        "W is shown for one cage vertex: select or hover one".into()
                    });
                    None
                }
            },
            InfluenceChoice::Difference(_) => match &self.map.baseline {
                Some(baseline) if baseline_ready => {
                    let scene = &self.doc.scene;
                    let other = baseline.binding.deform(&scene.cages.vertices, &scene.pose);
                    Some(influence::difference(rig.deformed(), &other).0)
                }
                _ => {
                    self.map.note = Some("binding the single-cage baseline…".into());
                    None
                }
            },
        };
        let count = rig.deformed().len();
        let colors = influence::vertex_colors(values.as_ref().map(|m| m.values.as_slice()), count);
        let generation = self.map.colors.as_ref().map_or(0, |c| c.0 + 1);
        self.map.key = Some(key);
        self.map.values = values;
        self.map.colors = Some((generation, Arc::new(colors)));
    }

    fn start_baseline(&mut self, kind: CoordinateKind) {
        let (document, mesh) = (self.document_id, self.generations.mesh);
        let running = self
            .map
            .baseline_job
            .as_ref()
            .is_some_and(|b| b.kind == kind && b.document == document && b.mesh == mesh);
        if running {
            return;
        }
        let scene = self.doc.scene.clone();
        let label = format!("binding the single-{} baseline", kind.short_name());
        let job = Job::spawn("baseline", label, self.waker.clone(), move |control| {
            bind_baseline(&scene, kind, control)
        });
        // Replacing a stale job drops it, which cancels it.
        self.map.baseline_job = Some(BaselineJob {
            kind,
            document,
            mesh,
            job,
        });
    }
}

//! A live rig: a scene's binding, hierarchy and deformation held together while a person (or a
//! script) poses it — hand moves propagated down the hierarchy, the operator's DOFs brought up
//! to date column by column, the mesh rows they touch deformed again, a drag through an
//! internal cage followed by a [`DriverMap`] — and what a change of the scene makes stale. The
//! editor drives it and `starcages-bench --drags` times it, so the benchmark measures the
//! product's own path.

use std::sync::{Arc, OnceLock};

use glam::{DVec3, Vec3};

use crate::hierarchy::{Hierarchy, HierarchyError};
use crate::scene::{CageSet, Scene, SceneSettings};
use crate::star::{DriverMap, StarBinding};

/// DOFs and deformed mesh positions of one pose.
pub type RestView = (Arc<Vec<Vec3>>, Arc<Vec<Vec3>>);

/// How much of a live rig a change of its scene makes stale.
#[derive(Debug, Clone)]
pub enum RebindScope {
    /// Everything: the mesh and the hierarchy.
    Full,
    /// Everything, quickly first (a preview with mean value join cages where some would be
    /// harmonic), then refined.
    Preview,
    /// The mesh rows of these leaf cages (their kind or h changed), and the hierarchy; with
    /// `quick`, harmonic leaf cages at the preview resolution first.
    Leaves(Arc<StarBinding>, Vec<usize>, bool),
    /// Only the hierarchy (internal cages changed); the mesh binding is kept.
    Hierarchy(Arc<StarBinding>),
    /// The rest positions of these cage vertices moved: the rows they can change, and the
    /// hierarchy.
    RestEdit(Arc<StarBinding>, Vec<u32>),
}

/// The binding in use and the deformation it gives.
#[derive(Debug)]
pub struct LiveRig {
    /// The mesh binding (weights, computed once per bind).
    pub binding: Arc<StarBinding>,
    /// Internal cages.
    pub hierarchy: Hierarchy,
    /// Deformed welded mesh positions of the scene's current pose, updated incrementally.
    pub deformed: Arc<Vec<Vec3>>,
    /// The operator's degrees of freedom for the current pose (GPU deformation reads them).
    pub dofs: Arc<Vec<Vec3>>,
    /// The cages and settings this binding is for.
    pub bound_for: (CageSet, SceneSettings),
    /// A preview binding (mean value join cages in place of harmonic ones, or harmonic leaf
    /// cages at the preview resolution) while the refinement runs.
    pub preview: bool,
    /// The leaf cages a leaf preview bound coarsely (empty for a join-cage preview).
    pub coarse_leaves: Vec<usize>,
    /// The rest pose's DOFs and deformed mesh: computed when first asked for.
    rest_view: OnceLock<RestView>,
    /// The drag in progress as an affine map of the vertices it moves by hand, when its moves
    /// reach far through the hierarchy ([`LiveRig::redeform_drag`]).
    drag: Option<DriverMap>,
    /// The drivers of the drag in progress when it can have no map (a Green cage on the way,
    /// too many coefficients): its updates go the sparse way without trying again.
    drag_without_map: Option<Vec<u32>>,
}

impl LiveRig {
    /// A rig of `binding` and `hierarchy` (bound for `bound_for`), deforming `scene`'s current
    /// pose.
    pub fn new(
        binding: Arc<StarBinding>,
        hierarchy: Hierarchy,
        bound_for: (CageSet, SceneSettings),
        scene: &Scene,
    ) -> Self {
        let mut rig = Self {
            binding,
            hierarchy,
            deformed: Arc::new(Vec::new()),
            dofs: Arc::new(Vec::new()),
            bound_for,
            preview: false,
            coarse_leaves: Vec::new(),
            rest_view: OnceLock::new(),
            drag: None,
            drag_without_map: None,
        };
        rig.redeform_all(scene);
        rig
    }

    /// The DOFs and the deformed mesh of the rest cages this binding was made for (computed
    /// once per rig).
    pub fn rest_view(&self) -> RestView {
        let (dofs, deformed) = self.rest_view.get_or_init(|| {
            let rest = &self.bound_for.0.vertices;
            (
                Arc::new(self.binding.operator.dofs(rest, rest)),
                Arc::new(self.binding.deform(rest, rest)),
            )
        });
        (Arc::clone(dofs), Arc::clone(deformed))
    }

    /// Whether the binding still fits `scene`'s cages and settings.
    pub fn is_current_for(&self, scene: &Scene) -> bool {
        self.bound_for.0 == scene.cages && self.bound_for.1 == scene.settings
    }

    /// Whether hand moves can be applied to `scene` with this rig: the hierarchy and the
    /// operator were bound for the same vertices, leaf faces and internal cages (a kind or h
    /// change being bound meanwhile does not matter).
    pub fn can_pose(&self, scene: &Scene) -> bool {
        let (bound, now) = (&self.bound_for.0, &scene.cages);
        bound.vertices == now.vertices
            && bound.internals == now.internals
            && bound.leaves.len() == now.leaves.len()
            && bound
                .leaves
                .iter()
                .zip(&now.leaves)
                .all(|(a, b)| a.faces == b.faces)
    }

    /// Hand moves (vertex, new position) applied to `scene`'s current pose and propagated down
    /// the hierarchy (its state kept in the scene), the mesh following: during a drag
    /// (`in_drag`) through [`LiveRig::redeform_drag`], otherwise through the rows the moves
    /// touch. Returns the cage vertices whose position changed; on error nothing changed.
    pub fn move_vertices(
        &mut self,
        scene: &mut Scene,
        moves: &[(u32, DVec3)],
        in_drag: bool,
    ) -> Result<Vec<u32>, HierarchyError> {
        let changed = self.hierarchy.apply(&mut scene.pose, moves)?;
        scene.pose_state = self.hierarchy.state();
        if changed.is_empty() {
            return Ok(changed);
        }
        if in_drag {
            let mut drivers: Vec<u32> = moves.iter().map(|(v, _)| *v).collect();
            drivers.sort_unstable();
            drivers.dedup();
            self.redeform_drag(scene, &drivers, &changed);
        } else {
            self.redeform_rows(scene, &changed);
        }
        Ok(changed)
    }

    /// Recomputes the whole deformation of `scene`'s current pose.
    pub fn redeform_all(&mut self, scene: &Scene) {
        // The DOFs once, for the product and for the GPU (playback calls this every frame).
        let operator = &self.binding.operator;
        let dofs = operator.dofs(&scene.cages.vertices, &scene.pose);
        let mut deformed = vec![Vec3::ZERO; operator.row_count()];
        operator.apply(&dofs, &mut deformed);
        self.dofs = Arc::new(dofs);
        self.deformed = Arc::new(deformed);
    }

    /// Brings the DOFs up to date after the cage vertices `changed` moved: their columns and
    /// the Green DOFs of their triangles, not every column.
    fn update_dofs(&mut self, scene: &Scene, changed: &[u32]) {
        let operator = &self.binding.operator;
        if self.dofs.len() == operator.dof_count() {
            let dofs = Arc::make_mut(&mut self.dofs);
            operator.update_dofs(&scene.cages.vertices, &scene.pose, changed, dofs);
        } else {
            self.dofs = Arc::new(operator.dofs(&scene.cages.vertices, &scene.pose));
        }
    }

    /// Updates the deformation during a drag of the vertices `drivers` (sorted) that moved the
    /// cage vertices `changed`. The first update of a drag that reaches further than its
    /// drivers (an internal cage's vertices moving leaf cages) is [`LiveRig::redeform_rows`];
    /// it then builds a [`DriverMap`], and the next updates move only its rows at a few
    /// weights each (one per driver) instead of a sparse product. Where there is no map (a
    /// Green cage on the way, a pose the map does not describe) it is
    /// [`LiveRig::redeform_rows`]; a drag that can have no map tries once. The drag's end makes
    /// the result exact again ([`LiveRig::end_drag`]).
    pub fn redeform_drag(&mut self, scene: &Scene, drivers: &[u32], changed: &[u32]) {
        if let Some(map) = self.drag.as_ref().filter(|map| map.drivers() == drivers) {
            let deformed = Arc::make_mut(&mut self.deformed);
            if map.apply(&scene.pose, deformed) {
                self.update_dofs(scene, changed);
                return;
            }
        }
        self.redeform_rows(scene, changed);
        self.drag = None;
        let tried = self.drag_without_map.as_deref() == Some(drivers);
        if changed.len() > drivers.len() && !tried {
            self.drag = self
                .hierarchy
                .driver_sensitivity(drivers)
                .and_then(|sensitivity| {
                    DriverMap::new(
                        &self.binding.operator,
                        drivers,
                        &sensitivity,
                        &scene.pose,
                        &self.deformed,
                    )
                });
            if self.drag.is_none() {
                self.drag_without_map = Some(drivers.to_vec());
            }
        }
    }

    /// The driver map of the drag in progress, if it has one.
    pub fn drag_map(&self) -> Option<&DriverMap> {
        self.drag.as_ref()
    }

    /// The drivers of the drag in progress when it can have no driver map.
    pub fn drag_without_map(&self) -> Option<&[u32]> {
        self.drag_without_map.as_deref()
    }

    /// Ends a drag: a drag that went through a [`DriverMap`] gets the whole product, so the mesh
    /// is what a full deformation of the pose gives, bit for bit.
    pub fn end_drag(&mut self, scene: &Scene) {
        self.drag_without_map = None;
        if self.drag.take().is_some() {
            self.redeform_all(scene);
        }
    }

    /// Updates the deformation after the cage vertices `changed` moved: their DOFs, then only
    /// the mesh rows they touch, or all of them in one parallel product where those are most
    /// of the mesh (`StarOperator::apply_after_move`).
    pub fn redeform_rows(&mut self, scene: &Scene, changed: &[u32]) {
        self.update_dofs(scene, changed);
        let operator = &self.binding.operator;
        let deformed = Arc::make_mut(&mut self.deformed);
        if deformed.len() == operator.row_count() {
            operator.apply_after_move(changed, &self.dofs, deformed);
        } else {
            *deformed = self.binding.deform(&scene.cages.vertices, &scene.pose);
        }
    }

    /// Whether the DOFs and the deformed mesh are those a full deformation of `scene`'s
    /// current pose gives (a drag through a driver map aside, which is exact at its end):
    /// the invariant every update keeps, for tests.
    pub fn is_up_to_date(&self, scene: &Scene) -> bool {
        let operator = &self.binding.operator;
        let dofs = operator.dofs(&scene.cages.vertices, &scene.pose);
        if *self.dofs != dofs {
            return false;
        }
        self.drag.is_some()
            || *self.deformed == self.binding.deform(&scene.cages.vertices, &scene.pose)
    }

    /// How much of this rig must be bound again for `scene`: a full bind (preview first) only
    /// when the geometry, the hierarchy's structure or the settings changed, or the rig is a
    /// preview; a leaf cage's kind, h or border h changes only its own mesh rows; internal
    /// cages change only the hierarchy.
    pub fn rebind_scope(&self, scene: &Scene) -> RebindScope {
        if self.preview && self.coarse_leaves.is_empty() {
            // Re-binding part of a preview would keep its join cages: bind it all again.
            return RebindScope::Preview;
        }
        if self.preview {
            // A leaf preview: its coarse leaves are bound again with whatever else changed.
            return match self.exact_scope(scene) {
                RebindScope::Leaves(binding, mut leaves, quick) => {
                    leaves.extend(&self.coarse_leaves);
                    leaves.sort_unstable();
                    leaves.dedup();
                    RebindScope::Leaves(binding, leaves, quick)
                }
                RebindScope::Hierarchy(binding) => {
                    RebindScope::Leaves(binding, self.coarse_leaves.clone(), true)
                }
                _ => RebindScope::Preview,
            };
        }
        self.exact_scope(scene)
    }

    /// [`LiveRig::rebind_scope`] for a binding that is not a preview.
    fn exact_scope(&self, scene: &Scene) -> RebindScope {
        let (bound, settings) = &self.bound_for;
        let now = &scene.cages;
        let same_structure = *settings == scene.settings
            && bound.vertices.len() == now.vertices.len()
            && bound.leaves == now.leaves
            && bound.internals == now.internals;
        if same_structure && bound.vertices != now.vertices {
            // Only rest positions moved: bind again what they can change.
            let moved = bound
                .vertices
                .iter()
                .zip(&now.vertices)
                .enumerate()
                .filter(|(_, (a, b))| a != b)
                .map(|(v, _)| v as u32)
                .collect();
            return RebindScope::RestEdit(Arc::clone(&self.binding), moved);
        }
        if *settings != scene.settings
            || bound.vertices != now.vertices
            || bound.leaves.len() != now.leaves.len()
            || bound.internals.len() != now.internals.len()
        {
            return RebindScope::Preview;
        }
        let mut leaves = Vec::new();
        for (i, (a, b)) in bound.leaves.iter().zip(&now.leaves).enumerate() {
            if a.faces != b.faces || a.name != b.name {
                return RebindScope::Preview;
            }
            if a != b {
                leaves.push(i);
            }
        }
        if leaves.is_empty() {
            RebindScope::Hierarchy(Arc::clone(&self.binding))
        } else {
            RebindScope::Leaves(Arc::clone(&self.binding), leaves, true)
        }
    }
}

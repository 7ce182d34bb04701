//! A live rig: a scene's binding, hierarchy and deformation held together while a person (or a
//! script) poses it — hand moves propagated down the hierarchy, the operator's DOFs brought up
//! to date column by column, the mesh rows they touch deformed again, a drag through an
//! internal cage followed by a [`DriverMap`] — and what a change of the scene makes stale. The
//! editor drives it and `starcages-bench --drags` times it, so the benchmark measures the
//! product's own path.

use std::sync::{Arc, OnceLock};

use glam::{DVec3, Vec3};

use crate::hierarchy::{Hierarchy, HierarchyError};
use crate::joint_volume::JointVolumes;
use crate::scene::{CageSet, Scene, SceneSettings};
use crate::star::{DriverMap, StarBinding};

/// The deformed mesh of one set of DOFs, computed when first read (a GPU that deforms from the
/// DOFs never needs it), then kept.
#[derive(Debug)]
pub struct DeformedMesh {
    binding: Arc<StarBinding>,
    /// The DOFs it is the product of.
    pub dofs: Arc<Vec<Vec3>>,
    positions: OnceLock<Arc<Vec<Vec3>>>,
}

impl DeformedMesh {
    /// The mesh of `dofs`, not computed yet.
    fn lazy(binding: &Arc<StarBinding>, dofs: Arc<Vec<Vec3>>) -> Self {
        Self {
            binding: Arc::clone(binding),
            dofs,
            positions: OnceLock::new(),
        }
    }

    /// The mesh of `dofs`, already computed as `positions`.
    fn computed(binding: &Arc<StarBinding>, dofs: Arc<Vec<Vec3>>, positions: Vec<Vec3>) -> Self {
        let mesh = Self::lazy(binding, dofs);
        let _ = mesh.positions.set(Arc::new(positions));
        mesh
    }

    /// The deformed welded mesh positions: S·x, computed on the first call.
    pub fn positions(&self) -> &Arc<Vec<Vec3>> {
        self.positions.get_or_init(|| {
            let operator = &self.binding.operator;
            let mut positions = vec![Vec3::ZERO; operator.row_count()];
            operator.apply(&self.dofs, &mut positions);
            Arc::new(positions)
        })
    }

    /// The positions if something read them already.
    pub fn computed_positions(&self) -> Option<&Arc<Vec<Vec3>>> {
        self.positions.get()
    }
}

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
    /// The operator's degrees of freedom for the current pose and the deformed mesh, computed
    /// only when something reads it and from then on kept up to date move by move.
    mesh: Arc<DeformedMesh>,
    /// The cages and settings this binding is for.
    pub bound_for: (CageSet, SceneSettings),
    /// A preview binding (mean value join cages in place of harmonic ones, or harmonic leaf
    /// cages at the preview resolution) while the refinement runs.
    pub preview: bool,
    /// The leaf cages a leaf preview bound coarsely (empty for a join-cage preview).
    pub coarse_leaves: Vec<usize>,
    /// The rest pose's DOFs and deformed mesh: computed when first asked for.
    rest_view: OnceLock<Arc<DeformedMesh>>,
    /// The drag in progress as an affine map of the vertices it moves by hand, when its moves
    /// reach far through the hierarchy ([`LiveRig::redeform_drag`]).
    drag: Option<DriverMap>,
    /// The drivers of the drag in progress when it can have no map (a Green cage on the way,
    /// too many coefficients): its updates go the sparse way without trying again.
    drag_without_map: Option<Vec<u32>>,
    /// The joints' regions in this binding's mesh, built on the first move that bends one.
    joint_volumes: OnceLock<JointVolumes>,
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
        let dofs = Arc::new(binding.operator.dofs(&scene.cages.vertices, &scene.pose));
        let mesh = Arc::new(DeformedMesh::lazy(&binding, dofs));
        Self {
            binding,
            hierarchy,
            mesh,
            bound_for,
            preview: false,
            coarse_leaves: Vec::new(),
            rest_view: OnceLock::new(),
            drag: None,
            drag_without_map: None,
            joint_volumes: OnceLock::new(),
        }
    }

    /// The DOFs and the deformed mesh of the rest cages this binding was made for (the DOFs
    /// computed once per rig, the mesh when read).
    pub fn rest_view(&self) -> Arc<DeformedMesh> {
        let view = self.rest_view.get_or_init(|| {
            let rest = &self.bound_for.0.vertices;
            let dofs = Arc::new(self.binding.operator.dofs(rest, rest));
            Arc::new(DeformedMesh::lazy(&self.binding, dofs))
        });
        Arc::clone(view)
    }

    /// The current pose's DOFs and deformed mesh (a cheap handle: the mesh is computed when
    /// read).
    pub fn mesh(&self) -> Arc<DeformedMesh> {
        Arc::clone(&self.mesh)
    }

    /// The current pose's DOFs.
    pub fn dofs(&self) -> &Arc<Vec<Vec3>> {
        &self.mesh.dofs
    }

    /// The current pose's deformed welded mesh (computed now if nothing read it before).
    pub fn deformed(&self) -> &Arc<Vec<Vec3>> {
        self.mesh.positions()
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
        let mut changed = self.hierarchy.apply(&mut scene.pose, moves)?;
        scene.pose_state = self.hierarchy.state();
        if changed.is_empty() {
            return Ok(changed);
        }
        let settled = self.keep_joint_volumes(scene, &changed);
        if !settled.is_empty() {
            changed.extend(settled);
            changed.sort_unstable();
            changed.dedup();
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

    /// Gives the rig its joints' regions, built for this binding elsewhere (a bind's worker),
    /// so that the first turn of a control does not build them on the caller's thread.
    pub fn set_joint_volumes(&mut self, volumes: JointVolumes) {
        self.joint_volumes = OnceLock::from(volumes);
    }

    /// Settles the joints whose rings the hierarchy just moved (`changed`, sorted) to their
    /// rest volume ([`JointVolumes`]); returns the ring vertices it moved.
    fn keep_joint_volumes(&self, scene: &mut Scene, changed: &[u32]) -> Vec<u32> {
        if scene.cages.internals.iter().all(|c| c.joint.is_empty()) {
            return Vec::new();
        }
        let volumes = self.joint_volumes.get_or_init(|| {
            JointVolumes::new(
                &self.bound_for.0,
                scene.mesh.welded_triangles(),
                &self.binding.operator,
            )
        });
        let hierarchy = &self.hierarchy;
        volumes.settle(
            &self.binding.operator,
            &mut scene.pose,
            Some(changed),
            &|v| hierarchy.is_hand_moved(v),
        )
    }

    /// Recomputes the DOFs of `scene`'s current pose; the mesh follows when read (playback
    /// calls this every frame).
    pub fn redeform_all(&mut self, scene: &Scene) {
        let dofs = self
            .binding
            .operator
            .dofs(&scene.cages.vertices, &scene.pose);
        self.mesh = Arc::new(DeformedMesh::lazy(&self.binding, Arc::new(dofs)));
    }

    /// The DOFs after the cage vertices `changed` moved: the previous ones with their columns
    /// and the Green DOFs of their triangles brought up to date, not every column.
    fn updated_dofs(&self, scene: &Scene, changed: &[u32]) -> Vec<Vec3> {
        let operator = &self.binding.operator;
        let mut dofs = (*self.mesh.dofs).clone();
        if dofs.len() == operator.dof_count() {
            operator.update_dofs(&scene.cages.vertices, &scene.pose, changed, &mut dofs);
            dofs
        } else {
            operator.dofs(&scene.cages.vertices, &scene.pose)
        }
    }

    /// The previous mesh's positions to update in place, if something read them (taken
    /// without a copy where no one else holds them).
    fn take_computed_positions(&mut self) -> Option<Vec<Vec3>> {
        self.mesh.computed_positions()?;
        let placeholder = Arc::new(DeformedMesh::lazy(
            &self.binding,
            Arc::clone(&self.mesh.dofs),
        ));
        let mesh = std::mem::replace(&mut self.mesh, placeholder);
        let positions = match Arc::try_unwrap(mesh) {
            Ok(mesh) => mesh.positions.into_inner(),
            Err(shared) => shared.computed_positions().cloned(),
        }?;
        Some(Arc::try_unwrap(positions).unwrap_or_else(|shared| (*shared).clone()))
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
        let mapped = self
            .drag
            .as_ref()
            .is_some_and(|map| map.drivers() == drivers);
        if mapped && self.mesh.computed_positions().is_some() {
            let dofs = Arc::new(self.updated_dofs(scene, changed));
            if let (Some(mut positions), Some(map)) = (self.take_computed_positions(), &self.drag)
                && map.apply(&scene.pose, &mut positions)
            {
                self.mesh = Arc::new(DeformedMesh::computed(&self.binding, dofs, positions));
                return;
            }
        }
        self.redeform_rows(scene, changed);
        self.drag = None;
        let tried = self.drag_without_map.as_deref() == Some(drivers);
        // A map moves the CPU mesh: worth building only where something reads it.
        let read = self.mesh.computed_positions().is_some();
        if read && changed.len() > drivers.len() && !tried {
            self.drag = self
                .hierarchy
                .driver_sensitivity(drivers)
                .and_then(|sensitivity| {
                    DriverMap::new(
                        &self.binding.operator,
                        drivers,
                        &sensitivity,
                        &scene.pose,
                        self.mesh.positions(),
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
        let dofs = Arc::new(self.updated_dofs(scene, changed));
        let binding = Arc::clone(&self.binding);
        let operator = &binding.operator;
        self.mesh = Arc::new(match self.take_computed_positions() {
            Some(mut positions) if positions.len() == operator.row_count() => {
                operator.apply_after_move(changed, &dofs, &mut positions);
                DeformedMesh::computed(&self.binding, dofs, positions)
            }
            _ => DeformedMesh::lazy(&self.binding, dofs),
        });
    }

    /// Whether the DOFs and the deformed mesh (where computed) are those a full deformation of
    /// `scene`'s current pose gives (a drag through a driver map aside, which is exact at its
    /// end): the invariant every update keeps, for tests.
    pub fn is_up_to_date(&self, scene: &Scene) -> bool {
        let operator = &self.binding.operator;
        let dofs = operator.dofs(&scene.cages.vertices, &scene.pose);
        if *self.mesh.dofs != dofs {
            return false;
        }
        match self.mesh.computed_positions() {
            Some(positions) if self.drag.is_none() => {
                **positions == self.binding.deform(&scene.cages.vertices, &scene.pose)
            }
            _ => true,
        }
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

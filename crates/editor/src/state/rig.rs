//! The bound scene: the mesh operator, the hierarchy and the deformed mesh, and how much of it
//! a change of the document makes stale.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use starcages_core::hierarchy::Hierarchy;
use starcages_core::scene::{CageSet, Scene, SceneSettings};
use starcages_core::star::{DriverMap, StarBinding};

use super::jobs::Scope;

/// DOFs and deformed mesh positions of one pose.
pub type RestView = (Arc<Vec<Vec3>>, Arc<Vec<Vec3>>);

/// The binding in use and the deformation it gives.
#[derive(Debug)]
pub struct Rig {
    /// The mesh binding (weights, computed once per bind).
    pub binding: Arc<StarBinding>,
    /// Internal cages.
    pub hierarchy: Hierarchy,
    /// Deformed welded mesh positions, updated incrementally.
    pub deformed: Arc<Vec<Vec3>>,
    /// Degrees of freedom of the current pose (for GPU deformation).
    pub dofs: Arc<Vec<Vec3>>,
    /// The cages and settings this binding is for.
    pub bound_for: (CageSet, SceneSettings),
    /// A preview binding (mean value join cages in place of harmonic ones, or harmonic leaf
    /// cages at the preview resolution) while the refinement runs.
    pub preview: bool,
    /// The leaf cages a leaf preview bound coarsely (empty for a join-cage preview).
    pub coarse_leaves: Vec<usize>,
    /// The rest pose's DOFs and deformed mesh, as Rig mode shows them: computed on the first
    /// frame that needs them, not on every frame (a full product over a large mesh).
    pub rest_view: std::sync::OnceLock<RestView>,
    /// The drag in progress as an affine map of the vertices it moves by hand, when its moves
    /// reach far through the hierarchy ([`Rig::redeform_drag`]).
    pub drag: Option<DriverMap>,
    /// The drivers of the drag in progress when it can have no map (a Green cage on the way,
    /// too many coefficients): its updates go the sparse way without trying again.
    pub drag_without_map: Option<Vec<u32>>,
}

impl Rig {
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

    /// Updates the deformation during a drag of the vertices `drivers` (sorted) that moved the
    /// cage vertices `changed`. The first update of a drag that reaches further than its
    /// drivers (an internal cage's vertices moving leaf cages) is [`Rig::redeform_rows`]; it
    /// then builds a [`DriverMap`], and the next updates move only its rows at a few weights
    /// each (one per driver) instead of a sparse product. Where there is no map (a Green cage
    /// on the way, a pose the map does not describe) it is [`Rig::redeform_rows`]; a drag that
    /// can have no map tries once ([`Rig::drag_without_map`]). The drag's
    /// end makes the result exact again ([`Rig::end_drag`]).
    pub fn redeform_drag(&mut self, scene: &Scene, drivers: &[u32], changed: &[u32]) {
        if let Some(map) = self.drag.as_ref().filter(|map| map.drivers() == drivers) {
            let deformed = Arc::make_mut(&mut self.deformed);
            if map.apply(&scene.pose, deformed) {
                let operator = &self.binding.operator;
                self.dofs = Arc::new(operator.dofs(&scene.cages.vertices, &scene.pose));
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

    /// Ends a drag: a drag that went through a [`DriverMap`] gets the whole product, so the mesh
    /// is what a full deformation of the pose gives, bit for bit.
    pub fn end_drag(&mut self, scene: &Scene) {
        self.drag_without_map = None;
        if self.drag.take().is_some() {
            self.redeform_all(scene);
        }
    }

    /// Updates the deformation after the cage vertices `changed` moved: only the mesh rows
    /// they touch are recomputed, or all of them in one parallel product where those are
    /// most of the mesh (`StarOperator::apply_after_move`).
    pub fn redeform_rows(&mut self, scene: &Scene, changed: &[u32]) {
        let operator = &self.binding.operator;
        let dofs = operator.dofs(&scene.cages.vertices, &scene.pose);
        let deformed = Arc::make_mut(&mut self.deformed);
        if deformed.len() == operator.row_count() {
            operator.apply_after_move(changed, &dofs, deformed);
        } else {
            *deformed = self.binding.deform(&scene.cages.vertices, &scene.pose);
        }
        self.dofs = Arc::new(dofs);
    }
}

/// How much of `rig` must be bound again for `scene`: a full bind (preview first) only when the
/// geometry, the hierarchy's structure or the settings changed, or the rig is a preview; a leaf cage's kind, h or border h changes
/// only its own mesh rows; internal cages change only the hierarchy.
pub fn rebind_scope(rig: &Rig, scene: &Scene) -> Scope {
    let (bound, settings) = &rig.bound_for;
    let now = &scene.cages;
    if rig.preview && rig.coarse_leaves.is_empty() {
        // Re-binding part of a preview would keep its join cages: bind it all again.
        return Scope::Preview;
    }
    if rig.preview {
        // A leaf preview: its coarse leaves are bound again with whatever else changed.
        return match exact_scope(rig, scene, bound, settings, now) {
            Scope::Leaves(binding, mut leaves, quick) => {
                leaves.extend(&rig.coarse_leaves);
                leaves.sort_unstable();
                leaves.dedup();
                Scope::Leaves(binding, leaves, quick)
            }
            Scope::Hierarchy(binding) => Scope::Leaves(binding, rig.coarse_leaves.clone(), true),
            _ => Scope::Preview,
        };
    }
    exact_scope(rig, scene, bound, settings, now)
}

/// [`rebind_scope`] for a binding that is not a preview.
fn exact_scope(
    rig: &Rig,
    scene: &Scene,
    bound: &CageSet,
    settings: &SceneSettings,
    now: &CageSet,
) -> Scope {
    let same_structure = *settings == scene.settings
        && bound.vertices.len() == now.vertices.len()
        && bound.leaves == now.leaves
        && bound.internals == now.internals;
    if same_structure && bound.vertices != now.vertices {
        // Only rest positions moved: bind again what they can change.
        let moved = (0..now.vertices.len() as u32)
            .filter(|&v| bound.vertices[v as usize] != now.vertices[v as usize])
            .collect();
        return Scope::RestEdit(Arc::clone(&rig.binding), moved);
    }
    if *settings != scene.settings
        || bound.vertices != now.vertices
        || bound.leaves.len() != now.leaves.len()
        || bound.internals.len() != now.internals.len()
    {
        return Scope::Preview;
    }
    let mut leaves = Vec::new();
    for (i, (a, b)) in bound.leaves.iter().zip(&now.leaves).enumerate() {
        if a.faces != b.faces || a.name != b.name {
            return Scope::Preview;
        }
        if a != b {
            leaves.push(i);
        }
    }
    if leaves.is_empty() {
        Scope::Hierarchy(Arc::clone(&rig.binding))
    } else {
        Scope::Leaves(Arc::clone(&rig.binding), leaves, true)
    }
}

/// `moves` plus their mirror partners' moves across x = 0 (`partners` from
/// [`super::mirror::partners`]); a vertex on the plane stays on it.
pub fn with_mirror(
    moves: &[(u32, DVec3)],
    partners: &[Option<u32>],
    pose: &[DVec3],
) -> Vec<(u32, DVec3)> {
    let moving: std::collections::BTreeSet<u32> = moves.iter().map(|m| m.0).collect();
    let mut out = moves.to_vec();
    for &(v, p) in moves {
        match partners.get(v as usize).copied().flatten() {
            Some(partner) if partner == v => {
                if let (Some(last), Some(at)) =
                    (out.iter_mut().find(|m| m.0 == v), pose.get(v as usize))
                {
                    last.1.x = at.x;
                }
            }
            Some(partner) if !moving.contains(&partner) => {
                out.push((partner, DVec3::new(-p.x, p.y, p.z)));
            }
            _ => {}
        }
    }
    out
}

//! StarCages core: the deformation math and the scene model, with no GPU, window or UI
//! dependency and no C or C++ code; files are `starcages-io`'s.
//!
//! * [`anim`]: keys on a timeline and their evaluation at any frame.
//! * [`bake`]: the mesh at a run of frames through one binding, re-bound where keyed h changes.
//! * [`cage`]: validated closed triangle cages (polygon faces kept for eq. 7 of *Cages).
//! * [`check`]: validation of a whole scene: the model's rules and the engine's dry runs.
//! * [`coords`]: Mean Value, Harmonic and Green coordinates behind one [`coords::bind`] API.
//! * [`generate`]: rigs and scenes made by the program (the auto rig, box grids, demos).
//! * [`geometry`]: small geometric primitives.
//! * [`live`]: a rig being posed: binding, hierarchy, DOFs and mesh kept up to date move by move.
//! * [`hierarchy`]: internal cages driving lower-level cage vertices (section 3.4).
//! * [`posing`]: the one posing engine: a pose, a frame or a pose file plus edits, as cages.
//! * [`rig`]: rig operations on the rest cages (one file per operation) and their scripts.
//! * [`scene`]: the scene model, its validation and files.
//! * [`star`]: *Cages deformation compiled into one sparse operator.
//! * [`surface_nets`]: closed meshes of implicit surfaces (the creature demo).

pub mod anim;
pub mod bake;
pub mod cage;
pub mod check;
pub mod coords;
pub mod generate;
pub mod geometry;
pub mod hierarchy;
pub mod joint_volume;
pub mod live;
pub mod mesh;
mod messages;
pub mod posing;
pub mod rig;
pub mod scene;
pub mod star;
pub mod surface_nets;

pub use cage::{Cage, CageError};
pub use coords::{BindControl, BindSettings, CageWeights, CoordError, CoordinateKind, bind};

//! StarCages core: the deformation math and the scene model, with no GPU, window or UI
//! dependency.
//!
//! * [`anim`]: keys on a timeline and their evaluation at any frame.
//! * [`cage`]: validated closed triangle cages (polygon faces kept for eq. 7 of *Cages).
//! * [`coords`]: Mean Value, Harmonic and Green coordinates behind one [`coords::bind`] API.
//! * [`generate`]: rigs and scenes made by the program (the auto rig, box grids, demos).
//! * [`io`]: cage OBJ files and point lists, with errors naming file and line.
//! * [`geometry`]: small geometric primitives.
//! * [`hierarchy`]: internal cages driving lower-level cage vertices (section 3.4).
//! * [`posing`]: the one posing engine: a pose, a frame or a pose file plus edits, as cages.
//! * [`rig`]: rig operations on the rest cages (one file per operation) and their scripts.
//! * [`scene`]: the scene model, its validation and files.
//! * [`star`]: *Cages deformation compiled into one sparse operator.
//! * [`surface_nets`]: closed meshes of implicit surfaces (the creature demo).

pub mod anim;
pub mod cage;
pub mod coords;
pub mod generate;
pub mod geometry;
pub mod hierarchy;
pub mod io;
pub mod mesh;
mod messages;
pub mod posing;
pub mod rig;
pub mod scene;
pub mod star;
pub mod surface_nets;

pub use cage::{Cage, CageError};
pub use coords::{BindControl, BindSettings, CageWeights, CoordError, CoordinateKind, bind};

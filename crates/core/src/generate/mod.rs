//! Generated rigs: cages made from a mesh by the program rather than by hand.
//!
//! * [`mod@autorig`]: a shape-following multi-cage rig (chains of cages along limbs).
//! * [`autocage()`]: a grid of box cages over a mesh.
//! * [`demo`], [`creature`]: the generated demo scenes (with their poses and animations).

mod autocage;
pub mod autorig;
pub mod creature;
pub mod demo;
mod demo_pose;

pub use autocage::{AutocageOptions, DEFAULT_GRID, autocage};

pub use autorig::{
    Autorig, AutorigError, AutorigReport, AutorigSettings, MAX_DETAIL, Mirror, autorig,
    autorig_settings, surface_pieces_per_leaf,
};

//! Generated rigs: cages made from a mesh by the program rather than by hand.
//!
//! * [`mod@autorig`]: a shape-following multi-cage rig (chains of cages along limbs).

pub mod autorig;

pub use autorig::{
    Autorig, AutorigError, AutorigReport, AutorigSettings, Mirror, autorig, autorig_settings,
    surface_pieces_per_leaf,
};

//! The core's integration tests in one binary (linking one test binary per file took longer
//! than running the tests): coordinates, *Cages, hierarchies, scenes and readers.
#![allow(clippy::unwrap_used)]

mod animation;
mod autorig;
mod common;
mod green;
mod harmonic;
mod hierarchy;
mod hostile;
mod joint_volume;
mod lanes;
mod layout;
mod limb_names;
mod live;
mod mean_value;
mod narrow_joints;
mod posable_rig;
mod posing;
mod rig_edit;
mod rig_inset;
mod rig_script;
mod scenes;
mod star;
mod star_rebind;

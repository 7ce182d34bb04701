//! One module per subcommand.

pub mod weights;

//! One module per subcommand.

pub mod args;
pub mod bifurcation;
pub mod boundary;
pub mod check;
pub mod compare;
pub mod demo;
pub mod disturbances;
pub mod fk;
pub mod helix;
pub mod ik;
pub mod layout;
pub mod merge;
pub mod plan;
pub mod plot;
pub mod reach;
pub mod render;
pub mod robot;
pub mod simulate;

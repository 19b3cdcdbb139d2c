//! Rig files, pose paths, ladder graph, trajectories (DESIGN.md §4–5).
//!
//! | module | holds |
//! |---|---|
//! | [`rig`] | the rig TOML schema, its validation, embedded rigs |
//! | [`ladder`] | the layered graph of IK solutions and its forward dynamic programming |
//! | [`trajectory`] | time parametrization and the CSV / JSON writers |

pub mod ladder;
pub mod rig;
pub mod trajectory;

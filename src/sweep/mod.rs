//! Sweeps over direction sets (DESIGN.md §6).
//!
//! - [`driver`]: the generic resumable, checkpointed, deterministic parallel map over directions
//!   (used by `boundary` and `reach`).
//! - [`reach`]: the reachability sweep of a rig.

pub mod driver;
pub mod reach;

//! Sweeps over direction sets ([architecture §6](crate::architecture)).
//!
//! - [`driver`]: the generic resumable, checkpointed, locked, deterministic parallel map over
//!   items with its data-safety rules (used by `boundary`, `reach` and every other sweep).
//! - [`record`]: the settings record of every sweep output, in its sidecar `F.meta.json`.
//! - [`merge`]: joining shard outputs, with completeness, order and settings checks.
//! - [`reach`]: the reachability sweep of a rig.

pub mod driver;
pub mod merge;
pub mod reach;
pub mod record;

//! Resumable, checkpointed, deterministic parallel map over a direction set.

//! The stability boundary along rays (DESIGN.md §3).
//!
//! - [`continuum`]: the exact Kirchhoff-rod conjugate-point test.
//! - [`der`]: the Discrete Elastic Rods statics boundary.

pub mod continuum;
pub mod der;

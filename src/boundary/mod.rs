//! The stability boundary along rays ([architecture §3](crate::architecture)).
//!
//! - [`continuum`]: the exact Kirchhoff-rod conjugate-point test.
//! - [`der`]: the Discrete Elastic Rods statics boundary.

pub mod continuum;
pub mod der;

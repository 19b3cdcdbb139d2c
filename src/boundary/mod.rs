//! The stability boundary along rays ([architecture §3](crate::architecture)).
//!
//! - [`continuum`]: the exact Kirchhoff-rod conjugate-point test.
//! - [`der`]: the Discrete Elastic Rods statics boundary.
//! - [`Method`]: which of the two a command or the study uses.

pub mod continuum;
pub mod der;
pub mod method;

pub use method::Method;

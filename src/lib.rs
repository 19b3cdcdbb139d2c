//! # helixreach
//!
//! Plan robotic stability experiments on elastic rods with helical centerlines.
//!
//! A rod of length L is clamped at one end; a robot holds the other end and a motor twists it.
//! Every helical shape is a point (κ, τ, ω) (nondimensional: L = 1); the experiment drives the rod
//! from straight along a ray (κ, τ, ω) = s·S̄ until it snaps. This crate answers, for a given robot
//! and rig, which rays can be driven and with what joint + motor trajectory, and where the
//! stability boundary lies.
//!
//! ## Map
//! | module | holds |
//! |---|---|
//! | [`architecture`] | the design: math, conventions, data flow (`docs/ARCHITECTURE.md`) |
//! | [`math`] | scalar/geometry aliases, named tolerances, stable ratios (sin x/x, …) |
//! | [`error`] | the typed [`Error`] |
//! | [`io`] | atomic file output, output locks and checks, CSV input |
//! | [`cpu_time`] | the calling thread's CPU time (ns resolution), for speed figures |
//! | [`limits`] | the upper bound of every size parameter |
//! | [`helix`] | exact helix geometry: centerline, Frenet/Bishop/material frames, end pose, discrete helix, error metric |
//! | [`directions`] | direction sets on the half-sphere κ ≥ 0 (Fibonacci lattice, CSV) |
//! | [`rod`] | Discrete Elastic Rods: energies, gradients, Hessians, statics, dynamics |
//! | [`bifurcation`] | snap or gradual departure at s*: Koiter coefficient from DER statics, static return on unloading |
//! | [`compare`] | measured versus simulated boundaries (the paper's err per direction and its statistics) |
//! | [`detect`] | the snap from a recorded run (joints + tracked marker): s by projection, clamp, camera extrinsics and marker arc length, e, jump, streaming |
//! | [`boundary`] | the stability boundary along rays: continuum conjugate points and DER statics |
//! | [`robot`] | URDF robots: compiled kinematics, IK, collision |
//! | [`planning`] | rig files, pose paths, ladder graph, trajectories |
//! | [`sweep`] | reachability over direction sets (parallel, resumable) |
//! | [`layout`] | rig layout: clamp placements that together cover a direction set |
//! | [`records`] | typed rows (boundary, reach, series, speed-vs-error, trajectory) and their CSV readers |
//! | [`experiment`] | the whole study (the demo) as library stages with typed outcomes |
//! | `plot` | (feature `plots`) figures from saved records |
//! | [`progress`] | the progress bar on stderr (feature `progress`; plain lines without it) |
//!
//! Features: `cli` (default: the binary, progress bars, plots), `plots`, `progress`, `interop`
//! (k ↔ helixreach robots); `--no-default-features` builds the core alone. Formulas render with
//! KaTeX: `RUSTDOCFLAGS="--html-in-header $PWD/docs/katex-header.html" cargo doc --no-deps --open`.
//!
//! Dependencies point one way: `planning` → {`helix`, `robot`, `boundary`}; `boundary` → {`rod`,
//! `helix`}; `rod` → `helix`; `sweep` → `planning`; `plot` reads records only.

#[doc = include_str!("../docs/ARCHITECTURE.md")]
pub mod architecture {}
pub mod bifurcation;
pub mod boundary;
pub mod compare;
pub mod cpu_time;
pub mod detect;
pub mod directions;
pub mod error;
pub mod experiment;
pub mod helix;
pub mod io;
pub mod layout;
pub mod limits;
pub mod math;
pub mod par;
pub mod planning;
#[cfg(feature = "plots")]
pub mod plot;
pub mod progress;
pub mod records;
pub mod robot;
pub mod rod;
pub mod sources;
pub mod sweep;

pub use error::{Error, Result};

//! Rig files, pose paths, the decision of a ray, trajectories ([architecture §4–5](crate::architecture)).
//!
//! | module | holds |
//! |---|---|
//! | [`rig`] | the rig TOML schema, its validation, embedded rigs |
//! | [`rig_init`] | a first commented rig for any URDF arm, the clamp placed where it holds the rod |
//! | [`pose_path`] | a ray (S̄, α) as rod-end poses in the base frame, adaptive in s |
//! | [`pose_projection`] | a measured tool pose's s on a ray: a run's samples tracked along its pose curve |
//! | [`planner`] | the planner of one ray: robot, collision model, start set, validity; the decision by `planner.search` |
//! | [`search`] | the decision of one ray by a search of its valid set: a path or a certificate (the default) |
//! | [`ladder`] | the decision by rungs of tracked IK solutions and dynamic programming (`--search ladder`, the peer) |
//! | [`cause`] | why a ray stops: the blocking causes and their counts |
//! | [`self_motion`] | walking the self-motion manifold of a held pose; resampling within 1e-6 m / rad |
//! | [`trajectory`] | time parametrization and the CSV / JSON writers |
//! | [`campaign`] | a test campaign: every testable ray of a set, ordered, the moves between runs, sessions |
//! | [`check`] | validation of an existing joint trajectory: limits, collisions, steps, pose error |
//! | [`witness`] | an executed run as a witness of a feasible ray: projection, correction, jump classification |
//!
//! The whole pipeline of one ray:
//!
//! ```no_run
//! use helixreach::planning::{planner::Planner, rig::{Rig, RollMode}};
//! use helixreach::directions::Direction;
//! let planner = Planner::new(Rig::load("sawyer-seed")?)?;
//! let dir = Direction::new(0.5, 0.5, 0.7)?;
//! let s_star = helixreach::boundary::continuum::critical_s(&dir, 1e-10)?.s_star;
//! let plan = planner.plan_ray(&dir, s_star, 0.0, RollMode::Fixed, true)?;
//! let traj = planner.trajectory(&plan)?;
//! let csv = helixreach::records::trajectory::trajectory_csv(&traj)?;
//! std::fs::write("traj.csv", csv).unwrap();
//! # Ok::<(), helixreach::Error>(())
//! ```

pub mod campaign;
pub mod cause;
pub mod check;
pub mod ladder;
pub mod planner;
pub mod pose_path;
pub mod pose_projection;
pub mod rig;
pub mod rig_init;
pub mod rig_write;
pub mod search;
pub mod self_motion;
pub mod trajectory;
pub mod witness;

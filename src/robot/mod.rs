//! URDF robots: the immutable model, compiled allocation-free kinematics, inverse kinematics
//! returning every solution found, and collision checking ([architecture §4](crate::architecture)).
//!
//! ## Map
//! | module | holds |
//! |---|---|
//! | [`model`] | [`RobotModel`]: links, collision primitives, actuated joints and limits |
//! | [`urdf`] | loading with urdf-rs, validation, the built-in robots ([`builtin`]) |
//! | [`kinematics`] | the compiled [`Chain`]: tool pose, all link frames, 6×n geometric [`Jacobian`] |
//! | [`collision`] | parry collision: self (filtered pairs), scene obstacles, the rod as capsules; clearance |
//! | [`ik`] | box-constrained Levenberg–Marquardt IK: all distinct solutions, track mode |
//! | `k_bridge` | (feature `interop`) a robot as a k chain (nalgebra 0.30): the reference FK and peer IK; the only nalgebra-0.30 code |
//!
//! ```
//! use helixreach::robot::RobotModel;
//! let sawyer = RobotModel::load("sawyer", None).unwrap();
//! let q = [-0.857, -0.873, -1.819, -0.034, 1.860, 2.434, -2.200];
//! let tool = sawyer.tool_pose(&q).unwrap();
//! let (tool2, jac) = sawyer.jacobian(&q).unwrap();
//! assert_eq!(tool, tool2);
//! assert!(jac.column(0).norm() > 0.0);
//! ```

pub mod collision;
pub mod ik;
#[cfg(feature = "interop")]
pub mod k_bridge;
pub mod kinematics;
pub mod mesh;
pub mod model;
pub mod urdf;
pub mod xml_depth;

pub use collision::{
    CollisionModel, CollisionWorkspace, Contact, DisabledPairs, RodGeometry, SceneObstacle,
};
pub use ik::{IkParams, IkSolution, IkSolver, IkTarget};
pub use kinematics::{Chain, Frame, Jacobian, MAX_DOF};
pub use model::{
    pose_from_matrix, pose_from_xyz_wxyz, pose_to_xyz_wxyz, CollisionGeometry, JointInfo, LinkInfo,
    MeshGeometry, RobotModel, Shape,
};
pub use urdf::{builtin, Builtin, LoadOptions, BUILTINS};

//! The one place where k (built on nalgebra 0.30) meets the rest of the crate (nalgebra 0.34).
//!
//! k is the independent reference: its FK cross-checks the compiled chain in the tests, and its
//! `JacobianIkSolver` is the peer of [`crate::robot::ik`] in the benches. Conversions copy the
//! scalar components (translation and quaternion `w, i, j, k`), so they are exact.

use super::kinematics::Frame;
use super::model::RobotModel;
use crate::error::{Error, Result};
use crate::math::{Iso3, Quat, Real, Vec3};
use k::nalgebra as na30;
use k::prelude::*;

/// An isometry of k's nalgebra (0.30).
pub type KIso = na30::Isometry3<Real>;

/// nalgebra 0.30 isometry → ours.
pub fn iso_from_k(iso: &KIso) -> Iso3 {
    let t = iso.translation.vector;
    let q = iso.rotation.quaternion();
    Iso3::from_parts(
        Vec3::new(t.x, t.y, t.z).into(),
        Quat::new_unchecked(nalgebra::Quaternion::new(q.w, q.i, q.j, q.k)),
    )
}

/// Our isometry → nalgebra 0.30.
pub fn iso_to_k(iso: &Iso3) -> KIso {
    let t = iso.translation.vector;
    let q = iso.rotation.quaternion();
    KIso::from_parts(
        na30::Translation3::new(t.x, t.y, t.z),
        na30::UnitQuaternion::new_unchecked(na30::Quaternion::new(q.w, q.i, q.j, q.k)),
    )
}

/// k's view of a model: the whole tree and the serial chain from the root to the tool link.
#[derive(Debug)]
pub struct KRobot {
    /// The whole tree, as `k::Chain::from(&urdf)` builds it.
    pub chain: k::Chain<Real>,
    /// Root → tool link.
    pub arm: k::SerialChain<Real>,
    /// For every link of the model (model order), the k node whose child is that link (`None`
    /// for the root).
    nodes: Vec<Option<k::Node<Real>>>,
    /// Nodes of frozen (off-chain) movable joints and their values.
    frozen: Vec<(k::Node<Real>, Real)>,
}

impl KRobot {
    /// Build k's chain from the model's URDF.
    pub fn new(model: &RobotModel) -> Result<KRobot> {
        let chain = k::Chain::<Real>::from(model.urdf());
        let missing = |what: &str| Error::invalid("k chain", what, "link not found by k");
        let tip = chain
            .find_link(model.tip_link())
            .ok_or_else(|| missing(model.tip_link()))?
            .clone();
        let arm = k::SerialChain::from_end(&tip);
        let mut nodes = Vec::with_capacity(model.links().len());
        for (i, l) in model.links().iter().enumerate() {
            if i == 0 {
                nodes.push(None);
            } else {
                nodes.push(Some(
                    chain
                        .find_link(&l.name)
                        .ok_or_else(|| missing(&l.name))?
                        .clone(),
                ));
            }
        }
        let mut frozen = Vec::new();
        for (name, v) in model.frozen_joints() {
            if let Some(n) = chain.find(name) {
                frozen.push((n.clone(), *v));
            }
        }
        Ok(KRobot {
            chain,
            arm,
            nodes,
            frozen,
        })
    }

    /// Tool pose by k's FK.
    pub fn tool_pose(&self, q: &[Real]) -> Frame {
        self.arm.set_joint_positions_unchecked(q);
        Frame::from_iso(&iso_from_k(&self.arm.end_transform()))
    }

    /// Every link frame by k's FK, in the model's link order.
    pub fn link_frames(&self, q: &[Real]) -> Vec<Frame> {
        self.arm.set_joint_positions_unchecked(q);
        for (n, v) in &self.frozen {
            n.set_joint_position_unchecked(*v);
        }
        self.chain.update_transforms();
        self.nodes
            .iter()
            .map(|n| match n {
                None => Frame::identity(),
                Some(n) => Frame::from_iso(&iso_from_k(
                    &n.world_transform().unwrap_or_else(KIso::identity),
                )),
            })
            .collect()
    }

    /// k's `JacobianIkSolver` from the seed `seed` toward `target`; the joints on success.
    /// `solver` is e.g. `k::JacobianIkSolver::new(1e-10, 1e-10, 0.5, 100)`.
    pub fn solve_ik(
        &self,
        solver: &k::JacobianIkSolver<Real>,
        target: &Frame,
        seed: &[Real],
    ) -> Option<Vec<Real>> {
        self.arm.set_joint_positions_unchecked(seed);
        let t = iso_to_k(&target.to_iso());
        solver.solve(&self.arm, &t).ok()?;
        Some(self.arm.joint_positions())
    }
}

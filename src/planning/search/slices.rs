//! The slices of a ray: its waypoints s₀ = 0 < s₁ < … < s_N = s*·(1 + margin) (the rig's pose
//! path spacing), and at each one the test that a configuration belongs to the slice's valid set.
//!
//! A configuration of slice i is a joint vector q and, in roll `motor`, the arm's roll ψ about
//! the rod tangent relative to the transported frame. It holds the slice's rod-end pose when
//! the tip pose of q is `T_i·Rz(−ψ)·tool⁻¹` (ψ = 0 in roll `fixed`); the motor then turns the rod
//! by `m = ω_i/c − ψ` ([`crate::planning::planner`], "Shared by both decisions": the same convention). It is
//! **valid** when q lies in the joint limits (IK iterates stay in the box), m in the motor range,
//! and q is free of self, scene and rod collision, the rod being the helix of slice i as
//! `planner.rod_capsules` capsules of radius r + `rod_clearance`, without the last
//! `rod_end_exclusion` metres.
//!
//! A joint-linear segment between configurations of slices i and j (|i − j| ≤ 1) is checked at
//! interior samples no more than `planner.segment_check_step` apart (max-norm) against the rod of
//! the larger s: the same rule as the ladder's edges, so each edge is checked the same way in
//! both directions.

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::{rot_z, tol, Real, Vec3};
use crate::planning::cause::BlockCause;
use crate::planning::planner::{cause_of, Planner};
use crate::planning::pose_path::{pose_path, PoseMap, Ray, Spacing, Waypoint};
use crate::planning::rig::iso_from;
use crate::robot::{CollisionWorkspace, Frame, IkTarget, MAX_DOF};

/// The slices of one ray: waypoints and rods.
#[derive(Debug)]
pub(crate) struct Slices {
    /// Waypoints, s increasing from 0.
    pub wps: Vec<Waypoint>,
    /// Rod capsule nodes of each slice (base frame).
    pub rods: Vec<Vec<Vec3>>,
    /// The boundary s* of the ray (back-off is allowed at slices with s ≤ s*).
    pub s_star: Real,
    /// Target s of the ray.
    pub s_end: Real,
    /// The ray's direction (κ, τ, ω) per unit s, its azimuth, and its pose map (for poses
    /// between slices).
    dir: [Real; 3],
    azimuth: Real,
    map: PoseMap,
}

impl Slices {
    /// The slices of `dir` at `azimuth` up to `s*·(1 + margin)` (`tol::S_MAX` when `s_star` is
    /// infinite). Errors: `s_star` not positive, a non-finite azimuth.
    pub fn new(planner: &Planner, dir: &Direction, s_star: Real, azimuth: Real) -> Result<Slices> {
        if s_star.is_nan() || s_star <= 0.0 {
            return Err(Error::invalid("s_star", s_star, "must be > 0 (or +inf)"));
        }
        crate::error::require_finite("azimuth", azimuth)?;
        let rig = &planner.rig;
        let s_end = if s_star.is_finite() {
            s_star * (1.0 + rig.planner.margin)
        } else {
            tol::S_MAX
        };
        let ray = Ray {
            dir: [dir.kappa, dir.tau, dir.omega],
            azimuth,
        };
        let wps = pose_path(rig, &ray, s_end, &Spacing::of(rig))?;
        let mut rods = Vec::with_capacity(wps.len());
        for w in &wps {
            let mut r = vec![Vec3::zeros(); rig.planner.rod_capsules + 1];
            planner.rod_nodes(w.kto, azimuth, &mut r)?;
            rods.push(r);
        }
        Ok(Slices {
            wps,
            rods,
            s_star,
            s_end,
            dir: ray.dir,
            azimuth,
            map: PoseMap::new(rig, azimuth),
        })
    }

    /// Number of slices.
    pub fn len(&self) -> usize {
        self.wps.len()
    }

    /// The tip-link pose of slice `i` at arm roll `psi`.
    pub fn tip(&self, planner: &Planner, i: usize, psi: Real) -> Frame {
        tip_of(planner, &self.wps[i], psi)
    }

    /// The full-pose IK target of slice `i` at arm roll `psi`.
    pub fn target(&self, planner: &Planner, i: usize, psi: Real) -> IkTarget {
        IkTarget::Pose(self.tip(planner, i, psi))
    }

    /// Motor angle of a configuration of slice `i` at arm roll `psi`.
    pub fn motor(&self, i: usize, psi: Real) -> Real {
        self.wps[i].motor - psi
    }

    /// The waypoint at `s` between slices (a bridge's intermediate pose) and its rod's nodes
    /// written into `rod` (`planner.rod_capsules` + 1 points).
    pub fn between(&self, planner: &Planner, s: Real, rod: &mut [Vec3]) -> Result<Waypoint> {
        let kto = [s * self.dir[0], s * self.dir[1], s * self.dir[2]];
        let (tool, motor) = self.map.end(kto)?;
        planner.rod_nodes(kto, self.azimuth, rod)?;
        Ok(Waypoint {
            s,
            kto,
            tool,
            motor,
        })
    }

    /// Collision test of `q` against the scene, itself and the rod of slice `i`.
    pub fn check(
        &self,
        planner: &Planner,
        i: usize,
        q: &[Real],
        ws: &mut CollisionWorkspace,
    ) -> std::result::Result<(), BlockCause> {
        check_rod(planner, &self.rods[i], q, ws)
    }

    /// Collision test of the interior of the joint-linear segment a → b against the rod of
    /// slice `i` (the larger s of the two ends), samples at most `segment_check_step` apart.
    pub fn segment(
        &self,
        planner: &Planner,
        i: usize,
        a: &[Real; MAX_DOF],
        b: &[Real; MAX_DOF],
        ws: &mut CollisionWorkspace,
    ) -> std::result::Result<(), BlockCause> {
        segment_rod(planner, &self.rods[i], a, b, ws)
    }
}

/// The tip-link pose of waypoint `w` (a slice's, or one between slices) at arm roll `psi`.
pub(crate) fn tip_of(planner: &Planner, w: &Waypoint, psi: Real) -> Frame {
    let r = w.tool.rotation.to_rotation_matrix().into_inner() * rot_z(-psi);
    planner.tip_target(&iso_from(&r, &w.tool.translation.vector))
}

/// Collision test of `q` against the scene, itself and the rod with capsule nodes `rod`.
pub(crate) fn check_rod(
    planner: &Planner,
    rod: &[Vec3],
    q: &[Real],
    ws: &mut CollisionWorkspace,
) -> std::result::Result<(), BlockCause> {
    let rod = planner.rig.rod_geometry(rod);
    match planner.collision.check(q, ws, Some(&rod)) {
        None => Ok(()),
        Some(c) => Err(cause_of(&c)),
    }
}

/// Collision test of the interior of the joint-linear segment a → b against the rod with
/// capsule nodes `rod`, samples at most `segment_check_step` apart.
pub(crate) fn segment_rod(
    planner: &Planner,
    rod: &[Vec3],
    a: &[Real; MAX_DOF],
    b: &[Real; MAX_DOF],
    ws: &mut CollisionWorkspace,
) -> std::result::Result<(), BlockCause> {
    let dof = planner.dof;
    let dmax = (0..dof).map(|j| (b[j] - a[j]).abs()).fold(0.0, Real::max);
    let n = (dmax / planner.rig.planner.segment_check_step).ceil() as usize;
    let mut qi = [0.0; MAX_DOF];
    for k in 1..n {
        let t = k as Real / n as Real;
        for j in 0..dof {
            qi[j] = a[j] + t * (b[j] - a[j]);
        }
        check_rod(planner, rod, &qi[..dof], ws)?;
    }
    Ok(())
}

/// A fixture of the search's unit tests: the seed rig after `edit`, its planner, the slices of
/// direction 100 of the 200-direction quarter-sphere lattice at azimuth 0 (s* of the continuum
/// test), and a collision model of the test's own with the rig's obstacles.
#[cfg(test)]
pub(crate) fn seed_ray_100(
    edit: impl FnOnce(&mut crate::planning::rig::Rig),
) -> (
    crate::planning::rig::Rig,
    Planner,
    Slices,
    crate::robot::CollisionModel,
) {
    let mut rig = crate::planning::rig::Rig::load("sawyer-seed").unwrap();
    edit(&mut rig);
    let planner = Planner::new(rig.clone()).unwrap();
    let dir = crate::directions::fibonacci(200, true).unwrap()[100];
    let s_star = crate::boundary::continuum::critical_s(&dir, 1e-10)
        .unwrap()
        .s_star;
    let slices = Slices::new(&planner, &dir, s_star, 0.0).unwrap();
    let mut cm = crate::robot::CollisionModel::for_model(planner.model()).unwrap();
    cm.set_obstacles(&rig.obstacles).unwrap();
    (rig, planner, slices, cm)
}

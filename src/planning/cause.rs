//! Why a ray stops, or a node or an edge is rejected: the blocking causes shared by both
//! decisions of a ray ([`crate::planning::search`] and [`crate::planning::ladder`]) and the
//! records, and their counts.
//!
//! ```
//! use helixreach::planning::cause::{BlockCause, CauseCounts};
//! let mut c = CauseCounts::default();
//! c.add(BlockCause::JointLimit);
//! c.add(BlockCause::SelfCollision);
//! c.add(BlockCause::SelfCollision);
//! assert_eq!(c.dominant(), Some(BlockCause::SelfCollision));
//! assert_eq!(BlockCause::parse("no_ik"), Some(BlockCause::NoIk));
//! ```

/// Why a ray could not be driven further (or a node / an edge was rejected). The one
/// blocking-cause type: records read and write it by serde (the [`BlockCause::as_str`] names).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum BlockCause {
    /// No IK solution for the pose.
    NoIk,
    /// IK solutions exist only outside the joint (or motor) limits.
    JointLimit,
    /// The arm collides with itself.
    SelfCollision,
    /// The arm collides with a scene obstacle.
    SceneCollision,
    /// The arm collides with the rod.
    RodCollision,
    /// Valid configurations exist but none is within a joint step of the previous rung.
    Discontinuity,
    /// The pose path hit the rig's `planner.max_waypoints` before s*·(1 + margin): the ray was
    /// planned only up to its last waypoint.
    WaypointLimit,
}

impl BlockCause {
    /// All causes, in pipeline order.
    pub const ALL: [BlockCause; 7] = [
        BlockCause::NoIk,
        BlockCause::JointLimit,
        BlockCause::SelfCollision,
        BlockCause::SceneCollision,
        BlockCause::RodCollision,
        BlockCause::Discontinuity,
        BlockCause::WaypointLimit,
    ];

    /// The name used in CSV output (`no_ik`, `joint_limit`, …).
    pub fn as_str(&self) -> &'static str {
        match self {
            BlockCause::NoIk => "no_ik",
            BlockCause::JointLimit => "joint_limit",
            BlockCause::SelfCollision => "self_collision",
            BlockCause::SceneCollision => "scene_collision",
            BlockCause::RodCollision => "rod_collision",
            BlockCause::Discontinuity => "discontinuity",
            BlockCause::WaypointLimit => "waypoint_limit",
        }
    }

    /// Parse the CSV name.
    pub fn parse(s: &str) -> Option<BlockCause> {
        BlockCause::ALL.into_iter().find(|c| c.as_str() == s)
    }

    fn index(&self) -> usize {
        *self as usize
    }
}

impl std::fmt::Display for BlockCause {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Counts of rejections per cause; [`CauseCounts::dominant`] names the most frequent one
/// (ties go to the earlier cause in pipeline order).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CauseCounts(pub [u32; BlockCause::ALL.len()]);

impl CauseCounts {
    /// Count one rejection.
    pub fn add(&mut self, c: BlockCause) {
        self.0[c.index()] += 1;
    }
    /// Add all counts of `other`.
    pub fn merge(&mut self, other: &CauseCounts) {
        for (a, b) in self.0.iter_mut().zip(other.0) {
            *a += b;
        }
    }
    /// Total number of rejections.
    pub fn total(&self) -> u32 {
        self.0.iter().sum()
    }
    /// The most frequent cause, or `None` when nothing was rejected.
    pub fn dominant(&self) -> Option<BlockCause> {
        let mut best: Option<(u32, BlockCause)> = None;
        for c in BlockCause::ALL {
            let n = self.0[c.index()];
            if n > 0 && best.is_none_or(|(m, _)| n > m) {
                best = Some((n, c));
            }
        }
        best.map(|(_, c)| c)
    }
}

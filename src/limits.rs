//! Upper bounds of every size parameter, in one place.
//!
//! Each limit is far above any sensible use (the seed paper's largest sweep is 58,352
//! directions; its trajectories have 2,000 waypoints) and far below what would exhaust memory
//! or run for days, so a typo (`--fibonacci 100000000000`, `--n-edges 100000000`) is a clear
//! error naming the flag, the value and the limit — never an out-of-memory abort or a hang.
//!
//! | parameter | limit | why |
//! |---|---|---|
//! | directions in a set (`--fibonacci`, rows of a `--directions` CSV) | [`MAX_DIRECTIONS`] = 10,000,000 | 171× the paper's sweep; ~1 GB of rows |
//! | rows of a trajectory file (`check`, `render`, `plot trajectory`) | [`MAX_TRAJECTORY_ROWS`] = 1,000,000 | 500× the seed's runs |
//! | DER edges (`--n-edges`) | [`MAX_N_EDGES`] = 10,000 | 100× the default; cost grows ~n² per direction |
//! | azimuths per ray (`--azimuths`, rig `azimuths`) | [`MAX_AZIMUTHS`] = 3,600 | 0.1° spacing |
//! | IK redundancy samples (`ik --samples`) | [`MAX_IK_SAMPLES`] = 100,000 | |
//! | IK random restarts (`ik --restarts`) | [`MAX_IK_RESTARTS`] = 1,000,000 | ≥ 40 × [`MAX_RIG_COUNT`], the planner's start sampling |
//! | IK explicit lock values and lock seeds ([`crate::robot::ik::IkParams`]) | [`MAX_IK_SAMPLES`] | |
//! | IK iterations per run ([`crate::robot::ik::IkParams::max_iterations`]) | [`MAX_IK_ITERATIONS`] = 100,000 | |
//! | waypoints per ray (`plan --waypoints`, rig `waypoints`) | the rig's `max_waypoints`, itself ≤ [`MAX_WAYPOINTS`] = 1,000,000 | |
//! | self-collision sampling (`robot --samples`, [`crate::robot::DisabledPairs::compute`]) | [`MIN_DISABLED_SAMPLES`] = 10,000 ≤ n ≤ [`MAX_DISABLED_SAMPLES`] = 10,000,000 | see [`crate::robot`]'s disabled pairs |
//! | DER edges of `simulate`/`disturbances` (`--n-edges`) | [`MAX_N_EDGES`] | |
//! | rendered frames (`render --frames`, `--gif-frames`) | [`MAX_FRAMES`] = 10,000 | one image each |
//! | shards (`--shard I/N`) | N ≤ [`MAX_SHARDS`] = 100,000 | |
//! | checkpoint interval (`--checkpoint-secs`) | ≤ [`MAX_CHECKPOINT_SECS`] = 1 day | |
//! | search nodes per ray (rig `planner.max_search_nodes`) | [`MAX_SEARCH_NODES`] = 6,000,000 | ≈ 1 GiB |
//! | the search's self-motion step (rig `planner.search_step`) | ≤ `planner.max_joint_step`, and coarse enough that one slice's cover (16 curves of length 2π at 0.6 of the step) fits `planner.max_search_nodes` ([`crate::planning::search::check_resolution`]) | nodes per slice ∝ 1 / step |
//! | halvings of a slice interval by a search bridge (rig `planner.bridge_halvings`) | [`MAX_BRIDGE_HALVINGS`] = 8 | at most 2⁸ tracks per bridge |
//! | collision mesh files ([`crate::robot::mesh`]) | [`MAX_MESH_FILE_BYTES`] = 64 MiB, [`MAX_MESH_TRIANGLES`] = 1,000,000 triangles | bounded memory |
//! | rig TOML counts (`roll.samples`, `planner.redundancy_samples`, `planner.rod_capsules`) | [`MAX_RIG_COUNT`] = 10,000 | per ray, per waypoint |
//! | distance along a ray (`--s-max` of `boundary`, `check`, `simulate`) | ≤ [`MAX_S`] = 1e4 | bounds every scan over s |
//! | worker threads (`--threads`) | 1 ≤ n ≤ [`MAX_THREADS`] = 1,024 | one OS thread each |
//! | collision sampling of a joint step (rig `planner.segment_check_step`) | ≥ [`MIN_SEGMENT_CHECK_STEP`] = 0.001 rad | samples ∝ step / segment_check_step; `check` samples a step with at most [`MAX_SEGMENT_SAMPLES`] = 10,000 configurations (a step that needs more is a jump) |
//! | continuum scan step (`boundary --step`) | ≥ [`MIN_CONTINUUM_STEP`] = 1e-4 | ≈ 0.2 s per direction at the limit |
//! | URDF element nesting | ≤ [`MAX_XML_DEPTH`] = 256 | a URDF nests ≈ 6 deep; the XML parser recurses per level |
//!
//! ```
//! use helixreach::limits::{check_size, MAX_N_EDGES};
//! assert!(check_size("--n-edges", 100, MAX_N_EDGES).is_ok());
//! let e = check_size("--n-edges", 100_000_000, MAX_N_EDGES).unwrap_err().to_string();
//! assert!(e.contains("--n-edges") && e.contains("100000000") && e.contains("10000"), "{e}");
//! ```

use crate::error::{Error, Result};

/// Most directions in one direction set.
pub const MAX_DIRECTIONS: usize = 10_000_000;
/// Most rows of a trajectory file (`check --trajectory`, `render --trajectory`, the figure's
/// trajectory; [`crate::records::trajectory::read_trajectory_file`]).
pub const MAX_TRAJECTORY_ROWS: usize = 1_000_000;
/// Most DER edges.
pub const MAX_N_EDGES: usize = 10_000;
/// Most azimuths tried per ray.
pub const MAX_AZIMUTHS: usize = 3_600;
/// Most IK redundancy samples.
pub const MAX_IK_SAMPLES: usize = 100_000;
/// Most IK random restarts per redundancy sample. At least 40 × [`MAX_RIG_COUNT`]: the planner
/// samples a start pose's self-motion manifold with `40 × max(redundancy_samples,
/// roll.samples)` restarts ([`IkSolver::new`](crate::robot::ik::IkSolver::new) checks this
/// limit), so every rig the rig limits accept stays plannable.
pub const MAX_IK_RESTARTS: usize = 1_000_000;
const _: () = assert!(40 * MAX_RIG_COUNT <= MAX_IK_RESTARTS);
/// Most Levenberg–Marquardt iterations of one IK run.
pub const MAX_IK_ITERATIONS: usize = 100_000;
/// Most waypoints per ray (the rig's `max_waypoints` may be lower).
pub const MAX_WAYPOINTS: usize = 1_000_000;
/// Most nodes of one ray's search (rig `planner.max_search_nodes`): 1 GiB at ≈ 168 bytes per
/// node ([`crate::planning::search::MAX_SEARCH_BYTES`]).
pub const MAX_SEARCH_NODES: usize = 6_000_000;

/// Most halvings of a slice interval by the search's bridges (rig `planner.bridge_halvings`):
/// poses down to 1/256 of the interval, at most 2⁸ tracks per bridge.
pub const MAX_BRIDGE_HALVINGS: usize = 8;
/// Fewest random configurations for recomputing a robot's never-colliding link pairs: with n
/// samples, a pair that collides on a fraction p of the configuration space is missed with
/// probability (1 − p)ⁿ; n = 10,000 misses a p = 0.1 % pair with probability < 5·10⁻⁵.
pub const MIN_DISABLED_SAMPLES: usize = 10_000;
/// Most random configurations for the never-colliding pairs.
pub const MAX_DISABLED_SAMPLES: usize = 10_000_000;
/// Most time steps of one DER dynamics run (load, hold and unload together): at the seed's
/// n = 100 a step costs ≈ 0.1–1 ms, so this is minutes to hours of CPU, not days.
pub const MAX_SIM_STEPS: usize = 10_000_000;
/// Most rendered frames.
pub const MAX_FRAMES: usize = 10_000;
/// Most shards of a sweep.
pub const MAX_SHARDS: usize = 100_000;
/// Longest checkpoint interval, seconds.
pub const MAX_CHECKPOINT_SECS: f64 = 86_400.0;

/// Largest `s_max`, the distance along a ray a command scans, loads or checks to (`boundary`,
/// `check`, `simulate`, the DER statics): 50× the farthest s* of the half sphere (≈ 200), and
/// it bounds every scan over s (`s_max / step` points).
pub const MAX_S: f64 = 1e4;

/// Most worker threads (`--threads`).
pub const MAX_THREADS: usize = 1_024;
/// Smallest rig `planner.segment_check_step` (rad): the planner and `check` sample each joint
/// step every `segment_check_step`.
pub const MIN_SEGMENT_CHECK_STEP: f64 = 1e-3;
/// Most collision samples of one joint step in `check`.
pub const MAX_SEGMENT_SAMPLES: usize = 10_000;
/// Smallest scan step of the continuum boundary test (`boundary --step`).
pub const MIN_CONTINUUM_STEP: f64 = 1e-4;
/// Deepest element nesting of a URDF file.
pub const MAX_XML_DEPTH: usize = 256;

/// Most of any other per-ray or per-waypoint count of a rig TOML.
pub const MAX_RIG_COUNT: usize = 10_000;

/// The upper bound of the rig TOML count `field` (`azimuth.count`, `planner.max_waypoints`, or
/// [`MAX_RIG_COUNT`]).
pub fn rig_count_max(field: &str) -> usize {
    match field {
        "azimuth.count" => MAX_AZIMUTHS,
        "planner.max_waypoints" => MAX_WAYPOINTS,
        "planner.max_search_nodes" => MAX_SEARCH_NODES,
        "planner.bridge_halvings" => MAX_BRIDGE_HALVINGS,
        _ => MAX_RIG_COUNT,
    }
}

/// `Ok(n)` when `n ≤ max`, else an [`Error::InvalidParameter`] naming `what`, `n` and the limit.
pub fn check_size(what: &str, n: usize, max: usize) -> Result<usize> {
    if n <= max {
        Ok(n)
    } else {
        Err(Error::invalid(
            what,
            n,
            format!("must be <= {max} (helixreach::limits)"),
        ))
    }
}

/// `Ok(n)` when `min ≤ n ≤ max`, else an error naming `what`, `n` and the range.
pub fn check_range(what: &str, n: usize, min: usize, max: usize) -> Result<usize> {
    if (min..=max).contains(&n) {
        Ok(n)
    } else {
        Err(Error::invalid(
            what,
            n,
            format!("must be in {min}..={max} (helixreach::limits)"),
        ))
    }
}

/// Largest mesh file read for collision geometry (bytes): checked before reading, so a huge
/// mesh is a clear error, never an out-of-memory abort (a 2-million-triangle binary STL is
/// 100 MB; the arms' collision meshes are ≤ 3 MB).
pub const MAX_MESH_FILE_BYTES: u64 = 64 * 1024 * 1024;
/// Most triangles of one collision mesh (a binary STL's declared count is checked before it is
/// parsed).
pub const MAX_MESH_TRIANGLES: usize = 1_000_000;

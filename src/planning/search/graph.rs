//! The search: best-first flood fill of the valid set from every start configuration.
//!
//! # Nodes and resolution
//! A node is a configuration ([`super::linking::Config`]) reached by an accepted edge (or a
//! start). A new configuration is **the same node** as an existing one of the same slice when
//! every joint differs by at most `MERGE_FRACTION`·h (h = `planner.search_step`) and the
//! roll by at most `MERGE_FRACTION`·`ROLL_STEP`: the valid set of a slice is represented by
//! samples at most about h apart along each self-motion curve (roll `fixed`, 7-DOF), by a
//! grid-like cover of h × `ROLL_STEP` (roll `motor`), or by its isolated points (6-DOF).
//!
//! Lookup: a slice's nodes are kept in cells, buckets of the redundancy joint at least the merge
//! radius wide and, with roll moves, once the slice holds more than `SPLIT_AT` nodes, roll cells
//! at least the roll merge radius wide (ψ modulo the period when it is compared modulo one,
//! else folded modulo the cell count); a lookup scans the (at most) 3 × 3 cells around a
//! configuration, so its cost is that of the nodes near it, not of the slice (a slice of a roll
//! `motor` piece holds thousands of nodes spread over the roll).
//!
//! The roll ψ is the arm's turn about the rod tangent, unwrapped along each edge; the motor
//! then stands at m = ω/c − ψ. When the motor turns freely (range (−∞, ∞)) the roll is compared
//! modulo 2π: (q, ψ) and (q, ψ + 2π) hold the same rod end with the same joints, every move
//! from one has its copy from the other (the targets are 2π-periodic in ψ and no motor angle is
//! refused), so they are one node. Unwrapped, the search would flood a copy of a piece for
//! every winding of the motor that a loop of the piece makes. With a bounded motor range the
//! winding decides which motor angles are left, and the roll is compared as it is.
//!
//! # Order
//! Nodes wait in a priority queue keyed by (probe, slice, move kind, insertion order), largest
//! first; a node is queued once for its load move, then for its moves inside the slice, then
//! (stage 2) for its back-off move. **Probe chains** come first: a few start configurations of
//! every start component (the caller marks them) and the nodes their load steps make; each probe
//! chain is driven forward until it is blocked, like one tracked branch. Then the search drives
//! forward from the farthest unexpanded node (a testable ray costs about one node per slice) and
//! falls back to reconfiguration or back-off when blocked. The order decides only how soon a path
//! is found: every node is expanded in full before the queue empties. When the queue empties the
//! reachable piece is exhausted: every node reachable from the starts at this resolution has
//! been expanded, and the farthest slice among them is the ray's `s_reached` (the certificate).
//!
//! # Moves
//! Load and (when the rig allows reconfiguration, and always at slice 0, where the rod is not
//! yet clamped) walk/roll moves; back-off moves from slices with s ≤ s* when the rig allows
//! them. A reverse graph ([`Direction::Reverse`], the far-end search of the certificate) makes
//! the reversed moves: from slice j to j − 1 (a reversed load), inside the slice (always at its
//! first slice, to cover that slice's valid set), to j + 1 ≤ cap where s ≤ s* (a reversed
//! back-off).
//!
//! A node reached across slices (a load or back-off edge from its parent) goes back to its
//! parent's slice by that edge reversed: the same joint-linear segment (or a bridge's chain of
//! them), checked against the same rods, within the same step bound, so it is an edge of the
//! graph and the parent is already a node. That move is not tracked again.
//!
//! With [`Rules::defer_segments`] an edge of one step is kept once its end is valid, marked
//! unchecked; [`Graph::check_deferred`] tests the marked segments of one path (parent module
//! docs, "Deferred segment tests").
//!
//! # Bound
//! At most `planner.max_search_nodes` nodes (each ≈ 168 bytes with its null direction, and the
//! cell heads: one row of buckets per slice with a node, a row of buckets × roll cells, at most
//! `MAX_ROW_CELLS` heads of 4 bytes, per slice of more than `SPLIT_AT` nodes): a search that
//! would create more stops and the ray is `undecided` (never a guessed class).

use super::linking::{Config, Linker, Move, Proposal, ROLL_STEP};
use crate::math::Real;
use crate::planning::cause::CauseCounts;
use crate::planning::pose_path::Waypoint;
use crate::planning::self_motion::Q;
use std::collections::BinaryHeap;

/// Two configurations of one slice closer than this fraction of the walk step (every joint; and
/// of the roll step in ψ) are one node.
pub(crate) const MERGE_FRACTION: Real = 0.6;

/// Queue entry kinds, expanded in this order at one slice: the load move, the moves inside the
/// slice, the back-off move.
const LOAD: u8 = 2;
const INSIDE: u8 = 1;
const BACK: u8 = 0;

/// Bytes per node, for the memory bound's message (node, null direction, bucket link, queue
/// entry).
pub(crate) const NODE_BYTES: usize = 168;

/// Most buckets of the redundancy joint per slice: a finer merge radius gets wider buckets
/// (never narrower than the radius, so a lookup scans three).
const MAX_BUCKETS: usize = 1024;

/// Most cell heads of a slice split by roll (buckets × roll cells; 32 KB).
const MAX_ROW_CELLS: usize = 8192;

/// Nodes of a slice beyond which its buckets are split by roll (roll moves only): a slice
/// holding fewer keeps one row of buckets.
const SPLIT_AT: usize = 512;

/// No node.
const NONE: u32 = u32::MAX;

/// How a node was reached.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Via {
    /// A start configuration.
    Start,
    /// A load step from the previous slice.
    Load,
    /// A back-off step from the next slice.
    Backoff,
    /// A move inside the slice (walk or roll).
    Reconfigure,
}

/// A node of the search graph.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Node {
    /// The configuration.
    pub c: Config,
    /// The node it was reached from (`u32::MAX` for a start).
    pub parent: u32,
    /// How.
    pub via: Via,
}

/// The outcome of a search.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Outcome {
    /// A node of the last slice (its index).
    Reached(u32),
    /// The reachable piece is exhausted.
    Exhausted,
    /// The node bound was hit.
    Bound,
}

/// Search settings.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Rules {
    /// Moves inside a slice after slice 0.
    pub reconfigure: bool,
    /// Back-off moves (stage 2).
    pub backoff: bool,
    /// Roll moves (roll `motor`).
    pub roll: bool,
    /// Node bound.
    pub max_nodes: usize,
    /// Defer the interior collision test of single-step edges (module docs, "Deferred
    /// segment tests"): the node is kept with its edge marked unchecked.
    pub defer_segments: bool,
}

/// The search graph of one ray.
pub(crate) struct Graph {
    /// Nodes in insertion order.
    pub nodes: Vec<Node>,
    /// Per slice: the last node inserted in each cell (redundancy-joint bucket, or bucket ×
    /// roll cell row-major once the slice is split; empty until the slice gets a node; `NONE`
    /// for an empty cell).
    heads: Vec<Vec<u32>>,
    /// Per slice: its nodes.
    counts: Vec<u32>,
    /// Per node: the node inserted before it in its cell (`NONE` for the first).
    next: Vec<u32>,
    /// Lower end and width of the redundancy joint's buckets, and their number.
    red_lo: Real,
    width: Real,
    n_buckets: usize,
    /// Roll cells per bucket of a split slice (1 without roll moves: never split) and their
    /// width in ψ.
    psi_cells: usize,
    psi_width: Real,
    queue: BinaryHeap<(bool, u32, u8, u32)>,
    /// Per node: on a probe chain (a probe start and its load steps).
    probe: Vec<bool>,
    /// Per node: the interior of the segment from its parent is not yet checked.
    unchecked: Vec<bool>,
    /// Per node: its null direction, kept from the track that made it for its walks (NaN when
    /// none was at hand; [`Linker::null_hint`]).
    nulls: Vec<Q>,
    /// Probe entries in the queue.
    probing: usize,
    /// Rejected forward (load) moves per slice, by cause.
    pub causes: Vec<CauseCounts>,
    /// Farthest slice of any node.
    pub farthest: u32,
    /// Nodes made by the last [`Graph::step`].
    pub fresh: Vec<u32>,
    /// Per node reached by a bridged move ([`super::linking::Proposal::Bridged`]): the poses,
    /// configurations and arm rolls between its parent and it, from the parent's side.
    pub bridges: std::collections::HashMap<u32, Vec<(Waypoint, Q, Real)>>,
    merge_q: Real,
    /// The period of the arm roll ψ in the merge rule (`Some(2π)` when the motor turns freely).
    roll_period: Option<Real>,
    red: usize,
    dof: usize,
}

impl Rules {
    /// Whether nodes of `slice` make moves inside it: with reconfiguration allowed, and always
    /// at slice 0 (and at the first slice of a reverse search, to cover its valid set).
    fn walks(&self, dir: Direction, slice: u32) -> bool {
        match dir {
            Direction::Forward => self.reconfigure || slice == 0,
            Direction::Reverse { cap } => self.reconfigure || slice == 0 || slice == cap,
        }
    }
}

/// Which way a graph searches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Direction {
    /// From the starts toward the last slice.
    Forward,
    /// From the valid set of slice `cap` toward the starts, along reversed edges, never above
    /// `cap` (the far-end search of the certificate).
    Reverse {
        /// The slice it starts from.
        cap: u32,
    },
}

/// How the merge rule meets the arm roll ψ (module docs, "Nodes and resolution").
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum RollMerge {
    /// No roll moves: every node has the start's ψ.
    Constant,
    /// Roll moves; ψ compared as it is (a bounded motor).
    Unwrapped,
    /// Roll moves; ψ compared modulo this period (a freely turning motor: 2π).
    Periodic(Real),
}

impl Graph {
    /// An empty graph for `n_slices` slices of a `dof`-joint arm, bucketed on joint `red`
    /// whose range is `red_range` and, with roll moves, on the roll (module docs, "Nodes and
    /// resolution").
    pub fn new(
        n_slices: usize,
        dof: usize,
        red: usize,
        red_range: (Real, Real),
        merge_q: Real,
        roll: RollMerge,
    ) -> Graph {
        let span = (red_range.1 - red_range.0).max(0.0);
        let width = merge_q.max(span / MAX_BUCKETS as Real);
        let n_buckets = ((span / width).floor() as usize + 1).min(MAX_BUCKETS + 1);
        let rpsi = MERGE_FRACTION * ROLL_STEP;
        let most = (MAX_ROW_CELLS / n_buckets).max(1);
        let psi_cells = match roll {
            RollMerge::Constant => 1,
            RollMerge::Unwrapped => most,
            RollMerge::Periodic(p) => ((p / rpsi).floor() as usize).clamp(1, most),
        };
        let psi_width = match roll {
            RollMerge::Periodic(p) => p / psi_cells as Real,
            RollMerge::Constant | RollMerge::Unwrapped => rpsi,
        };
        Graph {
            nodes: Vec::new(),
            heads: vec![Vec::new(); n_slices],
            counts: vec![0; n_slices],
            next: Vec::new(),
            red_lo: red_range.0,
            width,
            n_buckets,
            psi_cells,
            psi_width,
            queue: BinaryHeap::new(),
            probe: Vec::new(),
            unchecked: Vec::new(),
            nulls: Vec::new(),
            probing: 0,
            causes: vec![CauseCounts::default(); n_slices],
            farthest: 0,
            fresh: Vec::new(),
            bridges: std::collections::HashMap::new(),
            merge_q,
            roll_period: match roll {
                RollMerge::Periodic(p) => Some(p),
                RollMerge::Constant | RollMerge::Unwrapped => None,
            },
            red,
            dof,
        }
    }

    /// The bucket of `c`'s redundancy joint (joints stay in their limits; round-off is
    /// clamped into the end buckets).
    fn bucket(&self, c: &Config) -> usize {
        let k = ((c.q[self.red] - self.red_lo) / self.width).floor();
        if k >= 0.0 {
            (k as usize).min(self.n_buckets - 1)
        } else {
            0
        }
    }

    /// The roll cell of `c` among `n` (1 on a slice not split): ψ modulo the period in cells
    /// of `psi_width` (at least the roll merge radius, so two rolls within it are in the same
    /// or cyclically neighbouring cells), or, unwrapped, ψ in cells of that radius folded
    /// modulo the cell count.
    fn roll_cell(&self, c: &Config, n: usize) -> usize {
        if n == 1 {
            return 0;
        }
        let k = match self.roll_period {
            Some(p) => (c.psi.rem_euclid(p) / self.psi_width).floor(),
            None => (c.psi / self.psi_width).floor(),
        };
        // Finite ψ: the cast saturates, the remainder folds it into the cells.
        (k as i64).rem_euclid(n as i64) as usize
    }

    /// Roll cells per bucket of a slice's row: `psi_cells` once split, else 1.
    fn cells_of(&self, row: &[u32]) -> usize {
        if row.len() > self.n_buckets {
            self.psi_cells
        } else {
            1
        }
    }

    /// The node of `c`'s slice within the merge radius of `c`, if any: a scan of the 3 × 3
    /// cells around it (fewer when a dimension has fewer cells).
    pub fn find(&self, c: &Config) -> Option<u32> {
        let row = self.heads.get(c.slice as usize)?;
        if row.is_empty() {
            return None;
        }
        let k = self.bucket(c);
        let n = self.cells_of(row);
        let r = self.roll_cell(c, n);
        let rolls = [r, (r + 1) % n, (r + n - 1) % n];
        let rolls = &rolls[..n.min(3)];
        let rpsi = MERGE_FRACTION * ROLL_STEP;
        for kk in k.saturating_sub(1)..=(k + 1).min(self.n_buckets - 1) {
            for &rr in rolls {
                let mut id = row[kk * n + rr];
                while id != NONE {
                    let o = &self.nodes[id as usize].c;
                    // Joints first (most candidates differ there), then the roll.
                    if (0..self.dof).all(|j| (o.q[j] - c.q[j]).abs() <= self.merge_q) {
                        let mut dpsi = (o.psi - c.psi).abs();
                        if let (true, Some(p)) = (dpsi > rpsi, self.roll_period) {
                            let r = dpsi % p;
                            dpsi = r.min(p - r);
                        }
                        if dpsi <= rpsi {
                            return Some(id);
                        }
                    }
                    id = self.next[id as usize];
                }
            }
        }
        None
    }

    /// The nodes from a root (a start) to `end`, root first, and the index of the first one off
    /// slice 0 (the length when there is none).
    pub fn chain_to(&self, end: u32) -> (Vec<u32>, usize) {
        let mut chain = Vec::new();
        let mut id = end;
        while id != NONE {
            chain.push(id);
            id = self.nodes[id as usize].parent;
        }
        chain.reverse();
        let first = chain
            .iter()
            .position(|&i| self.nodes[i as usize].c.slice != 0)
            .unwrap_or(chain.len());
        (chain, first)
    }

    /// Check the deferred segments on the path to node `end` from the last slice-0 node before
    /// its first load step (where a path begins: [`super::path`]); `false` at the first one in
    /// collision. Checked edges are marked so.
    pub fn check_deferred(&mut self, end: u32, linker: &mut Linker<'_>) -> bool {
        // The edges into the nodes from the first one off slice 0.
        let (chain, first) = self.chain_to(end);
        for &i in &chain[first..] {
            let n = self.nodes[i as usize];
            if self.unchecked[i as usize] {
                let parent = self.nodes[n.parent as usize].c;
                if linker.accept_segment(&parent, &n.c).is_err() {
                    return false;
                }
                self.unchecked[i as usize] = false;
            }
        }
        true
    }

    /// Add a node and queue it (on a probe chain when its load step came from one).
    pub fn insert(&mut self, n: Node) -> u32 {
        let probe = n.via == Via::Load && self.probe[n.parent as usize];
        self.insert_as(n, probe)
    }

    /// Add a start node that begins a probe chain: its load steps are expanded before any
    /// other move (module docs, "Order").
    pub fn insert_probe(&mut self, n: Node) -> u32 {
        self.insert_as(n, true)
    }

    fn insert_as(&mut self, n: Node, probe: bool) -> u32 {
        let id = self.nodes.len() as u32;
        let slice = n.c.slice as usize;
        if self.heads[slice].is_empty() {
            self.heads[slice].resize(self.n_buckets, NONE);
        }
        self.counts[slice] += 1;
        if self.psi_cells > 1
            && self.counts[slice] as usize > SPLIT_AT
            && self.heads[slice].len() == self.n_buckets
        {
            self.split(slice);
        }
        let cells = self.cells_of(&self.heads[slice]);
        let k = self.bucket(&n.c) * cells + self.roll_cell(&n.c, cells);
        self.next.push(self.heads[slice][k]);
        self.heads[slice][k] = id;
        self.farthest = self.farthest.max(n.c.slice);
        self.queue.push((probe, n.c.slice, LOAD, id));
        self.probing += usize::from(probe);
        self.probe.push(probe);
        self.unchecked.push(false);
        self.nulls.push([Real::NAN; crate::robot::MAX_DOF]);
        self.nodes.push(n);
        id
    }

    /// Split a slice's buckets by roll: its nodes relinked into buckets × `psi_cells` cells,
    /// each cell's list newest first (as inserted).
    fn split(&mut self, slice: usize) {
        let mut ids: Vec<u32> = Vec::with_capacity(self.counts[slice] as usize);
        for &head in &self.heads[slice] {
            let mut id = head;
            while id != NONE {
                ids.push(id);
                id = self.next[id as usize];
            }
        }
        ids.sort_unstable();
        let n = self.psi_cells;
        let mut row = vec![NONE; self.n_buckets * n];
        for id in ids {
            let c = &self.nodes[id as usize].c;
            let k = self.bucket(c) * n + self.roll_cell(c, n);
            self.next[id as usize] = row[k];
            row[k] = id;
        }
        self.heads[slice] = row;
    }

    /// The merge radius in joints (rad).
    pub fn merge_q(&self) -> Real {
        self.merge_q
    }

    /// The slice of the next queued node (`None` when the queue is empty).
    pub fn top(&self) -> Option<u32> {
        self.queue.peek().map(|e| e.1)
    }

    /// Whether probe chains are still queued.
    pub fn probing(&self) -> bool {
        self.probing > 0
    }

    /// Expand the next queued node (module docs). Returns `Some` when the search ends: a node
    /// of slice `goal` was made (forward: the last slice), the queue is empty, or the bound was
    /// hit. The nodes made are listed in `self.fresh`.
    pub fn step(
        &mut self,
        linker: &mut Linker<'_>,
        rules: &Rules,
        goal: u32,
        dir: Direction,
        backoff_ok: &dyn Fn(u32) -> bool,
    ) -> Option<Outcome> {
        self.fresh.clear();
        let Some((probe, slice, kind, id)) = self.queue.pop() else {
            return Some(Outcome::Exhausted);
        };
        self.probing -= usize::from(probe);
        let x = self.nodes[id as usize].c;
        let mut moves = [Move::Load; 4];
        let mut n_moves = 0;
        let mut push = |m: Move| {
            moves[n_moves] = m;
            n_moves += 1;
        };
        // Forward: load, then inside, then back-off. Reverse (the nodes from which `cap` can be
        // reached): the reverse of a load (to the previous slice), inside, the reverse of a
        // back-off (to the next slice, at most `cap`, where s ≤ s*).
        match kind {
            LOAD => {
                match dir {
                    Direction::Forward => push(Move::Load),
                    Direction::Reverse { .. } => push(Move::Backoff),
                }
                self.queue.push((false, slice, INSIDE, id));
            }
            INSIDE => {
                if rules.walks(dir, slice) {
                    let n = self.nulls[id as usize];
                    if !n[0].is_nan() {
                        linker.prime_null(&x.q, n);
                    }
                    push(Move::Walk(1));
                    push(Move::Walk(-1));
                    if rules.roll {
                        push(Move::Roll(1));
                        push(Move::Roll(-1));
                    }
                }
                if rules.backoff {
                    self.queue.push((false, slice, BACK, id));
                }
            }
            _ => match dir {
                Direction::Forward if backoff_ok(slice) => push(Move::Backoff),
                Direction::Reverse { cap } if slice < cap && backoff_ok(slice + 1) => {
                    push(Move::Load)
                }
                _ => {}
            },
        }
        // A node reached across slices returns to its parent's slice by the edge it came by
        // (the same segment, checked the same way in both directions): no track for it.
        let n = &self.nodes[id as usize];
        let came_from = match n.via {
            Via::Load | Via::Backoff => Some(self.nodes[n.parent as usize].c.slice),
            Via::Start | Via::Reconfigure => None,
        };
        for &mv in &moves[..n_moves] {
            let to = match mv {
                Move::Load => Some(slice + 1),
                Move::Backoff => slice.checked_sub(1),
                Move::Walk(_) | Move::Roll(_) => None,
            };
            if to.is_some() && to == came_from {
                continue;
            }
            let counted = dir == Direction::Forward && mv == Move::Load;
            let (y, bridged) = match linker.propose(&x, mv, &|c| self.find(c).is_some()) {
                Ok(Some(Proposal::Step(y))) => (y, false),
                Ok(Some(Proposal::Bridged(y))) => (y, true),
                Ok(None) => continue,
                Err(cause) => {
                    if counted {
                        self.causes[slice as usize].add(cause);
                    }
                    continue;
                }
            };
            if self.find(&y).is_some() {
                continue;
            }
            let mut ys = [Some(y), None];
            if !bridged {
                let checked = if rules.defer_segments {
                    linker.accept_end(&y)
                } else {
                    linker.accept(&x, &y)
                };
                if let Err(cause) = checked {
                    if counted {
                        self.causes[slice as usize].add(cause);
                    }
                    if !matches!(mv, Move::Load | Move::Backoff) {
                        continue;
                    }
                    // The track landed on an invalid point: the nearest valid ones of its
                    // slice within the joint-step bound, on either side (module docs).
                    ys = [1.0, -1.0].map(|sign| {
                        linker
                            .landing(&x, &y, sign, &|c| self.find(c).is_some())
                            .filter(|l| {
                                rules.defer_segments || linker.accept_segment(&x, l).is_ok()
                            })
                    });
                }
            }
            let via = match (mv, dir) {
                (Move::Walk(_) | Move::Roll(_), _) => Via::Reconfigure,
                (Move::Load, Direction::Forward) | (Move::Backoff, Direction::Reverse { .. }) => {
                    Via::Load
                }
                _ => Via::Backoff,
            };
            for y in ys.into_iter().flatten() {
                if self.nodes.len() >= rules.max_nodes {
                    return Some(Outcome::Bound);
                }
                let nid = self.insert(Node {
                    c: y,
                    parent: id,
                    via,
                });
                if bridged {
                    self.bridges.insert(nid, std::mem::take(&mut linker.bridge));
                } else {
                    self.unchecked[nid as usize] = rules.defer_segments;
                }
                if rules.walks(dir, y.slice) {
                    if let Some(n) = linker.null_hint(&y) {
                        self.nulls[nid as usize] = n;
                    }
                }
                self.fresh.push(nid);
                if y.slice == goal {
                    return Some(Outcome::Reached(nid));
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// With a roll period of 2π, a configuration whose roll differs from a node's by a whole
    /// number of turns (within the roll merge radius) is that node; without one, or off by more
    /// than the radius, or with other joints, it is not. At rolls far from 0 (several windings),
    /// both signs.
    #[test]
    fn roll_is_compared_modulo_the_period() {
        let tau = std::f64::consts::TAU;
        let merge_q = 0.096;
        let rpsi = MERGE_FRACTION * ROLL_STEP;
        let mut q = [0.0; crate::robot::MAX_DOF];
        q[..7].copy_from_slice(&[0.3, -0.8, 0.2, 1.4, -0.3, 0.9, 0.1]);
        for roll in [RollMerge::Unwrapped, RollMerge::Periodic(tau)] {
            for psi in [-11.3, -0.7, 0.0, 2.9, 9.6] {
                let c = Config { slice: 1, q, psi };
                let mut g = Graph::new(2, 7, 0, (-3.05, 3.05), merge_q, roll);
                let id = g.insert(Node {
                    c,
                    parent: u32::MAX,
                    via: Via::Start,
                });
                // The same roll, and one within the radius, are the node in every mode.
                assert_eq!(g.find(&c), Some(id));
                let near = Config {
                    psi: psi - 0.9 * rpsi,
                    ..c
                };
                assert_eq!(g.find(&near), Some(id));
                for turns in [-2.0, -1.0, 1.0, 3.0] {
                    for off in [0.0, 0.9 * rpsi, -0.9 * rpsi] {
                        let w = Config {
                            psi: psi + turns * tau + off,
                            ..c
                        };
                        let expect = (roll != RollMerge::Unwrapped).then_some(id);
                        assert_eq!(g.find(&w), expect, "{psi} {turns} {off}");
                        let mut other = w;
                        other.q[6] += 1.5 * merge_q;
                        assert_eq!(g.find(&other), None, "{psi} {turns}");
                    }
                    let far = Config {
                        psi: psi + turns * tau + 1.5 * rpsi,
                        ..c
                    };
                    assert_eq!(g.find(&far), None, "{psi} {turns}");
                }
            }
        }
    }

    /// The bucketed lookup equals a linear scan of the slice's nodes (the merge rule of the
    /// module docs: every joint within the radius, the roll within its radius, modulo the period
    /// when there is one), for configurations near stored ones, at bucket edges and at the ends
    /// of the redundancy joint's range (values at and just past the limits), with a merge radius
    /// finer than `MAX_BUCKETS` buckets can cover (wider buckets); with roll moves at rolls of
    /// several turns either way, on roll-cell edges and whole turns apart, before and after a
    /// slice is split by roll (more than `SPLIT_AT` nodes), with the rig's roll cells and with
    /// one, two or three of them (folded cells).
    #[test]
    fn find_equals_a_linear_scan() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let tau = std::f64::consts::TAU;
        let rpsi = MERGE_FRACTION * ROLL_STEP;
        for (merge_q, range, roll, cells) in [
            (0.012, (-3.05, 3.05), RollMerge::Constant, None),
            (1e-4, (-3.05, 3.05), RollMerge::Constant, None),
            (0.3, (0.0, 1.0), RollMerge::Constant, None),
            (0.05, (0.0, 1.0), RollMerge::Unwrapped, None),
            (0.05, (0.0, 1.0), RollMerge::Periodic(tau), None),
            (0.012, (-3.05, 3.05), RollMerge::Periodic(tau), None),
            (0.05, (0.0, 1.0), RollMerge::Periodic(tau), Some(1)),
            (0.05, (0.0, 1.0), RollMerge::Unwrapped, Some(2)),
            (0.05, (0.0, 1.0), RollMerge::Periodic(tau), Some(3)),
        ] {
            let mut g = Graph::new(4, 7, 0, range, merge_q, roll);
            if let Some(n) = cells {
                g.psi_cells = n;
                if let RollMerge::Periodic(p) = roll {
                    g.psi_width = p / n as Real;
                }
            }
            let draw = |rng: &mut ChaCha8Rng| {
                let mut q = [0.0; crate::robot::MAX_DOF];
                // Joint 0 often on a bucket edge or a limit; the others in a small box so that
                // merges happen.
                q[0] = match rng.random_range(0..4) {
                    0 => range.0 + merge_q * rng.random_range(0..40) as Real,
                    1 => range.1 - 1e-12,
                    2 => range.0,
                    _ => rng.random_range(range.0..range.1),
                };
                for v in q.iter_mut().skip(1) {
                    *v = rng.random_range(-0.05..0.05);
                }
                // The roll: on a cell edge, near whole turns, or anywhere in ±2 turns.
                let psi = match (roll, rng.random_range(0..3)) {
                    (RollMerge::Constant, _) => 0.37,
                    (_, 0) => rpsi * rng.random_range(-800..800) as Real,
                    (_, 1) => tau * rng.random_range(-2..=2) as Real + rng.random_range(-0.1..0.1),
                    _ => rng.random_range(-2.0 * tau..2.0 * tau),
                };
                Config {
                    slice: rng.random_range(0..4),
                    q,
                    psi,
                }
            };
            let scan = |g: &Graph, c: &Config| {
                g.nodes.iter().any(|n| {
                    let d = n.c.psi - c.psi;
                    let dpsi = match roll {
                        RollMerge::Periodic(p) => (d - p * (d / p).round()).abs(),
                        _ => d.abs(),
                    };
                    n.c.slice == c.slice
                        && (0..7).all(|j| (n.c.q[j] - c.q[j]).abs() <= merge_q)
                        && dpsi <= rpsi
                })
            };
            for _ in 0..3000 {
                let c = draw(&mut rng);
                let found = g.find(&c);
                assert_eq!(found.is_some(), scan(&g, &c), "{roll:?} {c:?}");
                if let Some(id) = found {
                    let o = &g.nodes[id as usize].c;
                    assert_eq!(o.slice, c.slice);
                    assert!((0..7).all(|j| (o.q[j] - c.q[j]).abs() <= merge_q));
                } else {
                    g.insert(Node {
                        c,
                        parent: u32::MAX,
                        via: Via::Start,
                    });
                }
                // A configuration just inside the merge radius of a stored one (a whole turn
                // away with a period) is found.
                let k = rng.random_range(0..g.nodes.len());
                let mut near = g.nodes[k].c;
                for v in near.q.iter_mut().take(7) {
                    *v += rng.random_range(-0.99..0.99) * merge_q;
                }
                if roll != RollMerge::Constant {
                    near.psi += rng.random_range(-0.99..0.99) * rpsi;
                }
                if let RollMerge::Periodic(p) = roll {
                    near.psi += p * rng.random_range(-1..=1) as Real;
                }
                assert_eq!(g.find(&near).is_some(), scan(&g, &near), "{roll:?}");
                assert!(g.find(&near).is_some());
            }
            // With roll moves every slice ended split (the lookups above ran on both forms).
            let split = g.heads.iter().filter(|r| r.len() > g.n_buckets).count();
            let expect = if g.psi_cells > 1 { 4 } else { 0 };
            assert_eq!(split, expect, "{roll:?} {cells:?} {:?}", g.counts);
        }
    }

    /// `check_deferred` tests exactly the unchecked edges of the path after its last slice-0
    /// node before the first load step, by the segment rule (samples at most
    /// `planner.segment_check_step` apart, the rod of the larger slice): on paths start →
    /// (load) slice 1 → (inside) another configuration, its answer equals a reference of the
    /// test's own (a collision model and the pose map's centreline) for jumps to start
    /// configurations of every start component and to random joint vectors — some in
    /// collision, some free —; a colliding
    /// move at slice 0 before the first load is not on the path; a checked edge is not tested.
    #[test]
    fn deferred_segments_are_checked_on_the_path_only() {
        use crate::planning::pose_path::PoseMap;
        use crate::planning::rig::RollMode;
        let (rig, planner, slices, cm) = super::super::slices::seed_ray_100(|_| {});
        let mut linker = Linker::new(&planner, &slices).unwrap();
        let mut ws = cm.workspace();
        let rod1 = PoseMap::new(&rig, 0.0)
            .centerline(slices.wps[1].kto, rig.planner.rod_capsules)
            .unwrap();
        let reference_free = |a: &Q, b: &Q, ws: &mut crate::robot::CollisionWorkspace| {
            let dmax = (0..7).map(|j| (b[j] - a[j]).abs()).fold(0.0, Real::max);
            let n = (dmax / rig.planner.segment_check_step).ceil() as usize;
            (1..n).all(|m| {
                let t = m as Real / n as Real;
                let q: Vec<Real> = (0..7).map(|j| a[j] + t * (b[j] - a[j])).collect();
                cm.check(&q, ws, Some(&rig.rod_geometry(&rod1))).is_none()
            })
        };
        let starts: Vec<Q> = planner
            .start(RollMode::Fixed)
            .unwrap()
            .comps
            .iter()
            .flat_map(|c| c.iter().step_by(9).map(|n| n.q))
            .collect();
        let a = starts[0];
        // Other starts, and random joint vectors in the limits (many of their segments cross
        // the pedestal or the arm itself).
        let (lo, hi) = (planner.model().lower(), planner.model().upper());
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut targets = starts[1..].to_vec();
        for _ in 0..20 {
            let mut q = [0.0; crate::robot::MAX_DOF];
            for j in 0..7 {
                q[j] = rng.random_range(lo[j]..hi[j]);
            }
            targets.push(q);
        }
        let (mut blocked, mut free) = (0, 0);
        for &q in &targets {
            let mut g = Graph::new(slices.len(), 7, 0, (-3.05, 3.05), 1e-9, RollMerge::Constant);
            let node = |slice, q, parent, via| Node {
                c: Config { slice, q, psi: 0.0 },
                parent,
                via,
            };
            let root = g.insert(node(0, a, NONE, Via::Start));
            // A colliding or free jump at slice 0, then the load: only the load is on the path.
            let jump0 = g.insert(node(0, q, root, Via::Reconfigure));
            let load0 = g.insert(node(1, q, jump0, Via::Load));
            g.unchecked[jump0 as usize] = true;
            g.unchecked[load0 as usize] = true;
            assert!(g.check_deferred(load0, &mut linker));
            assert!(!g.unchecked[load0 as usize] && g.unchecked[jump0 as usize]);
            // The load, then the jump at slice 1.
            let load = g.insert(node(1, a, root, Via::Load));
            let jump = g.insert(node(1, q, load, Via::Reconfigure));
            g.unchecked[load as usize] = true;
            g.unchecked[jump as usize] = true;
            let expect = reference_free(&a, &q, &mut ws);
            assert_eq!(g.check_deferred(jump, &mut linker), expect);
            assert_eq!(g.unchecked[jump as usize], !expect);
            if expect {
                free += 1;
            } else {
                blocked += 1;
                // Marked checked, an edge is taken as it is.
                g.unchecked[jump as usize] = false;
                assert!(g.check_deferred(jump, &mut linker));
            }
        }
        assert!(blocked >= 1 && free >= 1, "{blocked} blocked, {free} free");
    }
}

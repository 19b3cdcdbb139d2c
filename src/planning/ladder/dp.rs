//! The ladder graph (Descartes-style) and its minimum-cost path by forward dynamic programming.
//!
//! Waypoint k of a pose path owns a **rung**: a set of candidate configurations (nodes) that all
//! realize the waypoint's pose. Edges join consecutive rungs only; the graph is a layered DAG, so
//! the minimum-cost path is a single forward sweep:
//!
//! `C(k+1, j) = min_i { C(k, i) + c(i, j) }` over the edges `i → j` that pass both gates,
//!
//! where `c(i, j)` is the edge cost (‖W·Δθ‖ + w_m·|Δmotor| in the planner) and the two gates are a
//! cheap one (every joint step below the bound: `cost` returns `None` otherwise) and an expensive
//! one (the straight-line joint motion is collision-free: `check`). The expensive gate is run
//! lazily: candidate predecessors of `j` are visited in increasing `C(k, i) + c(i, j)` and the
//! first that passes wins, which is exact because the gate does not change the cost.
//!
//! **Early pruning**: nodes of rung k+1 without any admissible predecessor are dropped at once
//! (they can never be on a full path), so later rungs only see reachable nodes; when a rung has
//! none left the sweep stops and reports the farthest rung reached and the blocking cause.
//! Work is O(V + E·log d) for V nodes, E cheap-gate edges and in-degree d (the log from sorting the
//! candidates of each node), memory O(V).
//!
//! The ladder is generic over the node contents `N`; the planner stores joint vectors and motor
//! angles in it.
//!
//! ```
//! use helixreach::planning::{cause::BlockCause, ladder::dp::Ladder};
//! // Two tracks along three rungs; the cheap gate forbids steps larger than 1.
//! let mut l: Ladder<f64> = Ladder::new();
//! l.push_first(vec![0.0, 10.0]);
//! let cost = |a: &f64, b: &f64| { let d = (a - b).abs(); (d <= 1.0).then_some(d) };
//! let ok = |_: &f64, _: &f64| Ok(());
//! assert_eq!(l.push_rung(vec![0.5, 10.2], cost, ok).reachable, 2);
//! assert_eq!(l.push_rung(vec![1.0, 20.0], cost, ok).reachable, 1);
//! let (path, c) = l.best_path().unwrap();
//! assert_eq!(path, vec![&0.0, &0.5, &1.0]);
//! assert!((c - 1.0).abs() < 1e-15);
//! // A rung out of reach stops the sweep with a discontinuity.
//! let out = l.push_rung(vec![5.0], cost, ok);
//! assert_eq!((out.reachable, out.cause), (0, Some(BlockCause::Discontinuity)));
//! ```

use crate::math::Real;
use crate::planning::cause::{BlockCause, CauseCounts};

/// The outcome of pushing one rung.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RungOutcome {
    /// Nodes of the new rung with an admissible predecessor (kept).
    pub reachable: usize,
    /// When `reachable == 0`: why (no nodes at all is reported by the caller; here it is
    /// [`BlockCause::Discontinuity`] when no edge passed the step bound, else the dominant cause
    /// of the failed segment checks).
    pub cause: Option<BlockCause>,
    /// Edges that passed the cheap gate.
    pub edges: usize,
}

/// A layered graph under forward dynamic programming. Only reachable nodes are stored.
#[derive(Debug, Clone)]
pub struct Ladder<N> {
    nodes: Vec<Vec<N>>,
    cost: Vec<Vec<Real>>,
    pred: Vec<Vec<u32>>,
    // Scratch: candidate (total cost, predecessor) pairs of one node.
    cand: Vec<(Real, u32)>,
}

impl<N> Default for Ladder<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<N> Ladder<N> {
    /// An empty ladder.
    pub fn new() -> Self {
        Ladder {
            nodes: Vec::new(),
            cost: Vec::new(),
            pred: Vec::new(),
            cand: Vec::new(),
        }
    }

    /// Start the ladder with its first rung (all nodes reachable at cost 0).
    /// Any previous content is cleared.
    pub fn push_first(&mut self, nodes: Vec<N>) {
        self.nodes.clear();
        self.cost.clear();
        self.pred.clear();
        self.cost.push(vec![0.0; nodes.len()]);
        self.pred.push(vec![u32::MAX; nodes.len()]);
        self.nodes.push(nodes);
    }

    /// Number of rungs (including the first).
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// True when no rung was pushed.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The reachable nodes of the last rung and their costs.
    pub fn last(&self) -> (&[N], &[Real]) {
        match (self.nodes.last(), self.cost.last()) {
            (Some(n), Some(c)) => (n, c),
            _ => (&[], &[]),
        }
    }

    /// Total number of stored (reachable) nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.iter().map(Vec::len).sum()
    }

    /// Push the next rung. `cost(prev, next)` is the cheap gate and edge cost (`None` = no edge);
    /// `check(prev, next)` the expensive gate, run lazily on the cheapest candidates first.
    /// Nodes without an admissible predecessor are dropped. When none is left the rung is **not**
    /// stored (the ladder keeps its farthest reachable rung) and the outcome names the cause.
    /// Pushing onto an empty ladder acts as [`Ladder::push_first`].
    pub fn push_rung<C, K>(&mut self, nodes: Vec<N>, mut cost: C, mut check: K) -> RungOutcome
    where
        C: FnMut(&N, &N) -> Option<Real>,
        K: FnMut(&N, &N) -> Result<(), BlockCause>,
    {
        if self.nodes.is_empty() {
            let n = nodes.len();
            self.push_first(nodes);
            return RungOutcome {
                reachable: n,
                cause: None,
                edges: 0,
            };
        }
        let prev_nodes = self.nodes.last().expect("non-empty");
        let prev_cost = self.cost.last().expect("non-empty");
        let mut keep: Vec<bool> = Vec::with_capacity(nodes.len());
        let mut new_cost = Vec::with_capacity(nodes.len());
        let mut new_pred = Vec::with_capacity(nodes.len());
        let mut edges = 0usize;
        let mut failed = CauseCounts::default();
        for nj in &nodes {
            self.cand.clear();
            for (i, ni) in prev_nodes.iter().enumerate() {
                if let Some(c) = cost(ni, nj) {
                    self.cand.push((prev_cost[i] + c, i as u32));
                }
            }
            edges += self.cand.len();
            // Cheapest first; ties by index keep the result deterministic.
            self.cand
                .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let mut chosen = None;
            for &(c, i) in &self.cand {
                match check(&prev_nodes[i as usize], nj) {
                    Ok(()) => {
                        chosen = Some((c, i));
                        break;
                    }
                    Err(cause) => failed.add(cause),
                }
            }
            match chosen {
                Some((c, i)) => {
                    keep.push(true);
                    new_cost.push(c);
                    new_pred.push(i);
                }
                None => keep.push(false),
            }
        }
        let reachable = new_cost.len();
        if reachable == 0 {
            let cause = if edges == 0 {
                BlockCause::Discontinuity
            } else {
                failed.dominant().unwrap_or(BlockCause::Discontinuity)
            };
            return RungOutcome {
                reachable: 0,
                cause: Some(cause),
                edges,
            };
        }
        let kept: Vec<N> = nodes
            .into_iter()
            .zip(keep)
            .filter_map(|(n, k)| k.then_some(n))
            .collect();
        self.nodes.push(kept);
        self.cost.push(new_cost);
        self.pred.push(new_pred);
        RungOutcome {
            reachable,
            cause: None,
            edges,
        }
    }

    /// The minimum-cost path from the first rung to the last stored rung, and its cost.
    /// `None` for an empty ladder (or an empty first rung).
    pub fn best_path(&self) -> Option<(Vec<&N>, Real)> {
        let (last_nodes, last_cost) = self.last();
        if last_nodes.is_empty() {
            return None;
        }
        let mut j = 0usize;
        for (k, c) in last_cost.iter().enumerate() {
            if c.total_cmp(&last_cost[j]).is_lt() {
                j = k;
            }
        }
        self.path_to(j)
    }

    /// The minimum-cost path from the first rung to node `j` of the last stored rung, and its
    /// cost; `None` when there is no such node.
    pub fn path_to(&self, j: usize) -> Option<(Vec<&N>, Real)> {
        let (last_nodes, last_cost) = self.last();
        if j >= last_nodes.len() {
            return None;
        }
        let mut j = j;
        let total = last_cost[j];
        let mut path = Vec::with_capacity(self.nodes.len());
        for r in (0..self.nodes.len()).rev() {
            path.push(&self.nodes[r][j]);
            j = self.pred[r][j] as usize;
        }
        path.reverse();
        Some((path, total))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// Brute force over every path of a small layered graph: the DP optimum must equal it.
    #[test]
    fn dp_matches_brute_force() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for trial in 0..200 {
            let n_rungs = rng.random_range(2..6);
            let rungs: Vec<Vec<f64>> = (0..n_rungs)
                .map(|_| {
                    let m = rng.random_range(1..5);
                    (0..m).map(|_| rng.random_range(0.0..3.0)).collect()
                })
                .collect();
            // Blocked edges: a deterministic pseudo-random subset (by value hash).
            let blocked = |a: &f64, b: &f64| ((a * 1000.0) as i64 + (b * 7919.0) as i64) % 5 == 0;
            let cost = |a: &f64, b: &f64| {
                let d = (a - b).abs();
                (d <= 1.5).then_some(d * d + 0.1)
            };
            let mut l = Ladder::new();
            l.push_first(rungs[0].clone());
            let mut full = true;
            for r in &rungs[1..] {
                let out = l.push_rung(r.clone(), cost, |a, b| {
                    if blocked(a, b) {
                        Err(BlockCause::RodCollision)
                    } else {
                        Ok(())
                    }
                });
                if out.reachable == 0 {
                    full = false;
                    break;
                }
            }
            // Brute force: enumerate all index tuples.
            let mut best = f64::INFINITY;
            let mut idx = vec![0usize; n_rungs];
            'outer: loop {
                let mut c = 0.0;
                let mut ok = true;
                for k in 1..n_rungs {
                    let (a, b) = (&rungs[k - 1][idx[k - 1]], &rungs[k][idx[k]]);
                    match cost(a, b) {
                        Some(e) if !blocked(a, b) => c += e,
                        _ => {
                            ok = false;
                            break;
                        }
                    }
                }
                if ok {
                    best = best.min(c);
                }
                for k in (0..n_rungs).rev() {
                    idx[k] += 1;
                    if idx[k] < rungs[k].len() {
                        continue 'outer;
                    }
                    idx[k] = 0;
                }
                break;
            }
            if full {
                let (path, c) = l.best_path().unwrap();
                assert!((c - best).abs() < 1e-12, "trial {trial}: {c} vs {best}");
                // The path's own cost recomputed edge by edge equals the reported one.
                let recomputed: f64 = path.windows(2).map(|w| cost(w[0], w[1]).unwrap()).sum();
                assert!((recomputed - c).abs() < 1e-12);
            } else {
                assert!(
                    best.is_infinite(),
                    "trial {trial}: DP blocked but a path exists"
                );
            }
        }
    }

    #[test]
    fn causes_are_reported() {
        let mut l: Ladder<f64> = Ladder::new();
        l.push_first(vec![0.0]);
        let cost = |a: &f64, b: &f64| ((a - b).abs() < 1.0).then_some(0.0);
        let out = l.push_rung(vec![0.5, 0.6], cost, |_, b| {
            if *b < 0.55 {
                Err(BlockCause::SelfCollision)
            } else {
                Err(BlockCause::SceneCollision)
            }
        });
        assert_eq!(out.reachable, 0);
        // One of each: the tie goes to the earlier cause.
        assert_eq!(out.cause, Some(BlockCause::SelfCollision));
        assert_eq!(l.len(), 1, "a dead rung is not stored");
        let mut cc = CauseCounts::default();
        assert_eq!(cc.dominant(), None);
        cc.add(BlockCause::RodCollision);
        cc.add(BlockCause::RodCollision);
        cc.add(BlockCause::NoIk);
        assert_eq!(cc.dominant(), Some(BlockCause::RodCollision));
        for c in BlockCause::ALL {
            assert_eq!(BlockCause::parse(c.as_str()), Some(c));
        }
    }
}

//! Maximum coverage with K sets ("budgeted set cover"): choose at most `k` of the candidate
//! placements so that the union of the directions they can test is largest.
//!
//! - [`greedy`]: repeatedly take the set that adds the most uncovered elements (ties: the lowest
//!   index). The classic bound holds: greedy ≥ (1 − (1 − 1/k)^k)·OPT ≥ (1 − 1/e)·OPT.
//! - [`exact`]: the optimum by depth-first branch and bound over the sets in index order. A node
//!   with `r` picks left is pruned when its coverage plus the `r` largest marginal gains of the
//!   sets still allowed cannot beat the incumbent (an upper bound: a union never covers more than
//!   the sum of its parts). The incumbent starts at the greedy value, so the search only has to
//!   prove optimality or find a better choice. Work is bounded by `node_limit`; when the limit is
//!   hit the answer is returned as *not proven* ([`Cover::proven`] = false), never as optimal.
//! - [`brute_force`]: every subset of size ≤ k (for tests and tiny instances).
//!
//! Sets are [`BitSet`]s over the element indices `0..n`.
//!
//! ```
//! use helixreach::layout::set_cover::{exact, greedy, BitSet};
//! // Greedy takes {0,1,2,3} first and then needs two more sets; the optimum {0,1,4},{2,3,5}
//! // covers all six with two.
//! let sets: Vec<BitSet> = [vec![0, 1, 2, 3], vec![0, 1, 4], vec![2, 3, 5]]
//!     .iter()
//!     .map(|s| BitSet::from_indices(6, s))
//!     .collect();
//! assert_eq!(greedy(&sets, 2).covered, 5);
//! let opt = exact(&sets, 2, 1_000_000);
//! assert_eq!((opt.covered, opt.proven), (6, true));
//! assert_eq!(opt.chosen, vec![1, 2]);
//! ```

/// A fixed-size set of element indices `0..len`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct BitSet {
    len: usize,
    words: Vec<u64>,
}

impl BitSet {
    /// The empty set over `0..len`.
    pub fn new(len: usize) -> Self {
        BitSet {
            len,
            words: vec![0; len.div_ceil(64)],
        }
    }

    /// The set of `indices` (each `< len`; larger ones are ignored).
    pub fn from_indices(len: usize, indices: &[usize]) -> Self {
        let mut s = BitSet::new(len);
        for &i in indices {
            if i < len {
                s.insert(i);
            }
        }
        s
    }

    /// Size of the universe.
    pub fn universe(&self) -> usize {
        self.len
    }

    /// Add element `i` (`i < len`).
    pub fn insert(&mut self, i: usize) {
        self.words[i / 64] |= 1 << (i % 64);
    }

    /// Whether `i` is in the set.
    pub fn contains(&self, i: usize) -> bool {
        i < self.len && self.words[i / 64] & (1 << (i % 64)) != 0
    }

    /// Number of elements.
    pub fn count(&self) -> usize {
        self.words.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// `|self ∪ other| − |self|`: what `other` adds.
    pub fn gain(&self, other: &BitSet) -> usize {
        self.words
            .iter()
            .zip(&other.words)
            .map(|(a, b)| (b & !a).count_ones() as usize)
            .sum()
    }

    /// `self ← self ∪ other`.
    pub fn union_with(&mut self, other: &BitSet) {
        for (a, b) in self.words.iter_mut().zip(&other.words) {
            *a |= b;
        }
    }

    /// The elements, ascending.
    pub fn indices(&self) -> Vec<usize> {
        (0..self.len).filter(|&i| self.contains(i)).collect()
    }
}

/// A choice of sets and what it covers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cover {
    /// Indices of the chosen sets, in the order chosen (greedy) or ascending (exact).
    pub chosen: Vec<usize>,
    /// Size of their union.
    pub covered: usize,
    /// The exact search finished (the value is optimal). Always true for greedy's own claim
    /// "this is what greedy finds"; false only when [`exact`] hit its node limit.
    pub proven: bool,
    /// Search nodes visited (exact and brute force; 0 for greedy).
    pub nodes: u64,
}

/// Greedy maximum coverage with at most `k` sets: each step takes the set with the largest
/// marginal gain (lowest index on ties) and stops early when nothing is gained.
pub fn greedy(sets: &[BitSet], k: usize) -> Cover {
    let n = sets.first().map_or(0, BitSet::universe);
    let mut cov = BitSet::new(n);
    let mut chosen = Vec::new();
    for _ in 0..k {
        let mut best: Option<(usize, usize)> = None;
        for (i, s) in sets.iter().enumerate() {
            if chosen.contains(&i) {
                continue;
            }
            let g = cov.gain(s);
            if g > 0 && best.is_none_or(|(_, bg)| g > bg) {
                best = Some((i, g));
            }
        }
        let Some((i, _)) = best else { break };
        cov.union_with(&sets[i]);
        chosen.push(i);
    }
    Cover {
        covered: cov.count(),
        chosen,
        proven: true,
        nodes: 0,
    }
}

struct Search<'a> {
    sets: &'a [BitSet],
    best: usize,
    best_choice: Vec<usize>,
    nodes: u64,
    limit: u64,
    stopped: bool,
    gains: Vec<usize>,
}

impl Search<'_> {
    fn dfs(&mut self, from: usize, left: usize, cov: &BitSet, chosen: &mut Vec<usize>) {
        self.nodes += 1;
        if self.nodes > self.limit {
            self.stopped = true;
            return;
        }
        let c = cov.count();
        if c > self.best {
            self.best = c;
            self.best_choice = chosen.clone();
        }
        if left == 0 || from >= self.sets.len() {
            return;
        }
        // Upper bound: the `left` largest marginal gains among the sets still allowed.
        self.gains.clear();
        for s in &self.sets[from..] {
            self.gains.push(cov.gain(s));
        }
        let mut g = self.gains.clone();
        g.sort_unstable_by(|a, b| b.cmp(a));
        let bound: usize = c + g.iter().take(left).sum::<usize>();
        if bound <= self.best {
            return;
        }
        // Try the sets with the largest gains first (better incumbents earlier); index order
        // among equal gains keeps the search deterministic.
        let mut order: Vec<usize> = (from..self.sets.len()).collect();
        let gains = self.gains.clone();
        order.sort_by(|&a, &b| gains[b - from].cmp(&gains[a - from]).then(a.cmp(&b)));
        // Sets are combined in index order (i after the previous pick) so each subset is
        // visited once; the order above only decides which branch is explored first.
        for i in order {
            if gains[i - from] == 0 || self.stopped {
                continue;
            }
            let mut next = cov.clone();
            next.union_with(&self.sets[i]);
            chosen.push(i);
            // Only sets after i may follow: subsets are enumerated as increasing sequences.
            self.dfs(i + 1, left - 1, &next, chosen);
            chosen.pop();
        }
    }
}

/// The maximum coverage with at most `k` sets by branch and bound (see the module docs),
/// visiting at most `node_limit` search nodes. Ties keep the first optimum found, which starts
/// from greedy's choice.
pub fn exact(sets: &[BitSet], k: usize, node_limit: u64) -> Cover {
    let g = greedy(sets, k);
    let n = sets.first().map_or(0, BitSet::universe);
    let mut s = Search {
        sets,
        best: g.covered,
        best_choice: g.chosen.clone(),
        nodes: 0,
        limit: node_limit,
        stopped: false,
        gains: Vec::with_capacity(sets.len()),
    };
    let mut chosen = Vec::with_capacity(k);
    s.dfs(0, k, &BitSet::new(n), &mut chosen);
    let mut chosen = s.best_choice;
    chosen.sort_unstable();
    Cover {
        chosen,
        covered: s.best,
        proven: !s.stopped,
        nodes: s.nodes,
    }
}

/// The maximum coverage with at most `k` sets by enumerating every subset of size ≤ k (the
/// first optimum in lexicographic order). Exponential: for tests and tiny instances.
pub fn brute_force(sets: &[BitSet], k: usize) -> Cover {
    let n = sets.first().map_or(0, BitSet::universe);
    let mut best = Cover {
        chosen: vec![],
        covered: 0,
        proven: true,
        nodes: 0,
    };
    fn rec(
        sets: &[BitSet],
        from: usize,
        left: usize,
        cov: &BitSet,
        chosen: &mut Vec<usize>,
        best: &mut Cover,
    ) {
        best.nodes += 1;
        let c = cov.count();
        if c > best.covered {
            best.covered = c;
            best.chosen = chosen.clone();
        }
        if left == 0 {
            return;
        }
        for i in from..sets.len() {
            let mut next = cov.clone();
            next.union_with(&sets[i]);
            chosen.push(i);
            rec(sets, i + 1, left - 1, &next, chosen, best);
            chosen.pop();
        }
    }
    rec(sets, 0, k, &BitSet::new(n), &mut Vec::new(), &mut best);
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bitset_basics() {
        let a = BitSet::from_indices(130, &[0, 64, 129]);
        let b = BitSet::from_indices(130, &[64, 65]);
        assert_eq!(a.count(), 3);
        assert_eq!(a.gain(&b), 1);
        let mut c = a.clone();
        c.union_with(&b);
        assert_eq!(c.indices(), vec![0, 64, 65, 129]);
        assert!(!c.contains(130));
    }

    #[test]
    fn empty_and_zero_budget() {
        let sets: Vec<BitSet> = vec![];
        assert_eq!(greedy(&sets, 3).covered, 0);
        assert_eq!(exact(&sets, 3, 100).covered, 0);
        let sets = vec![BitSet::from_indices(4, &[1, 2])];
        assert_eq!(exact(&sets, 0, 100).covered, 0);
    }

    #[test]
    fn node_limit_is_reported() {
        // Greedy covers 7 of 8 here, so the root cannot be pruned and the search must branch.
        let sets: Vec<BitSet> = [vec![1, 2, 3, 4, 5, 6], vec![0, 1, 2, 3], vec![4, 5, 6, 7]]
            .iter()
            .map(|s| BitSet::from_indices(8, s))
            .collect();
        let c = exact(&sets, 2, 1);
        assert!(!c.proven);
        assert!(c.covered >= greedy(&sets, 2).covered);
        assert!(exact(&sets, 2, 100).proven);
    }
}

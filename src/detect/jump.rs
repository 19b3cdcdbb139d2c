//! The snap: where e jumps on loading, where it comes back on unloading, or why no snap is
//! claimed.
//!
//! # The scan (causal, shared by the batch and the streaming detector)
//! [`Scanner`] is fed the samples in time order; only samples with a usable marker take part.
//! With the usable samples numbered u = 0, 1, …:
//!
//! - **Jump** at u = i (while loading: s_i within [`LOADING_SLACK`] of the largest s so far):
//!   the level before, `pre` = median of e over the [`JumpOptions::window`] samples ending at i,
//!   the level after, `post` = median over the next [`JumpOptions::lookahead`] samples, and the
//!   level of the window before that, `pre₀`, satisfy `post ≥ ratio·pre`, `post − pre ≥
//!   min_jump` and `post − pre ≥ trend_factor·max(|pre − pre₀|, slope·(s̄_post − s̄_pre),
//!   TREND_FLOOR)` with `slope = |pre − pre₀| / (s̄_pre − s̄_pre₀)` (s̄ the windows' median s):
//!   a step, not the continuation of the ramp before it, whether the ramp is measured per sample
//!   or per unit s (a gradual departure driven fast covers much s in few samples). The median
//!   over the lookahead
//!   ignores up to half of it as spikes. `post` is then raised to the median of the next
//!   lookahead when larger (the settled level), and the threshold is `h = (pre + post)/2`; the jump is at the
//!   first sample j after i − window with e_j > h and the next [`CONFIRM`] samples > h too;
//!   **s_snap is the s of the usable sample before j** (the last state on the helix).
//! - **Return** (after a snap, while unloading: s below the largest s by more than
//!   [`LOADING_SLACK`]): the first sample j with e ≤ h whose next [`CONFIRM`] samples are ≤ h
//!   and the median of the [`JumpOptions::lookahead`] samples from j is ≤ h; s_return = s_j.
//!
//! Latency: a snap is reported when sample i + 2·lookahead + CONFIRM has been seen, i.e. at
//! most [`JumpOptions::latency`] usable samples after the last helical sample (plus the
//! [`super::observations::OUTLIER_HALF_WINDOW`] raw samples the spike test looks ahead).
//!
//! # No snap, and doubts
//! - two usable samples around the jump more than [`super::observations::LOST_GAP`] raw samples
//!   apart: the jump happened while the marker was lost — **tracking_lost**, no s claimed;
//! - no jump, and e at the end of loading ≥ [`GRADUAL_RATIO`] × e at the end of the extrinsics
//!   fit: **gradual** departure;
//! - no jump and the sample-to-sample scatter of e (robust σ of differences) exceeds
//!   `min_jump / 4`: **noise** (a jump could hide in it);
//! - no jump and the run turned back before 0.97 s* (continuum): **stopped_early**;
//! - otherwise **no_departure**.
//!
//! A snap is reported with **high** confidence when `post ≥ 2·pre` and `post − pre ≥ 2·min_jump`, no sample of the jump's
//! window is off the pose curve (a disturbed path) and the track has no gap there; else **low**,
//! with the doubt in the notes.

use super::observations::{SampleFlag, LOST_GAP};
use crate::math::Real;

/// Samples after the threshold crossing that must stay on the same side.
pub const CONFIRM: usize = 2;
/// A sample is loading while its s is within this of the largest s so far.
pub const LOADING_SLACK: Real = 0.02;
/// e at the end of loading over e at the end of the fit above this: a gradual departure.
pub const GRADUAL_RATIO: Real = 2.0;
/// post/pre at or above this, and post − pre ≥ 2 × min_jump: high confidence.
pub const HIGH_RATIO: Real = 2.0;

/// Settings of the jump test.
#[derive(Debug, Clone, PartialEq)]
pub struct JumpOptions {
    /// Usable samples in the level before a candidate.
    pub window: usize,
    /// Usable samples in the level after it.
    pub lookahead: usize,
    /// Smallest post/pre.
    pub ratio: Real,
    /// Smallest post − pre (e units).
    pub min_jump: Real,
    /// post − pre must exceed this many times the change of the level over the window before
    /// (`|pre − pre_before|`, at least [`TREND_FLOOR`]): a jump, not a steep ramp.
    pub trend_factor: Real,
}

/// Smallest trend of the level used in the jump test (e units per window).
pub const TREND_FLOOR: Real = 0.02;
/// Smallest s between two windows used for the ramp's slope.
pub const TREND_DS_FLOOR: Real = 0.01;

impl Default for JumpOptions {
    fn default() -> Self {
        JumpOptions {
            window: 15,
            lookahead: 8,
            ratio: 1.25,
            min_jump: 0.5,
            trend_factor: 3.0,
        }
    }
}

impl JumpOptions {
    /// The latency of a snap report in usable samples after the last helical sample.
    pub fn latency(&self) -> usize {
        2 * self.lookahead + CONFIRM + 1
    }
}

/// Why a snap was or was not claimed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Reason {
    /// e jumped.
    Snap,
    /// e grew without a jump.
    Gradual,
    /// The scatter of e could hide a jump.
    Noise,
    /// The marker was lost where e changed level.
    TrackingLost,
    /// The run turned back before the predicted boundary.
    StoppedEarly,
    /// e stayed at its early level.
    NoDeparture,
}

impl Reason {
    /// The CSV spelling.
    pub fn as_str(&self) -> &'static str {
        match self {
            Reason::Snap => "snap",
            Reason::Gradual => "gradual",
            Reason::Noise => "noise",
            Reason::TrackingLost => "tracking_lost",
            Reason::StoppedEarly => "stopped_early",
            Reason::NoDeparture => "no_departure",
        }
    }
}

/// How far a snap value can be trusted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Confidence {
    /// A clear jump on a clean track.
    High,
    /// A jump with a doubt (see the notes).
    Low,
    /// No snap claimed.
    None,
}

impl Confidence {
    /// The CSV spelling.
    pub fn as_str(&self) -> &'static str {
        match self {
            Confidence::High => "high",
            Confidence::Low => "low",
            Confidence::None => "none",
        }
    }
}

/// The verdict on one run.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// s of the last helical state before the jump.
    pub s_snap: Option<Real>,
    /// s where e came back on unloading.
    pub s_return: Option<Real>,
    /// Sample index of the snap (last helical sample) and of the return.
    pub index_snap: Option<usize>,
    /// See `index_snap`.
    pub index_return: Option<usize>,
    /// Levels of e before and after the jump.
    pub levels: Option<(Real, Real)>,
    /// Why.
    pub reason: Reason,
    /// How sure.
    pub confidence: Confidence,
    /// Doubts and flags.
    pub notes: Vec<String>,
}

/// A found jump (before classification).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jump {
    /// Sample index of the last helical sample.
    pub before: usize,
    /// Sample index of the first departed sample.
    pub after: usize,
    /// Levels before and after.
    pub pre: Real,
    /// See `pre`.
    pub post: Real,
    /// Sample index at which the jump was decided.
    pub decided_at: usize,
}

/// The causal scan (module docs). Feed samples with [`Scanner::push`].
#[derive(Debug, Clone)]
pub struct Scanner {
    o: JumpOptions,
    /// Usable samples: (sample index, s, e).
    u: Vec<(usize, Real, Real)>,
    /// Largest s so far, at each usable sample.
    peak: Vec<Real>,
    s_peak: Real,
    next_candidate: usize,
    /// The jump, once found.
    pub jump: Option<Jump>,
    /// The return (sample index, decided at), once found.
    pub ret: Option<(usize, usize)>,
    next_return: usize,
    buf: Vec<Real>,
}

fn median_of(buf: &mut Vec<Real>, it: impl Iterator<Item = Real>) -> Real {
    buf.clear();
    buf.extend(it);
    buf.sort_by(Real::total_cmp);
    buf[buf.len() / 2]
}

impl Scanner {
    /// A scanner with the settings `o`.
    pub fn new(o: JumpOptions) -> Self {
        Scanner {
            o,
            u: Vec::new(),
            peak: Vec::new(),
            s_peak: Real::NEG_INFINITY,
            next_candidate: 0,
            jump: None,
            ret: None,
            next_return: 0,
            buf: Vec::new(),
        }
    }

    /// Feed sample `index` with distance `s` and error `e` (NaN when unusable; its s still counts
    /// for the phase when finite). Returns true when this sample completed a decision (a jump or
    /// a return).
    pub fn push(&mut self, index: usize, s: Real, e: Real) -> bool {
        if s.is_finite() && s > self.s_peak {
            self.s_peak = s;
        }
        if !(e.is_finite() && s.is_finite()) {
            return false;
        }
        self.u.push((index, s, e));
        self.peak.push(self.s_peak);
        let before = (self.jump.is_some(), self.ret.is_some());
        self.advance();
        (self.jump.is_some(), self.ret.is_some()) != before
    }

    fn advance(&mut self) {
        let (w, k) = (self.o.window, self.o.lookahead);
        let n = self.u.len();
        while self.jump.is_none() && self.next_candidate + 2 * k + CONFIRM < n {
            let i = self.next_candidate;
            self.next_candidate += 1;
            if i + 1 < 2 * w || self.u[i].1 < self.peak[i] - LOADING_SLACK {
                continue;
            }
            let pre = median_of(&mut self.buf, self.u[i + 1 - w..=i].iter().map(|x| x.2));
            let post = median_of(&mut self.buf, self.u[i + 1..=i + k].iter().map(|x| x.2));
            if !(post >= self.o.ratio * pre && post - pre >= self.o.min_jump) {
                continue;
            }
            let before = median_of(
                &mut self.buf,
                self.u[i + 1 - 2 * w..=i - w].iter().map(|x| x.2),
            );
            // The ramp's slope in s, carried over the s between the two levels.
            let s_mid = |buf: &mut Vec<Real>, a: usize, b: usize| {
                median_of(buf, self.u[a..=b].iter().map(|x| x.1))
            };
            let s_before = s_mid(&mut self.buf, i + 1 - 2 * w, i - w);
            let s_pre = s_mid(&mut self.buf, i + 1 - w, i);
            let s_post = s_mid(&mut self.buf, i + 1, i + k);
            let slope = (pre - before).abs() / (s_pre - s_before).max(TREND_DS_FLOOR);
            let expected = (pre - before)
                .abs()
                .max(slope * (s_post - s_pre).max(0.0))
                .max(TREND_FLOOR);
            if post - pre < self.o.trend_factor * expected {
                continue;
            }
            // The settled level: the jump may still be under way in the first lookahead.
            let settled = median_of(
                &mut self.buf,
                self.u[i + k + 1..=i + 2 * k].iter().map(|x| x.2),
            );
            let post = post.max(settled);
            let h = 0.5 * (pre + post);
            let lo = (i + 2).saturating_sub(w).max(1);
            let Some(j) = (lo..=i + k).find(|&j| (j..=j + CONFIRM).all(|m| self.u[m].2 > h)) else {
                continue;
            };
            self.jump = Some(Jump {
                before: self.u[j - 1].0,
                after: self.u[j].0,
                pre,
                post,
                decided_at: self.u[n - 1].0,
            });
            self.next_return = j;
        }
        if let Some(jp) = self.jump {
            let h = 0.5 * (jp.pre + jp.post);
            while self.ret.is_none() && self.next_return + k.max(CONFIRM + 1) <= n {
                let j = self.next_return;
                self.next_return += 1;
                if self.u[j].1 >= self.peak[j] - LOADING_SLACK {
                    continue;
                }
                if (j..=j + CONFIRM).all(|m| self.u[m].2 <= h)
                    && median_of(&mut self.buf, self.u[j..j + k].iter().map(|x| x.2)) <= h
                {
                    self.ret = Some((self.u[j].0, self.u[n - 1].0));
                }
            }
        }
    }
}

/// Robust σ (1.4826 × median absolute deviation) of successive differences of `v`.
fn scatter(v: &[Real]) -> Real {
    if v.len() < 3 {
        return 0.0;
    }
    let mut d: Vec<Real> = v.windows(2).map(|w| w[1] - w[0]).collect();
    d.sort_by(Real::total_cmp);
    let m = d[d.len() / 2];
    let mut a: Vec<Real> = d.iter().map(|x| (x - m).abs()).collect();
    a.sort_by(Real::total_cmp);
    1.4826 * a[a.len() / 2] / std::f64::consts::SQRT_2
}

/// Classify a run: `s`, `e` per sample (NaN where unusable), the flags, the reversal index,
/// the continuum s*, the index of the last sample of the extrinsics fit.
pub fn detect(
    s: &[Real],
    e: &[Real],
    flags: &[SampleFlag],
    rev: usize,
    s_predicted: Real,
    fit_end: usize,
    o: &JumpOptions,
) -> Outcome {
    let mut sc = Scanner::new(o.clone());
    for i in 0..s.len() {
        sc.push(i, s[i], e[i]);
    }
    classify(&sc, s, e, flags, rev, s_predicted, fit_end)
}

/// The outcome of a scan (module docs).
pub fn classify(
    sc: &Scanner,
    s: &[Real],
    e: &[Real],
    flags: &[SampleFlag],
    rev: usize,
    s_predicted: Real,
    fit_end: usize,
) -> Outcome {
    let mut notes = Vec::new();
    let mut out = Outcome {
        s_snap: None,
        s_return: None,
        index_snap: None,
        index_return: None,
        levels: None,
        reason: Reason::NoDeparture,
        confidence: Confidence::None,
        notes: Vec::new(),
    };
    let usable_loading: Vec<Real> = (0..=rev.min(s.len() - 1))
        .filter(|&i| e[i].is_finite())
        .map(|i| e[i])
        .collect();
    if let Some(j) = sc.jump {
        out.levels = Some((j.pre, j.post));
        if j.after - j.before > LOST_GAP {
            out.reason = Reason::TrackingLost;
            notes.push(format!(
                "e changed from {:.3} to {:.3} while the marker was lost between s = {:.4} and {:.4}",
                j.pre, j.post, s[j.before], s[j.after]
            ));
            out.notes = notes;
            return out;
        }
        out.s_snap = Some(s[j.before]);
        out.index_snap = Some(j.before);
        out.reason = Reason::Snap;
        let lo = j.before.saturating_sub(2 * LOST_GAP);
        let hi = (j.after + 2 * LOST_GAP).min(s.len());
        let off = (lo..hi)
            .filter(|&i| flags[i] == SampleFlag::OffPath)
            .count();
        let gap = (lo..hi)
            .filter(|&i| flags[i] == SampleFlag::Dropped)
            .count();
        let mut high = j.post >= HIGH_RATIO * j.pre && j.post - j.pre >= 2.0 * sc.o.min_jump;
        if !high {
            notes.push(format!("small jump: e from {:.3} to {:.3}", j.pre, j.post));
        }
        if off > 0 {
            high = false;
            notes.push(format!(
                "path disturbed near the jump: {off} samples off the pose curve"
            ));
        }
        if gap > LOST_GAP / 2 {
            high = false;
            notes.push(format!("{gap} dropped markers near the jump"));
        }
        out.confidence = if high {
            Confidence::High
        } else {
            Confidence::Low
        };
        match sc.ret {
            Some((r, _)) => {
                out.s_return = Some(s[r]);
                out.index_return = Some(r);
            }
            None => notes.push(if rev + 1 >= s.len() {
                "no unloading recorded: no return".into()
            } else {
                "e did not come back on unloading".into()
            }),
        }
        out.notes = notes;
        return out;
    }
    // No jump: why.
    let (g0, glen) = super::observations::longest_gap(flags, 0..(rev + 1).min(s.len()));
    let end_level = {
        let tail: Vec<Real> = usable_loading
            .iter()
            .rev()
            .take(sc.o.window)
            .copied()
            .collect();
        median_plain(tail)
    };
    let fit_level = {
        let tail: Vec<Real> = (0..=fit_end.min(s.len() - 1))
            .rev()
            .filter(|&i| e[i].is_finite())
            .take(sc.o.window)
            .map(|i| e[i])
            .collect();
        median_plain(tail)
    };
    let sigma = scatter(&usable_loading);
    if glen > LOST_GAP && g0 + glen + LOST_GAP >= rev {
        out.reason = Reason::TrackingLost;
        notes.push(format!(
            "marker lost for {glen} samples from s = {:.4} to the end of loading",
            s[g0]
        ));
    } else if end_level >= GRADUAL_RATIO * fit_level {
        out.reason = Reason::Gradual;
        notes.push(format!(
            "e grew from {fit_level:.3} (end of the fit) to {end_level:.3} (end of loading) without a jump"
        ));
    } else if sigma > 0.25 * sc.o.min_jump {
        out.reason = Reason::Noise;
        notes.push(format!("scatter of e {sigma:.3}"));
    } else if s_predicted.is_finite() && s[rev] < 0.97 * s_predicted {
        out.reason = Reason::StoppedEarly;
        notes.push(format!(
            "the run turned back at s = {:.4}, before the predicted s* = {s_predicted:.4}",
            s[rev]
        ));
    }
    out.notes = notes;
    out
}

fn median_plain(mut v: Vec<Real>) -> Real {
    if v.is_empty() {
        return Real::NAN;
    }
    v.sort_by(Real::total_cmp);
    v[v.len() / 2]
}

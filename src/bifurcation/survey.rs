//! The bifurcation type over a set of directions (the demo's map, examples), and the seed's
//! labelled directions.
//!
//! [`survey`] runs [`classify`] on every direction, in parallel over
//! directions (rayon, the outermost level), results in input order (identical for any
//! thread count). For a resumable, checkpointed sweep use `helixreach bifurcation` (the sweep
//! driver); this is the in-memory form for figures and reports.
//!
//! [`seed_labels`] are the 42 directions the seed's own DER runs labelled (101 vertices, ray
//! speed 0.1, load then unload; `subcritical` where the error jumped and the rod returned to
//! the helix only at a smaller s): a copy of `bifurcation_examples.csv` of the seed's data
//! (github.com/StructuresComp/Helix_Bifurcation_Types, commit 2de678b, `DataProcessing/`),
//! embedded as `src/bifurcation/seed_labels.csv` so that figures mark them without the data
//! folder.

use super::{classify, Bifurcation, BifurcationParams, BifurcationType};
use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::Real;
use crate::par::Par;

/// The seed's labelled directions (see the module docs), as CSV.
pub const SEED_LABELS_CSV: &str = include_str!("seed_labels.csv");

/// One labelled direction of the seed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeedLabel {
    /// The direction (normalized).
    pub dir: Direction,
    /// The seed's label.
    pub kind: BifurcationType,
    /// Where the seed's dynamic run jumped (s; `None` for a supercritical ray: no jump).
    pub s_jump: Option<Real>,
    /// Where it returned to the helix on unloading (s; `None` for a supercritical ray).
    pub s_return: Option<Real>,
}

/// The 42 labelled directions of [`SEED_LABELS_CSV`], in file order.
///
/// ```
/// let l = helixreach::bifurcation::survey::seed_labels().unwrap();
/// assert_eq!(l.len(), 42);
/// use helixreach::bifurcation::BifurcationType::Subcritical;
/// assert!(l.iter().filter(|x| x.kind == Subcritical).all(|x| x.s_return < x.s_jump));
/// assert_eq!(l.iter().filter(|x| x.kind != Subcritical).count(), 4);
/// ```
pub fn seed_labels() -> Result<Vec<SeedLabel>> {
    let mut out = Vec::new();
    for (k, line) in SEED_LABELS_CSV.lines().enumerate().skip(1) {
        let bad = |why: String| {
            Error::invalid(
                format!("seed_labels.csv line {}", k + 1),
                line.to_string(),
                why,
            )
        };
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != 6 {
            return Err(bad(format!("{} fields, want 6", f.len())));
        }
        let x = |i: usize| -> Result<Real> {
            f[i].parse::<Real>()
                .map_err(|e| bad(format!("field {}: {e}", i + 1)))
        };
        let opt = |i: usize| -> Result<Option<Real>> {
            if f[i].is_empty() {
                Ok(None)
            } else {
                x(i).map(Some)
            }
        };
        out.push(SeedLabel {
            dir: Direction::new(x(0)?, x(1)?, x(2)?)?,
            kind: BifurcationType::parse(f[3])?,
            s_jump: opt(4)?,
            s_return: opt(5)?,
        });
    }
    Ok(out)
}

/// [`classify`] every direction of `dirs` (in parallel on `par`, results in input order).
/// Fails only on invalid parameters or directions: an undecided ray is a `degenerate` result
/// with its reason.
pub fn survey(par: Par, dirs: &[Direction], p: &BifurcationParams) -> Result<Vec<Bifurcation>> {
    p.validate()?;
    par.map(dirs, |d| classify(d, p))?.into_iter().collect()
}

//! Which link pairs the self-collision check skips: links of one rigid group (joined by fixed
//! or frozen joints), links joined by a joint (adjacent), and the pairs of a [`DisabledPairs`]
//! list — the pairs found never (or always) in collision over many random configurations,
//! computed once by [`DisabledPairs::compute`] and stored beside the URDF as
//! `<robot>.collision.toml` (like an SRDF's disabled collisions).

use super::narrow::{intersects, Body, Owner, Part};
use super::CollisionModel;
use crate::error::{Error, Result};
use crate::robot::model::{LinkInfo, RobotModel};
use serde::{Deserialize, Serialize};
use std::collections::HashSet;

/// Link pairs excluded from self-collision checks (besides same-group and adjacent links).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DisabledPairs {
    /// Random configurations sampled to compute the list.
    #[serde(default)]
    pub samples: usize,
    /// Seed of the sampling.
    #[serde(default)]
    pub seed: u64,
    /// The pairs.
    #[serde(default)]
    pub disabled: Vec<DisabledPair>,
}

/// One excluded link pair.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DisabledPair {
    /// First link.
    pub a: String,
    /// Second link.
    pub b: String,
    /// `never` (never in collision in the samples) or `always`.
    pub reason: String,
}

/// The body pairs (indices into `bodies`, all [`Owner::Link`]) the self-collision check tests:
/// every pair of bodies on different links that are not in one rigid group, not joined by a
/// joint and not in `disabled`.
pub(super) fn self_pairs(
    model: &RobotModel,
    bodies: &[Body],
    disabled: &DisabledPairs,
) -> Result<Vec<(u16, u16)>> {
    let links = model.links();
    let mut off = HashSet::new();
    for p in &disabled.disabled {
        match (model.link_index(&p.a), model.link_index(&p.b)) {
            (Some(a), Some(b)) => {
                off.insert((a.min(b), a.max(b)));
            }
            _ => {
                return Err(Error::invalid(
                    "disabled collision pair",
                    format!("{} / {}", p.a, p.b),
                    format!("no such link in {}", model.source()),
                ))
            }
        }
    }
    let link = |b: &Body| match b.owner {
        Owner::Link(l) => l,
        Owner::Obstacle(_) => unreachable!("self pairs are built from link bodies only"),
    };
    let mut pairs = Vec::new();
    for (i, bi) in bodies.iter().enumerate() {
        for (j, bj) in bodies.iter().enumerate().skip(i + 1) {
            let (a, b) = (link(bi), link(bj));
            if candidate(links, a, b) && !off.contains(&(a.min(b), a.max(b))) {
                pairs.push((i as u16, j as u16));
            }
        }
    }
    Ok(pairs)
}

/// Whether links `a` and `b` may collide at all: different rigid groups, not joined by a joint.
fn candidate(links: &[LinkInfo], a: usize, b: usize) -> bool {
    if a == b || links[a].group == links[b].group {
        return false;
    }
    !(links[a].parent == Some(b) || links[b].parent == Some(a))
}

/// Where the never-colliding pair list of the URDF file `urdf` lives:
/// `<urdf stem>.collision.toml` beside it.
pub fn collision_toml_path(urdf: &str) -> std::path::PathBuf {
    std::path::Path::new(urdf).with_extension("collision.toml")
}

impl DisabledPairs {
    /// Parse a `<robot>.collision.toml`; `source` names it in errors.
    pub fn from_toml(text: &str, source: &str) -> Result<DisabledPairs> {
        toml::from_str(text).map_err(|e| Error::File {
            path: source.into(),
            reason: format!("malformed disabled-pairs file: {e}"),
        })
    }

    /// The `<disable_collisions link1=… link2=… reason=…/>` elements of a MoveIt SRDF; `source`
    /// names it in errors (a malformed file, an element without both links). Unknown link names
    /// are reported when the list is applied to a model.
    ///
    /// ```
    /// use helixreach::robot::DisabledPairs;
    /// let d = DisabledPairs::from_srdf(
    ///     r#"<robot name="r"><disable_collisions link1="a" link2="b" reason="Adjacent"/></robot>"#,
    ///     "r.srdf",
    /// ).unwrap();
    /// assert_eq!((d.disabled[0].a.as_str(), d.disabled[0].b.as_str()), ("a", "b"));
    /// assert!(DisabledPairs::from_srdf("<robot>", "bad.srdf").unwrap_err().to_string().contains("bad.srdf"));
    /// ```
    pub fn from_srdf(text: &str, source: &str) -> Result<DisabledPairs> {
        let doc = roxmltree::Document::parse(text).map_err(|e| Error::File {
            path: source.into(),
            reason: format!("malformed SRDF: {e}"),
        })?;
        let mut disabled = Vec::new();
        for n in doc
            .descendants()
            .filter(|n| n.has_tag_name("disable_collisions"))
        {
            let pos = doc.text_pos_at(n.range().start);
            let (Some(a), Some(b)) = (n.attribute("link1"), n.attribute("link2")) else {
                return Err(Error::BadLine {
                    path: source.into(),
                    line: pos.row as usize,
                    field: "disable_collisions".into(),
                    reason: "needs both link1 and link2".into(),
                });
            };
            disabled.push(DisabledPair {
                a: a.to_string(),
                b: b.to_string(),
                reason: n.attribute("reason").unwrap_or("srdf").to_string(),
            });
        }
        Ok(DisabledPairs {
            samples: 0,
            seed: 0,
            disabled,
        })
    }

    /// Read a MoveIt SRDF file ([`DisabledPairs::from_srdf`]).
    pub fn from_srdf_file(path: &std::path::Path) -> Result<DisabledPairs> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_srdf(&text, &path.display().to_string())
    }

    /// This list and `other`'s pairs (duplicates kept once).
    pub fn merged(mut self, other: &DisabledPairs) -> DisabledPairs {
        for p in &other.disabled {
            let dup = self
                .disabled
                .iter()
                .any(|q| (q.a == p.a && q.b == p.b) || (q.a == p.b && q.b == p.a));
            if !dup {
                self.disabled.push(p.clone());
            }
        }
        self
    }

    /// The list for a model: the built-in one, or `<urdf stem>.collision.toml` beside the URDF
    /// file if it exists, else empty.
    pub fn for_model(model: &RobotModel) -> Result<DisabledPairs> {
        if let Some(name) = model.source().strip_prefix("builtin:") {
            if let Some(b) = crate::robot::urdf::builtin(name) {
                return Self::from_toml(b.collision, &format!("builtin:{name}.collision.toml"));
            }
        }
        let p = collision_toml_path(model.source());
        if p.exists() {
            let text = std::fs::read_to_string(&p).map_err(|source| Error::Io {
                path: p.clone(),
                source,
            })?;
            return Self::from_toml(&text, &p.display().to_string());
        }
        Ok(DisabledPairs::default())
    }

    /// Sample `samples` random in-limit configurations (ChaCha8 stream from `seed`) and list
    /// the candidate link pairs (not same group, not adjacent) that never — or always — collide.
    ///
    /// `samples` must lie in [`MIN_DISABLED_SAMPLES`](crate::limits::MIN_DISABLED_SAMPLES) ..=
    /// [`MAX_DISABLED_SAMPLES`](crate::limits::MAX_DISABLED_SAMPLES): fewer would list pairs
    /// that do collide as never colliding (0 samples: every pair), more would run for hours.
    pub fn compute(model: &RobotModel, samples: usize, seed: u64) -> Result<DisabledPairs> {
        use rand::SeedableRng;
        crate::limits::check_range(
            "samples",
            samples,
            crate::limits::MIN_DISABLED_SAMPLES,
            crate::limits::MAX_DISABLED_SAMPLES,
        )?;
        let cm = CollisionModel::new(model, &DisabledPairs::default(), &[])?;
        let mut ws = cm.workspace();
        let pairs = cm.self_pair_links();
        let mut link_pairs: Vec<(usize, usize)> =
            pairs.iter().map(|&(a, b)| (a.min(b), a.max(b))).collect();
        link_pairs.sort_unstable();
        link_pairs.dedup();
        let mut count = vec![0usize; link_pairs.len()];
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let n = model.dof();
        let mut hit = vec![false; link_pairs.len()];
        for _ in 0..samples {
            let q = model.random_config(&mut rng);
            cm.update(&q[..n], &mut ws);
            hit.iter_mut().for_each(|h| *h = false);
            for &(i, j) in &cm.self_pairs {
                let (i, j) = (i as usize, j as usize);
                let (la, lb) = cm.body_links(i, j);
                let k = link_pairs
                    .binary_search(&(la.min(lb), la.max(lb)))
                    .expect("pair listed");
                if !hit[k]
                    && intersects(
                        &Part::Body(&cm.bodies[i], &ws.posed[i]),
                        &Part::Body(&cm.bodies[j], &ws.posed[j]),
                    )
                {
                    hit[k] = true;
                }
            }
            for (c, h) in count.iter_mut().zip(&hit) {
                *c += usize::from(*h);
            }
        }
        let names = model.links();
        let disabled = link_pairs
            .iter()
            .zip(&count)
            .filter(|(_, &c)| c == 0 || c == samples)
            .map(|(&(a, b), &c)| DisabledPair {
                a: names[a].name.clone(),
                b: names[b].name.clone(),
                reason: if c == 0 { "never" } else { "always" }.into(),
            })
            .collect();
        Ok(DisabledPairs {
            samples,
            seed,
            disabled,
        })
    }

    /// The TOML text, with a header naming the robot and the command that regenerates it
    /// (`regenerate`: the full `helixreach robot …` line, with the load options it was made
    /// with: tool link, package paths, links without collision geometry, samples and seed).
    pub fn to_toml(&self, robot: &str, regenerate: &str) -> Result<String> {
        let mut s = format!(
            "# Link pairs of {robot} never checked for self-collision (like an SRDF's disabled\n\
             # collisions), besides links joined by a joint or rigidly attached to each other.\n\
             # \"never\": not in collision in any of the random in-limit samples; \"always\": in all.\n\
             # Regenerate: {regenerate}\n"
        );
        let body = toml::to_string(self).map_err(|e| {
            Error::invalid("disabled pairs", self.disabled.len(), format!("TOML: {e}"))
        })?;
        s.push_str(&body);
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::limits::{MAX_DISABLED_SAMPLES, MIN_DISABLED_SAMPLES};

    /// Too few samples (0 would disable every pair) or too many is an error naming the field,
    /// the value and the range, before any sampling.
    #[test]
    fn compute_refuses_sample_counts_outside_the_limits() {
        let model = RobotModel::load("sawyer", None).unwrap();
        for n in [0, MIN_DISABLED_SAMPLES - 1, MAX_DISABLED_SAMPLES + 1] {
            let e = DisabledPairs::compute(&model, n, 1)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("samples")
                    && e.contains(&format!("= {n}"))
                    && e.contains(&MIN_DISABLED_SAMPLES.to_string())
                    && e.contains(&MAX_DISABLED_SAMPLES.to_string()),
                "{e}"
            );
        }
    }
}

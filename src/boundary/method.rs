//! Which stability test gives s* ([`Method`]): the one choice of `helixreach boundary`,
//! `helixreach compare` and the study's boundary rows (their `method` column).

/// A stability test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Kirchhoff-rod conjugate-point test (exact reference).
    Continuum,
    /// Discrete Elastic Rods statics with `--n-edges` edges.
    Der,
}

impl Method {
    /// The name in a boundary CSV's `method` column: `continuum` or `der`.
    ///
    /// ```
    /// use helixreach::boundary::Method;
    /// assert_eq!((Method::Continuum.as_str(), Method::Der.as_str()), ("continuum", "der"));
    /// ```
    pub fn as_str(self) -> &'static str {
        match self {
            Method::Continuum => "continuum",
            Method::Der => "der",
        }
    }
}

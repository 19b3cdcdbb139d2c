//! The library's typed errors. One enum, `#[non_exhaustive]`, whose variants carry the context a
//! user needs to fix the input: the file, the field (or line) and the offending value.
//! The binary wraps these in `anyhow` for display; the library never panics on bad input.

use std::path::PathBuf;

/// Every error the library reports.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is outside its domain (NaN, ∞, negative where it must not be, …).
    #[error("invalid {field} = {value}: {reason}")]
    InvalidParameter {
        /// Name of the parameter or field.
        field: String,
        /// The offending value, as text.
        value: String,
        /// What was expected.
        reason: String,
    },
    /// A line of an input file is malformed.
    #[error("{}:{line}: {field}: {reason}", path.display())]
    BadLine {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// The column or field.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// A file could not be read, parsed or written.
    #[error("{}: {reason}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
    /// An iterative method did not converge.
    #[error("{what} did not converge after {iterations} iterations (residual {residual:e})")]
    NotConverged {
        /// What was being solved.
        what: String,
        /// Iterations used.
        iterations: usize,
        /// Last residual.
        residual: f64,
    },
    /// One item of a sweep failed (its key, e.g. the direction, and the cause).
    #[error("item {key}: {cause}")]
    Item {
        /// The item's key fields, comma-separated.
        key: String,
        /// The underlying error (displayed inline, so it is not also a `source`).
        cause: Box<Error>,
    },
    /// An I/O error with the path it concerns.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}

/// The crate's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// Shorthand for [`Error::InvalidParameter`].
    pub fn invalid(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        reason: impl Into<String>,
    ) -> Self {
        Error::InvalidParameter {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

/// Check that `value` is finite; otherwise an [`Error::InvalidParameter`] naming `field`.
pub fn require_finite(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::invalid(field, value, "must be finite"))
    }
}

/// Check that `value` is finite and > 0.
pub fn require_positive(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::invalid(field, value, "must be finite and > 0"))
    }
}

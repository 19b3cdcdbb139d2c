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
    /// A converged result failed its check against an independent method (e.g. a DER-statics
    /// s* farther from the continuum s* than its error estimate): no number is returned.
    #[error("{what}")]
    Inconsistent {
        /// What was computed, both values and the estimate they violate.
        what: String,
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
            value: compact_number_text(value.to_string()),
            reason: reason.into(),
        }
    }
}

/// Format a number for messages: shortest round-trip text, switching to scientific notation
/// when the magnitude is ≥ 1e15 or < 1e-4 (so 1e300 prints as `1e300`, not 301 digits, and
/// 1e-300 not as 300 zeros). The one number formatter of error messages.
///
/// ```
/// use helixreach::error::fmt_num;
/// assert_eq!(fmt_num(1e300), "1e300");
/// assert_eq!(fmt_num(-2.5e-7), "-2.5e-7");
/// assert_eq!(fmt_num(0.25), "0.25");
/// assert_eq!(fmt_num(-0.0), "-0");
/// assert_eq!(fmt_num(f64::NAN), "NaN");
/// assert_eq!(fmt_num(f64::INFINITY), "inf");
/// ```
pub fn fmt_num(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1e-4..1e15).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A value's text for a message: every number in it (also inside tuples and lists) that is a
/// decimal expansion of a magnitude < 1e-4 or ≥ 1e15, or is longer than 40 characters, is
/// rewritten with [`fmt_num`]; anything else (integers up to 40 digits, ordinary decimals,
/// names) is kept as is.
pub(crate) fn compact_number_text(text: String) -> String {
    let is_num = |c: char| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-');
    let mut out = String::with_capacity(text.len());
    let mut rest = text.as_str();
    while let Some(start) = rest.find(is_num) {
        out.push_str(&rest[..start]);
        let tail = &rest[start..];
        let len = tail.find(|c: char| !is_num(c)).unwrap_or(tail.len());
        let token = &tail[..len];
        let tiny_or_huge = |x: f64| x != 0.0 && !(1e-4..1e15).contains(&x.abs());
        match token.parse::<f64>() {
            Ok(x) if token.len() > 40 || (token.contains('.') && tiny_or_huge(x)) => {
                out.push_str(&fmt_num(x))
            }
            _ => out.push_str(token),
        }
        rest = &tail[len..];
    }
    out.push_str(rest);
    out
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_and_tiny_values_print_compactly() {
        let e = Error::invalid("tol", 1e300, "must be < 0.5").to_string();
        assert_eq!(e, "invalid tol = 1e300: must be < 0.5");
        let e = Error::invalid("tol", -1e-300, "x").to_string();
        assert!(e.contains("-1e-300"), "{e}");
        // Integers keep every digit; ordinary floats are untouched.
        let e = Error::invalid("n", u64::MAX, "x").to_string();
        assert!(e.contains("18446744073709551615"), "{e}");
        let e = Error::invalid("d", format!("({}, {}, 1)", 6.1e-17, 1e300), "x").to_string();
        assert!(e.contains("(6.1e-17, 1e300, 1)"), "{e}");
        assert!(Error::invalid("x", 0.1 + 0.2, "y")
            .to_string()
            .contains("0.30000000000000004"));
    }
}

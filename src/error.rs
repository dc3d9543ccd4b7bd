//! Errors as values.
//!
//! Every public constructor and every update of the core checks its input
//! before it touches any state, and reports what it rejected as an
//! [`OccError`] that names the field and the offending value. The bindings
//! turn these into JavaScript `Error`s with the same message, so a widget can
//! show it instead of dying on a panic.

use std::borrow::Cow;
use std::fmt;

/// What went wrong, with enough detail for a reader to fix the input.
#[derive(Debug, Clone, PartialEq)]
pub enum OccError {
    /// A parameter is outside its domain: `field` is its name as the caller
    /// spells it, `value` the rejected value as text, `expected` the domain
    /// (owned when it is built from the limits the check uses).
    InvalidParameter {
        field: String,
        value: String,
        expected: Cow<'static, str>,
    },
    /// Two inputs that must agree in length do not.
    LengthMismatch {
        field: String,
        expected: usize,
        found: usize,
    },
    /// A line of an input file could not be read.
    Parse { line: usize, reason: String },
    /// A call that the session's state does not allow yet (or any more),
    /// said in words: "the log has not been read yet".
    State(String),
}

impl fmt::Display for OccError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OccError::InvalidParameter {
                field,
                value,
                expected,
            } => write!(f, "invalid {field}: {value} (expected {expected})"),
            OccError::LengthMismatch {
                field,
                expected,
                found,
            } => write!(
                f,
                "invalid {field}: length {found} does not match the expected {expected}"
            ),
            OccError::Parse { line, reason } => write!(f, "line {line}: {reason}"),
            OccError::State(what) => f.write_str(what),
        }
    }
}

impl std::error::Error for OccError {}

pub type Result<T> = std::result::Result<T, OccError>;

/// Builds an [`OccError::InvalidParameter`] for `field = value`.
pub fn invalid(
    field: &str,
    value: impl fmt::Display,
    expected: impl Into<Cow<'static, str>>,
) -> OccError {
    invalid_shown(field, &value, expected.into())
}

/// [`invalid`] written once for every kind of value (it is called from
/// hundreds of checks).
#[inline(never)]
fn invalid_shown(field: &str, value: &dyn fmt::Display, expected: Cow<'static, str>) -> OccError {
    OccError::InvalidParameter {
        field: field.to_string(),
        value: value.to_string(),
        expected,
    }
}

/// A number as a reader wants it in a message: plain, or in exponent form
/// when plain would print dozens of digits (1e300, 2.2e-308).
pub fn show(v: f64) -> String {
    let a = v.abs();
    if v.is_finite() && (a >= 1e16 || (a != 0.0 && a < 1e-6)) {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// `value` must be a finite number.
pub fn finite(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(invalid(field, show(value), "a finite number"))
    }
}

/// `value` must be finite and strictly positive.
pub fn positive(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(invalid(
            field,
            show(value),
            "a finite number greater than 0",
        ))
    }
}

/// `value` must be finite and not negative.
pub fn non_negative(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(invalid(field, show(value), "a finite number of at least 0"))
    }
}

/// `value` must be a probability strictly between 0 and 1: at 0 or 1 the log
/// odds are infinite and a cell could never be revised.
pub fn open_probability(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 && value < 1.0 {
        Ok(value)
    } else {
        Err(invalid(
            field,
            show(value),
            "a probability strictly between 0 and 1",
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_field_and_the_value() {
        let e = positive("resolution", -0.5).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("resolution"), "{text}");
        assert!(text.contains("-0.5"), "{text}");
        let e = open_probability("prior", 1.0).unwrap_err().to_string();
        assert!(e.contains("prior") && e.contains('1'), "{e}");
        assert!(finite("x", f64::NAN)
            .unwrap_err()
            .to_string()
            .contains("NaN"));
    }
}

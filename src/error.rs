//! The crate's error type: what went wrong when a parameter was rejected.

use core::fmt;

/// An error raised when a configuration value is rejected at construction.
///
/// Every constructor that takes user parameters validates them once and returns this
/// error naming the offending field, so hot per-pixel paths never re-check them.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is outside its valid range or not finite.
    InvalidParameter {
        /// Name of the parameter as it appears in the API (for example `"eta"`).
        name: &'static str,
        /// The rejected value, widened to `f64` for display.
        value: f64,
        /// What the parameter must satisfy (for example `"must be in (0, 1]"`).
        expected: &'static str,
    },
    /// Two parameters are individually valid but inconsistent with each other.
    InconsistentParameters {
        /// Names of the parameters involved.
        names: &'static str,
        /// What they must satisfy together (for example `"min_samples <= max_samples"`).
        expected: &'static str,
    },
}

impl Error {
    /// Shorthand for [`Error::InvalidParameter`].
    #[must_use]
    pub const fn invalid(name: &'static str, value: f64, expected: &'static str) -> Self {
        Self::InvalidParameter {
            name,
            value,
            expected,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidParameter {
                name,
                value,
                expected,
            } => write!(
                f,
                "invalid parameter `{name}` = {}: {expected}",
                Compact(*value)
            ),
            Self::InconsistentParameters { names, expected } => {
                write!(f, "inconsistent parameters {names}: {expected}")
            }
        }
    }
}

impl core::error::Error for Error {}

/// An `f64` written compactly: plain decimal (`{}`) where that is short (zero, and
/// magnitudes in `[1e-4, 1e6)`), scientific (`{:e}`) elsewhere, so that `1e-320` prints
/// as `1e-320` rather than as 330 digits. Non-finite values print as `NaN`, `inf`,
/// `-inf`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Compact(pub(crate) f64);

impl fmt::Display for Compact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        let a = v.abs();
        if !v.is_finite() || v == 0.0 || (1e-4..1e6).contains(&a) {
            write!(f, "{v}")
        } else {
            write!(f, "{v:e}")
        }
    }
}

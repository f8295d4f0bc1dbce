//! Errors of the report.

use core::fmt;
use std::path::{Path, PathBuf};

use crate::wgpu_api::PassError;

/// What can go wrong while making the report.
#[derive(Debug)]
pub enum ReportError {
    /// A command-line value out of range (the message names the flag).
    Usage(String),
    /// The pass failed (device, parameters, frame size).
    Pass(PassError),
    /// No device for `--backend`, or one that failed (the message names the flag and the
    /// cause).
    Device(String),
    /// A GPU run differs from its CPU twin (the message names the section, scene, run and
    /// frame): the run is corrupt and not scored.
    Corrupt(String),
    /// A kept asset (a mesh) that cannot be read (the message names it and why).
    Asset(String),
    /// Reading or writing a file failed.
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Drawing a chart failed.
    Chart {
        /// The chart file.
        path: PathBuf,
        /// What the chart library said.
        message: String,
    },
}

impl ReportError {
    /// An I/O error on `path`.
    #[must_use]
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

impl fmt::Display for ReportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Usage(s) | Self::Device(s) | Self::Corrupt(s) | Self::Asset(s) => {
                write!(f, "{s}")
            }
            Self::Pass(e) => write!(f, "{e}"),
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Chart { path, message } => write!(f, "chart {}: {message}", path.display()),
        }
    }
}

impl std::error::Error for ReportError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Pass(e) => Some(e),
            Self::Io { source, .. } => Some(source),
            Self::Chart { .. }
            | Self::Usage(_)
            | Self::Device(_)
            | Self::Corrupt(_)
            | Self::Asset(_) => None,
        }
    }
}

impl From<PassError> for ReportError {
    fn from(e: PassError) -> Self {
        Self::Pass(e)
    }
}

impl From<spvg::Error> for ReportError {
    fn from(e: spvg::Error) -> Self {
        Self::Pass(PassError::Param(e))
    }
}

impl From<crate::wgpu_api::AdaptiveError> for ReportError {
    fn from(e: crate::wgpu_api::AdaptiveError) -> Self {
        Self::Pass(PassError::from(e))
    }
}

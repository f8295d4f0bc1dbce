//! The online control variate's per-pixel history `J`.

/// Per-pixel history of the online control variate (OCV): the parts of the exponential
/// moving covariance matrix of `Z = [fbar, G]` that the coefficient needs (docs/algorithms.md §3).
/// `Sigma_xx` is never used, so it is not stored.
///
/// `Default` is the zero state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CvHistory<T> {
    /// `Sigma_xy`: covariance of the distant estimate `fbar` and the control `G`.
    pub cov_fg: T,
    /// `Sigma_yy`: variance of the control `G`.
    pub var_g: T,
    /// `zeta_f`: EMA of `fbar`.
    pub mean_f: T,
    /// `zeta_g`: EMA of `G`.
    pub mean_g: T,
}

//! The separable profile's fit to each preset's Burley channels (docs/algorithms.md §5.1).

use spvg::burley::{FalloffMatch, ShapeFit, fit_falloff, presets};

use crate::error::ReportError;

/// One preset's separable fit: falloff and relative residual per channel.
#[derive(Clone, Debug, PartialEq)]
pub struct FitRow {
    /// The preset's name.
    pub name: &'static str,
    /// Falloff per channel (shape match, as the filter uses it).
    pub falloff: [f64; 3],
    /// `sqrt(S_delta / sum (r R_B)^2)` per channel: the radial profile error.
    pub residual: [f64; 3],
}

/// The fit of every preset ([`presets::ALL`]).
///
/// # Errors
///
/// A preset that does not build (never for the shipped ones).
pub fn fit_rows() -> Result<Vec<FitRow>, ReportError> {
    presets::ALL
        .iter()
        .map(|m| {
            let p = m.profiles::<f64>(ShapeFit::DiffuseMeanFreePath)?;
            let fits = p.map(|c| fit_falloff(&c, FalloffMatch::Shape));
            Ok(FitRow {
                name: m.name,
                falloff: fits.map(|f| f.falloff),
                residual: fits.map(|f| f.relative_residual),
            })
        })
        .collect()
}

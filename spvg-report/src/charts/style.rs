//! What every chart shares: the font, the colours, and the error of a chart that could not
//! be drawn.

use std::path::Path;

use plotters::style::RGBColor;

use crate::error::ReportError;

/// Font family of every chart label (resolved by the SVG viewer).
pub(crate) const FONT: &str = "sans-serif";

/// A colour, `[r, g, b]`.
pub type Colour = [u8; 3];

/// `c` as `plotters`' colour.
pub(crate) fn rgb(c: Colour) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

/// The error of a chart that could not be drawn or written.
pub(crate) fn chart_error(path: &Path) -> impl Fn(Box<dyn std::error::Error>) -> ReportError + '_ {
    move |e| ReportError::Chart {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

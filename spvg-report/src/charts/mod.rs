//! The report's one chart module: every chart is drawn here by `plotters` into SVG (text
//! stays SVG text, so no font files are needed). It knows lines and points, not runs: a
//! section turns its figures into a [`LineChart`] or a [`ScatterChart`] and names the
//! file.
//!
//! - [`draw_lines`]: series against the frame index (or any x), on a linear or log10 y
//!   axis, with the legend in its own column or inside a corner, a shaded x range and
//!   dashed reference levels;
//! - [`draw_scatter`]: panels of labelled points, the labels of coincident
//!   points merged and placed so that no two overprint.

mod lines;
mod scatter;
mod style;

pub use lines::{Legend, Line, LineChart, draw_lines};
pub use scatter::{Panel, ScatterChart, ScatterPoint, draw_scatter};
pub use style::Colour;

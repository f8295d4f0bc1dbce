//! The report's charts section: draws each scene's per-frame charts and the Pareto
//! panels ([`crate::charts`]) and links them.

use std::fmt::Write as _;
use std::path::Path;

use super::Report;
use crate::charts::{self, ParetoX, Series};
use crate::error::ReportError;
use crate::evaluate::RunSummary;

/// The charts section drawn into `dir`, as markdown, and each PSNR chart with its number
/// of points off the axis (for the notes).
///
/// # Errors
///
/// [`ReportError::Chart`] naming the file.
pub(crate) fn charts_section(
    r: &Report,
    dir: &Path,
) -> Result<(String, Vec<(String, usize)>), ReportError> {
    let i = &r.inputs;
    let mut clipped = Vec::new();
    let mut md = String::new();
    if !i.reference {
        md.push_str("(no charts: --no-reference)\n");
        return Ok((md, clipped));
    }
    for s in &r.scenes {
        let mut links = Vec::new();
        for series in Series::ALL {
            let (file, outside) = charts::write_series(dir, s.kind.name(), series, &s.per_frame)?;
            if series == Series::Psnr {
                clipped.push((file.clone(), outside));
            }
            links.push(format!("![{} {}]({file})", s.kind.name(), series.name()));
        }
        if let Some(b) = i.budget_spp {
            let file = charts::write_budget(dir, s.kind.name(), b, &s.per_frame)?;
            links.push(format!("![{} budget]({file})", s.kind.name()));
        }
        let _ = writeln!(md, "### {}\n\n{}\n", s.kind.name(), links.join("\n"));
    }
    let names: Vec<&str> = r.scenes.iter().map(|s| s.kind.name()).collect();
    let all: Vec<RunSummary> = r.scenes.iter().flat_map(|s| s.summaries.clone()).collect();
    for x in [ParetoX::Spp, ParetoX::Time] {
        let file = charts::write_pareto(dir, x, &names, &all, i.timing.short())?;
        let _ = writeln!(md, "![pareto {}]({file})\n", x.name());
    }
    Ok((md, clipped))
}

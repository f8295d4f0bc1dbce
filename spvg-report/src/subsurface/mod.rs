//! The subsurface section: every scene ([`crate::scene`]) through every model on the
//! subsurface pass, against the quadrature references of [`crate::reference`].
//!
//! One concept per module, each importing only those listed before it: one run of a
//! scene ([`run`]), a scene's runs and frame images ([`scene_runs`]), what the section was
//! asked and measured ([`data`]), which runs ([`runs`]), the equal-quality figures
//! (`equal_quality`), the acceptance checks ([`acceptance`]), the charts ([`figures`]),
//! the notes computed from the figures ([`notes`]), the markdown ([`markdown`]) and the
//! CSV files ([`csv`]). This file runs them in order.

pub mod acceptance;
pub mod csv;
pub mod data;
pub(crate) mod equal_quality;
pub mod figures;
pub mod markdown;
pub mod notes;
pub mod run;
pub mod runs;
pub mod scene_runs;

use std::fmt::Write as _;
use std::path::Path;

use crate::error::ReportError;
use crate::policies::{damped, firefly};
use crate::section::Section;

pub use data::{Report, ReportInputs};
pub use runs::{RunPlan, SWEEP_SIGMA0_SQ, run_scenes, sweep_settings};
pub use scene_runs::{ImageRow, SceneRuns};

impl Report {
    /// Judges the runs (and the core's policies) and writes the charts, `runs.csv` and
    /// `frames.csv` into `dir`; `duplicates` is the number of frame images linked instead
    /// of written. Returns the section.
    ///
    /// # Errors
    ///
    /// [`ReportError::Io`] / [`ReportError::Chart`] naming the file.
    pub fn finish(&mut self, dir: &Path, duplicates: usize) -> Result<Section, ReportError> {
        self.circle = damped::circle_sweep()?;
        self.firefly = firefly::firefly_sweep()?;
        self.groups = acceptance::groups(&self.inputs, &self.scenes, &self.circle, &self.firefly);
        let (charts, clipped) = figures::charts_section(self, dir)?;
        let notes = notes::notes(self, &clipped);
        let md = markdown::section_md(self, duplicates, &charts, &notes);
        write(dir, "runs.csv", &csv::runs_csv(self))?;
        write(dir, "frames.csv", &csv::frames_csv(self))?;
        Ok(Section {
            name: "subsurface",
            markdown: md,
            groups: self.groups.clone(),
        })
    }

    /// The results table, for stdout.
    #[must_use]
    pub fn stdout_summary(&self) -> String {
        let mut o = format!("{}\n", markdown::table_header());
        for s in self.scenes.iter().flat_map(|s| &s.summaries) {
            let _ = writeln!(o, "{}", markdown::table_row(s));
        }
        o
    }
}

/// Writes `text` into `dir/file`.
fn write(dir: &Path, file: &str, text: &str) -> Result<(), ReportError> {
    let path = dir.join(file);
    std::fs::write(&path, text).map_err(|e| ReportError::io(&path, e))
}

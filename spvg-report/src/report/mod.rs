//! The subsurface report: its runs ([`runs`]), each scene's results ([`scene_runs`]), the
//! acceptance checks and verdict ([`acceptance`]), the equal-quality figures
//! (`equal_quality`), the notes computed from the figures
//! ([`notes`]), the charts section ([`charts`]), `report.md` ([`markdown`]) and the CSV
//! files ([`csv`]).

pub mod acceptance;
pub mod charts;
pub mod csv;
pub(crate) mod equal_quality;
pub mod markdown;
pub mod notes;
pub mod runs;
pub mod scene_runs;

use std::fmt::Write as _;
use std::path::Path;

use crate::acceptance::Check;
use crate::damped::{self, PolicyFigures};
use crate::error::ReportError;
use crate::firefly::{self, FireflyFigures};
use crate::images::Written;
use crate::scene::Lighting;
use crate::timing::Timing;
use crate::wgpu_api::PassConfig;

use acceptance::Verdicts;
pub use runs::{RunPlan, SWEEP_SIGMA0_SQ, run_scenes, sweep_settings};
pub use scene_runs::SceneRuns;

/// What the report was asked to do.
#[derive(Clone, Debug)]
pub struct ReportInputs {
    /// Frame width.
    pub width: u32,
    /// Frame height.
    pub height: u32,
    /// Frames per run.
    pub frames: u32,
    /// Material name.
    pub material: &'static str,
    /// Lighting variant.
    pub lighting: Lighting,
    /// Filtered sampling.
    pub afis: bool,
    /// The report's target variance.
    pub sigma0_sq: f32,
    /// Whether references (and so PSNR, acceptance, charts) were computed.
    pub reference: bool,
    /// Frame whose images are written.
    pub image_frame: u32,
    /// One line naming the backend.
    pub backend: String,
    /// What the pass times mean.
    pub timing: Timing,
    /// The settings run (first: the report setting).
    pub settings: Vec<(String, PassConfig)>,
    /// The budget of the `budget` runs (samples per subsurface pixel), if run.
    pub budget_spp: Option<f64>,
    /// The budget governor's integral gain.
    pub budget_gain: f64,
    /// What this run holds against the whole suite (`--full`), in one sentence.
    pub suite: String,
}

/// The frame images of one run.
#[derive(Clone, Debug)]
pub struct ImageRow {
    /// Run label.
    pub label: String,
    /// Result image.
    pub result: Written,
    /// Count image.
    pub count: Written,
    /// Error image (with a reference only).
    pub error: Option<Written>,
}

/// The report being assembled.
#[derive(Debug)]
pub struct Report {
    inputs: ReportInputs,
    scenes: Vec<SceneRuns>,
    verdicts: Verdicts,
    /// The damped policy in the kappa sweep (circle scenario, core crate).
    circle: Vec<PolicyFigures>,
    /// The firefly clamp's recovery from an outlier (core crate).
    firefly: Vec<FireflyFigures>,
    /// The acceptance lines of the sections written to their own files and appended to
    /// `report.md` (motion, separable), by section name (counted by the verdict).
    sections: Vec<(String, Vec<Check>)>,
}

impl Report {
    /// An empty report.
    #[must_use]
    pub fn new(inputs: ReportInputs) -> Self {
        Self {
            inputs,
            scenes: Vec::new(),
            verdicts: Verdicts::default(),
            circle: Vec::new(),
            firefly: Vec::new(),
            sections: Vec::new(),
        }
    }

    /// Adds the acceptance lines of the section `name` (`motion`, `separable`) to the
    /// verdict (the section itself lists them, under *Acceptance (name)*).
    pub fn push_section_checks(&mut self, name: &str, checks: &[Check]) {
        self.sections.push((name.to_owned(), checks.to_vec()));
    }

    /// Adds a scene's runs.
    pub fn push_scene(&mut self, runs: SceneRuns) {
        self.scenes.push(runs);
    }

    /// Judges the runs and writes the charts, `report.md`, `runs.csv` and `frames.csv`
    /// into `dir`; `wall_s` is the run's wall time so far, `duplicates` the frame images
    /// linked instead of written.
    ///
    /// # Errors
    ///
    /// [`ReportError::Io`] / [`ReportError::Chart`] naming the file.
    pub fn finish(
        &mut self,
        dir: &Path,
        wall_s: f64,
        duplicates: usize,
    ) -> Result<(), ReportError> {
        self.circle = damped::circle_sweep()?;
        self.firefly = firefly::firefly_sweep()?;
        self.verdicts = acceptance::judge(
            &self.inputs,
            &self.scenes,
            &self.circle,
            &self.firefly,
            &self.sections,
        );
        let (charts, clipped) = charts::charts_section(self, dir)?;
        let notes = notes::notes(self, &clipped);
        let md = markdown::report_md(self, wall_s, duplicates, &charts, &notes);
        write(dir, "report.md", &md)?;
        write(dir, "runs.csv", &csv::runs_csv(self))?;
        write(dir, "frames.csv", &csv::frames_csv(self))
    }

    /// Whether every judged acceptance check holds (after [`finish`](Self::finish)).
    #[must_use]
    pub fn passed(&self) -> bool {
        self.verdicts.line.starts_with("**Verdict: PASS**")
    }

    /// The results table, the acceptance lines and the verdict, for stdout.
    #[must_use]
    pub fn stdout_summary(&self) -> String {
        let mut o = format!("{}\n", markdown::table_header());
        for s in self.scenes.iter().flat_map(|s| &s.summaries) {
            let _ = writeln!(o, "{}", markdown::table_row(s));
        }
        let _ = writeln!(o, "\n{}\n{}", self.verdicts.markdown, self.verdicts.line);
        o
    }
}

/// Writes `text` into `dir/file`.
fn write(dir: &Path, file: &str, text: &str) -> Result<(), ReportError> {
    let path = dir.join(file);
    std::fs::write(&path, text).map_err(|e| ReportError::io(&path, e))
}

//! What the subsurface section was asked to do and what it measured, as its acceptance,
//! notes, charts, markdown and CSV read it.

use super::scene_runs::SceneRuns;
use crate::policies::damped::PolicyFigures;
use crate::policies::firefly::FireflyFigures;
use crate::scene::Lighting;
use crate::section::Group;
use crate::timing::Timing;
use crate::wgpu_api::PassConfig;

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

/// The section being assembled.
#[derive(Debug)]
pub struct Report {
    /// What it was asked to do.
    pub inputs: ReportInputs,
    /// Each scene's runs.
    pub scenes: Vec<SceneRuns>,
    /// The acceptance lines, in titled groups (after the runs are judged).
    pub groups: Vec<Group>,
    /// The damped policy in the kappa sweep (circle scenario, core crate).
    pub circle: Vec<PolicyFigures>,
    /// The firefly clamp's recovery from an outlier (core crate).
    pub firefly: Vec<FireflyFigures>,
}

impl Report {
    /// An empty section.
    #[must_use]
    pub fn new(inputs: ReportInputs) -> Self {
        Self {
            inputs,
            scenes: Vec::new(),
            groups: Vec::new(),
            circle: Vec::new(),
            firefly: Vec::new(),
        }
    }

    /// Adds a scene's runs.
    pub fn push_scene(&mut self, runs: SceneRuns) {
        self.scenes.push(runs);
    }
}

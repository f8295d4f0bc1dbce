//! The runs of the subsurface report: which settings run ([`sweep_settings`]) and every
//! scene through every run specification ([`run_scenes`]), with their frame images.

use spvg::burley::MaterialPreset;

use super::data::Report;
use super::run::{ReferenceCache, RunSpec, run_scene};
use super::scene_runs::SceneRuns;
use crate::error::ReportError;
use crate::images::ImageWriter;
use crate::progress::Progress;
use crate::reference::Quadrature;
use crate::scene::{Lighting, Scene, SceneKind};
use crate::timing;
use crate::wgpu_api::{Backend, PassConfig};

/// The target variances of the sweep (the report setting is skipped if among them).
pub const SWEEP_SIGMA0_SQ: [f32; 4] = [1e-3, 1e-4, 1e-5, 1e-6];

/// The swept settings: a label suffix ("" for the report setting) and the configuration.
/// A swept value the controller rejects with the base's other settings is left out.
#[must_use]
pub fn sweep_settings(base: PassConfig, sweep: bool) -> Vec<(String, PassConfig)> {
    let mut v = vec![(String::new(), base)];
    if sweep {
        for sigma0_sq in SWEEP_SIGMA0_SQ {
            if sigma0_sq != base.spvg.target_variance()
                && let Ok(spvg) = base.spvg.to_builder().target_variance(sigma0_sq).build()
            {
                v.push((format!(" s0^2={sigma0_sq:e}"), PassConfig { spvg, ..base }));
            }
        }
        for kappa in [0.0_f32, 1.0] {
            if kappa != base.spvg.kappa()
                && let Ok(spvg) = base.spvg.to_builder().kappa(kappa).build()
            {
                v.push((format!(" kappa={kappa}"), PassConfig { spvg, ..base }));
            }
        }
    }
    v
}

/// Everything the scene runs need besides the backend.
#[derive(Clone, Debug)]
pub struct RunPlan {
    /// The scenes, in report order.
    pub scenes: Vec<SceneKind>,
    /// The runs of each scene.
    pub specs: Vec<RunSpec>,
    /// The subsurface material.
    pub material: MaterialPreset,
    /// The lighting variant.
    pub lighting: Lighting,
    /// Frame width.
    pub width: u32,
    /// Frame height.
    pub height: u32,
    /// Frames per run.
    pub frames: u32,
    /// The frame whose images are written (report-setting runs).
    pub image_frame: u32,
    /// Whether each frame is measured against a quadrature reference.
    pub reference: bool,
    /// Whether the budget run runs on every scene; else only on the scenes its acceptance
    /// checks judge ([`BUDGET_SCENES`]).
    pub budget_everywhere: bool,
    /// Whether the TAA-guided AS run and the resolved-image run run on every scene; else
    /// only on the scenes their acceptance lines judge ([`GUIDE_SCENES`],
    /// [`RESOLVED_SCENES`]).
    pub guide_everywhere: bool,
}

/// The scenes whose budget runs the acceptance checks judge.
pub const BUDGET_SCENES: [SceneKind; 2] = [SceneKind::Flash, SceneKind::Switch];

/// The scenes whose TAA-guided AS run the acceptance line judges.
pub const GUIDE_SCENES: [SceneKind; 2] = [SceneKind::Flash, SceneKind::Switch];

/// The scenes whose resolved-image run ([`RunSpec::resolved`]) the acceptance line
/// judges (every scene under `--full`).
pub const RESOLVED_SCENES: [SceneKind; 1] = [SceneKind::Static];

impl RunPlan {
    /// The runs of scene `kind`: every spec, less the budget and guided runs where they
    /// are not judged (unless [`budget_everywhere`](Self::budget_everywhere),
    /// [`guide_everywhere`](Self::guide_everywhere)).
    pub fn specs_for(&self, kind: SceneKind) -> impl Iterator<Item = &RunSpec> {
        let budget = self.budget_everywhere || BUDGET_SCENES.contains(&kind);
        let guided = self.guide_everywhere || GUIDE_SCENES.contains(&kind);
        let resolved = self.guide_everywhere || RESOLVED_SCENES.contains(&kind);
        self.specs
            .iter()
            .filter(move |s| budget || s.budget_spp.is_none())
            .filter(move |s| guided || !s.guided)
            .filter(move |s| resolved || s.label != RunSpec::RESOLVED)
    }

    /// Frames the plan renders (for a progress bar).
    #[must_use]
    pub fn frames_to_render(&self) -> u64 {
        let runs: usize = self.scenes.iter().map(|&k| self.specs_for(k).count()).sum();
        runs as u64 * u64::from(self.frames)
    }
}

/// Runs one scene through every run of `plan`, writing the frame images of the
/// report-setting runs.
fn run_one_scene(
    backend: &Backend,
    plan: &RunPlan,
    kind: SceneKind,
    images: &mut ImageWriter,
    progress: &Progress,
) -> Result<SceneRuns, ReportError> {
    let scene = Scene {
        lighting: plan.lighting,
        ..Scene::new(kind, plan.width, plan.height)
    };
    let mut refs = ReferenceCache::new(
        scene,
        plan.material,
        PassConfig::default(),
        Quadrature::default(),
    );
    let mut runs = SceneRuns::new(kind);
    for spec in plan.specs_for(kind) {
        progress.stage(&format!("{} {}", kind.name(), spec.label));
        let mut shot = None;
        let (records, summary) = run_scene(
            backend,
            scene,
            &plan.material,
            spec,
            plan.frames,
            plan.reference.then_some(&mut refs),
            |t, out, reference, mask| {
                progress.inc(1);
                if t == plan.image_frame && !spec.is_sweep() {
                    shot = Some((out.clone(), reference.to_vec(), mask.to_vec()));
                }
            },
        )?;
        if let Some((out, reference, mask)) = shot {
            let t = plan.image_frame;
            runs.frame_images(images, &spec.label, t, scene, &out, &reference, &mask)?;
        }
        progress.println(&format!(
            "{} {}: {:.1} spp, PSNR {:.2} dB, p50 {}, {:.0} s",
            kind.name(),
            spec.label,
            summary.mean_spp,
            summary.mean_psnr,
            timing::ms(summary.p50_ms),
            progress.elapsed_s()
        ));
        runs.push(spec, records, summary);
    }
    Ok(runs)
}

/// Runs every scene of `plan` on `backend` into `report`, frame images into `images`;
/// `progress` counts frames.
///
/// # Errors
///
/// Parameter validation, device errors, or an image that cannot be written.
pub fn run_scenes(
    backend: &Backend,
    plan: &RunPlan,
    report: &mut Report,
    images: &mut ImageWriter,
    progress: &Progress,
) -> Result<(), ReportError> {
    for &kind in &plan.scenes {
        report.push_scene(run_one_scene(backend, plan, kind, images, progress)?);
    }
    Ok(())
}

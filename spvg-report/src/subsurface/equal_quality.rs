//! The equal-quality figures of each adaptive run of a scene against the scene's fixed
//! runs ([`crate::equal_quality`]), single-frame and after the TAA resolve.

use super::run::RunSummary;
use crate::equal_quality::{EqualQuality, FixedPoint, FlickerPoint, Interpolated, psnr_at};
use crate::wgpu_api::Model;

/// An adaptive run's figures against its scene's fixed runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RunFigures {
    /// The fixed count reaching the run's single-frame PSNR.
    pub(crate) single: EqualQuality,
    /// The fixed count reaching the run's PSNR after TAA.
    pub(crate) taa: EqualQuality,
    /// The fixed runs' PSNR after TAA at the run's mean spp.
    pub(crate) fixed_taa_at_spp: Interpolated,
}

/// The fixed-count runs of `all` (not under a budget) as (spp, PSNR) points: single-frame,
/// or after TAA.
pub(crate) fn fixed_points(all: &[RunSummary], taa: bool) -> Vec<FixedPoint> {
    all.iter()
        .filter(|s| matches!(s.model, Model::Fixed(_)) && s.budget_spp.is_none())
        .map(|s| FixedPoint {
            spp: s.mean_spp,
            psnr: if taa { s.mean_psnr_taa } else { s.mean_psnr },
        })
        .collect()
}

/// The fixed runs among `all` as (PSNR, instability) points after TAA.
pub(crate) fn fixed_flicker_points(all: &[RunSummary]) -> Vec<FlickerPoint> {
    all.iter()
        .filter(|s| matches!(s.model, Model::Fixed(_)) && s.budget_spp.is_none())
        .map(|s| FlickerPoint {
            psnr: s.mean_psnr_taa,
            flicker: s.flicker_taa,
        })
        .collect()
}

/// The figures of `run` against the fixed runs among `all`; `None` for a fixed run.
pub(crate) fn figures(all: &[RunSummary], run: &RunSummary) -> Option<RunFigures> {
    if matches!(run.model, Model::Fixed(_)) {
        return None;
    }
    let (single, taa) = (fixed_points(all, false), fixed_points(all, true));
    Some(RunFigures {
        single: EqualQuality::new(&single, run.mean_spp, run.mean_psnr),
        taa: EqualQuality::new(&taa, run.mean_spp, run.mean_psnr_taa),
        fixed_taa_at_spp: psnr_at(&taa, run.mean_spp),
    })
}

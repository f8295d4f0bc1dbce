//! Scenes with motion, run through the second consumer (ambient occlusion) and the
//! adaptive component: camera pans at 1 to 8 px per frame, a camera rotation, a sphere
//! moving across the surface, and several objects (three spheres and a thin bar) moving
//! faster in different directions (disocclusion by motion). Each scene runs AS with
//! reprojection and the fixed counts 16, 32 and 64 (the equal-quality figures; with
//! `full`, every scene also runs AS with the identity history: zero motion vectors, no
//! depth test, a renderer without reprojection), against a converged quadrature reference
//! of its own ([`reference()`]), each run measured also after a TAA resolve
//! ([`crate::taa`]).
//!
//! One concept per module: the scenes and the ways of running them ([`scenes`]), the
//! dolly's static baseline ([`baseline`]), the
//! references ([`mod@reference`]), the runs ([`runs`]), the error of uncovered pixels by
//! their age on screen ([`uncovered`]), the acceptance lines
//! ([`acceptance`]), the markdown and CSV ([`mod@markdown`]) and the chart ([`mod@chart`]).
//! [`MotionOptions::full`] selects the whole suite; the default runs what every
//! acceptance line needs (see [`scenes::variants`]).

pub mod acceptance;
pub mod baseline;
pub mod chart;
pub mod markdown;
pub mod poses;
pub mod reference;
pub mod runs;
pub mod scenes;
pub mod uncovered;

use std::fmt::Write as _;
use std::path::Path;

use spvg::SpvgConfig;

use crate::acceptance::Check;
use crate::error::ReportError;
use crate::progress::Progress;
use crate::wgpu_api::{GpuDevice, Motion};

pub use chart::{write_chart, write_uncovered_chart};
pub use markdown::markdown;
pub use reference::{reference, references};
pub use runs::{MotionBound, MotionReport, MotionRun, WARM_UP, motion_bound, report, run};
pub use scenes::{
    AGE_WEIGHT, BORDER_TEXEL, DOLLY, NEAREST_ONLY, NO_DILATION, NO_NEIGHBOUR_PRIOR, NO_PRIOR,
    NO_REPROJECTED_DEPTH, NO_SPATIAL, OBJECTS, SPATIAL, SPATIAL_FRAMES, TIGHTER_TARGETS, Variant,
    YOUNG, others, pans, tighter_name,
};
pub use uncovered::{AgeErrors, since_uncovered};

/// Settings of the motion report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionOptions {
    /// Frame size of the pans and their static camera (wide, so that the pixels entering
    /// at 8 px per frame are a small part of the frame, as at real resolutions).
    pub pan_size: [u32; 2],
    /// Frame size of the rotation, the moving sphere and their static camera.
    pub size: [u32; 2],
    /// Frames per run.
    pub frames: u32,
    /// The controller (AS).
    pub config: SpvgConfig<f32>,
    /// Directions per axis of the reference quadrature (`grid^2` per pixel).
    pub grid: u32,
    /// Count dilation radius of the AS runs (`spvg::dilation`); the full suite also runs
    /// radius 0 (`as-no-dilation`) on the static cameras, the fastest pan and the rotation.
    pub dilation: u32,
    /// The whole suite: `as-identity` on every scene and every knob row
    /// (`as-beta-min`,
    /// `as-border-texel`, `as-no-dilation`, `as-nearest-only`; [`scenes::variants`]), and
    /// the warm-up frames scored ([`reference::first_scored`]), besides what the acceptance
    /// lines need.
    pub full: bool,
}

impl MotionOptions {
    /// The defaults: pans at 384x192, the rest at 128x96, 48 frames, `sigma0^2 = 1e-4`
    /// (the library's published default), budget [8, 64], a 32x32 reference grid, count
    /// dilation radius 1, the default suite (not [`full`](Self::full)).
    ///
    /// # Errors
    ///
    /// Never with these constants; typed for a caller that changes them.
    pub fn new() -> Result<Self, spvg::Error> {
        Ok(Self {
            pan_size: [384, 192],
            size: [128, 96],
            frames: 48,
            config: SpvgConfig::builder().target_variance(1e-4).build()?,
            grid: 32,
            dilation: 1,
            full: false,
        })
    }

    /// The whole suite ([`new`](Self::new) with [`full`](Self::full) set).
    ///
    /// # Errors
    ///
    /// As [`new`](Self::new).
    pub fn full() -> Result<Self, spvg::Error> {
        Ok(Self {
            full: true,
            ..Self::new()?
        })
    }
}

/// Runs the motion report and writes `motion.md`, `motion.csv` and the charts into `dir`;
/// returns the markdown (with the charts linked) and the acceptance lines.
///
/// # Errors
///
/// A device failure, or a file that cannot be written (naming it).
pub fn write(
    dir: &Path,
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    backend: &str,
    progress: &Progress,
) -> Result<(String, Vec<Check>), ReportError> {
    let rep = report(dev, opts, progress)
        .map_err(|e| ReportError::Usage(format!("motion report: {e}")))?;
    let (mut md, csv) = markdown(&rep, opts, backend);
    std::fs::create_dir_all(dir).map_err(|e| ReportError::io(dir, e))?;
    let _ = writeln!(
        md,
        "\nPer-frame values: [motion.csv](motion.csv); per run, with the equal-quality figures: [motion_runs.csv](motion_runs.csv).\n"
    );
    let mut charts: Vec<String> = vec!["static-pan".into(), "static".into()];
    charts.extend(pans().iter().chain(&others()).map(Motion::name));
    for scene in charts {
        let file = write_chart(dir, &rep, &scene)?;
        let _ = writeln!(md, "![{scene}]({file})\n");
    }
    for scene in OBJECTS.map(|m| m.name()) {
        if let Some(file) = write_uncovered_chart(dir, &rep, &scene)? {
            let _ = writeln!(
                md,
                "{scene}: PSNR per frame of the steady pixels and of the newly uncovered ones at \
                 their first, second and third frame on screen (`as` solid, `{YOUNG}` dashed):\n\n\
                 ![{scene} uncovered]({file})\n"
            );
        }
    }
    let runs_path = dir.join("motion_runs.csv");
    std::fs::write(&runs_path, markdown::runs_csv(&rep))
        .map_err(|e| ReportError::io(&runs_path, e))?;
    let csv_path = dir.join("motion.csv");
    std::fs::write(&csv_path, csv).map_err(|e| ReportError::io(&csv_path, e))?;
    let md_path = dir.join("motion.md");
    std::fs::write(&md_path, &md).map_err(|e| ReportError::io(&md_path, e))?;
    Ok((md, rep.lines))
}

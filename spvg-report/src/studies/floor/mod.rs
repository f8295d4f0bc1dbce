//! Fractional counts below the floor (docs/algorithms.md §8.6) and the resolved-image rule
//! (§8.7), swept after a temporal resolve: the fractional floor over a range of targets
//! against fixed counts from 1 to 64 and against AS [8, 64], on ambient occlusion
//! ([`ao`]: the static camera, the 4 px/frame pan, the floating sphere) and on the
//! subsurface effect's static scene ([`sss`]). Each runs on the effects' CPU twins (equal
//! to the GPU: `spvg-effects/tests/ao.rs`, `sss_consumer.rs`), so the figures are the same
//! on every machine. A study: it judges nothing (the report's `as-resolved` runs judge the
//! rule).

use std::path::Path;

use crate::error::ReportError;
use crate::progress::Progress;
use crate::section::Section;

/// The resolve's blend weight of the current frame (the report's, `crate::taa::WEIGHT`).
pub const TAA_WEIGHT: f32 = crate::taa::WEIGHT;

/// Appends one formatted line (or an empty one) to a markdown string.
macro_rules! say {
    ($md:ident) => {
        $md.push('\n')
    };
    ($md:ident, $($t:tt)*) => {{
        let _ = writeln!($md, $($t)*);
    }};
}

pub mod ao;
pub mod sss;

pub use ao::SparseBox;

/// `log2(spp)` of `curve` (sorted by spp, PSNR rising; `key` gives a point's spp, PSNR and
/// flicker) interpolated linearly in PSNR at `psnr`, and the flicker interpolated the same
/// way; `None` outside the curve.
fn at_psnr<F>(curve: &[F], psnr: f64, key: impl Fn(&F) -> [f64; 3]) -> Option<(f64, f64)> {
    curve.windows(2).find_map(|w| {
        let ([sa, pa, fa], [sb, pb, fb]) = (key(&w[0]), key(&w[1]));
        let (lo, hi) = (pa.min(pb), pa.max(pb));
        (psnr >= lo && psnr <= hi && hi > lo).then(|| {
            let s = (psnr - pa) / (pb - pa);
            let l = sa.log2() + s * (sb.log2() - sa.log2());
            (l.exp2(), fa + s * (fb - fa))
        })
    })
}

/// The label a sweep adds for the resolved-image rule's weight (nothing for 0, the
/// per-frame target).
fn rule_label(resolve: f32) -> String {
    if resolve > 0.0 {
        format!(" resolved {resolve}")
    } else {
        String::new()
    }
}

/// Which effects the study sweeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FloorEffects {
    /// Ambient occlusion only.
    Ao,
    /// The subsurface effect only.
    Sss,
    /// Both (subsurface first: it is the shorter).
    Both,
}

/// What the study sweeps. `None` lists take each effect's default.
#[derive(Clone, Debug, PartialEq)]
pub struct FloorOptions {
    /// The effects.
    pub effects: FloorEffects,
    /// AO: one scene (`static`, `pan4`, `object3`), or all three.
    pub scene: Option<String>,
    /// The fractional floors (AO: 0.25; subsurface: 0.25, 0.125, 0).
    pub floors: Option<Vec<f32>>,
    /// The targets `sigma0^2` of the floor's sweep (AO: ten from 3.2e-2 to 6.25e-5, or three
    /// with `quick`; subsurface: nine from 1e-3 to 1.6e-8).
    pub targets: Option<Vec<f32>>,
    /// AO: the count dilation radii.
    pub dilations: Vec<u32>,
    /// The resolved-image rule's steady weights, 0 for the per-frame target.
    pub resolves: Vec<f32>,
    /// AO: `beta_max` of the fractional runs.
    pub max_samples: u32,
    /// AO: what stands in the clamp box for a neighbour that skipped.
    pub sparse: SparseBox,
    /// AO: three targets instead of ten.
    pub quick: bool,
}

impl Default for FloorOptions {
    fn default() -> Self {
        Self {
            effects: FloorEffects::Both,
            scene: None,
            floors: None,
            targets: None,
            dilations: vec![1],
            resolves: vec![0.0, TAA_WEIGHT],
            max_samples: 64,
            sparse: SparseBox::History,
            quick: false,
        }
    }
}

/// Runs the study and writes `floor.md` into `dir`.
///
/// # Errors
///
/// A configuration the core refuses (a floor or target out of range, named), a twin
/// failure, a file that cannot be written.
pub fn write(dir: &Path, opts: &FloorOptions, progress: &Progress) -> Result<Section, ReportError> {
    let mut md = String::from(
        "## Fractional counts and the resolved-image rule after TAA (study, not judged)\n",
    );
    if matches!(opts.effects, FloorEffects::Sss | FloorEffects::Both) {
        md.push_str(&sss::markdown(opts, progress)?);
    }
    if matches!(opts.effects, FloorEffects::Ao | FloorEffects::Both) {
        md.push_str(&ao::markdown(opts, progress)?);
    }
    std::fs::create_dir_all(dir).map_err(|e| ReportError::io(dir, e))?;
    let path = dir.join("floor.md");
    std::fs::write(&path, &md).map_err(|e| ReportError::io(&path, e))?;
    Ok(Section {
        name: "floor",
        markdown: md,
        groups: Vec::new(),
    })
}

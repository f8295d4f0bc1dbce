//! The motion scenes (pans, a rotation, a moving sphere, a dolly, their static cameras) and the
//! ways of running each one ([`Variant`]): which runs the default suite holds and which
//! only [`MotionOptions::full`] adds.

use spvg::reproject::{BorderCount, Reprojection};

use super::MotionOptions;
use crate::wgpu_api::{AoMode, Motion};

/// The pans (along `+x` at 1, 2, 4 and 8 px per frame), compared with a static camera at
/// the same size.
#[must_use]
pub fn pans() -> Vec<Motion> {
    [1.0, 2.0, 4.0, 8.0]
        .map(|speed| Motion::Pan { speed })
        .to_vec()
}

/// The other moving scenes: a rotation of 2 degrees per frame (about 2 px per frame at the
/// frame's corners), a sphere crossing at 3 px per frame and a dolly of 3 world units per
/// frame (every depth changes by 3% or more per frame), compared with a static camera at
/// the same size.
#[must_use]
pub fn others() -> Vec<Motion> {
    vec![
        Motion::Rotate { degrees: 2.0 },
        Motion::MovingSphere { speed: 3.0 },
        DOLLY,
    ]
}

/// The dolly scene of [`others`].
pub const DOLLY: Motion = Motion::Dolly { rate: 3.0 };

/// The name of the AS run whose depth test compares this frame's depth instead of the
/// reprojected depth (a renderer that does not pass
/// `spvg_wgpu::adaptive::EstimateInputs::reprojected_depth`).
pub const NO_REPROJECTED_DEPTH: &str = "as-no-reprojected-depth";

/// The name of the AS run without the border prior (`spvg::reproject`): pixels entering
/// the frame start at `beta_min`, the papers' disocclusion rule.
pub const NO_PRIOR: &str = "as-beta-min";

/// The name of the AS run without count dilation (`spvg::dilation`, radius 0): each pixel
/// spends its own estimate, the papers' rule.
pub const NO_DILATION: &str = "as-no-dilation";

/// The name of the AS run without the footprint search (`spvg::reproject`): the nearest
/// texel only, rejected when it fails the mask or depth test.
pub const NEAREST_ONLY: &str = "as-nearest-only";

/// The name of the AS run whose entering pixels take the border texel's count
/// (`spvg::reproject::BorderCount::Texel`) instead of `beta_max`.
pub const BORDER_TEXEL: &str = "as-border-texel";

/// The name of the AS run with the TAA-guided update (docs/algorithms.md §8.4): each
/// frame's update takes the report's TAA history, reprojected and clamped against the
/// frame before its blend, as its guide.
pub const GUIDED: &str = "as-guided";

/// The fixed counts every scene also runs besides `fixed64`, for the equal-quality
/// figures: the fixed count that reaches AS's PSNR, and the fixed runs' PSNR at AS's mean
/// count, are interpolated in `log2(spp)` between the fixed runs that bracket them. AS
/// spends about 30 spp on every scene and matches fixed counts near 64, so the ladder is
/// 16, 32, 64 (a fixed8 run brackets nothing).
pub const EQUAL_QUALITY_FIXED: [u32; 2] = [16, 32];

/// One way of running a scene: the renderer's mode, the reprojection rule and the count
/// dilation radius of the adaptive component.
#[derive(Clone, Copy, Debug)]
pub struct Variant {
    /// Fixed count, AS with reprojection, or AS with the identity history.
    pub mode: AoMode,
    /// The reprojection rule (depth tolerance, border prior).
    pub reprojection: Reprojection<f32>,
    /// The count dilation radius.
    pub dilation: u32,
    /// Whether the depth test compares the reprojected depth (the AO consumer's default).
    pub reprojected_depth: bool,
    /// Whether the update takes the TAA guide ([`GUIDED`]).
    pub guided: bool,
}

impl Variant {
    /// The run's name: the mode's, or [`NO_REPROJECTED_DEPTH`] / [`NO_PRIOR`] /
    /// [`NEAREST_ONLY`] / [`BORDER_TEXEL`] / [`NO_DILATION`] for AS with the reprojected
    /// depth, the border prior, the footprint search, the entering pixels' `beta_max` or
    /// the dilation of `opts` switched off.
    #[must_use]
    pub fn name(&self, opts: &MotionOptions) -> String {
        if self.mode != AoMode::Adaptive {
            self.mode.name()
        } else if self.guided {
            GUIDED.into()
        } else if !self.reprojected_depth {
            NO_REPROJECTED_DEPTH.into()
        } else if !self.reprojection.border_prior() {
            NO_PRIOR.into()
        } else if !self.reprojection.footprint_search() {
            NEAREST_ONLY.into()
        } else if self.reprojection.border_count() == BorderCount::Texel {
            BORDER_TEXEL.into()
        } else if self.dilation == 0 && opts.dilation > 0 {
            NO_DILATION.into()
        } else {
            self.mode.name()
        }
    }
}

/// The ways `motion` is run. The default suite runs what the acceptance lines judge: `as`
/// (the component with reprojection), the fixed counts of [`EQUAL_QUALITY_FIXED`] and
/// `fixed64` (the quality bar) on every scene. [`MotionOptions::full`] adds
/// `as-identity` (the history read at the same pixel: the contrast the pan lines quote)
/// and [`GUIDED`] (the TAA-guided update) everywhere, and the knob rows, which no line judges: [`NO_PRIOR`] and [`BORDER_TEXEL`]
/// where pixels enter the frame (pans, rotation), [`NO_DILATION`] at rest and under the
/// fastest motions (static cameras, `pan8`, rotation), [`NEAREST_ONLY`] under sub-pixel
/// motion (rotation). The dolly also runs [`NO_REPROJECTED_DEPTH`] in both suites: its
/// acceptance line quotes it.
#[must_use]
pub fn variants(motion: Motion, opts: &MotionOptions) -> Vec<Variant> {
    let with = Reprojection::default();
    let d = opts.dilation;
    let variant = |mode, reprojection, dilation| Variant {
        mode,
        reprojection,
        dilation,
        reprojected_depth: true,
        guided: false,
    };
    let fixed = variant(AoMode::Fixed(64), with, 0);
    let adaptive = variant(AoMode::Adaptive, with, d);
    let dolly = matches!(motion, Motion::Dolly { .. });
    let without_reprojected_depth = Variant {
        reprojected_depth: false,
        ..adaptive
    };
    let mut v = EQUAL_QUALITY_FIXED
        .map(|n| variant(AoMode::Fixed(n), with, 0))
        .to_vec();
    v.extend([fixed, adaptive]);
    if dolly {
        v.push(without_reprojected_depth);
    }
    if !opts.full {
        return v;
    }
    v.push(variant(AoMode::Identity, with, d));
    // AS with the TAA-guided update, on every scene.
    v.push(Variant {
        guided: true,
        ..adaptive
    });
    // The border prior matters only where pixels enter the frame.
    if matches!(motion, Motion::Pan { .. } | Motion::Rotate { .. }) {
        v.push(variant(AoMode::Adaptive, with.with_border_prior(false), d));
        v.push(variant(
            AoMode::Adaptive,
            with.with_border_count(BorderCount::Texel),
            d,
        ));
    }
    // What the dilation buys and costs: at rest, and under the fastest motions.
    let hardest = matches!(motion, Motion::Static | Motion::Rotate { .. })
        || motion == Motion::Pan { speed: 8.0 };
    if d > 0 && hardest {
        v.push(variant(AoMode::Adaptive, with, 0));
    }
    // The footprint search matters only under sub-pixel motion.
    if matches!(motion, Motion::Rotate { .. }) {
        v.push(variant(
            AoMode::Adaptive,
            with.with_footprint_search(false),
            d,
        ));
    }
    v
}

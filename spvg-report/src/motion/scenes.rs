//! The motion scenes (pans, a rotation, a moving sphere, several moving objects, a dolly, their
//! static cameras) and the
//! ways of running each one ([`Variant`]): which runs the default suite holds and which
//! only [`MotionOptions::full`] adds.

use spvg::reproject::{BorderCount, Reprojection};

use super::options::MotionOptions;
use crate::wgpu_api::{AoMode, Motion};

/// The pan speeds of the full suite, px per frame along `+x`.
pub const PAN_SPEEDS: [f32; 4] = [1.0, 2.0, 4.0, 8.0];

/// The fastest pan (its entering columns are the hardest young histories, and its pixels
/// the furthest from their static camera's): the one pan of the default suite.
pub const FASTEST_PAN: Motion = Motion::Pan { speed: 8.0 };

/// The pans of the suite, compared with a static camera at the same size: every speed of
/// [`PAN_SPEEDS`] with `full`, else the fastest ([`FASTEST_PAN`]).
#[must_use]
pub fn pans(full: bool) -> Vec<Motion> {
    if full {
        PAN_SPEEDS.map(|speed| Motion::Pan { speed }).to_vec()
    } else {
        vec![FASTEST_PAN]
    }
}

/// The other moving scenes: a rotation of 2 degrees per frame (about 2 px per frame at the
/// frame's corners), the moving objects ([`OBJECTS`]) and a dolly of 3 world units per
/// frame (every depth changes by 3% or more per frame), compared with a static camera at
/// the same size.
#[must_use]
pub fn others() -> Vec<Motion> {
    vec![
        Motion::Rotate { degrees: 2.0 },
        OBJECTS[0],
        DOLLY,
        OBJECTS[1],
    ]
}

/// The scenes where objects move under a static camera: a sphere crossing at 3 px per
/// frame (`object3`), and three spheres and a 3 px bar crossing in different directions at
/// 5 px per frame (`objects5`, the harder one: faster, more, and thinner, disocclusions).
pub const OBJECTS: [Motion; 2] = [
    Motion::MovingSphere { speed: 3.0 },
    Motion::MovingObjects { speed: 5.0 },
];

/// The factors on `sigma0^2` of the extra AS runs on the moving-object scenes: AS at a
/// tighter target spends a little more, as the identity history does at the report's
/// target (it carries the counts that the history of whatever was at a pixel left there),
/// so the identity line can compare the two at no more samples.
pub const TIGHTER_TARGETS: [f32; 2] = [0.9, 0.8];

/// The name of AS at `scale` times the report's target variance ([`TIGHTER_TARGETS`]):
/// `as s0^2 x0.9`.
#[must_use]
pub fn tighter_name(scale: f32) -> String {
    format!("as s0^2 x{scale}")
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

/// The name of the AS run with the age-aware weight (`spvg::controller::young::age_weight`):
/// a young history updates with weight `max(eta, 1/age)`.
pub const AGE_WEIGHT: &str = "as-age-weight";

/// The name of the AS run with the spatial variance of young histories
/// (`spvg::controller::young`): a history at most [`SPATIAL_FRAMES`] frames old takes the
/// variance of its same-surface 3x3 neighbourhood.
pub const SPATIAL: &str = "as-spatial";

/// The name of the AS run without the depth-aware neighbour prior of the count dilation
/// (the component's default has it on: `spvg::dilation::dilated_count_with_prior`, a
/// pixel without history takes the mean count of its same-surface neighbours within
/// `spvg::dilation::PRIOR_RADIUS` that have history): a pixel without history keeps the
/// papers' `beta_min`.
pub const NO_NEIGHBOUR_PRIOR: &str = "as-no-neighbour-prior";

/// The name of the AS run with every young-history rule: the age-aware weight besides the
/// spatial variance and the neighbour prior of the default.
pub const YOUNG: &str = "as-young";

/// The largest history age that takes the spatial variance in the [`SPATIAL`] and
/// [`YOUNG`] runs: the core's default (`spvg::controller::young::SPATIAL_FRAMES`).
pub use spvg::controller::young::SPATIAL_FRAMES;

/// The name of the AS run without the spatial variance of young histories (the core's
/// default has it on): the papers' rule, where a seed keeps `sigma0^2`.
pub const NO_SPATIAL: &str = "as-no-spatial";

/// The scenes that run the young-history rows in the default suite: where histories are
/// young (the moving objects' uncovered pixels, the fastest pan's entering columns, the
/// rotation's sub-pixel disocclusions) and the static cameras they are judged against.
fn young_scene(motion: Motion) -> bool {
    matches!(
        motion,
        Motion::Static
            | Motion::MovingSphere { .. }
            | Motion::MovingObjects { .. }
            | Motion::Rotate { .. }
    ) || motion == FASTEST_PAN
}

/// The name of the AS run with the TAA-guided update (docs/algorithms.md §8.5): each
/// frame's update takes the report's TAA history, reprojected and clamped against the
/// frame before its blend, as its guide.
pub const GUIDED: &str = "as-guided";

/// The name of AS with the resolved-image count rule (docs/algorithms.md §8.7): fractional
/// counts with the floor [`RESOLVED_FLOOR`] under a count that aims at the image after the
/// report's TAA resolve (`SpvgConfig::resolve_weight` of the resolve's weight
/// `crate::taa::WEIGHT`), at the resolved-image target that AS's per-frame target leaves
/// after that resolve ([`resolved_target_scale`]). Each frame's estimate also takes the
/// weight the run's own resolve gave the previous frame per pixel
/// (`crate::taa::Taa::resolve_weights`: 1 where it rejected or clamped away the history),
/// as a renderer hands its resolve's weight to the AO effect
/// (`spvg_effects::ao::AoPass::set_resolve_weight`).
pub const RESOLVED: &str = "as-resolved";

/// The fractional floor of the [`RESOLVED`] run: 0.5, the one floor of 0, 0.125, 0.25 and
/// 0.5 that loses no scene's equal quality after TAA against AS but objects5's (one
/// default run each at this head: object3 1.87x against AS's 1.84x, where 0.25 gave
/// 1.13x and 0.125 0.83x; static 2.08x against 2.15x and 2.14x; objects5 0.95x against
/// 1.09x). Below it, the pixels a moving object leaves keep a stale history mean for
/// frames.
pub const RESOLVED_FLOOR: f32 = 0.5;

/// The factor on the report's `sigma0^2` of the [`RESOLVED`] run: `a / (2 - a)` at the
/// resolve's weight `a` (0.0526 at 0.1), the variance a resolve leaves of a frame aimed
/// at `sigma0^2`. Both runs then aim at the same resolved image; the rule spends its
/// samples where the resolve cannot average (young histories) and the floor lets the
/// rest go below `beta_min`.
#[must_use]
pub fn resolved_target_scale() -> f32 {
    spvg::controller::fractional::resolved_factor(crate::taa::WEIGHT)
}

/// The smaller fixed counts that the [`RESOLVED`] run's equal-quality figures need (it
/// spends a few samples where AS spends 30), read as prefixes of `fixed64` as
/// [`EQUAL_QUALITY_FIXED`] are.
pub const RESOLVED_FIXED: [u32; 2] = [4, 8];

/// The fixed counts every scene also runs besides `fixed64`, for the equal-quality
/// figures: the fixed count that reaches AS's PSNR, and the fixed runs' PSNR at AS's mean
/// count, are interpolated in `log2(spp)` between the fixed runs that bracket them. AS
/// spends about 30 spp on every scene and matches fixed counts near 64, so the ladder is
/// 16, 32, 64 (a fixed8 run brackets nothing). The fixed64 run yields them as prefixes of
/// its own samples ([`Variant::prefixes`]), so the ladder costs one run, not three.
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
    /// Fixed counts read from the same frames as prefixes of a fixed run's samples
    /// (`spvg_effects::ao::AoPass::set_prefix_counts`; 0: none): each is scored as its own
    /// fixed run, bit for bit what a separate run gives, for the cost of none.
    pub prefixes: [u32; 4],
    /// The age-aware weight (`spvg::SpvgConfigBuilder::age_weight`).
    pub age_weight: bool,
    /// The spatial variance's age limit (`spvg::SpvgConfigBuilder::spatial_variance`), 0
    /// off.
    pub spatial_variance: u32,
    /// The depth-aware neighbour prior (`AdaptivePass::set_neighbour_prior`).
    pub neighbour_prior: bool,
    /// Whether the update takes the TAA guide ([`GUIDED`]).
    pub guided: bool,
    /// The factor on the report's target variance `sigma0^2` (1: the report's;
    /// [`TIGHTER_TARGETS`]).
    pub target_scale: f32,
    /// The resolved-image rule with fractional counts ([`RESOLVED`]).
    pub resolved: bool,
}

impl Variant {
    /// The controller configuration of the run: `base` with the young-history rules of
    /// the variant.
    ///
    /// # Errors
    ///
    /// A rule the core rejects (not for the report's variants).
    pub fn config(
        &self,
        base: &spvg::SpvgConfig<f32>,
    ) -> Result<spvg::SpvgConfig<f32>, spvg::Error> {
        let b = base
            .to_builder()
            .target_variance(base.target_variance() * self.target_scale)
            .age_weight(self.age_weight)
            .spatial_variance(self.spatial_variance);
        if self.resolved {
            b.target_variance(base.target_variance() * resolved_target_scale())
                .fractional_floor(Some(RESOLVED_FLOOR))
                .resolve_weight(Some(crate::taa::WEIGHT))
                .build()
        } else {
            b.build()
        }
    }

    /// The run's name: the mode's, or [`YOUNG`] / [`NO_NEIGHBOUR_PRIOR`] / [`AGE_WEIGHT`] / [`SPATIAL`]
    /// for AS with young-history rules, or [`NO_REPROJECTED_DEPTH`] / [`NO_PRIOR`] /
    /// [`NEAREST_ONLY`] / [`BORDER_TEXEL`] / [`NO_DILATION`] for AS with the reprojected
    /// depth, the border prior, the footprint search, the entering pixels' `beta_max` or
    /// the dilation of `opts` switched off.
    #[must_use]
    pub fn name(&self, opts: &MotionOptions) -> String {
        if self.mode != AoMode::Adaptive {
            self.mode.name()
        } else if self.resolved {
            RESOLVED.into()
        } else if self.target_scale != 1.0 {
            tighter_name(self.target_scale)
        } else if self.guided {
            GUIDED.into()
        } else if self.age_weight && self.spatial_variance > 0 && self.neighbour_prior {
            YOUNG.into()
        } else if !self.neighbour_prior {
            NO_NEIGHBOUR_PRIOR.into()
        } else if self.age_weight {
            AGE_WEIGHT.into()
        } else if self.spatial_variance != opts.config.spatial_variance() {
            if self.spatial_variance == 0 {
                NO_SPATIAL.into()
            } else {
                SPATIAL.into()
            }
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

/// A run of `mode` with `reprojection` and `dilation`, every other rule at its default.
fn plain(
    opts: &MotionOptions,
    mode: AoMode,
    reprojection: Reprojection<f32>,
    dilation: u32,
) -> Variant {
    Variant {
        mode,
        reprojection,
        dilation,
        reprojected_depth: true,
        prefixes: [0; 4],
        age_weight: false,
        spatial_variance: opts.config.spatial_variance(),
        neighbour_prior: true,
        guided: false,
        target_scale: 1.0,
        resolved: false,
    }
}

/// The runs of every scene: `fixed64` carrying the ladder's smaller counts as prefixes
/// of its own samples ([`RESOLVED_FIXED`], [`EQUAL_QUALITY_FIXED`]), `as`, and
/// [`RESOLVED`] (judged after the TAA).
#[must_use]
pub fn core_variants(opts: &MotionOptions) -> Vec<Variant> {
    let with = Reprojection::default();
    let ladder = Variant {
        prefixes: [
            RESOLVED_FIXED[0],
            RESOLVED_FIXED[1],
            EQUAL_QUALITY_FIXED[0],
            EQUAL_QUALITY_FIXED[1],
        ],
        ..plain(opts, AoMode::Fixed(64), with, 0)
    };
    let adaptive = plain(opts, AoMode::Adaptive, with, opts.dilation);
    let resolved = Variant {
        resolved: true,
        ..adaptive
    };
    vec![ladder, adaptive, resolved]
}

/// The ways `motion` is run. The default suite runs what its acceptance lines judge:
/// `as` (the component with reprojection) and `fixed64` (the quality bar, carrying the
/// fixed counts of [`EQUAL_QUALITY_FIXED`] as prefixes) on every scene, and on the moving
/// objects ([`OBJECTS`]) `as-identity` (the history read at the same pixel: what the
/// reprojection and disocclusion lines compare with) and AS at the [`TIGHTER_TARGETS`].
/// [`MotionOptions::full`] adds `as-identity` and [`GUIDED`] (the TAA-guided update)
/// everywhere; the young-history rows where histories are young (the static cameras, the
/// fastest pan, the rotation, the moving objects): [`NO_NEIGHBOUR_PRIOR`] (the papers'
/// `beta_min` for a pixel without history), [`YOUNG`] (every young-history rule) and the
/// spatial variance switched ([`SPATIAL`] or [`NO_SPATIAL`]); and the knob rows, which no
/// line judges: [`NO_PRIOR`] and [`BORDER_TEXEL`] where pixels enter the frame (pans,
/// rotation), [`NO_DILATION`] at rest and under the fastest motions (static cameras,
/// `pan8`, rotation), [`NEAREST_ONLY`] under sub-pixel motion (rotation) and
/// [`NO_REPROJECTED_DEPTH`] on the dolly.
#[must_use]
pub fn variants(motion: Motion, opts: &MotionOptions) -> Vec<Variant> {
    let mut v = core_variants(opts);
    let with = Reprojection::default();
    let d = opts.dilation;
    let variant = |mode, reprojection, dilation| plain(opts, mode, reprojection, dilation);
    let adaptive = variant(AoMode::Adaptive, with, d);
    // The moving objects' identity history and AS's own quality-cost curve beside it:
    // their acceptance lines compare AS with it.
    let objects = OBJECTS.contains(&motion);
    if objects {
        v.push(variant(AoMode::Identity, with, d));
        for &target_scale in &TIGHTER_TARGETS {
            v.push(Variant {
                target_scale,
                ..adaptive
            });
        }
    }
    if !opts.full {
        return v;
    }
    if matches!(motion, Motion::Dolly { .. }) {
        v.push(Variant {
            reprojected_depth: false,
            ..adaptive
        });
    }
    // The young-history rules where histories are young, each switched alone and all
    // together.
    if young_scene(motion) {
        let base = opts.config.spatial_variance();
        for (age_weight, spatial_variance, neighbour_prior) in [
            (false, if base == 0 { SPATIAL_FRAMES } else { 0 }, true),
            (false, base, false),
            (true, base.max(1), true),
        ] {
            v.push(Variant {
                age_weight,
                spatial_variance,
                neighbour_prior,
                ..adaptive
            });
        }
    }
    if !objects {
        v.push(variant(AoMode::Identity, with, d));
    }
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
    let hardest = matches!(motion, Motion::Static | Motion::Rotate { .. }) || motion == FASTEST_PAN;
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

//! The motion section's results, as the runs produce them and the acceptance lines,
//! markdown and CSV read them: per-frame figures of each run, the baselines, the motion
//! bound and the GPU runs' checks against the twin.

use super::uncovered::AgeErrors;
use crate::equal_quality::{FixedPoint, FlickerPoint};
use crate::metrics::psnr_of_pairs;

/// Frames left out of the run means: the controller's warm-up from a cold history (every
/// mode and scene alike; the charts and `motion.csv` show every frame).
pub const WARM_UP: usize = 16;

/// Per-frame results of one scene through one mode.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MotionRun {
    /// Scene name (`static`, `pan4`, ...).
    pub scene: String,
    /// Mode name (`fixed64`, `as`, `as-identity`).
    pub mode: String,
    /// Mean samples per pixel, per frame.
    pub spp: Vec<f64>,
    /// PSNR of the AO against the reference, per frame (dB, peak 1; NaN where the frame is
    /// not scored).
    pub psnr: Vec<f64>,
    /// PSNR over the pixels whose surface point was on screen in this and the two previous
    /// frames (the steady part of the frame; the pixels entering the frame have no history
    /// of their own for their first frames).
    pub psnr_steady: Vec<f64>,
    /// PSNR of the AO after the TAA resolve ([`crate::taa`]), per frame (dB; NaN where
    /// the frame is not scored).
    pub psnr_taa: Vec<f64>,
    /// Relative MSE of the AO after the TAA resolve, per frame.
    pub relmse_taa: Vec<f64>,
    /// The part of the squared error after TAA that a sample count can fix, per frame: the
    /// mean over pixels of the variance across two independent seeds of the same run
    /// (`(a - b)^2 / 2` per pixel; NaN where the run had one seed or the frame is not
    /// scored). See [`split_taa`].
    pub var_taa: Vec<f64>,
    /// The part it cannot fix: the squared bias of the resolved image, the mean over
    /// pixels of `((a + b) / 2 - ref)^2 - (a - b)^2 / 4` (an unbiased estimate; the two
    /// parts sum to the seeds' mean squared error). See [`split_taa`].
    pub bias2_taa: Vec<f64>,
    /// Temporal instability of the resolved AO ([`crate::metrics::Flicker`]), per frame
    /// (NaN on a frame whose previous frame was not scored).
    pub flicker_taa: Vec<f64>,
    /// The count's step per pixel, per frame: the mean over pixels of `|n_t - n_(t-1)|`
    /// at the same pixel of the screen (NaN on frame 0).
    pub count_step: Vec<f64>,
    /// Per scored frame, what allocating samples per pixel saves against a fixed count at
    /// equal PSNR under independent samples at best: `[the variance-equalizing rule, any
    /// rule]` ([`allocation_bounds`]; NaN on unscored frames).
    pub allocation_bounds: Vec<[f64; 2]>,
    /// Moving-object scenes: mean spp of the pixels uncovered this frame (`None` where no
    /// pixel was).
    pub uncovered_spp: Vec<Option<f64>>,
    /// Moving-object scenes: mean spp of the steady pixels (no object in either frame).
    pub steady_spp: Vec<Option<f64>>,
    /// Moving-object scenes: fraction of the uncovered pixels at the maximum count.
    pub uncovered_at_max: Vec<Option<f64>>,
    /// Moving-object scenes: mean spp of the pixels showing a moving object now.
    pub object_spp: Vec<Option<f64>>,
    /// Moving-object scenes: per frame, the squared error and the samples of the steady
    /// pixels and of the uncovered ones by their age on screen ([`AgeErrors`]; all 0 on
    /// unscored frames), of the frame itself.
    pub uncovered_errors: Vec<AgeErrors>,
    /// The same after the TAA resolve (the image a player sees).
    pub uncovered_errors_taa: Vec<AgeErrors>,
}

impl MotionRun {
    /// A run of `scene` in `mode` with no frame yet.
    #[must_use]
    pub fn named(scene: impl Into<String>, mode: impl Into<String>) -> Self {
        Self {
            scene: scene.into(),
            mode: mode.into(),
            ..Self::default()
        }
    }

    /// Mean over the scored frames after [`WARM_UP`] (all frames of a shorter run) of the
    /// per-frame mean spp.
    #[must_use]
    pub fn mean_spp(&self) -> f64 {
        let scored: Vec<f64> = steady(&self.spp)
            .iter()
            .zip(steady(&self.psnr))
            .filter(|(_, p)| !p.is_nan())
            .map(|(s, _)| *s)
            .collect();
        if scored.is_empty() {
            mean(steady(&self.spp))
        } else {
            mean(&scored)
        }
    }

    /// Mean over the scored frames after [`WARM_UP`] of the per-frame PSNR.
    #[must_use]
    pub fn mean_psnr(&self) -> f64 {
        scored_mean(steady(&self.psnr))
    }

    /// Mean over the scored frames after [`WARM_UP`] of the PSNR after TAA.
    #[must_use]
    pub fn mean_psnr_taa(&self) -> f64 {
        scored_mean(steady(&self.psnr_taa))
    }

    /// Mean over the scored frames after [`WARM_UP`] of the variance after TAA
    /// ([`var_taa`](Self::var_taa)).
    #[must_use]
    pub fn mean_var_taa(&self) -> f64 {
        scored_mean(steady(&self.var_taa))
    }

    /// Mean over the scored frames after [`WARM_UP`] of the squared bias after TAA
    /// ([`bias2_taa`](Self::bias2_taa)).
    #[must_use]
    pub fn mean_bias2_taa(&self) -> f64 {
        scored_mean(steady(&self.bias2_taa))
    }

    /// The variance after TAA in decibels, `-10 log10(mean_var_taa)` (peak 1, as PSNR):
    /// what [`EqualQuality`](crate::equal_quality::EqualQuality) interpolates for equal
    /// quality at equal variance.
    #[must_use]
    pub fn var_db_taa(&self) -> f64 {
        -10.0 * self.mean_var_taa().log10()
    }

    /// Mean over the scored frames after [`WARM_UP`] of the relative MSE after TAA.
    #[must_use]
    pub fn mean_relmse_taa(&self) -> f64 {
        scored_mean(steady(&self.relmse_taa))
    }

    /// Mean over the frames after [`WARM_UP`] that have one of the instability after TAA
    /// (NaN when none has).
    #[must_use]
    pub fn mean_flicker_taa(&self) -> f64 {
        scored_mean(steady(&self.flicker_taa))
    }

    /// Mean over the frames after [`WARM_UP`] of the count's step per pixel
    /// ([`count_step`](Self::count_step); NaN when no frame has one).
    #[must_use]
    pub fn mean_count_step(&self) -> f64 {
        scored_mean(steady(&self.count_step))
    }

    /// Mean over the scored frames after [`WARM_UP`] of the [`allocation_bounds`].
    #[must_use]
    pub fn mean_allocation_bounds(&self) -> [f64; 2] {
        let b = steady(&self.allocation_bounds);
        [0, 1].map(|k| scored_mean(&b.iter().map(|x| x[k]).collect::<Vec<_>>()))
    }

    /// Mean over the scored frames after [`WARM_UP`] of the PSNR of the steady pixels.
    #[must_use]
    pub fn mean_psnr_steady(&self) -> f64 {
        scored_mean(steady(&self.psnr_steady))
    }

    /// The squared errors by age since uncovered pooled over the frames after
    /// [`WARM_UP`] (all frames of a shorter run): every pixel-frame weighs the same.
    #[must_use]
    pub fn pooled_uncovered_errors(&self) -> AgeErrors {
        AgeErrors::pooled(steady(&self.uncovered_errors))
    }

    /// [`pooled_uncovered_errors`](Self::pooled_uncovered_errors) after the TAA resolve.
    #[must_use]
    pub fn pooled_uncovered_errors_taa(&self) -> AgeErrors {
        AgeErrors::pooled(steady(&self.uncovered_errors_taa))
    }

    /// Whether the run has a fixed count (its mode is `fixedN`).
    #[must_use]
    pub fn is_fixed(&self) -> bool {
        self.mode.starts_with("fixed")
    }
}

/// One frame's after-TAA error split over two independent seeds `a` and `b` of the same
/// run against `reference`: `[variance, squared bias]`, means over pixels of
/// `(a - b)^2 / 2` and `((a + b) / 2 - ref)^2 - (a - b)^2 / 4`. With `m = (a + b) / 2`,
/// `((a - ref)^2 + (b - ref)^2) / 2 = (m - ref)^2 + (a - b)^2 / 4`, so the two parts sum to
/// the seeds' mean squared error exactly; each is an unbiased estimate of its part (the
/// squared bias can come out below 0 where it is small). NaN for images of other lengths
/// or none.
///
/// ```
/// use spvg_report::motion::data::split_taa;
/// // One pixel: seeds 0.4 and 0.6 around a reference of 0.4: variance 0.02, bias^2 0.01 - 0.01.
/// let [v, b] = split_taa(&[0.4], &[0.6], &[0.4]);
/// assert!((v - 0.02).abs() < 1e-7 && b.abs() < 1e-7);
/// ```
#[must_use]
pub fn split_taa(a: &[f32], b: &[f32], reference: &[f32]) -> [f64; 2] {
    if a.len() != b.len() || a.len() != reference.len() || a.is_empty() {
        return [f64::NAN; 2];
    }
    let (mut var, mut bias2) = (0.0_f64, 0.0_f64);
    for ((&a, &b), &r) in a.iter().zip(b).zip(reference) {
        let (a, b, r) = (f64::from(a), f64::from(b), f64::from(r));
        let d = a - b;
        let m = 0.5 * (a + b) - r;
        var += 0.5 * d * d;
        bias2 += m * m - 0.25 * d * d;
    }
    let n = a.len() as f64;
    [var / n, bias2 / n]
}

/// The frames after [`WARM_UP`] of a run longer than twice it, else every frame.
pub(crate) fn steady<T>(v: &[T]) -> &[T] {
    if v.len() > 2 * WARM_UP {
        &v[WARM_UP..]
    } else {
        v
    }
}

/// The mean of `v` (0 when empty).
#[must_use]
pub fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// The mean of the non-NaN values of `v` (NaN when there is none): the scored frames.
fn scored_mean(v: &[f64]) -> f64 {
    let (s, n) = v
        .iter()
        .filter(|x| !x.is_nan())
        .fold((0.0, 0_usize), |(s, n), x| (s + x, n + 1));
    if n == 0 { f64::NAN } else { s / n as f64 }
}

/// What allocating samples per pixel saves at best against a fixed count at equal PSNR
/// (equal mean squared error), for independent one-sample estimates of variance `v_i` at
/// the pixels of `reference` (an AO sample is 0 or 1: `v_i = p (1 - p)`, `p` the
/// reference), with exact variances and no floor or cap:
///
/// - `[0]`, the variance-equalizing rule (`n_i = v_i / sigma0^2`, SPVG's without its
///   clamps): every pixel of `v_i > 0` ends at `sigma0^2`, the converged ones at 0, so
///   the mean squared error is `f sigma0^2` (`f` the fraction with `v_i > 0`) for
///   `sum v_i / sigma0^2` samples, where a fixed count needs `1 / f` times as many;
/// - `[1]`, any rule: `mean(v) / mean(sqrt v)^2` (Cauchy-Schwarz; `n_i` in proportion to
///   `sqrt v_i` reaches it).
///
/// NaN where every pixel has converged.
///
/// ```
/// use spvg_report::motion::data::allocation_bounds;
/// // Half the pixels converged, half at p = 1/2: f = 1/2, mean(v) = 1/8, mean(sqrt v) = 1/4.
/// assert_eq!(allocation_bounds(&[0.0, 0.5, 1.0, 0.5]), [2.0, 2.0]);
/// // p = 1/2 and p = 0.1: the equalizing rule saves nothing, the best rule 1.06x.
/// let [eq, best] = allocation_bounds(&[0.5, 0.1]);
/// assert_eq!(eq, 1.0);
/// assert!((best - 0.34 / 2.0 / (0.4 * 0.4)).abs() < 1e-6);
/// ```
#[must_use]
pub fn allocation_bounds(reference: &[f32]) -> [f64; 2] {
    let (mut v, mut s, mut nonzero) = (0.0_f64, 0.0_f64, 0_usize);
    for &p in reference {
        let p = f64::from(p).clamp(0.0, 1.0);
        let var = p * (1.0 - p);
        v += var;
        s += var.sqrt();
        nonzero += usize::from(var > 0.0);
    }
    if nonzero == 0 {
        return [f64::NAN; 2];
    }
    let n = reference.len() as f64;
    [n / nonzero as f64, (v / n) / ((s / n) * (s / n))]
}

/// PSNR of AO values against their reference ([`psnr_of_pairs`]: peak 1, the AO's range).
#[must_use]
pub fn psnr(image: &[f32], reference: &[f32]) -> f64 {
    psnr_of_pairs(
        image
            .iter()
            .zip(reference)
            .map(|(a, b)| (f64::from(*a), f64::from(*b))),
    )
}

/// One frame of broken motion vectors (every vector `1e30` pixels, far beyond the motion
/// bound of `spvg::reproject`) on the static camera, AS: the mean spp of the frames
/// around it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionBound {
    /// The frame whose motion vectors are broken.
    pub frame: u32,
    /// Mean spp of the frame before it.
    pub before: f64,
    /// Mean spp of the broken frame (every pixel disoccluded).
    pub broken: f64,
    /// Mean spp of the frame after it.
    pub after: f64,
}

/// A camera held still at some poses of a moving camera: AS and `fixed64`, frame by frame
/// after AS's warm-up.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StillBaseline {
    /// The moving scene's name (`pan8`).
    pub scene: String,
    /// The moving scene's frames whose poses were held.
    pub frames: Vec<u32>,
    /// Per held pose: AS's mean spp over the frames after its warm-up.
    pub spp: Vec<f64>,
    /// Per held pose: AS's mean PSNR over the same frames, against the moving scene's
    /// reference of that frame (the same view).
    pub psnr: Vec<f64>,
    /// Per held pose: `fixed64`'s mean PSNR over the same frames (no history: what the
    /// pose's content gives a fixed count).
    pub fixed_psnr: Vec<f64>,
}

impl StillBaseline {
    /// `run`'s mean spp and PSNR over the frames whose poses were held (NaN where `run`
    /// is shorter), beside this baseline's AS means: `((run spp, run PSNR), (spp, PSNR))`.
    #[must_use]
    pub fn compare(&self, run: &MotionRun) -> ((f64, f64), (f64, f64)) {
        let at = |v: &[f64]| -> Vec<f64> {
            self.frames
                .iter()
                .map(|&t| v.get(t as usize).copied().unwrap_or(f64::NAN))
                .collect()
        };
        (
            (mean(&at(&run.spp)), mean(&at(&run.psnr))),
            (mean(&self.spp), mean(&self.psnr)),
        )
    }
}

/// How a GPU run was held against its CPU twin ([`crate::motion::render`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TwinCheck {
    /// The scene the run belongs to (a baseline's or bound's under its moving scene's or
    /// static camera's name).
    pub scene: String,
    /// The run's name.
    pub run: String,
    /// Frames compared.
    pub frames: u32,
    /// Whether the run has the adaptive component (counts and history texels compared on
    /// every pixel).
    pub adaptive: bool,
    /// Pixel-frames of the lattice whose AO value (and prefix estimates) were compared.
    pub lattice: u64,
    /// The first frame that differs, if any (the run is then corrupt and not scored).
    pub corrupt: Option<Difference>,
    /// Frames that differ.
    pub frames_differing: u32,
}

/// Where a GPU frame differs from its twin.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Difference {
    /// The frame.
    pub frame: u32,
    /// What differs first: `count`, `history`, `value` or `prefix`.
    pub what: &'static str,
    /// Pixels of that frame where it differs (of those compared).
    pub pixels: usize,
    /// The first such pixel.
    pub first: [u32; 2],
    /// Those pixels by `x mod 8` (the SIMD lane of a software rasterizer's 8-wide rows).
    pub lanes: [usize; 8],
}

/// The whole motion section: every run, the baselines, the motion bound, the GPU runs'
/// checks against the twin, and the acceptance lines.
#[derive(Clone, Debug, Default)]
pub struct MotionReport {
    /// Every run that was scored (not the corrupt ones).
    pub runs: Vec<MotionRun>,
    /// The motion bound on the static camera ([`super::bound::motion_bound_of`]), where the
    /// run was long enough.
    pub motion_bound: Option<MotionBound>,
    /// The motion bound of the young-history rows on the static camera, by run name.
    pub motion_bound_young: Vec<(String, MotionBound)>,
    /// The moving cameras held still at their own poses (the young-history lines'
    /// baseline).
    pub still: Vec<StillBaseline>,
    /// Every GPU run's check against its twin (empty on the CPU twin).
    pub twin_checks: Vec<TwinCheck>,
}

impl MotionReport {
    /// The run `mode` of `scene`, if it ran and was scored.
    #[must_use]
    pub fn find(&self, scene: &str, mode: &str) -> Option<&MotionRun> {
        self.runs
            .iter()
            .find(|r| r.scene == scene && r.mode == mode)
    }

    /// The fixed runs of `scene` as (PSNR, instability) points after TAA.
    #[must_use]
    pub fn fixed_flicker_points(&self, scene: &str) -> Vec<FlickerPoint> {
        self.runs
            .iter()
            .filter(|r| r.scene == scene && r.is_fixed())
            .map(|r| FlickerPoint {
                psnr: r.mean_psnr_taa(),
                flicker: r.mean_flicker_taa(),
            })
            .collect()
    }

    /// The fixed runs of `scene` as (mean spp, variance after TAA in dB) points
    /// ([`MotionRun::var_db_taa`]): equal quality at equal variance.
    #[must_use]
    pub fn fixed_variance_points(&self, scene: &str) -> Vec<FixedPoint> {
        self.runs
            .iter()
            .filter(|r| r.scene == scene && r.is_fixed())
            .map(|r| FixedPoint {
                spp: r.mean_spp(),
                psnr: r.var_db_taa(),
            })
            .collect()
    }

    /// The fixed runs of `scene` as (mean spp, PSNR) points: single-frame, or after TAA.
    #[must_use]
    pub fn fixed_points(&self, scene: &str, taa: bool) -> Vec<FixedPoint> {
        self.runs
            .iter()
            .filter(|r| r.scene == scene && r.is_fixed())
            .map(|r| FixedPoint {
                spp: r.mean_spp(),
                psnr: if taa {
                    r.mean_psnr_taa()
                } else {
                    r.mean_psnr()
                },
            })
            .collect()
    }
}

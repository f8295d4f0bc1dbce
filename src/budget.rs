//! A frame-level sample budget (docs/algorithms.md §8.2): a governor that sets each
//! frame's global target variance `sigma0^2` so the frame's total sample count tracks a
//! budget, while the controller keeps allocating samples between pixels by their variance.
//!
//! # Model
//!
//! For the SPVG estimate (docs/algorithms.md §2.1) the raw count of a pixel is linear in
//! `1 / sigma0^2`: with `r = var / sigma0^2`,
//! `n_hat = (1 + kappa (k - 1)) var nbar / sigma0^2 - kappa (k - 1) nbar`. Summed over the
//! pixels a frame will estimate, before the budget clamp and rounding, the total is
//!
//! ```text
//! N_hat(sigma0^2) = scaled / sigma0^2 - offset + fixed
//! ```
//!
//! with `scaled = sum a var nbar` (`a = 1 + kappa (k - 1)`), `offset = sum b nbar`
//! (`b = kappa (k - 1)`), and `fixed` the counts that do not depend on the target
//! (disoccluded pixels take `min_samples`, a `Fixed(n)` policy takes `n`). These three
//! sums are one reduction over the history the frame reads ([`FrameDemand`]).
//!
//! That total ignores the per-pixel clamp to `[min_samples, max_samples]` and the
//! rounding. The count a pixel really takes is `n_i(sigma0^2) = ceil(clamp(n_hat_i))`,
//! non-increasing in `sigma0^2`, and where many pixels sit at a bound the clamped total
//! `N(sigma0^2) = sum_i n_i(sigma0^2)` is far from `N_hat`. The [`DemandCurve`] samples
//! `N` itself: the reduction evaluates each pixel's count ([`count_at`], the estimate
//! with the target replaced) at [`CURVE_POINTS`] candidate targets around the current
//! feed-forward target ([`Governor::curve_targets`]) and sums each.
//!
//! The [`Governor`] combines:
//! - **feed-forward** ([`Governor::plan_curve`]): the target at which the clamped total
//!   `N` crosses the budget, interpolated linearly in `1 / sigma0^2` between the two
//!   candidates that bracket it, from the demand of the history the next frame reads, so
//!   a sudden change of lighting moves the target in the same frame
//!   ([`Governor::plan`] is the unclamped form, `base = scaled / (B - fixed + offset)`);
//! - **integral feedback on `log sigma0^2`** ([`Governor::observe`]): the interpolation,
//!   a stale or approximate demand and noise make the real total differ from the
//!   planned one; a correction `c` integrates `ln(N / B)` of the measured totals with
//!   gain `g`, and the target is `clamp(base e^c, min_target, max_target)`.
//!
//! The total is roughly proportional to `1 / sigma0^2`, so `ln N = ln K - ln sigma0^2`:
//! the loop is linear in `log sigma0^2` with plant gain -1, and an integral gain `g`
//! with a feedback latency of `d` frames has characteristic polynomial
//! `z^d - z^(d-1) + g`. With `d = 1` the pole is `1 - g`; with `d = 2` (CPU read-back)
//! the poles are `(1 +- sqrt(1 - 4 g)) / 2`, critically damped at `g = 1/4`, oscillating
//! above, unstable from `g = 1`. The default `g = 1/4` is therefore free of overshoot at
//! both latencies.
//!
//! # Latency and the GPU form
//!
//! Per frame `t`, in this order:
//! 1. `plan_curve(curve(H_{t-1}))` sets `sigma0^2_t` from the history frame `t` reads
//!    (the curve at the candidates [`Governor::curve_targets`] gave before the call);
//! 2. the estimate, sampling and update passes run with `sigma0^2_t`;
//! 3. `observe(N_t)` with the frame's total count.
//!
//! On the CPU all three happen in the frame (feedback latency 1: `N_t` first acts on
//! `sigma0^2_{t+1}`). On a GPU, the curve and the total are reductions (the per-pixel
//! counts [`DemandCurve::pixel_counts`] over the history after the update pass, and the
//! counts of the frame); a one-invocation pass then runs `observe` and `plan_curve` and writes
//! `sigma0^2_{t+1}` to the buffer the next estimate pass reads: no CPU read-back, the
//! same one frame of feedback latency, and a feed-forward without latency. The
//! `spvg-wgpu` reduction (`spvg_wgpu::sss::reduce`) reads the per-workgroup sums back with
//! frame `t`'s results and plans frame `t + 1` on the CPU before submitting it: the same
//! latencies, at the cost of a round trip per frame. A renderer that reads the sums back
//! one frame late instead (`d = 2`, and a feed-forward one frame stale): the default
//! gain still does not overshoot, but a stale feed-forward tracks fast lighting changes
//! less well (measured in `tests/budget.rs`).
//!
//! # Stored variances and a moving target
//!
//! The texel layouts store the variance divided by a power-of-two scale chosen from a
//! target (`spvg::texel::TexelEncoding`). Under the governor, build that encoding once
//! (from the initial or a typical target) and keep it while the controller's target
//! moves: the frame functions take the configuration and the encoding separately, so
//! `estimate_frame(&config_with_new_target, &fixed_encoding, ..)` reads the stored
//! variances correctly. Rebuilding the encoding from each frame's target would
//! reinterpret the stored variances whenever the target crosses a power of two. (The
//! `spvg-wgpu` pass does so with `PassConfig::encoding_target`.)
//!
//! # Non-finite input
//!
//! A demand with a non-finite or negative sum, or a zero `scaled` sum (all variances 0:
//! every pixel takes `min_samples` whatever the target), keeps the previous feed-forward
//! target; so does a curve whose targets are not finite, positive and non-decreasing or
//! whose totals are not finite and non-negative. A non-finite, zero or negative total is ignored by `observe` (it returns
//! `false`). The state is never NaN or infinite, and the target always lies in
//! `[min_target, max_target]`.
//!
//! # Examples
//!
//! ```
//! use spvg::budget::{BudgetConfig, DemandCurve, FrameDemand, Governor};
//! use spvg::{SpvgConfig, SpvgHistory};
//!
//! let pixels = [
//!     SpvgHistory { mean: 1.0_f64, variance: 4e-3, mean_count: 20.0 },
//!     SpvgHistory { mean: 1.0, variance: 1e-3, mean_count: 10.0 },
//! ];
//! let controller = SpvgConfig::<f64>::builder().kappa(0.0).build()?;
//! let budget = BudgetConfig::builder(48.0).build()?;
//! let mut governor = Governor::new(budget, 1e-4)?;
//! // Reduce the demand of the histories the frame will read, then plan its target.
//! let demand = pixels
//!     .iter()
//!     .map(|h| FrameDemand::pixel(&controller, h, 1.0, true))
//!     .fold(FrameDemand::default(), |a, b| a + b);
//! let target = governor.plan(&demand);
//! // kappa = 0: the target puts (4e-3 * 20 + 1e-3 * 10) / target on the budget of 48.
//! assert!((target - 0.09 / 48.0).abs() < 1e-12);
//! let config = controller.to_builder().target_variance(target).build()?;
//! let total: u32 = pixels.iter().map(|h| config.estimate(h, 1.0)).sum();
//! assert!(governor.observe(f64::from(total)));
//!
//! // The clamp-aware feed-forward: the pixels' counts at the governor's candidate
//! // targets, summed, and the target where that total crosses the budget. Here the
//! // second pixel takes the minimum of 8 samples at every candidate, so the first must
//! // take 40: at 2 / 40 = 0.05. The unclamped model puts 2.005 / 48 = 0.042 on the
//! // budget, where the clamped counts are 48 + 8 = 56.
//! let pixels = [
//!     SpvgHistory { mean: 1.0_f64, variance: 1e-1, mean_count: 20.0 },
//!     SpvgHistory { mean: 1.0, variance: 1e-3, mean_count: 5.0 },
//! ];
//! let mut governor = Governor::new(budget, 0.04)?;
//! let curve = DemandCurve::from_pixels(
//!     &controller,
//!     governor.curve_targets(),
//!     pixels.iter().map(|h| (h, 1.0, true)),
//! );
//! let target = governor.plan_curve(&curve);
//! assert!((target - 0.05).abs() < 1e-3, "{target}");
//! let config = controller.to_builder().target_variance(target).build()?;
//! let counts: Vec<u32> = pixels.iter().map(|h| config.estimate(h, 1.0)).collect();
//! assert_eq!(counts[1], 8);
//! assert!(counts[0].abs_diff(40) <= 1, "{counts:?}"); // the ceiling of 2 / target
//! # Ok::<(), spvg::Error>(())
//! ```

use core::ops::Add;

use num_traits::Float;

use crate::Error;
use crate::controller::{CountPolicy, SpvgConfig, SpvgHistory, rules};
use crate::stats::saturate;

/// Default bounds of the target, the controller's supported range of `sigma0^2`.
mod defaults {
    pub(super) const MIN_TARGET: f64 = 1e-8;
    pub(super) const MAX_TARGET: f64 = 1e2;
    pub(super) const GAIN: f64 = 0.25;
}

#[inline]
fn widen<T: Float>(v: T) -> f64 {
    v.to_f64().unwrap_or(f64::NAN)
}

/// Parameters of the [`Governor`], validated at construction.
///
/// | field | meaning | valid range | default |
/// |---|---|---|---|
/// | `budget` | `B`, the target total sample count per frame | finite, `> 0` | (required) |
/// | `gain` | `g`, integral gain of the feedback on `log sigma0^2` | `(0, 1]` | 0.25 |
/// | `min_target` | smallest `sigma0^2` the governor sets | finite, `> 0`, `1 / min_target` finite | 1e-8 |
/// | `max_target` | largest `sigma0^2` the governor sets | finite, `>= min_target` | 1e2 |
///
/// # Examples
///
/// ```
/// use spvg::budget::BudgetConfig;
/// let c = BudgetConfig::<f32>::builder(16.0 * 1920.0 * 1080.0).gain(0.5).build().unwrap();
/// assert_eq!(c.gain(), 0.5);
/// let err = BudgetConfig::<f32>::builder(-1.0).build().unwrap_err();
/// assert!(err.to_string().contains("budget"));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BudgetConfig<T> {
    budget: T,
    gain: T,
    min_target: T,
    max_target: T,
    // Derived: ln(min_target), ln(max_target), the bound of the correction.
    max_correction: T,
}

/// Builder of [`BudgetConfig`]; [`build`](Self::build) validates every field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BudgetConfigBuilder<T> {
    budget: T,
    gain: T,
    min_target: T,
    max_target: T,
}

impl<T: Float> BudgetConfig<T> {
    /// A builder with the given per-frame budget (total samples) and the defaults of the
    /// other fields (see the table on [`BudgetConfig`]).
    #[must_use]
    pub fn builder(budget: T) -> BudgetConfigBuilder<T> {
        let c = |v: f64| T::from(v).unwrap_or_else(T::one);
        BudgetConfigBuilder {
            budget,
            gain: c(defaults::GAIN),
            min_target: c(defaults::MIN_TARGET),
            max_target: c(defaults::MAX_TARGET),
        }
    }

    /// The per-frame budget `B` (total samples).
    #[inline]
    #[must_use]
    pub fn budget(&self) -> T {
        self.budget
    }

    /// The integral gain `g`.
    #[inline]
    #[must_use]
    pub fn gain(&self) -> T {
        self.gain
    }

    /// The smallest target `sigma0^2` the governor sets.
    #[inline]
    #[must_use]
    pub fn min_target(&self) -> T {
        self.min_target
    }

    /// The largest target `sigma0^2` the governor sets.
    #[inline]
    #[must_use]
    pub fn max_target(&self) -> T {
        self.max_target
    }
}

impl<T: Float> BudgetConfigBuilder<T> {
    /// The per-frame budget `B` (total samples), finite and positive.
    #[must_use]
    pub fn budget(mut self, budget: T) -> Self {
        self.budget = budget;
        self
    }

    /// The integral gain `g` in `(0, 1]`.
    #[must_use]
    pub fn gain(mut self, gain: T) -> Self {
        self.gain = gain;
        self
    }

    /// The range `[min_target, max_target]` of the target `sigma0^2`.
    #[must_use]
    pub fn target_range(mut self, min_target: T, max_target: T) -> Self {
        self.min_target = min_target;
        self.max_target = max_target;
        self
    }

    /// Validates every field.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming the field (`budget`, `gain`, `min_target`,
    /// `max_target`) when it is out of range or not finite;
    /// [`Error::InconsistentParameters`] when `min_target > max_target`.
    pub fn build(self) -> Result<BudgetConfig<T>, Error> {
        if !(self.budget.is_finite() && self.budget > T::zero()) {
            return Err(Error::invalid(
                "budget",
                widen(self.budget),
                "must be finite and > 0",
            ));
        }
        if !(self.gain > T::zero() && self.gain <= T::one()) {
            return Err(Error::invalid(
                "gain",
                widen(self.gain),
                "must be in (0, 1]",
            ));
        }
        let min = self.min_target;
        if !(min.is_finite() && min > T::zero() && (T::one() / min).is_finite()) {
            return Err(Error::invalid(
                "min_target",
                widen(min),
                "must be finite and > 0 with a finite reciprocal",
            ));
        }
        let max = self.max_target;
        if !max.is_finite() {
            return Err(Error::invalid("max_target", widen(max), "must be finite"));
        }
        if min > max {
            return Err(Error::InconsistentParameters {
                names: "min_target, max_target",
                expected: "min_target <= max_target",
            });
        }
        // The correction never needs to move the target by more than the whole range.
        let max_correction = (max / min).ln();
        Ok(BudgetConfig {
            budget: self.budget,
            gain: self.gain,
            min_target: min,
            max_target: max,
            max_correction,
        })
    }
}

/// The demand of a frame: the three sums that make its unclamped total a function of the
/// target, `N_hat(sigma0^2) = scaled / sigma0^2 - offset + fixed` (see the
/// [module docs](self)). One reduction over the history the frame reads: map each pixel
/// with [`pixel`](Self::pixel), sum with `+`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameDemand<T> {
    /// `sum a var nbar`, the part of the total proportional to `1 / sigma0^2`.
    pub scaled: T,
    /// `sum b nbar`, the part of the SPVG correction that does not scale with the target.
    pub offset: T,
    /// The counts that do not depend on the target.
    pub fixed: T,
}

impl<T: Float> Add for FrameDemand<T> {
    type Output = Self;

    /// Sums each field (saturating at the largest finite value).
    #[inline]
    fn add(self, other: Self) -> Self {
        Self {
            scaled: saturate(self.scaled + other.scaled),
            offset: saturate(self.offset + other.offset),
            fixed: saturate(self.fixed + other.fixed),
        }
    }
}

impl<T: Float> FrameDemand<T> {
    /// One pixel's terms, for the history `history` that the next estimate reads with
    /// validity `history_valid` and distant energy ratio `gamma`:
    /// - nothing when the pixel takes no distant samples
    ///   ([`SpvgConfig::samples_distant`]);
    /// - `fixed = n` under [`CountPolicy::Fixed`]`(n)`, `fixed = min_samples` when the
    ///   history is invalid;
    /// - otherwise, with `var` and `nbar` read as the estimate reads them
    ///   ([`rules::read_non_negative`]: NaN and values not `> 0` read as 0, `+inf` as the
    ///   largest finite value): `Spvg` gives `scaled = a var nbar`, `offset = b nbar`
    ///   (`a = 1 + kappa (k - 1)`, `b = kappa (k - 1)`), `TwoPhase` gives
    ///   `scaled = var nbar`, `UnrealClamp` gives `scaled = var`.
    ///
    /// Products saturate at the largest finite value.
    #[must_use]
    pub fn pixel(
        config: &SpvgConfig<T>,
        history: &SpvgHistory<T>,
        gamma: T,
        history_valid: bool,
    ) -> Self {
        let zero = T::zero();
        if !config.samples_distant(gamma) {
            return Self::default_zero();
        }
        let fixed = |n: T| Self {
            scaled: zero,
            offset: zero,
            fixed: n,
        };
        if let CountPolicy::Fixed(n) = config.policy() {
            return fixed(T::from(n).map_or(T::max_value(), saturate));
        }
        if !history_valid {
            return fixed(config.min_samples_f());
        }
        let (var, nbar) = (
            rules::read_non_negative(history.variance),
            rules::read_non_negative(history.mean_count),
        );
        match config.policy() {
            CountPolicy::Spvg => {
                let b = config.kappa() * config.k_minus_1();
                Self {
                    scaled: saturate(saturate((T::one() + b) * var) * nbar),
                    offset: saturate(b * nbar),
                    fixed: zero,
                }
            }
            CountPolicy::TwoPhase => Self {
                scaled: saturate(var * nbar),
                offset: zero,
                fixed: zero,
            },
            CountPolicy::UnrealClamp | CountPolicy::Fixed(_) => Self {
                scaled: var,
                offset: zero,
                fixed: zero,
            },
        }
    }

    /// All sums zero (`Default` for any `Float`).
    fn default_zero() -> Self {
        Self {
            scaled: T::zero(),
            offset: T::zero(),
            fixed: T::zero(),
        }
    }

    /// The unclamped total `scaled / target - offset + fixed` at a target (before the
    /// budget clamp and rounding of each pixel).
    #[must_use]
    pub fn unclamped_total(&self, target: T) -> T {
        self.scaled / target - self.offset + self.fixed
    }
}

/// The number of candidate targets of a [`DemandCurve`].
pub const CURVE_POINTS: usize = 16;

/// The candidate targets span `2^(-CURVE_HALF_OCTAVES / 2)` to
/// `2^((CURVE_POINTS - 1 - CURVE_HALF_OCTAVES) / 2)` times the centre: a factor 16 below
/// and 11.3 above, in steps of `sqrt 2`.
const CURVE_HALF_OCTAVES: usize = 8;

/// The count a pixel takes at the target `target`: exactly
/// [`SpvgConfig::estimate_with_validity`] of `config` with its target variance replaced
/// by `target` (0 under the zero-sample rule, `n` under [`CountPolicy::Fixed`]`(n)`,
/// `min_samples` for an invalid history, else the rounded, clamped raw count of the
/// history read as texel decode reads it, the damped correction included). A `target`
/// not `> 0` (NaN included) reads as the smallest positive normal value of `T`.
///
/// Every count is non-increasing in `target` (for `target > 0`): `var / target` is, and
/// every later step of the estimate is non-decreasing in `r`.
///
/// # Examples
///
/// ```
/// use spvg::budget::count_at;
/// use spvg::{SpvgConfig, SpvgHistory};
/// let c = SpvgConfig::<f32>::builder().kappa(0.0).build().unwrap(); // budget [8, 64]
/// let h = SpvgHistory { mean: 1.0, variance: 1e-3, mean_count: 20.0 };
/// assert_eq!(count_at(&c, 1e-3, &h, 1.0, true), 20); // r = 1
/// assert_eq!(count_at(&c, 2e-3, &h, 1.0, true), 10);
/// assert_eq!(count_at(&c, 1e-4, &h, 1.0, true), 64); // clamped
/// assert_eq!(count_at(&c, 1e-4, &h, 1.0, false), 8); // disoccluded
/// ```
#[inline]
#[must_use]
pub fn count_at<T: Float>(
    config: &SpvgConfig<T>,
    target: T,
    history: &SpvgHistory<T>,
    gamma: T,
    history_valid: bool,
) -> u32 {
    if !config.samples_distant(gamma) {
        return 0;
    }
    if let CountPolicy::Fixed(n) = config.policy() {
        return n;
    }
    let h = if history_valid {
        rules::read_history(history)
    } else {
        SpvgHistory {
            mean: T::zero(),
            variance: T::zero(),
            mean_count: T::zero(),
        }
    };
    let mut u = rules::EstimateUniforms::new(config);
    u.target = if target > T::zero() {
        target
    } else {
        T::min_positive_value()
    };
    rules::round_count(
        &rules::Budget::new(config),
        rules::raw_count(&u, h.variance, h.mean_count),
    )
}

/// The clamped demand of a frame: at each of [`CURVE_POINTS`] candidate targets
/// (non-decreasing), the total count the frame's pixels take there (see the
/// [module docs](self)). One reduction over the history the frame reads: each pixel
/// contributes [`count_at`] at every candidate ([`DemandCurve::pixel_counts`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DemandCurve<T> {
    /// The candidate targets `sigma0^2`, non-decreasing (as the reduction used them).
    pub targets: [T; CURVE_POINTS],
    /// The frame's total count at each candidate target (non-increasing).
    pub totals: [T; CURVE_POINTS],
}

impl<T: Float> DemandCurve<T> {
    /// One pixel's counts at every candidate target, `count_at(config, targets[j], ..)`.
    #[must_use]
    pub fn pixel_counts(
        config: &SpvgConfig<T>,
        targets: &[T; CURVE_POINTS],
        history: &SpvgHistory<T>,
        gamma: T,
        history_valid: bool,
    ) -> [u32; CURVE_POINTS] {
        targets.map(|t| count_at(config, t, history, gamma, history_valid))
    }

    /// The curve of a set of pixels `(history, gamma, valid)`, summed in `T`.
    #[must_use]
    pub fn from_pixels<'a>(
        config: &SpvgConfig<T>,
        targets: [T; CURVE_POINTS],
        pixels: impl IntoIterator<Item = (&'a SpvgHistory<T>, T, bool)>,
    ) -> Self
    where
        T: 'a,
    {
        let mut totals = [T::zero(); CURVE_POINTS];
        for (h, gamma, valid) in pixels {
            let n = Self::pixel_counts(config, &targets, h, gamma, valid);
            for (s, c) in totals.iter_mut().zip(n) {
                *s = saturate(*s + rules::count_value(c));
            }
        }
        Self { targets, totals }
    }

    /// The total at `target`: the totals interpolated linearly in `1 / target` between
    /// the two candidates around it, the end value outside the candidates' range (the
    /// feed-forward's model of the clamped total `N`). NaN when the curve is not usable
    /// (see [`Governor::plan_curve`]).
    #[must_use]
    pub fn total_at(&self, target: T) -> T {
        if !self.usable() || target.is_nan() || target <= T::zero() {
            return T::nan();
        }
        let (ts, ns) = (&self.targets, &self.totals);
        if target <= ts[0] {
            return ns[0];
        }
        for j in 1..CURVE_POINTS {
            if target <= ts[j] {
                let (x0, x1, x) = (ts[j - 1].recip(), ts[j].recip(), target.recip());
                let w = if x0 > x1 {
                    (x - x1) / (x0 - x1)
                } else {
                    T::one()
                };
                return ns[j] + w * (ns[j - 1] - ns[j]);
            }
        }
        ns[CURVE_POINTS - 1]
    }

    /// Targets finite, positive and non-decreasing; totals finite and non-negative.
    fn usable(&self) -> bool {
        let zero = T::zero();
        self.targets
            .iter()
            .all(|t| t.is_finite() && *t > zero && t.recip().is_finite())
            && self.totals.iter().all(|n| n.is_finite() && *n >= zero)
            && self.targets.windows(2).all(|w| w[0] <= w[1])
    }
}

/// Which bound the last target was clamped to (for the anti-windup).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pinned {
    No,
    Low,
    High,
}

/// The frame-level budget governor (see the [module docs](self)): sets each frame's
/// `sigma0^2` from the frame's demand (feed-forward) and the measured totals (integral
/// feedback on `log sigma0^2` with anti-windup), within `[min_target, max_target]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Governor<T> {
    config: BudgetConfig<T>,
    /// Feed-forward target (the initial target until `plan` sees a usable demand).
    base: T,
    /// Integral correction `c` on `ln sigma0^2`, within `+-ln(max_target / min_target)`.
    correction: T,
    /// The current target `clamp(base e^c, min_target, max_target)`.
    target: T,
    pinned: Pinned,
}

impl<T: Float> Governor<T> {
    /// A governor starting at `initial_target`.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `initial_target` when it is not within
    /// `[min_target, max_target]` (NaN included).
    pub fn new(config: BudgetConfig<T>, initial_target: T) -> Result<Self, Error> {
        if !(initial_target >= config.min_target && initial_target <= config.max_target) {
            return Err(Error::invalid(
                "initial_target",
                widen(initial_target),
                "must be within [min_target, max_target]",
            ));
        }
        let mut g = Self {
            config,
            base: initial_target,
            correction: T::zero(),
            target: initial_target,
            pinned: Pinned::No,
        };
        g.retarget();
        Ok(g)
    }

    /// The configuration.
    #[inline]
    #[must_use]
    pub fn config(&self) -> &BudgetConfig<T> {
        &self.config
    }

    /// The current target `sigma0^2` (for the next frame to estimate).
    #[inline]
    #[must_use]
    pub fn target(&self) -> T {
        self.target
    }

    /// The integral correction `c` (`ln` of the factor applied to the feed-forward
    /// target).
    #[inline]
    #[must_use]
    pub fn correction(&self) -> T {
        self.correction
    }

    fn retarget(&mut self) {
        let t = self.base * self.correction.exp();
        let (min, max) = (self.config.min_target, self.config.max_target);
        // `base` and `e^c` are finite and positive: `t` is positive, possibly `+inf` or 0.
        (self.target, self.pinned) = if t < min {
            (min, Pinned::Low)
        } else if t > max {
            (max, Pinned::High)
        } else {
            (t, Pinned::No)
        };
    }

    /// Feed-forward: sets and returns the target for the frame that reads the history
    /// whose demand is `demand`, `clamp(base e^c, min_target, max_target)` with
    /// `base = scaled / (budget - fixed + offset)` (`max_target` when the budget does not
    /// cover the fixed counts).
    ///
    /// A demand with a non-finite or negative sum, or `scaled == 0`, keeps the previous
    /// feed-forward target.
    pub fn plan(&mut self, demand: &FrameDemand<T>) -> T {
        let zero = T::zero();
        let usable = |v: T| v.is_finite() && v >= zero;
        if usable(demand.scaled)
            && usable(demand.offset)
            && usable(demand.fixed)
            && demand.scaled > zero
        {
            let room = self.config.budget - demand.fixed + demand.offset;
            let base = if room > zero {
                demand.scaled / room
            } else {
                self.config.max_target
            };
            // An overflow or underflow of the quotient is clamped by `retarget`; keep the
            // base itself inside the range so it stays finite and positive.
            self.base = base.max(self.config.min_target).min(self.config.max_target);
        }
        self.retarget();
        self.target
    }

    /// The candidate targets for the [`DemandCurve`] of the next frame:
    /// `base * 2^((j - 8) / 2)` for `j` in `0..CURVE_POINTS` (a factor 16 below the
    /// current feed-forward target to 11.3 above, in steps of `sqrt 2`), each clamped to
    /// `[min_target, max_target]`.
    #[must_use]
    pub fn curve_targets(&self) -> [T; CURVE_POINTS] {
        let half = T::from(0.5_f64).unwrap_or_else(T::one);
        let two = T::one() + T::one();
        let (min, max) = (self.config.min_target, self.config.max_target);
        core::array::from_fn(|j| {
            let e = T::from(j as f64 - CURVE_HALF_OCTAVES as f64).unwrap_or_else(T::zero);
            let t = self.base * two.powf(e * half);
            if t < min {
                min
            } else if t > max {
                max
            } else {
                t
            }
        })
    }

    /// Clamp-aware feed-forward: sets and returns the target for the frame that reads
    /// the history whose clamped demand is `curve`, `clamp(base e^c, min_target,
    /// max_target)` with `base` the target at which the clamped total crosses the budget
    /// `B`:
    /// - between the candidates `j` and `j + 1` with `totals[j] >= B > totals[j + 1]`,
    ///   `1 / base` interpolates `1 / targets[j + 1]` and `1 / targets[j]` with weight
    ///   `(B - totals[j + 1]) / (totals[j] - totals[j + 1])`: exact for the pixels that no
    ///   bound clamps over the interval, whose counts are linear in `1 / sigma0^2`, and for
    ///   the clamped ones, which are constant;
    /// - the largest candidate when even it gives `B` or more (raising the target never
    ///   raises a count); the smallest when even it gives less than `B` and the curve
    ///   falls somewhere (the next frame's candidates extend further);
    /// - the previous base when the curve is flat below the budget (no pixel's count
    ///   moves with the target within the candidates, e.g. a zero history).
    ///
    /// A curve whose targets are not finite, positive and non-decreasing, or whose
    /// totals are not finite and non-negative, keeps the previous feed-forward target.
    pub fn plan_curve(&mut self, curve: &DemandCurve<T>) -> T {
        if curve.usable() {
            let (ts, ns, b) = (&curve.targets, &curve.totals, self.config.budget);
            let last = CURVE_POINTS - 1;
            let base = if ns[last] >= b {
                Some(ts[last])
            } else if ns[0] < b {
                (ns[0] > ns[last]).then_some(ts[0])
            } else {
                // ns[0] >= b > ns[last]: the first candidate below the budget.
                let j = (1..=last).find(|&j| ns[j] < b).unwrap_or(last);
                let (x0, x1) = (ts[j - 1].recip(), ts[j].recip());
                let w = (b - ns[j]) / (ns[j - 1] - ns[j]);
                Some((x1 + w * (x0 - x1)).recip())
            };
            if let Some(base) = base {
                self.base = base.max(self.config.min_target).min(self.config.max_target);
            }
        }
        self.retarget();
        self.target
    }

    /// Changes the per-frame budget `B` (total samples) from the next
    /// [`plan`](Self::plan) / [`plan_curve`](Self::plan_curve) and
    /// [`observe`](Self::observe) on; the integral correction is kept. A frame-time
    /// governor ([`crate::frame_time::FrameTimeGovernor::budget`]) calls it every frame.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `budget` when it is not finite and positive;
    /// nothing changes then.
    pub fn set_budget(&mut self, budget: T) -> Result<(), Error> {
        if !(budget.is_finite() && budget > T::zero()) {
            return Err(Error::invalid(
                "budget",
                widen(budget),
                "must be finite and > 0",
            ));
        }
        self.config.budget = budget;
        Ok(())
    }

    /// Feedback: folds the total sample count of a frame into the integral correction,
    /// `c += g ln(total / budget)`, clamped to `+-ln(max_target / min_target)`, and
    /// updates the target. Anti-windup: while the target is pinned at a bound, an error
    /// that pushes it further out is not integrated.
    ///
    /// Returns `false` and changes nothing when `total` is not finite and positive.
    pub fn observe(&mut self, total: T) -> bool {
        if !(total.is_finite() && total > T::zero()) {
            return false;
        }
        let error = (total / self.config.budget).ln();
        let outward = match self.pinned {
            Pinned::High => error > T::zero(),
            Pinned::Low => error < T::zero(),
            Pinned::No => false,
        };
        if !outward && error.is_finite() {
            let bound = self.config.max_correction;
            self.correction = (self.correction + self.config.gain * error)
                .max(-bound)
                .min(bound);
        }
        self.retarget();
        true
    }
}

/// The allocation exponent applied to a raw count (docs/algorithms.md §8.2,
/// [`SpvgConfigBuilder::allocation_exponent`](crate::controller::SpvgConfigBuilder::allocation_exponent)):
/// `count^p` for a positive finite count, the count itself otherwise (0, negative, NaN
/// and `+-inf` pass unchanged, so the rounding rule treats them as before) and, bit for
/// bit, at `p = 1`.
///
/// Under the frame budget the governor scales `1 / sigma0^2` until the counts meet the
/// budget, so with the raw count `E = v / sigma0^2` (per-sample variance `v`, `kappa = 0`)
/// the counts become `v^p` times one factor for the frame: `p = 1` equalises every
/// pixel's variance at `sigma0^2`, `p = 1/2` is the Neyman allocation, which minimises
/// the mean of `v / n` at a fixed total. Each count stays non-increasing in `sigma0^2`
/// (`x^p` is increasing), so the [`DemandCurve`] and [`count_at`] hold as they are; the
/// linear model of [`FrameDemand`] and [`Governor::plan`] assumes `p = 1` (with `p < 1`
/// use [`Governor::plan_curve`]).
///
/// Computed as `exp(p ln(count))` through `num_traits::Float` (the `libm` path in
/// `no_std`).
///
/// # Examples
///
/// ```
/// use spvg::budget::allocate;
/// assert_eq!(allocate(1.0_f32, 37.3), 37.3);
/// assert!((allocate(0.5_f64, 64.0) - 8.0).abs() < 1e-12);
/// assert_eq!(allocate(0.5_f64, 0.0), 0.0);
/// ```
#[inline(always)]
#[must_use]
pub fn allocate<T: Float>(p: T, count: T) -> T {
    if p == T::one() || !(count > T::zero() && count.is_finite()) {
        count
    } else {
        (p * count.ln()).exp()
    }
}

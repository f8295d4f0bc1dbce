//! A frame-time governor: a target in milliseconds for a renderer's sampling pass, turned
//! into the per-frame sample budget that [`budget::Governor`](crate::budget::Governor)
//! holds (docs/algorithms.md §8.2).
//!
//! Engines budget a pass in milliseconds; the budget governor holds a frame's total sample
//! count. Between the two sits the pass's cost, which this governor learns online from
//! the frames it sees (timestamp queries where the adapter has them, else the wall time
//! from submit to completion), as a known shape times a learnt scale:
//!
//! ```text
//! ms(N) = s shape(N),   shape(N) = phi + (1 - phi) N / max_budget
//! ```
//!
//! with `N` the frame's total sample count, `phi` the configured share of the time at
//! `max_budget` that does not depend on the samples (`fixed_share`, 0 by default: a pure
//! rate) and `s` the pass's time at `max_budget`.
//!
//! # Why a scale, not a line
//!
//! Under the governor the totals stay near the operating point (a few percent apart,
//! against device noise of several percent), so a fitted line `t0 + k N` is not
//! identifiable: one noisy frame moves its intercept and slope far apart. The scale only
//! needs the time at the operating point, where the governor has many frames; the shape
//! only decides how fast a budget far from the target converges, not where it converges
//! (the fixed point `ms(B) = target` is the same for any shape).
//!
//! # The rule
//!
//! Per frame, after its time `ms_t` and total `N_t` are known,
//! [`FrameTimeGovernor::observe`] takes the log residual
//! `e = ln ms_t - ln shape(N_t) - ln s` and, with `sigma` the robust spread of the
//! residuals and the clip `c = 2.5 sigma`:
//! 1. the first frame sets `ln s` to `ln ms_t - ln shape(N_t)` (it is exact);
//! 2. `|e| <= c`: `ln s += gain e` (noise around the operating point, averaged);
//! 3. `|e| > c`, the previous frame's residual not beyond the clip on the same side:
//!    `ln s += gain c sign(e)` (Huber: one outlier moves the scale by `gain c` at most);
//! 4. `|e| > c` twice in a row on the same side: a real shift of the cost (a costlier
//!    view, a settings change), and `ln s` takes at once the mean of the two frames'
//!    values (both saw the new cost);
//! 5. the frame after a shift, beyond the clip from the new `ln s` and within it from
//!    the `ln s` before the shift's first frame: the two frames were an outlier pair (a
//!    device's noise has them), and `ln s` returns to its value before them, then takes
//!    this frame by rule 2;
//! 6. the spread follows `sigma += 0.1 (sqrt(pi / 2) min(|e|, c) - sigma)` (from 5%, at
//!    least 0.5%), the mean absolute deviation of a normal noise scaled to its standard
//!    deviation, clipped so that outliers do not inflate it. A frame beyond the clip
//!    enters it only when the next one lies beyond the clip on the other side (the noise
//!    grew): when the next lies within the clip it was a single outlier, and when it
//!    confirms a shift neither frame was noise, and the spread returns to its value
//!    before it. Otherwise single outliers, a tenth of a device's frames, would each
//!    raise the spread by a fifth and widen the clip until a real shift hides in it;
//! 7. the next budget is `B = max_budget (target_ms / s - phi) / (1 - phi)` clamped to
//!    `[min_budget, max_budget]` (`min_budget` is what the frame takes at the
//!    controller's least count everywhere, `beta_min` times the pixels; `max_budget` at
//!    its most), and [`Reach::BelowFloor`] when even `min_budget` costs more than
//!    `target_ms` by the model, [`Reach::AboveCeiling`] when even `max_budget` costs
//!    less.
//!
//! Without noise and with `phi` the pass's own share, the first frame gives the exact
//! scale and the next frame meets the target; a cost that steps is met again two frames
//! after the step. With `phi` below the pass's share the budget converges monotonically.
//!
//! The caller passes [`budget`](FrameTimeGovernor::budget) to
//! [`budget::Governor::set_budget`](crate::budget::Governor::set_budget) before the
//! frame's plan ([`FrameTimeSteering`] does both, with the demand curve). The twin of a
//! pass has no time of its own: give it a cost model ([`CostModel::ms`]) and the rule is
//! the same.
//!
//! ```
//! use spvg::frame_time::{FrameTimeConfig, FrameTimeGovernor, Reach};
//!
//! let pixels: f64 = 1920.0 * 1080.0;
//! let (lo, hi) = (pixels, 64.0 * pixels);
//! // A pass that costs 0.3 ms plus 0.1 ms per million samples: 0.3 of its 13.57 ms at
//! // the largest budget does not depend on the samples.
//! let cost = |n: f64| 0.3 + 1e-7 * n;
//! let share = 0.3 / cost(hi);
//! let cfg = FrameTimeConfig::builder(1.5, lo, hi).fixed_share(share).build().unwrap();
//! let mut g = FrameTimeGovernor::new(cfg, 8.0 * pixels).unwrap();
//! let n = g.budget();
//! g.observe(n, cost(n));
//! assert!((cost(g.budget()) - 1.5).abs() < 1e-9);
//! assert_eq!(g.reach(), Reach::Reachable);
//! ```

use num_traits::Float;

use crate::Error;
use crate::budget::{CURVE_POINTS, DemandCurve, Governor};

fn widen<T: Float>(v: T) -> f64 {
    v.to_f64().unwrap_or(f64::NAN)
}

fn constant<T: Float>(v: f64) -> T {
    T::from(v).unwrap_or_else(T::zero)
}

/// Defaults of [`FrameTimeConfig`].
pub mod defaults {
    /// The share of a residual within the clip that the scale takes.
    pub const GAIN: f64 = 0.25;
    /// The share of the time at `max_budget` that does not depend on the samples.
    pub const FIXED_SHARE: f64 = 0.0;
}

/// A residual beyond this many robust spreads is clipped (and, twice on one side, a shift).
const CLIP: f64 = 2.5;
/// The weight of a frame in the robust spread.
const SPREAD_RATE: f64 = 0.1;
/// The spread before any residual is seen: 5% frame-to-frame noise.
const INITIAL_SPREAD: f64 = 0.05;
/// The least spread: 0.5%, so that rounding is not taken for a shift of the cost.
const MIN_SPREAD: f64 = 0.005;
/// `sqrt(pi / 2)`: a normal noise's standard deviation over its mean absolute deviation.
const MAD_TO_SIGMA: f64 = 1.253_314_137_315_500_3;

/// The frame-time governor's configuration.
///
/// | field | default | range |
/// | --- | --- | --- |
/// | `target_ms` | (required) | finite, > 0 |
/// | `min_budget` | (required) | finite, > 0 |
/// | `max_budget` | (required) | finite, >= `min_budget` |
/// | `gain` | 0.25 | (0, 1] |
/// | `fixed_share` | 0 | [0, 1) |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTimeConfig<T> {
    target_ms: T,
    min_budget: T,
    max_budget: T,
    gain: T,
    fixed_share: T,
}

/// Builder of [`FrameTimeConfig`]; [`build`](Self::build) validates every field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTimeConfigBuilder<T> {
    config: FrameTimeConfig<T>,
}

impl<T: Float> FrameTimeConfig<T> {
    /// A builder for a pass time of `target_ms`, budgets within `[min_budget,
    /// max_budget]` (total samples per frame: the controller's least and most count
    /// times the pixels), and the defaults of the other fields.
    #[must_use]
    pub fn builder(target_ms: T, min_budget: T, max_budget: T) -> FrameTimeConfigBuilder<T> {
        FrameTimeConfigBuilder {
            config: Self {
                target_ms,
                min_budget,
                max_budget,
                gain: constant(defaults::GAIN),
                fixed_share: constant(defaults::FIXED_SHARE),
            },
        }
    }

    /// The target pass time in milliseconds.
    #[inline]
    #[must_use]
    pub fn target_ms(&self) -> T {
        self.target_ms
    }

    /// The smallest budget (total samples).
    #[inline]
    #[must_use]
    pub fn min_budget(&self) -> T {
        self.min_budget
    }

    /// The largest budget (total samples).
    #[inline]
    #[must_use]
    pub fn max_budget(&self) -> T {
        self.max_budget
    }

    /// The share of a residual within the clip that the scale takes.
    #[inline]
    #[must_use]
    pub fn gain(&self) -> T {
        self.gain
    }

    /// The share of the time at `max_budget` that does not depend on the samples.
    #[inline]
    #[must_use]
    pub fn fixed_share(&self) -> T {
        self.fixed_share
    }

    /// The cost's shape at `samples`: `phi + (1 - phi) samples / max_budget`.
    fn shape(&self, samples: T) -> T {
        self.fixed_share + (T::one() - self.fixed_share) * (samples / self.max_budget)
    }
}

impl<T: Float> FrameTimeConfigBuilder<T> {
    /// The target pass time in milliseconds, finite and positive.
    #[must_use]
    pub fn target_ms(mut self, target_ms: T) -> Self {
        self.config.target_ms = target_ms;
        self
    }

    /// The share of a residual within the clip that the scale takes, in `(0, 1]`:
    /// smaller values average the noise over about `2 / gain` frames.
    #[must_use]
    pub fn gain(mut self, gain: T) -> Self {
        self.config.gain = gain;
        self
    }

    /// The share of the pass's time at `max_budget` that does not depend on the samples,
    /// in `[0, 1)` (its per-pixel work, the component's steps if timed with it). 0, a pure
    /// rate, converges monotonically on any pass; the pass's own share converges in one
    /// frame; a share above the pass's overshoots.
    #[must_use]
    pub fn fixed_share(mut self, fixed_share: T) -> Self {
        self.config.fixed_share = fixed_share;
        self
    }

    /// Validates every field.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming the field (`target_ms`, `min_budget`,
    /// `max_budget`, `gain`, `fixed_share`) when it is out of range or not finite;
    /// [`Error::InconsistentParameters`] when `min_budget > max_budget`.
    pub fn build(self) -> Result<FrameTimeConfig<T>, Error> {
        let c = self.config;
        let positive = |v: T| v.is_finite() && v > T::zero();
        for (name, v) in [
            ("target_ms", c.target_ms),
            ("min_budget", c.min_budget),
            ("max_budget", c.max_budget),
        ] {
            if !positive(v) {
                return Err(Error::invalid(name, widen(v), "must be finite and > 0"));
            }
        }
        if c.min_budget > c.max_budget {
            return Err(Error::InconsistentParameters {
                names: "min_budget, max_budget",
                expected: "min_budget <= max_budget",
            });
        }
        if !(c.gain > T::zero() && c.gain <= T::one()) {
            return Err(Error::invalid("gain", widen(c.gain), "must be in (0, 1]"));
        }
        if !(c.fixed_share >= T::zero() && c.fixed_share < T::one()) {
            return Err(Error::invalid(
                "fixed_share",
                widen(c.fixed_share),
                "must be in [0, 1)",
            ));
        }
        Ok(c)
    }
}

/// The pass's cost as the governor has learnt it: `ms(N) = fixed_ms + ms_per_sample N`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostModel<T> {
    /// What the pass costs whatever it samples, in ms (>= 0).
    pub fixed_ms: T,
    /// What one sample costs, in ms (> 0).
    pub ms_per_sample: T,
}

impl<T: Float> CostModel<T> {
    /// The modelled time of a frame of `samples` total samples, in ms.
    #[inline]
    #[must_use]
    pub fn ms(&self, samples: T) -> T {
        self.fixed_ms + self.ms_per_sample * samples
    }

    /// The total samples that take `ms` by the model (negative below `fixed_ms`).
    #[inline]
    #[must_use]
    pub fn samples_for(&self, ms: T) -> T {
        (ms - self.fixed_ms) / self.ms_per_sample
    }
}

/// Whether the target pass time can be met within the budget range, by the model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reach<T> {
    /// No frame observed yet.
    Unknown,
    /// A budget within `[min_budget, max_budget]` meets the target.
    Reachable,
    /// Even `min_budget` (the least count everywhere) takes longer than the target:
    /// `floor_ms` by the model. The budget stays at `min_budget`.
    BelowFloor {
        /// The modelled time at `min_budget`, in ms.
        floor_ms: T,
    },
    /// Even `max_budget` (the most count everywhere) takes less than the target:
    /// `ceiling_ms` by the model. The budget stays at `max_budget`.
    AboveCeiling {
        /// The modelled time at `max_budget`, in ms.
        ceiling_ms: T,
    },
}

/// The last frame, when its residual lay beyond the clip and was not taken as a shift.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Beyond<T> {
    /// Its observed `ln s`.
    observed: T,
    /// `ln s` before it moved the scale: where a shift it starts is measured from.
    log_scale: T,
    /// The spread before it entered it: restored when the next frame shows it was a single
    /// outlier or the first frame of a shift.
    spread: T,
}

/// The frame-time governor (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTimeGovernor<T> {
    config: FrameTimeConfig<T>,
    /// `ln s`, the log of the modelled time at `max_budget` (`None` before a frame).
    log_scale: Option<T>,
    /// The robust spread of the log residuals.
    spread: T,
    /// The last frame, when its residual lay beyond the clip (rules 3 and 4).
    beyond: Option<Beyond<T>>,
    /// `ln s` before the shift the last frame confirmed, for the next frame to refute it
    /// (rule 5).
    before_shift: Option<T>,
    budget: T,
    reach: Reach<T>,
}

impl<T: Float> FrameTimeGovernor<T> {
    /// A governor whose first frame takes `initial_budget` samples.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `initial_budget` when it is not within
    /// `[min_budget, max_budget]` (NaN included).
    pub fn new(config: FrameTimeConfig<T>, initial_budget: T) -> Result<Self, Error> {
        if !(initial_budget >= config.min_budget && initial_budget <= config.max_budget) {
            return Err(Error::invalid(
                "initial_budget",
                widen(initial_budget),
                "must be within [min_budget, max_budget]",
            ));
        }
        Ok(Self {
            config,
            log_scale: None,
            spread: constant(INITIAL_SPREAD),
            beyond: None,
            before_shift: None,
            budget: initial_budget,
            reach: Reach::Unknown,
        })
    }

    /// The configuration.
    #[inline]
    #[must_use]
    pub fn config(&self) -> &FrameTimeConfig<T> {
        &self.config
    }

    /// The budget (total samples) for the next frame.
    #[inline]
    #[must_use]
    pub fn budget(&self) -> T {
        self.budget
    }

    /// The robust spread of the log residuals (about the device's relative frame-to-frame
    /// noise).
    #[inline]
    #[must_use]
    pub fn spread(&self) -> T {
        self.spread
    }

    /// The cost learnt so far (`None` before the first observed frame): the shape scaled
    /// by the learnt time at `max_budget`.
    #[must_use]
    pub fn model(&self) -> Option<CostModel<T>> {
        let s = self.log_scale?.exp();
        let phi = self.config.fixed_share;
        Some(CostModel {
            fixed_ms: s * phi,
            ms_per_sample: s * (T::one() - phi) / self.config.max_budget,
        })
    }

    /// Whether the target can be met, by the model.
    #[inline]
    #[must_use]
    pub fn reach(&self) -> Reach<T> {
        self.reach
    }

    /// Changes the target pass time; the learnt cost is kept and the budget follows at
    /// once.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `target_ms` when it is not finite and positive;
    /// nothing changes then.
    pub fn set_target_ms(&mut self, target_ms: T) -> Result<(), Error> {
        self.config = FrameTimeConfigBuilder {
            config: self.config,
        }
        .target_ms(target_ms)
        .build()?;
        self.steer();
        Ok(())
    }

    /// Folds a frame's total sample count and its measured pass time (ms) into the scale
    /// (steps 1-6 of the [rule](self)) and sets the next budget. Returns `false` and
    /// changes nothing when `samples` is not finite and non-negative, `ms` is not finite
    /// and positive, or the shape is 0 there (no samples with `fixed_share` 0).
    pub fn observe(&mut self, samples: T, ms: T) -> bool {
        if !(samples.is_finite() && samples >= T::zero() && ms.is_finite() && ms > T::zero()) {
            return false;
        }
        let observed = ms.ln() - self.config.shape(samples).ln();
        if !observed.is_finite() {
            return false;
        }
        let Some(log_scale) = self.log_scale else {
            self.log_scale = Some(observed);
            self.steer();
            return true;
        };
        let clip = constant::<T>(CLIP) * self.spread;
        // Rule 5: a frame beyond the clip from a shift just taken and within it from the
        // scale before refutes the shift (its two frames were an outlier pair).
        let log_scale = match self.before_shift.take() {
            Some(b) if (observed - log_scale).abs() > clip && (observed - b).abs() <= clip => b,
            _ => log_scale,
        };
        let e = observed - log_scale;
        let side = e > T::zero();
        let last = self.beyond.take();
        let log_scale = if e.abs() <= clip {
            // The last frame beyond the clip, if any, was a single outlier: it leaves the
            // spread as it found it.
            if let Some(b) = last {
                self.spread = b.spread;
            }
            self.fold_spread(e, clip);
            log_scale + self.config.gain * e
        } else {
            match last.filter(|b| (b.observed - log_scale > T::zero()) == side) {
                Some(b) => {
                    // A shift: both frames saw the new cost, and their mean halves the
                    // noise of either; neither is noise about the scale.
                    self.spread = b.spread;
                    self.before_shift = Some(b.log_scale);
                    (b.observed + observed) * constant(0.5)
                }
                None => {
                    // A first frame beyond the clip (or one on the other side of the last:
                    // the noise grew, and that one stays in the spread).
                    self.beyond = Some(Beyond {
                        observed,
                        log_scale,
                        spread: self.spread,
                    });
                    self.fold_spread(e, clip);
                    log_scale + self.config.gain * clip.copysign(e)
                }
            }
        };
        self.log_scale = Some(log_scale);
        self.steer();
        true
    }

    /// Rule 6: folds the residual `e`, clipped at `clip`, into the robust spread.
    fn fold_spread(&mut self, e: T, clip: T) {
        let sample = constant::<T>(MAD_TO_SIGMA) * e.abs().min(clip);
        let spread = self.spread + constant::<T>(SPREAD_RATE) * (sample - self.spread);
        self.spread = spread.max(constant(MIN_SPREAD));
    }

    /// The budget that meets the target by the model, and whether it is reachable.
    fn steer(&mut self) {
        let Some(m) = self.model() else {
            return;
        };
        let (min, max, target) = (
            self.config.min_budget,
            self.config.max_budget,
            self.config.target_ms,
        );
        let (floor_ms, ceiling_ms) = (m.ms(min), m.ms(max));
        (self.budget, self.reach) = if floor_ms > target {
            (min, Reach::BelowFloor { floor_ms })
        } else if ceiling_ms < target {
            (max, Reach::AboveCeiling { ceiling_ms })
        } else {
            (m.samples_for(target).max(min).min(max), Reach::Reachable)
        };
    }
}

/// The frame-time governor and the budget governor chained: after each frame, its total
/// samples, its pass time and the clamped demand curve of the history the next frame
/// reads give the target variance `sigma0^2` of the next frame
/// (`AdaptivePass::set_target_variance` in spvg-wgpu, or the controller's target in a
/// renderer's own pass).
///
/// Per frame: reduce the curve at [`curve_targets`](Self::curve_targets) (taken before
/// [`after_frame`](Self::after_frame)), then `after_frame`. The curve lets the target meet
/// a new budget in the same frame: without it (`None`) the budget governor only has its
/// feedback, and near the count bounds the total barely moves with the target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTimeSteering<T> {
    time: FrameTimeGovernor<T>,
    spp: Governor<T>,
}

impl<T: Float> FrameTimeSteering<T> {
    /// Chains `time` to `spp`, whose budget becomes `time`'s.
    ///
    /// # Errors
    ///
    /// As [`Governor::set_budget`] (not reached for a valid `time`).
    pub fn new(time: FrameTimeGovernor<T>, mut spp: Governor<T>) -> Result<Self, Error> {
        spp.set_budget(time.budget())?;
        Ok(Self { time, spp })
    }

    /// The frame-time governor.
    #[must_use]
    pub fn time(&self) -> &FrameTimeGovernor<T> {
        &self.time
    }

    /// The frame-time governor, to change its target.
    pub fn time_mut(&mut self) -> &mut FrameTimeGovernor<T> {
        &mut self.time
    }

    /// The budget governor.
    #[must_use]
    pub fn spp(&self) -> &Governor<T> {
        &self.spp
    }

    /// The budget governor.
    pub fn spp_mut(&mut self) -> &mut Governor<T> {
        &mut self.spp
    }

    /// The target variance for the next frame.
    #[must_use]
    pub fn target(&self) -> T {
        self.spp.target()
    }

    /// The candidate targets at which to reduce the demand curve passed to the next
    /// [`after_frame`](Self::after_frame) ([`Governor::curve_targets`]).
    #[must_use]
    pub fn curve_targets(&self) -> [T; CURVE_POINTS] {
        self.spp.curve_targets()
    }

    /// After a frame of `samples` total samples whose pass took `ms`, with `curve` the
    /// clamped demand of the history the next frame reads: folds the total into the
    /// budget governor against the budget the frame was planned for, learns the cost,
    /// moves the budget, plans the next target on the curve and returns it. A time the
    /// frame-time governor refuses (non-finite, negative or zero) keeps the budget; a
    /// total or curve the budget governor refuses changes nothing there.
    pub fn after_frame(&mut self, samples: T, ms: T, curve: Option<&DemandCurve<T>>) -> T {
        self.spp.observe(samples);
        if self.time.observe(samples, ms) {
            // Always finite and positive: within [min_budget, max_budget].
            let _ = self.spp.set_budget(self.time.budget());
        }
        match curve {
            Some(c) => self.spp.plan_curve(c),
            None => self.spp.target(),
        }
    }
}

//! A frame-time governor: a target in milliseconds for a renderer's sampling pass, turned
//! into the per-frame sample budget that [`budget::Governor`](crate::budget::Governor)
//! holds.
//!
//! Engines budget a pass in milliseconds; the budget governor holds a frame's total sample
//! count. Between the two sits the pass's cost, which this governor learns online from
//! the frames it sees (timestamp queries where the adapter has them, else the wall time
//! from submit to completion):
//!
//! ```text
//! ms(N) = fixed_ms + ms_per_sample * N
//! ```
//!
//! with `N` the frame's total sample count and `fixed_ms` what the pass costs whatever it
//! samples (its per-pixel work, the component's steps if the caller times them with it).
//!
//! # The rule
//!
//! Per frame, after the frame's time `ms_t` and total `N_t` are known,
//! [`FrameTimeGovernor::observe`]:
//! 1. folds `(N_t, ms_t)` into exponentially forgotten sums (factor `forgetting` per
//!    frame), with the counts in units of `max_budget` so that the sums keep their
//!    precision in `f32`;
//! 2. fits the cost: where the remembered totals spread (their standard deviation above
//!    2% of their mean), the weighted least-squares line; otherwise, or where the line
//!    has a non-positive slope or a negative intercept, the line through the mean time
//!    with the previous `fixed_ms` (0 at first; half the mean time when the times fell
//!    to it or below): a pure rate at first, which the next budget moves
//!    away from, so that the line becomes identifiable;
//! 3. sets the next budget `B = (target_ms - fixed_ms) / ms_per_sample`, clamped to
//!    `[min_budget, max_budget]` (`min_budget` is what the frame takes at the controller's
//!    least count everywhere, `beta_min` times the pixels; `max_budget` at its most);
//! 4. says whether the target is reachable: [`Reach::BelowFloor`] when even `min_budget`
//!    costs more than `target_ms` by the model, [`Reach::AboveCeiling`] when even
//!    `max_budget` costs less.
//!
//! For a cost that is exactly affine the first frame whose total differs from the others
//! gives the exact line and the next frame meets the target; from a pure-rate start the
//! error shrinks by the factor `fixed_ms / target_ms` per frame until then.
//!
//! The caller passes [`budget`](FrameTimeGovernor::budget) to
//! [`budget::Governor::set_budget`](crate::budget::Governor::set_budget) before the
//! frame's plan; the budget governor then sets the target variance that makes the total
//! meet it. The twin of a pass has no time of its own: give it a cost model
//! ([`CostModel::ms`]) and the rule is the same.
//!
//! ```
//! use spvg::frame_time::{FrameTimeConfig, FrameTimeGovernor, Reach};
//!
//! let pixels: f64 = 1920.0 * 1080.0;
//! let cfg = FrameTimeConfig::builder(1.5, pixels, 64.0 * pixels).build().unwrap();
//! let mut g = FrameTimeGovernor::new(cfg, 8.0 * pixels).unwrap();
//! // A pass that costs 0.3 ms plus 0.1 ms per million samples.
//! for _ in 0..4 {
//!     let n = g.budget();
//!     g.observe(n, 0.3 + 1e-7 * n);
//! }
//! let ms = 0.3 + 1e-7 * g.budget();
//! assert!((ms - 1.5).abs() < 1e-6);
//! assert_eq!(g.reach(), Reach::Reachable);
//! ```

use num_traits::Float;

use crate::Error;

fn widen<T: Float>(v: T) -> f64 {
    v.to_f64().unwrap_or(f64::NAN)
}

/// Defaults of [`FrameTimeConfig`].
pub mod defaults {
    /// The weight a frame's observation keeps per later frame.
    pub const FORGETTING: f64 = 0.75;
}

/// The remembered totals spread when their standard deviation is above this share of
/// their mean: then the fixed cost and the rate are told apart.
const MIN_SPREAD: f64 = 0.02;

/// The frame-time governor's configuration.
///
/// | field | default | range |
/// | --- | --- | --- |
/// | `target_ms` | (required) | finite, > 0 |
/// | `min_budget` | (required) | finite, > 0 |
/// | `max_budget` | (required) | finite, >= `min_budget` |
/// | `forgetting` | 0.75 | [0, 1) |
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTimeConfig<T> {
    target_ms: T,
    min_budget: T,
    max_budget: T,
    forgetting: T,
}

/// Builder of [`FrameTimeConfig`]; [`build`](Self::build) validates every field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTimeConfigBuilder<T> {
    config: FrameTimeConfig<T>,
}

impl<T: Float> FrameTimeConfig<T> {
    /// A builder for a pass time of `target_ms`, budgets within `[min_budget,
    /// max_budget]` (total samples per frame: the controller's least and most count
    /// times the pixels), and the default forgetting.
    #[must_use]
    pub fn builder(target_ms: T, min_budget: T, max_budget: T) -> FrameTimeConfigBuilder<T> {
        FrameTimeConfigBuilder {
            config: Self {
                target_ms,
                min_budget,
                max_budget,
                forgetting: T::from(defaults::FORGETTING).unwrap_or_else(T::zero),
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

    /// The weight an observation keeps per later frame.
    #[inline]
    #[must_use]
    pub fn forgetting(&self) -> T {
        self.forgetting
    }
}

impl<T: Float> FrameTimeConfigBuilder<T> {
    /// The target pass time in milliseconds, finite and positive.
    #[must_use]
    pub fn target_ms(mut self, target_ms: T) -> Self {
        self.config.target_ms = target_ms;
        self
    }

    /// The weight an observation keeps per later frame, in `[0, 1)`: 0 fits the last
    /// frame alone; larger values average over about `1 / (1 - forgetting)` frames.
    #[must_use]
    pub fn forgetting(mut self, forgetting: T) -> Self {
        self.config.forgetting = forgetting;
        self
    }

    /// Validates every field.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming the field (`target_ms`, `min_budget`,
    /// `max_budget`, `forgetting`) when it is out of range or not finite;
    /// [`Error::InconsistentParameters`] when `min_budget > max_budget`.
    pub fn build(self) -> Result<FrameTimeConfig<T>, Error> {
        let c = self.config;
        let positive = |v: T| v.is_finite() && v > T::zero();
        if !positive(c.target_ms) {
            return Err(Error::invalid(
                "target_ms",
                widen(c.target_ms),
                "must be finite and > 0",
            ));
        }
        if !positive(c.min_budget) {
            return Err(Error::invalid(
                "min_budget",
                widen(c.min_budget),
                "must be finite and > 0",
            ));
        }
        if !positive(c.max_budget) {
            return Err(Error::invalid(
                "max_budget",
                widen(c.max_budget),
                "must be finite and > 0",
            ));
        }
        if c.min_budget > c.max_budget {
            return Err(Error::InconsistentParameters {
                names: "min_budget, max_budget",
                expected: "min_budget <= max_budget",
            });
        }
        if !(c.forgetting >= T::zero() && c.forgetting < T::one()) {
            return Err(Error::invalid(
                "forgetting",
                widen(c.forgetting),
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

/// The frame-time governor (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTimeGovernor<T> {
    config: FrameTimeConfig<T>,
    /// Forgotten sums of 1, n, ms, n^2 and n ms, with n in units of `max_budget`.
    sums: [T; 5],
    model: Option<CostModel<T>>,
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
            sums: [T::zero(); 5],
            model: None,
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

    /// The cost learnt so far (`None` before the first observed frame).
    #[inline]
    #[must_use]
    pub fn model(&self) -> Option<CostModel<T>> {
        self.model
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

    /// Folds a frame's total sample count and its measured pass time (ms) into the cost
    /// model and sets the next budget. Returns `false` and changes nothing when `samples`
    /// is not finite and non-negative or `ms` is not finite and positive.
    pub fn observe(&mut self, samples: T, ms: T) -> bool {
        if !(samples.is_finite() && samples >= T::zero() && ms.is_finite() && ms > T::zero()) {
            return false;
        }
        let n = samples / self.config.max_budget;
        let f = self.config.forgetting;
        let add = [T::one(), n, ms, n * n, n * ms];
        let mut sums = self.sums;
        for (s, a) in sums.iter_mut().zip(add) {
            *s = f * *s + a;
        }
        if !sums.iter().all(|s| s.is_finite()) {
            return false;
        }
        self.sums = sums;
        self.model = self.fit();
        self.steer();
        true
    }

    /// The cost line of the remembered frames (with n in units of `max_budget`).
    fn fit(&self) -> Option<CostModel<T>> {
        let [w, sn, st, snn, snt] = self.sums;
        let (mean_n, mean_t) = (sn / w, st / w);
        let var = (snn / w - mean_n * mean_n).max(T::zero());
        let spread = T::from(MIN_SPREAD).unwrap_or_else(T::zero) * mean_n;
        let scale = self.config.max_budget;
        let line = (var > spread * spread)
            .then(|| {
                let b = (snt / w - mean_n * mean_t) / var;
                let a = mean_t - b * mean_n;
                (b > T::zero() && a >= T::zero()).then_some((a, b))
            })
            .flatten();
        let (a, b) = match line {
            Some(ab) => ab,
            None if mean_n > T::zero() => {
                // The previous fixed cost (a pure rate at first); half the mean time if
                // the times fell to it or below (the fixed cost was overestimated).
                let a = self.model.map_or(T::zero(), |m| m.fixed_ms);
                let a = if a < mean_t {
                    a
                } else {
                    mean_t * T::from(0.5).unwrap_or_else(T::zero)
                };
                (a, (mean_t - a) / mean_n)
            }
            None => return self.model,
        };
        let m = CostModel {
            fixed_ms: a,
            ms_per_sample: b / scale,
        };
        (m.fixed_ms.is_finite() && m.ms_per_sample.is_finite() && m.ms_per_sample > T::zero())
            .then_some(m)
            .or(self.model)
    }

    /// The budget that meets the target by the model, and whether it is reachable.
    fn steer(&mut self) {
        let Some(m) = self.model else {
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
/// samples and its pass time give the target variance `sigma0^2` of the next
/// (`AdaptivePass::set_target_variance` in spvg-wgpu, or the controller's target in a
/// renderer's own pass). The budget governor runs on its feedback alone here
/// ([`Governor::observe`](crate::budget::Governor::observe)); a renderer with a demand
/// curve also calls [`Governor::plan_curve`](crate::budget::Governor::plan_curve) on
/// [`spp_mut`](Self::spp_mut) before the frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTimeSteering<T> {
    time: FrameTimeGovernor<T>,
    spp: crate::budget::Governor<T>,
}

impl<T: Float> FrameTimeSteering<T> {
    /// Chains `time` to `spp`, whose budget becomes `time`'s.
    ///
    /// # Errors
    ///
    /// As [`Governor::set_budget`](crate::budget::Governor::set_budget) (not reached for a
    /// valid `time`).
    pub fn new(
        time: FrameTimeGovernor<T>,
        mut spp: crate::budget::Governor<T>,
    ) -> Result<Self, Error> {
        spp.set_budget(time.budget())?;
        Ok(Self { time, spp })
    }

    /// The frame-time governor.
    #[must_use]
    pub fn time(&self) -> &FrameTimeGovernor<T> {
        &self.time
    }

    /// The budget governor.
    #[must_use]
    pub fn spp(&self) -> &crate::budget::Governor<T> {
        &self.spp
    }

    /// The budget governor, to plan with a demand curve.
    pub fn spp_mut(&mut self) -> &mut crate::budget::Governor<T> {
        &mut self.spp
    }

    /// The target variance for the next frame.
    #[must_use]
    pub fn target(&self) -> T {
        self.spp.target()
    }

    /// After a frame of `samples` total samples whose pass took `ms`: learns the cost,
    /// moves the budget, folds the total into the budget governor against it, and
    /// returns the next frame's target variance. A frame the frame-time governor refuses
    /// (non-finite, negative or zero time) changes nothing.
    pub fn after_frame(&mut self, samples: T, ms: T) -> T {
        if self.time.observe(samples, ms) {
            // Always finite and positive: within [min_budget, max_budget].
            let _ = self.spp.set_budget(self.time.budget());
            self.spp.observe(samples);
        }
        self.spp.target()
    }
}

//! The controller's shared parameters, validated once with derived constants precomputed.

use num_traits::Float;

use super::CountPolicy;
use crate::Error;
use crate::stats::Weight;

/// Published parameters (docs/algorithms.md §2; Unreal Engine and the SPVG paper).
mod published {
    pub(super) const ETA: f64 = 0.2;
    pub(super) const TARGET_VARIANCE: f64 = 1e-4;
    pub(super) const KAPPA: f64 = 0.2;
    pub(super) const MIN_SAMPLES: u32 = 8;
    pub(super) const MAX_SAMPLES: u32 = 64;
    pub(super) const EPS_U: f64 = 0.01;
}

/// The largest budget maximum `beta_max` a configuration accepts: 4096 samples per pixel
/// per frame, 64 times the published maximum. Above it a frame is no real-time frame on any
/// device (a demo page at 1024 spp took about 12 s per frame on a software adapter, and an
/// unbounded maximum froze it): a larger value is a typo or a unit error, refused by
/// [`SpvgConfigBuilder::build`] with [`Error::InvalidParameter`] naming `max_samples`.
pub const MAX_BUDGET: u32 = 4096;

/// Parameters of the SPVG controller shared by every pixel (docs/algorithms.md §2), validated at
/// construction, with the constants that the per-pixel [`estimate`](Self::estimate) and
/// [`update`](Self::update) need precomputed.
///
/// Build one with [`SpvgConfig::builder`] (every field starts at its published value) or
/// take the published set with [`SpvgConfig::published`].
///
/// | field | meaning | valid range | published |
/// |---|---|---|---|
/// | `eta` | EMA/EMV weight of the history | finite, `(0, 1]` | 0.2 |
/// | `target_variance` | `sigma0^2`, the variance the count aims for | finite, `> 0` | 1e-4 |
/// | `kappa` | control factor | `[0, 1]` | 0.2 |
/// | `min_samples` | `beta_min` | `>= 1`, `<= max_samples` | 8 |
/// | `max_samples` | `beta_max` | `>= 1`, `<=` [`MAX_BUDGET`] | 64 |
/// | `eps_u` | distant-energy threshold for zero samples (docs/algorithms.md §2.4) | `[0, 1]` | 0.01 |
/// | `policy` | count rule ([`CountPolicy`]) | `Fixed(n)` needs `min <= n <= max` | `Spvg` |
/// | `max_change` | damped correction: cap `c` on the count's relative change against `nbar` (docs/algorithms.md §8.1) | `None`, or finite `> 0` | `None` |
/// | `firefly_clamp` | firefly clamp: `k` of the clamp of the monitored value to `mean +- k sigma` before the update (docs/algorithms.md §8.3) | `None`, or `> 0` (`+inf` reads as `None`) | `None` |
/// | `age_weight` | young histories update with weight `max(eta, 1/age)` (docs/algorithms.md §8.4) | `bool` | `false` |
/// | `spatial_variance` | histories of age at most this many frames take the spatial variance of their same-surface neighbours (docs/algorithms.md §8.4); 0 = off | `0..=`[`young::AGE_CAP`](super::young::AGE_CAP) | [`young::SPATIAL_FRAMES`](super::young::SPATIAL_FRAMES) (3) |
/// | `fractional_floor` | fractional counts (docs/algorithms.md §8.6): `Some(beta)` lets a pixel with history take the real count `c >= beta`, realised by dithered rounding; `None` keeps integer counts | `None`, or finite in `[0, `[`fractional::MAX_FLOOR`](super::fractional::MAX_FLOOR)`]` and `<= max_samples`; not with `max_change` | `None` |
/// | `allocation_exponent` | `p` of the allocation `n ∝ E^p` ([`budget::allocate`](crate::budget::allocate), docs/algorithms.md §8.2): 1 equalises every pixel's variance, 0.5 minimises the mean error at a fixed total (Neyman); meant for the frame budget | finite, `(0, 1]`; `!= 1` not with `fractional_floor` | 1 |
/// | `resolve_weight` | the resolved-image count rule (docs/algorithms.md §8.7): `Some(alpha)`, the weight a temporal resolve gives the current frame in steady state, aims the count at `sigma0^2` for the resolved image, `n = v1 a / ((2 - a) sigma0^2)` with `a` the resolve's weight at the pixel; `None` aims every frame at `sigma0^2` | `None`, or finite in `(0, 1]`; needs `fractional_floor` | `None` |
///
/// # Examples
///
/// ```
/// use spvg::{SpvgConfig, controller::CountPolicy};
/// let config = SpvgConfig::<f32>::builder()
///     .target_variance(1e-3)
///     .kappa(1.0)
///     .build()
///     .unwrap();
/// assert_eq!(config.eta(), 0.2);
/// assert_eq!(config.target_variance(), 1e-3);
/// assert_eq!(config.policy(), CountPolicy::Spvg);
///
/// // A renderer switches the count rule with one line.
/// let unreal = config.with_policy(CountPolicy::UnrealClamp).unwrap();
/// assert_eq!(unreal.policy(), CountPolicy::UnrealClamp);
///
/// // Invalid values are rejected with an error naming the field.
/// let err = SpvgConfig::<f32>::builder().kappa(1.5).build().unwrap_err();
/// assert!(err.to_string().contains("kappa"));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpvgConfig<T> {
    weight: Weight<T>,
    target_variance: T,
    kappa: T,
    min_samples: u32,
    max_samples: u32,
    eps_u: T,
    policy: CountPolicy,
    max_change: Option<T>,
    firefly_clamp: Option<T>,
    age_weight: bool,
    spatial_variance: u32,
    fractional_floor: Option<T>,
    resolve_weight: Option<T>,
    allocation_exponent: T,
    // Derived constants (see `estimate`).
    inv_target: T,
    cap_down: T,
    cap_up: T,
    k_minus_1: T,
    min_f: T,
    max_f: T,
    floor_f: T,
}

/// Builder of [`SpvgConfig`]: every field starts at its published value, and
/// [`build`](Self::build) validates them all.
///
/// # Examples
///
/// ```
/// use spvg::SpvgConfig;
/// let c = SpvgConfig::<f64>::builder().min_samples(4).max_samples(32).build().unwrap();
/// assert_eq!((c.min_samples(), c.max_samples()), (4, 32));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpvgConfigBuilder<T> {
    eta: T,
    target_variance: T,
    kappa: T,
    min_samples: u32,
    max_samples: u32,
    eps_u: T,
    policy: CountPolicy,
    max_change: Option<T>,
    firefly_clamp: Option<T>,
    age_weight: bool,
    spatial_variance: u32,
    fractional_floor: Option<T>,
    resolve_weight: Option<T>,
    allocation_exponent: T,
}

/// Converts a published `f64` constant to `T`; every `Float` type in use (`f16`, `f32`,
/// `f64`) represents these constants, so the fallback only guards exotic types.
#[inline]
fn constant<T: Float>(v: f64, fallback: T) -> T {
    T::from(v).unwrap_or(fallback)
}

#[inline]
fn widen<T: Float>(v: T) -> f64 {
    v.to_f64().unwrap_or(f64::NAN)
}

/// Builder setters, one per `field: Type;` (each preceded by its doc comment): `field(v)`
/// stores `v` in the field of the same name; validation waits for `build`.
macro_rules! setters {
    ($($(#[$doc:meta])* $field:ident: $ty:ty;)*) => {$(
        $(#[$doc])*
        #[must_use]
        pub fn $field(mut self, $field: $ty) -> Self {
            self.$field = $field;
            self
        }
    )*};
}

/// Getters, one per `field: Type;` (each preceded by its doc comment): `field()` returns
/// the field of the same name.
macro_rules! getters {
    ($($(#[$doc:meta])* $field:ident: $ty:ty;)*) => {$(
        $(#[$doc])*
        #[inline]
        #[must_use]
        pub fn $field(&self) -> $ty {
            self.$field
        }
    )*};
}

impl<T: Float> SpvgConfigBuilder<T> {
    setters! {
        /// The EMA/EMV weight `eta` of the history, in `(0, 1]`.
        eta: T;
        /// The target variance `sigma0^2`, finite and positive.
        target_variance: T;
        /// The control factor `kappa`, in `[0, 1]`.
        kappa: T;
        /// The smallest count `beta_min` (at least 1) used when the pixel samples at all.
        min_samples: u32;
        /// The largest count `beta_max`.
        max_samples: u32;
    }

    /// Both budget bounds `[beta_min, beta_max]`.
    #[must_use]
    pub fn budget(self, min_samples: u32, max_samples: u32) -> Self {
        self.min_samples(min_samples).max_samples(max_samples)
    }

    setters! {
        /// The distant-energy threshold `eps_u` in `[0, 1]` below which a pixel takes zero
        /// samples (docs/algorithms.md §2.4).
        eps_u: T;
        /// The count rule.
        policy: CountPolicy;
        /// The damped correction (docs/algorithms.md §8.1): `Some(c)` clamps the
        /// [`CountPolicy::Spvg`] raw count to `[nbar / (1 + c), nbar (1 + c)]` before the
        /// budget clamp; `None` (the default) leaves the published rule unchanged. The
        /// other policies ignore it.
        max_change: Option<T>;
        /// The firefly clamp (docs/algorithms.md §8.3): `Some(k)` clamps the monitored
        /// value of a frame to `[mean - k sigma, mean + k sigma]` of the history before
        /// the update, with `sigma = sqrt(max(variance, sigma0^2))`; `None` (the default)
        /// leaves the published update unchanged, and so does `Some(+inf)`. Disocclusion
        /// seeds are never clamped.
        firefly_clamp: Option<T>;
        /// The age-aware weight (docs/algorithms.md §8.4): `true` updates a history that
        /// has absorbed `a` frames with weight `max(eta, 1 / (a + 1))` (the mean of its
        /// frames while that is above `eta`), so a seeded history replaces most of its
        /// seeded variance on its second frame instead of over about `1/eta` frames;
        /// `false` (the default) keeps `eta`. Needs the history's age
        /// ([`SpvgConfig::update_young`]).
        age_weight: bool;
        /// The spatial variance of young histories (docs/algorithms.md §8.4): a history
        /// whose age after the update is at most `frames` takes as its variance the
        /// sample variance of this frame's monitored values of its same-surface
        /// neighbours ([`young::SpatialMoments`](super::young::SpatialMoments)) instead
        /// of the seed's `sigma0^2` or its temporal estimate; 0 is off. The default is
        /// [`young::SPATIAL_FRAMES`](super::young::SPATIAL_FRAMES) (3): it changes only
        /// [`SpvgConfig::update_young`] (what the GPU component runs), never
        /// [`SpvgConfig::update`].
        /// At most [`young::AGE_CAP`](super::young::AGE_CAP).
        spatial_variance: u32;
        /// Fractional counts below the floor (docs/algorithms.md §8.6): `Some(beta)`, a
        /// real floor in `[0, 8]`, lets a pixel with a valid history take a real-valued
        /// count `c` in `[beta, beta_max]`, which
        /// [`SpvgConfig::estimate_fractional`] realises per pixel and frame by dithered
        /// rounding (`c = 0.25` is one sample one frame in four); a frame that takes no
        /// sample keeps the history's mean and variance
        /// ([`SpvgConfig::update_fractional`]). `beta = 0` lets a pixel whose variance
        /// reads 0 stop sampling until its history is invalidated. Pixels without
        /// history still take the integer `min_samples`, so a history is always seeded
        /// from a sample. `None` (the default) keeps integer counts and every rule
        /// unchanged. The floor in use is never below
        /// [`fractional::REVISIT_COUNT`](super::fractional::REVISIT_COUNT) (1/32): a pixel
        /// whose variance reads 0 still samples at least once every
        /// [`fractional::REVISIT_FRAMES`](super::fractional::REVISIT_FRAMES) (55) frames,
        /// so `beta = 0` never stalls ([`SpvgConfig::floor_f`]).
        fractional_floor: Option<T>;
        /// The resolved-image count rule (docs/algorithms.md §8.7): `Some(alpha)`, the
        /// weight in `(0, 1]` that the renderer's temporal resolve gives the current frame
        /// once its history is old (0.1 for a typical TAA). The count then aims at
        /// `sigma0^2` for the *resolved* image: `c = E a / (2 - a)` with `E` the
        /// fractional rule's count and `a` the resolve's weight at the pixel
        /// ([`fractional::resolve_weight`](super::fractional::resolve_weight): the
        /// renderer's own weight where it passes one, else `max(alpha, 1 / (age + 1))` from
        /// the history's age). Needs `fractional_floor` (the resolved count of converged
        /// content is below one sample). `None` (the default) aims every frame at
        /// `sigma0^2`.
        resolve_weight: Option<T>;
        /// The allocation exponent `p` in `(0, 1]` (docs/algorithms.md §8.2): the raw count
        /// `E` of a pixel becomes `E^p` ([`budget::allocate`](crate::budget::allocate))
        /// before the clamp to `[beta_min, beta_max]`, so that under the frame budget
        /// ([`budget::Governor`](crate::budget::Governor), which moves `sigma0^2` until
        /// the total meets the budget) the counts are proportional to `v^p`, `v` the
        /// per-sample variance. 1 (the default) is the equalising rule, bit for bit; 0.5
        /// minimises the mean squared error at a fixed total (Neyman). Without a budget
        /// a `p < 1` no longer aims every pixel at `sigma0^2`. CPU only: the WGSL
        /// library and the GPU passes refuse `p != 1`.
        allocation_exponent: T;
    }

    /// Validates every field and precomputes the derived constants.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming the field (`eta`, `target_variance`, `kappa`,
    /// `min_samples`, `max_samples` (also above [`MAX_BUDGET`]), `eps_u`, `policy`,
    /// `max_change`, `firefly_clamp`, `spatial_variance`, `fractional_floor`,
    /// `resolve_weight`, `allocation_exponent`) when it is out of range or not finite;
    /// [`Error::InconsistentParameters`] when `min_samples >
    /// max_samples`, a `Fixed(n)` policy lies outside the budget, the fractional floor is
    /// above `max_samples`, the fractional floor and the damped correction are both set,
    /// the resolve weight is set without the fractional floor, or an allocation exponent
    /// below 1 is set with the fractional floor.
    pub fn build(self) -> Result<SpvgConfig<T>, Error> {
        let weight = Weight::new(self.eta)?;
        let target = self.target_variance;
        if !(target.is_finite() && target > T::zero()) {
            return Err(Error::invalid(
                "target_variance",
                widen(target),
                "must be finite and > 0",
            ));
        }
        let inv_target = T::one() / target;
        if !inv_target.is_finite() {
            return Err(Error::invalid(
                "target_variance",
                widen(target),
                "its reciprocal must be finite",
            ));
        }
        if !(self.kappa >= T::zero() && self.kappa <= T::one()) {
            return Err(Error::invalid(
                "kappa",
                widen(self.kappa),
                "must be in [0, 1]",
            ));
        }
        if self.max_samples == 0 {
            return Err(Error::invalid("max_samples", 0.0, "must be at least 1"));
        }
        if self.max_samples > MAX_BUDGET {
            return Err(Error::invalid(
                "max_samples",
                f64::from(self.max_samples),
                "must be at most MAX_BUDGET (4096)",
            ));
        }
        if self.min_samples == 0 {
            return Err(Error::invalid(
                "min_samples",
                0.0,
                "must be at least 1: a pixel at zero samples never observes variance again",
            ));
        }
        if self.min_samples > self.max_samples {
            return Err(Error::InconsistentParameters {
                names: "min_samples, max_samples",
                expected: "min_samples <= max_samples",
            });
        }
        if !(self.eps_u >= T::zero() && self.eps_u <= T::one()) {
            return Err(Error::invalid(
                "eps_u",
                widen(self.eps_u),
                "must be in [0, 1]",
            ));
        }
        if let CountPolicy::Fixed(n) = self.policy
            && (n < self.min_samples || n > self.max_samples)
        {
            return Err(Error::InconsistentParameters {
                names: "policy, min_samples, max_samples",
                expected: "a Fixed(n) policy needs min_samples <= n <= max_samples",
            });
        }
        let (cap_down, cap_up) = match self.max_change {
            None => (T::zero(), T::infinity()),
            Some(c) if c.is_finite() && c > T::zero() => {
                let up = T::one() + c;
                (T::one() / up, up)
            }
            Some(c) => {
                return Err(Error::invalid(
                    "max_change",
                    widen(c),
                    "must be finite and > 0",
                ));
            }
        };
        // An infinite k clamps nothing: it is the clamp off, stored as `None` so that the
        // getter and the uniforms say so.
        let firefly_clamp = match self.firefly_clamp {
            Some(k) if k == T::infinity() => None,
            Some(k) if k.is_finite() && k > T::zero() => Some(k),
            None => None,
            Some(k) => {
                return Err(Error::invalid(
                    "firefly_clamp",
                    widen(k),
                    "must be > 0 (+inf or None for off)",
                ));
            }
        };
        if self.spatial_variance > super::young::AGE_CAP {
            return Err(Error::invalid(
                "spatial_variance",
                f64::from(self.spatial_variance),
                "must be at most the age cap, 255 frames",
            ));
        }
        let floor_f = self.fractional_floor_checked()?;
        self.allocation_exponent_checked()?;
        let resolve_weight = self.resolve_weight_checked()?;
        let two = T::one() + T::one();
        // `2/eta - 2` written as `2 (1 - eta) / eta`: the subtraction form cancels
        // catastrophically as eta nears 1 (in f32 at eta = 1 - 9 * 2^-24 it is off by 11%,
        // enough to flip the sign of the estimate), while `retain = 1 - eta` is exact
        // there (Sterbenz) and the product and quotient add one ulp each.
        let k_minus_1 = two * weight.retain() / weight.eta();
        if !k_minus_1.is_finite() {
            return Err(Error::invalid(
                "eta",
                widen(self.eta),
                "2/eta - 2 must be finite in the float type",
            ));
        }
        Ok(SpvgConfig {
            weight,
            target_variance: target,
            kappa: self.kappa,
            min_samples: self.min_samples,
            max_samples: self.max_samples,
            eps_u: self.eps_u,
            policy: self.policy,
            max_change: self.max_change,
            firefly_clamp,
            age_weight: self.age_weight,
            spatial_variance: self.spatial_variance,
            fractional_floor: self.fractional_floor,
            resolve_weight,
            allocation_exponent: self.allocation_exponent,
            inv_target,
            cap_down,
            cap_up,
            k_minus_1,
            // Counts beyond the type's range (f16 above 65504) become the largest finite
            // value: the comparisons in `estimate` stay ordered.
            min_f: T::from(self.min_samples).map_or(T::max_value(), |v| v.min(T::max_value())),
            max_f: T::from(self.max_samples).map_or(T::max_value(), |v| v.min(T::max_value())),
            floor_f: floor_f.unwrap_or_else(|| {
                T::from(self.min_samples).map_or(T::max_value(), |v| v.min(T::max_value()))
            }),
        })
    }

    /// The fractional floor validated: `None` when off, else the floor in `T`.
    fn fractional_floor_checked(&self) -> Result<Option<T>, Error> {
        let Some(beta) = self.fractional_floor else {
            return Ok(None);
        };
        let max_floor = constant(super::fractional::MAX_FLOOR, T::max_value());
        if !(beta >= T::zero() && beta <= max_floor) {
            return Err(Error::invalid(
                "fractional_floor",
                widen(beta),
                "must be finite and in [0, 8]",
            ));
        }
        if T::from(self.max_samples).is_some_and(|m| beta > m) {
            return Err(Error::InconsistentParameters {
                names: "fractional_floor, max_samples",
                expected: "fractional_floor <= max_samples",
            });
        }
        if self.max_change.is_some() {
            // The damped correction bounds the count per unit of the mean count of a
            // sampled frame, which is at least 1: below one sample it would stop the
            // count at 1 / (1 + c) whatever the floor.
            return Err(Error::InconsistentParameters {
                names: "fractional_floor, max_change",
                expected: "the fractional floor and the damped correction are not combined",
            });
        }
        // The floor in use never lets a count reach 0: the revisit count keeps a pixel
        // whose variance reads 0 sampling (docs/algorithms.md §8.6).
        let revisit = constant(super::fractional::REVISIT_COUNT, T::zero());
        Ok(Some(if beta > revisit { beta } else { revisit }))
    }

    /// The allocation exponent validated: finite, in `(0, 1]`, and 1 with fractional
    /// counts (whose real count does not pass through the allocation).
    fn allocation_exponent_checked(&self) -> Result<(), Error> {
        let p = self.allocation_exponent;
        if !(p > T::zero() && p <= T::one()) {
            return Err(Error::invalid(
                "allocation_exponent",
                widen(p),
                "must be finite and in (0, 1]",
            ));
        }
        if p != T::one() && self.fractional_floor.is_some() {
            return Err(Error::InconsistentParameters {
                names: "allocation_exponent, fractional_floor",
                expected: "an allocation exponent below 1 needs integer counts (no fractional_floor)",
            });
        }
        Ok(())
    }

    /// The resolve weight validated: `None` when off, else `alpha` in `(0, 1]`.
    fn resolve_weight_checked(&self) -> Result<Option<T>, Error> {
        let Some(alpha) = self.resolve_weight else {
            return Ok(None);
        };
        if !(alpha > T::zero() && alpha <= T::one()) {
            return Err(Error::invalid(
                "resolve_weight",
                widen(alpha),
                "must be finite and in (0, 1]",
            ));
        }
        if self.fractional_floor.is_none() {
            return Err(Error::InconsistentParameters {
                names: "resolve_weight, fractional_floor",
                expected: "the resolved-image rule needs fractional counts (a fractional_floor)",
            });
        }
        Ok(Some(alpha))
    }
}

impl<T: Float> SpvgConfig<T> {
    /// A builder starting from the published parameters (see the table on
    /// [`SpvgConfig`]).
    #[must_use]
    pub fn builder() -> SpvgConfigBuilder<T> {
        SpvgConfigBuilder {
            eta: constant(published::ETA, T::one()),
            target_variance: constant(published::TARGET_VARIANCE, T::one()),
            kappa: constant(published::KAPPA, T::zero()),
            min_samples: published::MIN_SAMPLES,
            max_samples: published::MAX_SAMPLES,
            eps_u: constant(published::EPS_U, T::zero()),
            policy: CountPolicy::Spvg,
            max_change: None,
            firefly_clamp: None,
            age_weight: false,
            spatial_variance: super::young::SPATIAL_FRAMES,
            fractional_floor: None,
            resolve_weight: None,
            allocation_exponent: T::one(),
        }
    }

    /// The published parameters: `eta = 0.2`, `sigma0^2 = 1e-4`, `kappa = 0.2`, budget
    /// `[8, 64]`, `eps_u = 0.01`, policy [`CountPolicy::Spvg`]; plus the default spatial
    /// variance of young histories ([`young::SPATIAL_FRAMES`](super::young::SPATIAL_FRAMES)),
    /// which only [`SpvgConfig::update_young`] reads (the published
    /// [`SpvgConfig::update`] is unchanged).
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::SpvgConfig;
    /// let c = SpvgConfig::<f32>::published();
    /// assert_eq!((c.eta(), c.target_variance(), c.kappa()), (0.2, 1e-4, 0.2));
    /// assert_eq!((c.min_samples(), c.max_samples(), c.eps_u()), (8, 64, 0.01));
    /// ```
    #[must_use]
    pub fn published() -> Self {
        // The published values are valid in every float type that represents them.
        Self::builder().build().unwrap_or_else(|_| Self::fallback())
    }

    /// A configuration assembled without validation from values valid in every float
    /// type; only reachable if a float type cannot represent 1 and 2.
    fn fallback() -> Self {
        Self {
            weight: Weight::one(),
            target_variance: T::one(),
            kappa: T::zero(),
            min_samples: published::MIN_SAMPLES,
            max_samples: published::MAX_SAMPLES,
            eps_u: T::zero(),
            policy: CountPolicy::Spvg,
            max_change: None,
            firefly_clamp: None,
            age_weight: false,
            spatial_variance: super::young::SPATIAL_FRAMES,
            fractional_floor: None,
            resolve_weight: None,
            allocation_exponent: T::one(),
            inv_target: T::one(),
            cap_down: T::zero(),
            cap_up: T::infinity(),
            k_minus_1: T::zero(),
            min_f: T::from(published::MIN_SAMPLES).unwrap_or(T::one()),
            max_f: T::from(published::MAX_SAMPLES).unwrap_or(T::one()),
            floor_f: T::from(published::MIN_SAMPLES).unwrap_or(T::one()),
        }
    }

    /// This configuration with another count rule, validated against the budget.
    ///
    /// # Errors
    ///
    /// [`Error::InconsistentParameters`] for a `Fixed(n)` outside `[min_samples,
    /// max_samples]`.
    pub fn with_policy(self, policy: CountPolicy) -> Result<Self, Error> {
        self.to_builder().policy(policy).build()
    }

    /// A builder holding this configuration's fields, to change a few of them.
    #[must_use]
    pub fn to_builder(&self) -> SpvgConfigBuilder<T> {
        SpvgConfigBuilder {
            eta: self.weight.eta(),
            target_variance: self.target_variance,
            kappa: self.kappa,
            min_samples: self.min_samples,
            max_samples: self.max_samples,
            eps_u: self.eps_u,
            policy: self.policy,
            max_change: self.max_change,
            firefly_clamp: self.firefly_clamp,
            age_weight: self.age_weight,
            spatial_variance: self.spatial_variance,
            fractional_floor: self.fractional_floor,
            resolve_weight: self.resolve_weight,
            allocation_exponent: self.allocation_exponent,
        }
    }

    /// The history weight `eta`.
    #[inline]
    #[must_use]
    pub fn eta(&self) -> T {
        self.weight.eta()
    }

    getters! {
        /// The validated history weight (`eta` with `1 - eta` and `eta (1 - eta)`).
        weight: Weight<T>;
        /// The target variance `sigma0^2`.
        target_variance: T;
        /// The control factor `kappa`.
        kappa: T;
        /// The smallest count `beta_min` of a sampling pixel.
        min_samples: u32;
        /// The largest count `beta_max`.
        max_samples: u32;
        /// The zero-sample threshold `eps_u` on the distant energy ratio `gamma`.
        eps_u: T;
        /// The count rule.
        policy: CountPolicy;
        /// The damped correction's cap `c` (docs/algorithms.md §8.1), `None` when off.
        max_change: Option<T>;
        /// The firefly clamp's `k` (docs/algorithms.md §8.3), `None` when off.
        firefly_clamp: Option<T>;
        /// Whether the age-aware weight is on (docs/algorithms.md §8.4).
        age_weight: bool;
        /// The largest age that takes the spatial variance (docs/algorithms.md §8.4); 0
        /// when off.
        spatial_variance: u32;
        /// The fractional floor `beta` (docs/algorithms.md §8.6), `None` when counts are
        /// integers.
        fractional_floor: Option<T>;
        /// The resolve's steady weight `alpha` of the resolved-image rule
        /// (docs/algorithms.md §8.7), `None` when each frame aims at `sigma0^2`.
        resolve_weight: Option<T>;
        /// The allocation exponent `p` (docs/algorithms.md §8.2), 1 when equalising.
        allocation_exponent: T;
        /// Derived constant `1 / (1 + c)` of the damped correction, computed once in `T`
        /// as `1 / (1 + c)` (0 when `max_change` is `None`).
        cap_down: T;
        /// Derived constant `1 + c` of the damped correction, computed once in `T`
        /// (`+inf` when `max_change` is `None`).
        cap_up: T;
        /// Derived constant `1 / sigma0^2`, computed once in `T`. The estimate no longer
        /// uses it (it divides by `sigma0^2`, see
        /// [`raw_estimate`](SpvgConfig::raw_estimate)); validation still requires it to be
        /// finite, and it remains for callers that scale by it.
        inv_target: T;
        /// Derived constant `k - 1 = 2/eta - 2`, computed in `T` as `(2 * (1 - eta)) / eta`.
        k_minus_1: T;
    }

    /// `min_samples` converted to `T` (saturated to the largest finite value).
    #[inline]
    #[must_use]
    pub fn min_samples_f(&self) -> T {
        self.min_f
    }

    /// `max_samples` converted to `T` (saturated to the largest finite value).
    #[inline]
    #[must_use]
    pub fn max_samples_f(&self) -> T {
        self.max_f
    }

    /// The lower bound of a real count: the fractional floor where it is set (at least
    /// [`fractional::REVISIT_COUNT`](super::fractional::REVISIT_COUNT), so that no pixel
    /// stalls), else [`min_samples_f`](Self::min_samples_f).
    #[inline]
    #[must_use]
    pub fn floor_f(&self) -> T {
        self.floor_f
    }
}

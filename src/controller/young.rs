//! The young-history rules (docs/algorithms.md §8.4): a history's age, the age-aware
//! weight and the spatial variance of young histories, each written once here.
//!
//! A history seeded at a disocclusion holds one frame's observation and the seed's
//! variance `sigma0^2`, which says nothing about the pixel: with the weight `eta` the
//! temporal variance needs about `1/eta` frames to forget it, and until then the count
//! follows the seed rather than the pixel. The rules here let a renderer count the
//! frames a history has absorbed (its *age*) and treat young histories differently:
//!
//! - [`age_weight`]: the update weight `max(eta, 1 / (age + 1))`, the plain mean of the
//!   frames absorbed so far while that weighs more than `eta`;
//! - [`SpatialMoments`] and [`young_variance`]: the variance of this frame's monitored
//!   values over the pixel's same-surface neighbours, used instead of the seed's
//!   `sigma0^2` (and the temporal estimate) while the history is at most a few frames old.
//!
//! The age is stored in the history texel's spare channel by the GPU component
//! (`spvg-wgpu`'s adaptive pass): age 0 is "never written", so an age of 1 or more is
//! also the mark that tells a written texel from a cleared one. The core texel encoding
//! ([`crate::texel`]) keeps writing 0 there: it stores a [`SpvgHistory`](super::SpvgHistory),
//! which has no age, and a renderer that keeps ages in its own buffer passes them to
//! [`SpvgConfig::update_young`](super::SpvgConfig::update_young).
//!
//! WGSL twins: `spvg_read_age`, `spvg_next_age`, `spvg_age_weight`, `spvg_spatial_push`,
//! `spvg_spatial_variance` and `spvg_update_young` in `spvg-shaders/wgsl/update.wgsl`.

use num_traits::Float;

use crate::stats::{Weight, rules::saturate};

/// The largest age stored: ages saturate here (an `f16` stores every integer up to 2048
/// exactly, so the cap fits the spare channel of an `f16` texel with room to spare, and
/// no young-history rule looks further than a few frames).
pub const AGE_CAP: u32 = 255;

/// The default age limit of the spatial variance
/// ([`SpvgConfigBuilder::spatial_variance`](super::SpvgConfigBuilder::spatial_variance)):
/// the seed and its first two updates take their same-surface neighbourhood's variance.
/// SVGF and ReLAX switch to the temporal variance after about four frames; three is where
/// the temporal estimate has absorbed three frames. On by default because it never lost
/// on a scene the report measures and it alone keeps a full-frame disocclusion (one
/// frame of absurd motion) from sending every pixel to `beta_min` for the frames after
/// (docs/algorithms.md §8.4).
pub const SPATIAL_FRAMES: u32 = 3;

/// The age a stored spare channel reads as: 0 (never written) unless it is `>= 0.5`,
/// else its integer part, at least 1 and at most [`AGE_CAP`] (NaN reads as 0, `+inf` as
/// the cap).
///
/// # Examples
///
/// ```
/// use spvg::controller::young::read_age;
/// assert_eq!(read_age(0.0_f32), 0);
/// assert_eq!(read_age(1.0_f32), 1);
/// assert_eq!(read_age(0.7_f32), 1);
/// assert_eq!(read_age(17.9_f32), 17);
/// assert_eq!(read_age(f32::INFINITY), 255);
/// assert_eq!(read_age(f32::NAN), 0);
/// ```
#[inline(always)]
#[must_use]
pub fn read_age<T: Float>(stored: T) -> u32 {
    let half = T::from(0.5).unwrap_or_else(T::zero);
    let cap = T::from(AGE_CAP).unwrap_or_else(T::max_value);
    // NaN fails both comparisons and reads as never written.
    if stored >= cap {
        AGE_CAP
    } else if stored >= half {
        stored.to_u32().unwrap_or(AGE_CAP).max(1)
    } else {
        0
    }
}

/// The age after a frame of the update: a seeded history (an invalid one that absorbed
/// the frame) is 1 frame old, a valid one that absorbed it one frame older (saturating
/// at [`AGE_CAP`]); a refused frame keeps a valid history's age and leaves an invalid one
/// at 0, as it leaves the history itself.
///
/// # Examples
///
/// ```
/// use spvg::controller::young::next_age;
/// assert_eq!(next_age(0, false, true), 1);
/// assert_eq!(next_age(3, true, true), 4);
/// assert_eq!(next_age(255, true, true), 255);
/// assert_eq!(next_age(3, true, false), 3);
/// assert_eq!(next_age(3, false, false), 0);
/// ```
#[inline(always)]
#[must_use]
pub fn next_age(age: u32, valid: bool, accepted: bool) -> u32 {
    match (valid, accepted) {
        (true, true) => age.saturating_add(1).min(AGE_CAP),
        (false, true) => 1,
        (true, false) => age.min(AGE_CAP),
        (false, false) => 0,
    }
}

/// The age-aware weight of the update of a valid history `age` frames old: `max(eta,
/// 1 / (a + 1))` with `a = max(age, 1)` (a valid history has absorbed at least its seed),
/// in this order in `T`:
///
/// ```text
/// young = 1 / (f(a) + 1)
/// weight = if young > eta { Weight(young) } else { w }   // retain = 1 - young, eta_retain = young * retain
/// ```
///
/// While `young > eta` the mean is the plain average of the frames absorbed and the
/// variance mostly this history's own: on its second frame a seeded history keeps half
/// of the seed's `sigma0^2` instead of `1 - eta` of it.
///
/// # Examples
///
/// ```
/// use spvg::controller::young::age_weight;
/// use spvg::stats::Weight;
/// let w = Weight::new(0.2_f32).unwrap();
/// assert_eq!(age_weight(&w, 1).eta(), 0.5);
/// assert_eq!(age_weight(&w, 3).eta(), 0.25);
/// assert_eq!(age_weight(&w, 4).eta(), 0.2);
/// assert_eq!(age_weight(&w, 200), w);
/// ```
#[inline(always)]
#[must_use]
pub fn age_weight<T: Float>(w: &Weight<T>, age: u32) -> Weight<T> {
    let a = T::from(age.clamp(1, AGE_CAP)).unwrap_or_else(T::one) + T::one();
    let young = T::one() / a;
    if young > w.eta() {
        // `young` is in (0, 1/2]: always a valid weight.
        Weight::new(young).unwrap_or(*w)
    } else {
        *w
    }
}

/// The moments of a pixel's same-surface neighbourhood in this frame, accumulated one
/// monitored value at a time relative to the pixel's own value (`centre`), so that the
/// sums stay small where the neighbourhood is nearly constant.
///
/// The caller decides which neighbours count (the component: the pixel itself and the
/// neighbours of its [`spatial_window`] that took samples this frame and pass the
/// reprojection's depth test against the pixel's depth) and pushes them in row-major
/// order.
///
/// # Examples
///
/// ```
/// use spvg::controller::young::SpatialMoments;
/// let m = [1.0_f32, 2.0, 3.0]
///     .iter()
///     .fold(SpatialMoments::default(), |m, &v| m.push(2.0, v));
/// assert_eq!(m.variance(), Some(1.0)); // the sample variance of 1, 2, 3
/// assert_eq!(SpatialMoments::default().push(2.0, 2.0).variance(), None);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpatialMoments<T> {
    /// The number of values pushed.
    pub count: u32,
    /// The sum of `value - centre`.
    pub sum: T,
    /// The sum of `(value - centre)^2`.
    pub sum_sq: T,
}

impl<T: Float> SpatialMoments<T> {
    /// Adds `value` (a non-finite value is skipped), in this order in `T`:
    /// `d = sat(value - centre)`, `sum = sat(sum + d)`, `sum_sq = sat(sum_sq + sat(d * d))`.
    #[inline(always)]
    #[must_use]
    pub fn push(self, centre: T, value: T) -> Self {
        if !value.is_finite() {
            return self;
        }
        let d = saturate(value - centre);
        Self {
            count: self.count.saturating_add(1),
            sum: saturate(self.sum + d),
            sum_sq: saturate(self.sum_sq + saturate(d * d)),
        }
    }

    /// The sample variance of the values pushed (divided by `count - 1`), or `None` for
    /// fewer than two values, in this order in `T` with `m = f(count)`:
    ///
    /// ```text
    /// v = (sum_sq - sat(sum * sum) / m) / (m - 1)
    /// variance = if v > 0 { sat(v) } else { 0 }
    /// ```
    #[inline(always)]
    #[must_use]
    pub fn variance(&self) -> Option<T> {
        if self.count < 2 {
            return None;
        }
        let m = T::from(self.count).unwrap_or_else(T::max_value);
        let v = (self.sum_sq - saturate(self.sum * self.sum) / m) / (m - T::one());
        Some(if v > T::zero() {
            saturate(v)
        } else {
            T::zero()
        })
    }
}

/// The window of `pixel` whose values of this frame its spatial moments take: the 3x3
/// window around it, clipped to its [`TILE`](crate::dilation::TILE) x `TILE` tile
/// ([`tile_region`](crate::dilation::tile_region) without a halo), which clips it to the
/// `size[0] x size[1]` frame too; `[low corner, high corner]`, both inclusive.
///
/// The moments need this frame's *values*, which exist only after the sampling; a
/// one-pass dispatch holds them for its own tile alone (a halo would have to sample it),
/// so the window stops at the tile's edge, in both forms of the component.
///
/// # Examples
///
/// ```
/// use spvg::controller::young::spatial_window;
/// assert_eq!(spatial_window([9, 3], [100, 100]), [[8, 2], [10, 4]]);
/// // (7, 7) is the corner of its tile: its window is 2 x 2.
/// assert_eq!(spatial_window([7, 7], [100, 100]), [[6, 6], [7, 7]]);
/// ```
#[inline]
#[must_use]
pub fn spatial_window(pixel: [u32; 2], size: [u32; 2]) -> [[u32; 2]; 2] {
    let [lo, hi] = crate::dilation::tile_region(pixel, size, 0);
    [
        core::array::from_fn(|k| pixel[k].saturating_sub(1).max(lo[k])),
        core::array::from_fn(|k| pixel[k].saturating_add(1).min(hi[k])),
    ]
}

/// The variance a history keeps after the update: the spatial one where the history is
/// young (`1 <= age <= frames`, `age` the age after the update) and the neighbourhood
/// gave one, else the temporal (or seeded) `variance`.
///
/// # Examples
///
/// ```
/// use spvg::controller::young::young_variance;
/// assert_eq!(young_variance(2, 1, 1e-4_f32, Some(5e-3)), 5e-3);
/// assert_eq!(young_variance(2, 3, 1e-4_f32, Some(5e-3)), 1e-4);
/// assert_eq!(young_variance(2, 1, 1e-4_f32, None), 1e-4);
/// assert_eq!(young_variance(0, 1, 1e-4_f32, Some(5e-3)), 1e-4);
/// ```
#[inline(always)]
#[must_use]
pub fn young_variance<T: Float>(frames: u32, age: u32, variance: T, spatial: Option<T>) -> T {
    match spatial {
        Some(s) if age >= 1 && age <= frames => s,
        _ => variance,
    }
}

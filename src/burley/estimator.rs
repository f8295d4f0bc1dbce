//! Monte Carlo estimators of the scattered radiance (docs/algorithms.md §5): the plain importance-sampled
//! mean, the depth-aware ratio estimator, and the mip level of filtered sampling (AFIS).

use num_traits::Float;

use super::{BurleyProfile, lit};
use crate::stats::saturate;

/// The plain importance-sampled estimate `L_o = A * mean(L_j)` for radii drawn from the
/// profile's own pdf, where every weight `2 pi r R(r) / pdf(r)` equals `A` (docs/algorithms.md §5).
///
/// The mean is kept as a running mean, `m_k = m_{k-1} + (L_k - m_{k-1}) / k`, so constant
/// lighting `L` gives exactly `A * L` (every step adds `0`) and large sums cannot overflow.
///
/// # Examples
///
/// ```
/// use spvg::burley::{BurleyProfile, PlainEstimator};
/// let p = BurleyProfile::from_shape(0.7_f64, 1.0).unwrap();
/// let mut est = PlainEstimator::new(&p);
/// assert_eq!(est.finish(), None);
/// for _ in 0..10 {
///     assert!(est.add(0.3));
/// }
/// assert_eq!(est.finish(), Some(0.7 * 0.3));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlainEstimator<T> {
    albedo: T,
    mean: T,
    count: u32,
}

impl<T: Float> PlainEstimator<T> {
    /// An empty estimator for `profile` (only its albedo is used).
    #[inline]
    #[must_use]
    pub fn new(profile: &BurleyProfile<T>) -> Self {
        Self {
            albedo: profile.albedo(),
            mean: T::zero(),
            count: 0,
        }
    }

    /// Adds the lighting `L_j` read at one sample. Returns `false`, leaving the state
    /// unchanged, when `lighting` is not finite or `u32::MAX` samples were already added.
    #[inline]
    pub fn add(&mut self, lighting: T) -> bool {
        if !lighting.is_finite() || self.count == u32::MAX {
            return false;
        }
        self.count += 1;
        let k = T::from(self.count).unwrap_or_else(T::max_value);
        self.mean = saturate(self.mean + saturate(lighting - self.mean) / k);
        true
    }

    /// The number of samples added.
    #[inline]
    #[must_use]
    pub fn count(&self) -> u32 {
        self.count
    }

    /// `A * mean(L_j)`, or `None` when no sample was added.
    #[inline]
    #[must_use]
    pub fn finish(&self) -> Option<T> {
        (self.count > 0).then(|| self.albedo * self.mean)
    }
}

/// The depth-aware ratio estimator (docs/algorithms.md §5): weights
/// `w_j = 1_s(q_j) r'_j R(r'_j) / pdf(r_j)` with `r'_j = sqrt(r_j^2 + dz_j^2)`, and
/// `L_o = A * sum w_j L_j / sum w_j`.
///
/// Samples whose depth differs much from the shaded pixel's (`dz` large) get the weight
/// of a far-away point and so contribute almost nothing: light does not bleed across
/// depth discontinuities. With `dz = 0` everywhere and radii drawn from the profile's pdf,
/// every weight is the same and the estimate equals [`PlainEstimator`]'s.
///
/// Two deliberate differences from the literal formula of docs/algorithms.md §5, neither changing its value:
/// - the weights drop the factor `A` of `R` (they are [`weight`](Self::weight)
///   `= w_j / A`), because it cancels in the ratio, and `A = 0` (ketchup's blue channel)
///   would otherwise make every weight 0;
/// - [`finish`](Self::finish) multiplies the ratio by `A`. docs/algorithms.md §5 writes
///   `L_o = sum w_j L_j / sum w_j`, which is a weighted mean of the lighting, without
///   the total reflectance `A` that the plain estimate `A * mean(L)` carries; the bare
///   ratio is [`mean_lighting`](Self::mean_lighting).
///
/// The ratio is kept as a running weighted mean, `W += w; m += (w / W) (L - m)`, so
/// constant lighting gives it exactly.
///
/// # Examples
///
/// ```
/// use spvg::burley::{BurleyProfile, RatioEstimator};
/// let p = BurleyProfile::from_shape(0.5_f64, 1.0).unwrap();
/// let mut est = RatioEstimator::new(&p);
/// // Same surface (dz = 0): lighting 1.
/// assert!(est.add(0.5, 0.0, true, p.pdf(0.5), 1.0));
/// // Across a depth edge 50 d away: lighting 100, but a negligible weight.
/// assert!(est.add(0.5, 50.0, true, p.pdf(0.5), 100.0));
/// // Not a subsurface pixel: weight 0.
/// assert!(est.add(0.5, 0.0, false, p.pdf(0.5), 100.0));
/// let lo = est.finish().unwrap();
/// assert!((lo - 0.5).abs() < 1e-5, "{lo}");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RatioEstimator<T> {
    profile: BurleyProfile<T>,
    sum_weights: T,
    mean: T,
}

impl<T: Float> RatioEstimator<T> {
    /// An empty estimator for `profile`.
    #[inline]
    #[must_use]
    pub fn new(profile: &BurleyProfile<T>) -> Self {
        Self {
            profile: *profile,
            sum_weights: T::zero(),
            mean: T::zero(),
        }
    }

    /// The weight of one sample divided by `A`:
    /// `1_s (e^{-r'/d} + e^{-r'/(3d)}) / (8 pi d pdf)` with `r' = hypot(r, dz)`, which is
    /// `1_s r' R(r') / (A pdf)`.
    ///
    /// Total: 0 when `is_subsurface` is false; otherwise plain arithmetic: NaN
    /// propagates, and `pdf <= 0` gives an infinite, NaN or negative value, all of which
    /// [`add`](Self::add) rejects before they can reach the state.
    #[inline]
    #[must_use]
    pub fn weight(&self, r: T, dz: T, is_subsurface: bool, pdf: T) -> T {
        if !is_subsurface {
            return T::zero();
        }
        let x = r.hypot(dz) * self.profile.inv_shape();
        let kernel = ((-x).exp() + (-x / lit(3.0)).exp()) * self.profile.inv_shape()
            / lit(8.0 * core::f64::consts::PI);
        kernel / pdf
    }

    /// Adds one sample: `r` its radius, `dz` the depth difference to the shaded pixel,
    /// `is_subsurface` whether the sample lands on a subsurface pixel, `pdf` the density
    /// `r` was drawn with, `lighting` the lighting read there.
    ///
    /// Returns `false`, leaving the state unchanged, when an input is not finite, `r < 0`,
    /// `pdf <= 0`, or the weight is not finite. A sample with weight 0 (not subsurface, or
    /// `r'` so large that the profile underflows) is accepted and changes nothing.
    #[inline]
    pub fn add(&mut self, r: T, dz: T, is_subsurface: bool, pdf: T, lighting: T) -> bool {
        let finite = r.is_finite() && dz.is_finite() && pdf.is_finite() && lighting.is_finite();
        if !finite || r < T::zero() || pdf <= T::zero() {
            return false;
        }
        let w = self.weight(r, dz, is_subsurface, pdf);
        if !w.is_finite() {
            return false;
        }
        if w == T::zero() {
            return true;
        }
        let sum = saturate(self.sum_weights + w);
        self.mean = saturate(self.mean + (w / sum) * saturate(lighting - self.mean));
        self.sum_weights = sum;
        true
    }

    /// The sum of the weights added so far (divided by `A`, see [`weight`](Self::weight)).
    #[inline]
    #[must_use]
    pub fn sum_weights(&self) -> T {
        self.sum_weights
    }

    /// The bare ratio `sum w_j L_j / sum w_j` of docs/algorithms.md §5, a weighted mean of the lighting;
    /// `None` when the sum of weights is 0 (no sample, or none on a subsurface pixel at a
    /// reachable distance: the caller falls back, for example to the pixel's own lighting).
    #[inline]
    #[must_use]
    pub fn mean_lighting(&self) -> Option<T> {
        (self.sum_weights > T::zero()).then_some(self.mean)
    }

    /// The estimate `L_o = A * sum w_j L_j / sum w_j`, comparable with
    /// [`PlainEstimator::finish`]; `None` when the sum of weights is 0 (see
    /// [`mean_lighting`](Self::mean_lighting)).
    #[inline]
    #[must_use]
    pub fn finish(&self) -> Option<T> {
        self.mean_lighting().map(|m| self.profile.albedo() * m)
    }
}

/// The mip level of filtered importance sampling (AFIS, docs/algorithms.md §5):
/// `level = 0.5 max(-log2(a pdf n / (lmax^2 t)), 0)` with `a = 1/16`, `pdf` the density of
/// the sample, `n` the sample count, `lmax` the largest mean free path of the RGB profile
/// and `t` the texel area at the sample depth. Fewer samples read coarser mips.
///
/// Evaluated as `q = pdf * n / (16 * lmax * lmax * t)`, then `0.5 * max(-log2(q), 0)`.
/// Total, in `[0, +inf]`:
/// - `q` NaN (a NaN input, or `0/0`, `inf/inf`): 0, the finest level, which filters
///   nothing;
/// - `q <= 0` (`n = 0`, `pdf <= 0`, a negative `t`): `+inf`, which a texture fetch clamps
///   to the coarsest level;
/// - `q = +inf` (`lmax = 0` or `t = 0`): 0.
///
/// # Examples
///
/// ```
/// use spvg::burley::filtered_mip_level;
/// // q = 1 * 1 / (16 * 1 * 1) = 2^-4: level 2.
/// assert_eq!(filtered_mip_level(1.0_f64, 1, 1.0, 1.0), 2.0);
/// // Enough samples: the finest level.
/// assert_eq!(filtered_mip_level(1.0_f64, 64, 1.0, 1.0), 0.0);
/// ```
#[inline]
#[must_use]
pub fn filtered_mip_level<T: Float>(pdf: T, n: u32, lmax: T, texel_area: T) -> T {
    let n = T::from(n).unwrap_or_else(T::max_value);
    let q = pdf * n / (lit::<T>(16.0) * lmax * lmax * texel_area);
    if q.is_nan() {
        T::zero()
    } else if q <= T::zero() {
        T::infinity()
    } else {
        lit::<T>(0.5) * (-q.log2()).max(T::zero())
    }
}

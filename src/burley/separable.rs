//! The separable profile engines ship (separable subsurface scattering, Jimenez et al.
//! 2015) and its pre-integrated one-dimensional kernel (docs/algorithms.md §5.1).
//!
//! The profile is a sum of five Gaussians of the radius scaled by `s = 0.001 + f`, with a
//! per-channel falloff `f` in `(0, 1]` and radii in millimetres:
//!
//! `R_S(r; f) = sum_k w_k G(v_k, r / s)`, `G(v, r) = e^{-r^2 / (2 v)} / (2 pi v)`.
//!
//! Its rank-1 separable kernel is the profile integrated across one axis,
//! `a(x) = int R_S(sqrt(x^2 + y^2)) dy = s sum_k w_k e^{-x^2 / (2 v_k s^2)} / sqrt(2 pi v_k)`,
//! a closed form because each term is a Gaussian; the filter applies `a(x) a(y) / ||R_S||_1`
//! with `||R_S||_1 = int a = s^2 sum_k w_k`. The discrete kernel samples `a` at offsets that
//! crowd towards the centre and weights each by the width of the interval it stands for.

use core::f64::consts::PI;

use num_traits::Float;

use super::lit;
use crate::Error;

/// The `(variance, weight)` pairs of the separable skin profile, variances in mm^2.
///
/// d'Eon & Luebke's six-Gaussian skin fit without its narrowest term `(0.0064, 0.233)`:
/// the shipped filter replaces that one by blending with the unfiltered pixel
/// (its `strength`), so the profile the filter spreads is these five.
pub const SEPARABLE_GAUSSIANS: [(f64, f64); 5] = [
    (0.0484, 0.100),
    (0.187, 0.118),
    (0.567, 0.113),
    (1.99, 0.358),
    (7.41, 0.078),
];

/// The offset added to the falloff before it scales the radius: `s = 0.001 + f` keeps the
/// Gaussians finite as `f` goes to 0.
pub const FALLOFF_EPSILON: f64 = 0.001;

/// The kernel range (mm) for a given number of samples: 2, or 3 above 20 samples (more
/// samples can afford to reach further into the tail).
#[inline]
#[must_use]
pub fn kernel_range(samples: usize) -> f64 {
    if samples > 20 { 3.0 } else { 2.0 }
}

/// The separable profile `R_S(r; f)` of one colour channel, with a validated falloff.
///
/// # Examples
///
/// ```
/// use spvg::burley::SeparableProfile;
/// let p = SeparableProfile::new(0.5_f64).unwrap();
/// // The radial integral is s^2 sum w_k with s = 0.001 + f.
/// let s: f64 = 0.501;
/// assert!((p.total() - s * s * 0.767).abs() < 1e-12);
/// // The pre-integrated 1D kernel integrates to the same total.
/// let n = 4000;
/// let h = 40.0 / n as f64;
/// let integral: f64 = (0..n).map(|i| p.kernel_1d(-20.0 + (i as f64 + 0.5) * h) * h).sum();
/// assert!((integral - p.total()).abs() < 1e-9);
/// assert!(SeparableProfile::new(0.0_f64).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeparableProfile<T> {
    falloff: T,
    scale: T,
    inv_scale: T,
}

impl<T: Float> SeparableProfile<T> {
    /// The profile of falloff `f`.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `falloff` when it is NaN or outside `(0, 1]`.
    pub fn new(falloff: T) -> Result<Self, Error> {
        if !(falloff > T::zero() && falloff <= T::one()) {
            return Err(Error::invalid(
                "falloff",
                falloff.to_f64().unwrap_or(f64::NAN),
                "must be in (0, 1]",
            ));
        }
        let scale = falloff + lit(FALLOFF_EPSILON);
        Ok(Self {
            falloff,
            scale,
            inv_scale: T::one() / scale,
        })
    }

    /// The falloff `f`.
    #[inline]
    #[must_use]
    pub fn falloff(&self) -> T {
        self.falloff
    }

    /// The radius scale `s = 0.001 + f`.
    #[inline]
    #[must_use]
    pub fn scale(&self) -> T {
        self.scale
    }

    /// `R_S(r) = sum_k w_k e^{-(r/s)^2 / (2 v_k)} / (2 pi v_k)`, `r` in mm.
    ///
    /// Total: even in `r`; NaN for NaN `r`; 0 for infinite `r`.
    #[inline]
    #[must_use]
    pub fn profile(&self, r: T) -> T {
        let x = r * self.inv_scale;
        let x2 = x * x;
        let mut sum = T::zero();
        for (v, w) in SEPARABLE_GAUSSIANS {
            let v: T = lit(v);
            sum = sum + lit::<T>(w) * (-x2 / (v + v)).exp() / (lit::<T>(2.0 * PI) * v);
        }
        sum
    }

    /// The radial integral `int 2 pi r R_S(r) dr = s^2 sum_k w_k` (each scaled Gaussian
    /// integrates to `s^2`).
    #[inline]
    #[must_use]
    pub fn total(&self) -> T {
        let sum_w = SEPARABLE_GAUSSIANS.iter().map(|g| g.1).sum::<f64>();
        self.scale * self.scale * lit(sum_w)
    }

    /// The profile integrated across one axis,
    /// `a(x) = int R_S(sqrt(x^2 + y^2)) dy = s sum_k w_k e^{-(x/s)^2 / (2 v_k)} / sqrt(2 pi v_k)`.
    ///
    /// Even in `x`; integrates to [`total`](Self::total) over the real line.
    #[inline]
    #[must_use]
    pub fn kernel_1d(&self, x: T) -> T {
        let u = x * self.inv_scale;
        let u2 = u * u;
        let mut sum = T::zero();
        for (v, w) in SEPARABLE_GAUSSIANS {
            let v: T = lit(v);
            sum = sum + lit::<T>(w) * (-u2 / (v + v)).exp() / (lit::<T>(2.0 * PI) * v).sqrt();
        }
        sum * self.scale
    }

    /// Fills the discrete rank-1 kernel: `offsets[i]` (mm) and `weights[i]`, normalised to
    /// sum to 1, with `n = offsets.len()` samples over the range `R = kernel_range(n)`.
    ///
    /// With `x_i = -R + 2 R i / (n - 1)`, the offsets are `o_i = sign(x_i) x_i^2 / R` (dense
    /// near the centre, where the profile is steep) and each weight is `a(o_i)` times half
    /// the distance between the neighbouring offsets (the interval the sample stands for),
    /// divided by the sum of them all. The centre sample is `i = (n - 1) / 2`, offset 0.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `samples` when `n` is even or below 3 (the
    /// kernel needs a centre sample), and [`Error::InconsistentParameters`] when the two
    /// slices differ in length.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::burley::SeparableProfile;
    /// let p = SeparableProfile::new(0.8_f32).unwrap();
    /// let (mut o, mut w) = ([0.0_f32; 11], [0.0_f32; 11]);
    /// p.fill_kernel(&mut o, &mut w).unwrap();
    /// assert_eq!((o[0], o[5], o[10]), (-2.0, 0.0, 2.0));
    /// assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
    /// assert!(p.fill_kernel(&mut o[..10], &mut w[..10]).is_err());
    /// ```
    pub fn fill_kernel(&self, offsets: &mut [T], weights: &mut [T]) -> Result<(), Error> {
        let n = offsets.len();
        if n < 3 || n.is_multiple_of(2) {
            return Err(Error::invalid(
                "samples",
                n as f64,
                "must be odd and at least 3",
            ));
        }
        if weights.len() != n {
            return Err(Error::InconsistentParameters {
                names: "offsets, weights",
                expected: "slices of the same length",
            });
        }
        let range: T = lit(kernel_range(n));
        let step = (range + range) / lit((n - 1) as f64);
        let centre = (n - 1) / 2;
        for (i, o) in offsets.iter_mut().enumerate() {
            // Built from the centre out so that the kernel is exactly symmetric.
            let x = step * lit(i.abs_diff(centre) as f64);
            let o_abs = x * x / range;
            *o = if i < centre { -o_abs } else { o_abs };
        }
        let mut sum = T::zero();
        for i in 0..n {
            let left = if i > 0 {
                offsets[i] - offsets[i - 1]
            } else {
                T::zero()
            };
            let right = if i + 1 < n {
                offsets[i + 1] - offsets[i]
            } else {
                T::zero()
            };
            let w = self.kernel_1d(offsets[i]) * (left + right) * lit(0.5);
            weights[i] = w;
            sum = sum + w;
        }
        // sum > 0: the centre weight alone is a(0) * step^2 / R > 0 for every valid f.
        for w in weights.iter_mut() {
            *w = *w / sum;
        }
        Ok(())
    }
}

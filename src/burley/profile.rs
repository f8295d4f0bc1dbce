//! The profile itself: shape fits, validated parameters, `R(r)`, `pdf(r)` and `cdf(r)`.

use core::f64::consts::PI;

use num_traits::Float;

use super::lit;
use crate::Error;

/// Which of Christensen & Burley's (2015) fits maps albedo `A` and mean free path `l` to
/// the profile shape `d = l / s(A)`.
///
/// | fit | `s(A)` |
/// |---|---|
/// | [`Searchlight`](Self::Searchlight) | `1.85 - A + 7 abs(A - 0.8)^3` |
/// | [`DiffuseTransmission`](Self::DiffuseTransmission) | `1.9 - A + 3.5 (A - 0.8)^2` |
/// | [`DiffuseMeanFreePath`](Self::DiffuseMeanFreePath) | `3.5 + 100 (A - 0.33)^4` |
///
/// The last one, with `l` the diffuse mean free path measured on the surface, is the
/// artist-friendly parametrization and the default (docs/algorithms.md §5). For `A` in `[0, 1]` every
/// `s(A)` lies in `[0.85, 5.6]`, so `d` is finite and positive whenever `l` is.
///
/// # Examples
///
/// ```
/// use spvg::burley::ShapeFit;
/// assert_eq!(ShapeFit::default(), ShapeFit::DiffuseMeanFreePath);
/// // At A = 0.33 the quartic term of the default fit vanishes: d = l / 3.5.
/// assert!((ShapeFit::DiffuseMeanFreePath.shape(0.33_f64, 7.0) - 2.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShapeFit {
    /// Searchlight configuration: `s = 1.85 - A + 7 |A - 0.8|^3`.
    Searchlight,
    /// Diffuse transmission: `s = 1.9 - A + 3.5 (A - 0.8)^2`.
    DiffuseTransmission,
    /// Diffuse mean free path on the surface: `s = 3.5 + 100 (A - 0.33)^4` (default).
    #[default]
    DiffuseMeanFreePath,
}

impl ShapeFit {
    /// The scaling factor `s(A)` of the fit, so that `d = l / s(A)`.
    ///
    /// NaN in gives NaN out; no range check (the constructors of [`BurleyProfile`] do it).
    #[inline]
    #[must_use]
    pub fn scale<T: Float>(self, albedo: T) -> T {
        match self {
            Self::Searchlight => {
                let t = (albedo - lit(0.8)).abs();
                lit::<T>(1.85) - albedo + lit::<T>(7.0) * t * t * t
            }
            Self::DiffuseTransmission => {
                let t = albedo - lit(0.8);
                lit::<T>(1.9) - albedo + lit::<T>(3.5) * t * t
            }
            Self::DiffuseMeanFreePath => {
                let t = albedo - lit(0.33);
                let t2 = t * t;
                lit::<T>(3.5) + lit::<T>(100.0) * t2 * t2
            }
        }
    }

    /// The profile shape `d = mean_free_path / s(albedo)`.
    ///
    /// Unvalidated arithmetic: NaN in gives NaN out. Use [`BurleyProfile::new`] to get a
    /// checked profile.
    #[inline]
    #[must_use]
    pub fn shape<T: Float>(self, albedo: T, mean_free_path: T) -> T {
        mean_free_path / self.scale(albedo)
    }
}

/// Burley's normalized diffusion profile for one color channel: albedo `A` in `[0, 1]` and
/// shape `d > 0` (a length, in the unit of the radii passed to it).
///
/// Construction validates the parameters once; every evaluation is a total function that
/// never panics. With `x = r / d` (computed as `r * (1/d)`, the reciprocal stored at
/// construction):
///
/// - [`profile`](Self::profile) `R(r) = A (e^{-x} + e^{-x/3}) / (8 pi d r)`;
/// - [`pdf`](Self::pdf) `= (e^{-x} + e^{-x/3}) / (4 d)`;
/// - [`cdf`](Self::cdf) `= 1 - e^{-x}/4 - 3 e^{-x/3}/4`, evaluated as
///   `-(expm1(-x) + 3 expm1(-x/3)) / 4` so that it keeps full relative accuracy near 0;
/// - [`distant_ratio`](Self::distant_ratio) `= 1 - cdf(r)`, evaluated directly as
///   `(e^{-x} + 3 e^{-x/3}) / 4` so that it keeps full relative accuracy in the tail.
///
/// Nothing divides by `A`: `A = 0` (ketchup's blue channel) is a valid profile whose
/// `R` is identically zero while `pdf` and `cdf` stay those of the shape `d`.
///
/// # Examples
///
/// ```
/// use spvg::burley::{BurleyProfile, ShapeFit};
/// let p = BurleyProfile::from_shape(0.5_f64, 2.0).unwrap();
/// assert_eq!(p.shape(), 2.0);
/// // pdf(0) = 2 / (4 d); the cdf starts at 0 and tends to 1.
/// assert_eq!(p.pdf(0.0), 0.25);
/// assert_eq!(p.cdf(0.0), 0.0);
/// assert!(p.cdf(1e3) == 1.0);
/// // The weight 2 pi r R(r) / pdf(r) of importance sampling is the albedo.
/// let r = 0.7;
/// let w = 2.0 * std::f64::consts::PI * r * p.profile(r) / p.pdf(r);
/// assert!((w - 0.5).abs() < 1e-15);
/// assert!(BurleyProfile::new(1.5_f64, 1.0, ShapeFit::default()).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BurleyProfile<T> {
    albedo: T,
    d: T,
    inv_d: T,
}

impl<T: Float> BurleyProfile<T> {
    /// The profile for albedo `A` and mean free path `l` under the shape fit `fit`:
    /// `d = fit.shape(A, l)`.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `albedo` when it is not finite or outside
    /// `[0, 1]`; naming `mean_free_path` when it is not finite or not positive, or when the
    /// resulting `d` is not a normal positive float (a subnormal `l`).
    pub fn new(albedo: T, mean_free_path: T, fit: ShapeFit) -> Result<Self, Error> {
        check_albedo(albedo)?;
        if !(mean_free_path.is_finite() && mean_free_path > T::zero()) {
            return Err(Error::invalid(
                "mean_free_path",
                mean_free_path.to_f64().unwrap_or(f64::NAN),
                "must be finite and positive",
            ));
        }
        let d = fit.shape(albedo, mean_free_path);
        if !d.is_normal() {
            return Err(Error::invalid(
                "mean_free_path",
                mean_free_path.to_f64().unwrap_or(f64::NAN),
                "must give a normal positive shape d = l / s(A)",
            ));
        }
        Ok(Self::from_valid(albedo, d))
    }

    /// The profile for albedo `A` and shape `d` given directly.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `albedo` when it is not finite or outside
    /// `[0, 1]`; naming `d` when it is not a normal positive float (zero, negative,
    /// subnormal, infinite or NaN).
    pub fn from_shape(albedo: T, d: T) -> Result<Self, Error> {
        check_albedo(albedo)?;
        if !(d.is_normal() && d > T::zero()) {
            return Err(Error::invalid(
                "d",
                d.to_f64().unwrap_or(f64::NAN),
                "must be a normal positive float",
            ));
        }
        Ok(Self::from_valid(albedo, d))
    }

    fn from_valid(albedo: T, d: T) -> Self {
        Self {
            albedo,
            d,
            inv_d: T::one() / d,
        }
    }

    /// The albedo `A`, the total diffuse reflectance `int 2 pi r R(r) dr`.
    #[inline]
    #[must_use]
    pub fn albedo(&self) -> T {
        self.albedo
    }

    /// The shape `d`.
    #[inline]
    #[must_use]
    pub fn shape(&self) -> T {
        self.d
    }

    /// `1 / d`, precomputed at construction; `x = r * inv_shape()` everywhere.
    #[inline]
    #[must_use]
    pub fn inv_shape(&self) -> T {
        self.inv_d
    }

    /// The profile `R(r) = A (e^{-r/d} + e^{-r/(3d)}) / (8 pi d r)`.
    ///
    /// Total: NaN for NaN `r`; 0 for `r < 0`, for `r = +inf` and for every `r` when
    /// `A = 0`; `+inf` at `r = 0` when `A > 0` (the profile's integrable singularity; a
    /// tiny subnormal `r` may also overflow to `+inf`).
    #[inline]
    #[must_use]
    pub fn profile(&self, r: T) -> T {
        if r.is_nan() {
            return r;
        }
        if r < T::zero() || self.albedo == T::zero() {
            return T::zero();
        }
        if r == T::zero() {
            return T::infinity();
        }
        let x = r * self.inv_d;
        self.albedo * ((-x).exp() + (-x / lit(3.0)).exp()) / (lit::<T>(8.0 * PI) * self.d * r)
    }

    /// The radial pdf `(e^{-r/d} + e^{-r/(3d)}) / (4 d)`, which includes the `2 pi r`
    /// Jacobian and integrates to 1 over `[0, inf)`.
    ///
    /// Total: NaN for NaN `r`; 0 for `r < 0` and `r = +inf`; `1 / (2 d)` at `r = 0`.
    #[inline]
    #[must_use]
    pub fn pdf(&self, r: T) -> T {
        if r.is_nan() {
            return r;
        }
        if r < T::zero() {
            return T::zero();
        }
        let x = r * self.inv_d;
        ((-x).exp() + (-x / lit(3.0)).exp()) * self.inv_d * lit(0.25)
    }

    /// The cdf `1 - e^{-r/d}/4 - 3 e^{-r/(3d)}/4`, evaluated through `expm1` so that small
    /// values keep full relative accuracy.
    ///
    /// Total: NaN for NaN `r`; 0 for `r <= 0`; 1 at `r = +inf`. Non-decreasing.
    #[inline]
    #[must_use]
    pub fn cdf(&self, r: T) -> T {
        if r.is_nan() {
            return r;
        }
        if r <= T::zero() {
            return T::zero();
        }
        let x = r * self.inv_d;
        -((-x).exp_m1() + lit::<T>(3.0) * (-x / lit(3.0)).exp_m1()) * lit(0.25)
    }
}

fn check_albedo<T: Float>(albedo: T) -> Result<(), Error> {
    if albedo.is_finite() && albedo >= T::zero() && albedo <= T::one() {
        Ok(())
    } else {
        Err(Error::invalid(
            "albedo",
            albedo.to_f64().unwrap_or(f64::NAN),
            "must be finite and in [0, 1]",
        ))
    }
}

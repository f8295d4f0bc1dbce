//! Sampling radii: the exact inverse cdf, the approximate inverse of SPVG (21), truncated
//! sampling of the distant part (docs/algorithms.md §2.4) and the footprint radius that splits it.

use num_traits::Float;

use super::{BurleyProfile, lit};

/// The constant `c` of the approximate inverse that the SPVG paper fits by least squares.
///
/// Measured on a uniform grid of `10^6` midpoints in `(0, 1)` (test `approx_inverse_error`
/// in `tests/burley.rs`): `max |cdf(g(xi)) - xi| = 9.87e-3` (at `xi ~ 0.92`, where `g` is
/// too short), RMS `5.38e-3`. A golden-section
/// least-squares fit of `c` over the same kind of grid (test `approx_constant_fit`) gives
/// `c = 2.57150`, reproducing the paper's value.
pub const APPROX_C_PAPER: f64 = 2.5715;

/// The constant `c` of the approximate inverse that Unreal Engine ships.
///
/// Same measurement as [`APPROX_C_PAPER`]: `max |cdf(g(xi)) - xi| = 8.57e-3` (smaller; at
/// `xi ~ 0.46`, where `g` is too long), RMS `5.67e-3` (larger than the least-squares
/// optimum, as it must be).
pub const APPROX_C_UNREAL: f64 = 2.6;

/// A radius drawn from the profile truncated to `r > r0`, with its density.
///
/// # Examples
///
/// ```
/// use spvg::burley::BurleyProfile;
/// let p = BurleyProfile::from_shape(1.0_f64, 1.0).unwrap();
/// let s = p.sample_distant(0.25, 0.5);
/// assert!(s.radius >= 0.5);
/// assert!((s.pdf - p.pdf(s.radius) / p.distant_ratio(0.5)).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistantSample<T> {
    /// The radius, `>= r0`.
    pub radius: T,
    /// The truncated radial pdf `pdf(radius) / (1 - cdf(r0))` at `radius`; 0 when no sample
    /// could be drawn (see [`BurleyProfile::sample_distant`]).
    pub pdf: T,
}

impl<T: Float> BurleyProfile<T> {
    /// The exact inverse cdf: the radius `r` with `cdf(r) = xi`.
    ///
    /// This is Golubev's (2019) closed form with `u = 1 - xi` (docs/algorithms.md §5),
    /// `r = 3 d ln((1 + G^{-1/3} + G^{1/3}) / (4 u))`, `G = 1 + 4 u (2 u + sqrt(1 + 4 u^2))`,
    /// rewritten without cancellation. Writing `y = e^{-r/(3d)}`, the complementary cdf is
    /// `u = (y^3 + 3 y) / 4`, whose real root is `y = 2 sinh(asinh(2 u) / 3)` (the closed
    /// form above is the same root: `G^{1/3} = (2u + sqrt(1 + 4u^2))^{2/3}`). Then
    /// `r = -3 d ln y`, evaluated in one of two branches:
    ///
    /// - `xi > 1/2` (tail, `u = 1 - xi` exact): `y = 2 sinh(asinh(2 u) / 3)`,
    ///   `r = -3 d ln(y)`. Relative accuracy holds down to subnormal `u`.
    /// - `xi <= 1/2` (head): `1 - y` is computed without subtracting nearly equal numbers.
    ///   With `theta1 = ln(phi) = asinh(2) / 3` (`2 sinh(theta1) = 1`) and
    ///   `delta = asinh(2) - asinh(2 u) = asinh(2 xi (1 + u) / (sqrt(1 + 4 u^2) + sqrt(5) u))`,
    ///   `e = 1 - y = 4 cosh(theta1 - delta/6) sinh(delta/6)` and `r = -3 d ln_1p(-e)`.
    ///   Near 0 this gives `r ~ 2 d xi` with full relative accuracy.
    ///
    /// Measured in `f64` (test `inverse_roundtrip`, `xi` from `1e-300` to `1 - 2^-53`):
    /// `|cdf(r) - xi| <= 1e-12` absolutely, and relatively the result is as good as
    /// rounding `r` itself allows: the relative error of `cdf(r)` against `xi` (of
    /// `1 - cdf(r)` against `1 - xi` above 1/2) stays within `2 eps (1 + kappa)`, where
    /// `kappa = r pdf(r) / min(cdf, 1 - cdf)` is the condition number (`~1` in the head,
    /// `~r / (3d)` in the tail, `37` at `xi = 1 - 2^-53`). No Newton polish is needed. In
    /// `f32` the same holds with `1.3 eps_f32 (1 + kappa)`. Below about 7 times the
    /// smallest normal float (`xi` subnormal, e.g. `< 8e-38` in `f32`) the head's
    /// intermediates are subnormal and the bound becomes absolute: a few subnormal steps
    /// (measured by the `burley` fuzz target: 2.5 steps at `xi = 6.9e-41` in `f32`, a
    /// relative 5e-5), no coarser than the spacing of such an `xi` itself.
    ///
    /// GPU port (WGSL has `sinh`, `cosh`, `asinh` but no `log1p`): the same two branches in
    /// `f32`; `ln_1p(-e)` may be `log(1 - e)`, which loses relative accuracy only for
    /// `xi < ~1e-4` where `r < 2e-4 d` (an absolute cdf error below `1e-7`).
    ///
    /// Total: NaN for NaN `xi`; 0 for `xi <= 0`; `+inf` for `xi >= 1`. The largest `f64`
    /// below 1 gives `r ~ 109 d`, the largest `f32` below 1 `r ~ 49 d`. Non-decreasing in
    /// `xi` (so it preserves stratification and low-discrepancy sequences).
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::burley::BurleyProfile;
    /// let p = BurleyProfile::from_shape(0.5_f64, 2.0).unwrap();
    /// for xi in [1e-12, 0.25, 0.5, 0.9, 1.0 - 1e-12] {
    ///     let r = p.inverse_cdf(xi);
    ///     assert!((p.cdf(r) - xi).abs() <= 1e-15, "{xi}");
    /// }
    /// // Near 0 the radius is 2 d xi (to first order), with full relative accuracy.
    /// assert!((p.inverse_cdf(1e-12) - 4e-12).abs() <= 1e-11 * 4e-12);
    /// assert_eq!(p.inverse_cdf(1.0), f64::INFINITY);
    /// ```
    #[inline]
    #[must_use]
    pub fn inverse_cdf(&self, xi: T) -> T {
        if xi.is_nan() {
            return xi;
        }
        if xi <= T::zero() {
            return T::zero();
        }
        if xi >= T::one() {
            return T::infinity();
        }
        self.inverse_split(xi, T::one() - xi)
    }

    /// The inverse cdf from both `xi` and `u = 1 - xi`, each accurate on its own, both in
    /// `(0, 1]` up to rounding; the smaller one selects the branch.
    fn inverse_split(&self, xi: T, u: T) -> T {
        let three = lit::<T>(3.0);
        let x = if xi <= u {
            // Head: e = 1 - y without cancellation (see `inverse_cdf`). theta1 = ln(phi) =
            // 0.4812118250596034475 and sqrt(5), each the nearest f64.
            let theta1 = lit::<T>(0.481_211_825_059_603_47);
            let sqrt5 = lit::<T>(2.236_067_977_499_79);
            let two = lit::<T>(2.0);
            let q =
                two * xi * (T::one() + u) / ((T::one() + lit::<T>(4.0) * u * u).sqrt() + sqrt5 * u);
            let h = q.asinh() / lit(6.0);
            let e = lit::<T>(4.0) * (theta1 - h).cosh() * h.sinh();
            -three * (-e).ln_1p()
        } else {
            // Tail: y = 2 sinh(asinh(2 u) / 3) keeps relative accuracy as u -> 0.
            let y = lit::<T>(2.0) * ((u + u).asinh() / three).sinh();
            -three * y.ln()
        };
        x * self.shape()
    }

    /// The approximate inverse cdf of SPVG (21), `g(xi) = d ((2 - c) xi - 2) ln(1 - xi)`,
    /// with `ln(1 - xi)` evaluated as `ln_1p(-xi)`.
    ///
    /// Use [`APPROX_C_PAPER`] or [`APPROX_C_UNREAL`] for `c`; their errors are stated
    /// there. Near `xi = 0`, `g ~ 2 d xi`, exact to first order. For `c` in `(0, 2]` the
    /// result is non-decreasing in `xi` and non-negative.
    ///
    /// Total: NaN for NaN `xi` or `c`; 0 for `xi <= 0`; `+inf` for `xi >= 1`.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::burley::{APPROX_C_PAPER, BurleyProfile};
    /// let p = BurleyProfile::from_shape(1.0_f64, 1.0).unwrap();
    /// let r = p.approx_inverse_cdf(0.5, APPROX_C_PAPER);
    /// assert!((p.cdf(r) - 0.5).abs() < 0.01);
    /// ```
    #[inline]
    #[must_use]
    pub fn approx_inverse_cdf(&self, xi: T, c: T) -> T {
        if xi.is_nan() || c.is_nan() {
            return T::nan();
        }
        if xi <= T::zero() {
            return T::zero();
        }
        if xi >= T::one() {
            return T::infinity();
        }
        let two = lit::<T>(2.0);
        self.shape() * ((two - c) * xi - two) * (-xi).ln_1p()
    }

    /// The distant energy ratio `gamma = 1 - cdf(r0) = (e^{-x} + 3 e^{-x/3}) / 4` with
    /// `x = r0 / d` (docs/algorithms.md §2.4), evaluated directly (not as `1 - cdf`) so that it keeps full
    /// relative accuracy as it tends to 0.
    ///
    /// Total: NaN for NaN `r0`; 1 for `r0 <= 0`; 0 at `r0 = +inf`. Non-increasing.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::burley::BurleyProfile;
    /// let p = BurleyProfile::from_shape(0.5_f64, 1.0).unwrap();
    /// assert_eq!(p.distant_ratio(0.0), 1.0);
    /// assert!((p.distant_ratio(0.3) - (1.0 - p.cdf(0.3))).abs() < 1e-16);
    /// // Far out, 1 - cdf would round to 0; gamma keeps its relative accuracy.
    /// let g = p.distant_ratio(150.0);
    /// assert!((g - 0.75 * (-50.0_f64).exp()).abs() <= 1e-15 * g);
    /// ```
    #[doc(alias = "gamma")]
    #[doc(alias = "distant_energy_ratio")]
    #[inline]
    #[must_use]
    pub fn distant_ratio(&self, r0: T) -> T {
        if r0.is_nan() {
            return r0;
        }
        if r0 <= T::zero() {
            return T::one();
        }
        let x = r0 * self.inv_shape();
        ((-x).exp() + lit::<T>(3.0) * (-x / lit(3.0)).exp()) * lit(0.25)
    }

    /// The distant energy ratio under the papers' name `gamma`: the same function as
    /// [`distant_ratio`](Self::distant_ratio), whose docs give the formula.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::burley::BurleyProfile;
    /// let p = BurleyProfile::from_shape(0.5_f64, 1.0).unwrap();
    /// // d = 1, x = r0 / d = 0.3: gamma = (e^-0.3 + 3 e^-0.1) / 4.
    /// let want = ((-0.3_f64).exp() + 3.0 * (-0.1_f64).exp()) / 4.0;
    /// assert!((p.gamma(0.3) - want).abs() <= 1e-15, "{} != {want}", p.gamma(0.3));
    /// ```
    #[inline]
    #[must_use]
    pub fn gamma(&self, r0: T) -> T {
        self.distant_ratio(r0)
    }

    /// A radius from the profile truncated to `r > r0` (docs/algorithms.md §2.4):
    /// `r = cdf^{-1}((1 - xi) cdf(r0) + xi)`.
    ///
    /// The target `xi' = cdf(r0) + xi gamma` and its complement `u' = (1 - xi) gamma`
    /// (`gamma = `[`distant_ratio`](Self::distant_ratio)`(r0)`) are both formed from
    /// accurate pieces and fed to the branch of [`inverse_cdf`](Self::inverse_cdf) that
    /// uses the smaller one, so the tail stays accurate even when `gamma` is tiny. The
    /// radius is clamped to `>= r0` against rounding. `pdf = pdf(r) / gamma`.
    ///
    /// `r0 <= 0` gives plain sampling (`gamma = 1`). Total:
    /// - NaN `xi` or `r0`: both fields NaN;
    /// - `xi < 0` is treated as 0 (radius `r0`); `xi >= 1` gives `radius = +inf`, `pdf = 0`;
    /// - `gamma = 0` (no distant energy: `r0 = +inf`, or `r0` so large that `gamma`
    ///   underflows): `radius = r0`, `pdf = 0`. A zero pdf means "no sample": callers skip
    ///   it (docs/algorithms.md §2.4 takes no distant sample at all once `gamma < eps_u`).
    #[inline]
    #[must_use]
    pub fn sample_distant(&self, xi: T, r0: T) -> DistantSample<T> {
        if xi.is_nan() || r0.is_nan() {
            return DistantSample {
                radius: T::nan(),
                pdf: T::nan(),
            };
        }
        let r0 = r0.max(T::zero());
        let gamma = self.distant_ratio(r0);
        if gamma <= T::zero() {
            return DistantSample {
                radius: r0,
                pdf: T::zero(),
            };
        }
        if xi >= T::one() {
            return DistantSample {
                radius: T::infinity(),
                pdf: T::zero(),
            };
        }
        let xi = xi.max(T::zero());
        let target = self.cdf(r0) + xi * gamma;
        let complement = (T::one() - xi) * gamma;
        let radius = if target <= T::zero() {
            T::zero()
        } else {
            self.inverse_split(target, complement)
        }
        .max(r0);
        DistantSample {
            radius,
            pdf: self.pdf(radius) / gamma,
        }
    }
}

/// The footprint radius of one texel, `r0 = |Z| sqrt(w^2 + h^2) / 2` (docs/algorithms.md §2.4): `Z` the
/// view depth, `w` and `h` the texel size in world units at unit depth.
///
/// The sign of `depth` is ignored (view-space `z` is negative in right-handed
/// conventions); the hypotenuse is computed without intermediate overflow. NaN in gives
/// NaN out.
///
/// # Examples
///
/// ```
/// use spvg::burley::footprint_radius;
/// assert_eq!(footprint_radius(2.0_f64, 3.0, 4.0), 5.0);
/// assert_eq!(footprint_radius(-2.0_f64, 3.0, 4.0), 5.0);
/// ```
#[inline]
#[must_use]
pub fn footprint_radius<T: Float>(depth: T, texel_w: T, texel_h: T) -> T {
    depth.abs() * texel_w.hypot(texel_h) * lit(0.5)
}

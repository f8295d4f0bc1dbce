//! Fitting Burley's profile and the separable profile to each other (docs/algorithms.md
//! §5.1): for a falloff `f`, the nearest Burley `(A, l)`; for a Burley `(A, l)`, the
//! nearest falloff; nearest under
//!
//! `S_delta = sum_i (r_i R_B(r_i) - r_i R_S(r_i))^2`
//!
//! over a grid of radii (both profiles carry the `r` factor of the radial integral, so the
//! sum weighs each radius by the energy it holds rather than by the singular `R_B` at 0).
//!
//! # Method
//!
//! Burley's `r R_B(r) = A (e^{-r/d} + e^{-r/(3d)}) / (8 pi d)` is linear in `A`, so for a
//! fixed shape `d` the best albedo is the least-squares projection
//! `A(d) = <g_d, y> / <g_d, g_d>` (clamped to `[0, 1]`, where the quadratic in `A` is
//! least), `g_d` the profile with `A = 1` and `y` the target. That leaves one parameter
//! (variable projection): `S_delta(d)` is minimised over `ln d` by a scan of
//! [`SCAN_POINTS`] points, then golden-section search in the bracket around the best
//! scanned point down to a relative width of `1e-12`. The reverse fit minimises
//! `S_delta(f)` the same way over `f` in `[F_MIN, 1]`. Both are deterministic: no random
//! starts, no tolerance that depends on the input's history.
//!
//! The mean free path is `l = d s(A)` under the chosen [`ShapeFit`]; the fit itself is in
//! `(A, d)` and so the same for every shape fit.

use core::f64::consts::PI;

use num_traits::Float;

use super::separable::{SEPARABLE_GAUSSIANS, SeparableProfile};
use super::{BurleyProfile, ShapeFit};
use crate::Error;

/// Radii per fit grid.
pub const FIT_SAMPLES: usize = 1024;

/// Points of the coarse scan before the golden-section refinement.
pub const SCAN_POINTS: usize = 96;

/// The smallest falloff the reverse fit considers.
pub const F_MIN: f64 = 1e-3;

/// The forward fit's grid reaches this many standard deviations of the widest Gaussian.
const SIGMAS: f64 = 6.0;

/// The reverse fit's grid reaches at least this many shapes `d` (`e^{-10}` of the tail).
const SHAPES: f64 = 30.0;

/// The radius grid of a fit: `FIT_SAMPLES` midpoints `r_i = (i + 1/2) h`.
///
/// The forward fit ([`fit_burley`]) spans the separable profile, `r_max = 6 sqrt(v_max)
/// (0.001 + f)`; the reverse fit ([`fit_falloff`]) spans both the Burley tail and the
/// widest separable profile, `r_max = max(30 d, 6 sqrt(v_max) 1.001)`. Returns the spacing
/// `h`.
#[inline]
#[must_use]
pub fn fit_grid_spacing(r_max: f64) -> f64 {
    r_max / FIT_SAMPLES as f64
}

/// The forward fit's grid extent for falloff `f`.
#[inline]
#[must_use]
pub fn forward_grid_extent(falloff: f64) -> f64 {
    SIGMAS * widest_sigma() * (falloff + super::separable::FALLOFF_EPSILON)
}

/// The reverse fit's grid extent for Burley shape `d`.
#[inline]
#[must_use]
pub fn reverse_grid_extent(d: f64) -> f64 {
    (SHAPES * d).max(forward_grid_extent(1.0))
}

fn widest_sigma() -> f64 {
    SEPARABLE_GAUSSIANS
        .iter()
        .map(|g| g.0)
        .fold(0.0, f64::max)
        .sqrt()
}

/// The Burley parameters nearest a separable falloff ([`fit_burley`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BurleyFit {
    /// Albedo `A` in `[0, 1]`.
    pub albedo: f64,
    /// Shape `d` (mm).
    pub shape: f64,
    /// Mean free path `l = d s(A)` (mm) under the requested [`ShapeFit`].
    pub mean_free_path: f64,
    /// `S_delta` at the optimum, over the forward grid.
    pub residual: f64,
    /// `sqrt(S_delta / sum_i (r_i R_S(r_i))^2)`: the residual relative to the target.
    pub relative_residual: f64,
}

/// What the reverse fit ([`fit_falloff`]) compares.
///
/// The separable profile's energy `||R_S||_1 = s^2 sum w_k` is tied to its width, so the
/// plain `S_delta` trades the width against the energy: for a Burley albedo far from
/// `0.767 s^2` it picks a falloff that matches the energy rather than the shape. The
/// separable filter normalises its kernel and applies the albedo apart, so what a
/// renderer needs from the falloff is the shape alone.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FalloffMatch {
    /// `S_delta` of the profiles as they are (docs/algorithms.md §5.1, the dissertation's
    /// objective).
    Profile,
    /// `S_delta` with the separable profile rescaled to the Burley albedo,
    /// `A R_S / ||R_S||_1`: the width that the normalised kernel should have (default; what
    /// the separable subsurface pass uses).
    #[default]
    Shape,
}

/// The falloff nearest a Burley profile ([`fit_falloff`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FalloffFit {
    /// Falloff `f` in `[reverse_falloff_floor(h), 1]`.
    pub falloff: f64,
    /// `S_delta` at the optimum, over the reverse grid.
    pub residual: f64,
    /// `sqrt(S_delta / sum_i (r_i R_B(r_i))^2)`, or `S_delta` itself when `A = 0` (the
    /// target is zero and has no scale to be relative to).
    pub relative_residual: f64,
}

/// `r R_B(r)` with `A = 1`.
#[inline]
fn burley_r(r: f64, d: f64) -> f64 {
    ((-r / d).exp() + (-r / (3.0 * d)).exp()) / (8.0 * PI * d)
}

/// The nearest Burley `(A, l)` to the separable profile of falloff `f` (see the module
/// documentation for the method).
///
/// # Errors
///
/// [`Error::InvalidParameter`] naming `falloff` when it is NaN or outside `(0, 1]`.
///
/// # Examples
///
/// ```
/// use spvg::burley::{ShapeFit, fit_burley};
/// let fit = fit_burley(1.0, ShapeFit::DiffuseMeanFreePath).unwrap();
/// assert!(fit.albedo > 0.0 && fit.albedo <= 1.0 && fit.shape > 0.0);
/// assert!(fit.relative_residual < 0.5);
/// assert!(fit_burley(f64::NAN, ShapeFit::default()).is_err());
/// ```
pub fn fit_burley(falloff: f64, shape_fit: ShapeFit) -> Result<BurleyFit, Error> {
    let sep = SeparableProfile::new(falloff)?;
    let h = fit_grid_spacing(forward_grid_extent(falloff));
    let r = |i: usize| (i as f64 + 0.5) * h;
    let target = |i: usize| r(i) * sep.profile(r(i));
    let norm2: f64 = (0..FIT_SAMPLES).map(|i| target(i).powi(2)).sum();
    // For one shape: the projected albedo and the residual.
    let project = |d: f64| -> (f64, f64) {
        let (mut gy, mut gg) = (0.0, 0.0);
        for i in 0..FIT_SAMPLES {
            let g = burley_r(r(i), d);
            gy += g * target(i);
            gg += g * g;
        }
        let a = if gg > 0.0 {
            (gy / gg).clamp(0.0, 1.0)
        } else {
            0.0
        };
        // sum (a g - y)^2 = a^2 gg - 2 a gy + |y|^2, clamped at 0 against rounding.
        (a, (a * a * gg - 2.0 * a * gy + norm2).max(0.0))
    };
    let s = sep.scale();
    let ln_d = minimise(|x| project(x.exp()).1, (s * 1e-3).ln(), (s * 1e2).ln());
    let d = ln_d.exp();
    let (albedo, residual) = project(d);
    Ok(BurleyFit {
        albedo,
        shape: d,
        mean_free_path: d * shape_fit.scale(albedo),
        residual,
        relative_residual: (residual / norm2).sqrt(),
    })
}

/// The falloff whose separable profile is nearest `burley` under `S_delta`, comparing what
/// `matching` says (see the module documentation for the method). Infallible: the profile
/// is already validated.
///
/// # Examples
///
/// ```
/// use spvg::burley::{BurleyProfile, FalloffMatch, ShapeFit, fit_burley, fit_falloff};
/// // The round trip lands near where it started.
/// let fwd = fit_burley(0.6, ShapeFit::default()).unwrap();
/// let burley = BurleyProfile::from_shape(fwd.albedo, fwd.shape).unwrap();
/// let back = fit_falloff(&burley, FalloffMatch::Profile);
/// assert!((back.falloff - 0.6).abs() < 0.05, "{}", back.falloff);
/// ```
#[must_use]
pub fn fit_falloff(burley: &BurleyProfile<f64>, matching: FalloffMatch) -> FalloffFit {
    let (albedo, d) = (burley.albedo(), burley.shape());
    let h = fit_grid_spacing(reverse_grid_extent(d));
    let r = |i: usize| (i as f64 + 0.5) * h;
    let target = |i: usize| albedo * burley_r(r(i), d);
    let norm2: f64 = (0..FIT_SAMPLES).map(|i| target(i).powi(2)).sum();
    let cost = |f: f64| -> f64 {
        // f stays in [F_MIN, 1] inside the search, where the profile is valid.
        SeparableProfile::new(f).map_or(f64::INFINITY, |sep| {
            let gain = match matching {
                FalloffMatch::Profile => 1.0,
                FalloffMatch::Shape => albedo / sep.total(),
            };
            (0..FIT_SAMPLES)
                .map(|i| (target(i) - gain * r(i) * sep.profile(r(i))).powi(2))
                .sum()
        })
    };
    let ln_f = minimise(
        |x| cost(x.exp().min(1.0)),
        reverse_falloff_floor(h).ln(),
        0.0,
    );
    let falloff = ln_f.exp().clamp(F_MIN, 1.0);
    let residual = cost(falloff);
    FalloffFit {
        falloff,
        residual,
        relative_residual: if norm2 > 0.0 {
            (residual / norm2).sqrt()
        } else {
            residual
        },
    }
}

/// The smallest falloff the reverse fit searches on a grid of spacing `h`: `F_MIN`, or
/// where the widest Gaussian spans [`RESOLVED_STEPS`] grid steps if that is larger. Below
/// it the grid no longer resolves the separable profile, whose samples then all but
/// vanish, and `S_delta` would reward a kernel that does nothing (`|y|^2` can be less than
/// the error of a real but too narrow kernel).
#[inline]
#[must_use]
pub fn reverse_falloff_floor(h: f64) -> f64 {
    (RESOLVED_STEPS * h / widest_sigma() - super::separable::FALLOFF_EPSILON).clamp(F_MIN, 1.0)
}

/// Grid steps the widest separable Gaussian must span in the reverse fit.
pub const RESOLVED_STEPS: f64 = 8.0;

/// Minimises `cost` over `[lo, hi]`: a scan of `SCAN_POINTS` points, then golden-section
/// search in the bracket of the best scanned point's neighbours.
fn minimise(cost: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let step = (hi - lo) / (SCAN_POINTS - 1) as f64;
    let at = |j: usize| lo + step * j as f64;
    let mut best = (0, f64::INFINITY);
    for j in 0..SCAN_POINTS {
        let c = cost(at(j));
        if c < best.1 {
            best = (j, c);
        }
    }
    let (mut a, mut b) = (
        at(best.0.saturating_sub(1)),
        at((best.0 + 1).min(SCAN_POINTS - 1)),
    );
    let inv_phi = (5.0_f64.sqrt() - 1.0) / 2.0;
    let mut x1 = b - inv_phi * (b - a);
    let mut x2 = a + inv_phi * (b - a);
    let (mut c1, mut c2) = (cost(x1), cost(x2));
    let tol = 1e-12 * (hi - lo).abs().max(1.0);
    while (b - a).abs() > tol {
        if c1 <= c2 {
            b = x2;
            x2 = x1;
            c2 = c1;
            x1 = b - inv_phi * (b - a);
            c1 = cost(x1);
        } else {
            a = x1;
            x1 = x2;
            c1 = c2;
            x2 = a + inv_phi * (b - a);
            c2 = cost(x2);
        }
    }
    // The best of the refined point and the scanned one (the bracket's ends can win when
    // the minimum sits on the boundary).
    let mid = 0.5 * (a + b);
    if cost(mid) <= best.1 { mid } else { at(best.0) }
}

/// `S_delta` between a Burley profile and a separable one on a grid of `FIT_SAMPLES`
/// midpoints of spacing `r_max / FIT_SAMPLES`: the quantity both fits minimise, for
/// reports and tests that compare other parameter pairs on the same footing.
///
/// # Errors
///
/// [`Error::InvalidParameter`] naming `r_max` when it is not finite and positive.
pub fn s_delta<T: Float>(
    burley: &BurleyProfile<T>,
    separable: &SeparableProfile<T>,
    r_max: f64,
) -> Result<f64, Error> {
    if !(r_max.is_finite() && r_max > 0.0) {
        return Err(Error::invalid(
            "r_max",
            r_max,
            "must be finite and positive",
        ));
    }
    let h = fit_grid_spacing(r_max);
    let (a, d) = (
        burley.albedo().to_f64().unwrap_or(f64::NAN),
        burley.shape().to_f64().unwrap_or(f64::NAN),
    );
    let f = separable.falloff().to_f64().unwrap_or(f64::NAN);
    let sep = SeparableProfile::new(f)?;
    Ok((0..FIT_SAMPLES)
        .map(|i| {
            let r = (i as f64 + 0.5) * h;
            (a * burley_r(r, d) - r * sep.profile(r)).powi(2)
        })
        .sum())
}

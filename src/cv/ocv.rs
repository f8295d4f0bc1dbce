//! The online control variate (OCV): a coefficient learned per pixel by EMCM.

use num_traits::Float;

use super::{ControlModel, CvHistory, rules};
use crate::Error;
use crate::stats::Weight;

/// Default `eps_a` of [`Ocv`]: makes `alpha -> 1` when both moments vanish.
pub const DEFAULT_EPS_A: f64 = 1e-6;
/// Default `a0` of [`Ocv`]: the bound `D = [0, 1 + fbar / G] = [0, (fbar + G) / G]`.
pub const DEFAULT_A0: f64 = 1.0;

/// Online control variate (OCV, docs/algorithms.md §3): the coefficient is learned per pixel from the
/// exponential moving covariance matrix of `Z = [fbar, G]` kept in a [`CvHistory`].
///
/// Coefficient, from the previous state (exact operation order in `T`, no fused
/// multiply-add; `D`'s upper bound `u` only applies where it is defined):
///
/// ```text
/// a = (cov_fg + eps_a) / (var_g + eps_a)
/// if a is NaN { a = 1 }                            // corrupt state: fall back to CCV
/// a = sat(a)                                       // an overflowed ratio: +-MAX
/// if G > 0 { u = a0 + fbar / G; if u is finite (not NaN, not inf) { a = min(a, u) } }
/// a = max(a, 0)                                    // the lower bound wins when u < 0
/// ```
///
/// (`sat(x) = clamp(x, -MAX, MAX)` with `MAX` the largest finite value of `T`.) A ratio
/// that overflows (a huge covariance over a small `var_g + eps_a`) keeps its sign, so
/// the clamp takes the bound it points to: `+inf` the upper bound and `-inf` the lower
/// one, 0.
///
/// So `alpha` is always finite and in `D = [0, a0 + fbar / G]` whenever that interval is
/// non-empty and finite; with `G = 0`, a negative or non-finite `G`, or a non-finite
/// `fbar`, only `alpha >= 0` is enforced. A hard shadow (`fbar = G = 0` forever) gives
/// `eps_a / eps_a = 1` exactly.
///
/// State update (EMCM of docs/algorithms.md §1 with weight `eta_cv`; old means first):
///
/// ```text
/// df = fbar - mean_f;  dg = g - mean_g
/// cov_fg = retain * cov_fg + eta_retain * (df * dg)
/// var_g  = retain * var_g  + eta_retain * (dg * dg)
/// mean_f = retain * mean_f + eta * fbar
/// mean_g = retain * mean_g + eta * g
/// ```
///
/// With [`Ocv::with_f16_inputs`], `fbar` and `g` enter this update (not the coefficient
/// or the residual) rounded to the nearest `f16`, clamped to `+-65504`: the precision of
/// the means in an `f16` CV texel. Then a constant control equals its stored mean exactly;
/// without it, the rounding error `g - q(mean_g)` (up to 2^-12 relative) is a fixed `dg`
/// that multiplies the noise of `fbar` into `cov_fg`, and with a small `eps_a` the
/// coefficient wanders far from 1 on a static pixel (`tests/ocv_f16_inputs.rs` measures
/// it). Use it whenever the state is stored in `f16`; the GPU pass does the same.
///
/// An invalid history (disocclusion) reseeds with the first-sample seed: means = the
/// current `fbar` and `G`, moments 0 (so the next frame's coefficient is 1, CCV, until
/// the pixel has seen variation). A non-finite `fbar` or `G` leaves a valid state
/// unchanged and resets an invalid one to the zero state. Stored values are read
/// defensively (non-finite as 0, a negative `var_g` as 0) and overflow saturates.
///
/// # Examples
///
/// ```
/// use spvg::CvHistory;
/// use spvg::cv::{ControlModel, Ocv};
/// let ocv = Ocv::with_weight(0.1_f64).unwrap();
/// let mut j = CvHistory::default();
/// // A flat lit region: fbar = 1.2 G under changing light; alpha tends to 1.2.
/// for t in 0..200 {
///     let g = 1.0 + (t % 7) as f64 * 0.1;
///     ocv.update_state(&mut j, 1.2 * g, g, t > 0);
/// }
/// let alpha = ocv.coefficient(&j, 1.2, 1.0);
/// assert!((alpha - 1.2).abs() < 1e-3, "{alpha}");
/// // Hard shadow: nothing ever lit.
/// let dark = CvHistory::default();
/// assert_eq!(ocv.coefficient(&dark, 0.0, 0.0), 1.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ocv<T> {
    weight: Weight<T>,
    eps_a: T,
    a0: T,
    f16_inputs: bool,
}

/// The largest finite `f16`.
const F16_MAX: f64 = 65504.0;

/// `v` rounded to the nearest `f16` (ties to even), clamped to `+-65504` first. Finite in,
/// finite out.
#[inline]
fn round_to_f16<T: Float>(v: T) -> T {
    let wide = widen(v).clamp(-F16_MAX, F16_MAX);
    T::from(half::f16::from_f64(wide).to_f64()).unwrap_or(v)
}

#[inline]
fn widen<T: Float>(v: T) -> f64 {
    v.to_f64().unwrap_or(f64::NAN)
}

impl<T: Float> Ocv<T> {
    /// Validates the parameters.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `eta` (`eta_cv` outside `(0, 1]` or not finite),
    /// `eps_a` (negative or not finite) or `a0` (negative or not finite).
    pub fn new(eta_cv: T, eps_a: T, a0: T) -> Result<Self, Error> {
        let weight = Weight::new(eta_cv)?;
        if !(eps_a.is_finite() && eps_a >= T::zero()) {
            return Err(Error::invalid(
                "eps_a",
                widen(eps_a),
                "must be finite and >= 0",
            ));
        }
        if !(a0.is_finite() && a0 >= T::zero()) {
            return Err(Error::invalid("a0", widen(a0), "must be finite and >= 0"));
        }
        Ok(Self {
            weight,
            eps_a,
            a0,
            f16_inputs: false,
        })
    }

    /// The same model with `fbar` and `G` rounded to `f16` precision before the state
    /// update (`true`) or kept at full precision (`false`, the default of [`Ocv::new`]).
    /// Turn it on when the [`CvHistory`] is stored in `f16` texels (see [`Ocv`]).
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::CvHistory;
    /// use spvg::cv::{ControlModel, Ocv};
    /// use half::f16;
    /// let ocv = Ocv::with_weight(0.2_f32).unwrap().with_f16_inputs(true);
    /// let mut j = CvHistory::default();
    /// ocv.update_state(&mut j, 0.3, 0.7123, false);
    /// // The seeded mean is the f16 value of G, what an f16 texel stores.
    /// assert_eq!(j.mean_g, f16::from_f32(0.7123).to_f32());
    /// // A constant G then never deviates from its stored mean: var_g stays exactly 0.
    /// for t in 0..50 {
    ///     ocv.update_state(&mut j, 0.3 + 0.01 * (t % 3) as f32, 0.7123, true);
    ///     j.mean_g = f16::from_f32(j.mean_g).to_f32(); // the f16 store
    /// }
    /// assert_eq!(j.var_g, 0.0);
    /// assert_eq!(ocv.coefficient(&j, 0.3, 0.7123), 1.0);
    /// ```
    #[inline]
    #[must_use]
    pub fn with_f16_inputs(self, on: bool) -> Self {
        Self {
            f16_inputs: on,
            ..self
        }
    }

    /// Whether `fbar` and `G` enter the state update at `f16` precision
    /// ([`Ocv::with_f16_inputs`]).
    #[inline]
    #[must_use]
    pub fn f16_inputs(&self) -> bool {
        self.f16_inputs
    }

    /// `fbar` and `G` as the state update sees them: rounded to `f16` (clamped to
    /// `+-65504`) with [`Ocv::with_f16_inputs`], unchanged otherwise. Finite in, finite
    /// out.
    #[inline]
    #[must_use]
    pub fn update_inputs(&self, fbar: T, g: T) -> (T, T) {
        if self.f16_inputs {
            (round_to_f16(fbar), round_to_f16(g))
        } else {
            (fbar, g)
        }
    }

    /// The CV paper's model: `eta_cv = 0.2` with the defaults `eps_a = 1e-6`
    /// ([`DEFAULT_EPS_A`]) and `a0 = 1` ([`DEFAULT_A0`]), the counterpart of
    /// `SpvgConfig::published` (so settings types can default without an error path).
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::cv::Ocv;
    /// let o = Ocv::<f32>::published();
    /// assert_eq!((o.eta_cv(), o.eps_a(), o.a0()), (0.2, 1e-6, 1.0));
    /// assert_eq!(Ocv::with_weight(0.2_f32).unwrap(), o);
    /// ```
    #[must_use]
    pub fn published() -> Self {
        // Valid in every float type that represents 0.2 and 1e-6; a type that cannot
        // falls back to eta_cv = 1 with no regulariser, which is valid everywhere.
        T::from(0.2)
            .ok_or(())
            .and_then(|eta| Self::with_weight(eta).map_err(|_| ()))
            .unwrap_or(Self {
                weight: Weight::one(),
                eps_a: T::zero(),
                a0: T::one(),
                f16_inputs: false,
            })
    }

    /// [`Ocv::new`] with the defaults `eps_a = 1e-6` ([`DEFAULT_EPS_A`]) and `a0 = 1`
    /// ([`DEFAULT_A0`]).
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `eta` when `eta_cv` is not in `(0, 1]`, or
    /// `eps_a` when `T` cannot represent the default.
    pub fn with_weight(eta_cv: T) -> Result<Self, Error> {
        let eps_a = T::from(DEFAULT_EPS_A).unwrap_or(T::nan());
        Self::new(eta_cv, eps_a, T::one())
    }

    /// The EMCM weight `eta_cv`.
    #[inline]
    #[must_use]
    pub fn eta_cv(&self) -> T {
        self.weight.eta()
    }

    /// The validated EMCM weight.
    #[inline]
    #[must_use]
    pub fn weight(&self) -> Weight<T> {
        self.weight
    }

    /// The regularizer `eps_a` added to both moments.
    #[inline]
    #[must_use]
    pub fn eps_a(&self) -> T {
        self.eps_a
    }

    /// The offset `a0` of the upper bound of `D = [0, a0 + fbar / G]`.
    #[inline]
    #[must_use]
    pub fn a0(&self) -> T {
        self.a0
    }

    /// The unclamped coefficient `(Sigma_xy + eps_a) / (Sigma_yy + eps_a)` of a state,
    /// saturated to `+-MAX` where it overflows, or 1 where it is NaN (a corrupt state).
    ///
    /// Saturating rather than falling back to 1 keeps the coefficient monotone in the
    /// covariance: an overflowing positive ratio must clamp to the upper bound of `D`
    /// and a negative one to 0, not jump to CCV.
    #[inline]
    #[must_use]
    pub fn raw_coefficient(&self, state: &CvHistory<T>) -> T {
        rules::raw_coefficient(self.eps_a, state.cov_fg, state.var_g)
    }

    /// Clamps a coefficient to `D = [0, a0 + fbar / G]` as described on [`Ocv`].
    #[inline]
    #[must_use]
    pub fn clamp_to_bound(&self, alpha: T, fbar: T, g: T) -> T {
        rules::clamp_to_bound(self.a0, alpha, fbar, g)
    }
}

impl<T: Float + Default> ControlModel<T> for Ocv<T> {
    type State = CvHistory<T>;

    #[inline]
    fn coefficient(&self, state: &CvHistory<T>, fbar: T, g: T) -> T {
        self.clamp_to_bound(self.raw_coefficient(state), fbar, g)
    }

    #[inline]
    fn update_state(&self, state: &mut CvHistory<T>, fbar: T, g: T, history_valid: bool) -> bool {
        let (next, absorbed) =
            rules::update_state(&self.weight, state, fbar, g, history_valid, |f, g| {
                self.update_inputs(f, g)
            });
        *state = next;
        absorbed
    }
}

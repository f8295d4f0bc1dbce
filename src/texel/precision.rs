//! Can the configured weights move the stored numbers? A check users can call.

use num_traits::Float;

use super::encoding::Layout;
use super::rounding::Rounding;
use crate::cv::Ocv;
use crate::stats::Weight;
use crate::{Error, SpvgConfig};

/// Half an ulp relative to the value, worst case over a binade: `2^-11` for `f16`.
const F16_HALF_ULP: f32 = 1.0 / 2048.0;
/// The same for `f32` (24 significant bits): `2^-24`.
const F32_HALF_ULP: f32 = 1.0 / 16_777_216.0;

/// One number stored in a history texel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StoredQuantity {
    /// `mu`, EMA of the monitored luminance (weight `eta`).
    Mean,
    /// `var`, EMV of the monitored luminance (weight `eta`).
    Variance,
    /// `nbar`, EMA of the sample count (weight `eta`).
    MeanCount,
    /// `Sigma_xy` of the OCV history (weight `eta_cv`).
    CovFg,
    /// `Sigma_yy` of the OCV history (weight `eta_cv`).
    VarG,
    /// `zeta_f` of the OCV history (weight `eta_cv`).
    MeanF,
    /// `zeta_g` of the OCV history (weight `eta_cv`).
    MeanG,
}

/// Whether an update of typical size survives the store.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mobility {
    /// The update survives every store.
    Moves,
    /// Round-to-nearest would lose it, but stochastic rounding keeps it in expectation
    /// (with the noise given by [`QuantityPrecision::stochastic_noise`]).
    MovesInExpectation,
    /// The update is lost at every store: the stored value never moves.
    Frozen,
}

/// The precision verdict for one stored quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuantityPrecision {
    /// Which number.
    pub quantity: StoredQuantity,
    /// The weight of its update.
    pub eta: f32,
    /// Smallest relative deviation `|x - mu| / |mu|` whose update `eta |x - mu|` survives
    /// a round-to-nearest store in the layout: `2^-11 / eta` (`f16`), `2^-24 / eta`
    /// (`f32`).
    pub nearest_threshold: f32,
    /// The same with stochastic rounding: the update must only survive the `f32`
    /// arithmetic before the store, `2^-24 / eta`.
    pub stochastic_threshold: f32,
    /// Relative standard deviation that stochastic rounding adds to the stored state at
    /// equilibrium, an upper bound: `2^-11 / sqrt(2 eta - eta^2)` for `f16` (each store
    /// adds an error of standard deviation at most half an ulp, at most `2^-11` relative,
    /// and the EMA keeps `(1 - eta)^2` of the previous error's variance), 0 for `f32`.
    pub stochastic_noise: f32,
    /// The verdict for the checked typical deviation and rounding.
    pub mobility: Mobility,
}

/// The result of [`check_precision`]: one verdict per stored quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrecisionReport {
    /// The layout checked.
    pub layout: Layout,
    /// The relative deviation `|x - mu| / |mu|` taken as typical.
    pub typical_deviation: f32,
    /// `mu`, `var`, `nbar`.
    pub history: [QuantityPrecision; 3],
    /// `Sigma_xy`, `Sigma_yy`, `zeta_f`, `zeta_g`, when a CV weight was given.
    pub cv: Option<[QuantityPrecision; 4]>,
}

impl PrecisionReport {
    /// Every quantity checked, history first.
    pub fn quantities(&self) -> impl Iterator<Item = &QuantityPrecision> {
        self.history.iter().chain(self.cv.iter().flatten())
    }

    /// `true` when no checked quantity is [`Mobility::Frozen`].
    #[must_use]
    pub fn all_move(&self) -> bool {
        self.quantities().all(|q| q.mobility != Mobility::Frozen)
    }
}

fn verdict(
    quantity: StoredQuantity,
    eta: f32,
    layout: Layout,
    stochastic: bool,
    typical_deviation: f32,
) -> QuantityPrecision {
    let (half_ulp, noise) = match layout {
        Layout::F16 => (
            F16_HALF_ULP,
            F16_HALF_ULP / Float::sqrt(2.0 * eta - eta * eta),
        ),
        Layout::F32 => (F32_HALF_ULP, 0.0),
    };
    let nearest_threshold = half_ulp / eta;
    let stochastic_threshold = F32_HALF_ULP / eta;
    let mobility = if typical_deviation >= nearest_threshold {
        Mobility::Moves
    } else if stochastic && typical_deviation >= stochastic_threshold {
        Mobility::MovesInExpectation
    } else {
        Mobility::Frozen
    };
    QuantityPrecision {
        quantity,
        eta,
        nearest_threshold,
        stochastic_threshold,
        stochastic_noise: if stochastic { noise } else { 0.0 },
        mobility,
    }
}

/// Checks whether updates with the weights `eta` (history `H`) and `eta_cv` (OCV history
/// `J`, if any) can move numbers stored in `layout` with `rounding`, for a typical
/// relative deviation `|x - mu| / |mu|` of the inputs from the stored state. Takes the
/// numbers in any float type (`f32`, `f64`, ...); the verdict is computed in `f32`, the
/// precision the frame functions update in.
///
/// Rule: an update changes the state by `eta |x - mu|`, a relative change
/// `eta * typical_deviation`; a round-to-nearest store keeps it only when it reaches half
/// an ulp (relative `2^-11` in `f16`, worst case over a binade; `2^-24` in `f32`).
/// Stochastic rounding keeps it in expectation as long as it survives the `f32`
/// arithmetic (`2^-24`). A typical deviation of 1 (the variance's own relative
/// fluctuation, or its decay `var -> (1 - eta) var`) is the most favourable realistic
/// case; lighting changes of 10% (0.1) are common; Monte Carlo noise at the target is
/// `sigma0 / mu`.
///
/// # Errors
///
/// [`Error::InvalidParameter`] naming `eta` or `eta_cv` unless it is finite and in
/// `(0, 1]`, or `typical_deviation` unless it is finite and positive.
///
/// # Examples
///
/// ```
/// use spvg::texel::{check_precision, Layout, Mobility, Rounding};
/// // The CV paper's eta_cv = 1e-6 cannot move f16 storage: OCV would degenerate to CCV.
/// let r = check_precision(0.2, Some(1e-6), Layout::F16, Rounding::Nearest, 1.0).unwrap();
/// assert!(r.history.iter().all(|q| q.mobility == Mobility::Moves));
/// assert!(r.cv.unwrap().iter().all(|q| q.mobility == Mobility::Frozen));
/// // Stochastic rounding moves it in expectation; f32 texels move it outright.
/// let r = check_precision(0.2, Some(1e-6), Layout::F16, Rounding::Stochastic(0), 1.0)
///     .unwrap();
/// assert!(r.cv.unwrap().iter().all(|q| q.mobility == Mobility::MovesInExpectation));
/// let r = check_precision(0.2_f64, Some(1e-6), Layout::F32, Rounding::Nearest, 1.0).unwrap();
/// assert!(r.all_move());
/// assert!(check_precision(0.0, None, Layout::F16, Rounding::Nearest, 1.0).is_err());
/// ```
pub fn check_precision<T: Float>(
    eta: T,
    eta_cv: Option<T>,
    layout: Layout,
    rounding: Rounding,
    typical_deviation: T,
) -> Result<PrecisionReport, Error> {
    let weight = |name: &'static str, v: T| -> Result<f32, Error> {
        let w = Weight::new(v).map_err(|_| {
            Error::invalid(
                name,
                v.to_f64().unwrap_or(f64::NAN),
                "must be finite and in (0, 1]",
            )
        })?;
        // A positive weight below f32's range verdicts as the smallest positive f32
        // (frozen everywhere), not as 0.
        Ok(w.eta().to_f32().map_or(1.0, |e| e.max(f32::from_bits(1))))
    };
    let eta = weight("eta", eta)?;
    let eta_cv = eta_cv.map(|v| weight("eta_cv", v)).transpose()?;
    if !(typical_deviation.is_finite() && typical_deviation > T::zero()) {
        return Err(Error::invalid(
            "typical_deviation",
            typical_deviation.to_f64().unwrap_or(f64::NAN),
            "must be finite and positive",
        ));
    }
    // A positive deviation outside f32's range is the nearest positive finite f32.
    let typical_deviation = typical_deviation
        .to_f32()
        .map_or(f32::MAX, |d| d.clamp(f32::from_bits(1), f32::MAX));
    // f32 texels store the f32 result exactly: the rounding mode does not apply.
    let stochastic = matches!(rounding, Rounding::Stochastic(_)) && layout == Layout::F16;
    let v = |q, eta: f32| verdict(q, eta, layout, stochastic, typical_deviation);
    Ok(PrecisionReport {
        layout,
        typical_deviation,
        history: [
            v(StoredQuantity::Mean, eta),
            v(StoredQuantity::Variance, eta),
            v(StoredQuantity::MeanCount, eta),
        ],
        cv: eta_cv.map(|w| {
            [
                v(StoredQuantity::CovFg, w),
                v(StoredQuantity::VarG, w),
                v(StoredQuantity::MeanF, w),
                v(StoredQuantity::MeanG, w),
            ]
        }),
    })
}

/// [`check_precision`] for a controller configuration and, for OCV, its model, in any
/// float type: the weights are the configuration's `eta` and the model's `eta_cv`.
///
/// # Errors
///
/// As [`check_precision`].
///
/// # Examples
///
/// ```
/// use spvg::SpvgConfig;
/// use spvg::cv::Ocv;
/// use spvg::texel::{Layout, Mobility, Rounding, check_config_precision};
/// let config = SpvgConfig::<f32>::published();
/// let ocv = Ocv::with_weight(1e-6).unwrap(); // the CV paper's eta_cv
/// let r = check_config_precision(&config, Some(&ocv), Layout::F16, Rounding::Nearest, 0.1)
///     .unwrap();
/// assert!(!r.all_move());
/// assert_eq!(r.cv.unwrap()[0].mobility, Mobility::Frozen);
/// // The same in f64.
/// let config = SpvgConfig::<f64>::published();
/// let ocv = Ocv::with_weight(1e-6_f64).unwrap();
/// let r = check_config_precision(&config, Some(&ocv), Layout::F16, Rounding::Nearest, 0.1)
///     .unwrap();
/// assert_eq!(r.cv.unwrap()[0].mobility, Mobility::Frozen);
/// ```
pub fn check_config_precision<T: Float>(
    config: &SpvgConfig<T>,
    ocv: Option<&Ocv<T>>,
    layout: Layout,
    rounding: Rounding,
    typical_deviation: T,
) -> Result<PrecisionReport, Error> {
    check_precision(
        config.eta(),
        ocv.map(Ocv::eta_cv),
        layout,
        rounding,
        typical_deviation,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_thresholds() {
        // docs/algorithms.md §4: with eta = 0.005 a change under ~10% of the mean is lost.
        let w = 0.005_f32;
        let r = check_precision(w, None, Layout::F16, Rounding::Nearest, 0.09).unwrap();
        let t = r.history[0].nearest_threshold;
        assert!((t - 0.0977).abs() < 1e-3, "{t} != 0.0977");
        assert_eq!(r.history[0].mobility, Mobility::Frozen, "9% at eta 0.005");
        let r = check_precision(w, None, Layout::F16, Rounding::Nearest, 0.11).unwrap();
        assert!(r.all_move(), "11% at eta 0.005 moves");
        assert!(
            check_precision(w, None, Layout::F16, Rounding::Nearest, f32::NAN).is_err(),
            "NaN deviation is rejected"
        );
    }

    #[test]
    fn eta_cv_1e6_is_flagged_in_f16_only() {
        let w = 0.2_f32;
        let cv = 1e-6_f32;
        // Even the most favourable realistic deviation (100%) cannot move it: the update
        // 1e-6 relative is far under f16's 2^-11.
        for dev in [0.01_f32, 0.1, 1.0] {
            let r = check_precision(w, Some(cv), Layout::F16, Rounding::Nearest, dev).unwrap();
            let q = r.cv.unwrap();
            assert!(
                q.iter().all(|q| q.mobility == Mobility::Frozen),
                "eta_cv 1e-6 must be flagged at deviation {dev}: {q:?}"
            );
            // f32 moves it once eta_cv * dev reaches 2^-24 (dev >= 6%); below, even f32
            // freezes.
            let r = check_precision(w, Some(cv), Layout::F32, Rounding::Nearest, dev).unwrap();
            let moves = 1e-6 * f64::from(dev) >= 2f64.powi(-24);
            assert_eq!(
                r.all_move(),
                moves,
                "f32 with eta_cv 1e-6 at deviation {dev}"
            );
        }
    }

    #[test]
    fn stochastic_noise_bound() {
        let w = 1e-3_f32;
        let r = check_precision(w, None, Layout::F16, Rounding::Stochastic(1), 0.05).unwrap();
        let n = r.history[0].stochastic_noise;
        let want = (2.0_f64.powi(-11) / (2e-3_f64 - 1e-6).sqrt()) as f32;
        assert!((n - want).abs() <= 1e-6 * want, "{n} != {want}");
        assert_eq!(
            r.history[0].mobility,
            Mobility::MovesInExpectation,
            "eta 1e-3 with 5% steps moves only in expectation"
        );
    }
}

//! The joint per-pixel step: SPVG count control monitoring a control-variate residual.

use num_traits::Float;

use super::{ControlModel, rules};
use crate::controller::{SpvgConfig, SpvgHistory};

/// What a pixel measured this frame (luminances).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelFrame<T> {
    /// Luminance of the shaded result `L_o = (1 - gamma) B + gamma L_s`.
    pub radiance: T,
    /// Luminance of the pre-integrated lighting `B(p)` at the pixel.
    pub preintegrated: T,
    /// Distant energy ratio `gamma = 1 - cdf(r0)` (1 for renderers without the near/far
    /// split, docs/algorithms.md §2.4).
    pub gamma: T,
}

/// What [`PixelController::update`] did with a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelUpdate<T> {
    /// The coefficient used for this frame's residual (from the previous CV state).
    pub alpha: T,
    /// The monitored value `S = fbar - alpha G` given to the SPVG history.
    pub monitored: T,
    /// Whether the SPVG history absorbed the frame (see [`SpvgConfig::update`]).
    pub accepted: bool,
}

/// The per-pixel step of docs/algorithms.md §3: SPVG (a [`SpvgConfig`]) monitoring the residual of a
/// control-variate model `M` ([`As`](super::As), [`Ccv`](super::Ccv) or
/// [`Ocv`](super::Ocv)).
///
/// Per frame, before sampling: [`count`](Self::count). After sampling:
/// [`update`](Self::update), which computes, in this order in `T` (no fused
/// multiply-add):
///
/// ```text
/// fbar  = sat(radiance - (1 - gamma) * preintegrated)  // distant estimate, gamma L_s
/// g     = sat(gamma * preintegrated)                   // the control G
/// alpha = model.coefficient(cv_state, fbar, g)       // from the previous CV state;
///                                                    // the cold state if !history_valid
/// s     = sat(fbar - alpha * g)                      // monitored by the SPVG history
/// config.update(history, s, count, history_valid)
/// model.update_state(cv_state, fbar, g, history_valid)   // only if history accepted
/// ```
///
/// `sat` is the crate's overflow policy: where the operands are finite, a result beyond
/// the type's range becomes `+-MAX` (the largest finite value) instead of an infinity,
/// so finite luminances always give a finite residual and the frame is absorbed. A
/// non-finite operand is passed through unchanged (a non-finite `radiance`,
/// `preintegrated` or `gamma` always yields a non-finite `fbar` or `G`), and such a frame
/// is refused. Without a finite upper bound on `alpha` (`G <= 0`, see
/// [`Ocv`](super::Ocv)) `alpha G` can overflow even for moderate luminances; the
/// saturated residual then drives the variance, and the count, to their maxima.
///
/// When the SPVG history refuses the frame (zero samples, or a non-finite value) the CV
/// state follows the same rule: unchanged if valid, reset to its cold state if invalid.
/// AS and CCV have `State = ()`, so they need no storage beyond the SPVG history.
///
/// # Examples
///
/// ```
/// use spvg::{CvHistory, SpvgConfig, SpvgHistory};
/// use spvg::cv::{As, Ccv, ControlModel, Ocv, PixelController, PixelFrame};
/// let config = SpvgConfig::<f32>::published();
/// let frame = PixelFrame { radiance: 0.9, preintegrated: 1.0, gamma: 0.5 };
///
/// // AS and CCV: one SPVG history, no CV state.
/// fn first_frame<M: ControlModel<f32, State = ()>>(pixel: PixelController<f32, M>) -> f32 {
///     let frame = PixelFrame { radiance: 0.9, preintegrated: 1.0, gamma: 0.5 };
///     let mut h = SpvgHistory::default();
///     let n = pixel.count(&h, frame.gamma, true);
///     assert_eq!(n, 8); // cold start
///     let u = pixel.update(&mut h, &mut (), frame, n, true);
///     // fbar = 0.9 - 0.5 * 1.0 = 0.4 and G = 0.5, so S = 0.4 - alpha 0.5.
///     assert!((u.monitored - (0.4 - u.alpha * 0.5)).abs() < 1e-6);
///     u.alpha
/// }
/// assert_eq!(first_frame(PixelController::new(config, As)), 0.0);
/// assert_eq!(first_frame(PixelController::new(config, Ccv)), 1.0);
///
/// // OCV: a second per-pixel state.
/// let pixel = PixelController::new(config, Ocv::with_weight(0.05).unwrap());
/// let (mut h, mut j) = (SpvgHistory::default(), CvHistory::default());
/// let n = pixel.count(&h, frame.gamma, false);
/// let u = pixel.update(&mut h, &mut j, frame, n, false);
/// assert_eq!(u.alpha, 1.0); // a cold state has no moments: eps_a / eps_a
/// assert_eq!(h.variance, config.target_variance()); // disocclusion seed
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelController<T, M> {
    config: SpvgConfig<T>,
    model: M,
}

impl<T: Float, M: ControlModel<T>> PixelController<T, M> {
    /// Combines a validated controller configuration and a control-variate model.
    #[inline]
    #[must_use]
    pub fn new(config: SpvgConfig<T>, model: M) -> Self {
        Self { config, model }
    }

    /// The controller configuration.
    #[inline]
    #[must_use]
    pub fn config(&self) -> &SpvgConfig<T> {
        &self.config
    }

    /// The control-variate model.
    #[inline]
    #[must_use]
    pub fn model(&self) -> &M {
        &self.model
    }

    /// The sample count for this frame: [`SpvgConfig::estimate_with_validity`].
    #[inline]
    #[must_use]
    pub fn count(&self, history: &SpvgHistory<T>, gamma: T, history_valid: bool) -> u32 {
        self.config
            .estimate_with_validity(history, gamma, history_valid)
    }

    /// The distant estimate `fbar = L_o - (1 - gamma) B` and the control `G = gamma B` of
    /// a frame. Finite inputs give finite values (an overflow saturates to `+-MAX`); a
    /// non-finite input gives a non-finite `fbar` or `G`.
    #[inline]
    #[must_use]
    pub fn split(frame: &PixelFrame<T>) -> (T, T) {
        rules::split(frame.radiance, frame.preintegrated, frame.gamma)
    }

    /// Folds one frame into the pixel's SPVG history and CV state (see the type's
    /// documentation for the exact steps) and reports the coefficient used.
    #[inline]
    pub fn update(
        &self,
        history: &mut SpvgHistory<T>,
        cv: &mut M::State,
        frame: PixelFrame<T>,
        count: u32,
        history_valid: bool,
    ) -> PixelUpdate<T> {
        let (fbar, g) = Self::split(&frame);
        // A disoccluded pixel's CV state belongs to another surface: take the cold
        // state's coefficient, which is also what the reseeded state gives next frame, so
        // the monitored series does not jump between the two frames.
        let alpha = if history_valid {
            self.model.coefficient(cv, fbar, g)
        } else {
            self.model.coefficient(&M::State::default(), fbar, g)
        };
        // `alpha` is finite, so with finite `fbar` and `G` only an overflow can make the
        // residual infinite: saturate it (finite input must not be dropped), and keep a
        // non-finite operand's non-finite result so that the frame is refused.
        let monitored = rules::residual(fbar, g, alpha);
        let accepted = self.config.update(history, monitored, count, history_valid);
        if accepted {
            self.model.update_state(cv, fbar, g, history_valid);
        } else if !history_valid {
            *cv = M::State::default();
        }
        PixelUpdate {
            alpha,
            monitored,
            accepted,
        }
    }
}

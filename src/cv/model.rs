//! The control-variate model interface and the two stateless models, AS and CCV.

use num_traits::Float;

/// A control-variate model: how the coefficient `alpha` of the residual
/// `Res = fbar - alpha G` is chosen (docs/algorithms.md §3), and what per-pixel state it needs.
///
/// `fbar` is the distant-scattering estimate `L_o - (1 - gamma) B` and `G = gamma B` the
/// pre-integrated control, both luminances of the current frame. A frame's coefficient
/// comes from the state left by the previous frames ([`coefficient`](Self::coefficient)),
/// then the state absorbs the frame ([`update_state`](Self::update_state)).
///
/// # Examples
///
/// ```
/// use spvg::cv::{As, Ccv, ControlModel};
/// // The stateless models carry no per-pixel storage.
/// assert_eq!(core::mem::size_of::<<As as ControlModel<f32>>::State>(), 0);
/// assert_eq!(Ccv.coefficient(&(), 0.7_f32, 0.5), 1.0);
/// assert_eq!(As.coefficient(&(), 0.7_f32, 0.5), 0.0);
/// ```
pub trait ControlModel<T> {
    /// Per-pixel state kept between frames: `()` for the stateless models (AS, CCV),
    /// [`CvHistory`](super::CvHistory) for OCV. `Default` is the cold state.
    type State: Copy + Default;

    /// The coefficient `alpha` for this frame, from the previous frames' `state` and the
    /// current `fbar` and `G`. Always finite.
    fn coefficient(&self, state: &Self::State, fbar: T, g: T) -> T;

    /// Folds this frame's `fbar` and `G` into the state; `history_valid = false`
    /// (disocclusion) reseeds it. Returns `true` when the state absorbed the frame
    /// (stateless models always return `true`).
    fn update_state(&self, state: &mut Self::State, fbar: T, g: T, history_valid: bool) -> bool;
}

/// Plain adaptive sampling (AS): `alpha = 0`, so the controller monitors `S = fbar`,
/// temporal lighting changes included. No per-pixel state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct As;

/// Constant control variate (CCV, "main part separation", shipped in Unreal Engine 5):
/// `alpha = 1`, so `S = fbar - G`. No per-pixel state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Ccv;

impl<T: Float> ControlModel<T> for As {
    type State = ();

    #[inline]
    fn coefficient(&self, _state: &(), _fbar: T, _g: T) -> T {
        T::zero()
    }

    #[inline]
    fn update_state(&self, _state: &mut (), _fbar: T, _g: T, _history_valid: bool) -> bool {
        true
    }
}

impl<T: Float> ControlModel<T> for Ccv {
    type State = ();

    #[inline]
    fn coefficient(&self, _state: &(), _fbar: T, _g: T) -> T {
        T::one()
    }

    #[inline]
    fn update_state(&self, _state: &mut (), _fbar: T, _g: T, _history_valid: bool) -> bool {
        true
    }
}

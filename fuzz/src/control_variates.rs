//! Invariants of the control-variate pixel step (`spvg::cv`): `PixelController` with
//! `As`, `Ccv` and `Ocv` over a fuzzed frame sequence.

use spvg::CvHistory;
use spvg::controller::{SpvgConfig, SpvgHistory};
use spvg::cv::{As, Ccv, ControlModel, Ocv, PixelController, PixelFrame, PixelUpdate};

use crate::controller::check_history;
use crate::input::{Input, Real, same, sat};

/// Most frames one input drives.
const MAX_FRAMES: usize = 64;

/// Decodes a controller configuration, OCV parameters and up to 64 frames, and runs the
/// three models side by side in `f64` and `f32`, asserting:
/// - `Ocv::new` returns `Ok` exactly for `eta_cv` in `(0, 1]`, finite `eps_a >= 0` and
///   finite `a0 >= 0`;
/// - `split` gives `fbar = L_o - (1 - gamma) B` and `G = gamma B` (saturated);
/// - `alpha` is finite and `>= 0`; 0 for AS, 1 for CCV; for OCV `alpha <= a0 + fbar / G`
///   wherever `G > 0` and that bound is finite (and `alpha = 0` where the bound is
///   negative);
/// - the monitored residual is `sat(fbar - alpha G)`, finite for finite `fbar` and `G`,
///   and the frame is absorbed exactly when the count is non-zero and both are finite;
/// - the SPVG history and the OCV state stay finite, with `var >= 0`, a mean count `>= 0`
///   and `var_g >= 0`; a refused frame leaves a valid OCV state unchanged, zeroes an
///   invalid one, and a disoccluded frame reseeds it to `(0, 0, fbar, G)` (`fbar` and `G`
///   rounded to the nearest f16 when the model takes f16 inputs).
///
/// Layout: the controller's configuration bytes (see `check_controller`; an invalid one
/// falls back to the published parameters), a selector byte (bits 0-2: `eta_cv`,
/// `eps_a`, `a0` from all floats; bit 3: f16 inputs) and 8 bytes each for
/// `eta_cv`, `eps_a`, `a0`; then per frame a flag byte (bit 0 history valid, bit 1 count
/// override from the next byte, bit 2 `gamma` from all floats), 8 bytes each of radiance,
/// pre-integrated lighting and `gamma`.
pub fn check_control_variates(data: &[u8]) {
    run::<f64>(data);
    run::<f32>(data);
}

pub(crate) fn ocv<T: Real>(input: &mut Input<'_>) -> Ocv<T> {
    let wild = input.byte();
    let eta: T = if wild & 1 != 0 {
        input.hard()
    } else {
        input.weight()
    };
    let eps_a = if wild & 2 != 0 {
        input.hard()
    } else {
        let v = input.finite::<T>().abs();
        if input.byte() & 1 == 0 {
            T::from_f64(1e-6)
        } else {
            v
        }
    };
    let a0 = if wild & 4 != 0 {
        input.hard()
    } else {
        input.unit::<T>(T::one()) * T::from_f64(4.0)
    };
    let valid = eta.is_finite()
        && eta > T::zero()
        && eta <= T::one()
        && eps_a.is_finite()
        && eps_a >= T::zero()
        && a0.is_finite()
        && a0 >= T::zero();
    match Ocv::new(eta, eps_a, a0) {
        Ok(o) => {
            assert!(
                valid,
                "{}: Ocv accepted ({eta:?}, {eps_a:?}, {a0:?})",
                T::NAME
            );
            o.with_f16_inputs(wild & 8 != 0)
        }
        Err(e) => {
            assert!(
                !valid,
                "{}: Ocv rejected ({eta:?}, {eps_a:?}, {a0:?}): {e}",
                T::NAME
            );
            Ocv::with_weight(T::from_f64(0.05)).unwrap_or_else(|e| panic!("default Ocv: {e}"))
        }
    }
}

/// One model's per-pixel state and the checks common to all models.
struct Pixel<T, M: ControlModel<T>> {
    pixel: PixelController<T, M>,
    history: SpvgHistory<T>,
    state: M::State,
}

impl<T: Real, M: ControlModel<T>> Pixel<T, M> {
    fn new(config: SpvgConfig<T>, model: M) -> Self {
        Self {
            pixel: PixelController::new(config, model),
            history: SpvgHistory::default(),
            state: M::State::default(),
        }
    }

    /// Runs one frame and returns what the update did, after the model-independent checks.
    fn frame(
        &mut self,
        frame: PixelFrame<T>,
        overridden: Option<u32>,
        valid: bool,
    ) -> PixelUpdate<T> {
        let c = *self.pixel.config();
        let n = self.pixel.count(&self.history, frame.gamma, valid);
        let distant = frame.gamma >= c.eps_u() && frame.gamma > T::zero();
        assert!(
            if distant {
                (c.min_samples()..=c.max_samples()).contains(&n)
            } else {
                n == 0
            },
            "{}: count {n} for gamma {:?}",
            T::NAME,
            frame.gamma
        );
        let used = overridden.unwrap_or(n);
        let (fbar, g) = PixelController::<T, M>::split(&frame);
        let u = self
            .pixel
            .update(&mut self.history, &mut self.state, frame, used, valid);
        assert!(
            u.alpha.is_finite() && u.alpha >= T::zero(),
            "{}: alpha {:?}",
            T::NAME,
            u.alpha
        );
        let finite = fbar.is_finite() && g.is_finite();
        if finite {
            let want = sat(fbar - u.alpha * g);
            assert!(
                u.monitored.raw() == want.raw(),
                "{}: residual {:?} != sat({fbar:?} - {:?} * {g:?}) = {want:?}",
                T::NAME,
                u.monitored,
                u.alpha
            );
        }
        assert_eq!(
            u.accepted,
            used != 0 && finite,
            "{}: accepted {u:?}",
            T::NAME
        );
        check_history(&self.history);
        u
    }
}

fn run<T: Real>(data: &[u8]) {
    let mut input = Input::new(data);
    let (builder, _) = crate::controller::config::<T>(&mut input);
    let config = builder.build().unwrap_or_else(|_| SpvgConfig::published());
    let ocv_model = ocv::<T>(&mut input);
    let mut as_px = Pixel::new(config, As);
    let mut ccv_px = Pixel::new(config, Ccv);
    let mut ocv_px = Pixel::new(config, ocv_model);
    for _ in 0..MAX_FRAMES {
        if input.is_empty() {
            break;
        }
        let flags = input.byte();
        let valid = flags & 1 != 0;
        let radiance = input.hard::<T>();
        let preintegrated = input.hard::<T>();
        let gamma = if flags & 4 != 0 {
            input.hard()
        } else {
            input.unit(config.eps_u())
        };
        let overridden = (flags & 2 != 0).then(|| u32::from(input.byte()));
        let frame = PixelFrame {
            radiance,
            preintegrated,
            gamma,
        };

        let (fbar, g) = PixelController::<T, As>::split(&frame);
        check_split(&frame, fbar, g);

        let alpha = as_px.frame(frame, overridden, valid).alpha;
        assert_eq!(alpha, T::zero(), "{}: AS alpha", T::NAME);
        let alpha = ccv_px.frame(frame, overridden, valid).alpha;
        assert_eq!(alpha, T::one(), "{}: CCV alpha", T::NAME);

        let before = ocv_px.state;
        let u = ocv_px.frame(frame, overridden, valid);
        if g > T::zero() {
            let upper = ocv_model.a0() + fbar / g;
            if upper.is_finite() {
                let inside = if upper >= T::zero() {
                    u.alpha <= upper
                } else {
                    u.alpha == T::zero()
                };
                assert!(
                    inside,
                    "{}: alpha {:?} outside [0, {upper:?}]",
                    T::NAME,
                    u.alpha
                );
            }
        }
        let j = ocv_px.state;
        let fields = |j: &CvHistory<T>| [j.cov_fg, j.var_g, j.mean_f, j.mean_g];
        assert!(
            fields(&j).iter().all(|v| v.is_finite()) && j.var_g >= T::zero(),
            "{}: OCV state {j:?}",
            T::NAME
        );
        // With f16 inputs the seed is the nearest f16 of each, clamped to +-65504.
        let q = |v: T| {
            if ocv_model.f16_inputs() {
                T::from_f64(half::f16::from_f64(v.wide().clamp(-65504.0, 65504.0)).to_f64())
            } else {
                v
            }
        };
        let seeded = CvHistory {
            cov_fg: T::zero(),
            var_g: T::zero(),
            mean_f: q(fbar),
            mean_g: q(g),
        };
        match (u.accepted, valid) {
            (false, true) => assert!(
                same(fields(&j), fields(&before)),
                "{}: refused frame changed {before:?} to {j:?}",
                T::NAME
            ),
            (false, false) => {
                assert_eq!(j, CvHistory::default(), "{}: refused disocclusion", T::NAME);
            }
            (true, false) => assert_eq!(j, seeded, "{}: disocclusion reseed", T::NAME),
            (true, true) => {}
        }
    }
}

/// `fbar = L_o - (1 - gamma) B` and `G = gamma B`, saturated where finite inputs overflow.
fn check_split<T: Real>(frame: &PixelFrame<T>, fbar: T, g: T) {
    let want_f = frame.radiance - (T::one() - frame.gamma) * frame.preintegrated;
    let want_g = frame.gamma * frame.preintegrated;
    let inputs_finite =
        frame.radiance.is_finite() && frame.preintegrated.is_finite() && frame.gamma.is_finite();
    let (want_f, want_g) = if inputs_finite {
        (sat(want_f), sat(want_g))
    } else {
        (want_f, want_g)
    };
    let eq = |a: T, b: T| a.raw() == b.raw() || (a.is_nan() && b.is_nan());
    assert!(
        eq(fbar, want_f) && eq(g, want_g),
        "{}: split {frame:?} = ({fbar:?}, {g:?}), want ({want_f:?}, {want_g:?})",
        T::NAME
    );
    if inputs_finite {
        assert!(
            fbar.is_finite() && g.is_finite(),
            "{}: finite frame split to non-finite",
            T::NAME
        );
    } else {
        assert!(
            !(fbar.is_finite() && g.is_finite()),
            "{}: non-finite frame split to finite",
            T::NAME
        );
    }
}

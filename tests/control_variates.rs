//! Tests of the control-variate models and the joint per-pixel step (docs/algorithms.md §3): the OCV
//! update against a 2x2 EMCM written here, the coefficient's bound, hard shadows and flat
//! lit regions, and the reason CV exists: under switching and flashing light the
//! controller monitoring a CV residual takes far fewer samples than plain adaptive
//! sampling, without under-sampling static lighting.

mod common;

use common::splitmix::SplitMix64;
use proptest::prelude::*;
use spvg::controller::CountPolicy;
use spvg::cv::{As, Ccv, ControlModel, Ocv, PixelController, PixelFrame};
use spvg::stats::{Emc, Emv, Weight};
use spvg::{CvHistory, Error, SpvgConfig, SpvgHistory};

// AS and CCV carry no per-pixel CV state.
const _: () = assert!(
    size_of::<<As as ControlModel<f32>>::State>() == 0,
    "AS needs no CV storage"
);
const _: () = assert!(
    size_of::<<Ccv as ControlModel<f32>>::State>() == 0,
    "CCV needs no CV storage"
);
const _: () = assert!(
    size_of::<<Ocv<f32> as ControlModel<f32>>::State>() == 16,
    "OCV stores 4 numbers"
);

/// docs/algorithms.md §1's EMCM of `Z = [f, g]`, written out with a full 2x2 matrix.
#[derive(Clone, Copy, Debug, Default)]
struct Emcm2 {
    sigma: [[f64; 2]; 2],
    zeta: [f64; 2],
}

impl Emcm2 {
    fn update(&mut self, eta: f64, z: [f64; 2]) {
        let d = [z[0] - self.zeta[0], z[1] - self.zeta[1]];
        for (i, row) in self.sigma.iter_mut().enumerate() {
            for (j, s) in row.iter_mut().enumerate() {
                *s = (1.0 - eta) * *s + eta * (1.0 - eta) * d[i] * d[j];
            }
        }
        for (zeta, zi) in self.zeta.iter_mut().zip(z) {
            *zeta = (1.0 - eta) * *zeta + eta * zi;
        }
    }
}

fn close(got: f64, want: f64, rel: f64) -> bool {
    (got - want).abs() <= rel * want.abs().max(1e-300) + 1e-300
}

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0..10.0_f64,
        2 => 0.0..1e-6_f64,
        1 => Just(0.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(f64::MAX),
        1 => Just(f64::MIN_POSITIVE),
        1 => Just(-f64::MIN_POSITIVE),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn ocv_update_is_the_emcm_of_fbar_and_g(
        eta in 0.001..=1.0_f64,
        seq in prop::collection::vec((-5.0..5.0_f64, 0.0..5.0_f64), 1..40),
        cold in any::<bool>(),
    ) {
        let ocv = Ocv::new(eta, 1e-6, 1.0).expect("valid");
        let w = Weight::new(eta).expect("valid");
        let mut j = CvHistory::default();
        let mut m = Emcm2::default();
        let (mut emc, mut emv) = (Emc::default(), Emv::default());
        for (t, &(f, g)) in seq.iter().enumerate() {
            // Either a cold (zero) start, or a disocclusion seed on the first frame.
            let valid = cold || t > 0;
            prop_assert!(ocv.update_state(&mut j, f, g, valid), "finite frame refused");
            if valid {
                m.update(eta, [f, g]);
                emc.update(&w, f, g);
                emv.update(&w, g);
            } else {
                // First-sample seed: means = current values, moments 0.
                m = Emcm2 { sigma: [[0.0; 2]; 2], zeta: [f, g] };
                emc = Emc::seeded(f, g);
                emv = Emv::seeded(g);
            }
            for (got, want, what) in [
                (j.cov_fg, m.sigma[0][1], "Sigma_xy"),
                (j.var_g, m.sigma[1][1], "Sigma_yy"),
                (j.mean_f, m.zeta[0], "zeta_f"),
                (j.mean_g, m.zeta[1], "zeta_g"),
            ] {
                prop_assert!(close(got, want, 1e-9), "{what}: {got} != {want} (rel 1e-9)");
            }
            // Same recurrences as the crate's EMC (f, g) and EMV (g): bit for bit.
            prop_assert_eq!(j.cov_fg, emc.covariance(), "cov vs Emc");
            prop_assert_eq!(j.var_g, emv.variance(), "var vs Emv");
            prop_assert_eq!((j.mean_f, j.mean_g), (emc.mean_x(), emc.mean_y()), "means");
        }
    }

    #[test]
    fn alpha_is_finite_and_in_the_bound(
        cov in any_f64(), var in any_f64(), mf in any_f64(), mg in any_f64(),
        fbar in any_f64(), g in any_f64(),
        eps_a in prop_oneof![Just(0.0), Just(1e-6), 0.0..1.0_f64],
        a0 in prop_oneof![Just(0.0), Just(1.0), 0.0..4.0_f64],
    ) {
        let ocv = Ocv::new(0.1, eps_a, a0).expect("valid");
        let state = CvHistory { cov_fg: cov, var_g: var, mean_f: mf, mean_g: mg };
        let alpha = ocv.coefficient(&state, fbar, g);
        prop_assert!(alpha.is_finite() && alpha >= 0.0, "alpha {alpha} for {state:?}");
        if g > 0.0 {
            let upper = a0 + fbar / g;
            if upper.is_finite() {
                prop_assert!(alpha <= upper.max(0.0), "alpha {alpha} > upper {upper}");
            }
        }
        // An accepted update stores finite numbers; a refused one changes nothing.
        let bits = |j: &CvHistory<f64>| {
            [j.cov_fg.to_bits(), j.var_g.to_bits(), j.mean_f.to_bits(), j.mean_g.to_bits()]
        };
        for valid in [true, false] {
            let mut next = state;
            if ocv.update_state(&mut next, fbar, g, valid) {
                prop_assert!(
                    bits(&next).iter().all(|&b| f64::from_bits(b).is_finite()),
                    "non-finite state stored: {next:?}"
                );
            } else if valid {
                prop_assert_eq!(bits(&next), bits(&state), "refused update changed the state");
            } else {
                prop_assert_eq!(next, CvHistory::default(), "refused reseed resets");
            }
        }
    }
}

#[test]
fn ocv_validation_names_the_field() {
    let name = |r: Result<Ocv<f64>, Error>| match r {
        Err(Error::InvalidParameter { name, .. }) => name,
        other => panic!("expected an error, got {other:?}"),
    };
    assert_eq!(name(Ocv::new(0.0, 1e-6, 1.0)), "eta", "eta_cv = 0");
    assert_eq!(name(Ocv::new(f64::NAN, 1e-6, 1.0)), "eta", "eta_cv NaN");
    assert_eq!(name(Ocv::new(0.1, -1.0, 1.0)), "eps_a", "negative eps_a");
    assert_eq!(name(Ocv::new(0.1, f64::NAN, 1.0)), "eps_a", "NaN eps_a");
    assert_eq!(name(Ocv::new(0.1, 1e-6, -1.0)), "a0", "negative a0");
    assert_eq!(name(Ocv::new(0.1, 1e-6, f64::INFINITY)), "a0", "inf a0");
    let d = Ocv::with_weight(0.1_f64).expect("valid");
    assert_eq!((d.eps_a(), d.a0()), (1e-6, 1.0), "defaults");
}

#[test]
fn hard_shadow_gives_alpha_one_exactly() {
    let ocv = Ocv::with_weight(0.05_f32).expect("valid");
    let pixel = PixelController::new(SpvgConfig::<f32>::published(), ocv);
    let (mut h, mut j) = (SpvgHistory::default(), CvHistory::default());
    for t in 0..200 {
        let frame = PixelFrame {
            radiance: 0.0,
            preintegrated: 0.0,
            gamma: 0.5,
        };
        let n = pixel.count(&h, frame.gamma, t > 0);
        let u = pixel.update(&mut h, &mut j, frame, n, t > 0);
        assert_eq!(u.alpha, 1.0, "frame {t}: alpha {}", u.alpha);
        assert_eq!(u.monitored, 0.0, "frame {t}: residual");
    }
    assert_eq!(j, CvHistory::default(), "moments stay zero");
}

#[test]
fn flat_lit_region_drives_alpha_to_one() {
    let ocv = Ocv::with_weight(0.05_f64).expect("valid");
    // Static, noiseless: fbar = 1.2 G, constant. Seeded: no moments at all, alpha = 1.
    let mut j = CvHistory::default();
    ocv.update_state(&mut j, 0.6, 0.5, false);
    for _ in 0..10 {
        assert_eq!(ocv.coefficient(&j, 0.6, 0.5), 1.0, "seeded static region");
        ocv.update_state(&mut j, 0.6, 0.5, true);
    }
    // From a cold state the first update sees a jump (alpha starts near 1.2) and the
    // moments then decay as 0.95^t below eps_a: alpha -> eps_a / eps_a = 1.
    let mut j = CvHistory::default();
    for _ in 0..800 {
        ocv.update_state(&mut j, 0.6, 0.5, true);
    }
    let alpha = ocv.coefficient(&j, 0.6, 0.5);
    assert!((alpha - 1.0).abs() <= 1e-6, "{alpha} != 1 (tol 1e-6)");
    // Under changing light with fbar = G (docs/algorithms.md §3: flat lit, alpha* = 1).
    let mut j = CvHistory::default();
    for t in 0..400 {
        let g = 0.5 * (1.0 + (std::f64::consts::TAU * 5.0 * f64::from(t) / 60.0).sin());
        ocv.update_state(&mut j, g, g, t > 0);
    }
    let alpha = ocv.coefficient(&j, 0.5, 0.5);
    assert!((alpha - 1.0).abs() <= 1e-9, "{alpha} != 1 (tol 1e-9)");
    // And with fbar = c G it learns c = E(F)/E(G), up to eps_a's pull towards 1.
    let mut j = CvHistory::default();
    for t in 0..400 {
        let g = 0.5 * (1.0 + (std::f64::consts::TAU * 5.0 * f64::from(t) / 60.0).sin());
        ocv.update_state(&mut j, 1.2 * g, g, t > 0);
    }
    let alpha = ocv.coefficient(&j, 0.6, 0.5);
    assert!((alpha - 1.2).abs() <= 1e-4, "{alpha} != 1.2 (tol 1e-4)");
}

#[test]
fn bound_clamps_and_degenerate_controls() {
    let ocv = Ocv::with_weight(0.1_f64).expect("valid");
    let big = CvHistory {
        cov_fg: 10.0,
        var_g: 1.0,
        mean_f: 0.0,
        mean_g: 0.0,
    };
    // Raw alpha ~10; bound a0 + fbar/G = 1 + 0.5 = 1.5.
    assert_eq!(ocv.coefficient(&big, 0.5, 1.0), 1.5, "upper bound");
    let negative = CvHistory {
        cov_fg: -10.0,
        ..big
    };
    assert_eq!(ocv.coefficient(&negative, 0.5, 1.0), 0.0, "lower bound");
    // G = 0: no upper bound, alpha stays >= 0.
    assert!(
        (ocv.coefficient(&big, 0.5, 0.0) - 10.0).abs() < 1e-5,
        "G = 0 leaves alpha unbounded above"
    );
    // fbar < -a0 G: empty D, the lower bound wins.
    assert_eq!(ocv.coefficient(&big, -3.0, 1.0), 0.0, "empty bound");
    // Corrupt state: CCV fallback.
    let nan = CvHistory {
        cov_fg: f64::NAN,
        ..big
    };
    assert_eq!(
        ocv.coefficient(&nan, 0.5, 1.0),
        1.0,
        "NaN state falls back to 1"
    );
}

#[test]
fn pixel_update_uses_the_previous_state() {
    let ocv = Ocv::with_weight(0.1_f64).expect("valid");
    let pixel = PixelController::new(SpvgConfig::<f64>::published(), ocv);
    let mut h = SpvgHistory::default();
    let mut j = CvHistory {
        cov_fg: 0.3,
        var_g: 0.2,
        mean_f: 0.5,
        mean_g: 0.4,
    };
    let before = j;
    let frame = PixelFrame {
        radiance: 1.0,
        preintegrated: 0.8,
        gamma: 0.75,
    };
    let (fbar, g) = (1.0 - 0.25 * 0.8, 0.75 * 0.8);
    let u = pixel.update(&mut h, &mut j, frame, 8, true);
    assert_eq!(
        u.alpha,
        ocv.coefficient(&before, fbar, g),
        "alpha from J_(t-1)"
    );
    assert!(
        (u.monitored - (fbar - u.alpha * g)).abs() < 1e-15,
        "residual"
    );
    let mut want = before;
    ocv.update_state(&mut want, fbar, g, true);
    assert_eq!(j, want, "CV state updated after the residual");
    // Disocclusion: the stale state (raw alpha 1.5 here) is not used; the cold state's
    // coefficient (eps_a / eps_a = 1) is, as the reseeded state gives next frame.
    let mut stale = CvHistory {
        cov_fg: 0.3,
        var_g: 0.2,
        mean_f: 0.5,
        mean_g: 0.4,
    };
    let u = pixel.update(&mut h, &mut stale, frame, 8, false);
    assert_eq!(u.alpha, 1.0, "disoccluded frame uses the cold coefficient");
    assert_eq!(
        pixel.model().coefficient(&stale, fbar, g),
        1.0,
        "the reseeded state gives the same coefficient"
    );
    // A zero-sample frame on an invalid history resets both states.
    let u = pixel.update(&mut h, &mut j, frame, 0, false);
    assert!(!u.accepted, "zero-sample frame refused");
    assert_eq!(
        (h, j),
        (SpvgHistory::default(), CvHistory::default()),
        "reset"
    );
}

// ---------------------------------------------------------------------------------------
// Changing light: the reason control variates exist.

/// A pixel: distant-scattering mean `F` and pre-integrated control `G` under unit
/// lighting, Monte Carlo per-sample variance `v` of the distant estimate.
#[derive(Clone, Copy)]
struct Pixel {
    f: f64,
    g: f64,
    v: f64,
}

const FPS: f64 = 60.0;
const GAMMA: f64 = 0.5;
/// Published target variance and parameters (eta 0.2, kappa 0.2, budget [8, 64]).
const TARGET: f64 = 1e-4;
/// OCV weight: a 199-frame window (`2/eta - 1`), over 3 s at 60 fps. A 39-frame window
/// (0.05) lets the coefficient's own estimation noise leak into the residual
/// (`S` moves by `delta_alpha G`) and costs a few samples per pixel.
const ETA_CV: f64 = 0.01;

/// The oracle: a constant coefficient, here `alpha* = E(F)/E(G)` (docs/algorithms.md §3), known only
/// to the test. Also shows that the trait is implementable outside the crate.
#[derive(Clone, Copy)]
struct FixedAlpha(f64);

impl ControlModel<f64> for FixedAlpha {
    type State = ();

    fn coefficient(&self, _state: &(), _fbar: f64, _g: f64) -> f64 {
        self.0
    }

    fn update_state(&self, _state: &mut (), _fbar: f64, _g: f64, _valid: bool) -> bool {
        true
    }
}

/// Switch: a main light on for 3 s, off for 3 s, plus a small light flickering
/// uniformly in [0, 0.1] every frame.
fn switching(t: usize, rng: &mut SplitMix64) -> f64 {
    // 3 s at 60 fps = 180 frames per phase.
    let on = if (t / 180).is_multiple_of(2) {
        1.0
    } else {
        0.0
    };
    on + 0.1 * rng.next_open()
}

/// Flash: `I(t) = sin(2 pi 5 t) + 1`.
fn flashing(t: usize, _rng: &mut SplitMix64) -> f64 {
    (std::f64::consts::TAU * 5.0 * t as f64 / FPS).sin() + 1.0
}

fn steady(_t: usize, _rng: &mut SplitMix64) -> f64 {
    1.0
}

struct Outcome {
    mean_count: f64,
    /// Mean squared Monte Carlo error of `fbar` (about `I F`) over the target.
    mc_error_over_target: f64,
}

/// Runs `pixels` independent pixels for `frames` frames; frame 0 is a disocclusion.
/// Statistics skip the first `warm_up` frames.
fn simulate<M: ControlModel<f64>>(
    model: M,
    pixel: Pixel,
    lighting: fn(usize, &mut SplitMix64) -> f64,
    frames: usize,
) -> Outcome {
    let (pixels, warm_up) = (8_u64, 60);
    let controller = PixelController::new(SpvgConfig::<f64>::published(), model);
    let (mut count_sum, mut err_sum, mut n_obs) = (0.0, 0.0, 0.0);
    for p in 0..pixels {
        // Same seeds for every model: the models see the same lighting and noise.
        let mut light_rng = SplitMix64(0x11 + p);
        let mut noise_rng = SplitMix64(0xabc0 + p);
        let mut h = SpvgHistory::default();
        let mut j = M::State::default();
        for t in 0..frames {
            let valid = t > 0;
            let intensity = lighting(t, &mut light_rng);
            let n = controller.count(&h, GAMMA, valid);
            let noise = (pixel.v / f64::from(n)).sqrt() * noise_rng.normal();
            let fbar = intensity * (pixel.f + noise);
            let b = intensity * pixel.g / GAMMA;
            let frame = PixelFrame {
                radiance: (1.0 - GAMMA) * b + fbar,
                preintegrated: b,
                gamma: GAMMA,
            };
            let u = controller.update(&mut h, &mut j, frame, n, valid);
            assert!(u.alpha.is_finite() && u.alpha >= 0.0, "alpha {}", u.alpha);
            if t >= warm_up {
                count_sum += f64::from(n);
                err_sum += (intensity * noise).powi(2);
                n_obs += 1.0;
            }
        }
    }
    Outcome {
        mean_count: count_sum / n_obs,
        mc_error_over_target: err_sum / n_obs / TARGET,
    }
}

struct Comparison {
    as_: Outcome,
    ccv: Outcome,
    ocv: Outcome,
    oracle: Outcome,
}

fn compare(
    label: &str,
    pixel: Pixel,
    lighting: fn(usize, &mut SplitMix64) -> f64,
    frames: usize,
) -> Comparison {
    let ocv = Ocv::with_weight(ETA_CV).expect("valid");
    let c = Comparison {
        as_: simulate(As, pixel, lighting, frames),
        ccv: simulate(Ccv, pixel, lighting, frames),
        ocv: simulate(ocv, pixel, lighting, frames),
        oracle: simulate(FixedAlpha(pixel.f / pixel.g), pixel, lighting, frames),
    };
    println!(
        "{label} (F {}, G {}, v {}): mean spp AS {:.2} / CCV {:.2} / OCV {:.2} \
         (oracle alpha = F/G: {:.2}); MC error / target AS {:.2} / CCV {:.2} / OCV {:.2}",
        pixel.f,
        pixel.g,
        pixel.v,
        c.as_.mean_count,
        c.ccv.mean_count,
        c.ocv.mean_count,
        c.oracle.mean_count,
        c.as_.mc_error_over_target,
        c.ccv.mc_error_over_target,
        c.ocv.mc_error_over_target,
    );
    c
}

/// A pixel in a flat lit region: the distant estimate equals the pre-integrated
/// lighting (`alpha* = 1`). Per-sample standard deviation 0.035 (7% of F), so static
/// lighting needs `v / sigma0^2 = 12` samples.
const FLAT: Pixel = Pixel {
    f: 0.5,
    g: 0.5,
    v: 12e-4,
};
/// A pixel near a shadow edge: the distant estimate exceeds the pre-integrated lighting
/// by 20% (`alpha* = 1.2`), same noise. CCV's residual `(F - G) I(t)` keeps a temporal
/// part there.
const EDGE: Pixel = Pixel {
    f: 0.6,
    g: 0.5,
    v: 12e-4,
};

fn assert_at_least_twice_fewer(label: &str, model: &str, got: f64, as_: f64) {
    assert!(
        2.0 * got <= as_,
        "{label}: {model} takes {got} spp, not 2x fewer than AS {as_}"
    );
}

#[test]
fn switching_light_cv_takes_far_fewer_samples() {
    let frames = 2 * 360 + 60; // two on/off cycles after the warm-up
    for (label, pixel) in [("switch, flat", FLAT), ("switch, edge", EDGE)] {
        let c = compare(label, pixel, switching, frames);
        assert_at_least_twice_fewer(label, "CCV", c.ccv.mean_count, c.as_.mean_count);
        assert_at_least_twice_fewer(label, "OCV", c.ocv.mean_count, c.as_.mean_count);
    }
}

#[test]
fn flashing_light_cv_takes_far_fewer_samples() {
    // AS sits at the budget's top; the best any CV can do is the count that the Monte
    // Carlo noise alone needs under the flash (the oracle's), so the margin over 2x is
    // set by the pixel's noise (with v = 16e-4 the oracle needs 33 spp: 1.9x).
    let frames = 600 + 60;
    let c = compare("flash, flat", FLAT, flashing, frames);
    assert_at_least_twice_fewer("flash, flat", "CCV", c.ccv.mean_count, c.as_.mean_count);
    assert_at_least_twice_fewer("flash, flat", "OCV", c.ocv.mean_count, c.as_.mean_count);
    let c = compare("flash, edge", EDGE, flashing, frames);
    assert_at_least_twice_fewer("flash, edge", "OCV", c.ocv.mean_count, c.as_.mean_count);
    // OCV learns alpha*: within 10% of the oracle's count.
    let rel = (c.ocv.mean_count - c.oracle.mean_count).abs() / c.oracle.mean_count;
    assert!(
        rel <= 0.10,
        "OCV {} vs oracle {} (rel {rel}, tol 0.10)",
        c.ocv.mean_count,
        c.oracle.mean_count
    );
    // CCV cannot remove (F - G) I(t) at an edge: it does not beat AS by much there, which
    // is the case OCV exists for. Only its ordering is asserted.
    assert!(
        c.ccv.mean_count <= c.as_.mean_count,
        "CCV {} above AS {}",
        c.ccv.mean_count,
        c.as_.mean_count
    );
}

#[test]
fn static_light_cv_does_not_under_sample() {
    for (label, pixel) in [("static, flat", FLAT), ("static, edge", EDGE)] {
        let c = compare(label, pixel, steady, 600);
        for (model, o) in [("CCV", &c.ccv), ("OCV", &c.ocv)] {
            let rel = (o.mean_count - c.as_.mean_count).abs() / c.as_.mean_count;
            assert!(
                rel <= 0.10,
                "{label}: {model} {} vs AS {} (rel {rel}, tol 0.10)",
                o.mean_count,
                c.as_.mean_count
            );
        }
        // SPVG reaches the target up to the EMV's bias 2(1-eta)/(2-eta) = 0.89 and the
        // count's noise (the circle test measures 1.2 x target); [0.7, 1.5] x target.
        for (model, o) in [("AS", &c.as_), ("CCV", &c.ccv), ("OCV", &c.ocv)] {
            let r = o.mc_error_over_target;
            assert!(
                (0.7..=1.5).contains(&r),
                "{label}: {model} MC error {r} x target outside [0.7, 1.5]"
            );
        }
    }
}

#[test]
fn policies_switch_with_one_line() {
    // The same pixel loop runs every baseline; only the configuration changes.
    for policy in [
        CountPolicy::Spvg,
        CountPolicy::TwoPhase,
        CountPolicy::UnrealClamp,
        CountPolicy::Fixed(64),
    ] {
        let config = SpvgConfig::<f64>::published()
            .with_policy(policy)
            .expect("valid");
        let pixel = PixelController::new(config, Ccv);
        let mut h = SpvgHistory::default();
        for t in 0..50 {
            let n = pixel.count(&h, 1.0, t > 0);
            assert!((8..=64).contains(&n), "{policy:?}: {n}");
            let frame = PixelFrame {
                radiance: 1.0 + 0.01 * f64::from(t % 3),
                preintegrated: 1.0,
                gamma: 1.0,
            };
            pixel.update(&mut h, &mut (), frame, n, t > 0);
        }
    }
}

//! Precision of `f16` storage: EMV computed in `f16` versus computed in `f32` and rounded
//! to `f16` only when stored, both against an `f64` reference on the same 1000-step
//! stream. Run with `--nocapture` to see the figures (quoted in `spvg::stats` docs).

mod common;

use common::splitmix::unit_noise;
use half::f16;
use spvg::stats::{Emv, Weight};

/// Relative drift of (mean, variance) from the reference, as RMS over the last 900 steps
/// (after the warm-up from the zero state) and the maximum.
#[derive(Default)]
struct Drift {
    sum_sq: [f64; 2],
    max: [f64; 2],
    n: f64,
}

impl Drift {
    fn add(&mut self, got: [f64; 2], want: [f64; 2]) {
        for k in 0..2 {
            let e = ((got[k] - want[k]) / want[k]).abs();
            self.sum_sq[k] += e * e;
            self.max[k] = self.max[k].max(e);
        }
        self.n += 1.0;
    }
    fn rms(&self) -> [f64; 2] {
        self.sum_sq.map(|s| (s / self.n).sqrt())
    }
}

/// Runs the three variants on the stream with weight `eta` (a power of two, exact in
/// every type, so only the arithmetic differs); returns (f16 compute, f32 compute + f16
/// store) drifts.
fn run(eta: f64) -> (Drift, Drift) {
    let (w64, w32) = (Weight::new(eta), Weight::new(eta as f32));
    let w16 = Weight::new(f16::from_f64(eta));
    let (Ok(w64), Ok(w32), Ok(w16)) = (w64, w32, w16) else {
        panic!("eta = 1/16 is a valid weight in every type");
    };
    let mut reference = Emv::<f64>::default();
    let mut in_f16 = Emv::<f16>::default();
    // State held as f16 bits between steps, as in a half-float history texture.
    let mut stored: (u16, u16) = (0, 0);
    let (mut d16, mut d32) = (Drift::default(), Drift::default());
    for i in 0..1000 {
        // A luminance-like signal: level 0.5, uniform noise +-0.2, a step to 0.8 at 500.
        let level = if i < 500 { 0.5 } else { 0.8 };
        // Inputs rounded to f16 first so every variant sees the same numbers.
        let x = f16::from_f64(level + 0.4 * (unit_noise(i) - 0.5));
        reference.update(&w64, x.to_f64());
        in_f16.update(&w16, x);
        let mut mixed = Emv::from_parts(
            f16::from_bits(stored.0).to_f32(),
            f16::from_bits(stored.1).to_f32(),
        );
        mixed.update(&w32, x.to_f32());
        stored = (
            f16::from_f32(mixed.mean()).to_bits(),
            f16::from_f32(mixed.variance()).to_bits(),
        );
        if i >= 100 {
            let want = [reference.mean(), reference.variance()];
            d16.add([in_f16.mean().to_f64(), in_f16.variance().to_f64()], want);
            d32.add(
                [
                    f16::from_bits(stored.0).to_f64(),
                    f16::from_bits(stored.1).to_f64(),
                ],
                want,
            );
        }
    }
    (d16, d32)
}

#[test]
fn f32_compute_f16_store_beats_f16_compute() {
    println!("relative drift from f64 over steps 100..1000 (RMS / max), mean and variance:");
    for eta in [0.25, 0.0625, 0.015625] {
        let (d16, d32) = run(eta);
        check(eta, &d16, &d32);
    }
}

fn check(eta: f64, d16: &Drift, d32: &Drift) {
    let (r16, r32) = (d16.rms(), d32.rms());
    println!("  eta = {eta}");
    println!(
        "    f16 compute:             mean {:.2e} / {:.2e}, variance {:.2e} / {:.2e}",
        r16[0], d16.max[0], r16[1], d16.max[1]
    );
    println!(
        "    f32 compute, f16 store:  mean {:.2e} / {:.2e}, variance {:.2e} / {:.2e}",
        r32[0], d32.max[0], r32[1], d32.max[1]
    );
    for k in 0..2 {
        assert!(
            r32[k] < r16[k],
            "eta {eta}: f32-compute drift {} not below f16-compute drift {} (component {k})",
            r32[k],
            r16[k]
        );
    }
    // One rounding on store bounds the mixed variant near f16's half-ulp (2^-11 ~ 4.9e-4)
    // per stored number; errors feed back through the recurrence, so allow a few.
    assert!(
        r32[0] < 4.0 * 4.9e-4,
        "eta {eta}: mean drift {} above a few half-ulps",
        r32[0]
    );
    assert!(
        r32[1] < 8.0 * 4.9e-4,
        "eta {eta}: variance drift {} above a few half-ulps",
        r32[1]
    );
}

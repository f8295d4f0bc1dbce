//! The streaming estimators on a synthetic per-pixel stream: a noisy luminance with a step
//! at frame 60, and a control variate correlated with its noise.
//!
//! `cargo run --release --example stream`
//!
//! Columns: the frame, the sample, its EMA and EMV, the EMCM regression coefficient of the
//! sample on the control variate (`A_01 = Sigma_01 / Sigma_00`, expected
//! `0.5 s^2 / (0.25 s^2 + e^2) = 1.6` for the noise levels below), and the EMA kept in
//! `f16` against the same EMA in `f64`.

// The deterministic noise is shared with the tests.

use half::f16;
use spvg::stats::{Ema, Emcm, Emv, Weight};
use spvg_fixtures::splitmix::unit_noise;

fn main() -> Result<(), spvg::Error> {
    let eta = 0.1;
    let w = Weight::new(eta)?;
    let w16 = Weight::new(f16::from_f64(eta))?;
    let mut ema = Ema::<f64>::default();
    let mut emv = Emv::<f64>::default();
    let mut emcm = Emcm::<f64, 2>::default();
    let mut ema16 = Ema::<f16>::default();

    println!("eta = {eta}; level 0.5, steps to 0.8 at frame 60; noise s = 0.2/sqrt(12)");
    println!(
        "{:>5} {:>8} {:>8} {:>10} {:>8} {:>9} {:>9}",
        "frame", "sample", "EMA", "EMV", "A_01", "EMA f16", "f16-f64"
    );
    for frame in 0..120_u64 {
        let level = if frame < 60 { 0.5 } else { 0.8 };
        let n = 0.2 * (unit_noise(2 * frame) - 0.5);
        let e = 0.05 * (unit_noise(2 * frame + 1) - 0.5);
        let x = level + n;
        // The control variate sees half the sample's noise plus its own.
        let y = 0.5 * n + e;
        ema.update(&w, x);
        emv.update(&w, x);
        emcm.update(&w, [y, x]);
        ema16.update(&w16, f16::from_f64(x));
        if frame % 5 == 4 || (58..64).contains(&frame) {
            let a = emcm.coefficients();
            println!(
                "{frame:>5} {x:>8.4} {:>8.4} {:>10.3e} {:>8.3} {:>9.4} {:>+9.1e}",
                ema.mean(),
                emv.variance(),
                a[0][1],
                ema16.mean().to_f64(),
                ema16.mean().to_f64() - ema.mean(),
            );
        }
    }
    Ok(())
}

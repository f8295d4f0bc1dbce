//! Stability at the extremes: a property-test matrix over the supported numeric range
//! for `f32` and `f64`.
//!
//! Luminances are log-uniform in magnitude over 1e-30..1e30 with both signs, and exact
//! zeros, subnormals, NaN, infinities and `+-MAX` injected at a low rate; weights `eta`
//! and `eta_cv` are log-uniform in 1e-7..1 (and exactly 1); targets log-uniform in
//! 1e-8..1e2; budgets anywhere in `1 <= min <= max <= 1024`. Multi-frame sequences run
//! through [`PixelController`] with each model and through [`SpvgConfig`] with each
//! [`CountPolicy`], and after every frame the test checks the crate's guarantees: no
//! panic, finite stored state, non-negative variances, counts in the budget (or 0 by the
//! zero-sample rule) and equal to the docs/algorithms.md §2.1 count evaluated here in extended range, an
//! OCV coefficient inside its bound, and frames with usable observations absorbed.
//!
//! The generators are written here (`generators.rs`, not `spvg::arbitrary`) so these
//! tests stand alone. Modules: `generators`, `reference` (the formulas of docs/algorithms.md evaluated in `f64` and
//! the per-frame checks), `validation`, `thresholds` (the measured degradations the
//! controller documentation states) and `regressions` (one per defect found).

use core::fmt::{Debug, Display};

use num_traits::Float;
use proptest::prelude::*;
use spvg::cv::{As, Ccv};

use generators::{Params, frames, hard_lum, params};
use reference::{run_config, run_pixel};

/// `n` cases, unless `PROPTEST_CASES` asks for another number (a longer hunt).
pub(crate) fn cases(n: u32) -> ProptestConfig {
    let mut config = ProptestConfig::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        config.cases = n;
    }
    config
}

/// Frames per generated sequence.
pub(crate) const FRAMES: usize = 50;

/// The two float types under test, with what the reference needs to know of them.
pub(crate) trait Real: Float + Debug + Display + Default + 'static {
    /// Machine epsilon as `f64` (twice the unit roundoff).
    const EPS: f64;
    fn of(v: f64) -> Self {
        Self::from(v).expect("f64 converts to every tested float type")
    }
    fn wide(self) -> f64 {
        self.to_f64()
            .expect("every tested float type widens to f64")
    }
}

impl Real for f32 {
    const EPS: f64 = f32::EPSILON as f64;
}

impl Real for f64 {
    const EPS: f64 = f64::EPSILON;
}

mod generators;
mod reference;
mod regressions;
mod thresholds;
mod validation;

proptest! {
    #![proptest_config(cases(256))]

    #[test]
    fn pixel_controller_f32_every_model(
        p in params(), base in (hard_lum(), hard_lum()), seq in frames(),
    ) {
        run_pixel::<f32, _>(&p, As, base, &seq)?;
        run_pixel::<f32, _>(&p, Ccv, base, &seq)?;
        run_pixel::<f32, _>(&p, p.ocv::<f32>(), base, &seq)?;
    }

    #[test]
    fn pixel_controller_f64_every_model(
        p in params(), base in (hard_lum(), hard_lum()), seq in frames(),
    ) {
        run_pixel::<f64, _>(&p, As, base, &seq)?;
        run_pixel::<f64, _>(&p, Ccv, base, &seq)?;
        run_pixel::<f64, _>(&p, p.ocv::<f64>(), base, &seq)?;
    }

    #[test]
    fn config_every_policy(p in params(), base in hard_lum(), seq in frames()) {
        for policy in 0..4 {
            let p = Params { policy, ..p };
            run_config::<f32>(&p, base, &seq)?;
            run_config::<f64>(&p, base, &seq)?;
        }
    }
}

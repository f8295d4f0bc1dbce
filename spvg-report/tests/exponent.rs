//! The allocation exponent's line (`spvg_report::budget::exponent`): the ideal savings
//! against the motion section's independent bounds (`1/f` at `p = 1`, Cauchy-Schwarz at
//! `p = 1/2`), and the governor holding each exponent's frame at the budget on a small
//! AO static image.

use spvg_report::budget::exponent::{
    BUDGET_SPP, EXPONENTS, ideal_saving, run_budget, run_fixed, saved, static_ao,
};
use spvg_report::motion::data::allocation_bounds;

#[test]
fn ideal_savings_match_the_motion_bounds() {
    let q = static_ao([32, 24], 8);
    let [eq, best] = allocation_bounds(&q);
    assert!((ideal_saving(&q, 1.0) - eq).abs() < 1e-9 * eq, "{eq}");
    assert!((ideal_saving(&q, 0.5) - best).abs() < 1e-9 * best, "{best}");
    // Between the two, and Neyman's is the largest.
    let mid = ideal_saving(&q, 0.75);
    assert!(eq < mid && mid < best, "{eq} {mid} {best}");
}

#[test]
fn the_governor_holds_the_budget_at_every_exponent() {
    let q = static_ao([32, 24], 8);
    let fixed: Vec<_> = [4, 8, 16, 32, 64].map(|n| run_fixed(&q, n)).to_vec();
    for p in EXPONENTS {
        let r = run_budget(&q, p).expect("valid exponent");
        eprintln!("p {p}: {r:?}, saves {:.2} spp", saved(&r, &fixed));
        assert!(
            (r.spp - BUDGET_SPP).abs() < 0.05 * BUDGET_SPP,
            "p {p}: {r:?}"
        );
        assert!(r.psnr.is_finite() && r.worst_decile > 0.0, "{r:?}");
    }
    // An exponent outside (0, 1] is refused by name.
    let err = run_budget(&q, 1.5).unwrap_err();
    assert!(err.to_string().contains("allocation_exponent"), "{err}");
}

//! The firefly section's figures (core crate, `spvg_report::policies::firefly`): the clamp off
//! holds the count for tens of frames after a 100x outlier (the variance it adds,
//! `eta (1 - eta) (99 * 0.5)^2 ~ 392`, is millions of times the target), every `k`
//! shortens that (the variance it adds is `(1 - eta)(1 + eta k^2)` times the steady
//! one), a larger `k` lets more of the outlier through, the steady count is unchanged,
//! and a real step is still tracked.

use spvg_report::policies::firefly::{self, FireflyFigures};

fn sweep() -> Vec<FireflyFigures> {
    let rows = firefly::firefly_sweep().expect("fixed settings are valid");
    for r in &rows {
        eprintln!("{r:?}");
    }
    rows
}

#[test]
fn the_clamp_shortens_the_recovery_and_still_tracks_a_step() {
    let rows = sweep();
    let off = &rows[0];
    assert_eq!(off.k, None);
    let hundred = |r: &FireflyFigures| r.recoveries[0].frames;
    assert!(hundred(off) > 40, "off: {}", hundred(off));
    let (mut last, mut last_step) = (0, usize::MAX);
    for r in &rows[1..] {
        let k = r.k.expect("on");
        assert!(hundred(r) < hundred(off) / 4, "k = {k}: {}", hundred(r));
        assert!(hundred(r) >= last, "k = {k}: a larger k lets more through");
        last = hundred(r);
        // The steady count is the unclamped one within 5% (the clamp rarely engages
        // on Gaussian noise at these k).
        assert!(
            (r.steady_mean - off.steady_mean).abs() <= 0.05 * off.steady_mean,
            "k = {k}: steady {} vs {}",
            r.steady_mean,
            off.steady_mean
        );
        // A 10x step of the level is followed, the sooner the larger k.
        assert!(
            r.step_frames >= off.step_frames,
            "k = {k}: step {}",
            r.step_frames
        );
        assert!(
            r.step_frames <= last_step,
            "k = {k}: step {}",
            r.step_frames
        );
        last_step = r.step_frames;
    }
    let rec = rows
        .iter()
        .find(|r| r.k == Some(firefly::RECOMMENDED_K))
        .expect("the recommended k is measured");
    assert!(hundred(rec) <= firefly::RECOVERY_BOUND);
    // At the recommended k a real 10x step costs at most 8 updates more than the EMA.
    assert!(
        rec.step_frames <= off.step_frames + 8,
        "step {}",
        rec.step_frames
    );
}

#[test]
fn one_value_holds_the_ceiling_unless_clamped() {
    use firefly::{CEILING_VALUES, frames_at_ceiling};
    let off: Vec<usize> = CEILING_VALUES
        .iter()
        .map(|&v| frames_at_ceiling(None, v).expect("valid"))
        .collect();
    let on: Vec<usize> = CEILING_VALUES
        .iter()
        .map(|&v| frames_at_ceiling(Some(4.0), v).expect("valid"))
        .collect();
    eprintln!("frames at the ceiling after {CEILING_VALUES:?}: off {off:?}, k = 4 {on:?}");
    // Unclamped, the value's square enters the variance, which then decays by
    // 1 - eta = 0.8 per frame: a larger value holds the ceiling longer, and even 50
    // (variance ~0.16 * 49.5^2 ~ 392, about 6e6 times the target) holds it for more
    // than ln(6e6) / ln(1.25) ~ 70 frames minus the steady pixel's own margin.
    assert!(off[0] > off[1] && off[1] > off[2], "{off:?}");
    assert!(off[2] >= 50, "{off:?}");
    // Clamped, every value enters as mean + 4 sigma: the size no longer matters, and
    // the ceiling lasts at most the recovery bound of the ensemble line.
    assert!(on.iter().all(|&f| f == on[0]), "{on:?}");
    assert!(on[0] <= firefly::RECOVERY_BOUND, "{on:?}");
    // An invalid k is refused, naming the parameter.
    let err = frames_at_ceiling(Some(-1.0), 50.0).unwrap_err();
    assert!(err.to_string().contains("firefly_clamp"), "{err}");
}

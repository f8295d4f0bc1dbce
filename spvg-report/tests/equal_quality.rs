//! The equal-quality interpolation against hand-computed values: linear in log2(spp)
//! between the bracketing fixed runs, never extrapolated silently.

use spvg_report::equal_quality::{
    EqualQuality, FixedPoint, Interpolated, equal_spp, psnr_at, psnr_at_or_extrapolated,
};

fn ladder() -> Vec<FixedPoint> {
    // Out of order on purpose; fixed8..64 at 30, 33, 36, 39 dB (3 dB per octave).
    [(32.0, 36.0), (8.0, 30.0), (64.0, 39.0), (16.0, 33.0)]
        .map(|(spp, psnr)| FixedPoint { spp, psnr })
        .to_vec()
}

fn close(a: f64, b: f64, what: &str) {
    assert!((a - b).abs() < 1e-9, "{what}: {a} != {b}");
}

#[test]
fn equal_spp_interpolates_in_log2_between_the_bracketing_runs() {
    let f = ladder();
    // 34 dB: a third of the way from 33 (16 spp) to 36 (32 spp): 16 * 2^(1/3).
    let Interpolated::At(n) = equal_spp(&f, 34.0) else {
        panic!("34 dB lies inside the runs")
    };
    close(n, 16.0 * 2_f64.powf(1.0 / 3.0), "34 dB");
    assert_eq!(
        equal_spp(&f, 39.0),
        Interpolated::At(64.0),
        "the top run itself"
    );
    assert_eq!(equal_spp(&f, 39.5), Interpolated::Beyond(64.0));
    assert_eq!(equal_spp(&f, 29.0), Interpolated::Below(8.0));
    assert_eq!(equal_spp(&f[..1], 30.0), Interpolated::None, "one run");
    assert_eq!(equal_spp(&f, f64::NAN), Interpolated::None);
}

#[test]
fn psnr_at_interpolates_and_extrapolation_is_labelled() {
    let f = ladder();
    let Interpolated::At(p) = psnr_at(&f, 24.0) else {
        panic!("24 spp lies inside the runs")
    };
    close(p, 33.0 + 3.0 * (24_f64.log2() - 4.0), "24 spp");
    assert_eq!(psnr_at(&f, 100.0), Interpolated::Beyond(64.0));
    assert_eq!(psnr_at(&f, 4.0), Interpolated::Below(8.0));
    // Extrapolated from fixed8 and fixed16: one octave below fixed8 is 27 dB.
    let (p, extrapolated) = psnr_at_or_extrapolated(&f, 4.0).unwrap_or((f64::NAN, false));
    close(p, 27.0, "4 spp");
    assert!(extrapolated, "labelled as extrapolated");
    let (p, extrapolated) = psnr_at_or_extrapolated(&f, 128.0).unwrap_or((f64::NAN, false));
    close(p, 42.0, "128 spp from fixed32 and fixed64");
    assert!(extrapolated);
}

#[test]
fn the_ratio_and_its_words() {
    let f = ladder();
    // AS at 16 spp reaching 36 dB: equal to fixed32, a 2x ratio.
    let e = EqualQuality::new(&f, 16.0, 36.0);
    close(e.ratio().unwrap_or(f64::NAN), 2.0, "ratio");
    assert_eq!(e.to_string(), "fixed 32.0 (2.00x)");
    let e = EqualQuality::new(&f, 16.0, 40.0);
    assert_eq!(e.ratio(), None, "no ratio beyond the runs");
    assert_eq!(e.to_string(), "beyond fixed64 (> 4.00x)");
}

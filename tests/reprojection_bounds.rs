//! The reprojection rule at the limits of its types (an adversarial run): the
//! depth test with tolerances up to `f32::MAX` and non-finite depths, and the border
//! texel on every `u32` frame size, with the motion bound. Each property is checked
//! against exact (`f64`) arithmetic, not against the operation order under test.

use proptest::prelude::*;
use spvg::reproject::{HistorySource, PreviousSample, Reprojection, border_texel, previous_texel};

/// The three defects the adversarial run found, as reported.
#[test]
fn reported_cases() {
    let widest = Reprojection::<f32>::new(f32::MAX).expect("finite tolerance");
    assert!(
        !widest.depth_agrees(f32::INFINITY, 2.0),
        "tol * depth overflows: an infinite previous depth still fails"
    );
    assert!(!widest.depth_agrees(f32::NAN, 2.0));
    assert!(!widest.depth_agrees(f32::NEG_INFINITY, 2.0));
    assert!(
        widest.depth_agrees(1e38, 2.0),
        "finite depths within an infinite tolerance"
    );
    // `width - 1` = 33554435 rounds up to 33554436 in f32; the last texel is 33554435.
    assert_eq!(
        border_texel([0, 0], [1e7_f32, 0.0], [33_554_436, 1]),
        Some([10_000_000, 0]),
        "the inset itself where it is inside"
    );
    assert_eq!(
        border_texel([33_554_435, 0], [-3.0_f32, 0.0], [33_554_436, 1]),
        Some([33_554_435 - 3, 0]),
    );
    let q = border_texel([0, 0], [3e7_f32, 0.0], [33_554_436, 1]);
    assert_eq!(q, Some([30_000_000, 0]));
    // The reported motion, 1e10, lies beyond the motion bound (more than the frame size
    // past the edge): no texel at all, never texel 33554436.
    assert_eq!(border_texel([0, 0], [1e10_f32, 0.0], [33_554_436, 1]), None);
    // A motion that spans the frame: the inset is clamped to the last texel in integers.
    assert_eq!(
        border_texel([0, 0], [33_554_436.0_f32, 0.0], [33_554_436, 1]),
        Some([33_554_435, 0])
    );
    // `width - 1` = u32::MAX - 1 rounds to 2^32 in f32, past u32: still a texel.
    assert_eq!(
        border_texel([0, 0], [1e9_f32, 0.0], [u32::MAX, 1]),
        Some([1_000_000_000, 0])
    );
    assert_eq!(
        border_texel(
            [1_000_000_000, 0],
            [4_294_967_296.0_f32, 0.0],
            [u32::MAX, 1]
        ),
        Some([u32::MAX - 1, 0]),
        "an inset of 2^32 is clamped to the last texel"
    );
    assert_eq!(
        border_texel([u32::MAX - 1, 0], [-1e9_f32, 0.0], [u32::MAX, 1]),
        Some([u32::MAX - 1 - 1_000_000_000, 0])
    );
}

/// Absurd finite motion is a disocclusion, not a pan that takes the border prior.
#[test]
fn motion_beyond_the_bound_is_a_disocclusion() {
    let r = Reprojection::<f32>::default();
    let at = |_: [u32; 2]| PreviousSample {
        mask: true,
        depth: 1.0,
    };
    let size = [16, 8];
    for v in [1e30_f32, -1e30, f32::MAX, f32::MIN, 3e9, -3e9, 40.0, -40.0] {
        for pixel in [[0, 0], [7, 3], [15, 7]] {
            for m in [[v, 0.0], [0.0, v], [v, v]] {
                assert_eq!(
                    r.locate(pixel, m, 1.0, size, size, at),
                    HistorySource::Disoccluded,
                    "{pixel:?} {m:?}"
                );
            }
        }
    }
    // Within the bound, a pan still takes the prior.
    assert_eq!(
        r.locate([0, 0], [16.5, 0.0], 1.0, size, size, at),
        HistorySource::BorderPrior([15, 0])
    );
}

fn side() -> impl Strategy<Value = u32> {
    prop_oneof![
        1..16_u32,
        1..=65_536_u32,
        (1_u32 << 24)..(1 << 26),
        1..=u32::MAX,
        (u32::MAX - 8)..=u32::MAX,
    ]
}

/// `x + 0.5 - v` in exact arithmetic.
fn position(x: u32, v: f32) -> f64 {
    f64::from(x) + 0.5 - f64::from(v)
}

proptest! {
    #[test]
    fn border_texels_are_inside_every_u32_frame(
        size in (side(), side()),
        pixel in (any::<u32>(), any::<u32>()),
        v in (proptest::num::f32::ANY, proptest::num::f32::ANY),
        scale in (0.0..3.0_f64, 0.0..3.0_f64),
    ) {
        let size = [size.0, size.1];
        let pixel = [pixel.0 % size[0], pixel.1 % size[1]];
        // Half the time, motion on the scale of the frame (inside, past and beyond).
        let v = [v.0, v.1];
        let scaled = [
            ((scale.0 - 1.5) * f64::from(size[0])) as f32,
            ((scale.1 - 1.5) * f64::from(size[1])) as f32,
        ];
        for v in [v, scaled] {
            let got = border_texel(pixel, v, size);
            if let Some(q) = got {
                prop_assert!(q[0] < size[0] && q[1] < size[1], "{q:?} outside {size:?}");
            }
            if let Some(q) = previous_texel(pixel, v, size) {
                prop_assert_eq!(got, Some(q), "inside: the reprojected texel");
            }
            for a in 0..2 {
                let (p, n) = (position(pixel[a], v[a]), f64::from(size[a]));
                if !v[a].is_finite() {
                    prop_assert_eq!(got, None, "non-finite motion");
                } else if p.abs() > 3.0 * n + 2.0 && (p < -n * 1.01 || p > 2.02 * n) {
                    // Well beyond the bound (f32 rounding of the position is 2^-24 of it).
                    prop_assert_eq!(got, None, "axis {} position {} of {}", a, p, n);
                }
            }
            let tame = (0..2).all(|a| v[a].is_finite() && f64::from(v[a]).abs() <= 0.5 * f64::from(size[a]));
            if tame {
                prop_assert!(got.is_some(), "finite motion within half a frame: {:?}", v);
            }
        }
    }

    #[test]
    fn depth_test_against_exact_arithmetic(
        tol in prop_oneof![Just(0.0_f32), 0.0..1.0_f32, proptest::num::f32::POSITIVE | proptest::num::f32::NORMAL, Just(f32::MAX)],
        previous in proptest::num::f32::ANY,
        depth in proptest::num::f32::ANY,
    ) {
        let r = Reprojection::new(tol).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let agrees = r.depth_agrees(previous, depth);
        if !(previous.is_finite() && depth.is_finite() && depth > 0.0) {
            prop_assert!(!agrees, "{previous} vs {depth} at {tol}");
        } else {
            let diff = (f64::from(previous) - f64::from(depth)).abs();
            let allowed = f64::from(tol) * f64::from(depth);
            // Each f32 operation rounds by at most 2^-24 relative (and the difference is
            // exact or rounded once): outside a 1e-6 band the answer is exact.
            if diff < allowed * (1.0 - 1e-6) {
                prop_assert!(agrees, "{previous} vs {depth} at {tol}");
            } else if diff > allowed * (1.0 + 1e-6) {
                prop_assert!(!agrees, "{previous} vs {depth} at {tol}");
            }
        }
    }
}

//! The neighbourhood rules at the extremes (property tests): the footprint search and
//! the border prior of `spvg::reproject`, and count dilation (`spvg::dilation`), on any
//! `f32` motion and depth (NaN, infinities, subnormals, `+-MAX`), any pixel and frame
//! size: no panic, every texel they name inside the previous frame, the previous frame
//! read only there and at most four times, dilated counts between the pixel's own and
//! the frame's largest.

use core::cell::Cell;

use proptest::prelude::*;
use spvg::dilation::{KEEP, MAX_RADIUS, dilate_counts};
use spvg::reproject::{
    HistorySource, PreviousSample, Reprojection, footprint_texel, previous_texel,
};

fn inside(q: [u32; 2], size: [u32; 2]) -> bool {
    q[0] < size[0] && q[1] < size[1]
}

/// Frame sides: empty, one texel, small, up to the component's 2^16, and any `u32` (the
/// API accepts them; above 2^24 `width - 1` rounds in `f32`), `u32::MAX` itself.
fn side() -> impl Strategy<Value = u32> {
    prop_oneof![
        Just(0_u32),
        Just(1),
        1..16_u32,
        1..=65_536_u32,
        any::<u32>(),
        (u32::MAX - 8)..=u32::MAX,
    ]
}

/// Depth tolerances: none, the default, and any finite non-negative value up to
/// `f32::MAX` (where `tol * depth` overflows).
fn tolerance() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(0.0_f32),
        Just(0.02),
        0.0..=1.0_f32,
        proptest::num::f32::POSITIVE | proptest::num::f32::NORMAL,
        Just(f32::MAX),
    ]
}

/// Motion components: any bit pattern half the time, else sub-pixel offsets in the frame.
fn motion() -> impl Strategy<Value = f32> {
    prop_oneof![proptest::num::f32::ANY, -40.0..40.0_f32]
}

proptest! {
    #[test]
    fn footprint_texels_are_in_the_frame_and_next_to_the_nearest(
        size in (side(), side()),
        pixel in (any::<u32>(), any::<u32>()),
        v in (motion(), motion()),
        k in 0..6_u32,
    ) {
        let (size, v) = ([size.0, size.1], [v.0, v.1]);
        let pixel = [pixel.0 % size[0].max(1), pixel.1 % size[1].max(1)];
        let Some(q) = footprint_texel(pixel, v, size, k) else {
            return Ok(());
        };
        prop_assert!(inside(q, size), "{q:?} outside {size:?}");
        let near = previous_texel(pixel, v, size);
        prop_assert!(near.is_some(), "a neighbour without a nearest texel");
        let near = near.unwrap_or_default();
        let step = [q[0].abs_diff(near[0]), q[1].abs_diff(near[1])];
        let want = match k {
            1 => [1, 0],
            2 => [0, 1],
            3 => [1, 1],
            _ => [u32::MAX; 2],
        };
        prop_assert_eq!(step, want, "k = {}", k);
    }

    #[test]
    fn locate_reads_inside_at_most_four_times(
        size in (side(), side()),
        pixel in (any::<u32>(), any::<u32>()),
        v in (motion(), motion()),
        depth in proptest::num::f32::ANY,
        previous_depths in proptest::collection::vec(proptest::num::f32::ANY, 4),
        footprint in any::<bool>(),
        prior in any::<bool>(),
        tol in tolerance(),
    ) {
        let (size, v) = ([size.0, size.1], [v.0, v.1]);
        let pixel = [pixel.0 % size[0].max(1), pixel.1 % size[1].max(1)];
        let r = Reprojection::<f32>::new(tol)
            .map_err(|e| TestCaseError::fail(format!("tolerance {tol}: {e}")))?
            .with_footprint_search(footprint)
            .with_border_prior(prior);
        let (calls, outside) = (Cell::new(0_usize), Cell::new(false));
        let previous = |q: [u32; 2]| {
            outside.set(outside.get() || !inside(q, size));
            let k = calls.get();
            calls.set(k + 1);
            PreviousSample { mask: k % 3 != 2, depth: previous_depths[k % 4] }
        };
        let source = r.locate(pixel, v, depth, size, size, previous);
        prop_assert!(!outside.get(), "read outside the previous frame");
        prop_assert!(calls.get() <= 4, "{} reads", calls.get());
        match source {
            HistorySource::History(q) | HistorySource::BorderPrior(q) => {
                prop_assert!(inside(q, size), "{q:?} outside {size:?}");
                prop_assert!(depth > 0.0 && depth.is_finite(), "no surface, yet a history");
                // locate stops at the first texel that passes: the last one read.
                let last = previous_depths[(calls.get() + 3) % 4];
                prop_assert!(last.is_finite(), "a history at a previous depth of {last}");
            }
            HistorySource::Disoccluded => {}
        }
        if let HistorySource::BorderPrior(_) = source {
            prop_assert!(prior, "a border prior while it is off");
        }
    }

    #[test]
    fn dilated_counts_lie_between_the_own_and_the_largest(
        w in 0..12_u32,
        h in 0..12_u32,
        raw in proptest::collection::vec((0..1025_u32, any::<bool>()), 144),
        radius in 0..=MAX_RADIUS + 2,
    ) {
        let n = (w * h) as usize;
        let src: Vec<u32> = raw[..n].iter().map(|&(c, keep)| if keep { c | KEEP } else { c }).collect();
        let mut dst = vec![0; n];
        let result = dilate_counts(&src, &mut dst, [w, h], radius);
        prop_assert_eq!(result.is_ok(), radius <= MAX_RADIUS);
        if result.is_err() {
            return Ok(());
        }
        let largest = src.iter().map(|&c| c & !KEEP).max().unwrap_or(0);
        for (i, (&s, &d)) in src.iter().zip(&dst).enumerate() {
            let own = s & !KEEP;
            prop_assert!(d <= largest, "pixel {i}: {d} above the frame's largest {largest}");
            if own == 0 || s & KEEP != 0 {
                prop_assert_eq!(d, own, "pixel {}: kept", i);
            } else {
                prop_assert!(d >= own, "pixel {i}: {d} below its own {own}");
            }
        }
    }
}

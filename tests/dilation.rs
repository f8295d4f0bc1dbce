//! Count dilation (`spvg::dilation`) against a brute-force reference written from the
//! definition: for each covered pixel with history, the maximum over every pixel of the
//! frame within Chebyshev distance `radius`; pixels marked `KEEP` (no history) and
//! uncovered pixels (0) keep their own count.

use spvg::Error;
use spvg::dilation::{KEEP, MAX_RADIUS, dilate_counts, dilated_count};

/// The definition, by scanning the whole frame for each pixel.
fn reference(src: &[u32], w: usize, h: usize, radius: usize) -> Vec<u32> {
    (0..w * h)
        .map(|i| {
            if src[i] == 0 || src[i] >= KEEP {
                return src[i] - (src[i] & KEEP);
            }
            let (x, y) = (i % w, i / w);
            (0..w * h)
                .filter(|&j| (j % w).abs_diff(x) <= radius && (j / w).abs_diff(y) <= radius)
                .map(|j| src[j] % KEEP)
                .max()
                .unwrap_or(0)
        })
        .collect()
}

/// Frames of counts in {0 (masked), 8..=64}, some marked `KEEP`, from a fixed linear
/// congruential sequence.
fn frame(seed: u64, n: usize) -> Vec<u32> {
    let mut s = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let v = (s >> 33) as u32 % 60;
            let keep = if (s >> 20).is_multiple_of(7) { KEEP } else { 0 };
            if v < 6 { 0 } else { (8 + v - 4) | keep }
        })
        .collect()
}

#[test]
fn equals_the_definition_on_every_size_and_radius() {
    for (w, h) in [(1, 1), (1, 7), (9, 1), (5, 4), (13, 11), (32, 3)] {
        for radius in 0..=4_u32 {
            let src = frame(u64::from(radius) * 97 + (w * h) as u64, w * h);
            let mut got = vec![u32::MAX; w * h];
            dilate_counts(&src, &mut got, [w as u32, h as u32], radius).expect("valid");
            let want = reference(&src, w, h, radius as usize);
            assert_eq!(got, want, "{w}x{h} radius {radius}");
        }
    }
}

#[test]
fn radius_zero_is_the_identity_and_zero_stays_zero() {
    let (w, h) = (17, 9);
    let src = frame(5, w * h);
    assert!(
        src.iter().any(|&c| c >= KEEP),
        "the frame has marked pixels"
    );
    let mut out = vec![0; w * h];
    dilate_counts(&src, &mut out, [w as u32, h as u32], 0).expect("valid");
    let unmarked: Vec<u32> = src.iter().map(|&c| c & !KEEP).collect();
    assert_eq!(out, unmarked, "radius 0 only clears the marks");
    dilate_counts(&src, &mut out, [w as u32, h as u32], MAX_RADIUS).expect("valid");
    let max = *unmarked.iter().max().expect("non-empty");
    for (i, (&s, &d)) in src.iter().zip(&out).enumerate() {
        if s == 0 {
            assert_eq!(d, 0, "pixel {i}: a masked pixel stays at 0");
        } else if s >= KEEP {
            assert_eq!(d, s & !KEEP, "pixel {i}: a marked pixel keeps its count");
        } else {
            // At the centre column the 17x17 window covers the whole 17x9 frame.
            assert!(d >= s, "pixel {i}: dilation never lowers a count");
            if i % w == w / 2 {
                assert_eq!(d, max, "pixel {i}: the centre column sees the whole frame");
            }
        }
    }
}

#[test]
fn rejects_a_wide_radius_and_mismatched_slices_by_name() {
    let src = [8_u32; 6];
    let mut dst = [0_u32; 6];
    assert_eq!(
        dilate_counts(&src, &mut dst, [3, 2], MAX_RADIUS + 1),
        Err(Error::invalid(
            "radius",
            f64::from(MAX_RADIUS + 1),
            "the count dilation radius must be at most spvg::dilation::MAX_RADIUS = 8"
        ))
    );
    assert!(matches!(
        dilate_counts(&src, &mut dst, [4, 2], 1),
        Err(Error::InconsistentParameters { .. })
    ));
    assert!(matches!(
        dilate_counts(&src, &mut dst[..5], [3, 2], 1),
        Err(Error::InconsistentParameters { .. })
    ));
    assert_eq!(dst, [0; 6], "nothing written on an error");
}

#[test]
fn a_pixel_outside_the_frame_or_a_short_slice_reads_zero() {
    let src = [8_u32, 64, 8, 8];
    assert_eq!(dilated_count(&src, [2, 2], [2, 0], 1), 0, "x outside");
    assert_eq!(dilated_count(&src, [2, 2], [0, 2], 1), 0, "y outside");
    assert_eq!(
        dilated_count(&src[..3], [2, 2], [1, 1], 1),
        0,
        "pixel past the slice"
    );
    assert_eq!(
        dilated_count(&src[..3], [2, 2], [0, 1], 1),
        64,
        "reads what is there"
    );
    assert_eq!(
        dilated_count(&src, [2, 2], [1, 1], u32::MAX),
        64,
        "no overflow"
    );
}

/// The neighbour prior against a brute-force reference written here: a pixel marked
/// `KEEP` takes the rounded mean (in f64) of the unmarked, nonzero counts on its surface
/// within `max(radius, PRIOR_RADIUS)`, at least its own count; every other pixel is
/// `dilated_count`. The frame spans three one-pass tiles across and two down: the window
/// crosses tile edges and is clipped by the frame alone.
#[test]
fn neighbour_prior_is_the_same_surface_mean() {
    use spvg::dilation::{PRIOR_RADIUS, dilated_count_with_prior};
    let (w, h) = (21_u32, 11_u32);
    let mut g = 12_345_u32;
    let mut next = || {
        g = g.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        g >> 8
    };
    for _ in 0..50 {
        let counts: Vec<u32> = (0..w * h)
            .map(|_| match next() % 5 {
                0 => 0,
                1 => KEEP | (1 + next() % 64),
                _ => 1 + next() % 64,
            })
            .collect();
        let surface: Vec<u32> = (0..w * h).map(|_| next() % 2).collect();
        for radius in [0, 1, 2, 5_u32] {
            for y in 0..h {
                for x in 0..w {
                    let i = (y * w + x) as usize;
                    let same = |q: [u32; 2]| surface[(q[1] * w + q[0]) as usize] == surface[i];
                    let got = dilated_count_with_prior(&counts, [w, h], [x, y], radius, same);
                    let want = if counts[i] & KEEP == 0 {
                        dilated_count(&counts, [w, h], [x, y], radius)
                    } else {
                        let own = counts[i] & !KEEP;
                        let r = radius.max(PRIOR_RADIUS);
                        let mut taken = Vec::new();
                        for qy in y.saturating_sub(r)..=(y + r).min(h - 1) {
                            for qx in x.saturating_sub(r)..=(x + r).min(w - 1) {
                                let j = (qy * w + qx) as usize;
                                if counts[j] & KEEP == 0
                                    && counts[j] > 0
                                    && surface[j] == surface[i]
                                {
                                    taken.push(f64::from(counts[j]));
                                }
                            }
                        }
                        if taken.is_empty() {
                            own
                        } else {
                            let mean = taken.iter().sum::<f64>() / taken.len() as f64;
                            // Halves round up (f64 holds these sums exactly).
                            ((mean + 0.5).floor() as u32).max(own)
                        }
                    };
                    assert_eq!(got, want, "pixel ({x}, {y}) radius {radius}");
                }
            }
        }
    }
}

/// The prior's mean does not overflow: a window of the largest unmarked counts has that
/// count as its mean.
#[test]
fn neighbour_prior_mean_of_the_largest_counts() {
    use spvg::dilation::dilated_count_with_prior;
    let big = KEEP - 1;
    let mut counts = vec![big; 81];
    counts[40] = KEEP | 8;
    assert_eq!(
        dilated_count_with_prior(&counts, [9, 9], [4, 4], 1, |_| true),
        big
    );
    counts[0] = big - 120;
    // 80 neighbours: (79 big + (big - 120)) / 80 = big - 1.5, halves round up.
    assert_eq!(
        dilated_count_with_prior(&counts, [9, 9], [4, 4], 1, |_| true),
        big - 1
    );
}

/// The tile region and the spatial window against their definitions, by membership: a
/// texel `q` of the frame is in the region of `pixel` when each coordinate lies within
/// `halo` of the 8-wide tile holding the pixel's, and in the window when it is also
/// within 1 of the pixel and in the tile itself.
#[test]
fn tile_region_and_spatial_window_hold_what_their_definitions_hold() {
    use spvg::controller::young::spatial_window;
    use spvg::dilation::tile_region;
    for (w, h) in [(1_u32, 1_u32), (8, 8), (9, 17), (23, 5)] {
        for halo in [0_u32, 1, 3, 8] {
            for y in 0..h {
                for x in 0..w {
                    let [lo, hi] = tile_region([x, y], [w, h], halo);
                    let [slo, shi] = spatial_window([x, y], [w, h]);
                    for qy in 0..h {
                        for qx in 0..w {
                            let near = |q: u32, p: u32, r: u32| {
                                q + r >= p - p % 8 && q <= p - p % 8 + 7 + r
                            };
                            let inside = |lo: [u32; 2], hi: [u32; 2]| {
                                (lo[0]..=hi[0]).contains(&qx) && (lo[1]..=hi[1]).contains(&qy)
                            };
                            let region = near(qx, x, halo) && near(qy, y, halo);
                            assert_eq!(
                                inside(lo, hi),
                                region,
                                "region of ({x}, {y}) halo {halo}: ({qx}, {qy})"
                            );
                            let window = near(qx, x, 0)
                                && near(qy, y, 0)
                                && qx.abs_diff(x) <= 1
                                && qy.abs_diff(y) <= 1;
                            assert_eq!(
                                inside(slo, shi),
                                window,
                                "window of ({x}, {y}): ({qx}, {qy})"
                            );
                        }
                    }
                }
            }
        }
    }
}

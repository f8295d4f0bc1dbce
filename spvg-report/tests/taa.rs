//! The TAA resolve and the instability measure against closed forms: geometric convergence
//! with the blend weight, the neighbourhood clamp (min/max and variance), rejection on
//! disocclusion, exact history moves under integer pans, Catmull-Rom fetches under
//! sub-pixel motion (bilinear where the footprint leaves the frame).

use spvg_report::metrics::Flicker;
use spvg_report::taa::{CLAMP_FLOOR, CLAMP_TOLERANCE, Clamp, Taa, TaaFrame, WEIGHT};

const W: u32 = 8;
const H: u32 = 6;
const N: usize = (W * H) as usize;

/// A frame of `value` with uniform motion `v`, depth 1 and full coverage.
fn resolve(taa: &mut Taa, value: &[f32], v: [f32; 2]) -> Vec<f32> {
    resolve_masked(taa, value, v, &[1; N], &[1.0; N])
}

fn resolve_masked(
    taa: &mut Taa,
    value: &[f32],
    v: [f32; 2],
    mask: &[u8],
    depth: &[f32],
) -> Vec<f32> {
    let motion = vec![v; value.len()];
    let frame = TaaFrame {
        value,
        motion: &motion,
        depth,
        mask,
        skipped: None,
    };
    taa.resolve(&frame)
        .unwrap_or_else(|e| panic!("resolve: {e}"))
        .to_vec()
}

/// Columns alternating 0 and 1: every 3x3 neighbourhood spans [0, 1], so a history in
/// [0, 1] is never clamped by the min/max box.
fn stripes() -> Vec<f32> {
    (0..N).map(|i| (i % 2) as f32).collect()
}

fn close(a: f32, b: f32, tol: f32, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} != {b} (tol {tol})");
}

#[test]
fn static_image_converges_geometrically_with_the_weight() {
    let mut taa = Taa::report(W, H).unwrap_or_else(|e| panic!("{e}"));
    // Frame 0 (no history) takes the current image: a flat 0.5.
    let first = resolve(&mut taa, &[0.5; N], [0.0; 2]);
    assert!(
        first.iter().all(|v| *v == 0.5),
        "frame 0 is the current frame"
    );
    let target = stripes();
    for t in 1..=30 {
        let out = resolve(&mut taa, &target, [0.0; 2]);
        // out_t - c = (1 - w)^t (0.5 - c).
        let k = (1.0 - f64::from(WEIGHT)).powi(t);
        for (i, (o, c)) in out.iter().zip(&target).enumerate() {
            let want = f64::from(*c) + k * (0.5 - f64::from(*c));
            close(*o, want as f32, 1e-5, &format!("frame {t} pixel {i}"));
        }
    }
}

#[test]
fn history_outside_the_neighbourhood_is_clamped() {
    let mut taa = Taa::report(W, H).unwrap_or_else(|e| panic!("{e}"));
    resolve(&mut taa, &[1.0; N], [0.0; 2]);
    // The current frame spans [0.2, 0.4]: the history 1 is clamped to each pixel's 3x3
    // maximum before the blend.
    let cur: Vec<f32> = (0..N).map(|i| 0.2 + 0.2 * ((i % 3) as f32 / 2.0)).collect();
    let out = resolve(&mut taa, &cur, [0.0; 2]);
    for (i, (o, c)) in out.iter().zip(&cur).enumerate() {
        let (x, y) = (i % W as usize, i / W as usize);
        let mut hi = f32::MIN;
        for ny in y.saturating_sub(1)..(y + 2).min(H as usize) {
            for nx in x.saturating_sub(1)..(x + 2).min(W as usize) {
                hi = hi.max(cur[ny * W as usize + nx]);
            }
        }
        close(*o, hi + WEIGHT * (c - hi), 1e-6, &format!("pixel {i}"));
    }
}

#[test]
fn variance_clip_uses_mean_and_sigma_of_the_neighbourhood() {
    let mut taa =
        Taa::new(3, 3, 0.1, Clamp::Variance { gamma: 1.0 }).unwrap_or_else(|e| panic!("{e}"));
    let m = [1_u8; 9];
    let z = [1.0_f32; 9];
    let motion = [[0.0_f32; 2]; 9];
    let frame = |value: &[f32; 9]| {
        let value = value.to_vec();
        (value, motion, m, z)
    };
    let (v0, mo, ma, de) = frame(&[0.0; 9]);
    let _ = taa.resolve(&TaaFrame {
        value: &v0,
        motion: &mo,
        depth: &de,
        mask: &ma,
        skipped: None,
    });
    // The centre's neighbourhood is the whole 3x3: values 0.1..0.9, mean 0.5, population
    // sigma sqrt(sum (k/10 - 0.5)^2 / 9) = sqrt(0.6 / 9).
    let (v1, mo, ma, de) = frame(&[0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]);
    let out = taa
        .resolve(&TaaFrame {
            value: &v1,
            motion: &mo,
            depth: &de,
            mask: &ma,
            skipped: None,
        })
        .unwrap_or_else(|e| panic!("{e}"))
        .to_vec();
    let lo = 0.5 - (0.6_f32 / 9.0).sqrt();
    close(out[4], lo + 0.1 * (0.5 - lo), 1e-6, "centre pixel");
}

#[test]
fn disoccluded_pixels_take_the_current_value() {
    let mut taa = Taa::report(W, H).unwrap_or_else(|e| panic!("{e}"));
    // Frame 0: pixel 10 not covered (an occluder in front), pixel 20 at another depth.
    let mut mask = [1_u8; N];
    mask[10] = 0;
    let mut depth = [1.0_f32; N];
    depth[20] = 0.8;
    resolve_masked(&mut taa, &[0.9; N], [0.0; 2], &mask, &depth);
    let cur = stripes();
    let out = resolve(&mut taa, &cur, [0.0; 2]);
    assert_eq!(out[10], cur[10], "uncovered last frame: the current value");
    assert_eq!(out[20], cur[20], "depth moved by 20%: the current value");
    close(
        out[11],
        0.9 + WEIGHT * (cur[11] - 0.9),
        1e-6,
        "a pixel with history",
    );
    assert!(!taa.had_history()[10] && !taa.had_history()[20] && taa.had_history()[11]);
    // A pixel the current frame does not cover is passed through.
    let mut mask = [1_u8; N];
    mask[5] = 0;
    let out = resolve_masked(&mut taa, &[0.25; N], [0.0; 2], &mask, &[1.0; N]);
    assert_eq!(out[5], 0.25, "uncovered now: passed through");
}

#[test]
fn an_integer_pan_moves_the_history_exactly() {
    let mut taa = Taa::report(W, H).unwrap_or_else(|e| panic!("{e}"));
    // Frame 0: a ramp in [0, 1].
    let first: Vec<f32> = (0..N).map(|i| i as f32 / N as f32).collect();
    resolve(&mut taa, &first, [0.0; 2]);
    // The scene moves 2 px right and 1 px down on screen: pixel (x, y) was at (x-2, y-1).
    let cur = stripes();
    let out = resolve(&mut taa, &cur, [2.0, 1.0]);
    for (i, o) in out.iter().enumerate() {
        let (x, y) = (i % W as usize, i / W as usize);
        let want = if x >= 2 && y >= 1 {
            let h = first[(y - 1) * W as usize + x - 2];
            h + WEIGHT * (cur[i] - h)
        } else {
            cur[i] // entered the frame: no history
        };
        close(*o, want, 1e-6, &format!("pixel ({x}, {y})"));
    }
}

#[test]
fn a_half_pixel_pan_fetches_catmull_rom_inside_and_bilinear_at_the_border() {
    let mut taa = Taa::report(W, H).unwrap_or_else(|e| panic!("{e}"));
    let first: Vec<f32> = (0..N).map(|i| ((i * 7) % 11) as f32 / 10.0).collect();
    resolve(&mut taa, &first, [0.0; 2]);
    let cur: Vec<f32> = (0..N)
        .map(|i| if i % 2 == 0 { -1.0 } else { 2.0 })
        .collect();
    let out = resolve(&mut taa, &cur, [0.5, 0.0]);
    // Pixel (x, y) was at x + 0.5 - 0.5 = x: halfway between texels x-1 and x. Where the
    // 4x4 footprint (columns x-2..x+1, rows y-1..y+2) lies in the frame, the Catmull-Rom
    // weights at t = 1/2 are (-1, 9, 9, -1) / 16; elsewhere the bilinear taps.
    let (w, h) = (W as usize, H as usize);
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let hist = if x >= 2 && x + 1 < w && y >= 1 && y + 2 < h {
                (-first[i - 2] + 9.0 * first[i - 1] + 9.0 * first[i] - first[i + 1]) / 16.0
            } else if x >= 1 {
                0.5 * (first[i - 1] + first[i])
            } else {
                // Column 0: only its own texel is inside, renormalised to weight 1.
                first[i]
            };
            close(
                out[i],
                hist + WEIGHT * (cur[i] - hist),
                1e-6,
                &format!("pixel ({x}, {y})"),
            );
        }
    }
}

/// Catmull-Rom reproduces a linear image exactly: a ramp moved by a quarter pixel reads
/// the ramp a quarter pixel back (where the footprint lies in the frame).
#[test]
fn a_ramp_moves_exactly_under_sub_pixel_motion() {
    let mut taa = Taa::report(W, H).unwrap_or_else(|e| panic!("{e}"));
    let ramp = |x: f32, y: f32| 0.1 * x + 0.05 * y;
    let first: Vec<f32> = (0..N)
        .map(|i| ramp((i % W as usize) as f32, (i / W as usize) as f32))
        .collect();
    resolve(&mut taa, &first, [0.0; 2]);
    // A current frame whose every 3x3 box spans [-10, 10]: nothing is clamped.
    let cur: Vec<f32> = (0..N)
        .map(|i| if i % 2 == 0 { -10.0 } else { 10.0 })
        .collect();
    let v = [0.25, 0.75];
    let out = resolve(&mut taa, &cur, v);
    let (w, h) = (W as usize, H as usize);
    for y in 2..h - 2 {
        for x in 2..w - 2 {
            let i = y * w + x;
            let hist = ramp(x as f32 - v[0], y as f32 - v[1]);
            close(
                out[i],
                hist + WEIGHT * (cur[i] - hist),
                1e-5,
                &format!("pixel ({x}, {y})"),
            );
        }
    }
}

#[test]
fn bad_parameters_and_sizes_are_named() {
    for w in [0.0_f32, -0.1, 1.5, f32::NAN] {
        let e = Taa::new(4, 4, w, Clamp::MinMax)
            .err()
            .map(|e| e.to_string());
        assert!(e.is_some_and(|e| e.contains("weight")), "weight {w}");
    }
    let e = Taa::new(
        4,
        4,
        0.1,
        Clamp::Variance {
            gamma: f32::INFINITY,
        },
    )
    .err();
    assert!(e.is_some_and(|e| e.to_string().contains("gamma")));
    let mut taa = Taa::report(4, 4).unwrap_or_else(|e| panic!("{e}"));
    let frame = TaaFrame {
        value: &[0.0; 16],
        motion: &[[0.0; 2]; 15],
        depth: &[1.0; 16],
        mask: &[1; 16],
        skipped: None,
    };
    let e = taa.resolve(&frame).err().map(|e| e.to_string());
    assert!(
        e.is_some_and(|e| e.contains("motion")),
        "the short image is named"
    );
}

#[test]
fn flicker_is_the_change_of_the_error_along_the_motion() {
    let mut f = Flicker::default();
    let motion = vec![[1.0_f32, 0.0]; N];
    let frame = TaaFrame {
        value: &[],
        motion: &motion,
        depth: &[1.0; N],
        mask: &[1; N],
        skipped: None,
    };
    let reference: Vec<f32> = (0..N).map(|i| i as f32 / N as f32).collect();
    // Frame 0: the image is the reference plus 0.1: no previous frame.
    let x0: Vec<f32> = reference.iter().map(|r| r + 0.1).collect();
    assert!(
        f.push(&x0, &reference, &frame, [W, H]).is_nan(),
        "first frame"
    );
    // Frame 1: the error is 0.1 at even pixels and -0.2 at odd ones. Along the motion
    // (pixel x continues x - 1) the previous error was 0.1 everywhere.
    let x1: Vec<f32> = reference
        .iter()
        .enumerate()
        .map(|(i, r)| r + if i % 2 == 0 { 0.1 } else { -0.2 })
        .collect();
    let got = f.push(&x1, &reference, &frame, [W, H]);
    // Column 0 entered the frame; of the other 7 columns 3 are even (|0|) and 4 odd (0.3).
    let want = 4.0 * 0.3 / 7.0;
    assert!((got - want).abs() < 1e-5, "{got} != {want}");
    // An unscored frame restarts the measure.
    assert!(f.push(&x1, &[], &frame, [W, H]).is_nan());
    assert!(f.push(&x1, &reference, &frame, [W, H]).is_nan());
}

#[test]
fn clamped_history_is_the_history_before_the_blend() {
    let mut taa = Taa::report(W, H).unwrap_or_else(|e| panic!("{e}"));
    resolve(&mut taa, &[1.0; N], [0.0; 2]);
    assert!(
        taa.clamped_history().iter().all(|c| c.is_nan()),
        "frame 0 has no history: NaN everywhere"
    );
    // The current frame spans [0.2, 0.4]: C is the history 1 clamped to each pixel's 3x3
    // maximum, and the resolved value is C + w (S - C).
    let cur: Vec<f32> = (0..N).map(|i| 0.2 + 0.2 * ((i % 3) as f32 / 2.0)).collect();
    let out = resolve(&mut taa, &cur, [0.0; 2]);
    for (i, ((o, s), c)) in out.iter().zip(&cur).zip(taa.clamped_history()).enumerate() {
        let (x, y) = (i % W as usize, i / W as usize);
        let mut hi = f32::MIN;
        for ny in y.saturating_sub(1)..(y + 2).min(H as usize) {
            for nx in x.saturating_sub(1)..(x + 2).min(W as usize) {
                hi = hi.max(cur[ny * W as usize + nx]);
            }
        }
        assert_eq!(*c, hi, "pixel {i}: the clamped history");
        assert_eq!(*o, c + WEIGHT * (s - c), "pixel {i}: the blend of C");
    }
}

/// The weight each resolve gave its frame (`Taa::resolve_weights`, the resolved-image
/// rule's per-pixel input): 1 on the first frame, on a disoccluded pixel and where the
/// clamp moved the history by more than `CLAMP_TOLERANCE` of the box plus `CLAMP_FLOOR`;
/// `WEIGHT` where the history was kept (inside the box, or moved less than the
/// tolerance). The cases are built against the box by hand.
#[test]
fn resolve_weights_mark_rejected_and_clamped_away_histories() {
    let mut taa = Taa::report(W, H).unwrap_or_else(|e| panic!("{e}"));
    assert!(taa.resolve_weights().is_empty(), "before the first frame");
    // Frame 0: no history anywhere.
    resolve(&mut taa, &stripes(), [0.0; 2]);
    assert!(taa.resolve_weights().iter().all(|&w| w == 1.0), "frame 0");
    // The same stripes: every history inside its [0, 1] box, kept.
    resolve(&mut taa, &stripes(), [0.0; 2]);
    assert!(taa.resolve_weights().iter().all(|&w| w == WEIGHT), "steady");
    // A flat image at 0.5 over the history of stripes (0 or 1 before it, after one blend
    // near 0 or 1): the box is [0.5, 0.5], so every history moves by about 0.5 > the
    // floor: clamped away.
    resolve(&mut taa, &[0.5; N], [0.0; 2]);
    assert!(
        taa.resolve_weights().iter().all(|&w| w == 1.0),
        "clamped away"
    );
    // Now every history is 0.5. A box of width 0.2 around 0.6 ([0.5, 0.7] at every
    // pixel) holds it: kept. Then a box [0.5 + d, 0.7] with d under the tolerance
    // (CLAMP_TOLERANCE * 0.2 + CLAMP_FLOOR) keeps it, above it discards it.
    let rows = |lo: f32| -> Vec<f32> {
        (0..N)
            .map(|i| {
                if (i / W as usize).is_multiple_of(2) {
                    lo
                } else {
                    0.7
                }
            })
            .collect()
    };
    resolve(&mut taa, &rows(0.5), [0.0; 2]);
    assert!(taa.resolve_weights().iter().all(|&w| w == WEIGHT), "inside");
    let tol = |lo: f32| CLAMP_TOLERANCE * (0.7 - lo) + CLAMP_FLOOR;
    let mut small = Taa::report(W, H).unwrap_or_else(|e| panic!("{e}"));
    let mut large = Taa::report(W, H).unwrap_or_else(|e| panic!("{e}"));
    for t in [&mut small, &mut large] {
        resolve(t, &[0.5; N], [0.0; 2]);
        resolve(t, &[0.5; N], [0.0; 2]);
    }
    // Histories exactly 0.5 now (a flat 0.5 from frame 0 on).
    let d_small = 0.5 * tol(0.5);
    let d_large = 3.0 * tol(0.5);
    resolve(&mut small, &rows(0.5 + d_small), [0.0; 2]);
    resolve(&mut large, &rows(0.5 + d_large), [0.0; 2]);
    assert!(
        small.resolve_weights().iter().all(|&w| w == WEIGHT),
        "moved {d_small} < {}",
        tol(0.5 + d_small)
    );
    assert!(
        large.resolve_weights().iter().all(|&w| w == 1.0),
        "moved {d_large} > {}",
        tol(0.5 + d_large)
    );
    // Disocclusion: the right half's depth jumps (depth test fails): weight 1 there,
    // the left half keeps its history.
    let depth: Vec<f32> = (0..N)
        .map(|i| if i % W as usize >= 4 { 2.0 } else { 1.0 })
        .collect();
    resolve_masked(&mut taa, &rows(0.5), [0.0; 2], &[1; N], &depth);
    for (i, &w) in taa.resolve_weights().iter().enumerate() {
        let want = if i % W as usize >= 4 { 1.0 } else { WEIGHT };
        assert_eq!(w, want, "pixel {i}");
    }
}

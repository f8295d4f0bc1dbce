//! The error of the pixels a moving object uncovers, by their age on screen: per frame, the
//! squared error and the samples of the pixels uncovered this frame (age 1), the frame
//! before (age 2) and two frames before (age 3), and of the steady pixels, summed so that
//! frames pool into one MSE and one mean count per age.
//!
//! The moving-object scenes have a static camera, so an uncovered surface point stays at
//! its pixel: counting frames per pixel follows the point.

use crate::metrics::PSNR_PEAK;

/// Ages tracked: a pixel uncovered this frame is at age 1; after age [`AGES`] it counts as
/// steady.
pub const AGES: u8 = 3;

/// The mark of a pixel on a moving object (neither uncovered nor steady).
pub const ON_OBJECT: u8 = u8::MAX;

/// Each pixel's frames since it was uncovered, from the frame before's (`before`) and
/// whether the pixel shows a moving object now (`moving`): [`ON_OBJECT`] on an object; 1
/// where the pixel showed one the frame before and does not now; one more than the frame
/// before's up to [`AGES`]; 0 (steady) after that and where no object passed. `before` all
/// 0 on the first frame.
#[must_use]
pub fn since_uncovered(before: &[u8], moving: &[bool]) -> Vec<u8> {
    before
        .iter()
        .zip(moving)
        .map(|(&b, &m)| match (m, b) {
            (true, _) => ON_OBJECT,
            (false, ON_OBJECT) => 1,
            (false, k) if (1..AGES).contains(&k) => k + 1,
            _ => 0,
        })
        .collect()
}

/// Squared error and sample sums of one frame (or pooled frames) by age since uncovered:
/// index 0 the steady pixels, 1..=3 the pixels at age 1, 2, 3 ([`since_uncovered`]);
/// pixels on a moving object are in none.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AgeErrors {
    /// Sum of `(value - reference)^2` per class.
    pub sse: [f64; 4],
    /// Pixels per class.
    pub n: [u64; 4],
    /// Sum of the pixels' sample counts per class.
    pub samples: [f64; 4],
}

impl AgeErrors {
    /// The sums of one frame's `value` against `reference`, taken with `count` samples
    /// per pixel, with the pixels' `since` ([`since_uncovered`]). A non-finite difference
    /// counts as the largest error (the peak squared), as
    /// [`crate::metrics::psnr_of_pairs`] counts it.
    #[must_use]
    pub fn of_frame(value: &[f32], reference: &[f32], since: &[u8], count: &[u32]) -> Self {
        let mut e = Self::default();
        for (((v, r), &k), &c) in value.iter().zip(reference).zip(since).zip(count) {
            if k > AGES {
                continue;
            }
            let d = f64::from(*v) - f64::from(*r);
            let k = usize::from(k);
            e.sse[k] += if d.is_finite() {
                d * d
            } else {
                PSNR_PEAK * PSNR_PEAK
            };
            e.n[k] += 1;
            e.samples[k] += f64::from(c);
        }
        e
    }

    /// The sums of `frames` together (pooled: each pixel-frame weighs the same).
    #[must_use]
    pub fn pooled<'a>(frames: impl IntoIterator<Item = &'a Self>) -> Self {
        frames.into_iter().fold(Self::default(), |mut a, f| {
            for k in 0..4 {
                a.sse[k] += f.sse[k];
                a.n[k] += f.n[k];
                a.samples[k] += f.samples[k];
            }
            a
        })
    }

    /// The classes `ages` (each in 0..=3) together: their sums added.
    #[must_use]
    pub fn classes(&self, ages: core::ops::RangeInclusive<usize>) -> Self {
        let mut out = Self::default();
        for k in ages.filter(|k| *k < 4) {
            out.sse[0] += self.sse[k];
            out.n[0] += self.n[k];
            out.samples[0] += self.samples[k];
        }
        out
    }

    /// Mean samples per pixel of class `k` (`None` where it has no pixel).
    #[must_use]
    pub fn spp(&self, k: usize) -> Option<f64> {
        let (&s, &n) = (self.samples.get(k)?, self.n.get(k)?);
        (n > 0).then(|| s / n as f64)
    }

    /// PSNR of class `k` (0 steady, 1..=3 the ages): `10 log10(peak^2 / MSE)`, the MSE
    /// floored at 1e-12 as [`crate::metrics::psnr_of_pairs`] does; `None` where the class
    /// has no pixel (or `k` is out of range).
    #[must_use]
    pub fn psnr(&self, k: usize) -> Option<f64> {
        let (&sse, &n) = (self.sse.get(k)?, self.n.get(k)?);
        (n > 0).then(|| 10.0 * (PSNR_PEAK * PSNR_PEAK / (sse / n as f64).max(1e-12)).log10())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three pixels over five frames, by hand: pixel 0 never covered, pixel 1 covered on
    /// frames 0 and 1 then uncovered, pixel 2 covered on frame 2 only.
    #[test]
    fn ages_and_pooled_errors_by_hand() {
        let moving = [
            [false, true, false],
            [false, true, false],
            [false, false, true],
            [false, false, false],
            [false, false, false],
        ];
        let want: [[u8; 3]; 5] = [
            [0, ON_OBJECT, 0],
            [0, ON_OBJECT, 0],
            [0, 1, ON_OBJECT],
            [0, 2, 1],
            [0, 3, 2],
        ];
        let mut since = vec![0; 3];
        let mut frames = Vec::new();
        for (t, m) in moving.iter().enumerate() {
            since = since_uncovered(&since, m);
            assert_eq!(since, want[t], "frame {t}");
            // Errors 1/8, 2/8, 3/8 on pixels 0, 1, 2 (exact in f32 and f64).
            frames.push(AgeErrors::of_frame(
                &[0.625, 0.75, 0.875],
                &[0.5, 0.5, 0.5],
                &since,
                &[8, 16, 32],
            ));
        }
        let (e0, e1, e2) = (1.0 / 64.0, 4.0 / 64.0, 9.0 / 64.0);
        // The frame after age 3 is steady again.
        assert_eq!(since_uncovered(&since, &[false; 3]), [0, 0, 3]);
        // Frame 3: pixel 0 steady, pixel 1 at age 2, pixel 2 at age 1.
        let f3 = frames[3];
        assert_eq!(f3.n, [1, 1, 1, 0]);
        assert_eq!(f3.sse, [e0, e2, e1, 0.0]);
        assert!(f3.psnr(3).is_none());
        // Pooled over all frames: steady = pixel 0 on 5 frames and pixel 2 on frames 0
        // and 1; age 1: pixel 1 on frame 2 and pixel 2 on frame 3; age 2: pixel 1 on
        // frame 3 and pixel 2 on frame 4; age 3: pixel 1 on frame 4.
        let p = AgeErrors::pooled(&frames);
        assert_eq!(p.n, [7, 2, 2, 1]);
        let db = |sse: f64, n: f64| 10.0 * (n / sse).log10();
        let want = [
            db(5.0 * e0 + 2.0 * e2, 7.0),
            db(e1 + e2, 2.0),
            db(e1 + e2, 2.0),
            db(e1, 1.0),
        ];
        for (k, w) in want.iter().enumerate() {
            let got = p.psnr(k).expect("pixels in every class");
            assert!((got - w).abs() < 1e-9, "class {k}: {got} vs {w}");
        }
        assert!(p.psnr(4).is_none());
        // Samples: steady = 5 frames of pixel 0 (8) and 2 of pixel 2 (32); ages 1..=3
        // together: pixel 1 at 16 on three frames, pixel 2 at 32 on two.
        assert_eq!(p.spp(0), Some((5.0 * 8.0 + 2.0 * 32.0) / 7.0));
        let young = p.classes(1..=3);
        assert_eq!(young.n[0], 5);
        assert_eq!(young.spp(0), Some((3.0 * 16.0 + 2.0 * 32.0) / 5.0));
        assert_eq!(
            young.psnr(0),
            Some(db(3.0 * e1 + 2.0 * e2, 5.0)),
            "pooled ages: pixel 1 (e1) on frames 2-4, pixel 2 (e2) on frames 3-4"
        );
    }
}

//! Frame metrics: samples per pixel and PSNR of luminance over subsurface pixels, and the
//! temporal accumulation used for the "accumulated" PSNR.

use half::f16;

use crate::wgpu_api::luminance;

/// Peak luminance of the PSNR (the key light's lit level is about 1).
pub const PSNR_PEAK: f64 = 1.0;

/// Mean of `count` over pixels with `mask != 0` (0 when there are none).
#[must_use]
pub fn mean_spp(count: &[u32], mask: &[u8]) -> f64 {
    let (sum, n) = count
        .iter()
        .zip(mask)
        .filter(|(_, m)| **m != 0)
        .fold((0.0, 0_usize), |(s, n), (c, _)| (s + f64::from(*c), n + 1));
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// The crate's one PSNR: `10 log10(PSNR_PEAK^2 / MSE)` in dB over `(value, reference)`
/// pairs, with [`PSNR_PEAK`] = 1 (the lit level of the subsurface scenes' key light, and
/// the largest ambient-occlusion value). A non-finite difference counts as an error of
/// `PSNR_PEAK`; the MSE is floored at 1e-12, so identical values (or no pairs) give a
/// finite 120 dB rather than infinity.
///
/// The subsurface report applies it to the luminance of the scored pixels ([`psnr`]); the
/// motion report to the AO value of every pixel, or of its steady pixels.
///
/// # Examples
///
/// ```
/// use spvg_report::metrics::psnr_of_pairs;
/// // An error of 0.1 everywhere: 10 log10(1 / 0.01) = 20 dB.
/// assert!((psnr_of_pairs([(0.6, 0.5), (0.4, 0.5)]) - 20.0).abs() < 1e-9);
/// // Identical values reach the 120 dB floor, not infinity.
/// assert_eq!(psnr_of_pairs([(0.5, 0.5)]), 120.0);
/// ```
#[must_use]
pub fn psnr_of_pairs(pairs: impl IntoIterator<Item = (f64, f64)>) -> f64 {
    let (mut se, mut n) = (0.0_f64, 0_usize);
    for (a, b) in pairs {
        let d = a - b;
        se += if d.is_finite() {
            d * d
        } else {
            PSNR_PEAK * PSNR_PEAK
        };
        n += 1;
    }
    let mse = if n == 0 { 0.0 } else { se / n as f64 };
    10.0 * (PSNR_PEAK * PSNR_PEAK / mse.max(1e-12)).log10()
}

/// PSNR ([`psnr_of_pairs`]) of the luminance of `image` against `reference` over pixels
/// with `mask != 0`.
///
/// # Examples
///
/// ```
/// use spvg_report::metrics::psnr;
/// let reference = [[0.5_f32; 3]; 4];
/// let image = [[0.51_f32; 3]; 4];
/// // Luminance error 0.01 everywhere: 10 log10(1 / 1e-4) = 40 dB.
/// assert!((psnr(&image, &reference, &[1; 4]) - 40.0).abs() < 1e-3);
/// // Masked-out pixels do not count.
/// assert!(psnr(&image, &reference, &[0; 4]) > 119.0);
/// ```
#[must_use]
pub fn psnr(image: &[[f32; 3]], reference: &[[f32; 3]], mask: &[u8]) -> f64 {
    psnr_of_pairs(
        image
            .iter()
            .zip(reference)
            .zip(mask)
            .filter(|(_, m)| **m != 0)
            .map(|((a, b), _)| (f64::from(luminance(*a)), f64::from(luminance(*b)))),
    )
}

/// The `eps` of [`relmse`]: keeps near-black reference pixels from dominating the mean.
pub const RELMSE_EPS: f64 = 1e-4;

/// Relative MSE of the luminance of `image` against `reference` over pixels with
/// `mask != 0`: the mean of `(x - ref)^2 / (ref^2 + eps)` with `eps = RELMSE_EPS`, the
/// metric of the CV paper (Xie & Olano 2021). A non-finite pixel counts as a relative
/// error of 1; no pixels give 0.
///
/// # Examples
///
/// ```
/// use spvg_report::metrics::{RELMSE_EPS, relmse};
/// let reference = [[0.5_f32; 3], [0.0; 3]];
/// let image = [[0.55_f32; 3], [0.01; 3]];
/// // (0.05^2 / (0.25 + eps) + 0.01^2 / (0 + eps)) / 2: the dark pixel counts as 1.
/// let want = (0.05_f64.powi(2) / (0.25 + RELMSE_EPS) + 1e-4 / RELMSE_EPS) / 2.0;
/// assert!((relmse(&image, &reference, &[1, 1]) - want).abs() < 1e-6);
/// ```
#[must_use]
pub fn relmse(image: &[[f32; 3]], reference: &[[f32; 3]], mask: &[u8]) -> f64 {
    let (mut sum, mut n) = (0.0_f64, 0_usize);
    for ((a, b), m) in image.iter().zip(reference).zip(mask) {
        if *m == 0 {
            continue;
        }
        let r = f64::from(luminance(*b));
        let d = f64::from(luminance(*a)) - r;
        let e = d * d / (r * r + RELMSE_EPS);
        sum += if e.is_finite() { e } else { 1.0 };
        n += 1;
    }
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// RGB of a result texel.
#[inline]
#[must_use]
pub fn rgb(t: [f16; 4]) -> [f32; 3] {
    [t[0].to_f32(), t[1].to_f32(), t[2].to_f32()]
}

/// Temporal accumulation of results: `acc = 0.8 acc + 0.2 result`, reset to the result
/// where the pixel has no valid history (not subsurface in the previous frame, or the
/// first frame), as a TAA-like resolve would.
#[derive(Clone, Debug, Default)]
pub struct Accumulator {
    acc: Vec<[f32; 3]>,
    prev_mask: Vec<u8>,
}

/// Weight of the new frame in [`Accumulator`].
pub const ACCUMULATION_WEIGHT: f32 = 0.2;

impl Accumulator {
    /// Adds a frame and returns the accumulated image.
    pub fn push(&mut self, result: &[[f32; 3]], mask: &[u8]) -> &[[f32; 3]] {
        if self.acc.len() != result.len() {
            self.acc = result.to_vec();
        } else {
            for (i, (a, r)) in self.acc.iter_mut().zip(result).enumerate() {
                let valid = self.prev_mask.get(i).copied().unwrap_or(0) != 0
                    && mask.get(i).copied().unwrap_or(0) != 0
                    && a.iter().all(|v| v.is_finite());
                if valid {
                    for c in 0..3 {
                        a[c] = (1.0 - ACCUMULATION_WEIGHT) * a[c] + ACCUMULATION_WEIGHT * r[c];
                    }
                } else {
                    *a = *r;
                }
            }
        }
        self.prev_mask = mask.to_vec();
        &self.acc
    }
}

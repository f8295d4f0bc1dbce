//! Frame metrics: samples per pixel, PSNR and relative MSE against the converged reference,
//! and the temporal stability of a resolved image ([`Flicker`]).

use half::f16;

use spvg::reproject::Reprojection;

use crate::taa::{TaaFrame, reproject_taps};
use crate::wgpu_api::luminance;

/// Peak luminance of the PSNR (the key light's lit level is about 1).
pub const PSNR_PEAK: f64 = 1.0;

/// Luminance RMSE of `image` against `reference` over the pixels where `set` is nonzero
/// (0 for an empty set).
#[must_use]
pub fn rmse(image: &[[f32; 3]], reference: &[[f32; 3]], set: &[u8]) -> f64 {
    let (mut se, mut n) = (0.0_f64, 0_usize);
    for ((a, b), _) in image
        .iter()
        .zip(reference)
        .zip(set)
        .filter(|(_, s)| **s != 0)
    {
        let d = f64::from(luminance(*a)) - f64::from(luminance(*b));
        se += d * d;
        n += 1;
    }
    if n == 0 { 0.0 } else { (se / n as f64).sqrt() }
}

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
    relmse_of_pairs(
        image
            .iter()
            .zip(reference)
            .zip(mask)
            .filter(|(_, m)| **m != 0)
            .map(|((a, b), _)| (f64::from(luminance(*a)), f64::from(luminance(*b)))),
    )
}

/// The relative MSE of [`relmse`] over `(value, reference)` pairs: the mean of
/// `(x - ref)^2 / (ref^2 + RELMSE_EPS)`, a non-finite term counting as 1, no pairs 0.
///
/// # Examples
///
/// ```
/// use spvg_report::metrics::{RELMSE_EPS, relmse_of_pairs};
/// let want = 0.01 / (0.25 + RELMSE_EPS);
/// assert!((relmse_of_pairs([(0.6, 0.5), (0.4, 0.5)]) - want).abs() < 1e-12);
/// ```
#[must_use]
pub fn relmse_of_pairs(pairs: impl IntoIterator<Item = (f64, f64)>) -> f64 {
    let (mut sum, mut n) = (0.0_f64, 0_usize);
    for (a, r) in pairs {
        let d = a - r;
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

/// Temporal instability of a sequence of images against their references: per frame, the
/// mean over the covered pixels that have a reprojected previous frame (the TAA's bilinear
/// taps and rejection, [`reproject_taps`]) of `|(x_t - x_(t-1)) - (r_t - r_(t-1))|`, the
/// frame-to-frame change of the image less the reference's own change along the motion.
/// A converged, stable image scores 0 however the lighting or camera moves; flicker and
/// lag score its size (in the image's units: luminance, AO).
#[derive(Clone, Debug, Default)]
pub struct Flicker {
    /// The previous frame's error image `x - r`, depth and mask.
    previous: Option<(Vec<f32>, Vec<f32>, Vec<u8>)>,
}

impl Flicker {
    /// Adds a frame (`image` against `reference`, with the motion, depth and mask of
    /// `frame`; `frame.value` is not read) of `size`, and returns its instability: NaN on
    /// the first frame, after a frame without a reference, or with no pixel reprojected.
    /// An empty `reference` (an unscored frame) restarts the measure.
    pub fn push(
        &mut self,
        image: &[f32],
        reference: &[f32],
        frame: &TaaFrame<'_>,
        size: [u32; 2],
    ) -> f64 {
        if reference.len() != image.len() || image.len() != frame.mask.len() {
            self.previous = None;
            return f64::NAN;
        }
        let error: Vec<f32> = image
            .iter()
            .zip(reference)
            .zip(frame.mask)
            .map(|((x, r), m)| if *m != 0 { x - r } else { 0.0 })
            .collect();
        let rule = Reprojection::<f32>::default();
        let w = size[0] as usize;
        let (mut sum, mut n) = (0.0_f64, 0_usize);
        if let Some((before, depth, mask)) = &self.previous {
            for (i, e) in error.iter().enumerate() {
                if frame.mask[i] == 0 {
                    continue;
                }
                let px = [(i % w) as u32, (i / w) as u32];
                let motion = frame.motion.get(i).copied().unwrap_or([f32::NAN; 2]);
                let z = frame.depth.get(i).copied().unwrap_or(f32::NAN);
                if let Some(t) = reproject_taps(px, motion, z, size, depth, mask, &rule) {
                    let d = f64::from(*e) - f64::from(t.fetch(before));
                    if d.is_finite() {
                        sum += d.abs();
                        n += 1;
                    }
                }
            }
        }
        self.previous = Some((error, frame.depth.to_vec(), frame.mask.to_vec()));
        if n == 0 { f64::NAN } else { sum / n as f64 }
    }
}

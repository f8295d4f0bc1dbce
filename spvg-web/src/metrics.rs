//! The figures the page shows: mean, PSNR against a reference, and the equal-quality
//! fixed count (interpolated in `log2(spp)`, as the report does: a fixed count's MSE falls
//! as `1 / n`, so its PSNR is linear in `log2(n)`).

/// The mean of `values` (0 for none).
#[must_use]
pub fn mean(values: impl IntoIterator<Item = f64>) -> f64 {
    let (sum, n) = values
        .into_iter()
        .fold((0.0, 0_u64), |(s, n), v| (s + v, n + 1));
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// The samples per pixel behind the last frame of a TAA resolve that started with the
/// first of `spp` (each frame's mean count) and blends each later frame with weight
/// `alpha`: frame `k` of `K` counts `alpha (1 - alpha)^(K - 1 - k)`, the first
/// `(1 - alpha)^(K - 1)` (it had no history), which sum to 1. The neighbourhood clamp
/// is ignored: these are the blend's nominal weights.
#[must_use]
pub fn taa_weighted(spp: &[f64], alpha: f64) -> f64 {
    let k = spp.len();
    spp.iter()
        .enumerate()
        .map(|(i, s)| {
            let kept = (1.0 - alpha).powi((k - 1 - i) as i32);
            s * if i == 0 { kept } else { alpha * kept }
        })
        .sum()
}

/// PSNR in dB of `image` against `reference`, both in `[0, 1]` (peak 1); infinite where
/// they are equal, NaN where their lengths differ or they are empty.
#[must_use]
pub fn psnr(image: &[f32], reference: &[f32]) -> f64 {
    if image.len() != reference.len() || image.is_empty() {
        return f64::NAN;
    }
    let mse = mean(
        image
            .iter()
            .zip(reference)
            .map(|(&a, &b)| (f64::from(a) - f64::from(b)).powi(2)),
    );
    -10.0 * mse.log10()
}

/// Where a run of PSNR `psnr` sits among fixed-count runs `(count, psnr)` (counts
/// increasing): the fixed count of equal PSNR, interpolated linearly in `log2(count)`
/// between the two runs that bracket it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum EqualQuality {
    /// The fixed count that gives the same PSNR.
    Count(f64),
    /// Better than the largest fixed count measured (that count).
    Beyond(u32),
    /// Worse than the smallest fixed count measured (that count).
    Below(u32),
    /// No fixed runs.
    #[default]
    Unknown,
}

impl EqualQuality {
    /// Places `psnr` among `fixed` (`(count, psnr)`, counts increasing).
    #[must_use]
    pub fn of(psnr: f64, fixed: &[(u32, f64)]) -> Self {
        let (Some(first), Some(last)) = (fixed.first(), fixed.last()) else {
            return Self::Unknown;
        };
        if psnr < first.1 {
            return Self::Below(first.0);
        }
        for w in fixed.windows(2) {
            let [(a, pa), (b, pb)] = [w[0], w[1]];
            if psnr >= pa && psnr <= pb {
                let (la, lb) = (f64::from(a).log2(), f64::from(b).log2());
                let f = if pb > pa {
                    (psnr - pa) / (pb - pa)
                } else {
                    0.0
                };
                return Self::Count((la + f * (lb - la)).exp2());
            }
        }
        if psnr <= last.1 {
            // Between two runs whose PSNR fell with the count (noise): the larger one.
            Self::Count(f64::from(last.0))
        } else {
            Self::Beyond(last.0)
        }
    }

    /// One phrase for the page and the log, for a run of `spp` samples per pixel:
    /// `fixed 23.4 spp (2.1x the samples)`, `beyond fixed 64`, `below fixed 4`.
    #[must_use]
    pub fn describe(&self, spp: f64) -> String {
        match *self {
            Self::Count(n) => format!("fixed {n:.1} spp ({:.2}x the samples)", n / spp),
            Self::Beyond(n) => format!("beyond fixed {n}"),
            Self::Below(n) => format!("below fixed {n}"),
            Self::Unknown => "not measured".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn psnr_of_a_known_error() {
        // Every pixel off by 0.1: MSE 0.01, 20 dB.
        let r = [0.2_f32, 0.5, 0.9];
        let a = r.map(|x| x + 0.1);
        let p = psnr(&a, &r);
        assert!((p - 20.0).abs() < 1e-4, "{p}");
        assert!(psnr(&r, &r).is_infinite(), "equal images");
        assert!(psnr(&r[..2], &r).is_nan(), "lengths differ");
    }

    #[test]
    fn taa_weights_sum_to_one_and_favour_the_last_frames() {
        assert!(
            (taa_weighted(&[7.0; 20], 0.1) - 7.0).abs() < 1e-12,
            "a constant count"
        );
        // One frame of 1 then ten of 0: only the first frame's weight, 0.9^10.
        let mut spp = vec![0.0; 11];
        spp[0] = 1.0;
        assert!((taa_weighted(&spp, 0.1) - 0.9_f64.powi(10)).abs() < 1e-12);
        assert_eq!(taa_weighted(&[3.0], 0.1), 3.0, "one frame is the resolve");
        assert_eq!(taa_weighted(&[], 0.1), 0.0, "no frames");
    }

    #[test]
    fn equal_quality_interpolates_in_log2_of_the_count() {
        let fixed = [(8, 30.0), (16, 33.0), (32, 36.0)];
        // Halfway between 16 and 32 in PSNR is halfway in log2: 16 * sqrt(2).
        let EqualQuality::Count(n) = EqualQuality::of(34.5, &fixed) else {
            panic!("bracketed");
        };
        assert!((n - 16.0 * 2f64.sqrt()).abs() < 1e-9, "{n}");
        assert_eq!(EqualQuality::of(30.0, &fixed), EqualQuality::Count(8.0));
        assert_eq!(EqualQuality::of(40.0, &fixed), EqualQuality::Beyond(32));
        assert_eq!(EqualQuality::of(20.0, &fixed), EqualQuality::Below(8));
        assert_eq!(EqualQuality::of(20.0, &[]), EqualQuality::Unknown);
        assert_eq!(
            EqualQuality::Count(32.0).describe(16.0),
            "fixed 32.0 spp (2.00x the samples)"
        );
    }
}

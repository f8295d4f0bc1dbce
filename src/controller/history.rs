//! The per-pixel SPVG history `H = (mu, var, nbar)`.

use num_traits::Float;

use super::{SpvgConfig, rules};

/// Per-pixel SPVG history: EMA and EMV of the monitored luminance `S`, and EMA of the
/// sample count actually used (docs/algorithms.md §2).
///
/// `Default` is the cold (all-zero) history that a freshly cleared texture holds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpvgHistory<T> {
    /// EMA of the monitored value `S` (`mu`).
    pub mean: T,
    /// EMV of the monitored value `S` (`var`), never negative.
    pub variance: T,
    /// EMA of the sample count used (`nbar`).
    pub mean_count: T,
}

impl<T: Float> SpvgHistory<T> {
    /// The history a disoccluded pixel starts from (docs/algorithms.md §2.3):
    /// `mean = sample`, `variance = sigma0^2` of `config`, `mean_count = count`, which is what
    /// [`SpvgConfig::update`] stores for `history_valid = false`. A frame without a usable
    /// observation (`count == 0` or a non-finite `sample`) gives the zero history, as
    /// that update does.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::{SpvgConfig, SpvgHistory};
    /// let c = SpvgConfig::<f32>::published();
    /// let h = SpvgHistory::seeded(0.5, &c, 32);
    /// assert_eq!(h, SpvgHistory { mean: 0.5, variance: 1e-4, mean_count: 32.0 });
    /// let mut updated = SpvgHistory { mean: 9.0, variance: 9.0, mean_count: 9.0 };
    /// c.update(&mut updated, 0.5, 32, false);
    /// assert_eq!(h, updated);
    /// assert_eq!(SpvgHistory::seeded(f32::NAN, &c, 32), SpvgHistory::default());
    /// ```
    #[inline]
    #[must_use]
    pub fn seeded(sample: T, config: &SpvgConfig<T>, count: u32) -> Self {
        rules::seed(config.target_variance(), sample, count)
    }
}

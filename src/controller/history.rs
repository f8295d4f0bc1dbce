//! The per-pixel SPVG history `H = (mu, var, nbar)`.

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

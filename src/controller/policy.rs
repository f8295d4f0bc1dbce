//! The count rules a configuration can use: SPVG and the comparison baselines.

/// Which rule turns a pixel's history into a sample count (docs/algorithms.md §2.1).
///
/// All rules share the zero-sample rule of docs/algorithms.md §2.4 (`gamma < eps_u` takes no samples),
/// the budget clamp and the rounding of [`SpvgConfig::estimate`](super::SpvgConfig::estimate),
/// and the history update of [`SpvgConfig::update`](super::SpvgConfig::update), so a
/// renderer compares them by changing one line. With `r = var / sigma0^2` (computed as
/// `var * inv_target`):
///
/// | policy | raw count `n_hat` |
/// |---|---|
/// | `Spvg` | `kappa Delta + E`, `E = r nbar`, `Delta = (r - 1) nbar (k - 1)` |
/// | `TwoPhase` | `r n_prev` (SPVG 7), `n_prev` stored in `mean_count` |
/// | `UnrealClamp` | `r` |
/// | `Fixed(n)` | `n` (the history is not read) |
///
/// # Examples
///
/// ```
/// use spvg::{SpvgConfig, SpvgHistory, controller::CountPolicy};
/// let h = SpvgHistory { mean: 1.0_f64, variance: 5.0, mean_count: 16.0 };
/// let c = SpvgConfig::<f64>::builder().target_variance(0.25).kappa(0.0).build().unwrap();
/// // r = 20: SPVG with kappa = 0 asks for r * nbar = 320, clamped to 64.
/// assert_eq!(c.estimate(&h, 1.0), 64);
/// // Unreal's rule ignores the count history: clamp(20, 8, 64) = 20.
/// let unreal = c.with_policy(CountPolicy::UnrealClamp).unwrap();
/// assert_eq!(unreal.estimate(&h, 1.0), 20);
/// let fixed = c.with_policy(CountPolicy::Fixed(32)).unwrap();
/// assert_eq!(fixed.estimate(&h, 1.0), 32);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CountPolicy {
    /// SPVG (docs/algorithms.md §2.1): `n_hat = kappa Delta + E` from the temporally accumulated
    /// variance and mean count.
    #[default]
    Spvg,
    /// The two-phase baseline without temporal accumulation of the count (SPVG 7):
    /// `n = max(var n_prev / sigma0^2, beta_min)`, clamped to `beta_max`. Under this
    /// policy [`update`](super::SpvgConfig::update) stores the count just used in
    /// `mean_count` (instead of its EMA), so `mean_count` holds `n_prev`.
    TwoPhase,
    /// Unreal Engine's simplified rule `n = clamp(var / sigma0^2, beta_min, beta_max)`.
    UnrealClamp,
    /// A fixed count `n` for every sampling pixel (reference and comparison renders);
    /// construction checks `beta_min <= n <= beta_max`. Pixels under the zero-sample rule
    /// still take 0.
    Fixed(u32),
}

//! The budget table's acceptance line and the rows it reads.

use super::run::{BudgetRow, SAMPLE_SHARE, beta_mins};
use crate::acceptance::Check;
use crate::equal_quality::{FixedPoint, psnr_at_or_extrapolated};

/// The fixed row of `budget`.
pub(crate) fn fixed_row(rows: &[BudgetRow], budget: u32) -> Option<&BudgetRow> {
    rows.iter().find(|r| r.budget == budget && !r.adaptive)
}

/// The picked adaptive row of `budget` at `beta_min`.
#[must_use]
pub fn picked_row(rows: &[BudgetRow], budget: u32, beta_min: u32) -> Option<&BudgetRow> {
    rows.iter()
        .find(|r| r.budget == budget && r.adaptive && r.picked && r.beta_min == beta_min)
}

/// The judged adaptive row of `budget`: the picked one at the last of [`beta_mins`].
#[must_use]
pub fn judged_row(rows: &[BudgetRow], budget: u32) -> Option<&BudgetRow> {
    beta_mins(budget)
        .last()
        .and_then(|&b| picked_row(rows, budget, b))
}

/// `SRatio` of a row: its samples over the fixed run's at its budget.
#[must_use]
pub fn row_ratio(rows: &[BudgetRow], row: &BudgetRow) -> f64 {
    row.samples / fixed_row(rows, row.budget).map_or(1.0, |f| f.samples.max(1.0))
}

/// `SRatio` of a budget: the judged adaptive run's samples over the fixed run's.
#[must_use]
pub fn sample_ratio(rows: &[BudgetRow], budget: u32) -> f64 {
    judged_row(rows, budget).map_or(0.0, |r| row_ratio(rows, r))
}

/// The table's check as the acceptance states it: at budget 512 the judged adaptive run
/// (the interval `[64, 512]`, the picked target) uses at most half the fixed run's samples
/// within 1 dB of it. The line also quotes the picked run with the published
/// `beta_min = 8`, and the fixed runs' PSNR at the judged run's own mean count
/// (interpolated in `log2(spp)` between the fixed rows), the report's usual comparison.
#[must_use]
pub fn checks(rows: &[BudgetRow]) -> Vec<Check> {
    let ad = judged_row(rows, 512).cloned().unwrap_or_default();
    let floor8 = picked_row(rows, 512, 8).cloned().unwrap_or_default();
    let fx = fixed_row(rows, 512).cloned().unwrap_or_default();
    let ratio = sample_ratio(rows, 512);
    let spp = ratio * 512.0;
    let fixed: Vec<FixedPoint> = rows
        .iter()
        .filter(|r| !r.adaptive)
        .map(|r| FixedPoint {
            spp: f64::from(r.budget),
            psnr: r.psnr,
        })
        .collect();
    let (at, extrapolated) = psnr_at_or_extrapolated(&fixed, spp).unwrap_or((f64::NAN, false));
    vec![Check::new(
        ratio <= SAMPLE_SHARE && ad.psnr >= fx.psnr - 1.0,
        format!(
            "budget 512: adaptive [{}, 512] at sigma0^2 = {:.3e} (the smallest swept target within {:.0}% of the fixed samples) uses {:.1}% of the fixed samples (<= {:.0}%) at {:.2} dB vs fixed {:.2} dB (within 1 dB); with the published beta_min 8 the same rule gives {:.2} dB at {:.1}% (sigma0^2 = {:.3e}); at equal samples ({spp:.1} spp per subsurface pixel) the fixed runs give {at:.2} dB ({})",
            ad.beta_min,
            ad.sigma0_sq,
            100.0 * SAMPLE_SHARE,
            100.0 * ratio,
            100.0 * SAMPLE_SHARE,
            ad.psnr,
            fx.psnr,
            floor8.psnr,
            100.0 * row_ratio(rows, &floor8),
            floor8.sigma0_sq,
            if extrapolated {
                "extrapolated in log2(spp) from the nearest two fixed rows"
            } else {
                "interpolated in log2(spp)"
            },
        ),
    )]
}

//! The budget table's markdown: per budget the fixed row, the published target's row and
//! the picked rows, then every swept row.

use std::fmt::Write as _;

use super::acceptance::row_ratio;
use super::run::{BudgetOptions, BudgetRow, INTERVAL_RATIO, PUBLISHED_TARGET, SAMPLE_SHARE, SWEEP};

/// One markdown row.
fn line(s: &mut String, rows: &[BudgetRow], r: &BudgetRow, pixels: f64) {
    let count = if r.adaptive {
        format!(
            "adaptive [{}, {}], {:.3e}{}",
            r.beta_min,
            r.budget,
            r.sigma0_sq,
            if r.picked { " (picked)" } else { "" }
        )
    } else {
        "fixed".to_string()
    };
    let _ = writeln!(
        s,
        "| {} | {count} | {:.3} | {:.2} | {:.5} | {:.5} | {:.2} | {} |",
        r.budget,
        r.time_ms,
        r.psnr,
        r.err1,
        r.err2,
        r.samples / pixels,
        if r.adaptive {
            format!("{:.2}%", 100.0 * row_ratio(rows, r))
        } else {
            "100%".into()
        }
    );
}

/// The table's markdown: per budget the fixed row, the published target's row and the
/// picked rows, then every swept row.
#[must_use]
pub fn markdown(rows: &[BudgetRow], opts: &BudgetOptions, cpu_time: bool) -> String {
    let mut s = String::new();
    let [w, h] = opts.size;
    let _ = writeln!(
        s,
        "## Sample budget (Table 7.2's shape)\n\nThe static scene at {w}x{h}, {}, {} frames \
         (metrics over the second half); adaptive = AS with beta_max = the budget and \
         beta_min 8 (the published floor) or B / {INTERVAL_RATIO} (the published [8, 64] \
         scaled with the budget; judged). The target variance per budget and floor: a sweep \
         of sigma0^2 = 1e-4 / 4^j (j = 0..{}), and the picked row is the smallest target \
         whose mean count is at most {:.0}% of the fixed run's (a rule on the counts alone, \
         never the reference); the published 1e-4 stays as the reference row. err1: RMSE \
         over the pixels the adaptive run leaves at beta_min (already at the target, by its \
         history); err2: over the pixels above it (each adaptive row its own split, the \
         fixed row the judged row's). spp per frame pixel. Times are {}. The judged floor \
         was chosen after the beta_min 8 sweep showed its plateau: below some target the \
         counts stop changing, because the pixels at the floor are those whose history has \
         not yet seen a sample cross the shadow edge or the depth step \
         (docs/algorithms.md §7.1).\n",
        opts.material.name,
        opts.frames,
        SWEEP.len() - 1,
        100.0 * SAMPLE_SHARE,
        if cpu_time {
            "CPU time (software adapter or CPU twin)"
        } else {
            "GPU wall time"
        }
    );
    let head = "| budget | count (sigma0^2) | time (ms) | PSNR (dB) | err1 | err2 | spp | SRatio |\n\
                | --- | --- | --- | --- | --- | --- | --- | --- |";
    let _ = writeln!(s, "{head}");
    let pixels = f64::from(w * h).max(1.0);
    let mut budgets: Vec<u32> = rows.iter().map(|r| r.budget).collect();
    budgets.dedup();
    for b in &budgets {
        for r in rows.iter().filter(|r| r.budget == *b) {
            let published = r.adaptive && r.sigma0_sq == PUBLISHED_TARGET && r.beta_min == 8;
            if !r.adaptive || r.picked || published {
                line(&mut s, rows, r, pixels);
            }
        }
    }
    let _ = writeln!(s, "\n### The sweep of the target per budget\n\n{head}");
    for r in rows.iter().filter(|r| r.adaptive) {
        line(&mut s, rows, r, pixels);
    }
    s.push('\n');
    s
}

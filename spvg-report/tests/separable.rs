//! The separable section: the fit table covers every preset with the core's fit, and the
//! focus scene runs on the CPU twins with the hybrid's samples inside the disc only.

use spvg::burley::presets;
use spvg_report::separable::acceptance::checks;
use spvg_report::separable::fit::fit_rows;
use spvg_report::separable::markdown::markdown;
use spvg_report::separable::{FocusOptions, run_focus};

#[test]
fn fit_rows_cover_every_preset() {
    let rows = fit_rows().unwrap();
    assert_eq!(rows.len(), presets::ALL.len(), "one row per preset");
    for r in &rows {
        for c in 0..3 {
            assert!(
                r.falloff[c] > 0.0 && r.falloff[c] <= 1.0,
                "{} falloff {}",
                r.name,
                r.falloff[c]
            );
            assert!(
                r.residual[c].is_finite() && r.residual[c] >= 0.0,
                "{} residual",
                r.name
            );
        }
    }
}

#[test]
fn the_focus_scene_runs_on_the_twins() {
    let opts = FocusOptions {
        size: [48, 36],
        frames: 4,
        ..FocusOptions::default()
    };
    let r = run_focus(None, &opts).unwrap();
    let names: Vec<&str> = r.runs.iter().map(|x| x.name.as_str()).collect();
    assert_eq!(names, ["separable", "as", "ccv", "hybrid-ccv"], "runs");
    let spp = |n: &str| r.runs.iter().find(|x| x.name == n).map_or(0.0, |x| x.spp);
    assert_eq!(
        spp("separable"),
        0.0,
        "the separable filter takes no samples"
    );
    // The hybrid samples the disc only: its mean count over the frame is at most the
    // focus fraction of the CCV run's (8 to 64 samples per tagged pixel).
    assert!(
        spp("hybrid-ccv") <= 64.0 * r.focus_fraction + 1e-9 && spp("hybrid-ccv") > 0.0,
        "hybrid {} spp, focus {}",
        spp("hybrid-ccv"),
        r.focus_fraction
    );
    assert!(
        r.focus_fraction > 0.02 && r.focus_fraction < 0.2,
        "{}",
        r.focus_fraction
    );
    let md = markdown(&fit_rows().unwrap(), &r, &opts);
    assert!(md.contains("Work of the runs"), "{md}");
    let lines = checks(&r);
    assert_eq!(lines.len(), 3, "three acceptance lines");
    assert!(
        lines
            .iter()
            .all(|c| spvg_report::acceptance::is_line(&c.line())),
        "{lines:?}"
    );
    // On the twin the cost line judges the work, which the runs measured.
    assert!(
        lines[1].text.starts_with("hybrid work: "),
        "{}",
        lines[1].text
    );
    let w = r.work;
    assert!(w.separable > 0.0 && w.ccv > 0.0 && w.hybrid > 0.0, "{w:?}");
}

#[test]
fn the_budget_table_runs_on_the_twin() {
    use spvg_report::budget::{
        BUDGETS, BudgetOptions, SAMPLE_SHARE, SWEEP, beta_mins, judged_row, row_ratio, run_budgets,
        sample_ratio,
    };
    let opts = BudgetOptions {
        size: [24, 18],
        frames: 2,
        ..BudgetOptions::default()
    };
    let rows = run_budgets(None, &opts).unwrap();
    let runs: usize = BUDGETS
        .iter()
        .map(|&b| 1 + beta_mins(b).len() * SWEEP.len())
        .sum();
    assert_eq!(
        rows.len(),
        runs,
        "fixed and every swept target at every floor per budget"
    );
    let pixels = f64::from(24 * 18);
    for r in &rows {
        assert!(r.samples <= f64::from(r.budget) * pixels, "{r:?}");
        assert!(
            r.psnr.is_finite() && r.err1 >= 0.0 && r.err2 >= 0.0,
            "{r:?}"
        );
    }
    for b in BUDGETS {
        for floor in beta_mins(b) {
            // One picked row per budget and floor; the rule's bound holds for it unless no
            // swept target stays within it (then the published target, the sweep's first).
            let group: Vec<_> = rows
                .iter()
                .filter(|r| r.budget == b && r.adaptive && r.beta_min == floor)
                .collect();
            assert_eq!(group.len(), SWEEP.len(), "budget {b}, floor {floor}");
            let picked: Vec<_> = group.iter().filter(|r| r.picked).collect();
            assert_eq!(picked.len(), 1, "budget {b}, floor {floor}: {picked:?}");
            let p = picked[0];
            let ratio = row_ratio(&rows, p);
            assert!(
                ratio <= SAMPLE_SHARE || p.sigma0_sq == SWEEP[0],
                "budget {b}: {p:?}"
            );
            // No smaller swept target also stays within the share.
            for r in group.iter().filter(|r| r.sigma0_sq < p.sigma0_sq) {
                assert!(
                    row_ratio(&rows, r) > SAMPLE_SHARE,
                    "budget {b}: {r:?} within the share but not picked"
                );
            }
        }
        let judged = judged_row(&rows, b).unwrap();
        assert_eq!(
            judged.beta_min,
            (b / 8).max(8),
            "budget {b}: the scaled floor"
        );
        let ratio = sample_ratio(&rows, b);
        assert!(ratio > 0.0 && ratio < 1.0, "budget {b}: SRatio {ratio}");
    }
}

/// With `beta_min = beta_max = B` the adaptive count has nothing to choose: the run and
/// its score are the fixed count's, whatever the target (the table's runner and scoring
/// hold no model-specific path).
#[test]
fn a_pinned_adaptive_count_scores_as_the_fixed_count() {
    use spvg_report::budget::{BudgetOptions, run_model, scene_and_reference, score};
    use spvg_report::wgpu_api::{Model, PassConfig};
    let opts = BudgetOptions {
        size: [24, 18],
        frames: 4,
        ..BudgetOptions::default()
    };
    let (scene, reference) = scene_and_reference(&opts);
    let cfg = PassConfig {
        spvg: spvg::SpvgConfig::builder()
            .budget(16, 16)
            .target_variance(1e-7)
            .build()
            .expect("valid controller"),
        ..PassConfig::default()
    };
    let fixed = run_model(None, &scene, &opts, Model::Fixed(16), &cfg).unwrap();
    let pinned = run_model(None, &scene, &opts, Model::As, &cfg).unwrap();
    assert_eq!(fixed.samples, pinned.samples);
    assert_eq!(fixed.images, pinned.images);
    assert_eq!(
        score(&fixed, &reference, &fixed.classes),
        score(&pinned, &reference, &fixed.classes)
    );
    // Every subsurface pixel sits at beta_min = beta_max: all in err1's class.
    assert!(fixed.classes.iter().flatten().all(|&c| c != 2));
}

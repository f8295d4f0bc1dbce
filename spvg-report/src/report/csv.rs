//! The report's machine-readable files: `runs.csv` (one row per run) and `frames.csv`
//! (one row per frame).

use std::fmt::Write as _;

use super::Report;

/// `runs.csv`: one row per run, then the circle scenario's policies.
pub(crate) fn runs_csv(r: &Report) -> String {
    let mut o = String::from(
        "scene,model,setting,mean_spp,worst_spp,psnr_db,psnr_acc_db,relmse,p50_ms,p95_ms,history_bytes_per_pixel,budget_spp,budget_in_band_pct,frames_to_band,steady_mean_abs_step\n",
    );
    for s in r.scenes.iter().flat_map(|s| &s.summaries) {
        let setting = match s.budget_spp {
            Some(_) => "budget",
            None => s.label.split_once(' ').map_or("report", |(_, x)| x),
        };
        let num = |v: f64, p: usize| {
            if v.is_finite() {
                format!("{v:.p$}")
            } else {
                String::new()
            }
        };
        let _ = writeln!(
            o,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},,",
            s.scene,
            s.model.name(),
            setting,
            num(s.mean_spp, 3),
            num(s.worst_spp, 3),
            num(s.mean_psnr, 3),
            num(s.mean_psnr_acc, 3),
            if s.mean_relmse.is_finite() {
                format!("{:.4e}", s.mean_relmse)
            } else {
                String::new()
            },
            num(s.p50_ms, 4),
            num(s.p95_ms, 4),
            s.history_bytes,
            s.budget_spp.map_or(String::new(), |b| num(b, 2)),
            num(100.0 * s.in_band, 2),
        );
    }
    // The damped policy in the kappa sweep: circle scenario, core crate.
    for c in &r.circle {
        let _ = writeln!(
            o,
            "circle,core,{},{:.3},,,,,,,,,,{},{:.4}",
            c.label, c.steady_mean, c.frames_to_band, c.mean_abs_step
        );
    }
    o
}

/// `frames.csv`: one row per frame of every run.
pub(crate) fn frames_csv(r: &Report) -> String {
    let mut o = String::from(
        "scene,config,frame,spp,time_ms,psnr,psnr_acc,relmse,sigma0_sq,at_beta_min,at_beta_max,planned_spp\n",
    );
    for s in &r.scenes {
        for (label, recs) in &s.all_frames {
            for f in recs {
                let _ = writeln!(
                    o,
                    "{},{label},{},{:.4},{:.4},{:.3},{:.3},{:.4e},{:.4e},{:.4},{:.4},{:.4}",
                    s.kind.name(),
                    f.frame,
                    f.spp,
                    f.time_ms,
                    f.psnr,
                    f.psnr_acc,
                    f.relmse,
                    f.target,
                    f.at_bounds[0],
                    f.at_bounds[1],
                    f.planned_spp
                );
            }
        }
    }
    o
}

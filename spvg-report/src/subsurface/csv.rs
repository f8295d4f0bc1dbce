//! The report's machine-readable files: `runs.csv` (one row per run) and `frames.csv`
//! (one row per frame).

use std::fmt::Write as _;

use super::data::Report;
use super::equal_quality::figures;
use crate::equal_quality::{EqualQuality, Interpolated};

/// An equal-quality figure as three CSV fields: the fixed count and the ratio where
/// interpolated (else empty), and `beyond fixedN` / `below fixedN` where the run lies
/// outside the fixed runs (else empty).
fn eq_fields(e: Option<EqualQuality>) -> String {
    let Some(e) = e else {
        return ",,".into();
    };
    match e.fixed {
        Interpolated::At(n) => format!("{n:.3},{:.4},", n / e.spp),
        Interpolated::Beyond(n) => format!(",,beyond fixed{n:.0}"),
        Interpolated::Below(n) => format!(",,below fixed{n:.0}"),
        Interpolated::None => ",,".into(),
    }
}

/// `runs.csv`: one row per run, then the circle scenario's policies.
pub(crate) fn runs_csv(r: &Report) -> String {
    let mut o = String::from(
        "scene,model,setting,mean_spp,worst_spp,psnr_db,relmse,psnr_taa_db,relmse_taa,flicker_taa,eq_fixed_spp,eq_ratio,eq_outside,eq_fixed_spp_taa,eq_ratio_taa,eq_outside_taa,fixed_psnr_taa_at_spp_db,p50_ms,p95_ms,history_bytes_per_pixel,budget_spp,budget_in_band_pct,frames_to_band,steady_mean_abs_step\n",
    );
    for (sc, s) in r
        .scenes
        .iter()
        .flat_map(|sc| sc.summaries.iter().map(move |s| (sc, s)))
    {
        let eq = figures(&sc.summaries, s);
        let setting = match s.budget_spp {
            Some(_) => "budget",
            None => s.label.split_once(' ').map_or("report", |(_, x)| x),
        };
        let sci = |v: f64| {
            if v.is_finite() {
                format!("{v:.4e}")
            } else {
                String::new()
            }
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
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},,",
            s.scene,
            s.model.name(),
            setting,
            num(s.mean_spp, 3),
            num(s.worst_spp, 3),
            num(s.mean_psnr, 3),
            sci(s.mean_relmse),
            num(s.mean_psnr_taa, 3),
            sci(s.mean_relmse_taa),
            sci(s.flicker_taa),
            eq_fields(eq.map(|e| e.single)),
            eq_fields(eq.map(|e| e.taa)),
            eq.and_then(|e| e.fixed_taa_at_spp.value())
                .map_or(String::new(), |v| num(v, 3)),
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
            "circle,core,{},{:.3},,,,,,,,,,,,,,,,,,,{},{:.4}",
            c.label, c.steady_mean, c.frames_to_band, c.mean_abs_step
        );
    }
    o
}

/// `frames.csv`: one row per frame of every run.
pub(crate) fn frames_csv(r: &Report) -> String {
    let mut o = String::from(
        "scene,config,frame,spp,time_ms,psnr,relmse,psnr_taa,relmse_taa,flicker_taa,sigma0_sq,at_beta_min,at_beta_max,planned_spp\n",
    );
    for s in &r.scenes {
        for (label, recs) in &s.all_frames {
            for f in recs {
                let _ = writeln!(
                    o,
                    "{},{label},{},{:.4},{:.4},{:.3},{:.4e},{:.3},{:.4e},{:.4e},{:.4e},{:.4},{:.4},{:.4}",
                    s.kind.name(),
                    f.frame,
                    f.spp,
                    f.time_ms,
                    f.psnr,
                    f.relmse,
                    f.psnr_taa,
                    f.relmse_taa,
                    f.flicker_taa,
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

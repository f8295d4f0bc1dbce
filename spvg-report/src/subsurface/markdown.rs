//! `report.md`: the verdict, what this run was, the scenes, the acceptance lines, the
//! results table, the notes, the charts and the frame images.

use std::fmt::Write as _;

use super::data::Report;
use super::equal_quality::figures;
use super::run::RunSummary;
use super::scene_runs::ImageRow;
use crate::equal_quality::Interpolated;
use crate::images::{ERROR_FULL, Written};
use crate::metrics::RELMSE_EPS;
use crate::timing::ms;

/// The header of the results table.
pub(crate) fn table_header() -> &'static str {
    "| scene | config | mean spp | worst-frame spp | p50 ms | p95 ms | max ms | mean PSNR | worst PSNR | mean relMSE | mean PSNR TAA | worst PSNR TAA | mean relMSE TAA | flicker TAA | history B/px |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
}

/// One run's row of the results table.
pub(crate) fn table_row(s: &RunSummary) -> String {
    format!(
        "| {} | {} | {:.1} | {:.1} | {} | {} | {} | {:.2} | {:.2} | {:.3e} | {:.2} | {:.2} | {:.3e} | {:.2e} | {} |",
        s.scene,
        s.label,
        s.mean_spp,
        s.worst_spp,
        ms(s.p50_ms),
        ms(s.p95_ms),
        ms(s.max_ms),
        s.mean_psnr,
        s.worst_psnr,
        s.mean_relmse,
        s.mean_psnr_taa,
        s.worst_psnr_taa,
        s.mean_relmse_taa,
        s.flicker_taa,
        s.history_bytes
    )
}

/// The equal-quality table: each adaptive run against its scene's fixed runs.
fn equal_quality(r: &Report) -> String {
    let mut md = String::from(
        "## Equal quality

For each adaptive run, the fixed count that reaches its mean PSNR, single-frame and after TAA, interpolated linearly in log2(spp) between the scene's fixed runs that bracket it (the SPVG paper's measure), and that count over the run's mean spp; *beyond fixedN* where the run beats every fixed run (nothing is extrapolated). The last column is the fixed runs' PSNR after TAA at the run's mean spp (interpolated the same way).\n\n| scene | config | mean spp | PSNR | equal-quality fixed (ratio) | PSNR TAA | equal-quality fixed after TAA (ratio) | fixed PSNR TAA at its spp |\n|---|---|---|---|---|---|---|---|\n",
    );
    let mut rows = 0;
    for sc in &r.scenes {
        for s in &sc.summaries {
            let Some(f) = figures(&sc.summaries, s) else {
                continue;
            };
            let at = match f.fixed_taa_at_spp {
                Interpolated::At(v) => format!("{v:.2}"),
                Interpolated::Beyond(n) => format!("n/a (above fixed{n:.0})"),
                Interpolated::Below(n) => format!("n/a (below fixed{n:.0})"),
                Interpolated::None => "n/a".into(),
            };
            let _ = writeln!(
                md,
                "| {} | {} | {:.1} | {:.2} | {} | {:.2} | {} | {at} |",
                s.scene, s.label, s.mean_spp, s.mean_psnr, f.single, s.mean_psnr_taa, f.taa
            );
            rows += 1;
        }
    }
    if rows == 0 {
        return String::new();
    }
    md.push('\n');
    md
}

/// "This run": backend, timing, frame size, metrics, settings, suite, images.
fn this_run(r: &Report, duplicates: usize) -> String {
    let i = &r.inputs;
    let mut md = String::from("## Subsurface scattering: this run\n\n");
    let _ = writeln!(md, "- Backend: {}.", i.backend);
    let _ = writeln!(md, "- Timing: {}", i.timing.sentence());
    let _ = writeln!(
        md,
        "- {}x{} pixels, {} frames per run at 60 fps, material {}, lighting {:?}, AFIS {}; pass times leave out frame 0 (shader compilation).",
        i.width,
        i.height,
        i.frames,
        i.material,
        i.lighting,
        if i.afis {
            "on (mip chain)"
        } else {
            "off (mip 0)"
        }
    );
    let _ = writeln!(
        md,
        "- Metrics over subsurface pixels: PSNR of luminance (peak 1) against a 64x64-node quadrature reference; relMSE = mean of (x - ref)^2 / (ref^2 + {RELMSE_EPS:e}) on luminance (the CV paper's metric). TAA: the same after a TAA resolve of the luminance (Karis 2014, `spvg_report::taa`): history reprojected along the motion vectors (zero here: the camera is fixed) with a Catmull-Rom fetch (bilinear where its footprint is rejected), rejected where the previous frame did not cover the pixel or its depth differs by more than 2%, clamped to the current 3x3 neighbourhood's min/max, blended with weight {} on the current frame, no jitter; flicker TAA = mean over pixels and frames of |(x_t - x_(t-1)) - (ref_t - ref_(t-1))| of the resolved luminance (its frame-to-frame change less the reference's).",
        crate::taa::WEIGHT
    );
    let _ = writeln!(
        md,
        "- Settings: eta 0.2, sigma0^2 {:e} (the library default is the published 1e-4; ARCHITECTURE.md says why the report runs lower), kappa 0.2, budget [8, 64], eps_u 0.01 (docs/algorithms.md §2); firefly clamp {} (docs/algorithms.md §8.3).",
        i.sigma0_sq,
        i.settings
            .first()
            .and_then(|(_, c)| c.spvg.firefly_clamp())
            .map_or_else(|| "off".to_owned(), |k| format!("k = {k}"))
    );
    let _ = writeln!(
        md,
        "- `{}` (static scene): the resolved-image rule (docs/algorithms.md §8.7): fractional counts at floor {} with `resolve_weight` {} (this resolve's weight) and the target scaled by a/(2-a) = {:.4}, so that it aims at the image after the resolve that `as` leaves; a pixel of 0 samples shows its history's mean distant part and the resolve keeps its own history there. Its single-frame figures measure what it did not sample; its lines judge the image after TAA.",
        super::run::RunSpec::RESOLVED,
        super::run::RESOLVED_FLOOR,
        crate::taa::WEIGHT,
        spvg::controller::fractional::resolved_factor(crate::taa::WEIGHT)
    );
    let _ = writeln!(md, "- Suite: {}", i.suite);
    let _ = writeln!(
        md,
        "- {duplicates} frame images equal to an earlier one were linked to it instead of written again.\n"
    );
    md
}

/// The scenes table, with each scene's thumbnail.
fn scenes(r: &Report) -> String {
    let mut md = String::from("## Scenes\n\n| | scene | what it shows |\n|---|---|---|\n");
    for s in &r.scenes {
        let thumb = s
            .thumbnail
            .as_ref()
            .map_or(String::new(), |f| format!("![{}]({f})", s.kind.name()));
        let _ = writeln!(
            md,
            "| {thumb} | {} | {} |",
            s.kind.name(),
            s.kind.description()
        );
    }
    md
}

/// One run's row of the frame images table.
fn image_row(r: &ImageRow) -> String {
    let cell = |w: &Written, what: &str| {
        if w.duplicate {
            format!("[{what} =]({})", w.file)
        } else {
            format!("[![{what}]({f})]({f})", f = w.file)
        }
    };
    format!(
        "| {} | {} | {} | {} |",
        r.label,
        cell(&r.result, "result"),
        cell(&r.count, "count"),
        r.error.as_ref().map_or("n/a".into(), |e| cell(e, "error"))
    )
}

/// The frame images section.
fn images(r: &Report) -> String {
    let mut md = format!("## Frame images (frame {})\n\n", r.inputs.image_frame);
    let _ = writeln!(
        md,
        "Result (sRGB, clamped); samples per pixel (black 0 to white 64); luminance error (black 0 to white {ERROR_FULL}, dark blue outside the scored mask). A link marked = points to an earlier identical image.\n"
    );
    for s in &r.scenes {
        let _ = writeln!(
            md,
            "### {}\n\n| run | result | count | error |\n|---|---|---|---|",
            s.kind.name()
        );
        for row in &s.images {
            let _ = writeln!(md, "{}", image_row(row));
        }
        md.push('\n');
    }
    md
}

/// The section's markdown (`charts`: the charts section's markdown; `notes`: the notes'),
/// appended to `report.md` after the verdict.
pub(crate) fn section_md(r: &Report, duplicates: usize, charts: &str, notes: &str) -> String {
    let mut md = this_run(r, duplicates);
    md.push_str(&scenes(r));
    md.push_str("\n## Acceptance (subsurface)\n\n");
    if r.groups.is_empty() {
        md.push_str("(not judged: --no-reference)\n\n");
    }
    for g in &r.groups {
        md.push_str(&g.markdown());
    }
    let _ = writeln!(md, "## Results\n\n{}", table_header());
    for s in r.scenes.iter().flat_map(|s| &s.summaries) {
        let _ = writeln!(md, "{}", table_row(s));
    }
    let _ = writeln!(
        md,
        "\nThe same figures, machine-readable: [runs.csv](runs.csv); per frame: [frames.csv](frames.csv).\n"
    );
    md.push_str(&crate::policies::firefly_markdown(&r.firefly));
    if r.inputs.reference {
        md.push_str(&equal_quality(r));
    }
    let _ = writeln!(md, "## Notes computed from this run\n\n{notes}");
    let _ = writeln!(
        md,
        "## Charts\n\nPer-frame charts show the report-setting runs; colours: fixed8/16/32/64 light to dark grey, AS red, CCV green, OCV blue. Pareto panels show every run, each point labelled with its setting.\n\n{charts}"
    );
    md.push_str(&images(r));
    md
}

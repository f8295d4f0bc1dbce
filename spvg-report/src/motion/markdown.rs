//! The motion report as markdown (the section appended to report.md, and motion.md) and
//! as per-frame CSV (motion.csv).

use std::fmt::Write as _;

use super::data::{MotionReport, MotionRun, WARM_UP};
use super::options::MotionOptions;
use super::render::LATTICE;
use super::scenes::{
    AGE_WEIGHT, BORDER_TEXEL, GUIDED, NEAREST_ONLY, NO_DILATION, NO_NEIGHBOUR_PRIOR, NO_PRIOR,
    NO_REPROJECTED_DEPTH, NO_SPATIAL, SPATIAL_FRAMES, YOUNG,
};
use crate::equal_quality::{EqualQuality, Interpolated};
use crate::section::Group;

/// The section's heading and its description of the scenes, modes and metrics.
fn intro(opts: &MotionOptions, backend: &str) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "## Motion: the adaptive component on a second consumer (ambient occlusion)\n\n\
         Stochastic ambient occlusion (16 px rays, cosine-weighted) on a procedural height \
         field (a plane with one sphere per 64 px cell); pans and their static camera \
         (`static-pan`) at {}x{}, the rotation, the moving sphere (`object3`), the moving \
         objects (`objects5`: three floating spheres crossing at 5 px per frame along +x, -x \
         and +y, and a bar 3 px wide floating 11 to 14 px above the plane, crossing its width \
         at 5 px per frame), the dolly (`dolly3`: the \
         camera moves 3 units per frame between heights 100 and 61 and zooms with its \
         height, so every depth changes by 3% to 8% per frame; judged against a static \
         camera held at its poses, its heights and zooms, as the zoom changes what the frame \
         shows) and their static camera at \
         {}x{}; {} frames, sigma0^2 = {}, budget [{}, {}], backend: {backend}. Reference: \
         midpoint rule on {}x{} directions per pixel. Motion vectors in pixels (current minus \
         previous position), history read at the nearest texel, valid when inside the frame \
         with the previous depth within 2% of the reprojected depth (the surface point's depth \
         as the previous camera saw it; `{NO_REPROJECTED_DEPTH}` compares this frame's depth \
         instead) (where that texel fails, the first of the other \
         texels of its 2x2 footprint that passes). The motion bound line breaks one frame of \
         the static camera's motion vectors (every vector at 1e30). The young-history lines \
         compare `pan8` and the rotation with a static camera held at their own poses (every \
         4th frame after the warm-up, AS from a cold history for 16 frames and scored on the \
         next 8; `pan8`'s poses are windows of one static camera over the strip it crosses), \
         `fixed64` held there too. `as-identity` is a renderer without reprojection, for \
         contrast: the history read at the same pixel, no rejection. AS spends the largest count \
         within {} px (count dilation, docs/algorithms.md §2.5); `{NO_DILATION}` is AS with \
         each pixel's own count, `{NO_PRIOR}` AS without the border prior (entering pixels at \
         beta_min), `{BORDER_TEXEL}` AS with entering pixels at the border texel's count \
         instead of beta_max, `{NEAREST_ONLY}` AS \
         without the footprint search (the nearest texel only); the young-history rows \
         (docs/algorithms.md §8.4) on the static cameras, `pan8`, the rotation and the moving \
         objects: `as` itself has the spatial variance (the core's default: histories up to \
         {SPATIAL_FRAMES} frames old take the variance of their same-surface 3x3 \
         neighbourhood) and the count dilation's depth-aware neighbour prior (the \
         component's default: a pixel without history takes the mean count of its \
         same-surface neighbours within 4 px that have one), `{NO_SPATIAL}` is AS without \
         the spatial variance, `{NO_NEIGHBOUR_PRIOR}` AS without the prior (the papers' \
         beta_min for a pixel without history), `{AGE_WEIGHT}` and `{YOUNG}` add the weight \
         max(eta, 1/age); `{GUIDED}` AS with the TAA-guided update \
         (docs/algorithms.md §8.5: the variance follows the deviation from the report's TAA \
         history, reprojected and clamped against the frame, instead of the pixel's own \
         mean); on the moving-object scenes `as s0^2 x0.9` and `as s0^2 x0.8` are AS at \
         0.9 and 0.8 times sigma0^2 (points of AS's quality-cost curve beside the identity \
         history's, which spends more at the same target: its line asks for an AS point at \
         no more spp and no lower PSNR){}. On the moving-object scenes a pixel is *uncovered* on the frame it stops \
         showing a moving object, at age 1, 2 and 3 on that frame and the next two (the \
         camera is static, so the uncovered surface stays at its pixel), and *steady* when \
         it shows no object and was not uncovered in the last 3 frames; their lines compare \
         the PSNR of the MSE pooled over every pixel-frame of a class. Where a line judges a \
         loss under motion (the pan criterion, young history, uncovered pixels), it judges \
         AS's loss beyond `fixed64`'s own on the same pixels and cameras (the content's \
         share: `fixed64` has no history). Every GPU frame is held against the CPU twin: \
         the counts and history texels on every pixel (the twin's component fed the GPU's AO \
         values), the AO values and prefix estimates on a lattice ((x + 3y + 7t) mod {LATTICE} \
         = 0: every row and every x mod 8 in every frame); a run that differs on any frame is \
         corrupt and not scored. Means over frames {}..{} (the first {} are the warm-up from \
         a cold history).\n",
        opts.pan_size[0],
        opts.pan_size[1],
        opts.size[0],
        opts.size[1],
        opts.frames,
        opts.config.target_variance(),
        opts.config.min_samples(),
        opts.config.max_samples(),
        opts.grid,
        opts.grid,
        opts.dilation,
        if opts.full {
            ""
        } else {
            "; the default suite runs what its acceptance lines judge (`as`, `as-resolved`, `fixed4` to `fixed64` on `static-pan`, `pan8`, `static`, `rotate2`, `object3`, `dolly3` and `objects5`, `as-identity` and the tighter targets on the moving objects, no reference on the warm-up frames, and on the rotation and the dolly, whose frames each need a reference of their own, every 4th frame after it, the frames whose poses their baselines hold): `--full` adds `pan1`, `pan2` and `pan4`, `as-identity` and `as-guided` on every scene, the young-history and knob rows, and scores every frame"
        },
        WARM_UP,
        opts.frames - 1,
        WARM_UP
    );
    let _ = writeln!(
        md,
        "\nThe mesh scene (`{}`, content nobody here modelled): the Stanford bunny (npm `bunny` 1.0.1, 3674 triangles; `spvg-report/assets/README.md`: source and terms) on a ground plane at {}x{}, a perspective camera orbiting it by {} degrees per frame with sub-pixel Halton (2, 3) jitter (16-frame cycle; motion vectors without the jitter), its G-buffer ray cast through a BVH; AO rays of length {} (the bunny is 9.7 tall) traced on the CPU through the BVH in both backends (the GPU runs the component, held against the twin on every pixel: counts and history texels; no AO value on the GPU to compare); reference: the AO averaged over each pixel's footprint ({}x{} positions, {} rays each), every 4th frame after the warm-up.\n",
        crate::mesh::scene::NAME,
        opts.mesh_size[0],
        opts.mesh_size[1],
        crate::mesh::scene::ORBIT,
        crate::mesh::ao::RANGE,
        crate::mesh::ao::REFERENCE_GRID,
        crate::mesh::ao::REFERENCE_GRID,
        super::mesh::REFERENCE_SAMPLES
    );
    md
}

/// The section (markdown): the description, one row per run, the acceptance lines.
fn section(rep: &MotionReport, opts: &MotionOptions, backend: &str, groups: &[Group]) -> String {
    let mut md = intro(opts, backend);
    let _ = writeln!(
        md,
        "After the consumer, every run goes through the same TAA resolve (`spvg_report::taa`, Karis 2014): the AO history reprojected along the motion vectors with a Catmull-Rom fetch (the bilinear one where a texel of its 4x4 footprint is rejected), each tap rejected where its depth differs by more than 2% (disocclusion), clamped to the current 3x3 neighbourhood's min/max, blended with weight {} on the current frame, no jitter. *Flicker TAA* is the mean over pixels with a reprojected history of |(x_t - x_(t-1)) - (ref_t - ref_(t-1))| along the motion. *Equal quality*: the fixed count reaching the run's PSNR, interpolated linearly in log2(spp) between the scene's fixed runs, and its ratio to the run's mean spp; *beyond fixedN* where the run beats every fixed run.\n",
        crate::taa::WEIGHT
    );
    let _ = writeln!(
        md,
        "| scene | mode | mean spp | mean PSNR (dB) | PSNR on steady pixels (dB) | PSNR TAA (dB) | relMSE TAA | flicker TAA | equal quality | equal quality after TAA |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    for r in &rep.runs {
        let (eq, eq_taa) = equal_quality(rep, r);
        // A run assembled from still frames (the dolly's static cameras at its heights)
        // has no image sequence to resolve: its TAA cells read n/a.
        let taa = if r.psnr_taa.is_empty() {
            "n/a | n/a | n/a".to_string()
        } else {
            format!(
                "{:.2} | {:.3e} | {:.2e}",
                r.mean_psnr_taa(),
                r.mean_relmse_taa(),
                r.mean_flicker_taa()
            )
        };
        let _ = writeln!(
            md,
            "| {} | {} | {:.2} | {:.2} | {:.2} | {taa} | {eq} | {eq_taa} |",
            r.scene,
            r.mode,
            r.mean_spp(),
            r.mean_psnr(),
            r.mean_psnr_steady(),
        );
    }
    guide_note(rep, &mut md);
    md.push('\n');
    for g in groups {
        md.push_str(&g.markdown());
    }
    md
}

/// `as-guided` against `as` on every scene that ran both: mean spp, PSNR after TAA and
/// flicker, and which spends fewer samples for the PSNR it reaches after TAA.
fn guide_note(rep: &MotionReport, md: &mut String) {
    let rows: Vec<String> = rep
        .runs
        .iter()
        .filter(|g| g.mode == GUIDED)
        .filter_map(|g| {
            let a = rep
                .runs
                .iter()
                .find(|a| a.scene == g.scene && a.mode == "as")?;
            let (ds, dp) = (
                g.mean_spp() / a.mean_spp().max(1e-9),
                g.mean_psnr_taa() - a.mean_psnr_taa(),
            );
            Some(format!(
                "{}: {:.2}x AS's spp, {dp:+.2} dB after TAA ({:+.2} dB single-frame), flicker {:.2e} vs {:.2e}",
                g.scene,
                ds,
                g.mean_psnr() - a.mean_psnr(),
                g.mean_flicker_taa(),
                a.mean_flicker_taa()
            ))
        })
        .collect();
    if !rows.is_empty() {
        let _ = writeln!(
            md,
            "\n*TAA guide* (`{GUIDED}` against `as`): {}.",
            rows.join("; ")
        );
    }
}

/// The equal-quality figures of an adaptive run (single-frame, after TAA) against its
/// scene's fixed runs; empty strings for a fixed run.
fn equal_quality(rep: &MotionReport, r: &MotionRun) -> (String, String) {
    if r.is_fixed() {
        return (String::new(), String::new());
    }
    let single = rep.fixed_points(&r.scene, false);
    let taa = rep.fixed_points(&r.scene, true);
    (
        EqualQuality::new(&single, r.mean_spp(), r.mean_psnr()).to_string(),
        EqualQuality::new(&taa, r.mean_spp(), r.mean_psnr_taa()).to_string(),
    )
}

/// One row per run: `motion_runs.csv`, the run means of the table and the equal-quality
/// figures (fixed count and ratio where interpolated; `beyond fixedN` / `below fixedN`
/// where the run lies outside the fixed runs).
#[must_use]
pub fn runs_csv(rep: &MotionReport) -> String {
    let mut csv = String::from(
        "scene,mode,mean_spp,psnr_db,psnr_steady_db,psnr_taa_db,relmse_taa,flicker_taa,eq_fixed_spp,eq_ratio,eq_outside,eq_fixed_spp_taa,eq_ratio_taa,eq_outside_taa,count_step\n",
    );
    let fields = |e: Option<EqualQuality>| match e.map(|e| (e, e.fixed)) {
        Some((e, Interpolated::At(n))) => format!("{n:.3},{:.4},", n / e.spp),
        Some((_, Interpolated::Beyond(n))) => format!(",,beyond fixed{n:.0}"),
        Some((_, Interpolated::Below(n))) => format!(",,below fixed{n:.0}"),
        _ => ",,".into(),
    };
    for r in &rep.runs {
        let adaptive = !r.is_fixed();
        let eq = |taa: bool| {
            adaptive.then(|| {
                let psnr = if taa {
                    r.mean_psnr_taa()
                } else {
                    r.mean_psnr()
                };
                EqualQuality::new(&rep.fixed_points(&r.scene, taa), r.mean_spp(), psnr)
            })
        };
        let _ = writeln!(
            csv,
            "{},{},{:.4},{:.4},{:.4},{:.4},{:.4e},{:.4e},{},{},{:.4}",
            r.scene,
            r.mode,
            r.mean_spp(),
            r.mean_psnr(),
            r.mean_psnr_steady(),
            r.mean_psnr_taa(),
            r.mean_relmse_taa(),
            r.mean_flicker_taa(),
            fields(eq(false)),
            fields(eq(true)),
            r.mean_count_step()
        );
    }
    csv
}

/// Every frame of every run: `motion.csv`.
#[must_use]
pub fn frames_csv(rep: &MotionReport) -> String {
    let mut csv = String::from(
        "scene,mode,frame,spp,psnr_db,psnr_steady_db,psnr_taa_db,relmse_taa,flicker_taa,uncovered_spp,steady_spp,uncovered_at_max\n",
    );
    let opt = |v: Option<&Option<f64>>| {
        v.copied()
            .flatten()
            .map_or(String::new(), |x| format!("{x:.4}"))
    };
    for r in &rep.runs {
        for (t, (spp, p)) in r.spp.iter().zip(&r.psnr).enumerate() {
            let ps = r.psnr_steady.get(t).copied().unwrap_or(f64::NAN);
            let at = |v: &[f64]| v.get(t).copied().unwrap_or(f64::NAN);
            let _ = writeln!(
                csv,
                "{},{},{t},{spp:.4},{p:.4},{ps:.4},{:.4},{:.4e},{:.4e},{},{},{}",
                r.scene,
                r.mode,
                at(&r.psnr_taa),
                at(&r.relmse_taa),
                at(&r.flicker_taa),
                opt(r.uncovered_spp.get(t)),
                opt(r.steady_spp.get(t)),
                opt(r.uncovered_at_max.get(t))
            );
        }
    }
    csv
}

/// The section's markdown with its acceptance `groups`.
#[must_use]
pub fn markdown(
    rep: &MotionReport,
    opts: &MotionOptions,
    backend: &str,
    groups: &[Group],
) -> String {
    section(rep, opts, backend, groups)
}

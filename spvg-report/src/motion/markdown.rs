//! The motion report as markdown (the section appended to report.md, and motion.md) and
//! as per-frame CSV (motion.csv).

use std::fmt::Write as _;

use super::MotionOptions;
use super::runs::{MotionReport, WARM_UP};
use super::scenes::{BORDER_TEXEL, NEAREST_ONLY, NO_DILATION, NO_PRIOR, NO_REPROJECTED_DEPTH};

/// The section's heading and its description of the scenes, modes and metrics.
fn intro(opts: &MotionOptions, backend: &str) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "## Motion: the adaptive component on a second consumer (ambient occlusion)\n\n\
         Stochastic ambient occlusion (16 px rays, cosine-weighted) on a procedural height \
         field (a plane with one sphere per 64 px cell); pans and their static camera \
         (`static-pan`) at {}x{}, the rotation, the moving sphere, the dolly (`dolly3`: the \
         camera moves 3 units per frame between heights 100 and 61 and zooms with its \
         height, so every depth changes by 3% to 8% per frame; judged against `static-dolly3`: \
         per frame, AS on a static camera at that frame's height and zoom, after its \
         warm-up, as the zoom changes what the frame shows) and their static camera at \
         {}x{}; {} frames, sigma0^2 = {}, budget [{}, {}], backend: {backend}. Reference: \
         midpoint rule on {}x{} directions per pixel. Motion vectors in pixels (current minus \
         previous position), history read at the nearest texel, valid when inside the frame \
         with the previous depth within 2% of the reprojected depth (the surface point's depth \
         as the previous camera saw it; `{NO_REPROJECTED_DEPTH}` compares this frame's depth \
         instead) (where that texel fails, the first of the other \
         texels of its 2x2 footprint that passes). The motion bound line breaks one frame of \
         the static camera's motion vectors (every vector at 1e30). `as-identity` is today's behaviour for contrast: \
         the history read at the same pixel, no rejection. AS spends the largest count \
         within {} px (count dilation, docs/algorithms.md §2.5); `{NO_DILATION}` is AS with \
         each pixel's own count, `{NO_PRIOR}` AS without the border prior (entering pixels at \
         beta_min), `{BORDER_TEXEL}` AS with entering pixels at the border texel's count \
         instead of beta_max, `{NEAREST_ONLY}` AS \
         without the footprint search (the nearest texel only){}. Means over frames \
         {}..{} (the first {} are the warm-up from a cold history).\n",
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
            "; the default suite runs what the acceptance lines judge (`as` everywhere, `fixed64` on the static cameras, no reference on the warm-up frames): `--full` adds `fixed64` and `as-identity` on every scene, these knob rows and the warm-up's PSNR"
        },
        WARM_UP,
        opts.frames - 1,
        WARM_UP
    );
    md
}

/// The section (markdown): the description, one row per run, the acceptance lines.
fn section(rep: &MotionReport, opts: &MotionOptions, backend: &str) -> String {
    let mut md = intro(opts, backend);
    let _ = writeln!(
        md,
        "| scene | mode | mean spp | mean PSNR (dB) | PSNR on steady pixels (dB) |\n| --- | --- | --- | --- | --- |"
    );
    for r in &rep.runs {
        let _ = writeln!(
            md,
            "| {} | {} | {:.2} | {:.2} | {:.2} |",
            r.scene,
            r.mode,
            r.mean_spp(),
            r.mean_psnr(),
            r.mean_psnr_steady()
        );
    }
    let _ = writeln!(md, "\n### Acceptance (motion)\n");
    for c in &rep.lines {
        let _ = writeln!(md, "{}", c.line());
    }
    md
}

/// Every frame of every run: `motion.csv`.
fn csv(rep: &MotionReport) -> String {
    let mut csv = String::from(
        "scene,mode,frame,spp,psnr_db,psnr_steady_db,uncovered_spp,steady_spp,uncovered_at_max\n",
    );
    let opt = |v: Option<&Option<f64>>| {
        v.copied()
            .flatten()
            .map_or(String::new(), |x| format!("{x:.4}"))
    };
    for r in &rep.runs {
        for (t, (spp, p)) in r.spp.iter().zip(&r.psnr).enumerate() {
            let ps = r.psnr_steady.get(t).copied().unwrap_or(f64::NAN);
            let _ = writeln!(
                csv,
                "{},{},{t},{spp:.4},{p:.4},{ps:.4},{},{},{}",
                r.scene,
                r.mode,
                opt(r.uncovered_spp.get(t)),
                opt(r.steady_spp.get(t)),
                opt(r.uncovered_at_max.get(t))
            );
        }
    }
    csv
}

/// The report section (markdown) and the per-frame CSV.
#[must_use]
pub fn markdown(rep: &MotionReport, opts: &MotionOptions, backend: &str) -> (String, String) {
    (section(rep, opts, backend), csv(rep))
}

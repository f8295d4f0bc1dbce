//! PNG images and plots written with the `png` crate alone (no font dependencies): frame
//! images (result, count map, error map), per-frame series and Pareto scatter plots. Each
//! plot carries its title, axis names, tick labels and a legend in a built-in pixel font
//! ([`PLOT_NOTES`] repeats the legend for `report.md`).

mod canvas;
mod chart;
mod font;
mod runs;
mod scale_bar;

use std::path::Path;

use self::canvas::{Canvas, Rgb, text_size, write_png};
use self::chart::{Frame, GAP, INK, Marker, Scale, TEXT, draw_legend, legend_size, nice_step};
use self::runs::{colour, is_sweep, pareto_legend, series_legend};
use self::scale_bar::ScaleBar;
use crate::error::ReportError;
use crate::evaluate::{FrameRecord, RunSummary};
use crate::metrics::rgb;
use crate::scene::SceneKind;
use spvg_wgpu::FrameOutput;
use spvg_wgpu::frame::luminance;

/// Legend of the plots, for `report.md`.
pub const PLOT_NOTES: &str = "## Plots\n\n\
Every plot is labelled in the image: title, axis names, tick values and a legend. \
Colours: fixed8/16/32/64 light to dark grey, as red, ccv green, ocv blue. \
`<scene>_spp.png`: mean spp per frame (x: frame, y: spp 0 to 64). `<scene>_psnr.png`: \
single-frame PSNR per frame (dB). `pareto_spp.png` / `pareto_time.png`: x = mean spp or \
p50 pass time (ms), y = mean PSNR (dB), one panel per scene (static, flash, switch, \
occluders from top); runs with default settings are filled squares, swept settings \
(\"sweep\" in the legend) hollow squares in the lighter colour of their model. Images \
`<scene>_<model>_f<N>_{result,count,error}.png`: result (sRGB, clamped); count (black 0 to \
white 64 spp, scale bar below); error: |luminance error| x 20 (black 0 to white 0.05, \
scale bar below), pixels outside the scored mask blue.";

fn srgb8(v: f32) -> u8 {
    let v = if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// Grey level of a sample count: black 0 to white 64 (and above).
#[inline]
#[must_use]
fn count_grey(n: u32) -> u8 {
    (u64::from(n) * 255 / 64).min(255) as u8
}

/// Pixels outside the scored mask in the error image.
const UNSCORED: Rgb = [0, 0, 64];
/// Luminance error at which the error image turns white (it shows |error| x 20).
const ERROR_FULL: f32 = 0.05;

/// Scale bar labels of the count image: its ends and the quantity.
const COUNT_LABELS: [&str; 3] = ["0", "spp", "64"];
/// Scale bar labels of the error image (the ends match [`ERROR_FULL`]).
const ERROR_LABELS: [&str; 3] = ["0", "|err|", "0.05"];
/// Key of the [`UNSCORED`] colour.
const UNSCORED_NAME: &str = "unscored";
/// Per-frame plots: file suffix, title after the scene name, y axis name.
const SERIES: [(&str, &str, &str); 2] = [
    ("spp", "mean spp per frame", "spp"),
    ("psnr", "single-frame PSNR per frame", "PSNR dB"),
];
/// x axis name of the per-frame plots.
const X_FRAME: &str = "frame";
/// Pareto plots: file suffix, title, x axis name.
const PARETO: [(&str, &str, &str); 2] = [
    (
        "spp",
        "mean PSNR vs mean spp, one panel per scene",
        "mean spp",
    ),
    (
        "time",
        "mean PSNR vs p50 pass time, one panel per scene",
        "p50 ms",
    ),
];
/// y axis name of the Pareto panels.
const Y_PSNR: &str = "PSNR dB";
/// Pareto dots closer than this (pixels, either axis) overlap.
const NEAR: u32 = 6;
/// Shown in a Pareto panel without runs.
const NO_RUNS: &str = "no runs";

/// Writes `<stem>_result.png`, `<stem>_count.png` and `<stem>_error.png`.
///
/// # Errors
///
/// File or encoding errors.
pub fn write_frame_images(
    dir: &Path,
    stem: &str,
    width: u32,
    height: u32,
    out: &FrameOutput,
    reference: &[[f32; 3]],
    mask: &[u8],
) -> Result<(), ReportError> {
    let result: Vec<u8> = out.result.iter().flat_map(|t| rgb(*t).map(srgb8)).collect();
    write_png(
        &dir.join(format!("{stem}_result.png")),
        width,
        height,
        &result,
    )?;
    let count: Vec<u8> = out.count.iter().flat_map(|&c| [count_grey(c); 3]).collect();
    let count_bar = ScaleBar {
        ramp: &|f| [count_grey((f * 64.0).round() as u32); 3],
        labels: COUNT_LABELS,
        key: None,
    };
    count_bar
        .under(width, height, &count)
        .save(&dir.join(format!("{stem}_count.png")))?;
    let error: Vec<u8> = out
        .result
        .iter()
        .zip(reference)
        .zip(mask)
        .flat_map(|((t, r), m)| {
            if *m == 0 {
                UNSCORED
            } else {
                let e = (luminance(rgb(*t)) - luminance(*r)).abs() / ERROR_FULL;
                [srgb8(e); 3]
            }
        })
        .collect();
    let error_bar = ScaleBar {
        ramp: &|f| [srgb8(f as f32); 3],
        labels: ERROR_LABELS,
        key: Some((UNSCORED, UNSCORED_NAME)),
    };
    error_bar
        .under(width, height, &error)
        .save(&dir.join(format!("{stem}_error.png")))
}

/// Width of the plots, pixels.
const W: u32 = 800;
/// Height of a per-frame plot, pixels.
const H: u32 = 400;
/// Outer margin, pixels.
const MARGIN: i64 = 12;

/// Title, centred at the top.
fn title(c: &mut Canvas, s: &str) {
    let w = i64::from(text_size(s, TEXT).0);
    c.text(i64::from(W) / 2 - w / 2, MARGIN, s, TEXT, INK);
}

/// Per-frame spp and PSNR plots of one scene.
///
/// # Errors
///
/// File or encoding errors.
pub fn write_series_plots(
    dir: &Path,
    scene: &str,
    runs: &[(String, Vec<FrameRecord>)],
) -> Result<(), ReportError> {
    let frames = runs.iter().map(|(_, r)| r.len()).max().unwrap_or(0).max(2) as f64 - 1.0;
    let x = Scale::new(0.0, frames, nice_step(frames, 10).max(1.0));
    let legend = series_legend(runs);
    let (lw, _) = legend_size(&legend);
    let th = i64::from(text_size("0", TEXT).1);
    let getters: [fn(&FrameRecord) -> f64; 2] = [|r| r.spp, |r| r.psnr];
    for ((name, what, y_name), get) in SERIES.into_iter().zip(getters) {
        let y = if name == "spp" {
            Scale::new(0.0, 64.0, 16.0)
        } else {
            let vals = runs.iter().flat_map(|(_, r)| r.iter().map(get));
            let (lo, hi) = vals
                .filter(|v| v.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(v), b.max(v))
                });
            Scale::rounded(lo, hi, 6)
        };
        let mut c = Canvas::new(W, H);
        title(&mut c, &format!("{scene}: {what}"));
        let top = MARGIN + 2 * th + 3 * GAP;
        let frame = Frame {
            left: (MARGIN as f64) + Frame::label_margin(&y),
            top: top as f64,
            right: f64::from(W) - (2 * MARGIN) as f64 - f64::from(lw),
            bottom: (i64::from(H) - MARGIN - 2 * th - 2 * GAP) as f64,
            x,
            y,
        };
        frame.draw_axes(&mut c, X_FRAME, y_name);
        for ((_, recs), e) in runs.iter().zip(&legend) {
            let pts: Vec<(f64, f64)> = recs
                .iter()
                .map(|r| frame.at(f64::from(r.frame), get(r)))
                .collect();
            for w in pts.windows(2) {
                if let [a, b] = w {
                    c.thick_line(*a, *b, e.colour);
                }
            }
        }
        draw_legend(&mut c, frame.right as i64 + MARGIN, top, &legend);
        c.save(&dir.join(format!("{scene}_{name}.png")))?;
    }
    Ok(())
}

/// Pareto plots: mean spp vs mean PSNR and p50 time vs mean PSNR, one panel per scene.
///
/// # Errors
///
/// File or encoding errors.
pub fn write_pareto(dir: &Path, all: &[RunSummary]) -> Result<(), ReportError> {
    let scenes = SceneKind::ALL.map(|k| k.name());
    let th = i64::from(text_size("0", TEXT).1);
    let head = MARGIN + th + 2 * GAP;
    let panel: i64 = 270;
    let legend = pareto_legend(all);
    let (lw, _) = legend_size(&legend);
    let getters: [fn(&RunSummary) -> f64; 2] = [|s| s.mean_spp, |s| s.p50_ms];
    for ((name, what, x_name), get) in PARETO.into_iter().zip(getters) {
        let mut c = Canvas::new(W, (head + panel * scenes.len() as i64) as u32);
        title(&mut c, what);
        let right = f64::from(W) - (2 * MARGIN) as f64 - f64::from(lw);
        for (k, scene) in scenes.iter().enumerate() {
            let top = head + panel * k as i64 + th + 2 * GAP;
            let pts: Vec<&RunSummary> = all.iter().filter(|s| s.scene == *scene).collect();
            let range = |f: &dyn Fn(&RunSummary) -> f64| {
                pts.iter()
                    .map(|s| f(s))
                    .filter(|v| v.is_finite())
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                        (a.min(v), b.max(v))
                    })
            };
            let (_, x1) = range(&get);
            let (y0, y1) = range(&|s| s.mean_psnr);
            let heading = |c: &mut Canvas, left: f64| {
                let w = i64::from(text_size(scene, TEXT).0);
                let centre = ((left + right) / 2.0) as i64;
                c.text(centre - w / 2, top - GAP - th, scene, TEXT, INK);
            };
            if !(x1.is_finite() && y0.is_finite()) {
                heading(&mut c, MARGIN as f64);
                c.text(MARGIN, top + th, NO_RUNS, TEXT, INK);
                continue;
            }
            let x_hi = x1 * 1.05;
            let x = Scale::new(0.0, x_hi, nice_step(x_hi, 8));
            let pad = ((y1 - y0) * 0.05).max(0.25);
            let y = Scale::rounded(y0 - pad, y1 + pad, 5);
            let frame = Frame {
                left: (MARGIN as f64) + Frame::label_margin(&y),
                top: top as f64,
                right,
                bottom: (top + panel - 3 * th - 5 * GAP) as f64,
                x,
                y,
            };
            frame.draw_axes(&mut c, x_name, Y_PSNR);
            heading(&mut c, frame.left);
            // Swept settings first, so the default runs stay on top.
            for s in pts.iter().filter(|s| is_sweep(&s.label)) {
                let (px, py) = frame.at(get(s), s.mean_psnr);
                Marker::Ring.draw(&mut c, px, py, colour(&s.label));
            }
            let dots: Vec<((f64, f64), Rgb)> = pts
                .iter()
                .filter(|s| !is_sweep(&s.label))
                .map(|s| (frame.at(get(s), s.mean_psnr), colour(&s.label)))
                .collect();
            for (i, &((px, py), col)) in dots.iter().enumerate() {
                // A dot that later dots would cover grows two pixels a side per cover, so
                // coincident runs (adaptive models that all saturate, say) nest visibly.
                let covers = dots
                    .iter()
                    .skip(i + 1)
                    .filter(|((qx, qy), _)| (qx - px).abs().max((qy - py).abs()) < f64::from(NEAR));
                c.dot(px, py, 3 + 2 * covers.count() as u32, col);
            }
        }
        draw_legend(&mut c, right as i64 + MARGIN, head + th + 2 * GAP, &legend);
        c.save(&dir.join(format!("pareto_{name}.png")))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use half::f16;

    use super::chart::Entry;
    use super::runs::SWEEP;
    use super::runs::fixtures::{model_names, summary};
    use super::*;
    use spvg_wgpu::Timer;

    /// A fresh directory for one test's files.
    fn scratch_dir(tag: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("spvg-plot-{}-{tag}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display()));
        d
    }

    /// Decodes an RGB8 PNG: width, height, pixels.
    fn read_png(path: &Path) -> (u32, u32, Vec<u8>) {
        let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        let mut r = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .unwrap_or_else(|e| panic!("{path:?}: {e}"));
        let mut buf = vec![0; r.output_buffer_size().unwrap_or(0)];
        let info = r
            .next_frame(&mut buf)
            .unwrap_or_else(|e| panic!("{path:?}: {e}"));
        assert_eq!(info.color_type, png::ColorType::Rgb, "{path:?} colour type");
        buf.truncate(info.buffer_size());
        (info.width, info.height, buf)
    }

    /// Whether colour `c` appears in an image `w` wide left of column `x_end`.
    fn has_colour(px: &[u8], w: u32, x_end: u32, c: Rgb) -> bool {
        px.chunks_exact(3)
            .enumerate()
            .any(|(i, p)| (i as u32 % w) < x_end && p == c)
    }

    #[test]
    fn every_label_has_glyphs() {
        let mut labels: Vec<String> = model_names();
        for scene in SceneKind::ALL.map(|k| k.name()) {
            labels.push(scene.into());
            for (_, what, y_name) in SERIES {
                labels.push(format!("{scene}: {what}"));
                labels.push(y_name.into());
            }
        }
        for (_, what, x_name) in PARETO {
            labels.extend([what.into(), x_name.into()]);
        }
        labels.extend([X_FRAME, Y_PSNR, SWEEP, NO_RUNS, UNSCORED_NAME].map(String::from));
        labels.extend(
            COUNT_LABELS
                .into_iter()
                .chain(ERROR_LABELS)
                .map(String::from),
        );
        // Tick labels: digits, a point and a minus sign.
        labels.push("-0123456789.".into());
        for l in &labels {
            for ch in l.chars() {
                assert!(font::glyph(ch).is_some(), "{ch:?} in {l:?} has no glyph");
            }
        }
    }

    #[test]
    fn plot_files_show_each_series_colour() {
        let dir = scratch_dir("series");
        let runs: Vec<(String, Vec<FrameRecord>)> = ["fixed16", "as", "ocv"]
            .iter()
            .enumerate()
            .map(|(i, n)| {
                let recs = (0..12)
                    .map(|t| FrameRecord {
                        frame: t,
                        spp: 10.0 + 15.0 * i as f64 + f64::from(t),
                        time_ms: 1.0,
                        psnr: 30.0 + 3.0 * i as f64,
                        psnr_acc: 35.0,
                    })
                    .collect();
                (n.to_string(), recs)
            })
            .collect();
        let result = write_series_plots(&dir, "flash", &runs);
        assert!(result.is_ok(), "write_series_plots: {result:?}");
        // Data lie left of the legend, which holds the same colours.
        let legend_x = |entries: &[Entry]| W - MARGIN as u32 - legend_size(entries).0;
        for name in ["spp", "psnr"] {
            let (w, h, px) = read_png(&dir.join(format!("flash_{name}.png")));
            assert_eq!((w, h), (W, H), "flash_{name}.png size");
            let x_end = legend_x(&series_legend(&runs));
            for (label, _) in &runs {
                let c = colour(label);
                assert!(
                    has_colour(&px, w, x_end, c),
                    "{label} line missing from {name}"
                );
                assert!(
                    has_colour(&px, w, w, c),
                    "{label} missing from {name} legend"
                );
            }
        }
        // as, ccv and ocv coincide: each must still show.
        let all = vec![
            summary("flash", "fixed16", 16.0, 35.0),
            summary("flash", "as", 30.0, 41.0),
            summary("flash", "ccv", 30.0, 41.0),
            summary("flash", "ocv", 30.1, 41.0),
            summary("static", "as kappa=1", 25.0, 40.0),
        ];
        let result = write_pareto(&dir, &all);
        assert!(result.is_ok(), "write_pareto: {result:?}");
        for name in ["spp", "time"] {
            let (w, _, px) = read_png(&dir.join(format!("pareto_{name}.png")));
            let x_end = legend_x(&pareto_legend(&all));
            for s in &all {
                let c = colour(&s.label);
                assert!(has_colour(&px, w, x_end, c), "{} point missing", s.label);
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn frame_images_keep_their_scales() {
        let dir = scratch_dir("frame");
        let (w, h) = (20_u32, 10_u32);
        let n = (w * h) as usize;
        let counts: Vec<u32> = (0..n as u32).map(|i| i % 70).collect();
        let out = FrameOutput {
            result: vec![
                [
                    f16::from_f32(0.5),
                    f16::from_f32(0.5),
                    f16::from_f32(0.5),
                    f16::ONE
                ];
                n
            ],
            count: counts.clone(),
            time_ms: 0.0,
            timer: Timer::WallClock,
        };
        let reference = vec![[0.5_f32; 3]; n];
        let mask: Vec<u8> = (0..n).map(|i| u8::from(i % 3 != 0)).collect();
        let result = write_frame_images(&dir, "t", w, h, &out, &reference, &mask);
        assert!(result.is_ok(), "write_frame_images: {result:?}");

        let (rw, rh, _) = read_png(&dir.join("t_result.png"));
        assert_eq!((rw, rh), (w, h), "result image is the frame alone");
        let (cw, ch, px) = read_png(&dir.join("t_count.png"));
        assert!(
            cw >= w && ch > h,
            "count image {cw}x{ch} holds the frame and a bar"
        );
        for (i, &c) in counts.iter().enumerate() {
            let (x, y) = (i as u32 % w, i as u32 / w);
            let at = ((y * cw + x) * 3) as usize;
            // Black 0 to white 64, an independent statement of the scale.
            let want = (f64::from(c.min(64)) / 64.0 * 255.0).floor() as u8;
            assert_eq!(px[at], want, "count {c} at ({x},{y})");
        }
        let (ew, _, px) = read_png(&dir.join("t_error.png"));
        for (i, &m) in mask.iter().enumerate() {
            let (x, y) = (i as u32 % w, i as u32 / w);
            let at = ((y * ew + x) * 3) as usize;
            let want = if m == 0 { UNSCORED } else { [0, 0, 0] };
            assert_eq!(px[at..at + 3], want, "error pixel ({x},{y}), mask {m}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn notes_name_what_the_plots_show() {
        for n in model_names().iter().map(String::as_str).chain([SWEEP]) {
            let short = n.trim_start_matches("fixed");
            assert!(PLOT_NOTES.contains(short), "PLOT_NOTES lacks {n}");
        }
        for f in [
            "_spp.png",
            "_psnr.png",
            "pareto_spp.png",
            "pareto_time.png",
            "count",
            "error",
        ] {
            assert!(PLOT_NOTES.contains(f), "PLOT_NOTES lacks {f}");
        }
        for scene in SceneKind::ALL.map(|k| k.name()) {
            assert!(PLOT_NOTES.contains(scene), "PLOT_NOTES lacks {scene}");
        }
    }
}

//! PNG images and plots written with the `png` crate alone (no font dependencies): frame
//! images (result, count map, error map), per-frame series and Pareto scatter plots.
//! Axis ranges are printed with a built-in 3x5 digit font; the legend is in [`PLOT_NOTES`].

use std::path::Path;

use crate::error::PassError;
use crate::evaluate::{FrameRecord, RunSummary};
use crate::frame::{FrameOutput, luminance};
use crate::metrics::rgb;

/// Legend of the plots, for `report.md`.
pub const PLOT_NOTES: &str = "## Plots\n\n\
Colours: fixed 8/16/32/64 light to dark grey, AS red, CCV green, OCV blue (sweep points \
lighter). `<scene>_spp.png`: mean spp per frame (x: frame, y: spp, range printed on the \
axes). `<scene>_psnr.png`: single-frame PSNR per frame (dB). `pareto_spp.png` / \
`pareto_time.png`: x = mean spp or p50 pass time (ms), y = mean PSNR, one panel per scene \
(static, flash, switch, occluders from top). Images `<scene>_<model>_f<N>_{result,count,error}.png`: \
result (sRGB, clamped), count (black 0 to white 64), |luminance error| x 20.";

/// An RGB8 canvas.
struct Canvas {
    w: u32,
    h: u32,
    px: Vec<u8>,
}

const DIGITS: [u16; 12] = [
    0b111_101_101_101_111, // 0
    0b010_110_010_010_111, // 1
    0b111_001_111_100_111, // 2
    0b111_001_111_001_111, // 3
    0b101_101_111_001_001, // 4
    0b111_100_111_001_111, // 5
    0b111_100_111_101_111, // 6
    0b111_001_001_001_001, // 7
    0b111_101_111_101_111, // 8
    0b111_101_111_001_111, // 9
    0b000_000_000_000_010, // .
    0b000_000_111_000_000, // -
];

impl Canvas {
    fn new(w: u32, h: u32) -> Self {
        Self {
            w,
            h,
            px: vec![255; (w * h * 3) as usize],
        }
    }

    fn set(&mut self, x: i64, y: i64, c: [u8; 3]) {
        if x >= 0 && y >= 0 && (x as u32) < self.w && (y as u32) < self.h {
            let i = ((y as u32 * self.w + x as u32) * 3) as usize;
            if let Some(p) = self.px.get_mut(i..i + 3) {
                p.copy_from_slice(&c);
            }
        }
    }

    fn line(&mut self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), c: [u8; 3]) {
        let steps = ((x1 - x0).abs().max((y1 - y0).abs()).ceil() as i64).clamp(1, 10_000);
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            self.set(
                (x0 + t * (x1 - x0)).round() as i64,
                (y0 + t * (y1 - y0)).round() as i64,
                c,
            );
        }
    }

    fn dot(&mut self, x: f64, y: f64, c: [u8; 3]) {
        for dy in -2..=2 {
            for dx in -2..=2 {
                self.set(x.round() as i64 + dx, y.round() as i64 + dy, c);
            }
        }
    }

    fn text(&mut self, x: i64, y: i64, s: &str) {
        let mut cx = x;
        for ch in s.chars() {
            let glyph = match ch {
                '0'..='9' => DIGITS.get(ch as usize - '0' as usize).copied(),
                '.' => Some(DIGITS[10]),
                '-' => Some(DIGITS[11]),
                _ => None,
            };
            if let Some(g) = glyph {
                for row in 0..5 {
                    for col in 0..3 {
                        if g >> (14 - (row * 3 + col)) & 1 == 1 {
                            for (sx, sy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                                self.set(cx + col * 2 + sx, y + row * 2 + sy, [0, 0, 0]);
                            }
                        }
                    }
                }
            }
            cx += 8;
        }
    }

    fn save(&self, path: &Path) -> Result<(), PassError> {
        write_png(path, self.w, self.h, &self.px)
    }
}

fn write_png(path: &Path, w: u32, h: u32, rgb8: &[u8]) -> Result<(), PassError> {
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut enc = png::Encoder::new(file, w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let io = |e: png::EncodingError| PassError::Io(std::io::Error::other(e.to_string()));
    let mut writer = enc.write_header().map_err(io)?;
    writer.write_image_data(rgb8).map_err(io)?;
    writer.finish().map_err(io)
}

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
) -> Result<(), PassError> {
    let result: Vec<u8> = out.result.iter().flat_map(|t| rgb(*t).map(srgb8)).collect();
    write_png(
        &dir.join(format!("{stem}_result.png")),
        width,
        height,
        &result,
    )?;
    let count: Vec<u8> = out
        .count
        .iter()
        .flat_map(|c| [((c * 255) / 64).min(255) as u8; 3])
        .collect();
    write_png(
        &dir.join(format!("{stem}_count.png")),
        width,
        height,
        &count,
    )?;
    let error: Vec<u8> = out
        .result
        .iter()
        .zip(reference)
        .zip(mask)
        .flat_map(|((t, r), m)| {
            if *m == 0 {
                [0, 0, 64]
            } else {
                let e = (luminance(rgb(*t)) - luminance(*r)).abs() * 20.0;
                [srgb8(e); 3]
            }
        })
        .collect();
    write_png(
        &dir.join(format!("{stem}_error.png")),
        width,
        height,
        &error,
    )
}

fn colour(label: &str) -> [u8; 3] {
    let light = label.contains(' ');
    let base = match label.split(' ').next().unwrap_or("") {
        "fixed8" => [200, 200, 200],
        "fixed16" => [150, 150, 150],
        "fixed32" => [100, 100, 100],
        "fixed64" => [40, 40, 40],
        "as" => [220, 30, 30],
        "ccv" => [20, 160, 40],
        "ocv" => [30, 60, 220],
        _ => [0, 0, 0],
    };
    if light {
        base.map(|c| ((u16::from(c) + 255) / 2) as u8)
    } else {
        base
    }
}

const W: u32 = 640;
const H: u32 = 320;
const M: f64 = 40.0;

fn frame_axes(c: &mut Canvas, x0: f64, x1: f64, y0: f64, y1: f64, top: f64, height: f64) {
    let (l, r, b) = (M, f64::from(W) - 10.0, top + height - 20.0);
    c.line((l, top + 10.0), (l, b), [0, 0, 0]);
    c.line((l, b), (r, b), [0, 0, 0]);
    c.text(2, (top + 10.0) as i64, &format!("{y1:.0}"));
    c.text(2, (b - 10.0) as i64, &format!("{y0:.0}"));
    c.text(l as i64, (b + 5.0) as i64, &format!("{x0:.0}"));
    c.text((r - 40.0) as i64, (b + 5.0) as i64, &format!("{x1:.1}"));
}

fn map(v: f64, a: f64, b: f64, lo: f64, hi: f64) -> f64 {
    if (b - a).abs() < 1e-12 {
        lo
    } else {
        lo + (v - a) / (b - a) * (hi - lo)
    }
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
) -> Result<(), PassError> {
    let frames = runs.iter().map(|(_, r)| r.len()).max().unwrap_or(0).max(2) as f64 - 1.0;
    for (name, get, fixed) in [
        (
            "spp",
            (|r: &FrameRecord| r.spp) as fn(&FrameRecord) -> f64,
            Some((0.0, 64.0)),
        ),
        ("psnr", |r: &FrameRecord| r.psnr, None),
    ] {
        let vals = runs
            .iter()
            .flat_map(|(_, r)| r.iter().map(get))
            .filter(|v| v.is_finite());
        let (lo, hi) = fixed.unwrap_or_else(|| {
            vals.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            })
        });
        let (lo, hi) = if lo.is_finite() {
            (lo.floor(), hi.ceil())
        } else {
            (0.0, 1.0)
        };
        let mut c = Canvas::new(W, H);
        frame_axes(&mut c, 0.0, frames, lo, hi, 0.0, f64::from(H));
        for (label, recs) in runs {
            let col = colour(label);
            let pts: Vec<(f64, f64)> = recs
                .iter()
                .map(|r| {
                    (
                        map(f64::from(r.frame), 0.0, frames, M, f64::from(W) - 10.0),
                        map(get(r).clamp(lo, hi), lo, hi, f64::from(H) - 20.0, 10.0),
                    )
                })
                .collect();
            for w in pts.windows(2) {
                if let [a, b] = w {
                    c.line(*a, *b, col);
                }
            }
        }
        c.save(&dir.join(format!("{scene}_{name}.png")))?;
    }
    Ok(())
}

/// Pareto plots: mean spp vs mean PSNR and p50 time vs mean PSNR, one panel per scene.
///
/// # Errors
///
/// File or encoding errors.
pub fn write_pareto(dir: &Path, all: &[RunSummary]) -> Result<(), PassError> {
    let scenes = ["static", "flash", "switch", "occluders"];
    let panel = 240.0;
    for (name, get) in [
        (
            "spp",
            (|s: &RunSummary| s.mean_spp) as fn(&RunSummary) -> f64,
        ),
        ("time", |s: &RunSummary| s.p50_ms),
    ] {
        let mut c = Canvas::new(W, (panel * scenes.len() as f64) as u32);
        for (k, scene) in scenes.iter().enumerate() {
            let pts: Vec<&RunSummary> = all.iter().filter(|s| s.scene == *scene).collect();
            let top = panel * k as f64;
            let xs = pts.iter().map(|s| get(s));
            let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
            let ys = pts.iter().map(|s| s.mean_psnr);
            let (y0, y1) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
            if !(x0.is_finite() && y0.is_finite()) {
                continue;
            }
            let (x0, x1, y0, y1) = (0.0, x1 * 1.05, y0.floor(), y1.ceil());
            frame_axes(&mut c, x0, x1, y0, y1, top, panel);
            for s in pts {
                c.dot(
                    map(get(s), x0, x1, M, f64::from(W) - 10.0),
                    map(s.mean_psnr, y0, y1, top + panel - 20.0, top + 10.0),
                    colour(&s.label),
                );
            }
        }
        c.save(&dir.join(format!("pareto_{name}.png")))?;
    }
    Ok(())
}

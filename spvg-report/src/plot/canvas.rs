//! An RGB8 canvas with the few drawing primitives the plots need (pixels, lines, boxes,
//! markers, text in the built-in font), and PNG output through the `png` crate.

use std::path::Path;

use super::font::{self, CELL_H};
use crate::error::ReportError;

/// An 8-bit sRGB colour.
pub(super) type Rgb = [u8; 3];

/// A white RGB8 canvas; drawing outside it is clipped.
pub(super) struct Canvas {
    w: u32,
    h: u32,
    px: Vec<u8>,
}

impl Canvas {
    /// A white `w` x `h` canvas.
    pub(super) fn new(w: u32, h: u32) -> Self {
        Self {
            w,
            h,
            px: vec![255; w as usize * h as usize * 3],
        }
    }

    /// Width in pixels.
    #[cfg(test)]
    #[inline]
    #[must_use]
    pub(super) fn width(&self) -> u32 {
        self.w
    }

    /// Height in pixels.
    #[cfg(test)]
    #[inline]
    #[must_use]
    pub(super) fn height(&self) -> u32 {
        self.h
    }

    /// The pixel at (`x`, `y`), `None` outside.
    #[cfg(test)]
    #[must_use]
    pub(super) fn get(&self, x: u32, y: u32) -> Option<Rgb> {
        if x >= self.w || y >= self.h {
            return None;
        }
        let i = (y as usize * self.w as usize + x as usize) * 3;
        let p = self.px.get(i..i + 3)?;
        Some([p[0], p[1], p[2]])
    }

    /// Sets the pixel at (`x`, `y`) when it lies on the canvas.
    pub(super) fn set(&mut self, x: i64, y: i64, c: Rgb) {
        if x >= 0 && y >= 0 && x < i64::from(self.w) && y < i64::from(self.h) {
            let i = (y as usize * self.w as usize + x as usize) * 3;
            if let Some(p) = self.px.get_mut(i..i + 3) {
                p.copy_from_slice(&c);
            }
        }
    }

    /// Fills the `w` x `h` box with top-left corner (`x`, `y`).
    pub(super) fn fill(&mut self, x: i64, y: i64, w: u32, h: u32, c: Rgb) {
        for dy in 0..i64::from(h) {
            for dx in 0..i64::from(w) {
                self.set(x + dx, y + dy, c);
            }
        }
    }

    /// Outlines the `w` x `h` box with top-left corner (`x`, `y`).
    pub(super) fn outline(&mut self, x: i64, y: i64, w: u32, h: u32, c: Rgb) {
        let (r, b) = (x + i64::from(w) - 1, y + i64::from(h) - 1);
        for i in x..=r {
            self.set(i, y, c);
            self.set(i, b, c);
        }
        for j in y..=b {
            self.set(x, j, c);
            self.set(r, j, c);
        }
    }

    /// A one-pixel line from `a` to `b` (both ends drawn).
    pub(super) fn line(&mut self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), c: Rgb) {
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

    /// A two-pixel line (a 2x2 brush), for data series.
    pub(super) fn thick_line(&mut self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), c: Rgb) {
        for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            self.line((x0 + dx, y0 + dy), (x1 + dx, y1 + dy), c);
        }
    }

    /// A filled square `2 * half + 1` pixels wide centred on (`x`, `y`).
    pub(super) fn dot(&mut self, x: f64, y: f64, half: u32, c: Rgb) {
        let side = 2 * half + 1;
        let h = i64::from(half);
        self.fill(x.round() as i64 - h, y.round() as i64 - h, side, side, c);
    }

    /// A hollow 9x9 square centred on (`x`, `y`), two pixels thick.
    pub(super) fn ring(&mut self, x: f64, y: f64, c: Rgb) {
        let (x, y) = (x.round() as i64, y.round() as i64);
        self.outline(x - 4, y - 4, 9, 9, c);
        self.outline(x - 3, y - 3, 7, 7, c);
    }

    /// Draws `s` in the built-in font at integer `scale` (at least 1) with its cell's
    /// top-left corner at (`x`, `y`); returns the drawn box, as [`text_size`].
    pub(super) fn text(&mut self, x: i64, y: i64, s: &str, scale: u32, c: Rgb) -> (u32, u32) {
        let k = scale.max(1);
        for (at, g) in font::layout(s) {
            for row in 0..CELL_H {
                for col in 0..g.width() {
                    if g.pixel(col, row) {
                        let px = x + i64::from((at + col) * k);
                        self.fill(px, y + i64::from(row * k), k, k, c);
                    }
                }
            }
        }
        text_size(s, scale)
    }

    /// Copies an RGB8 image `w` pixels wide with its top-left corner at (`x`, `y`).
    pub(super) fn blit(&mut self, x: i64, y: i64, w: u32, rgb8: &[u8]) {
        for (i, p) in rgb8.chunks_exact(3).enumerate() {
            let (dx, dy) = (
                (i % w.max(1) as usize) as i64,
                (i / w.max(1) as usize) as i64,
            );
            self.set(x + dx, y + dy, [p[0], p[1], p[2]]);
        }
    }

    /// Writes the canvas as an RGB8 PNG.
    ///
    /// # Errors
    ///
    /// File or encoding errors.
    pub(super) fn save(&self, path: &Path) -> Result<(), ReportError> {
        write_png(path, self.w, self.h, &self.px)
    }
}

/// Size in pixels of `s` drawn at `scale` (at least 1): text width by [`font::text_width`],
/// and the full cell height with descenders.
#[inline]
#[must_use]
pub(super) fn text_size(s: &str, scale: u32) -> (u32, u32) {
    let k = scale.max(1);
    (font::text_width(s) * k, CELL_H * k)
}

/// Writes a `w` x `h` RGB8 image as a PNG.
///
/// # Errors
///
/// File or encoding errors (including a buffer of the wrong length).
pub(super) fn write_png(path: &Path, w: u32, h: u32, rgb8: &[u8]) -> Result<(), ReportError> {
    let file =
        std::io::BufWriter::new(std::fs::File::create(path).map_err(|e| ReportError::io(path, e))?);
    let mut enc = png::Encoder::new(file, w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let io = |e: png::EncodingError| ReportError::io(path, std::io::Error::other(e.to_string()));
    let mut writer = enc.write_header().map_err(io)?;
    writer.write_image_data(rgb8).map_err(io)?;
    writer.finish().map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;

    const INK: Rgb = [0, 0, 0];
    const WHITE: Rgb = [255, 255, 255];

    /// Every pixel that is not white, as (x, y).
    fn inked(c: &Canvas) -> Vec<(u32, u32)> {
        (0..c.height())
            .flat_map(|y| (0..c.width()).map(move |x| (x, y)))
            .filter(|&(x, y)| c.get(x, y) != Some(WHITE))
            .collect()
    }

    /// All printable characters the font has (space aside), as one string.
    fn charset() -> String {
        ('!'..='~')
            .filter(|&ch| font::glyph(ch).is_some())
            .collect()
    }

    #[test]
    fn text_stays_inside_its_box_and_fills_it_tightly() {
        let all = charset();
        let samples = [
            "flash: mean spp per frame",
            "PSNR dB",
            "p50 ms",
            "s0^2=1e-3 (sweep)",
            "|err| x20, 12.5%",
            " padded ",
            all.as_str(),
        ];
        for s in samples {
            for scale in 1..=3 {
                let (x0, y0) = (7_i64, 5_i64);
                let (w, h) = text_size(s, scale);
                let mut c = Canvas::new(w + 20, h + 12);
                assert_eq!(c.text(x0, y0, s, scale, INK), (w, h), "{s:?} x{scale}");
                let px = inked(&c);
                let inside = |&(x, y): &(u32, u32)| {
                    (x0..x0 + i64::from(w)).contains(&i64::from(x))
                        && (y0..y0 + i64::from(h)).contains(&i64::from(y))
                };
                assert!(
                    px.iter().all(inside),
                    "{s:?} x{scale} draws outside {w}x{h}"
                );
                // Tight horizontally: the text starts and ends on set glyph columns
                // (a leading or trailing space is part of the box but sets nothing).
                let xmin = px.iter().map(|p| p.0).min();
                let xmax = px.iter().map(|p| p.0).max();
                if !s.starts_with(' ') {
                    assert_eq!(xmin, Some(x0 as u32), "{s:?} x{scale}: left edge");
                }
                if !s.ends_with(' ') {
                    assert_eq!(xmax, Some(x0 as u32 + w - 1), "{s:?} x{scale}: right edge");
                }
                assert!(!px.is_empty(), "{s:?} x{scale}: nothing drawn");
            }
        }
    }

    #[test]
    fn cap_height_and_descenders_reach_the_cell_edges() {
        let (w, h) = text_size("Ag", 2);
        let mut c = Canvas::new(w, h);
        c.text(0, 0, "Ag", 2, INK);
        let px = inked(&c);
        let ymin = px.iter().map(|p| p.1).min();
        let ymax = px.iter().map(|p| p.1).max();
        assert_eq!(ymin, Some(0), "capital A starts on the top row");
        assert_eq!(ymax, Some(h - 1), "g descends to the last row");
    }

    #[test]
    fn scaled_text_is_the_unit_text_blown_up() {
        let s = "fixed64 ccv ocv: 0.5/PSNR";
        let (w1, h1) = text_size(s, 1);
        let mut one = Canvas::new(w1, h1);
        one.text(0, 0, s, 1, INK);
        for k in 2..=3 {
            let (w, h) = text_size(s, k);
            assert_eq!((w, h), (w1 * k, h1 * k), "size at scale {k}");
            let mut big = Canvas::new(w, h);
            big.text(0, 0, s, k, INK);
            for y in 0..h {
                for x in 0..w {
                    assert_eq!(big.get(x, y), one.get(x / k, y / k), "({x},{y}) at x{k}");
                }
            }
        }
    }

    #[test]
    fn text_is_clipped_at_the_canvas_edges() {
        let mut c = Canvas::new(10, 6);
        c.text(-20, -3, "clipped text", 2, INK);
        c.text(5, 4, "W", 3, INK);
        assert!(!inked(&c).is_empty(), "parts inside the canvas are drawn");
    }

    #[test]
    fn lines_join_their_ends_inside_their_box() {
        let mut c = Canvas::new(40, 30);
        let (a, b) = ((3.0, 25.0), (31.0, 4.0));
        c.line(a, b, INK);
        assert_eq!(c.get(3, 25), Some(INK), "start drawn");
        assert_eq!(c.get(31, 4), Some(INK), "end drawn");
        let px = inked(&c);
        assert!(
            px.iter()
                .all(|&(x, y)| (3..=31).contains(&x) && (4..=25).contains(&y)),
            "line leaves its bounding box"
        );
        // One pixel per step along the longer axis: every column is hit.
        for x in 3..=31 {
            assert!(px.iter().any(|p| p.0 == x), "gap in column {x}");
        }
    }

    #[test]
    fn markers_are_centred() {
        let mut c = Canvas::new(30, 30);
        c.dot(5.0, 6.0, 3, INK);
        c.ring(18.0, 17.0, INK);
        let px = inked(&c);
        let dot: Vec<_> = px.iter().filter(|p| p.0 < 11).collect();
        let ring: Vec<_> = px.iter().filter(|p| p.0 >= 11).collect();
        assert_eq!(dot.len(), 49, "7x7 dot");
        assert!(
            dot.iter()
                .all(|p| p.0.abs_diff(5) <= 3 && p.1.abs_diff(6) <= 3),
            "dot"
        );
        assert_eq!(ring.len(), 81 - 25, "9x9 ring with a 5x5 hole");
        assert!(
            ring.iter()
                .all(|p| p.0.abs_diff(18) <= 4 && p.1.abs_diff(17) <= 4),
            "ring"
        );
        assert_eq!(c.get(18, 17), Some(WHITE), "ring centre is hollow");
    }
}

//! The scale bar drawn under the count and error images: the colour ramp of the image,
//! its end values, the name of the quantity and an optional key swatch, in the built-in
//! font at a scale that follows the image width.

use super::canvas::{Canvas, Rgb, text_size};
use super::chart::INK;

/// A scale bar under an image: the colour ramp `ramp(0..=1)`, its end values and a name.
pub(super) struct ScaleBar<'a> {
    /// Colour at each point of the bar, 0 at the left end and 1 at the right.
    pub(super) ramp: &'a dyn Fn(f64) -> Rgb,
    /// Value at the left end, name of the quantity, value at the right end.
    pub(super) labels: [&'a str; 3],
    /// An extra line: a swatch and what it means.
    pub(super) key: Option<(Rgb, &'a str)>,
}

impl ScaleBar<'_> {
    /// Text scale for an image `width` pixels wide (1 below 320 pixels, up to 3).
    #[inline]
    #[must_use]
    fn scale(width: u32) -> u32 {
        (width / 160).clamp(1, 3)
    }

    /// The image (`width` x `height` RGB8) with the bar below it: the ramp, then the end
    /// values at its ends with the name centred between them (or on a line of its own
    /// when it does not fit there), then the key. The canvas is widened (white on the
    /// right) when the end values alone need more room than the image gives.
    pub(super) fn under(&self, width: u32, height: u32, rgb8: &[u8]) -> Canvas {
        let k = Self::scale(width);
        let (pad, bar_h, th) = (2 * k, 4 * k, text_size("0", k).1);
        let [lo, mid, hi] = self.labels.map(|s| (s, text_size(s, k).0));
        let key_w = self.key.map_or(0, |(_, s)| 6 * k + text_size(s, k).0);
        let w = width.max(2 * pad + (lo.1 + hi.1 + 3 * k).max(mid.1).max(key_w));
        // The name sits centred with at least 3k clear on each side, or moves down.
        let mid_x = (w / 2).saturating_sub(mid.1 / 2);
        let inline = mid_x >= pad + lo.1 + 3 * k && mid_x + mid.1 + 3 * k + pad + hi.1 <= w;
        let lines = 1 + u32::from(!inline) + u32::from(self.key.is_some());
        let h = height + pad + bar_h + lines * (k + th) + pad;
        let mut c = Canvas::new(w, h);
        c.blit(0, 0, width, rgb8);
        let (x0, bar_w) = (i64::from(pad), w - 2 * pad);
        let y = i64::from(height + pad);
        for i in 0..bar_w {
            let f = f64::from(i) / f64::from(bar_w.saturating_sub(1).max(1));
            c.fill(x0 + i64::from(i), y, 1, bar_h, (self.ramp)(f));
        }
        c.outline(x0 - 1, y - 1, bar_w + 2, bar_h + 2, [128, 128, 128]);
        let mut ty = y + i64::from(bar_h + k);
        c.text(x0, ty, lo.0, k, INK);
        c.text(i64::from(w - pad - hi.1), ty, hi.0, k, INK);
        if inline {
            c.text(i64::from(mid_x), ty, mid.0, k, INK);
        } else {
            ty += i64::from(th + k);
            c.text(x0, ty, mid.0, k, INK);
        }
        if let Some((colour, name)) = self.key {
            ty += i64::from(th + k);
            c.fill(x0, ty, 5 * k, 7 * k, colour);
            c.text(x0 + i64::from(6 * k), ty, name, k, INK);
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WHITE: Rgb = [255, 255, 255];

    fn grey(f: f64) -> Rgb {
        [(f * 255.0).round() as u8; 3]
    }

    /// A `w` x `h` test image: a colour that the bar never uses.
    fn image(w: u32, h: u32) -> Vec<u8> {
        [10_u8, 200, 90].repeat((w * h) as usize)
    }

    #[test]
    fn image_is_kept_and_the_bar_spans_the_ramp() {
        for (w, h) in [(16, 8), (64, 48), (128, 96), (400, 300), (1280, 720)] {
            for key in [None, Some(([0, 0, 64], "unscored"))] {
                let bar = ScaleBar {
                    ramp: &grey,
                    labels: ["0", "|err|", "0.05"],
                    key,
                };
                let c = bar.under(w, h, &image(w, h));
                assert!(
                    c.width() >= w && c.height() > h,
                    "{w}x{h}: canvas too small"
                );
                for y in 0..h {
                    for x in 0..w {
                        assert_eq!(c.get(x, y), Some([10, 200, 90]), "{w}x{h} at ({x},{y})");
                    }
                }
                // The ramp row lies 2k below the image, inset 2k from each side.
                let k = ScaleBar::scale(w);
                let y = h + 2 * k;
                let x0 = 2 * k;
                let x1 = c.width() - 2 * k - 1;
                assert_eq!(c.get(x0, y), Some(grey(0.0)), "{w}x{h}: left end");
                assert_eq!(c.get(x1, y), Some(grey(1.0)), "{w}x{h}: right end");
                let row: Vec<u8> = (x0..=x1)
                    .filter_map(|x| c.get(x, y))
                    .map(|p| p[0])
                    .collect();
                assert!(
                    row.windows(2).all(|p| p[0] <= p[1]),
                    "{w}x{h}: ramp not monotone"
                );
                // Margins stay clear: the outer columns and the last row below the image.
                for yy in h..c.height() {
                    assert_eq!(c.get(0, yy), Some(WHITE), "{w}x{h}: left margin row {yy}");
                    let r = c.width() - 1;
                    assert_eq!(c.get(r, yy), Some(WHITE), "{w}x{h}: right margin row {yy}");
                }
                for xx in 0..c.width() {
                    let b = c.height() - 1;
                    assert_eq!(c.get(xx, b), Some(WHITE), "{w}x{h}: bottom row col {xx}");
                }
                if let Some((colour, _)) = key {
                    let found = (h..c.height())
                        .any(|yy| (0..c.width()).any(|xx| c.get(xx, yy) == Some(colour)));
                    assert!(found, "{w}x{h}: key swatch missing");
                }
            }
        }
    }

    #[test]
    fn narrow_images_widen_the_canvas_for_the_end_values() {
        let bar = ScaleBar {
            ramp: &grey,
            labels: ["0", "spp", "64"],
            key: None,
        };
        let c = bar.under(4, 4, &image(4, 4));
        let need = text_size("0", 1).0 + text_size("64", 1).0;
        assert!(
            c.width() > need,
            "{} px holds {need} px of labels",
            c.width()
        );
        // Right of the image, beside it, the canvas is white.
        for y in 0..4 {
            for x in 4..c.width() {
                assert_eq!(c.get(x, y), Some(WHITE), "padding at ({x},{y})");
            }
        }
    }
}

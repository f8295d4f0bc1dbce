//! Chart furniture shared by the plots: axis scales with round tick steps, a framed plot
//! area with grid, ticks, tick labels and axis names, and the legend box.

use super::canvas::{Canvas, Rgb, text_size};

/// Scale of all chart text (5x7 glyphs drawn 10x14).
pub(super) const TEXT: u32 = 2;
/// Text and axis colour.
pub(super) const INK: Rgb = [0, 0, 0];
/// Grid lines at the ticks.
const GRID: Rgb = [228, 228, 228];
/// Gap between a label and what it labels, pixels.
pub(super) const GAP: i64 = 6;
/// Gap between the plot area and tick labels, pixels (wider than [`GAP`] so the lowest y
/// label and the first x label, which meet at the corner, stay apart).
const TICK_GAP: i64 = 9;

/// One axis: a data range and the step between its ticks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Scale {
    lo: f64,
    hi: f64,
    step: f64,
}

/// A round step (1, 2 or 5 times a power of ten) that cuts `span` into at most `target`
/// parts; 1 for an empty or non-finite span.
#[must_use]
pub(super) fn nice_step(span: f64, target: u32) -> f64 {
    if !(span.is_finite() && span > 0.0) {
        return 1.0;
    }
    let raw = span / f64::from(target.max(1));
    let decade = 10_f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&s| s >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0 * decade)
}

impl Scale {
    /// `lo` to `hi` with ticks every `step` (a degenerate or non-finite range becomes
    /// `lo` to `lo + 1`, a bad step the range's round step).
    #[must_use]
    pub(super) fn new(lo: f64, hi: f64, step: f64) -> Self {
        let lo = if lo.is_finite() { lo } else { 0.0 };
        let hi = if hi.is_finite() && hi > lo {
            hi
        } else {
            lo + 1.0
        };
        let step = if step.is_finite() && step > 0.0 {
            step
        } else {
            nice_step(hi - lo, 6)
        };
        Self { lo, hi, step }
    }

    /// The range `lo` to `hi` widened outward to whole round steps (about `target` ticks).
    #[must_use]
    pub(super) fn rounded(lo: f64, hi: f64, target: u32) -> Self {
        let s = Self::new(lo, hi, f64::NAN);
        let step = nice_step(s.hi - s.lo, target);
        let lo = (s.lo / step).floor() * step;
        let hi = (s.hi / step).ceil() * step;
        Self::new(lo, hi, step)
    }

    /// Tick values: the multiples of the step within the range.
    #[must_use]
    pub(super) fn ticks(&self) -> Vec<f64> {
        let first = (self.lo / self.step - 1e-9).ceil() as i64;
        let last = (self.hi / self.step + 1e-9).floor() as i64;
        (first..=last.min(first + 100))
            .map(|i| i as f64 * self.step)
            .collect()
    }

    /// `v` with as many decimals as the step needs.
    #[must_use]
    pub(super) fn label(&self, v: f64) -> String {
        let decimals = (-self.step.log10().floor()).clamp(0.0, 6.0) as usize;
        let v = if v.abs() < self.step * 1e-6 { 0.0 } else { v };
        format!("{v:.decimals$}")
    }

    /// Where `v` falls in the range, 0 at `lo` and 1 at `hi`, clamped.
    #[must_use]
    fn frac(&self, v: f64) -> f64 {
        if v.is_nan() {
            return 0.0;
        }
        ((v - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0)
    }
}

/// A plot area in pixels with its two scales.
pub(super) struct Frame {
    /// Left edge of the plot area.
    pub(super) left: f64,
    /// Top edge.
    pub(super) top: f64,
    /// Right edge.
    pub(super) right: f64,
    /// Bottom edge.
    pub(super) bottom: f64,
    /// Horizontal scale.
    pub(super) x: Scale,
    /// Vertical scale.
    pub(super) y: Scale,
}

impl Frame {
    /// Pixels left of the plot area that the y tick labels of `y` need.
    #[must_use]
    pub(super) fn label_margin(y: &Scale) -> f64 {
        let widest = y
            .ticks()
            .into_iter()
            .map(|v| text_size(&y.label(v), TEXT).0);
        (i64::from(widest.max().unwrap_or(0)) + TICK_GAP + GAP) as f64
    }

    /// Pixel position of data point (`x`, `y`), clamped to the plot area.
    #[must_use]
    pub(super) fn at(&self, x: f64, y: f64) -> (f64, f64) {
        (
            self.left + self.x.frac(x) * (self.right - self.left),
            self.bottom - self.y.frac(y) * (self.bottom - self.top),
        )
    }

    /// Grid, axis box, ticks with labels, the x name centred below the tick labels and the
    /// y name above the top-left corner.
    pub(super) fn draw_axes(&self, c: &mut Canvas, x_name: &str, y_name: &str) {
        let (l, t, r, b) = (self.left, self.top, self.right, self.bottom);
        for v in self.x.ticks() {
            let (px, _) = self.at(v, self.y.lo);
            c.line((px, t), (px, b), GRID);
        }
        for v in self.y.ticks() {
            let (_, py) = self.at(self.x.lo, v);
            c.line((l, py), (r, py), GRID);
        }
        c.outline(
            l as i64,
            t as i64,
            (r - l) as u32 + 1,
            (b - t) as u32 + 1,
            INK,
        );
        let (_, th) = text_size("0", TEXT);
        for v in self.x.ticks() {
            let (px, _) = self.at(v, self.y.lo);
            c.line((px, b), (px, b + 4.0), INK);
            let s = self.x.label(v);
            let w = text_size(&s, TEXT).0;
            c.text(
                px as i64 - i64::from(w / 2),
                b as i64 + TICK_GAP,
                &s,
                TEXT,
                INK,
            );
        }
        for v in self.y.ticks() {
            let (_, py) = self.at(self.x.lo, v);
            c.line((l - 4.0, py), (l, py), INK);
            let s = self.y.label(v);
            let w = text_size(&s, TEXT).0;
            // Centre the 7-row cap height (not the descenders) on the tick.
            let y = py as i64 - i64::from(7 * TEXT / 2);
            c.text(l as i64 - TICK_GAP - i64::from(w), y, &s, TEXT, INK);
        }
        let (xw, _) = text_size(x_name, TEXT);
        let xc = ((l + r) / 2.0) as i64 - i64::from(xw / 2);
        c.text(
            xc,
            b as i64 + TICK_GAP + GAP + i64::from(th),
            x_name,
            TEXT,
            INK,
        );
        c.text(l as i64, t as i64 - GAP - i64::from(th), y_name, TEXT, INK);
    }
}

/// How a legend entry (and its data) is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Marker {
    /// A line (per-frame series).
    Line,
    /// A filled square (a run with default settings).
    Dot,
    /// A hollow square (a swept setting).
    Ring,
}

impl Marker {
    /// Draws the marker centred on (`x`, `y`); a line is a 20-pixel stroke.
    pub(super) fn draw(self, c: &mut Canvas, x: f64, y: f64, colour: Rgb) {
        match self {
            Self::Line => c.thick_line((x - 10.0, y), (x + 9.0, y), colour),
            Self::Dot => c.dot(x, y, 3, colour),
            Self::Ring => c.ring(x, y, colour),
        }
    }
}

/// One legend line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Entry {
    /// Name shown.
    pub(super) name: String,
    /// Colour of the marker.
    pub(super) colour: Rgb,
    /// Marker.
    pub(super) marker: Marker,
}

/// Inner padding of the legend box, pixels.
const PAD: u32 = 8;
/// Width of the marker column, pixels.
const SWATCH: u32 = 24;

/// Pixel height of one legend line.
#[inline]
#[must_use]
fn row_height() -> u32 {
    text_size("0", TEXT).1 + 4
}

/// Size of the legend box of `entries`, pixels.
#[must_use]
pub(super) fn legend_size(entries: &[Entry]) -> (u32, u32) {
    let names = entries.iter().map(|e| text_size(&e.name, TEXT).0);
    let w = 2 * PAD + SWATCH + GAP as u32 + names.max().unwrap_or(0);
    (
        w,
        2 * PAD + row_height() * entries.len() as u32 - 4 * u32::from(!entries.is_empty()),
    )
}

/// Draws the legend box of `entries` with its top-left corner at (`x`, `y`): one line per
/// entry, marker then name, in the given order.
pub(super) fn draw_legend(c: &mut Canvas, x: i64, y: i64, entries: &[Entry]) {
    let (w, h) = legend_size(entries);
    c.fill(x, y, w, h, [255, 255, 255]);
    // Mid grey, a shade no model uses.
    c.outline(x, y, w, h, [128, 128, 128]);
    for (i, e) in entries.iter().enumerate() {
        let top = y + i64::from(PAD + row_height() * i as u32);
        let mid = top as f64 + f64::from(7 * TEXT) / 2.0;
        let sx = x as f64 + f64::from(PAD + SWATCH / 2);
        e.marker.draw(c, sx, mid, e.colour);
        let tx = x + i64::from(PAD + SWATCH) + GAP;
        c.text(tx, top, &e.name, TEXT, INK);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether `s` is 1, 2 or 5 times a power of ten.
    fn is_round(s: f64) -> bool {
        let m = s / 10_f64.powf(s.log10().floor());
        [1.0, 2.0, 5.0, 10.0].iter().any(|r| (m - r).abs() < 1e-9)
    }

    #[test]
    fn nice_steps_are_round_and_the_smallest_that_fit() {
        for e in -4..=5 {
            for m in [1.0, 1.3, 2.0, 2.7, 4.99, 5.0, 7.5, 9.99] {
                let span = m * 10_f64.powi(e);
                for target in [1, 4, 5, 6, 8, 10] {
                    let s = nice_step(span, target);
                    assert!(is_round(s), "step {s} for span {span} is not 1/2/5");
                    let parts = span / s;
                    assert!(
                        parts <= f64::from(target) + 1e-9,
                        "{span}/{s} = {parts} parts"
                    );
                    // The next smaller round step would cut the span into too many parts.
                    let smaller = [0.5, 0.4, 0.5]
                        .into_iter()
                        .map(|f| s * f)
                        .find(|&t| is_round(t))
                        .unwrap_or(s / 2.0);
                    let more = span / smaller;
                    assert!(
                        more > f64::from(target) - 1e-9,
                        "{span}: {smaller} fits too"
                    );
                }
            }
        }
        assert_eq!(nice_step(0.0, 5), 1.0, "empty span");
        assert_eq!(nice_step(f64::NAN, 5), 1.0, "NaN span");
    }

    #[test]
    fn ticks_cover_the_range_at_the_step() {
        let cases = [
            (0.0, 64.0, 16.0),
            (0.0, 23.0, 5.0),
            (31.79, 53.2, 5.0),
            (-3.5, 2.25, 0.5),
            (0.0, 0.07, 0.01),
        ];
        for (lo, hi, step) in cases {
            let sc = Scale::new(lo, hi, step);
            let t = sc.ticks();
            assert!(!t.is_empty(), "no ticks in {lo}..{hi}");
            assert!(
                t.iter().all(|&v| v >= lo - 1e-9 && v <= hi + 1e-9),
                "{t:?} in {lo}..{hi}"
            );
            assert!(t[0] - lo < step + 1e-9, "first tick {} far from {lo}", t[0]);
            assert!(
                hi - t[t.len() - 1] < step + 1e-9,
                "last tick far from {hi}: {t:?}"
            );
            for w in t.windows(2) {
                let d = w[1] - w[0];
                assert!(
                    (d - step).abs() < 1e-9 * step.max(1.0),
                    "spacing {d} != {step}"
                );
            }
            // Labels read back as the tick values and tell every tick apart.
            let labels: Vec<String> = t.iter().map(|&v| sc.label(v)).collect();
            for (v, l) in t.iter().zip(&labels) {
                let back: f64 = l.parse().unwrap_or(f64::NAN);
                assert!((back - v).abs() < 1e-9, "{l:?} != {v}");
            }
            let mut distinct = labels.clone();
            distinct.dedup();
            assert_eq!(distinct, labels, "repeated tick labels");
        }
    }

    #[test]
    fn rounded_ranges_contain_the_data_and_end_on_ticks() {
        for (lo, hi) in [
            (31.79, 46.1),
            (0.3, 0.9),
            (-12.0, 7.0),
            (5.0, 5.0),
            (100.0, 102.5),
        ] {
            let sc = Scale::rounded(lo, hi, 6);
            assert!(sc.lo <= lo && sc.hi >= hi, "{sc:?} misses {lo}..{hi}");
            let t = sc.ticks();
            assert!(
                (t[0] - sc.lo).abs() < 1e-9,
                "{sc:?} starts off a tick: {t:?}"
            );
            assert!(
                (t[t.len() - 1] - sc.hi).abs() < 1e-9,
                "{sc:?} ends off a tick"
            );
            assert!(t.len() <= 7 + 1, "{} ticks for {lo}..{hi}", t.len());
        }
        let bad = Scale::rounded(f64::INFINITY, f64::NEG_INFINITY, 6);
        assert!(
            bad.lo.is_finite() && bad.hi > bad.lo,
            "fallback range {bad:?}"
        );
    }

    #[test]
    fn frame_maps_corners_and_clamps() {
        let f = Frame {
            left: 40.0,
            top: 10.0,
            right: 240.0,
            bottom: 110.0,
            x: Scale::new(0.0, 20.0, 5.0),
            y: Scale::new(30.0, 50.0, 5.0),
        };
        assert_eq!(f.at(0.0, 30.0), (40.0, 110.0), "origin bottom-left");
        assert_eq!(f.at(20.0, 50.0), (240.0, 10.0), "far corner top-right");
        assert_eq!(f.at(10.0, 40.0), (140.0, 60.0), "centre");
        assert_eq!(f.at(-5.0, 99.0), (40.0, 10.0), "clamped");
        assert_eq!(f.at(f64::NAN, f64::INFINITY), (40.0, 10.0), "non-finite");
    }

    #[test]
    fn axes_stay_on_the_canvas() {
        let y = Scale::rounded(31.8, 46.2, 6);
        let left = 12.0 + Frame::label_margin(&y);
        let f = Frame {
            left,
            top: 40.0,
            right: 380.0,
            bottom: 200.0,
            x: Scale::new(0.0, 23.0, 5.0),
            y,
        };
        let mut c = Canvas::new(400, 250);
        f.draw_axes(&mut c, "frame", "PSNR dB");
        let white = [255, 255, 255];
        // Left and bottom margins hold tick labels; the outermost columns/rows stay clear.
        for yy in 0..250 {
            assert_eq!(c.get(0, yy), Some(white), "column 0, row {yy}");
        }
        for xx in 0..400 {
            assert_eq!(c.get(xx, 249), Some(white), "bottom row, column {xx}");
        }
        assert_eq!(c.get(left as u32, 120), Some(INK), "y axis drawn");
    }

    #[test]
    fn legend_shows_every_entry_in_order() {
        let entries: Vec<Entry> = [
            ("fixed8", [200, 200, 200], Marker::Line),
            ("as", [220, 30, 30], Marker::Dot),
            ("ccv", [20, 160, 40], Marker::Dot),
            ("sweep", [177, 177, 177], Marker::Ring),
        ]
        .into_iter()
        .map(|(n, colour, marker)| Entry {
            name: n.into(),
            colour,
            marker,
        })
        .collect();
        let (w, h) = legend_size(&entries);
        let (x0, y0) = (5_i64, 7_i64);
        let mut c = Canvas::new(w + 10, h + 14);
        draw_legend(&mut c, x0, y0, &entries);
        let white = [255, 255, 255];
        let inside = |x: u32, y: u32| {
            (x0..x0 + i64::from(w)).contains(&i64::from(x))
                && (y0..y0 + i64::from(h)).contains(&i64::from(y))
        };
        for y in 0..c.height() {
            for x in 0..c.width() {
                if !inside(x, y) {
                    assert_eq!(c.get(x, y), Some(white), "legend spills to ({x},{y})");
                }
            }
        }
        // Each entry's band holds its colour (the marker) and ink (its name).
        let row = i64::from(row_height());
        for (i, e) in entries.iter().enumerate() {
            let top = y0 + i64::from(PAD) + row * i as i64;
            let band = |colour: Rgb| {
                (top..top + row).any(|y| (0..c.width()).any(|x| c.get(x, y as u32) == Some(colour)))
            };
            assert!(
                band(e.colour),
                "{}: marker colour missing from its line",
                e.name
            );
            assert!(band(INK), "{}: name missing from its line", e.name);
        }
        // The widest name fits: its text ends inside the box.
        let widest = entries.iter().map(|e| text_size(&e.name, TEXT).0).max();
        assert!(
            widest.is_some_and(|tw| i64::from(PAD + SWATCH) + GAP + i64::from(tw) <= i64::from(w)),
            "box {w} too narrow"
        );
    }
}

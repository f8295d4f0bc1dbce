//! Frame images: PNG files of a frame's result, sample counts and error, each enlarged to a
//! readable size with a caption strip (scene, model, frame, what) drawn in an
//! `embedded-graphics` mono font, and a colour ramp with its end values under the count and
//! error images. Images whose pixels equal an earlier image's are not written again: the
//! writer returns the earlier file instead.

use std::collections::BTreeMap;
use std::hash::{DefaultHasher, Hash, Hasher};
use std::path::{Path, PathBuf};

use embedded_graphics::mono_font::MonoTextStyle;
use embedded_graphics::mono_font::ascii::FONT_6X10;
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::{DrawTarget, OriginDimensions, Point, RgbColor, Size};
use embedded_graphics::text::{Baseline, Text};
use embedded_graphics::{Drawable, Pixel};

use crate::error::ReportError;

/// An RGB8 colour.
pub type Rgb = [u8; 3];

/// Colour of pixels outside the scored (subsurface) mask in error images.
pub const UNSCORED: Rgb = [0, 0, 96];

/// Luminance error shown as white in error images.
pub const ERROR_FULL: f32 = 0.05;

/// Images are enlarged by an integer factor to at least this width.
pub const MIN_WIDTH: u32 = 256;

/// Line height of the caption font, pixels (the font's 10 plus spacing).
const LINE: u32 = 12;

/// An RGB8 image that `embedded-graphics` draws into.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    width: u32,
    height: u32,
    px: Vec<u8>,
}

impl Image {
    /// A `width` x `height` image filled with `fill`.
    #[must_use]
    pub fn new(width: u32, height: u32, fill: Rgb) -> Self {
        Self {
            width,
            height,
            px: fill.repeat(width as usize * height as usize),
        }
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pixel at (x, y), if inside.
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> Option<Rgb> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 3 * (y as usize * self.width as usize + x as usize);
        self.px.get(i..i + 3).and_then(|s| s.try_into().ok())
    }

    fn set(&mut self, x: u32, y: u32, c: Rgb) {
        if x < self.width && y < self.height {
            let i = 3 * (y as usize * self.width as usize + x as usize);
            if let Some(p) = self.px.get_mut(i..i + 3) {
                p.copy_from_slice(&c);
            }
        }
    }

    /// Draws `text` with its top-left corner at (x, y) in the 6 x 10 mono font.
    pub fn text(&mut self, x: u32, y: u32, text: &str, colour: Rgb) {
        let style = MonoTextStyle::new(&FONT_6X10, Rgb888::new(colour[0], colour[1], colour[2]));
        let at = Point::new(x as i32, y as i32);
        // Drawing into memory cannot fail (the error type is `Infallible`).
        let Ok(_) = Text::with_baseline(text, at, style, Baseline::Top).draw(self);
    }

    /// The raw RGB8 bytes, row by row.
    #[must_use]
    pub fn bytes(&self) -> &[u8] {
        &self.px
    }
}

impl OriginDimensions for Image {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl DrawTarget for Image {
    type Color = Rgb888;
    type Error = core::convert::Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Self::Color>>,
    {
        for Pixel(p, c) in pixels {
            if let (Ok(x), Ok(y)) = (u32::try_from(p.x), u32::try_from(p.y)) {
                self.set(x, y, [c.r(), c.g(), c.b()]);
            }
        }
        Ok(())
    }
}

/// The integer enlargement that brings `width` to at least [`MIN_WIDTH`] (at most 8).
#[must_use]
pub fn zoom(width: u32) -> u32 {
    MIN_WIDTH.div_ceil(width.max(1)).clamp(1, 8)
}

/// A colour ramp drawn under an image: colour at each point in [0, 1], its end labels.
pub struct Ramp<'a> {
    /// Colour at `f` in [0, 1] (left to right).
    pub colour: &'a dyn Fn(f64) -> Rgb,
    /// Label at the left end, label at the right end.
    pub ends: [&'a str; 2],
    /// An extra key line: a swatch colour and what it means.
    pub key: Option<(Rgb, &'a str)>,
}

impl std::fmt::Debug for Ramp<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ramp")
            .field("ends", &self.ends)
            .field("key", &self.key)
            .finish_non_exhaustive()
    }
}

/// Composes a captioned image: `rgb8` (`width` x `height`) enlarged by [`zoom`], an
/// optional ramp under it, then the caption lines, white on dark grey.
#[must_use]
pub fn compose(
    width: u32,
    height: u32,
    rgb8: &[u8],
    ramp: Option<&Ramp<'_>>,
    caption: &[&str],
) -> Image {
    let k = zoom(width);
    let w = (width * k).max(MIN_WIDTH);
    let ramp_h = ramp.map_or(0, |r| 8 + LINE + if r.key.is_some() { LINE } else { 0 } + 4);
    let cap_h = LINE * caption.len() as u32 + 6;
    let mut img = Image::new(w, height * k + ramp_h + cap_h, [255, 255, 255]);
    for y in 0..height * k {
        for x in 0..width * k {
            let i = 3 * ((y / k) as usize * width as usize + (x / k) as usize);
            if let Some(p) = rgb8.get(i..i + 3).and_then(|s| <Rgb>::try_from(s).ok()) {
                img.set(x, y, p);
            }
        }
    }
    let mut y = height * k;
    if let Some(r) = ramp {
        let (x0, bar_w) = (4, w - 8);
        for x in 0..bar_w {
            let c = (r.colour)(f64::from(x) / f64::from(bar_w.saturating_sub(1).max(1)));
            for dy in 2..8 {
                img.set(x0 + x, y + dy, c);
            }
        }
        let [lo, hi] = r.ends;
        img.text(x0, y + 9, lo, [0, 0, 0]);
        img.text(
            w.saturating_sub(4 + 6 * hi.len() as u32),
            y + 9,
            hi,
            [0, 0, 0],
        );
        if let Some((swatch, name)) = r.key {
            for dy in 0..9 {
                for dx in 0..9 {
                    img.set(x0 + dx, y + 9 + LINE + dy, swatch);
                }
            }
            img.text(x0 + 12, y + 9 + LINE, name, [0, 0, 0]);
        }
        y += ramp_h;
    }
    for yy in y..img.height {
        for x in 0..w {
            img.set(x, yy, [40, 40, 40]);
        }
    }
    for (i, line) in caption.iter().enumerate() {
        img.text(4, y + 3 + LINE * i as u32, line, [255, 255, 255]);
    }
    img
}

/// Writes `img` as an RGB8 PNG.
///
/// # Errors
///
/// [`ReportError::Io`] naming the file.
pub fn write_png(path: &Path, img: &Image) -> Result<(), ReportError> {
    let io = |e: std::io::Error| ReportError::io(path, e);
    let file = std::io::BufWriter::new(std::fs::File::create(path).map_err(io)?);
    let mut enc = png::Encoder::new(file, img.width, img.height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let png = |e: png::EncodingError| ReportError::io(path, std::io::Error::other(e.to_string()));
    let mut writer = enc.write_header().map_err(png)?;
    writer.write_image_data(&img.px).map_err(png)?;
    writer.finish().map_err(png)
}

/// Writes frame images into one folder, once per distinct content.
#[derive(Debug, Default)]
pub struct ImageWriter {
    dir: PathBuf,
    /// Hash of (kind, size, pixels) -> (file name, pixels) of the first image with them
    /// (`DefaultHasher::new` has fixed keys: the same images give the same links on every
    /// run).
    seen: BTreeMap<u64, Vec<(String, Vec<u8>)>>,
    /// Images not written because an earlier one had the same pixels.
    pub skipped: usize,
}

/// Where an image ended up.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Written {
    /// The file to link (the earlier file when this one was a duplicate).
    pub file: String,
    /// Whether this image duplicated an earlier one (and so was not written).
    pub duplicate: bool,
}

impl ImageWriter {
    /// A writer into `dir`.
    #[must_use]
    pub fn new(dir: &Path) -> Self {
        Self {
            dir: dir.to_path_buf(),
            ..Self::default()
        }
    }

    /// Writes `file` unless an image of the same `kind` with the same pixels (`width` x
    /// `height` RGB8, before captioning) was written before; the caption is drawn by
    /// [`compose`].
    ///
    /// # Errors
    ///
    /// [`ReportError::Io`] naming the file.
    pub fn write(
        &mut self,
        file: &str,
        kind: &str,
        (width, height): (u32, u32),
        rgb8: &[u8],
        ramp: Option<&Ramp<'_>>,
        caption: &[&str],
    ) -> Result<Written, ReportError> {
        let mut h = DefaultHasher::new();
        (kind, width, height, rgb8).hash(&mut h);
        let bucket = self.seen.entry(h.finish()).or_default();
        if let Some((first, _)) = bucket.iter().find(|(_, px)| px == rgb8) {
            self.skipped += 1;
            return Ok(Written {
                file: first.clone(),
                duplicate: true,
            });
        }
        let img = compose(width, height, rgb8, ramp, caption);
        write_png(&self.dir.join(file), &img)?;
        bucket.push((file.to_owned(), rgb8.to_vec()));
        Ok(Written {
            file: file.to_owned(),
            duplicate: false,
        })
    }
}

/// sRGB encoding of a linear value, clamped to [0, 1] (non-finite values black).
#[must_use]
pub fn srgb8(v: f32) -> u8 {
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
#[must_use]
pub fn count_grey(n: u32) -> u8 {
    (u64::from(n) * 255 / 64).min(255) as u8
}

//! A temporal anti-aliasing (TAA) resolve on scalar images, after Karis 2014 ("High
//! quality temporal supersampling"), run after each consumer so that the report measures
//! the image a renderer would show.
//!
//! Per pixel `p` of frame `t`, with motion vector `v` (this frame's position minus the
//! previous frame's, in pixels, the convention of `spvg::reproject`):
//!
//! 1. **Reproject.** The previous resolved image is read at `p + 0.5 - v` (pixel centres
//!    at half-integers) with a Catmull-Rom fetch over the 4x4 texels around that
//!    position, as Karis's resolve does: a bilinear fetch blurs the history a little on
//!    every frame of sub-pixel motion, and the blur accumulates (on the report's rotation
//!    it cost fixed 64 spp more than its noise). At an integer motion the fetch is the
//!    texel itself.
//! 2. **Reject.** A bilinear tap (the 2x2 texels around the position) counts only where
//!    the previous frame covered it (its mask) and its depth agrees with the pixel's
//!    within the relative tolerance of [`spvg::reproject::Reprojection::depth_agrees`]
//!    (2% by default). Where all four count and so do the other twelve texels of the
//!    Catmull-Rom footprint, the Catmull-Rom fetch is taken; otherwise the bilinear
//!    fetch over the taps that count, their weights renormalised. Where none counts (the
//!    position left the frame, or the surface was hidden: disocclusion), the pixel takes
//!    the current value and the history restarts there.
//! 3. **Clamp.** The reprojected history is clamped to the current frame's 3x3
//!    neighbourhood (the covered pixels of it): its min/max range ([`Clamp::MinMax`],
//!    what Karis's YCoCg box reduces to on one channel), or `mean +- gamma sigma`
//!    ([`Clamp::Variance`], Salvi's variance clipping).
//! 4. **Blend.** `out = h + w (c - h)`: an exponential moving average with weight `w` on
//!    the current value ([`WEIGHT`] = 0.1 in the report).
//!
//! A pixel that took no sample this frame (a fractional count's skipped frame,
//! [`TaaFrame::skipped`]) has no value to blend: it keeps its clamped history, and its
//! history stands in for its value in its neighbours' boxes.
//!
//! No sub-pixel jitter is added: the consumers already draw new sample positions every
//! frame, and the report's scenes are rendered at pixel centres.
//!
//! Pixels outside the mask (no surface of the consumer) are passed through and take no
//! part in any neighbourhood. The resolve is the renderer's, not the component's: it
//! reads only what a renderer has (the frame, its motion vectors, depth and coverage).

use spvg::reproject::Reprojection;

use crate::error::ReportError;

/// The blend weight of the current frame in the report's resolve (Karis 2014 uses about
/// 0.1: a history of about ten frames).
pub const WEIGHT: f32 = 0.1;

/// The share of the clamp box `hi - lo` by which the clamp may move the reprojected
/// history before the resolve counts it as discarded ([`Taa::resolve_weights`] 1). The
/// box is the min/max of nine noisy values, so its edges move from frame to frame by a
/// sizeable part of its width on a steady surface, and a steady history a little outside
/// it is the history's own noise trimmed, not a stale value replaced: it still carries
/// its frames. A move past a tenth of the box is a history the neighbourhood no longer
/// contains (a moving object's edge or shadow passed): the blended value then follows
/// the box's edge, a value of this frame, as a rejected history would.
pub const CLAMP_TOLERANCE: f32 = 0.1;

/// The absolute part of the clamp's tolerance, in the value's units: a box of width 0 (a
/// neighbourhood of equal values, e.g. an open plane's AO of 1) would otherwise count a
/// float rounding of the history as a discard. It lies far below a sample's quantum
/// (`1/n` at `n <= 64` spp for ambient occlusion), so every real move counts.
pub const CLAMP_FLOOR: f32 = 1e-3;

/// How the history is limited to the current frame's 3x3 neighbourhood.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Clamp {
    /// Clamp to the neighbourhood's `[min, max]`.
    MinMax,
    /// Clamp to `[mean - gamma sigma, mean + gamma sigma]` of the neighbourhood (the
    /// population standard deviation).
    Variance {
        /// The width of the box in standard deviations (Salvi uses about 1).
        gamma: f32,
    },
}

/// One frame as the resolve reads it: row-major images of the frame's size.
#[derive(Clone, Copy, Debug)]
pub struct TaaFrame<'a> {
    /// The consumer's value (luminance, ambient occlusion).
    pub value: &'a [f32],
    /// Motion vectors in pixels, this frame's position minus the previous frame's.
    pub motion: &'a [[f32; 2]],
    /// Linear depth (positive where there is a surface).
    pub depth: &'a [f32],
    /// Nonzero where the consumer covers the pixel.
    pub mask: &'a [u8],
    /// Where the frame holds no value for a covered pixel (a fractional count's skipped
    /// frame: no sample, docs/algorithms.md §8.6), or `None` where every covered pixel has
    /// one. A skipped pixel keeps its reprojected history, clamped to its neighbourhood,
    /// without a blend, and that history stands in for its value in its neighbours'
    /// boxes; without a history it takes its value as any pixel does.
    pub skipped: Option<&'a [bool]>,
}

/// The previous frame's images a reprojection reads.
#[derive(Clone, Debug, Default)]
struct Previous {
    value: Vec<f32>,
    depth: Vec<f32>,
    mask: Vec<u8>,
}

/// The bilinear taps of a reprojected position: up to four (texel index, weight) pairs,
/// the weights renormalised over the taps that pass the mask and depth tests.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Taps {
    taps: [(usize, f32); 4],
    len: usize,
}

impl Taps {
    /// `sum_k w_k image[i_k]` (the image of the previous frame).
    #[must_use]
    pub fn fetch(&self, image: &[f32]) -> f32 {
        self.taps[..self.len]
            .iter()
            .map(|&(i, w)| w * image.get(i).copied().unwrap_or(0.0))
            .sum()
    }
}

/// The taps of pixel `pixel` moved by `motion` in a `size` frame whose previous frame had
/// depth `prev_depth` and mask `prev_mask`; `None` where no tap passes (disocclusion).
#[must_use]
pub fn reproject_taps(
    pixel: [u32; 2],
    motion: [f32; 2],
    depth: f32,
    size: [u32; 2],
    prev_depth: &[f32],
    prev_mask: &[u8],
    rule: &Reprojection<f32>,
) -> Option<Taps> {
    if !(motion[0].is_finite() && motion[1].is_finite()) {
        return None;
    }
    // Position of the pixel's centre in the previous frame, in texel-centre units.
    let u = [
        pixel[0] as f32 + 0.5 - motion[0] - 0.5,
        pixel[1] as f32 + 0.5 - motion[1] - 0.5,
    ];
    let base = [u[0].floor(), u[1].floor()];
    let f = [u[0] - base[0], u[1] - base[1]];
    let (w, h) = (size[0] as i64, size[1] as i64);
    let mut out = Taps::default();
    let mut total = 0.0_f32;
    for (dy, wy) in [(0_i64, 1.0 - f[1]), (1, f[1])] {
        for (dx, wx) in [(0_i64, 1.0 - f[0]), (1, f[0])] {
            let weight = wx * wy;
            let (x, y) = (base[0] as i64 + dx, base[1] as i64 + dy);
            if weight <= 0.0 || x < 0 || y < 0 || x >= w || y >= h {
                continue;
            }
            let i = (y * w + x) as usize;
            let covered = prev_mask.get(i).is_some_and(|m| *m != 0);
            let d = prev_depth.get(i).copied().unwrap_or(f32::NAN);
            if covered && rule.depth_agrees(d, depth) {
                out.taps[out.len] = (i, weight);
                out.len += 1;
                total += weight;
            }
        }
    }
    if out.len == 0 || total <= 0.0 {
        return None;
    }
    for t in &mut out.taps[..out.len] {
        t.1 /= total;
    }
    Some(out)
}

/// The Catmull-Rom weights of the four texels around a position at fraction `t` past the
/// second (they sum to 1; at `t = 0` they are `[0, 1, 0, 0]`).
fn catmull_rom_weights(t: f32) -> [f32; 4] {
    let t2 = t * t;
    let t3 = t2 * t;
    [
        -0.5 * t + t2 - 0.5 * t3,
        1.0 - 2.5 * t2 + 1.5 * t3,
        0.5 * t + 2.0 * t2 - 1.5 * t3,
        -0.5 * t2 + 0.5 * t3,
    ]
}

/// The Catmull-Rom fetch of the previous `image` for pixel `pixel` moved by `motion`:
/// `None` unless every texel of the 4x4 footprint lies in the frame, was covered and
/// agrees with `depth` under `rule` (the caller then takes the bilinear taps).
fn catmull_rom_fetch(
    pixel: [u32; 2],
    motion: [f32; 2],
    depth: f32,
    size: [u32; 2],
    prev: &Previous,
    rule: &Reprojection<f32>,
) -> Option<f32> {
    let u = [pixel[0] as f32 - motion[0], pixel[1] as f32 - motion[1]];
    let base = [u[0].floor(), u[1].floor()];
    let (wx, wy) = (
        catmull_rom_weights(u[0] - base[0]),
        catmull_rom_weights(u[1] - base[1]),
    );
    let (w, h) = (i64::from(size[0]), i64::from(size[1]));
    let mut sum = 0.0_f32;
    for (j, wyj) in wy.iter().enumerate() {
        for (k, wxk) in wx.iter().enumerate() {
            let (x, y) = (base[0] as i64 + k as i64 - 1, base[1] as i64 + j as i64 - 1);
            if x < 0 || y < 0 || x >= w || y >= h {
                return None;
            }
            let i = (y * w + x) as usize;
            let covered = prev.mask.get(i).is_some_and(|m| *m != 0);
            let d = prev.depth.get(i).copied().unwrap_or(f32::NAN);
            if !(covered && rule.depth_agrees(d, depth)) {
                return None;
            }
            sum += wyj * wxk * prev.value.get(i).copied().unwrap_or(0.0);
        }
    }
    sum.is_finite().then_some(sum)
}

/// The range `[lo, hi]` the history of pixel `(x, y)` is clamped to: the 3x3
/// neighbourhood of `shown` (each pixel's value this frame, or its history where it
/// skipped; NaN where it has neither) over the covered pixels, under `clamp`; `None` where
/// no pixel of it shows a value.
fn neighbourhood(
    shown: &[f32],
    mask: &[u8],
    size: [u32; 2],
    x: usize,
    y: usize,
    clamp: Clamp,
) -> Option<[f32; 2]> {
    let (w, h) = (size[0] as usize, size[1] as usize);
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    let (mut sum, mut sq, mut n) = (0.0_f64, 0.0_f64, 0_u32);
    for ny in y.saturating_sub(1)..(y + 2).min(h) {
        for nx in x.saturating_sub(1)..(x + 2).min(w) {
            let i = ny * w + nx;
            let v = shown[i];
            if mask[i] == 0 || !v.is_finite() {
                continue;
            }
            lo = lo.min(v);
            hi = hi.max(v);
            sum += f64::from(v);
            sq += f64::from(v) * f64::from(v);
            n += 1;
        }
    }
    if n == 0 {
        return None;
    }
    Some(match clamp {
        Clamp::MinMax => [lo, hi],
        Clamp::Variance { gamma } => {
            let mean = sum / f64::from(n);
            let sigma = (sq / f64::from(n) - mean * mean).max(0.0).sqrt();
            let g = f64::from(gamma) * sigma;
            [(mean - g) as f32, (mean + g) as f32]
        }
    })
}

/// The resolve's state: the previous resolved image, depth and coverage.
#[derive(Clone, Debug)]
pub struct Taa {
    size: [u32; 2],
    weight: f32,
    clamp: Clamp,
    rule: Reprojection<f32>,
    previous: Option<Previous>,
    resolved: Vec<f32>,
    history: Vec<bool>,
    /// The last frame's clamped history `C_t` (NaN where it had none).
    clamped: Vec<f32>,
    /// The weight the last resolve gave its frame per pixel ([`Taa::resolve_weights`]).
    weights: Vec<f32>,
}

impl Taa {
    /// A resolve of `width x height` frames blending the current frame with `weight` and
    /// limiting the history by `clamp`; the first frame has no history.
    ///
    /// # Errors
    ///
    /// [`ReportError::Usage`] naming `weight` unless it lies in `(0, 1]`, or `gamma` unless
    /// it is finite and positive.
    pub fn new(width: u32, height: u32, weight: f32, clamp: Clamp) -> Result<Self, ReportError> {
        if !(weight > 0.0 && weight <= 1.0) {
            return Err(ReportError::Usage(format!(
                "TAA weight {weight}: must lie in (0, 1]"
            )));
        }
        if let Clamp::Variance { gamma } = clamp
            && !(gamma.is_finite() && gamma > 0.0)
        {
            return Err(ReportError::Usage(format!(
                "TAA variance clip gamma {gamma}: must be finite and > 0"
            )));
        }
        Ok(Self {
            size: [width, height],
            weight,
            clamp,
            rule: Reprojection::default(),
            previous: None,
            resolved: Vec::new(),
            history: Vec::new(),
            clamped: Vec::new(),
            weights: Vec::new(),
        })
    }

    /// The report's resolve: [`WEIGHT`] and [`Clamp::MinMax`].
    ///
    /// # Errors
    ///
    /// None with these constants (see [`new`](Self::new)).
    pub fn report(width: u32, height: u32) -> Result<Self, ReportError> {
        Self::new(width, height, WEIGHT, Clamp::MinMax)
    }

    /// Resolves `frame` against the history and returns the resolved image; it becomes the
    /// next frame's history. A non-finite current value is stored as 0 (never kept as
    /// history).
    ///
    /// # Errors
    ///
    /// [`ReportError::Usage`] when an image of `frame` does not hold `width x height` values.
    pub fn resolve(&mut self, frame: &TaaFrame<'_>) -> Result<&[f32], ReportError> {
        let n = self.size[0] as usize * self.size[1] as usize;
        for (what, len) in [
            ("value", frame.value.len()),
            ("motion", frame.motion.len()),
            ("depth", frame.depth.len()),
            ("mask", frame.mask.len()),
        ] {
            if len != n {
                return Err(ReportError::Usage(format!(
                    "TAA frame {what}: {len} values for a {}x{} frame",
                    self.size[0], self.size[1]
                )));
            }
        }
        if let Some(skipped) = frame.skipped
            && skipped.len() != n
        {
            return Err(ReportError::Usage(format!(
                "TAA frame skipped: {} values for a {}x{} frame",
                skipped.len(),
                self.size[0],
                self.size[1]
            )));
        }
        let w = self.size[0] as usize;
        let skips = |i: usize| frame.skipped.is_some_and(|s| s[i]);
        // Each covered pixel's reprojected history (Catmull-Rom where its whole footprint
        // passes, else the bilinear taps that do), before the clamp.
        let fetched: Vec<Option<f32>> = (0..n)
            .map(|i| {
                let p = self.previous.as_ref()?;
                if frame.mask[i] == 0 {
                    return None;
                }
                let pixel = [(i % w) as u32, (i / w) as u32];
                let taps = reproject_taps(
                    pixel,
                    frame.motion[i],
                    frame.depth[i],
                    self.size,
                    &p.depth,
                    &p.mask,
                    &self.rule,
                )?;
                // The Catmull-Rom footprint holds the bilinear one: it passes only where
                // every bilinear tap did.
                Some(
                    catmull_rom_fetch(
                        pixel,
                        frame.motion[i],
                        frame.depth[i],
                        self.size,
                        p,
                        &self.rule,
                    )
                    .unwrap_or_else(|| taps.fetch(&p.value)),
                )
            })
            .collect();
        // What each pixel shows its neighbours' boxes: its value, or its history where it
        // skipped the frame.
        let shown: Vec<f32> = (0..n)
            .map(|i| {
                if skips(i) {
                    fetched[i].unwrap_or(f32::NAN)
                } else {
                    frame.value[i]
                }
            })
            .collect();
        let mut out = Vec::with_capacity(n);
        let mut history = Vec::with_capacity(n);
        let mut clamped = Vec::with_capacity(n);
        let mut weights = Vec::with_capacity(n);
        for (i, (&c, &fetch)) in frame.value.iter().zip(&fetched).enumerate() {
            let c = if c.is_finite() { c } else { 0.0 };
            let Some(fetch) = fetch else {
                out.push(c);
                history.push(false);
                clamped.push(f32::NAN);
                weights.push(1.0);
                continue;
            };
            let (x, y) = (i % w, i / w);
            let (h, discarded) =
                match neighbourhood(&shown, frame.mask, self.size, x, y, self.clamp) {
                    Some([lo, hi]) => {
                        let h = fetch.max(lo).min(hi);
                        let box_width = (hi - lo).max(0.0);
                        (
                            h,
                            (h - fetch).abs() > CLAMP_TOLERANCE * box_width + CLAMP_FLOOR,
                        )
                    }
                    None => (fetch, false),
                };
            clamped.push(h);
            // A skipped pixel blends nothing this frame, but the weight is the next
            // frame's question (what the resolve will give its sample): the same test.
            weights.push(if discarded { 1.0 } else { self.weight });
            let v = if skips(i) {
                h
            } else {
                h + self.weight * (c - h)
            };
            out.push(if v.is_finite() { v } else { c });
            history.push(true);
        }
        self.previous = Some(Previous {
            value: out.clone(),
            depth: frame.depth.to_vec(),
            mask: frame.mask.to_vec(),
        });
        self.resolved = out;
        self.history = history;
        self.clamped = clamped;
        self.weights = weights;
        Ok(&self.resolved)
    }

    /// The last resolved frame's history after reprojection, rejection and clamp, before
    /// the blend: `C_t`, the guide of the component's TAA-guided update
    /// (`spvg_wgpu::adaptive::UpdateInputs::guide`, docs/algorithms.md §8.5). NaN where
    /// the pixel had no history (the component then takes the unguided update there).
    #[must_use]
    pub fn clamped_history(&self) -> &[f32] {
        &self.clamped
    }

    /// The weight the last resolve gave its frame per pixel: 1 where it took the current
    /// value (no history: first frame, uncovered, disoccluded, or a non-finite motion) or
    /// where the clamp discarded the history (moved it by more than
    /// [`CLAMP_TOLERANCE`] `(hi - lo)` + [`CLAMP_FLOOR`]), the blend weight otherwise
    /// (a skipped pixel too: it is the weight its next sample will get). Empty before
    /// the first frame. The next frame's estimate takes it as the resolved-image rule's
    /// per-pixel weight (`spvg_wgpu::adaptive::EstimateInputs::resolve_weight`,
    /// docs/algorithms.md §8.7): the estimate runs before this frame's resolve, so the
    /// previous resolve's weight is the one a renderer has.
    #[must_use]
    pub fn resolve_weights(&self) -> &[f32] {
        &self.weights
    }

    /// Whether each pixel of the last resolved frame continued a history (false where it
    /// took the current value: first frame, uncovered, disoccluded).
    #[must_use]
    pub fn had_history(&self) -> &[bool] {
        &self.history
    }
}

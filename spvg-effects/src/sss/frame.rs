//! Per-frame images exchanged with the pass, in the texel formats of the GPU textures.

use half::f16;

/// Inputs of one frame, stored exactly as the GPU textures hold them.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameInputs {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Pre-integrated lighting `B` (rgba16float; alpha unused).
    pub lighting: Vec<[f16; 4]>,
    /// View depth in mm (r32float).
    pub depth: Vec<f32>,
    /// Subsurface mask / profile id (r8uint; 0 = not subsurface).
    pub mask: Vec<u8>,
}

impl FrameInputs {
    /// Number of pixels.
    #[inline]
    #[must_use]
    pub fn len(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Whether the image has no pixels.
    #[inline]
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number of mip levels of the lighting chain down to 1 x 1.
    #[must_use]
    pub fn mip_levels(&self) -> u32 {
        32 - self.width.max(self.height).max(1).leading_zeros()
    }

    /// The lighting mip chain below level 0 (levels 1..), each level the 2 x 2 box average
    /// of the one above (edge texels repeated for odd sizes), averaged in f32 and stored in
    /// f16: the filtered lighting that AFIS reads. Returns `(width, height, texels)` per
    /// level.
    #[must_use]
    pub fn lighting_mips(&self) -> Vec<(u32, u32, Vec<[f16; 4]>)> {
        let mut out: Vec<(u32, u32, Vec<[f16; 4]>)> = Vec::new();
        let (mut w, mut h) = (self.width, self.height);
        for _ in 1..self.mip_levels() {
            let src = out.last().map_or(&self.lighting, |(_, _, v)| v);
            let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
            let at = |x: u32, y: u32| {
                let i = (y.min(h - 1) * w + x.min(w - 1)) as usize;
                src.get(i).copied().unwrap_or([f16::ZERO; 4])
            };
            let mut level = Vec::with_capacity((nw * nh) as usize);
            for y in 0..nh {
                for x in 0..nw {
                    let q = [
                        at(2 * x, 2 * y),
                        at(2 * x + 1, 2 * y),
                        at(2 * x, 2 * y + 1),
                        at(2 * x + 1, 2 * y + 1),
                    ];
                    level.push(core::array::from_fn(|c| {
                        let sum: f32 = q.iter().map(|t| t[c].to_f32()).sum();
                        f16::from_f32(0.25 * sum)
                    }));
                }
            }
            out.push((nw, nh, level));
            (w, h) = (nw, nh);
        }
        out
    }

    /// Whether all three images have `width * height` entries.
    #[must_use]
    pub fn is_consistent(&self) -> bool {
        let n = self.len();
        self.lighting.len() == n && self.depth.len() == n && self.mask.len() == n
    }
}

/// Outputs of one frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameOutput {
    /// Unified result `(1 - gamma) B + gamma L_s` (rgba16float).
    pub result: Vec<[f16; 4]>,
    /// Distant sample count per pixel (r32uint).
    pub count: Vec<u32>,
    /// Pass time in milliseconds (GPU timestamps, or CPU wall time; see [`FrameOutput::timer`]).
    pub time_ms: f64,
    /// How `time_ms` was measured.
    pub timer: Timer,
}

/// The renderer's TAA guide of a guided frame
/// ([`SssPass::run_frame_guided`](crate::sss::SssPass::run_frame_guided),
/// [`SssTwin::run_frame_guided`](crate::sss::SssTwin::run_frame_guided)): called after
/// the sampling with the frame's result texels and its monitored values (the luminance of
/// the distant part `fbar`), it returns the guide `C_t` per pixel in the monitored
/// values' space (docs/algorithms.md §8.5). The result's luminance is the near part's
/// plus the monitored value, so a TAA history `C` of the result's luminance becomes the
/// guide `C - (lum(result) - value)`; NaN where the resolve has no history.
pub type Guide<'a> = dyn FnMut(&[[f16; 4]], &[f32]) -> Vec<f32> + 'a;

/// How a pass time was measured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Timer {
    /// GPU timestamp queries around the compute pass.
    GpuTimestamp,
    /// CPU wall time from submit to `device.poll(wait)` returning.
    #[default]
    WallClock,
}

/// Per-pixel history of one model: the H texels and, for OCV, the J texels.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct History {
    /// `(mu, var / 2^k, nbar, written)` per pixel (`spvg::texel::SpvgTexel16` with the
    /// adaptive component's "written" flag in the spare channel).
    pub h: Vec<[f16; 4]>,
    /// `(Sigma_xy, Sigma_yy, zeta_f, zeta_g)` per pixel (OCV only, else empty).
    pub j: Vec<[f16; 4]>,
}

/// Luminance weights (Rec. 709), WGSL twin `LUMA` in `sss/shaders/estimator.wgsl`.
pub const LUMA: [f32; 3] = [0.2126, 0.7152, 0.0722];

/// Luminance of an RGB triple, same op order as WGSL `dot`.
#[inline]
#[must_use]
pub fn luminance(c: [f32; 3]) -> f32 {
    LUMA[0] * c[0] + LUMA[1] * c[1] + LUMA[2] * c[2]
}

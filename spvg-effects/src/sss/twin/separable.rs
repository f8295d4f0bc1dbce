//! The twins of `sss/shaders/separable.wgsl`: [`sep_horizontal`] and [`sep_vertical`], in
//! the shader's operation order, and [`SeparableTwin`], the two in a row.

use half::f16;

use super::to_texel;
use crate::error::PassError;
use crate::sss::{FrameInputs, FrameOutput, SeparableParams, Timer};

/// The hybrid frame's extra inputs: the technique per pixel (1 = AFIS) and the AFIS
/// result (meaningful where tagged).
#[derive(Clone, Copy, Debug)]
pub struct HybridSources<'a> {
    /// Technique id per pixel: 1 = AFIS, anything else = separable.
    pub technique: &'a [u8],
    /// The Monte Carlo result (rgba16float), read where `technique` is 1.
    pub afis: &'a [[f16; 4]],
}

struct Frame<'a> {
    p: &'a SeparableParams,
    inputs: &'a FrameInputs,
    hybrid: Option<HybridSources<'a>>,
}

impl Frame<'_> {
    fn idx(&self, x: i32, y: i32) -> usize {
        y as usize * self.p.width as usize + x as usize
    }

    fn tagged(&self, x: i32, y: i32) -> bool {
        self.p.hybrid != 0
            && self
                .hybrid
                .is_some_and(|h| h.technique.get(self.idx(x, y)) == Some(&1))
    }

    fn rgb(t: [f16; 4]) -> [f32; 3] {
        [t[0].to_f32(), t[1].to_f32(), t[2].to_f32()]
    }

    /// `sep_source`.
    fn source(&self, x: i32, y: i32) -> [f32; 3] {
        let i = self.idx(x, y);
        match self.hybrid {
            Some(h) if self.tagged(x, y) => h.afis.get(i).map_or([0.0; 3], |&t| Self::rgb(t)),
            _ => Self::rgb(self.inputs.lighting[i]),
        }
    }

    /// `sep_on_surface`.
    fn on_surface(&self, x: i32, y: i32) -> bool {
        x >= 0
            && y >= 0
            && x < self.p.width as i32
            && y < self.p.height as i32
            && self.inputs.mask[self.idx(x, y)] != 0
    }

    /// `sep_filter`: `read` is `sep_texel`'s read of an on-surface texel.
    fn filter(
        &self,
        x: i32,
        y: i32,
        vertical: bool,
        centre: [f32; 3],
        read: impl Fn(i32, i32) -> [f32; 3],
    ) -> [f32; 3] {
        let z = self.inputs.depth[self.idx(x, y)];
        let mm = z * if vertical { self.p.h_px } else { self.p.w_px };
        // NaN, zero or negative depth: the filter has no scale; the centre stands.
        if mm.is_nan() || mm <= 0.0 {
            return centre;
        }
        let inv_mm = 1.0 / mm;
        let texel = |qx: i32, qy: i32| {
            if self.on_surface(qx, qy) {
                read(qx, qy)
            } else {
                centre
            }
        };
        let mut sum = [0.0_f32; 3];
        let n = (self.p.samples as usize).min(self.p.kernel.len());
        for k in &self.p.kernel[..n] {
            let u = if vertical { y as f32 } else { x as f32 } + k[0] * inv_mm;
            let u0 = u.floor();
            let t = u - u0;
            let i0 = u0 as i32;
            let (a, b) = if vertical {
                (texel(x, i0), texel(x, i0 + 1))
            } else {
                (texel(i0, y), texel(i0 + 1, y))
            };
            for c in 0..3 {
                let v = a[c] * (1.0 - t) + b[c] * t;
                sum[c] += k[c + 1] * v;
            }
        }
        sum
    }
}

/// Twin of the entry point `sep_horizontal`: the first pass's output (rgba32float; alpha
/// 0), row-major.
#[must_use]
pub fn sep_horizontal(
    p: &SeparableParams,
    inputs: &FrameInputs,
    hybrid: Option<HybridSources<'_>>,
) -> Vec<[f32; 4]> {
    let f = Frame { p, inputs, hybrid };
    let (w, h) = (p.width as i32, p.height as i32);
    let mut out = Vec::with_capacity(inputs.len());
    for y in 0..h {
        for x in 0..w {
            if inputs.mask[f.idx(x, y)] == 0 {
                out.push([0.0; 4]);
                continue;
            }
            let c = f.source(x, y);
            let v = if f.tagged(x, y) {
                c
            } else {
                f.filter(x, y, false, c, |qx, qy| f.source(qx, qy))
            };
            out.push([v[0], v[1], v[2], 0.0]);
        }
    }
    out
}

/// Twin of the entry point `sep_vertical`: the result (rgba16float), row-major, from the
/// first pass's output `blurred`.
#[must_use]
pub fn sep_vertical(
    p: &SeparableParams,
    inputs: &FrameInputs,
    hybrid: Option<HybridSources<'_>>,
    blurred: &[[f32; 4]],
) -> Vec<[f16; 4]> {
    let f = Frame { p, inputs, hybrid };
    let (w, h) = (p.width as i32, p.height as i32);
    let at = |x: i32, y: i32| {
        let t = blurred[f.idx(x, y)];
        [t[0], t[1], t[2]]
    };
    let mut out = Vec::with_capacity(inputs.len());
    for y in 0..h {
        for x in 0..w {
            if inputs.mask[f.idx(x, y)] == 0 {
                out.push([f16::ZERO; 4]);
                continue;
            }
            let v = if f.tagged(x, y) {
                f.source(x, y)
            } else {
                f.filter(x, y, true, at(x, y), at)
            };
            out.push(to_texel([v[0], v[1], v[2], 1.0]));
        }
    }
    out
}

/// The separable filter on the CPU: the twin of
/// [`SeparablePass`](crate::sss::SeparablePass).
#[derive(Clone, Copy, Debug, Default)]
pub struct SeparableTwin;

impl SeparableTwin {
    /// Runs `sep_horizontal` then `sep_vertical`. The counts are all 0 (no Monte Carlo
    /// samples).
    ///
    /// # Errors
    ///
    /// [`PassError::InputSize`] when the inputs are inconsistent, are not the block's
    /// `width x height`, or (hybrid) the sources are not one per pixel.
    pub fn run_frame(
        &self,
        params: &SeparableParams,
        inputs: &FrameInputs,
        hybrid: Option<HybridSources<'_>>,
    ) -> Result<FrameOutput, PassError> {
        check_sizes(params, inputs, hybrid)?;
        let start = std::time::Instant::now();
        let blurred = sep_horizontal(params, inputs, hybrid);
        let result = sep_vertical(params, inputs, hybrid, &blurred);
        Ok(FrameOutput {
            result,
            count: vec![0; inputs.len()],
            time_ms: start.elapsed().as_secs_f64() * 1e3,
            timer: Timer::WallClock,
        })
    }
}

/// The inputs are one per pixel of the block's frame.
pub(crate) fn check_sizes(
    params: &SeparableParams,
    inputs: &FrameInputs,
    hybrid: Option<HybridSources<'_>>,
) -> Result<(), PassError> {
    let n = params.width as usize * params.height as usize;
    let hybrid_ok = hybrid.is_none_or(|h| h.technique.len() == n && h.afis.len() == n);
    if !inputs.is_consistent() || inputs.len() != n || inputs.width != params.width || !hybrid_ok {
        return Err(PassError::InputSize {
            expected: n,
            got: inputs.lighting.len(),
        });
    }
    Ok(())
}

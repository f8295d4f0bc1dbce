//! The work a focus frame dispatches, in fetched texels: what the hybrid time line judges
//! on an adapter whose timestamps do not time the passes (a software rasterizer, where
//! the frame times are CPU time that moves by more between runs than the bound's slack,
//! or the CPU twin).
//!
//! Each pass's invocations over the pixels it is dispatched on (the whole frame, or the
//! 8x8 tiles of a hybrid frame's lists, which the report rebuilds from the tags by the
//! passes' rule: the tiles holding a tagged pixel for the first step and the composition,
//! those holding an untagged one for the separable passes), each counted with the texels
//! it loads, as the WGSL reads them (`spvg-wgpu/src/sss/shaders/`):
//!
//! - the distant ratio: the depth (1);
//! - the component's estimate and update: the frame-size textures each binds per pixel
//!   (estimate: history, motion, depth, previous depth, this frame's and the last frame's
//!   mask, the distant ratio: 7; update: history, value, control, count, link: 5);
//! - the sampling: the mask; on the surface the lighting, depth and count, and 3 per
//!   Burley sample (the mask, depth and lighting where it lands; the frame's counts are
//!   read back);
//! - a separable pass: the mask; on the surface the pixel's value; in a tile of both kinds
//!   its technique id; where it filters, its depth and the texels its kernel walk loads
//!   (2 each on the surface, the mask and the value; 1 off it; none off the frame), the
//!   walk's span computed from the kernel and the pixel's depth as `sep_filter` does;
//! - the composition (hybrid): the technique id; at a tagged pixel the AFIS result.
//!
//! The model is the report's, not a counter of the passes (they expose none); it is
//! deterministic, so the line does not move between runs.

use crate::wgpu_api::{SeparableParams, TECHNIQUE_AFIS};

/// Texels the component's estimate binds per pixel in the subsurface pass.
pub const ESTIMATE_TEXELS: u64 = 7;
/// Texels the component's update binds per pixel (CCV).
pub const UPDATE_TEXELS: u64 = 5;
/// Texels a Burley sample loads where it lands on the surface.
pub const SAMPLE_TEXELS: u64 = 3;
/// The tile side of the hybrid's lists.
const TILE: usize = 8;
/// The walk's longest span per tap (`SEP_WALK_SPAN_PER_TAP` in `separable.wgsl`).
const WALK_SPAN_PER_TAP: i64 = 2;

/// The frame a focus run renders, as the work model reads it.
#[derive(Debug)]
pub struct Frame<'a> {
    /// Width and height.
    pub size: [u32; 2],
    /// The subsurface mask.
    pub mask: &'a [u8],
    /// The depth (mm).
    pub depth: &'a [f32],
    /// The technique id per pixel (hybrid frames).
    pub technique: &'a [u8],
    /// The separable block (kernel and texel size).
    pub sep: &'a SeparableParams,
}

impl Frame<'_> {
    fn pixels(&self) -> usize {
        self.size[0] as usize * self.size[1] as usize
    }

    fn on(&self, i: usize) -> bool {
        self.mask.get(i).is_some_and(|&m| m != 0)
    }

    fn tagged(&self, i: usize) -> bool {
        self.technique.get(i) == Some(&TECHNIQUE_AFIS)
    }

    /// The texels a separable pass's kernel walk loads at pixel `i` along `vertical`.
    fn kernel_texels(&self, i: usize, vertical: bool) -> u64 {
        let [w, h] = self.size.map(|s| s as i64);
        let (x, y) = ((i % w as usize) as i64, (i / w as usize) as i64);
        let z = self.depth.get(i).copied().unwrap_or(0.0);
        let mm = z * if vertical {
            self.sep.h_px
        } else {
            self.sep.w_px
        };
        // No scale (a depth of 0 or NaN): the filter keeps the centre and loads nothing.
        if mm.is_nan() || mm <= 0.0 {
            return 0;
        }
        let inv_mm = 1.0 / mm;
        let n = (self.sep.samples as usize).min(self.sep.kernel.len());
        let along = if vertical { y } else { x };
        let i0 =
            |k: usize| -> i64 { (along as f32 + self.sep.kernel[k][0] * inv_mm).floor() as i64 };
        // One texel along the axis: its mask and value on the surface, its mask off it,
        // nothing off the frame.
        let texel = |j: i64| -> u64 {
            let (qx, qy) = if vertical { (x, j) } else { (j, y) };
            if qx < 0 || qy < 0 || qx >= w || qy >= h {
                0
            } else if self.on((qy * w + qx) as usize) {
                2
            } else {
                1
            }
        };
        if n == 0 {
            return 0;
        }
        let (first, last) = (i0(0), i0(n - 1));
        if last >= first && last < first + WALK_SPAN_PER_TAP * n as i64 {
            // The walk: from the first tap's first texel to the last tap's second.
            (first..=last + 1).map(texel).sum()
        } else {
            (0..n).map(|k| texel(i0(k)) + texel(i0(k) + 1)).sum()
        }
    }

    /// One separable pass at pixel `i` (`mixed`: its tile holds both kinds).
    fn separable_at(&self, i: usize, vertical: bool, mixed: bool) -> u64 {
        if !self.on(i) {
            return 1;
        }
        // The mask and the centre value, the technique id in a mixed tile.
        let mut t = 2 + u64::from(mixed);
        if mixed && self.tagged(i) {
            return t;
        }
        // The depth, and the walk.
        t += 1 + self.kernel_texels(i, vertical);
        t
    }

    /// The first step's sampling at pixel `i` with `count` samples.
    fn sample_at(&self, i: usize, count: u32) -> u64 {
        if self.on(i) {
            4 + SAMPLE_TEXELS * u64::from(count)
        } else {
            1
        }
    }

    /// The tiles holding a pixel for which `keep` holds, as lists of their pixels.
    fn tiles(&self, keep: impl Fn(usize) -> bool) -> Vec<Vec<usize>> {
        let (w, h) = (self.size[0] as usize, self.size[1] as usize);
        let mut out = Vec::new();
        for ty in 0..h.div_ceil(TILE) {
            for tx in 0..w.div_ceil(TILE) {
                let px: Vec<usize> = (ty * TILE..((ty + 1) * TILE).min(h))
                    .flat_map(|y| (tx * TILE..((tx + 1) * TILE).min(w)).map(move |x| y * w + x))
                    .collect();
                if px.iter().any(|&i| keep(i)) {
                    out.push(px);
                }
            }
        }
        out
    }

    /// Separable-only: both passes over the whole frame.
    #[must_use]
    pub fn separable_only(&self) -> u64 {
        (0..self.pixels())
            .map(|i| self.separable_at(i, false, false) + self.separable_at(i, true, false))
            .sum()
    }

    /// A sampled (CCV-only) frame with `count` samples per pixel: the distant ratio, the
    /// estimate, the sampling and the update over the whole frame.
    #[must_use]
    pub fn sampled(&self, count: &[u32]) -> u64 {
        (0..self.pixels())
            .map(|i| {
                1 + ESTIMATE_TEXELS
                    + self.sample_at(i, count.get(i).copied().unwrap_or(0))
                    + UPDATE_TEXELS
            })
            .sum()
    }

    /// A hybrid frame with `count` samples per pixel (0 off the tags): the first step and
    /// the composition over the tiles holding a tagged pixel, the separable passes over
    /// those holding an untagged one.
    #[must_use]
    pub fn hybrid(&self, count: &[u32]) -> u64 {
        let mut work = 0;
        for tile in self.tiles(|i| self.tagged(i)) {
            for i in tile {
                let n = count.get(i).copied().unwrap_or(0);
                let compose = 1 + u64::from(self.tagged(i));
                work += 1 + ESTIMATE_TEXELS + self.sample_at(i, n) + UPDATE_TEXELS + compose;
            }
        }
        for tile in self.tiles(|i| !self.tagged(i)) {
            let mixed = tile.iter().any(|&i| self.tagged(i));
            for i in tile {
                work += self.separable_at(i, false, mixed) + self.separable_at(i, true, mixed);
            }
        }
        work
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wgpu_api::MAX_SEPARABLE_SAMPLES;

    fn block(samples: u32, offsets: &[f32]) -> SeparableParams {
        let mut kernel = [[0.0; 4]; MAX_SEPARABLE_SAMPLES];
        for (k, o) in kernel.iter_mut().zip(offsets) {
            k[0] = *o;
        }
        SeparableParams {
            width: 16,
            height: 8,
            samples,
            hybrid: 1,
            w_px: 1e-3,
            h_px: 1e-3,
            reserved: [0; 2],
            kernel,
        }
    }

    #[test]
    fn work_by_hand_on_a_small_frame() {
        // 16 x 8, all on the surface at 1 m (1 mm per texel), a 3-tap kernel at -1, 0, +1
        // mm: the walk spans texels x - 1 ..= x + 2.
        let (w, h) = (16_u32, 8_u32);
        let n = (w * h) as usize;
        let mask = vec![1_u8; n];
        let depth = vec![1000.0_f32; n];
        let mut technique = vec![0_u8; n];
        // Tag the left tile's first column.
        for y in 0..8 {
            technique[y * 16] = TECHNIQUE_AFIS;
        }
        let sep = block(3, &[-1.0, 0.0, 1.0]);
        let f = Frame {
            size: [w, h],
            mask: &mask,
            depth: &depth,
            technique: &technique,
            sep: &sep,
        };
        // An interior pixel: walk texels x-1..=x+2, 4 texels at 2 loads.
        assert_eq!(f.kernel_texels(16 + 5, false), 8);
        // At x = 0 the walk's first texel is off the frame.
        assert_eq!(f.kernel_texels(16, false), 6);
        // Separable-only: per pixel and pass mask, centre, depth and the walk.
        let walk: u64 = (0..n)
            .map(|i| f.kernel_texels(i, false) + f.kernel_texels(i, true))
            .sum();
        assert_eq!(f.separable_only(), 2 * 3 * n as u64 + walk);
        // Sampled with 2 samples everywhere: 1 + 7 + (4 + 6) + 5 per pixel.
        assert_eq!(f.sampled(&vec![2; n]), 23 * n as u64);
        // Hybrid: the tagged tile (the left one, 64 pixels) runs the first step and the
        // composition; both tiles hold untagged pixels, the left one mixed.
        let mut count = vec![0_u32; n];
        for y in 0..8 {
            count[y * 16] = 2;
        }
        let first: u64 = (0..8)
            .flat_map(|y| (0..8).map(move |x| y * 16 + x))
            .map(|i| {
                let tagged = i % 16 == 0;
                1 + 7 + if tagged { 4 + 6 } else { 4 } + 5 + if tagged { 2 } else { 1 }
            })
            .sum();
        let separable: u64 = (0..n)
            .map(|i| {
                let mixed = i % 16 < 8;
                let tagged = i % 16 == 0;
                let pass = |vertical| {
                    if tagged {
                        3
                    } else {
                        2 + u64::from(mixed) + 1 + f.kernel_texels(i, vertical)
                    }
                };
                pass(false) + pass(true)
            })
            .sum();
        assert_eq!(f.hybrid(&count), first + separable);
    }
}

//! CPU twin of the entry point of `shaders/reduce.wgsl`: the frame budget governor's
//! demand reduction, one partial sum per 8x8 workgroup in the shader's tree order.

use half::f16;
use spvg::budget::FrameDemand;

use super::math::{Twin, decode_history, from_texel};
use super::pass::pixel_gamma_s;
use crate::frame::FrameInputs;
use crate::reduce::DemandPartial;

/// Side of the reduction's square workgroup (`@workgroup_size(8, 8, 1)`).
pub const REDUCE_TILE: u32 = 8;

/// One invocation's terms: the pixel's demand for the next frame (zero outside the mask
/// or the image) and the count it used this frame.
fn pixel_terms(
    tw: &Twin,
    inputs: &FrameInputs,
    history: &[[f16; 4]],
    count: &[u32],
    x: u32,
    y: u32,
) -> (FrameDemand<f32>, u32) {
    let zero = FrameDemand::default();
    if x >= inputs.width || y >= inputs.height {
        return (zero, 0);
    }
    let i = (y * inputs.width + x) as usize;
    let n = count.get(i).copied().unwrap_or(0);
    if inputs.mask.get(i).copied().unwrap_or(0) == 0 {
        return (zero, n);
    }
    let h = from_texel(history.get(i).copied().unwrap_or([f16::ZERO; 4]));
    let (hist, valid) = decode_history(tw, h);
    let gamma = pixel_gamma_s(tw, inputs, x, y);
    (FrameDemand::pixel(&tw.spvg, &hist, gamma, valid), n)
}

/// CPU twin of the entry point `reduce_demand`: over the history `history` (the H
/// texels the next frame reads) and the counts `count` of the frame just run, the partial
/// sums of each 8x8 workgroup, in dispatch order (row of workgroups by row). Each
/// workgroup sums its 64 invocations as the shader does: at stride 32, 16, .., 1, slot
/// `i < s` adds slot `i + s` (demand with `FrameDemand`'s saturating `+`, counts
/// saturating), so the partials equal the GPU's bit for bit.
#[must_use]
pub fn reduce_demand(
    tw: &Twin,
    inputs: &FrameInputs,
    history: &[[f16; 4]],
    count: &[u32],
) -> Vec<DemandPartial> {
    let (gx, gy) = (
        inputs.width.div_ceil(REDUCE_TILE),
        inputs.height.div_ceil(REDUCE_TILE),
    );
    let lanes = (REDUCE_TILE * REDUCE_TILE) as usize;
    let mut out = Vec::with_capacity(gx as usize * gy as usize);
    let mut demand = vec![FrameDemand::<f32>::default(); lanes];
    let mut counts = vec![0_u32; lanes];
    for by in 0..gy {
        for bx in 0..gx {
            for (li, (d, c)) in demand.iter_mut().zip(counts.iter_mut()).enumerate() {
                let (lx, ly) = (li as u32 % REDUCE_TILE, li as u32 / REDUCE_TILE);
                let (x, y) = (bx * REDUCE_TILE + lx, by * REDUCE_TILE + ly);
                (*d, *c) = pixel_terms(tw, inputs, history, count, x, y);
            }
            let mut s = lanes / 2;
            while s > 0 {
                for i in 0..s {
                    demand[i] = demand[i] + demand[i + s];
                    counts[i] = counts[i].saturating_add(counts[i + s]);
                }
                s /= 2;
            }
            out.push(DemandPartial {
                scaled: demand[0].scaled,
                offset: demand[0].offset,
                fixed: demand[0].fixed,
                count: counts[0],
            });
        }
    }
    out
}

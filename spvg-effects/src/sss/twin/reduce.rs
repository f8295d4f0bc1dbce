//! CPU twin of the entry point of `sss/shaders/reduce.wgsl`: the frame budget governor's
//! demand reduction (the clamped demand curve and the frame's count), one partial per
//! 8x8 workgroup in the shader's tree order.

use half::f16;
use spvg::budget::{CURVE_POINTS, DemandCurve};

use super::BlockTwin;
use super::entry::pixel_gamma_s;
use crate::sss::{DemandPartial, FrameInputs};
use spvg::texel::SpvgTexel16;

/// Side of the reduction's square workgroup (`@workgroup_size(8, 8, 1)`).
pub const REDUCE_TILE: u32 = 8;

/// One invocation's terms: the pixel's counts at the candidate targets for the next frame
/// (zero outside the mask or the image) and the count it used this frame.
fn pixel_terms(
    tw: &BlockTwin,
    targets: &[f32; CURVE_POINTS],
    inputs: &FrameInputs,
    history: &[[f16; 4]],
    count: &[u32],
    x: u32,
    y: u32,
) -> ([u32; CURVE_POINTS], u32) {
    let zero = [0; CURVE_POINTS];
    if x >= inputs.width || y >= inputs.height {
        return (zero, 0);
    }
    let i = (y * inputs.width + x) as usize;
    let n = count.get(i).copied().unwrap_or(0);
    if inputs.mask.get(i).copied().unwrap_or(0) == 0 {
        return (zero, n);
    }
    // The H texel and its written mark (the history's age in the spare channel).
    let h = history.get(i).copied().unwrap_or([f16::ZERO; 4]);
    let (hist, valid) = (tw.enc.decode(SpvgTexel16(h)), h[3].to_f32() >= 0.5);
    let gamma = pixel_gamma_s(tw, inputs, x, y);
    (
        DemandCurve::pixel_counts(&tw.spvg, targets, &hist, gamma, valid),
        n,
    )
}

/// CPU twin of the entry point `reduce_demand`: over the history `history` (the H
/// texels the next frame reads) and the counts `count` of the frame just run, the partial
/// sums of each 8x8 workgroup at the candidate targets `targets`, in dispatch order (row
/// of workgroups by row). Each workgroup sums its 64 invocations as the shader does: at
/// stride 32, 16, .., 1, slot `i < s` adds slot `i + s` (saturating), so the partials
/// equal the GPU's.
#[must_use]
pub fn reduce_demand(
    tw: &BlockTwin,
    targets: &[f32; CURVE_POINTS],
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
    let mut demand = vec![[0_u32; CURVE_POINTS]; lanes];
    let mut counts = vec![0_u32; lanes];
    for by in 0..gy {
        for bx in 0..gx {
            for (li, (d, c)) in demand.iter_mut().zip(counts.iter_mut()).enumerate() {
                let (lx, ly) = (li as u32 % REDUCE_TILE, li as u32 / REDUCE_TILE);
                let (x, y) = (bx * REDUCE_TILE + lx, by * REDUCE_TILE + ly);
                (*d, *c) = pixel_terms(tw, targets, inputs, history, count, x, y);
            }
            let mut s = lanes / 2;
            while s > 0 {
                for i in 0..s {
                    let add = demand[i + s];
                    for (a, b) in demand[i].iter_mut().zip(add) {
                        *a = a.saturating_add(b);
                    }
                    counts[i] = counts[i].saturating_add(counts[i + s]);
                }
                s /= 2;
            }
            out.push(DemandPartial {
                curve: demand[0],
                count: counts[0],
            });
        }
    }
    out
}

//! CPU twins of the entry points of `shaders/sss.wgsl`, one function per entry point, each
//! running all pixels on `std::thread::scope` threads over rows.

use half::f16;

use super::math::{
    burley_distant_ratio, burley_pdf, burley_r_profile, burley_sample_distant, estimate_count,
    from_texel, is_finite_f32, ocv_alpha, pcg3d16, r2_fixed, to_texel, unit_dir, unit_from_fixed,
    update_cv, update_history,
};
use crate::frame::{FrameInputs, History, luminance};
use crate::params::PassParams;

/// WGSL twin: `struct PixelEstimate` in `shared/estimator.wgsl`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelEstimate {
    /// `(1 - gamma) B + gamma L_s` per channel.
    pub result: [f32; 3],
    /// `fbar = gamma L_s`.
    pub fbar: [f32; 3],
    /// `G = gamma B`.
    pub g: [f32; 3],
    /// Distant ratio of the sampling profile.
    pub gamma_s: f32,
}

fn load_rgb(inputs: &FrameInputs, i: usize) -> [f32; 3] {
    let t = inputs.lighting.get(i).copied().unwrap_or([f16::ZERO; 4]);
    [t[0].to_f32(), t[1].to_f32(), t[2].to_f32()]
}

/// WGSL twin: `pixel_gamma_s`.
#[must_use]
pub fn pixel_gamma_s(p: &PassParams, inputs: &FrameInputs, x: u32, y: u32) -> f32 {
    let i = (y * inputs.width + x) as usize;
    let z = inputs.depth.get(i).copied().unwrap_or(0.0);
    burley_distant_ratio(z * p.half_diag, p.d_s)
}

/// WGSL twin: `estimate_pixel`: `n` distant samples at pixel `(x, y)`.
#[must_use]
pub fn estimate_pixel(
    p: &PassParams,
    inputs: &FrameInputs,
    x: u32,
    y: u32,
    n: u32,
) -> PixelEstimate {
    let i = (y * inputs.width + x) as usize;
    let b = load_rgb(inputs, i);
    let z = inputs.depth.get(i).copied().unwrap_or(0.0);
    let r0 = z * p.half_diag;
    let d_rgb = [p.d_r, p.d_g, p.d_b];
    let gamma = d_rgb.map(|d| burley_distant_ratio(r0, d));
    let gamma_s = burley_distant_ratio(r0, p.d_s);
    let s16 = pcg3d16([x, y, p.frame]);
    let seed = [s16[0] << 16, s16[1] << 16];
    let mm_x = z * p.w_px;
    let mm_y = z * p.h_px;
    let mut sum_wl = [0.0_f32; 3];
    let mut sum_w = [0.0_f32; 3];
    for m in 0..n {
        let u = r2_fixed(seed, m);
        let xi_r = unit_from_fixed(u[0]);
        let dir = unit_dir(u[1]);
        let r = burley_sample_distant(xi_r, gamma_s, p.d_s);
        let qx = (x as f32 + 0.5 + r * dir[0] / mm_x).floor();
        let qy = (y as f32 + 0.5 + r * dir[1] / mm_y).floor();
        // `as i64` saturates and maps NaN to 0, like the bounds test on the GPU rejects them.
        let (qx, qy) = (qx as i64, qy as i64);
        if qx < 0 || qy < 0 || qx >= i64::from(p.width) || qy >= i64::from(p.height) {
            continue;
        }
        let j = (qy as usize) * (p.width as usize) + qx as usize;
        if inputs.mask.get(j).copied().unwrap_or(0) == 0 {
            continue;
        }
        let lq = load_rgb(inputs, j);
        if !lq.iter().all(|v| is_finite_f32(*v)) {
            continue;
        }
        let dz = inputs.depth.get(j).copied().unwrap_or(0.0) - z;
        let rp = (r * r + dz * dz).sqrt();
        let inv_pdf = 1.0 / burley_pdf(r, p.d_s);
        for c in 0..3 {
            let w = burley_r_profile(rp, d_rgb[c]) * inv_pdf;
            sum_wl[c] += w * lq[c];
            sum_w[c] += w;
        }
    }
    let mut ls = b;
    for c in 0..3 {
        if sum_w[c] > 0.0 {
            ls[c] = sum_wl[c] / sum_w[c];
        }
    }
    if n == 0 {
        ls = [0.0; 3];
    }
    let fbar: [f32; 3] = core::array::from_fn(|c| gamma[c] * ls[c]);
    PixelEstimate {
        result: core::array::from_fn(|c| (1.0 - gamma[c]) * b[c] + fbar[c]),
        fbar,
        g: core::array::from_fn(|c| gamma[c] * b[c]),
        gamma_s,
    }
}

/// WGSL twin: `distant_count` (zero-sample rule).
#[must_use]
fn distant_count(p: &PassParams, inputs: &FrameInputs, x: u32, y: u32, n: u32) -> u32 {
    if pixel_gamma_s(p, inputs, x, y) < p.eps_u {
        0
    } else {
        n
    }
}

/// One pixel's outputs: result texel, count, new H texel, new J texel.
type PixelOut = ([f16; 4], u32, [f16; 4], [f16; 4]);

fn result_texel(e: &PixelEstimate) -> [f16; 4] {
    to_texel([e.result[0], e.result[1], e.result[2], 1.0])
}

const ZERO: [f16; 4] = [f16::ZERO; 4];

/// The four output images of a pass: result, count, H texels, J texels.
type Images = (Vec<[f16; 4]>, Vec<u32>, Vec<[f16; 4]>, Vec<[f16; 4]>);

/// Runs `pixel` over every pixel on scoped threads, one band of rows per thread.
fn run_rows(inputs: &FrameInputs, pixel: impl Fn(u32, u32) -> PixelOut + Sync) -> Images {
    let (w, h) = (inputs.width as usize, inputs.height as usize);
    let n = w * h;
    let mut result = vec![ZERO; n];
    let mut count = vec![0_u32; n];
    let mut hist = vec![ZERO; n];
    let mut cv = vec![ZERO; n];
    if n == 0 {
        return (result, count, hist, cv);
    }
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let rows_per = h.div_ceil(threads).max(1);
    let chunk = rows_per * w;
    let pixel = &pixel;
    std::thread::scope(|s| {
        let parts = result
            .chunks_mut(chunk)
            .zip(count.chunks_mut(chunk))
            .zip(hist.chunks_mut(chunk).zip(cv.chunks_mut(chunk)));
        for (band, ((res, cnt), (hs, cvs))) in parts.enumerate() {
            s.spawn(move || {
                for (k, (((r, c), hh), jj)) in res
                    .iter_mut()
                    .zip(cnt.iter_mut())
                    .zip(hs.iter_mut())
                    .zip(cvs.iter_mut())
                    .enumerate()
                {
                    let idx = band * chunk + k;
                    let (x, y) = ((idx % w) as u32, (idx / w) as u32);
                    (*r, *c, *hh, *jj) = pixel(x, y);
                }
            });
        }
    });
    (result, count, hist, cv)
}

fn mask_at(inputs: &FrameInputs, x: u32, y: u32) -> u8 {
    inputs
        .mask
        .get((y * inputs.width + x) as usize)
        .copied()
        .unwrap_or(0)
}

fn texel_at(v: &[[f16; 4]], inputs: &FrameInputs, x: u32, y: u32) -> [f32; 4] {
    from_texel(
        v.get((y * inputs.width + x) as usize)
            .copied()
            .unwrap_or(ZERO),
    )
}

/// CPU twin of the entry point `sss_fixed`: returns `(result, count)`.
#[must_use]
pub fn sss_fixed(p: &PassParams, inputs: &FrameInputs) -> (Vec<[f16; 4]>, Vec<u32>) {
    let (result, count, _, _) = run_rows(inputs, |x, y| {
        if mask_at(inputs, x, y) == 0 {
            return (ZERO, 0, ZERO, ZERO);
        }
        let n = distant_count(p, inputs, x, y, p.fixed_count);
        let e = estimate_pixel(p, inputs, x, y, n);
        (result_texel(&e), n, ZERO, ZERO)
    });
    (result, count)
}

/// CPU twin of the entry point `sss_adaptive` (AS with `alpha_const = 0`, CCV with 1):
/// returns `(result, count, new history)`.
#[must_use]
pub fn sss_adaptive(
    p: &PassParams,
    inputs: &FrameInputs,
    hist_in: &History,
) -> (Vec<[f16; 4]>, Vec<u32>, History) {
    let (result, count, h, _) = run_rows(inputs, |x, y| {
        if mask_at(inputs, x, y) == 0 {
            return (ZERO, 0, ZERO, ZERO);
        }
        let h = texel_at(&hist_in.h, inputs, x, y);
        let n = distant_count(p, inputs, x, y, estimate_count(p, h));
        let e = estimate_pixel(p, inputs, x, y, n);
        if n == 0 {
            return (result_texel(&e), 0, ZERO, ZERO);
        }
        let s = luminance(e.fbar) - p.alpha_const * luminance(e.g);
        (
            result_texel(&e),
            n,
            to_texel(update_history(p, h, s, n)),
            ZERO,
        )
    });
    (result, count, History { h, j: Vec::new() })
}

/// CPU twin of the entry point `sss_ocv`: returns `(result, count, new history)`.
#[must_use]
pub fn sss_ocv(
    p: &PassParams,
    inputs: &FrameInputs,
    hist_in: &History,
) -> (Vec<[f16; 4]>, Vec<u32>, History) {
    let (result, count, h, j) = run_rows(inputs, |x, y| {
        if mask_at(inputs, x, y) == 0 {
            return (ZERO, 0, ZERO, ZERO);
        }
        let h = texel_at(&hist_in.h, inputs, x, y);
        let j = texel_at(&hist_in.j, inputs, x, y);
        let n = distant_count(p, inputs, x, y, estimate_count(p, h));
        let e = estimate_pixel(p, inputs, x, y, n);
        if n == 0 {
            return (result_texel(&e), 0, ZERO, ZERO);
        }
        let valid = h[3] >= 0.5;
        let f = luminance(e.fbar);
        let g = luminance(e.g);
        let alpha = ocv_alpha(p, j, valid, f, g);
        let s = f - alpha * g;
        (
            result_texel(&e),
            n,
            to_texel(update_history(p, h, s, n)),
            to_texel(update_cv(p, j, valid, f, g)),
        )
    });
    (result, count, History { h, j })
}

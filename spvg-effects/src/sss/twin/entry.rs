//! CPU twins of the entry points of `sss/shaders/sss.wgsl`, one function per entry point, each
//! running all pixels on `std::thread::scope` threads over rows.

use half::f16;

use spvg::burley::RatioEstimator;

use spvg::sequence::{pcg3d16, r2_offset_from_seed, r2_point, to_unit_f32};

use super::BlockTwin;
use super::to_texel;
use crate::common::unit_dir;
use crate::sss::{FrameInputs, luminance};

/// WGSL twin: `struct PixelEstimate` in `sss/shaders/estimator.wgsl`.
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
pub fn pixel_gamma_s(tw: &BlockTwin, inputs: &FrameInputs, x: u32, y: u32) -> f32 {
    let i = (y * inputs.width + x) as usize;
    let z = inputs.depth.get(i).copied().unwrap_or(0.0);
    let r0 = footprint_radius(z, tw.params.texel_diag);
    tw.sampling.distant_ratio(r0)
}

/// WGSL twin: `footprint_radius` (`spvg::burley::footprint_radius` with the host's
/// `hypot(w_px, h_px)` precomputed, same op order).
#[inline]
#[must_use]
fn footprint_radius(z: f32, texel_diag: f32) -> f32 {
    z.abs() * texel_diag * 0.5
}

/// One level of the lighting mip chain: width, height, texels.
pub type Mip = (u32, u32, Vec<[f16; 4]>);

/// The mip chain below level 0 when `afis` is on (empty otherwise).
fn mips_for(tw: &BlockTwin, inputs: &FrameInputs) -> Vec<Mip> {
    if tw.params.afis != 0 {
        inputs.lighting_mips()
    } else {
        Vec::new()
    }
}

/// WGSL twin: `estimate_pixel`: `n` distant samples at pixel `(x, y)` (`mips`: levels 1..
/// of the lighting for AFIS), built on
/// `BurleyProfile::sample_distant` and one `RatioEstimator` per channel.
#[must_use]
pub fn estimate_pixel(
    tw: &BlockTwin,
    inputs: &FrameInputs,
    mips: &[Mip],
    x: u32,
    y: u32,
    n: u32,
) -> PixelEstimate {
    let p = &tw.params;
    let i = (y * inputs.width + x) as usize;
    let b = load_rgb(inputs, i);
    let z = inputs.depth.get(i).copied().unwrap_or(0.0);
    let r0 = footprint_radius(z, p.texel_diag);
    let gamma = tw.profiles.map(|pr| pr.distant_ratio(r0));
    let gamma_s = tw.sampling.distant_ratio(r0);
    let seed = r2_offset_from_seed(pcg3d16([x, y, p.frame]));
    let mm_x = z * p.w_px;
    let mm_y = z * p.h_px;
    let mut est = tw.profiles.map(|pr| RatioEstimator::new(&pr));
    for m in 0..n {
        let u = r2_point(seed, m);
        let s = tw.sampling.sample_distant(to_unit_f32(u[0]), r0);
        let dir = unit_dir(u[1]);
        let qx = (x as f32 + 0.5 + s.radius * dir[0] / mm_x).floor();
        let qy = (y as f32 + 0.5 + s.radius * dir[1] / mm_y).floor();
        // `as i64` saturates and maps NaN to 0, like the bounds test on the GPU rejects them.
        let (qx, qy) = (qx as i64, qy as i64);
        if qx < 0 || qy < 0 || qx >= i64::from(p.width) || qy >= i64::from(p.height) {
            continue;
        }
        let j = (qy as usize) * (p.width as usize) + qx as usize;
        if inputs.mask.get(j).copied().unwrap_or(0) == 0 {
            continue;
        }
        let dz = inputs.depth.get(j).copied().unwrap_or(0.0) - z;
        let lq = if p.afis != 0 {
            let zq = z + dz;
            let area = (zq * p.w_px) * (zq * p.h_px);
            let li = filtered_mip_index(s.pdf, n, p.lmax, area, p.max_mip);
            match li.checked_sub(1).and_then(|k| mips.get(k as usize)) {
                Some((mw, mh, texels)) => {
                    // Clamped to the level's size, as the WGSL.
                    let mx = ((qx as u32) >> li).min(mw.saturating_sub(1));
                    let my = ((qy as u32) >> li).min(mh.saturating_sub(1));
                    let t = texels
                        .get((my * mw + mx) as usize)
                        .copied()
                        .unwrap_or([f16::ZERO; 4]);
                    [t[0].to_f32(), t[1].to_f32(), t[2].to_f32()]
                }
                None => load_rgb(inputs, j),
            }
        } else {
            load_rgb(inputs, j)
        };
        for (e, l) in est.iter_mut().zip(lq) {
            let _ = e.add(s.radius, dz, true, s.pdf, l);
        }
    }
    let mut ls = b;
    for (c, e) in est.iter().enumerate() {
        if let Some(m) = e.mean_lighting() {
            ls[c] = m;
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

/// WGSL twin: `filtered_mip_index`: `floor` of `spvg::burley::filtered_mip_level` (same
/// `q`), found by exact comparisons with powers of two instead of `log2`, clamped to
/// `max_mip`; NaN gives 0, `q <= 0` the coarsest level.
#[must_use]
pub fn filtered_mip_index(pdf: f32, n: u32, lmax: f32, area: f32, max_mip: u32) -> u32 {
    let q = pdf * n as f32 / (16.0 * lmax * lmax * area);
    if q.is_nan() {
        return 0;
    }
    let mut k = 0_u32;
    while k < max_mip && k < 62 && q <= f32::from_bits((125 - 2 * k) << 23) {
        k += 1;
    }
    k
}

/// WGSL twin: the zero-sample rule of `sss_fixed`.
#[must_use]
fn distant_count(tw: &BlockTwin, inputs: &FrameInputs, x: u32, y: u32, n: u32) -> u32 {
    if tw.spvg.samples_distant(pixel_gamma_s(tw, inputs, x, y)) {
        n
    } else {
        0
    }
}

fn result_texel(e: &PixelEstimate) -> [f16; 4] {
    to_texel([e.result[0], e.result[1], e.result[2], 1.0])
}

const ZERO: [f16; 4] = [f16::ZERO; 4];

/// Runs `pixel` over every pixel on scoped threads, one band of rows per thread, and
/// returns its outputs in row-major order.
fn run_rows<T: Copy + Default + Send>(
    inputs: &FrameInputs,
    pixel: impl Fn(u32, u32) -> T + Sync,
) -> Vec<T> {
    let (w, h) = (inputs.width as usize, inputs.height as usize);
    let mut out = vec![T::default(); w * h];
    if out.is_empty() {
        return out;
    }
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let chunk = h.div_ceil(threads).max(1) * w;
    let pixel = &pixel;
    std::thread::scope(|s| {
        for (band, part) in out.chunks_mut(chunk).enumerate() {
            s.spawn(move || {
                for (k, o) in part.iter_mut().enumerate() {
                    let idx = band * chunk + k;
                    *o = pixel((idx % w) as u32, (idx / w) as u32);
                }
            });
        }
    });
    out
}

fn mask_at(inputs: &FrameInputs, x: u32, y: u32) -> u8 {
    inputs
        .mask
        .get((y * inputs.width + x) as usize)
        .copied()
        .unwrap_or(0)
}

/// CPU twin of the entry point `sss_fixed`: returns `(result, count)`.
#[must_use]
pub fn sss_fixed(tw: &BlockTwin, inputs: &FrameInputs) -> (Vec<[f16; 4]>, Vec<u32>) {
    let mips = mips_for(tw, inputs);
    run_rows(inputs, |x, y| {
        if mask_at(inputs, x, y) == 0 {
            return (ZERO, 0);
        }
        let n = distant_count(tw, inputs, x, y, tw.params.fixed_count);
        (result_texel(&estimate_pixel(tw, inputs, &mips, x, y, n)), n)
    })
    .into_iter()
    .unzip()
}

/// CPU twin of the entry point `sss_gamma`: the distant-energy ratio of the sampling
/// profile per pixel, the `gamma` input of the adaptive component's estimate.
#[must_use]
pub fn sss_gamma(tw: &BlockTwin, inputs: &FrameInputs) -> Vec<f32> {
    run_rows(inputs, |x, y| pixel_gamma_s(tw, inputs, x, y))
}

/// The outputs of [`sss_sample`], one value per pixel.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SampleOutput {
    /// The result texels.
    pub result: Vec<[f16; 4]>,
    /// The monitored luminance `fbar` (the component's update `value`; 0 outside the mask).
    pub value: Vec<f32>,
    /// The control luminance `G` (the update's `control`; 0 outside the mask).
    pub control: Vec<f32>,
}

/// CPU twin of the entry point `sss_sample`: `count[i]` distant samples at each
/// subsurface pixel (the counts of the adaptive component's estimate).
#[must_use]
pub fn sss_sample(tw: &BlockTwin, inputs: &FrameInputs, count: &[u32]) -> SampleOutput {
    let mips = mips_for(tw, inputs);
    let px = run_rows(inputs, |x, y| {
        if mask_at(inputs, x, y) == 0 {
            return (ZERO, 0.0, 0.0);
        }
        let n = count
            .get((y * inputs.width + x) as usize)
            .copied()
            .unwrap_or(0);
        let e = estimate_pixel(tw, inputs, &mips, x, y, n);
        (result_texel(&e), luminance(e.fbar), luminance(e.g))
    });
    let mut out = SampleOutput::default();
    for (r, v, c) in px {
        out.result.push(r);
        out.value.push(v);
        out.control.push(c);
    }
    out
}

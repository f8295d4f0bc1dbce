//! CPU twins of the WGSL helper functions in `shaders/shared/`, same names and op order.
//!
//! The streaming updates call the core crate's estimators (`spvg::stats`), which the WGSL
//! mirrors operation by operation.

use half::f16;
use spvg::stats::{Ema, Emc, Emv, Weight};

use crate::params::PassParams;

/// WGSL twin: `pcg3d16` in `shared/pcg.wgsl`.
#[inline]
#[must_use]
pub fn pcg3d16(p: [u32; 3]) -> [u32; 3] {
    let mut v = p.map(|x| x.wrapping_mul(12829).wrapping_add(47989));
    for _ in 0..2 {
        v[0] = v[0].wrapping_add(v[1].wrapping_mul(v[2]));
        v[1] = v[1].wrapping_add(v[2].wrapping_mul(v[0]));
        v[2] = v[2].wrapping_add(v[0].wrapping_mul(v[1]));
    }
    v.map(|x| x >> 16)
}

/// R2 steps `round(2^32 / phi2^k)`, WGSL twin `R2_STEP` in `shared/r2.wgsl`.
pub const R2_STEP: [u32; 2] = [3_242_174_889, 2_447_445_414];

/// WGSL twin: `r2_fixed`.
#[inline]
#[must_use]
pub fn r2_fixed(seed: [u32; 2], m: u32) -> [u32; 2] {
    [
        seed[0].wrapping_add(m.wrapping_mul(R2_STEP[0])),
        seed[1].wrapping_add(m.wrapping_mul(R2_STEP[1])),
    ]
}

/// WGSL twin: `unit_from_fixed`: top 24 bits as a float in `[0, 1)`.
#[inline]
#[must_use]
pub fn unit_from_fixed(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// WGSL twin: `unit_dir`: unit vector at angle `2 pi x / 2^32` by quadrant and Taylor
/// polynomials (same op order as the WGSL; the built-in sin/cos differ between drivers).
#[inline]
#[must_use]
pub fn unit_dir(x: u32) -> [f32; 2] {
    let t = ((x >> 6) & 0x00ff_ffff) as f32 * (1.0 / 16_777_216.0) * core::f32::consts::FRAC_PI_2;
    let t2 = t * t;
    let s = t
        * (1.0
            + t2 * (-1.0 / 6.0
                + t2 * (1.0 / 120.0
                    + t2 * (-1.0 / 5040.0 + t2 * (1.0 / 362_880.0 + t2 * (-1.0 / 39_916_800.0))))));
    let c = 1.0
        + t2 * (-0.5
            + t2 * (1.0 / 24.0
                + t2 * (-1.0 / 720.0
                    + t2 * (1.0 / 40320.0
                        + t2 * (-1.0 / 3_628_800.0 + t2 * (1.0 / 479_001_600.0))))));
    match x >> 30 {
        0 => [c, s],
        1 => [-s, c],
        2 => [-c, -s],
        _ => [s, -c],
    }
}

/// WGSL twin: `burley_distant_ratio`.
#[inline]
#[must_use]
pub fn burley_distant_ratio(r0: f32, d: f32) -> f32 {
    0.25 * (-r0 / d).exp() + 0.75 * (-r0 / (3.0 * d)).exp()
}

/// WGSL twin: `burley_pdf`.
#[inline]
#[must_use]
pub fn burley_pdf(r: f32, d: f32) -> f32 {
    ((-r / d).exp() + (-r / (3.0 * d)).exp()) / (4.0 * d)
}

/// WGSL twin: `burley_r_profile` (`r R(r) / A`).
#[inline]
#[must_use]
pub fn burley_r_profile(r: f32, d: f32) -> f32 {
    ((-r / d).exp() + (-r / (3.0 * d)).exp()) / (8.0 * core::f32::consts::PI * d)
}

/// WGSL twin: `burley_inverse_ccdf` (Golubev's exact inverse in `uc = 1 - cdf`).
#[inline]
#[must_use]
pub fn burley_inverse_ccdf(uc: f32, d: f32) -> f32 {
    let g = 1.0 + 4.0 * uc * (2.0 * uc + (1.0 + 4.0 * uc * uc).sqrt());
    let c = g.powf(1.0 / 3.0);
    3.0 * d * ((1.0 + 1.0 / c + c) / (4.0 * uc)).ln()
}

/// WGSL twin: `burley_sample_distant`.
#[inline]
#[must_use]
pub fn burley_sample_distant(xi: f32, gamma: f32, d: f32) -> f32 {
    burley_inverse_ccdf((1.0 - xi) * gamma, d)
}

/// WGSL twin: `is_finite_f32` (bit test).
#[inline]
#[must_use]
pub fn is_finite_f32(x: f32) -> bool {
    x.is_finite()
}

/// Largest finite f16.
pub const F16_MAX: f32 = 65504.0;

/// WGSL twin: `sanitize_texel`: clamp to the f16 range so the store stays finite.
#[inline]
#[must_use]
pub fn sanitize_texel(t: [f32; 4]) -> [f32; 4] {
    t.map(|x| x.clamp(-F16_MAX, F16_MAX))
}

/// WGSL twin: `round_to_f16(clamp(x, -F16_MAX, F16_MAX))`: the nearest f16 (ties to
/// even) as f32; NaN stays NaN.
#[inline]
#[must_use]
pub fn round_to_f16(x: f32) -> f32 {
    f16::from_f32(x.clamp(-F16_MAX, F16_MAX)).to_f32()
}

/// Stores an f32 texel as rgba16float does (round to nearest even).
#[inline]
#[must_use]
pub fn to_texel(t: [f32; 4]) -> [f16; 4] {
    t.map(f16::from_f32)
}

/// Reads an rgba16float texel.
#[inline]
#[must_use]
pub fn from_texel(t: [f16; 4]) -> [f32; 4] {
    t.map(f16::to_f32)
}

fn ceil_count(x: f32) -> u32 {
    // In range [beta_min, beta_max] by construction; `as` saturates anyway.
    x.ceil() as u32
}

/// WGSL twin: `estimate_count` in `shared/controller.wgsl`.
#[inline]
#[must_use]
pub fn estimate_count(p: &PassParams, h: [f32; 4]) -> u32 {
    if h[3] < 0.5 {
        return ceil_count(p.beta_min);
    }
    let e = h[1] * h[2];
    let delta = ((h[1] - 1.0) * h[2]) * p.k_minus_1;
    let n_hat = p.kappa * delta + e;
    if !is_finite_f32(n_hat) {
        return ceil_count(p.beta_min);
    }
    ceil_count(n_hat.max(p.beta_min).min(p.beta_max))
}

/// WGSL twin: `update_history`, built on `spvg::stats::{Emv, Ema}`.
#[must_use]
pub fn update_history(p: &PassParams, h: [f32; 4], s: f32, n: u32) -> [f32; 4] {
    if !is_finite_f32(s) {
        return if h[3] < 0.5 { [0.0; 4] } else { h };
    }
    if h[3] < 0.5 {
        return sanitize_texel([s, 1.0, n as f32, 1.0]);
    }
    let Ok(w) = Weight::new(p.eta) else {
        return h;
    };
    let mut emv = Emv::from_parts(h[0], h[1] * p.sigma0_sq);
    let mut nbar = Ema::from_mean(h[2]);
    let _ = emv.update(&w, s);
    let _ = nbar.update(&w, n as f32);
    sanitize_texel([emv.mean(), emv.variance() / p.sigma0_sq, nbar.mean(), 1.0])
}

/// WGSL twin: `ocv_alpha` in `shared/cv.wgsl`.
#[inline]
#[must_use]
pub fn ocv_alpha(p: &PassParams, j: [f32; 4], valid: bool, f: f32, g: f32) -> f32 {
    let mut alpha = 1.0;
    if valid {
        alpha = (j[0] + p.eps_a) / (j[1] + p.eps_a);
    }
    if g > 0.0 {
        alpha = alpha.min(p.a0 + f / g);
    }
    alpha.max(0.0)
}

/// WGSL twin: `update_cv`, built on `spvg::stats::{Emc, Emv}` (the EMCM entries of
/// `Z = [f, g]` that the coefficient needs).
#[must_use]
pub fn update_cv(p: &PassParams, j: [f32; 4], valid: bool, f_in: f32, g_in: f32) -> [f32; 4] {
    // Storage precision, as the WGSL (see there for why).
    let f = round_to_f16(f_in);
    let g = round_to_f16(g_in);
    if !(is_finite_f32(f_in) && is_finite_f32(g_in)) {
        return if valid { j } else { [0.0; 4] };
    }
    if !valid {
        return sanitize_texel([0.0, 0.0, f, g]);
    }
    let Ok(w) = Weight::new(p.eta_cv) else {
        return j;
    };
    let mut fg = Emc::from_parts(j[2], j[3], j[0]);
    let mut gg = Emv::from_parts(j[3], j[1]);
    let _ = fg.update(&w, f, g);
    let _ = gg.update(&w, g);
    sanitize_texel([fg.covariance(), gg.variance(), fg.mean_x(), fg.mean_y()])
}

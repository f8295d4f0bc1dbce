// spvg::estimate: the sample count before sampling (docs/algorithms.md §2.1, §2.3, §2.4).
// Depends on: float, params, texel.
// Rust twins: `spvg::SpvgConfig::{samples_distant, raw_estimate, round_count, estimate,
// estimate_with_validity, real_count, real_count_at, estimate_fractional,
// estimate_resolved}` and `spvg::controller::fractional::{fractional_raw_count,
// resolved_factor, resolve_weight, clamp_real, realise_count}`, the same single-precision
// operation order.

// u32 -> f32 rounded to nearest, ties to even (Rust `as f32`, num_traits `T::from`):
// WGSL leaves the rounding of inexact integer conversions to the implementation.
fn spvg_u32_to_f32(n: u32) -> f32 {
    if (n <= 0x1000000u) {
        return f32(n);
    }
    // 2^24 < n: 1 to 8 bits do not fit in the 24-bit significand.
    let shift = 8u - countLeadingZeros(n);
    let half_unit = 1u << (shift - 1u);
    let rem = n & ((1u << shift) - 1u);
    var mant = n >> shift;
    if (rem > half_unit || (rem == half_unit && (mant & 1u) == 1u)) {
        mant += 1u;
    }
    // mant <= 2^24 and 2^shift are exact, so is their product.
    return f32(mant) * bitcast<f32>((127u + shift) << 23u);
}

// SpvgConfig::samples_distant: gamma >= eps_u && gamma > 0 (NaN takes no samples).
fn spvg_samples_distant(p: spvg_Params, gamma: f32) -> bool {
    return gamma >= p.eps_u && gamma > 0.0;
}

// The history as the estimate reads it, clamped exactly as a texel decode does: NaN to
// 0, variance and mean count not > 0 to 0, +-inf to +-f32::MAX.
fn spvg_read_history(h: spvg_History) -> spvg_History {
    return spvg_History(
        spvg_store_signed(h.mean, spvg_F32_MAX),
        spvg_store_non_negative(h.variance, spvg_F32_MAX),
        spvg_store_non_negative(h.mean_count, spvg_F32_MAX),
    );
}

// SpvgConfig::raw_estimate (n_hat before the clamp) on the history read as a texel
// decode reads it, sat = spvg_saturate, docs/algorithms.md §2.1:
//   r     = sat(variance / target)   (exactly 1 where variance == target)
//   t     = sat(kappa * sat((r - 1) * k_minus_one) + r)   (n_hat per unit of nbar)
//   damped: t = t below cap_down -> cap_down, above cap_up -> cap_up (NaN passes)
//   Spvg: sat(t * mean_count); TwoPhase: sat(r * mean_count); UnrealClamp: r;
//   Fixed(n): n.
// The select keeps r = 1 at the target on devices whose division is not correctly
// rounded (Vulkan allows 2.5 ulp); where it is (lavapipe) it changes nothing.
fn spvg_raw_estimate(p: spvg_Params, history: spvg_History) -> f32 {
    let h = spvg_read_history(history);
    let r = spvg_saturate(select(h.variance / p.target_variance, 1.0, h.variance == p.target_variance));
    switch (p.policy) {
        case 1u: { // spvg_POLICY_TWO_PHASE
            return spvg_saturate(r * h.mean_count);
        }
        case 2u: { // spvg_POLICY_UNREAL_CLAMP
            return r;
        }
        case 3u: { // spvg_POLICY_FIXED
            return spvg_u32_to_f32(p.fixed_count);
        }
        default: {
            var t = spvg_saturate(p.kappa * spvg_saturate((r - 1.0) * p.k_minus_one) + r);
            if (p.damped != 0u) {
                if (t < p.cap_down) {
                    t = p.cap_down;
                } else if (t > p.cap_up) {
                    t = p.cap_up;
                }
            }
            return spvg_saturate(t * h.mean_count);
        }
    }
}

// SpvgConfig::round_count: ceil(clamp(n_hat, min, max)), NaN giving min, +inf max; the
// comparisons are written out because WGSL leaves clamp's NaN behaviour open.
fn spvg_round_count(p: spvg_Params, n_hat: f32) -> u32 {
    if (n_hat >= p.min_samples_f) {
        if (n_hat < p.max_samples_f) {
            return clamp(u32(ceil(n_hat)), p.min_samples, p.max_samples);
        }
        return p.max_samples;
    }
    return p.min_samples;
}

// SpvgConfig::estimate: the count for a valid history (0 under the zero-sample rule).
fn spvg_estimate(p: spvg_Params, history: spvg_History, gamma: f32) -> u32 {
    if (!spvg_samples_distant(p, gamma)) {
        return 0u;
    }
    if (p.policy == spvg_POLICY_FIXED) {
        return p.fixed_count;
    }
    return spvg_round_count(p, spvg_raw_estimate(p, history));
}

// SpvgConfig::estimate_with_validity: an invalid history (disocclusion) counts as zero.
fn spvg_estimate_count(p: spvg_Params, history: spvg_History, gamma: f32, valid: bool) -> u32 {
    if (valid) {
        return spvg_estimate(p, history, gamma);
    }
    return spvg_estimate(p, spvg_History(0.0, 0.0, 0.0), gamma);
}

// The count from a history texel as a store with reprojection keeps it: the texel
// decoded (spvg_decode_history), valid where it carries the written mark
// (spvg_history_written), then spvg_estimate_count. A texel of zeros is the disocclusion.
fn spvg_estimate_texel(p: spvg_Params, t: vec4<f32>, gamma: f32) -> u32 {
    return spvg_estimate_count(p, spvg_decode_history(p, t), gamma, spvg_history_written(t));
}

// ---- fractional counts (spvg::controller::fractional, docs/algorithms.md §8.6) ----

// A pixel's count for one frame: the samples it takes and the real count they realise,
// -1 where the integer rule decided (spvg::controller::fractional::FrameCount, whose
// `real` is None there).
struct spvg_FrameCount {
    count: u32,
    real: f32,
}

// fractional_raw_count on the history read as a texel decode reads it, with the
// resolve's weight a at the pixel (spvg_resolve_weight; 1 where the resolved-image rule
// is off):
//   m = nbar > 1 ? nbar : 1   (the count of a sampled frame)
//   r = sat(variance / target)
//   Spvg, TwoPhase: c = sat(r * m); UnrealClamp: c = r; Fixed(n): return n
//   a < 1 ? sat(c * spvg_resolved_factor(a)) : c
fn spvg_fractional_raw_count(p: spvg_Params, history: spvg_History, a: f32) -> f32 {
    let h = spvg_read_history(history);
    var m = 1.0;
    if (h.mean_count > 1.0) {
        m = h.mean_count;
    }
    let r = spvg_saturate(select(h.variance / p.target_variance, 1.0, h.variance == p.target_variance));
    var c = r;
    switch (p.policy) {
        case 2u: { // spvg_POLICY_UNREAL_CLAMP
            c = r;
        }
        case 3u: { // spvg_POLICY_FIXED
            return spvg_u32_to_f32(p.fixed_count);
        }
        default: {
            c = spvg_saturate(r * m);
        }
    }
    if (a < 1.0) {
        return spvg_saturate(c * spvg_resolved_factor(a));
    }
    return c;
}

// fractional::resolved_factor: a / (2 - a), the share of one frame's variance a resolve of
// weight a keeps in steady state.
fn spvg_resolved_factor(a: f32) -> f32 {
    return a / (2.0 - a);
}

// fractional::resolve_weight: the weight the resolve gives this frame at a pixel whose
// history is `age` frames old; `input` is the renderer's own weight where it has one
// (anything not in (0, f32::MAX] means none, -1 by convention). 1 when the rule is off.
fn spvg_resolve_weight(p: spvg_Params, age: u32, input: f32) -> f32 {
    let alpha = p.resolve_weight;
    if (!(alpha > 0.0)) {
        return 1.0;
    }
    if (input > 0.0 && input <= spvg_F32_MAX) {
        return select(1.0, input, input < 1.0);
    }
    let young = 1.0 / (f32(clamp(age, 1u, spvg_AGE_CAP)) + 1.0);
    return select(alpha, young, young > alpha);
}

// clamp_real: raw clamped to [floor_f, max_samples_f], NaN giving the floor and +inf the
// maximum (comparisons written out: WGSL leaves clamp's NaN behaviour open).
fn spvg_clamp_real(p: spvg_Params, raw: f32) -> f32 {
    if (raw >= p.floor_f) {
        if (raw < p.max_samples_f) {
            return raw;
        }
        return p.max_samples_f;
    }
    return p.floor_f;
}

// fractional::real_count (SpvgConfig::real_count_at with a = spvg_resolve_weight(p, age,
// input)): the real count of a valid history with the resolve's weight a.
fn spvg_real_count(p: spvg_Params, history: spvg_History, a: f32) -> f32 {
    return spvg_clamp_real(p, spvg_fractional_raw_count(p, history, a));
}

// realise_count: floor(c) + [xi < frac(c)], every step exact; 0 for c not above 0 (NaN
// included), u32::MAX at or above 2^32.
fn spvg_realise_count(c: f32, xi: u32) -> u32 {
    if (c > 0.0) {
        if (c < 4294967296.0) {
            let whole = u32(c);
            let frac = c - spvg_u32_to_f32(whole);
            return whole + select(0u, 1u, spvg_to_unit_f32(xi) < frac);
        }
        return 0xffffffffu;
    }
    return 0u;
}

// SpvgConfig::estimate_resolved: with fractional counts on, a valid history and gamma
// passing the zero-sample rule, the real count (with the resolve's weight of a history
// `age` frames old and the renderer's weight `input`, -1 for none) realised with the
// threshold xi (spvg_dither_threshold); Fixed(n) gives n, real n. Elsewhere
// spvg_estimate_count with real -1.
fn spvg_estimate_resolved(p: spvg_Params, history: spvg_History, age: u32, gamma: f32, valid: bool, xi: u32, input: f32) -> spvg_FrameCount {
    if (p.fractional == 0u || !valid || !spvg_samples_distant(p, gamma)) {
        return spvg_FrameCount(spvg_estimate_count(p, history, gamma, valid), -1.0);
    }
    if (p.policy == spvg_POLICY_FIXED) {
        return spvg_FrameCount(p.fixed_count, spvg_u32_to_f32(p.fixed_count));
    }
    let c = spvg_real_count(p, history, spvg_resolve_weight(p, age, input));
    return spvg_FrameCount(spvg_realise_count(c, xi), c);
}

// SpvgConfig::estimate_fractional: spvg_estimate_resolved of a settled history (age at the
// cap) without the renderer's weight.
fn spvg_estimate_fractional(p: spvg_Params, history: spvg_History, gamma: f32, valid: bool, xi: u32) -> spvg_FrameCount {
    return spvg_estimate_resolved(p, history, spvg_AGE_CAP, gamma, valid, xi, -1.0);
}

// spvg_estimate_resolved on a history texel as spvg_estimate_texel reads it, its age
// read from the spare channel (spvg_read_age), with the renderer's weight `input` (-1 for
// none).
fn spvg_estimate_texel_resolved(p: spvg_Params, t: vec4<f32>, gamma: f32, xi: u32, input: f32) -> spvg_FrameCount {
    return spvg_estimate_resolved(p, spvg_decode_history(p, t), spvg_read_age(t.w), gamma, spvg_history_written(t), xi, input);
}

// spvg_estimate_texel_resolved without the renderer's weight: the age stands in for it.
fn spvg_estimate_texel_fractional(p: spvg_Params, t: vec4<f32>, gamma: f32, xi: u32) -> spvg_FrameCount {
    return spvg_estimate_texel_resolved(p, t, gamma, xi, -1.0);
}

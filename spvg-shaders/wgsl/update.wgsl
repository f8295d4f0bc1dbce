// spvg::update: the history update after sampling (docs/algorithms.md §2.2, §2.3).
// Depends on: float, params, texel (the texel form), estimate (spvg_u32_to_f32).
// Rust twin: `spvg::SpvgConfig::update`, the same single-precision operation order.

// The history after a frame, and whether it absorbed the frame (SpvgConfig::update's
// return value).
struct spvg_HistoryUpdate {
    history: spvg_History,
    accepted: bool,
}

// The firefly clamp (spvg::controller::rules::firefly_clamp, docs/algorithms.md §8.3) of a
// finite sample against a read history: the variance floored at sigma0^2 (a variance of 0
// would pin every later value to the mean), sigma its square root, the sample clamped to
// [mean - k sigma, mean + k sigma]. A bound that overflows to infinity opens that side.
// sqrt is correctly rounded on lavapipe, where the harness holds this equal to the core;
// Vulkan allows a device a few ulp there, which moves only a clamped value's bound.
fn spvg_firefly_clamp(p: spvg_Params, mean: f32, variance: f32, sample: f32) -> f32 {
    var floor_var = p.target_variance;
    if (variance > p.target_variance) {
        floor_var = variance;
    }
    let reach = p.firefly_k * sqrt(floor_var);
    let lo = mean - reach;
    let hi = mean + reach;
    if (sample < lo) {
        return lo;
    }
    if (sample > hi) {
        return hi;
    }
    return sample;
}

// SpvgConfig::update with the monitored value `sample` (S_t) and the count used:
// - count 0 or a non-finite sample: refused; a valid history is kept, an invalid one
//   becomes the zero history;
// - invalid history (disocclusion): mean = sample, variance = sigma0^2, mean_count = n;
// - otherwise, stored numbers read defensively (non-finite as 0, variance and mean
//   count not > 0 as 0), sat = spvg_saturate:
//     (firefly clamp, p.firefly_k > 0: sample = spvg_firefly_clamp(p, mean, variance, sample))
//     d          = sat(sample - mean)
//     variance   = sat(retain * variance + eta_retain * sat(d * d))
//     mean       = sat(retain * mean + eta * sample)
//     mean_count = sat(retain * mean_count + eta * n)   (TwoPhase: n)
fn spvg_update_history(p: spvg_Params, h: spvg_History, sample: f32, count: u32, valid: bool) -> spvg_HistoryUpdate {
    return spvg_update_history_centred(p, h, sample, 0.0, false, count, valid);
}

// SpvgConfig::update_guided (the dissertation's Eq. 4.4, docs/algorithms.md §8.4):
// spvg_update_history with the variance's deviation taken from `guide`, the renderer's
// resolved TAA history C_t at this pixel (reprojected and clamped, before its blend), in
// the luminance space of `sample`:
//     d = sat(sample - guide)
// instead of sat(sample - mean); the mean, the mean count, the firefly clamp (against the
// pixel's own history), the seed and refused frames are spvg_update_history's. A
// non-finite guide falls back to the history's mean (spvg::controller::rules::guide_centre).
fn spvg_update_history_guided(p: spvg_Params, h: spvg_History, sample: f32, guide: f32, count: u32, valid: bool) -> spvg_HistoryUpdate {
    return spvg_update_history_centred(p, h, sample, guide, true, count, valid);
}

// Both updates: the deviation about the guide where `guided` and the guide is finite,
// else about the read mean (spvg::controller::rules::update_guided).
fn spvg_update_history_centred(p: spvg_Params, h: spvg_History, sample: f32, guide: f32, guided: bool, count: u32, valid: bool) -> spvg_HistoryUpdate {
    if (count == 0u || !spvg_is_finite(sample)) {
        if (!valid) {
            return spvg_HistoryUpdate(spvg_History(0.0, 0.0, 0.0), false);
        }
        return spvg_HistoryUpdate(h, false);
    }
    let n = spvg_u32_to_f32(count);
    if (!valid) {
        return spvg_HistoryUpdate(spvg_History(sample, p.target_variance, n), true);
    }
    var mean = h.mean;
    if (!spvg_is_finite(mean)) {
        mean = 0.0;
    }
    var variance = h.variance;
    if (!(spvg_is_finite(variance) && variance > 0.0)) {
        variance = 0.0;
    }
    var old_count = h.mean_count;
    if (!(spvg_is_finite(old_count) && old_count > 0.0)) {
        old_count = 0.0;
    }
    var s = sample;
    if (p.firefly_k > 0.0) {
        s = spvg_firefly_clamp(p, mean, variance, sample);
    }
    var centre = mean;
    if (guided && spvg_is_finite(guide)) {
        centre = guide;
    }
    let d = spvg_saturate(s - centre);
    let variance_new = spvg_saturate(p.retain * variance + p.eta_retain * spvg_saturate(d * d));
    let mean_new = spvg_saturate(p.retain * mean + p.eta * s);
    var count_new = n;
    if (p.policy != spvg_POLICY_TWO_PHASE) {
        count_new = spvg_saturate(p.retain * old_count + p.eta * n);
    }
    return spvg_HistoryUpdate(spvg_History(mean_new, variance_new, count_new), true);
}

// spvg_update_history on a history texel as a store with reprojection keeps it (the
// texel `t` read at the continued texel, zeros where the pixel continues none; valid
// where it carries the written mark): the new texel with the written mark
// (spvg_encode_written_history). A refused frame (count 0, non-finite sample) keeps a
// valid texel as it is and clears an invalid one to zeros.
fn spvg_update_history_texel(p: spvg_Params, t: vec4<f32>, sample: f32, count: u32, random: u32) -> vec4<f32> {
    return spvg_update_history_texel_centred(p, t, sample, 0.0, false, count, random);
}

// spvg_update_history_texel with the guided update (spvg_update_history_guided).
fn spvg_update_history_texel_guided(p: spvg_Params, t: vec4<f32>, sample: f32, guide: f32, count: u32, random: u32) -> vec4<f32> {
    return spvg_update_history_texel_centred(p, t, sample, guide, true, count, random);
}

fn spvg_update_history_texel_centred(p: spvg_Params, t: vec4<f32>, sample: f32, guide: f32, guided: bool, count: u32, random: u32) -> vec4<f32> {
    let valid = spvg_history_written(t);
    let u = spvg_update_history_centred(p, spvg_decode_history(p, t), sample, guide, guided, count, valid);
    if (!u.accepted) {
        return select(vec4<f32>(0.0), t, valid);
    }
    return spvg_encode_written_history(p, u.history, random);
}

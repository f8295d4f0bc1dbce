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
    let w = vec3<f32>(p.eta, p.retain, p.eta_retain);
    return spvg_update_history_weighted(p, h, sample, 0.0, false, count, -1.0, valid, w, w, -1.0);
}

// SpvgConfig::update_guided (the dissertation's Eq. 4.4, docs/algorithms.md §8.5):
// spvg_update_history with the variance's deviation taken from `guide`, the renderer's
// resolved TAA history C_t at this pixel (reprojected and clamped, before its blend), in
// the luminance space of `sample`:
//     d = sat(sample - guide)
// instead of sat(sample - mean); the mean, the mean count, the firefly clamp (against the
// pixel's own history), the seed and refused frames are spvg_update_history's. A
// non-finite guide falls back to the history's mean (spvg::controller::rules::guide_centre).
fn spvg_update_history_guided(p: spvg_Params, h: spvg_History, sample: f32, guide: f32, count: u32, valid: bool) -> spvg_HistoryUpdate {
    let w = vec3<f32>(p.eta, p.retain, p.eta_retain);
    return spvg_update_history_weighted(p, h, sample, guide, true, count, -1.0, valid, w, w, -1.0);
}

// Every update (spvg::controller::rules::update_weighted): the weight w = (eta, retain,
// eta_retain) in place of p's in the mean and the variance (the age-aware weight of
// spvg_update_young, the span weight of fractional counts) and wc in the mean count, the
// deviation about the guide where `guided` and the guide is finite, else about the read
// mean, and the frame's real count `real` (negative: the integer rule): the mean count
// records spvg_recorded_count(real, count), and a skipped frame (a valid history, count
// 0, a real count) keeps the read mean and variance and moves only the mean count,
// returned as not accepted. `frame_var` is the frame's spvg_per_sample_variance (negative:
// none), which the variance then follows instead of the deviation
// (spvg_sampling_variance_step). The flag keeps the unguided form from depending on how a
// compiler treats a NaN guide.
fn spvg_update_history_weighted(p: spvg_Params, h: spvg_History, sample: f32, guide: f32, guided: bool, count: u32, real: f32, valid: bool, w: vec3<f32>, wc: vec3<f32>, frame_var: f32) -> spvg_HistoryUpdate {
    if (count == 0u || !spvg_is_finite(sample)) {
        if (!valid) {
            return spvg_HistoryUpdate(spvg_History(0.0, 0.0, 0.0), false);
        }
        if (spvg_skips(count, real, valid)) {
            let r = spvg_read_for_update(h);
            var skipped = real;
            if (p.policy != spvg_POLICY_TWO_PHASE) {
                skipped = spvg_saturate(wc.y * r.mean_count + wc.x * real);
            }
            return spvg_HistoryUpdate(spvg_History(r.mean, r.variance, skipped), false);
        }
        return spvg_HistoryUpdate(h, false);
    }
    let n = spvg_recorded_count(real, count);
    if (!valid) {
        return spvg_HistoryUpdate(spvg_History(sample, p.target_variance, spvg_u32_to_f32(count)), true);
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
    var variance_new = spvg_saturate(w.y * variance + w.z * spvg_saturate(d * d));
    let mean_new = spvg_saturate(w.y * mean + w.x * s);
    var count_new = n;
    if (p.policy != spvg_POLICY_TWO_PHASE) {
        count_new = spvg_saturate(wc.y * old_count + wc.x * n);
    }
    if (frame_var >= 0.0) {
        variance_new = spvg_sampling_variance_step(p, w, variance, old_count, count_new, frame_var);
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
    let w = vec3<f32>(p.eta, p.retain, p.eta_retain);
    let u = spvg_update_history_weighted(p, spvg_decode_history(p, t), sample, guide, guided, count, -1.0, valid, w, w, -1.0);
    if (!u.accepted) {
        return select(vec4<f32>(0.0), t, valid);
    }
    return spvg_encode_written_history(p, u.history, random);
}

// ---- the young-history rules (spvg::controller::young, docs/algorithms.md §8.4) ----

// spvg_AGE_CAP and spvg_read_age live in texel.wgsl (the age is the texel's spare
// channel, and the fractional estimate reads it too).

// young::next_age: a seed is 1 frame old, a valid history that absorbed the frame one
// older (saturating), a refused frame keeps a valid history's age and leaves 0 otherwise.
fn spvg_next_age(age: u32, valid: bool, accepted: bool) -> u32 {
    if (!accepted) {
        return select(0u, min(age, spvg_AGE_CAP), valid);
    }
    if (!valid) {
        return 1u;
    }
    return min(age + 1u, spvg_AGE_CAP);
}

// young::age_weight: (eta, retain, eta_retain) of max(eta, 1 / (a + 1)), a = clamp(age, 1,
// cap). The division is correctly rounded on lavapipe, where the harness holds this
// equal to the core (Vulkan allows a device 2.5 ulp).
fn spvg_age_weight(p: spvg_Params, age: u32) -> vec3<f32> {
    let young = 1.0 / (f32(clamp(age, 1u, spvg_AGE_CAP)) + 1.0);
    if (young > p.eta) {
        let retain = 1.0 - young;
        return vec3<f32>(young, retain, young * retain);
    }
    return vec3<f32>(p.eta, p.retain, p.eta_retain);
}

// young::SpatialMoments: the moments of a pixel's same-surface neighbourhood, relative to
// the pixel's own value.
struct spvg_SpatialMoments {
    count: u32,
    sum: f32,
    sum_sq: f32,
}

// SpatialMoments::push: a non-finite value is skipped.
fn spvg_spatial_push(m: spvg_SpatialMoments, centre: f32, value: f32) -> spvg_SpatialMoments {
    if (!spvg_is_finite(value)) {
        return m;
    }
    let d = spvg_saturate(value - centre);
    return spvg_SpatialMoments(
        min(m.count, 0xfffffffeu) + 1u,
        spvg_saturate(m.sum + d),
        spvg_saturate(m.sum_sq + spvg_saturate(d * d)),
    );
}

// SpatialMoments::variance: the sample variance (over count - 1); only meaningful for
// count >= 2 (the caller checks).
fn spvg_spatial_variance(m: spvg_SpatialMoments) -> f32 {
    let c = spvg_u32_to_f32(m.count);
    let v = (m.sum_sq - spvg_saturate(m.sum * m.sum) / c) / (c - 1.0);
    if (v > 0.0) {
        return spvg_saturate(v);
    }
    return 0.0;
}

// The history, its age after the frame, and whether it absorbed the frame.
struct spvg_YoungUpdate {
    history: spvg_History,
    age: u32,
    accepted: bool,
}

// spvg::controller::rules::update_young (SpvgConfig::update_young): spvg_update_history
// with the age-aware weight for a valid history where p.young has spvg_YOUNG_AGE_WEIGHT,
// then, for an absorbed frame whose new age is at most p.young's spatial limit, the
// spatial variance of `spatial` (where it holds two values or more) as the variance.
fn spvg_update_young(p: spvg_Params, h: spvg_History, sample: f32, count: u32, valid: bool, age: u32, spatial: spvg_SpatialMoments) -> spvg_YoungUpdate {
    return spvg_update_young_centred(p, h, sample, 0.0, false, count, valid, age, spatial);
}

// rules::update_young_guided (SpvgConfig::update_young_guided): spvg_update_young with
// the deviation about the TAA guide of spvg_update_history_guided.
fn spvg_update_young_guided(p: spvg_Params, h: spvg_History, sample: f32, guide: f32, count: u32, valid: bool, age: u32, spatial: spvg_SpatialMoments) -> spvg_YoungUpdate {
    return spvg_update_young_centred(p, h, sample, guide, true, count, valid, age, spatial);
}

fn spvg_update_young_centred(p: spvg_Params, h: spvg_History, sample: f32, guide: f32, guided: bool, count: u32, valid: bool, age: u32, spatial: spvg_SpatialMoments) -> spvg_YoungUpdate {
    return spvg_update_fractional_centred(p, h, sample, guide, guided, count, -1.0, valid, age, spatial);
}

// rules::update_fractional (SpvgConfig::update_fractional, docs/algorithms.md §8.6):
// spvg_update_young_guided with the frame's real count `real` (negative: the integer
// rule, spvg_update_young_guided exactly): the mean count records
// spvg_recorded_count(real, count); a skipped frame keeps the read mean and variance and
// the age and moves only the mean count (accepted false); a sampled frame of fewer than
// spvg_SPAN_SAMPLES samples updates the mean and the variance with spvg_span_weight.
// A non-finite guide is the unguided update.
fn spvg_update_fractional(p: spvg_Params, h: spvg_History, sample: f32, guide: f32, count: u32, real: f32, valid: bool, age: u32, spatial: spvg_SpatialMoments) -> spvg_YoungUpdate {
    return spvg_update_fractional_centred(p, h, sample, guide, true, count, real, valid, age, spatial);
}

fn spvg_update_fractional_centred(p: spvg_Params, h: spvg_History, sample: f32, guide: f32, guided: bool, count: u32, real: f32, valid: bool, age: u32, spatial: spvg_SpatialMoments) -> spvg_YoungUpdate {
    return spvg_update_moment_centred(p, h, sample, guide, guided, -1.0, count, real, valid, age, spatial);
}

// rules::update_moment (SpvgConfig::update_moment, docs/algorithms.md §8.8):
// spvg_update_fractional with the frame's second moment `second_moment` (the mean of the
// squares of the samples whose mean is `sample`): where spvg_per_sample_variance gives one
// (finite, 2 samples or more), an absorbed frame's variance follows the EMA of the
// per-sample variance over the mean count (spvg_sampling_variance_step) instead of the
// EMV of its deviation.
// A non-finite second moment is spvg_update_fractional exactly.
fn spvg_update_moment(p: spvg_Params, h: spvg_History, sample: f32, guide: f32, second_moment: f32, count: u32, real: f32, valid: bool, age: u32, spatial: spvg_SpatialMoments) -> spvg_YoungUpdate {
    return spvg_update_moment_centred(p, h, sample, guide, true, spvg_per_sample_variance(sample, second_moment, count), count, real, valid, age, spatial);
}

fn spvg_update_moment_centred(p: spvg_Params, h: spvg_History, sample: f32, guide: f32, guided: bool, frame_var: f32, count: u32, real: f32, valid: bool, age: u32, spatial: spvg_SpatialMoments) -> spvg_YoungUpdate {
    var w = vec3<f32>(p.eta, p.retain, p.eta_retain);
    if ((p.young & spvg_YOUNG_AGE_WEIGHT) != 0u && valid) {
        w = spvg_age_weight(p, age);
    }
    var ws = w;
    if (spvg_is_real(real)) {
        ws = spvg_span_weight(w, count);
    }
    var u = spvg_update_history_weighted(p, h, sample, guide, guided, count, real, valid, ws, w, frame_var);
    let next = spvg_next_age(age, valid, u.accepted);
    let frames = p.young & spvg_YOUNG_SPATIAL_MASK;
    if (u.accepted && spatial.count >= 2u && next >= 1u && next <= frames) {
        u.history.variance = spvg_spatial_variance(spatial);
    }
    return spvg_YoungUpdate(u.history, next, u.accepted);
}

// spvg_update_young on a history texel (as spvg_update_history_texel reads it) whose
// spare channel holds the age (spvg_read_age; age >= 1 is also the written mark): the new
// texel with the new age in the spare channel. A refused frame keeps a valid texel as it
// is and clears an invalid one to zeros.
fn spvg_update_young_texel(p: spvg_Params, t: vec4<f32>, sample: f32, count: u32, spatial: spvg_SpatialMoments, random: u32) -> vec4<f32> {
    return spvg_update_young_texel_centred(p, t, sample, 0.0, false, count, spatial, random);
}

// spvg_update_young_texel with the TAA guide (spvg_update_young_guided).
fn spvg_update_young_texel_guided(p: spvg_Params, t: vec4<f32>, sample: f32, guide: f32, count: u32, spatial: spvg_SpatialMoments, random: u32) -> vec4<f32> {
    return spvg_update_young_texel_centred(p, t, sample, guide, true, count, spatial, random);
}

fn spvg_update_young_texel_centred(p: spvg_Params, t: vec4<f32>, sample: f32, guide: f32, guided: bool, count: u32, spatial: spvg_SpatialMoments, random: u32) -> vec4<f32> {
    return spvg_update_fractional_texel_centred(p, t, sample, guide, guided, count, -1.0, spatial, random);
}

// spvg_update_fractional on a history texel (as spvg_update_young_texel reads it): the
// new texel with the new age in the spare channel; a skipped frame stores the history
// with its new mean count and the same age; a refused frame keeps a valid texel as it is
// and clears an invalid one to zeros.
fn spvg_update_fractional_texel(p: spvg_Params, t: vec4<f32>, sample: f32, guide: f32, count: u32, real: f32, spatial: spvg_SpatialMoments, random: u32) -> vec4<f32> {
    return spvg_update_fractional_texel_centred(p, t, sample, guide, true, count, real, spatial, random);
}

fn spvg_update_fractional_texel_centred(p: spvg_Params, t: vec4<f32>, sample: f32, guide: f32, guided: bool, count: u32, real: f32, spatial: spvg_SpatialMoments, random: u32) -> vec4<f32> {
    return spvg_update_moment_texel_centred(p, t, sample, guide, guided, -1.0, count, real, spatial, random);
}

// spvg_update_moment on a history texel (as spvg_update_fractional_texel reads and
// stores it); a non-finite second moment is spvg_update_fractional_texel exactly.
fn spvg_update_moment_texel(p: spvg_Params, t: vec4<f32>, sample: f32, guide: f32, second_moment: f32, count: u32, real: f32, spatial: spvg_SpatialMoments, random: u32) -> vec4<f32> {
    return spvg_update_moment_texel_centred(p, t, sample, guide, true, spvg_per_sample_variance(sample, second_moment, count), count, real, spatial, random);
}

fn spvg_update_moment_texel_centred(p: spvg_Params, t: vec4<f32>, sample: f32, guide: f32, guided: bool, frame_var: f32, count: u32, real: f32, spatial: spvg_SpatialMoments, random: u32) -> vec4<f32> {
    let valid = spvg_history_written(t);
    let u = spvg_update_moment_centred(p, spvg_decode_history(p, t), sample, guide, guided, frame_var, count, real, valid, spvg_read_age(t.w), spatial);
    if (!u.accepted && !spvg_skips(count, real, valid)) {
        return select(vec4<f32>(0.0), t, valid);
    }
    var out = spvg_encode_history(p, u.history, random);
    out.w = f32(u.age);
    return out;
}

// ---- fractional counts (spvg::controller::fractional, docs/algorithms.md §8.6) ----

// fractional::SPAN_SAMPLES: the samples a frame needs to weigh a whole frame.
const spvg_SPAN_SAMPLES: u32 = 8u;

// fractional::is_real: a real count that decided the frame (finite, >= 0).
fn spvg_is_real(real: f32) -> bool {
    return real >= 0.0 && real <= spvg_F32_MAX;
}

// fractional::skips: a valid history, no sample, a real count.
fn spvg_skips(count: u32, real: f32, valid: bool) -> bool {
    return valid && count == 0u && spvg_is_real(real);
}

// fractional::recorded_count: the real count where the count is the dither's outcome
// (n <= real + 1), else the count (the integer rule's, or one raised by the dilation).
fn spvg_recorded_count(real: f32, count: u32) -> f32 {
    let n = spvg_u32_to_f32(count);
    if (spvg_is_real(real) && n <= real + 1.0) {
        return real;
    }
    return n;
}

// fractional::span_weight: (eta, retain, eta_retain) of w.x * (n / 8) below
// spvg_SPAN_SAMPLES samples (n > 0), w at or above (and for n = 0). The division by 8 is
// exact; a product that underflows to 0 is no weight, and w is kept (Weight::new refuses
// it in the core).
fn spvg_span_weight(w: vec3<f32>, count: u32) -> vec3<f32> {
    if (count == 0u || count >= spvg_SPAN_SAMPLES) {
        return w;
    }
    let e = w.x * (f32(count) / 8.0);
    if (!(e > 0.0)) {
        return w;
    }
    let retain = 1.0 - e;
    return vec3<f32>(e, retain, e * retain);
}

// The update's defensive read of a stored history (spvg::controller::update's
// read_for_update): a non-finite mean reads 0, a variance or mean count that is not
// finite and > 0 reads 0.
fn spvg_read_for_update(h: spvg_History) -> spvg_History {
    var mean = h.mean;
    if (!spvg_is_finite(mean)) {
        mean = 0.0;
    }
    var variance = h.variance;
    if (!(spvg_is_finite(variance) && variance > 0.0)) {
        variance = 0.0;
    }
    var count = h.mean_count;
    if (!(spvg_is_finite(count) && count > 0.0)) {
        count = 0.0;
    }
    return spvg_History(mean, variance, count);
}

// ---- the second moment (spvg::controller::rules::per_sample_variance, docs/algorithms.md §8.8) ----

// rules::per_sample_variance: the frame's unbiased per-sample variance from its mean
// `sample` and the mean of its squares, sat(sat(q - sat(S * S)) * n) / (n - 1), 0 where
// rounding takes it below 0; -1 (none) below 2 samples or where either input is not
// finite.
fn spvg_per_sample_variance(sample: f32, second_moment: f32, count: u32) -> f32 {
    if (count < 2u || !spvg_is_finite(sample) || !spvg_is_finite(second_moment)) {
        return -1.0;
    }
    let n = spvg_u32_to_f32(count);
    let spread = spvg_saturate(second_moment - spvg_saturate(sample * sample));
    let v = spvg_saturate(spread * n) / (n - 1.0);
    if (v > 0.0) {
        return v;
    }
    return 0.0;
}

// rules::sampling_variance_step: the history's per-sample variance variance * count_old
// follows the EMA (weight w) of s2, capped with the firefly clamp on (p.firefly_k > 0) at
// sat(sat(k * k) * max(per, sigma0^2)); the new variance is that over count_new (0 where
// count_new is not > 0). The divisions are correctly rounded on lavapipe, where the
// harness holds this equal to the core.
fn spvg_sampling_variance_step(p: spvg_Params, w: vec3<f32>, variance: f32, count_old: f32, count_new: f32, s2: f32) -> f32 {
    let per = spvg_saturate(variance * count_old);
    var v = s2;
    if (p.firefly_k > 0.0) {
        var floor_var = p.target_variance;
        if (per > p.target_variance) {
            floor_var = per;
        }
        let cap = spvg_saturate(spvg_saturate(p.firefly_k * p.firefly_k) * floor_var);
        if (v > cap) {
            v = cap;
        }
    }
    let next = spvg_saturate(w.y * per + w.x * v);
    if (count_new > 0.0) {
        return next / count_new;
    }
    return 0.0;
}

// spvg::budget: one pixel's terms of a frame's demand (docs/algorithms.md §8.2), the map
// step of the reduction that feeds the frame budget governor.
// Depends on: float, params, estimate.
// Rust twins: `spvg::budget::FrameDemand::<f32>::pixel` (the unclamped sums) and
// `spvg::budget::count_at::<f32>` (one point of the clamped demand curve), the same
// single-precision operation order.

// spvg::budget::FrameDemand<f32>: the frame's unclamped total is
// scaled / sigma0^2 - offset + fixed.
struct spvg_FrameDemand {
    scaled: f32,
    offset: f32,
    fixed: f32,
}

// FrameDemand::pixel: nothing under the zero-sample rule; n under the fixed policy;
// min_samples for an invalid history; else, on the history read as the estimate reads
// it (spvg_read_history), SPVG gives (a var nbar, b nbar) with b = kappa (k - 1),
// a = 1 + b, two-phase var nbar, the Unreal clamp var. Products saturate.
fn spvg_frame_demand(p: spvg_Params, history: spvg_History, gamma: f32, valid: bool) -> spvg_FrameDemand {
    if (!spvg_samples_distant(p, gamma)) {
        return spvg_FrameDemand(0.0, 0.0, 0.0);
    }
    if (p.policy == spvg_POLICY_FIXED) {
        return spvg_FrameDemand(0.0, 0.0, spvg_u32_to_f32(p.fixed_count));
    }
    if (!valid) {
        return spvg_FrameDemand(0.0, 0.0, p.min_samples_f);
    }
    let h = spvg_read_history(history);
    switch (p.policy) {
        case 1u: { // spvg_POLICY_TWO_PHASE
            return spvg_FrameDemand(spvg_saturate(h.variance * h.mean_count), 0.0, 0.0);
        }
        case 2u: { // spvg_POLICY_UNREAL_CLAMP
            return spvg_FrameDemand(h.variance, 0.0, 0.0);
        }
        default: {
            let b = p.kappa * p.k_minus_one;
            let scaled = spvg_saturate(spvg_saturate((1.0 + b) * h.variance) * h.mean_count);
            return spvg_FrameDemand(scaled, spvg_saturate(b * h.mean_count), 0.0);
        }
    }
}

// spvg::budget::count_at: the count spvg_estimate_count gives with the target variance
// replaced by `sigma0_sq`, one candidate of the frame's clamped demand curve (the estimate
// reads no other field derived from the target). A `sigma0_sq` not > 0 (NaN included)
// reads as the smallest positive normal f32. Non-increasing in `sigma0_sq`.
fn spvg_count_at(p: spvg_Params, sigma0_sq: f32, history: spvg_History, gamma: f32, valid: bool) -> u32 {
    var q = p;
    q.target_variance = select(bitcast<f32>(0x00800000u), sigma0_sq, sigma0_sq > 0.0);
    return spvg_estimate_count(q, history, gamma, valid);
}

// spvg::cv: the control-variate coefficient and the OCV history update
// (docs/algorithms.md §3). Depends on: float, params, texel.
// Rust twins: `spvg::cv::ControlModel::{coefficient, update_state}` of `As`, `Ccv` and
// `Ocv` (`Ocv::{raw_coefficient, clamp_to_bound, update_inputs}`), the same
// single-precision operation order.

// Ocv::raw_coefficient: (Sigma_xy + eps_a) / (Sigma_yy + eps_a); NaN (a corrupt state)
// gives 1, an overflowed ratio saturates to +-f32::MAX (then the bound it points to wins).
fn spvg_raw_coefficient(p: spvg_Params, j: spvg_CvHistory) -> f32 {
    let a = (j.cov_fg + p.eps_a) / (j.var_g + p.eps_a);
    if (spvg_is_nan(a)) {
        return 1.0;
    }
    return spvg_saturate(a);
}

// Ocv::clamp_to_bound: alpha into D = [0, a0 + fbar / G]; the upper bound applies only
// where G > 0 and it is finite.
fn spvg_clamp_to_bound(p: spvg_Params, alpha: f32, fbar: f32, g: f32) -> f32 {
    var a = alpha;
    if (g > 0.0) {
        let upper = p.a_zero + fbar / g;
        if (spvg_is_finite(upper)) {
            a = spvg_min(a, upper);
        }
    }
    return spvg_max(a, 0.0);
}

// ControlModel::coefficient: AS 0, CCV 1, OCV the clamped learned coefficient of the
// state left by the previous frames. Always finite.
fn spvg_cv_coefficient(p: spvg_Params, j: spvg_CvHistory, fbar: f32, g: f32) -> f32 {
    if (p.model == spvg_MODEL_AS) {
        return 0.0;
    }
    if (p.model == spvg_MODEL_CCV) {
        return 1.0;
    }
    return spvg_clamp_to_bound(p, spvg_raw_coefficient(p, j), fbar, g);
}

// Ocv::update_inputs: fbar and G rounded to f16 (clamped to +-65504) when the model was
// built with_f16_inputs (f16 CV texels), unchanged otherwise. Finite in, finite out.
fn spvg_update_inputs(p: spvg_Params, fbar: f32, g: f32) -> vec2<f32> {
    if (p.f16_inputs != 0u) {
        return vec2<f32>(
            spvg_round_f16_nearest(spvg_store_signed(fbar, spvg_F16_MAX)),
            spvg_round_f16_nearest(spvg_store_signed(g, spvg_F16_MAX)),
        );
    }
    return vec2<f32>(fbar, g);
}

// The CV state after a frame and whether it absorbed it (update_state's return value).
struct spvg_CvUpdate {
    cv: spvg_CvHistory,
    accepted: bool,
}

fn spvg_finite_or_zero(v: f32) -> f32 {
    if (spvg_is_finite(v)) {
        return v;
    }
    return 0.0;
}

// ControlModel::update_state. AS and CCV keep no state: `j` comes back unchanged and
// accepted. OCV (EMCM of Z = [fbar, G] with weight eta_cv, old means first):
// - non-finite fbar or G: refused; a valid state is kept, an invalid one becomes zero;
// - invalid state (disocclusion): the first-sample seed (means = inputs, moments 0);
// - otherwise, stored numbers read as finite-or-0 (var_g also >= 0), sat = spvg_saturate:
//     df = sat(f - mean_f); dg = sat(g - mean_g)
//     cov_fg = sat(retain * cov_fg + eta_retain * sat(df * dg))
//     var_g  = sat(retain * var_g  + eta_retain * sat(dg * dg))
//     mean_f = sat(retain * mean_f + eta * f); mean_g = sat(retain * mean_g + eta * g)
//   with (f, g) = spvg_update_inputs(fbar, G).
fn spvg_update_cv(p: spvg_Params, j: spvg_CvHistory, fbar: f32, g_in: f32, valid: bool) -> spvg_CvUpdate {
    if (p.model != spvg_MODEL_OCV) {
        return spvg_CvUpdate(j, true);
    }
    if (!(spvg_is_finite(fbar) && spvg_is_finite(g_in))) {
        if (!valid) {
            return spvg_CvUpdate(spvg_CvHistory(0.0, 0.0, 0.0, 0.0), false);
        }
        return spvg_CvUpdate(j, false);
    }
    let z = spvg_update_inputs(p, fbar, g_in);
    let f = z.x;
    let g = z.y;
    if (!valid) {
        return spvg_CvUpdate(spvg_CvHistory(0.0, 0.0, f, g), true);
    }
    let mean_f = spvg_finite_or_zero(j.mean_f);
    let mean_g = spvg_finite_or_zero(j.mean_g);
    let cov_fg = spvg_finite_or_zero(j.cov_fg);
    let var_g = spvg_max(spvg_finite_or_zero(j.var_g), 0.0);
    let df = spvg_saturate(f - mean_f);
    let dg = spvg_saturate(g - mean_g);
    return spvg_CvUpdate(spvg_CvHistory(
        spvg_saturate(p.retain_cv * cov_fg + p.eta_retain_cv * spvg_saturate(df * dg)),
        spvg_saturate(p.retain_cv * var_g + p.eta_retain_cv * spvg_saturate(dg * dg)),
        spvg_saturate(p.retain_cv * mean_f + p.eta_cv * f),
        spvg_saturate(p.retain_cv * mean_g + p.eta_cv * g),
    ), true);
}

// spvg::pixel: one pixel's whole step after sampling, the SPVG history and the CV state
// together (docs/algorithms.md §2.2, §3). Depends on: float, params, texel, update, cv.
// Rust twin: `spvg::cv::PixelController::{split, update}`.

// PixelController::split: (fbar, G) = (radiance - (1 - gamma) B, gamma B), saturated
// where every input is finite (a non-finite input passes through, so the frame is
// refused).
fn spvg_split(radiance: f32, preintegrated: f32, gamma: f32) -> vec2<f32> {
    let fbar = radiance - (1.0 - gamma) * preintegrated;
    let g = gamma * preintegrated;
    if (spvg_is_finite(radiance) && spvg_is_finite(preintegrated) && spvg_is_finite(gamma)) {
        return vec2<f32>(spvg_saturate(fbar), spvg_saturate(g));
    }
    return vec2<f32>(fbar, g);
}

// The result of spvg_update_pixel (PixelController::update's PixelUpdate plus the new
// states).
struct spvg_PixelStep {
    history: spvg_History,
    cv: spvg_CvHistory,
    alpha: f32,
    monitored: f32,
    accepted: bool,
}

// PixelController::update: the coefficient from the previous CV state (the cold state
// when the history is invalid), the residual S = sat(fbar - alpha G) monitored by the
// SPVG history, then the CV state update when the history accepted the frame (a refused
// frame keeps a valid CV state and clears an invalid one). With AS and CCV the CV state
// is not used and comes back unchanged.
fn spvg_update_pixel(p: spvg_Params, h: spvg_History, j: spvg_CvHistory, radiance: f32, preintegrated: f32, gamma: f32, count: u32, valid: bool) -> spvg_PixelStep {
    let z = spvg_split(radiance, preintegrated, gamma);
    let fbar = z.x;
    let g = z.y;
    let cold = spvg_CvHistory(0.0, 0.0, 0.0, 0.0);
    var alpha: f32;
    if (valid) {
        alpha = spvg_cv_coefficient(p, j, fbar, g);
    } else {
        alpha = spvg_cv_coefficient(p, cold, fbar, g);
    }
    var monitored = fbar - alpha * g;
    if (spvg_is_finite(fbar) && spvg_is_finite(g)) {
        monitored = spvg_saturate(monitored);
    }
    let u = spvg_update_history(p, h, monitored, count, valid);
    var cv = j;
    if (p.model == spvg_MODEL_OCV) {
        if (u.accepted) {
            cv = spvg_update_cv(p, j, fbar, g, valid).cv;
        } else if (!valid) {
            cv = cold;
        }
    }
    return spvg_PixelStep(u.history, cv, alpha, monitored, u.accepted);
}

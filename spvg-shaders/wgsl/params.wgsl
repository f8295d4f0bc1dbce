// spvg::params: the parameter block and the per-pixel state types. Depends on nothing.
//
// Rust twin of `spvg_Params`: `spvg_shaders::Params` (same field order, 144 bytes, every
// field a 4-byte scalar, so the layout is identical in uniform and storage buffers).
// Fill it on the host with `Params::new` from the core crate's validated configuration;
// the derived constants (retain, eta_retain, k_minus_one, the texel scales) are computed
// there once, in f32, by the core crate, so both sides use identical values.
// Three WGSL names differ from the Rust fields so that no member name ends in a digit
// (naga's backends rename those, and naga_oil refuses them in a composable module):
// k_minus_one is `k_minus_1`, a_zero is `a0`.
struct spvg_Params {
    // SPVG controller (spvg::SpvgConfig<f32>).
    eta: f32,
    retain: f32,
    eta_retain: f32,
    target_variance: f32,
    inv_target: f32,
    kappa: f32,
    k_minus_one: f32,
    eps_u: f32,
    min_samples_f: f32,
    max_samples_f: f32,
    min_samples: u32,
    max_samples: u32,
    // spvg_POLICY_*; `fixed_count` is n of CountPolicy::Fixed(n).
    policy: u32,
    fixed_count: u32,
    // The damped correction (SpvgConfig::max_change, docs/algorithms.md §8.1): 1 when on,
    // with the caps 1 / (1 + c) and 1 + c of the count per unit of nbar.
    damped: u32,
    cap_down: f32,
    cap_up: f32,
    // Control variate: spvg_MODEL_*; OCV's weight, eps_a, a0 (a_zero) and f16-input flag.
    model: u32,
    f16_inputs: u32,
    eta_cv: f32,
    retain_cv: f32,
    eta_retain_cv: f32,
    eps_a: f32,
    a_zero: f32,
    // Texel storage: spvg_LAYOUT_*, spvg_ROUNDING_*, and the powers of two 2^k, 2^-k
    // (variance) and 2^c, 2^-c (CV moments) of spvg::texel::TexelEncoding.
    texel_layout: u32,
    rounding: u32,
    var_scale: f32,
    inv_var_scale: f32,
    cv_scale: f32,
    inv_cv_scale: f32,
    // The firefly clamp (SpvgConfig::firefly_clamp, docs/algorithms.md §8.3): k of the
    // clamp of the monitored value to mean +- k sigma before the update; 0 when off.
    firefly_k: f32,
    // The young-history rules (docs/algorithms.md §8.4): bits 0 to 7 the largest age that
    // takes the spatial variance (SpvgConfig::spatial_variance, 0 = off), bit 8 the
    // age-aware weight (SpvgConfig::age_weight): spvg_YOUNG_*.
    young: u32,
    // Fractional counts (SpvgConfig::fractional_floor, docs/algorithms.md §8.6): 1 when
    // on, and the lower bound of a real count (the fractional floor; beta_min without
    // fractional counts, SpvgConfig::floor_f).
    fractional: u32,
    floor_f: f32,
    // The resolved-image rule (SpvgConfig::resolve_weight, docs/algorithms.md §8.7): the
    // resolve's steady weight alpha on the current frame, 0 when the rule is off.
    resolve_weight: f32,
    // Unused, zero: the struct stays a multiple of 16 bytes.
    spare_b: u32,
}

// spvg_Params.young: the bits of the spatial variance's age limit and the age-aware
// weight's flag (spvg_shaders::{YOUNG_SPATIAL_MASK, YOUNG_AGE_WEIGHT}).
const spvg_YOUNG_SPATIAL_MASK: u32 = 255u;
const spvg_YOUNG_AGE_WEIGHT: u32 = 256u;

// spvg::controller::CountPolicy.
const spvg_POLICY_SPVG: u32 = 0u;
const spvg_POLICY_TWO_PHASE: u32 = 1u;
const spvg_POLICY_UNREAL_CLAMP: u32 = 2u;
const spvg_POLICY_FIXED: u32 = 3u;

// The control-variate model: spvg::cv::{As, Ccv, Ocv}.
const spvg_MODEL_AS: u32 = 0u;
const spvg_MODEL_CCV: u32 = 1u;
const spvg_MODEL_OCV: u32 = 2u;

// spvg::texel::Layout.
const spvg_LAYOUT_F16: u32 = 0u;
const spvg_LAYOUT_F32: u32 = 1u;

// spvg::texel::Rounding (f16 layout only).
const spvg_ROUNDING_NEAREST: u32 = 0u;
const spvg_ROUNDING_STOCHASTIC: u32 = 1u;

// spvg::SpvgHistory<f32>: H = (mu, var, nbar).
struct spvg_History {
    mean: f32,
    variance: f32,
    mean_count: f32,
}

// spvg::CvHistory<f32>: J = (Sigma_xy, Sigma_yy, zeta_f, zeta_g).
struct spvg_CvHistory {
    cov_fg: f32,
    var_g: f32,
    mean_f: f32,
    mean_g: f32,
}

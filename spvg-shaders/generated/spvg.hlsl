struct spvg_Params {
    float eta;
    float retain;
    float eta_retain;
    float target_variance;
    float inv_target;
    float kappa;
    float k_minus_one;
    float eps_u;
    float min_samples_f;
    float max_samples_f;
    uint min_samples;
    uint max_samples;
    uint policy;
    uint fixed_count;
    uint damped;
    float cap_down;
    float cap_up;
    uint model;
    uint f16_inputs;
    float eta_cv;
    float retain_cv;
    float eta_retain_cv;
    float eps_a;
    float a_zero;
    uint texel_layout;
    uint rounding;
    float var_scale;
    float inv_var_scale;
    float cv_scale;
    float inv_cv_scale;
    float firefly_k;
    uint young;
    uint fractional;
    float floor_f;
    float resolve_weight;
    uint spare_b;
};

struct spvg_History {
    float mean;
    float variance;
    float mean_count;
};

struct spvg_CvHistory {
    float cov_fg;
    float var_g;
    float mean_f;
    float mean_g;
};

struct spvg_FrameCount {
    uint count;
    float real;
};

struct spvg_HistoryUpdate {
    spvg_History history;
    bool accepted;
};

struct spvg_SpatialMoments {
    uint count;
    float sum;
    float sum_sq;
};

struct spvg_YoungUpdate {
    spvg_History history;
    uint age;
    bool accepted;
};

struct spvg_CvUpdate {
    spvg_CvHistory cv;
    bool accepted;
};

struct spvg_PixelStep {
    spvg_History history;
    spvg_CvHistory cv;
    float alpha;
    float monitored;
    bool accepted;
};

struct spvg_BurleyProfile {
    float albedo;
    float d;
    float inv_d;
};

struct spvg_DistantSample {
    float radius;
    float pdf;
};

struct spvg_RatioEstimator {
    float sum_weights;
    float mean;
};

struct spvg_FrameDemand {
    float scaled;
    float offset;
    float fixed;
};

struct spvg_Reprojection {
    float depth_tolerance;
    uint flags;
};

struct spvg_PreviousTexel {
    bool mask;
    float depth;
    bool written;
};

struct spvg_Locate {
    uint source;
    int _pad1_0;
    uint2 texel;
    uint candidate;
    int _end_pad_0;
};

struct spvg_Dilation {
    uint count;
    int _pad1_0;
    uint2 lo;
    uint2 hi;
};

struct spvg_DilationPrior {
    uint count;
    uint sum;
    uint n;
    int _pad3_0;
    uint2 lo;
    uint2 hi;
};

struct spvg_Region {
    uint2 lo;
    uint2 hi;
};

static const float spvg_F32_MAX = 3.4028235e38;
static const float spvg_F16_MAX = 65504.0;
static const uint spvg_YOUNG_SPATIAL_MASK = 255u;
static const uint spvg_YOUNG_AGE_WEIGHT = 256u;
static const uint spvg_POLICY_SPVG = 0u;
static const uint spvg_POLICY_TWO_PHASE = 1u;
static const uint spvg_POLICY_UNREAL_CLAMP = 2u;
static const uint spvg_POLICY_FIXED = 3u;
static const uint spvg_MODEL_AS = 0u;
static const uint spvg_MODEL_CCV = 1u;
static const uint spvg_MODEL_OCV = 2u;
static const uint spvg_LAYOUT_F16_ = 0u;
static const uint spvg_LAYOUT_F32_ = 1u;
static const uint spvg_ROUNDING_NEAREST = 0u;
static const uint spvg_ROUNDING_STOCHASTIC = 1u;
static const uint2 spvg_R2_STEP = uint2(3242174889u, 2447445414u);
static const uint spvg_AGE_CAP = 255u;
static const uint spvg_SPAN_SAMPLES = 8u;
static const float spvg_PI = 3.1415927;
static const uint spvg_REPROJECT_BORDER_PRIOR = 1u;
static const uint spvg_REPROJECT_FOOTPRINT = 2u;
static const uint spvg_REPROJECT_BORDER_MAXIMUM = 4u;
static const uint spvg_REPROJECT_DEFAULT_FLAGS = 7u;
static const uint spvg_SOURCE_DISOCCLUDED = 0u;
static const uint spvg_SOURCE_HISTORY = 1u;
static const uint spvg_SOURCE_BORDER_PRIOR = 2u;
static const uint spvg_SOURCE_PENDING = 3u;
static const uint spvg_DILATION_KEEP = 2147483648u;
static const uint spvg_DILATION_PRIOR_RADIUS = 4u;
static const uint spvg_TILE = 8u;

bool spvg_is_finite(float x)
{
    return ((asuint(x) & 2139095040u) != 2139095040u);
}

bool spvg_is_nan(float x_1)
{
    return ((asuint(x_1) & 2147483647u) > 2139095040u);
}

float spvg_f32_from_bits(uint bits)
{
    return asfloat(bits);
}

float spvg_inf()
{
    const float _e1 = spvg_f32_from_bits(2139095040u);
    return _e1;
}

float spvg_nan()
{
    const float _e1 = spvg_f32_from_bits(2143289344u);
    return _e1;
}

float spvg_saturate(float x_2)
{
    uint b_11 = asuint(x_2);
    if ((b_11 == 2139095040u)) {
        return spvg_F32_MAX;
    }
    if ((b_11 == 4286578688u)) {
        return -3.4028235e38;
    }
    return x_2;
}

float spvg_max(float a, float b)
{
    const bool _e2 = spvg_is_nan(a);
    if (_e2) {
        return b;
    }
    const bool _e3 = spvg_is_nan(b);
    if (_e3) {
        return a;
    }
    return ((b > a) ? b : a);
}

float spvg_min(float a_1, float b_1)
{
    const bool _e2 = spvg_is_nan(a_1);
    if (_e2) {
        return b_1;
    }
    const bool _e3 = spvg_is_nan(b_1);
    if (_e3) {
        return a_1;
    }
    return ((b_1 < a_1) ? b_1 : a_1);
}

uint3 spvg_pcg3d16_(uint3 p)
{
    uint3 v = (uint3)0;

    v = ((p * 12829u) + (47989u).xxx);
    uint _e8 = v.x;
    uint _e10 = v.y;
    uint _e12 = v.z;
    v.x = (_e8 + (_e10 * _e12));
    uint _e16 = v.y;
    uint _e18 = v.z;
    uint _e20 = v.x;
    v.y = (_e16 + (_e18 * _e20));
    uint _e24 = v.z;
    uint _e26 = v.x;
    uint _e28 = v.y;
    v.z = (_e24 + (_e26 * _e28));
    uint _e32 = v.x;
    uint _e34 = v.y;
    uint _e36 = v.z;
    v.x = (_e32 + (_e34 * _e36));
    uint _e40 = v.y;
    uint _e42 = v.z;
    uint _e44 = v.x;
    v.y = (_e40 + (_e42 * _e44));
    uint _e48 = v.z;
    uint _e50 = v.x;
    uint _e52 = v.y;
    v.z = (_e48 + (_e50 * _e52));
    uint3 _e55 = v;
    return (_e55 >> (16u).xxx);
}

uint3 spvg_pixel_seed(uint px, uint py, uint frame)
{
    const uint3 _e4 = spvg_pcg3d16_(uint3(px, py, frame));
    return _e4;
}

uint2 spvg_r2_offset_from_seed(uint3 seed)
{
    return uint2((seed.x << 16u), (seed.y << 16u));
}

uint2 spvg_r2_point(uint2 offset, uint index)
{
    return (offset + (index * spvg_R2_STEP));
}

float spvg_to_unit_f32_(uint u)
{
    return (float((u >> 8u)) * 5.9604645e-8);
}

uint spvg_dither_threshold(uint px_1, uint py_1, uint frame_1)
{
    return (((px_1 * 3242174889u) + (py_1 * 2447445414u)) + (frame_1 * 2654435769u));
}

uint spvg_channel_bits(uint random, uint channel)
{
    uint x_3 = (uint)0;

    x_3 = (random + (channel * 2654435769u));
    uint _e6 = x_3;
    uint _e7 = x_3;
    x_3 = (_e6 ^ (_e7 >> 16u));
    uint _e11 = x_3;
    x_3 = (_e11 * 2146121005u);
    uint _e14 = x_3;
    uint _e15 = x_3;
    x_3 = (_e14 ^ (_e15 >> 15u));
    uint _e19 = x_3;
    x_3 = (_e19 * 2221713035u);
    uint _e22 = x_3;
    uint _e23 = x_3;
    return (_e22 ^ (_e23 >> 16u));
}

float spvg_round_f16_nearest(float x_4)
{
    uint b_12 = asuint(x_4);
    uint sign_ = (b_12 & 2147483648u);
    uint a_6 = (b_12 & 2147483647u);
    if ((a_6 >= 947912704u)) {
        return asfloat((sign_ | (((a_6 + 4095u) + ((a_6 >> 13u) & 1u)) & 4294959104u)));
    }
    uint q_5 = (asuint((asfloat(a_6) + 0.5)) - 1056964608u);
    return asfloat((sign_ | asuint((float(q_5) * 5.9604645e-8))));
}

float spvg_round_f16_stochastic(float x_5, uint r)
{
    uint q = 0u;
    uint rem = (uint)0;
    uint k = (uint)0;

    uint b_13 = asuint(x_5);
    uint sign_1 = (b_13 & 2147483648u);
    uint a_7 = (b_13 & 2147483647u);
    if ((a_7 >= 947912704u)) {
        return asfloat((sign_1 | ((a_7 + (r >> 19u)) & 4294959104u)));
    }
    uint e = (a_7 >> 23u);
    if ((e == 0u)) {
        return asfloat(sign_1);
    }
    uint s_1 = (126u - e);
    if ((s_1 >= 56u)) {
        return asfloat(sign_1);
    }
    uint m_3 = ((a_7 & 8388607u) | 8388608u);
    rem = m_3;
    if ((s_1 < 24u)) {
        q = (m_3 >> s_1);
        rem = (m_3 & ((1u << s_1) - 1u));
    }
    if ((s_1 <= 32u)) {
        uint _e44 = rem;
        k = (_e44 << (32u - s_1));
    } else {
        uint _e48 = rem;
        k = (_e48 >> (s_1 - 32u));
    }
    uint _e54 = k;
    uint up = ((r < _e54) ? 1u : 0u);
    uint _e57 = q;
    return asfloat((sign_1 | asuint((float((_e57 + up)) * 5.9604645e-8))));
}

float spvg_store_signed(float v_1, float max_value)
{
    const bool _e2 = spvg_is_nan(v_1);
    if (_e2) {
        return 0.0;
    }
    if ((v_1 < -(max_value))) {
        return -(max_value);
    }
    if ((v_1 > max_value)) {
        return max_value;
    }
    return v_1;
}

float spvg_store_non_negative(float v_2, float max_value_1)
{
    if ((v_2 > 0.0)) {
        return min(v_2, max_value_1);
    }
    return 0.0;
}

float spvg_to_f16_(float x_6, uint rounding, uint random_1)
{
    const float _e4 = spvg_store_signed(x_6, spvg_F16_MAX);
    if ((rounding == spvg_ROUNDING_STOCHASTIC)) {
        const float _e7 = spvg_round_f16_stochastic(_e4, random_1);
        return _e7;
    }
    const float _e8 = spvg_round_f16_nearest(_e4);
    return _e8;
}

float spvg_texel_max(spvg_Params p_1)
{
    if ((p_1.texel_layout == spvg_LAYOUT_F32_)) {
        return spvg_F32_MAX;
    }
    return spvg_F16_MAX;
}

float spvg_narrow(spvg_Params p_2, float v_3, uint channel_1, uint random_2)
{
    if ((p_2.texel_layout == spvg_LAYOUT_F32_)) {
        return v_3;
    }
    const uint _e8 = spvg_channel_bits(random_2, channel_1);
    const float _e9 = spvg_to_f16_(v_3, p_2.rounding, _e8);
    return _e9;
}

float spvg_load_signed(float stored, float max_value_2, float scale)
{
    const float _e3 = spvg_store_signed(stored, max_value_2);
    const float _e5 = spvg_saturate((_e3 * scale));
    return _e5;
}

float spvg_load_non_negative(float stored_1, float max_value_3, float scale_1)
{
    const float _e3 = spvg_store_non_negative(stored_1, max_value_3);
    const float _e5 = spvg_saturate((_e3 * scale_1));
    return _e5;
}

spvg_History Constructspvg_History(float arg0, float arg1, float arg2) {
    spvg_History ret = (spvg_History)0;
    ret.mean = arg0;
    ret.variance = arg1;
    ret.mean_count = arg2;
    return ret;
}

spvg_History spvg_decode_history(spvg_Params p_3, float4 t)
{
    const float _e2 = spvg_texel_max(p_3);
    const float _e4 = spvg_store_signed(t.x, _e2);
    const float _e7 = spvg_load_non_negative(t.y, _e2, p_3.var_scale);
    const float _e9 = spvg_store_non_negative(t.z, _e2);
    const spvg_History spvg_history = Constructspvg_History(_e4, _e7, _e9);
    return spvg_history;
}

float4 spvg_encode_history(spvg_Params p_4, spvg_History h, uint random_3)
{
    const float _e3 = spvg_texel_max(p_4);
    const float _e5 = spvg_store_signed(h.mean, _e3);
    const float _e7 = spvg_narrow(p_4, _e5, 0u, random_3);
    const float _e11 = spvg_store_non_negative((h.variance * p_4.inv_var_scale), _e3);
    const float _e13 = spvg_narrow(p_4, _e11, 1u, random_3);
    const float _e15 = spvg_store_non_negative(h.mean_count, _e3);
    const float _e17 = spvg_narrow(p_4, _e15, 2u, random_3);
    const float _e20 = spvg_narrow(p_4, 0.0, 3u, random_3);
    return float4(_e7, _e13, _e17, _e20);
}

float4 spvg_encode_written_history(spvg_Params p_5, spvg_History h_1, uint random_4)
{
    float4 t_1 = (float4)0;

    const float4 _e3 = spvg_encode_history(p_5, h_1, random_4);
    t_1 = _e3;
    t_1.w = 1.0;
    float4 _e7 = t_1;
    return _e7;
}

bool spvg_history_written(float4 t_2)
{
    return (t_2.w >= 0.5);
}

spvg_CvHistory Constructspvg_CvHistory(float arg0, float arg1, float arg2, float arg3) {
    spvg_CvHistory ret = (spvg_CvHistory)0;
    ret.cov_fg = arg0;
    ret.var_g = arg1;
    ret.mean_f = arg2;
    ret.mean_g = arg3;
    return ret;
}

spvg_CvHistory spvg_decode_cv(spvg_Params p_6, float4 t_3)
{
    const float _e2 = spvg_texel_max(p_6);
    const float _e5 = spvg_load_signed(t_3.x, _e2, p_6.cv_scale);
    const float _e8 = spvg_load_non_negative(t_3.y, _e2, p_6.cv_scale);
    const float _e10 = spvg_store_signed(t_3.z, _e2);
    const float _e12 = spvg_store_signed(t_3.w, _e2);
    const spvg_CvHistory spvg_cvhistory = Constructspvg_CvHistory(_e5, _e8, _e10, _e12);
    return spvg_cvhistory;
}

float4 spvg_encode_cv(spvg_Params p_7, spvg_CvHistory j, uint random_5)
{
    const float _e3 = spvg_texel_max(p_7);
    const float _e7 = spvg_store_signed((j.cov_fg * p_7.inv_cv_scale), _e3);
    const float _e9 = spvg_narrow(p_7, _e7, 0u, random_5);
    const float _e13 = spvg_store_non_negative((j.var_g * p_7.inv_cv_scale), _e3);
    const float _e15 = spvg_narrow(p_7, _e13, 1u, random_5);
    const float _e17 = spvg_store_signed(j.mean_f, _e3);
    const float _e19 = spvg_narrow(p_7, _e17, 2u, random_5);
    const float _e21 = spvg_store_signed(j.mean_g, _e3);
    const float _e23 = spvg_narrow(p_7, _e21, 3u, random_5);
    return float4(_e9, _e15, _e19, _e23);
}

uint naga_f2u32(float value) {
    return uint(clamp(value, 0.0, 4294967000.0));
}

uint spvg_read_age(float stored_2)
{
    if (!((stored_2 >= 0.5))) {
        return 0u;
    }
    if ((stored_2 >= 255.0)) {
        return spvg_AGE_CAP;
    }
    return max(naga_f2u32(stored_2), 1u);
}

float spvg_u32_to_f32_(uint n)
{
    uint mant = (uint)0;
    bool local = (bool)0;
    bool local_1 = (bool)0;

    if ((n <= 16777216u)) {
        return float(n);
    }
    uint shift = (8u - (31u - firstbithigh(n)));
    uint half_unit = (1u << (shift - 1u));
    uint rem_1 = (n & ((1u << shift) - 1u));
    mant = (n >> shift);
    if (!((rem_1 > half_unit))) {
        if ((rem_1 == half_unit)) {
            uint _e25 = mant;
            local_1 = ((_e25 & 1u) == 1u);
        } else {
            local_1 = false;
        }
        bool _e31 = local_1;
        local = _e31;
    } else {
        local = true;
    }
    bool _e33 = local;
    if (_e33) {
        uint _e34 = mant;
        mant = (_e34 + 1u);
    }
    uint _e37 = mant;
    return (float(_e37) * asfloat(((127u + shift) << 23u)));
}

bool spvg_samples_distant(spvg_Params p_8, float gamma)
{
    bool local_2 = (bool)0;

    if ((gamma >= p_8.eps_u)) {
        local_2 = (gamma > 0.0);
    } else {
        local_2 = false;
    }
    bool _e9 = local_2;
    return _e9;
}

spvg_History spvg_read_history(spvg_History h_2)
{
    const float _e3 = spvg_store_signed(h_2.mean, spvg_F32_MAX);
    const float _e6 = spvg_store_non_negative(h_2.variance, spvg_F32_MAX);
    const float _e9 = spvg_store_non_negative(h_2.mean_count, spvg_F32_MAX);
    const spvg_History spvg_history_1 = Constructspvg_History(_e3, _e6, _e9);
    return spvg_history_1;
}

float spvg_raw_estimate(spvg_Params p_9, spvg_History history)
{
    float t_4 = (float)0;

    const spvg_History _e2 = spvg_read_history(history);
    const float _e11 = spvg_saturate(((_e2.variance == p_9.target_variance) ? 1.0 : (_e2.variance / p_9.target_variance)));
    switch(p_9.policy) {
        case 1u: {
            const float _e15 = spvg_saturate((_e11 * _e2.mean_count));
            return _e15;
        }
        case 2u: {
            return _e11;
        }
        case 3u: {
            const float _e17 = spvg_u32_to_f32_(p_9.fixed_count);
            return _e17;
        }
        default: {
            const float _e23 = spvg_saturate(((_e11 - 1.0) * p_9.k_minus_one));
            const float _e26 = spvg_saturate(((p_9.kappa * _e23) + _e11));
            t_4 = _e26;
            if ((p_9.damped != 0u)) {
                float _e31 = t_4;
                if ((_e31 < p_9.cap_down)) {
                    t_4 = p_9.cap_down;
                } else {
                    float _e35 = t_4;
                    if ((_e35 > p_9.cap_up)) {
                        t_4 = p_9.cap_up;
                    }
                }
            }
            float _e39 = t_4;
            const float _e42 = spvg_saturate((_e39 * _e2.mean_count));
            return _e42;
        }
    }
}

uint spvg_round_count(spvg_Params p_10, float n_hat)
{
    if ((n_hat >= p_10.min_samples_f)) {
        if ((n_hat < p_10.max_samples_f)) {
            return clamp(naga_f2u32(ceil(n_hat)), p_10.min_samples, p_10.max_samples);
        }
        return p_10.max_samples;
    }
    return p_10.min_samples;
}

uint spvg_estimate(spvg_Params p_11, spvg_History history_1, float gamma_1)
{
    const bool _e3 = spvg_samples_distant(p_11, gamma_1);
    if (!(_e3)) {
        return 0u;
    }
    if ((p_11.policy == spvg_POLICY_FIXED)) {
        return p_11.fixed_count;
    }
    const float _e10 = spvg_raw_estimate(p_11, history_1);
    const uint _e11 = spvg_round_count(p_11, _e10);
    return _e11;
}

uint spvg_estimate_count(spvg_Params p_12, spvg_History history_2, float gamma_2, bool valid)
{
    if (valid) {
        const uint _e4 = spvg_estimate(p_12, history_2, gamma_2);
        return _e4;
    }
    const uint _e9 = spvg_estimate(p_12, Constructspvg_History(0.0, 0.0, 0.0), gamma_2);
    return _e9;
}

uint spvg_estimate_texel(spvg_Params p_13, float4 t_5, float gamma_3)
{
    const spvg_History _e3 = spvg_decode_history(p_13, t_5);
    const bool _e4 = spvg_history_written(t_5);
    const uint _e5 = spvg_estimate_count(p_13, _e3, gamma_3, _e4);
    return _e5;
}

float spvg_resolved_factor(float a_2)
{
    return (a_2 / (2.0 - a_2));
}

float spvg_fractional_raw_count(spvg_Params p_14, spvg_History history_3, float a_3)
{
    float m = 1.0;
    float c = (float)0;

    const spvg_History _e3 = spvg_read_history(history_3);
    if ((_e3.mean_count > 1.0)) {
        m = _e3.mean_count;
    }
    const float _e18 = spvg_saturate(((_e3.variance == p_14.target_variance) ? 1.0 : (_e3.variance / p_14.target_variance)));
    c = _e18;
    switch(p_14.policy) {
        case 2u: {
            c = _e18;
            break;
        }
        case 3u: {
            const float _e22 = spvg_u32_to_f32_(p_14.fixed_count);
            return _e22;
        }
        default: {
            float _e23 = m;
            const float _e25 = spvg_saturate((_e18 * _e23));
            c = _e25;
            break;
        }
    }
    if ((a_3 < 1.0)) {
        float _e28 = c;
        const float _e29 = spvg_resolved_factor(a_3);
        const float _e31 = spvg_saturate((_e28 * _e29));
        return _e31;
    }
    float _e32 = c;
    return _e32;
}

float spvg_resolve_weight(spvg_Params p_15, uint age, float input)
{
    bool local_3 = (bool)0;

    float alpha_2 = p_15.resolve_weight;
    if (!((alpha_2 > 0.0))) {
        return 1.0;
    }
    if ((input > 0.0)) {
        local_3 = (input <= spvg_F32_MAX);
    } else {
        local_3 = false;
    }
    bool _e15 = local_3;
    if (_e15) {
        return ((input < 1.0) ? input : 1.0);
    }
    float young = (1.0 / (float(clamp(age, 1u, spvg_AGE_CAP)) + 1.0));
    return ((young > alpha_2) ? young : alpha_2);
}

float spvg_clamp_real(spvg_Params p_16, float raw)
{
    if ((raw >= p_16.floor_f)) {
        if ((raw < p_16.max_samples_f)) {
            return raw;
        }
        return p_16.max_samples_f;
    }
    return p_16.floor_f;
}

float spvg_real_count(spvg_Params p_17, spvg_History history_4, float a_4)
{
    const float _e3 = spvg_fractional_raw_count(p_17, history_4, a_4);
    const float _e4 = spvg_clamp_real(p_17, _e3);
    return _e4;
}

uint spvg_realise_count(float c_1, uint xi)
{
    if ((c_1 > 0.0)) {
        if ((c_1 < 4294967300.0)) {
            uint whole = naga_f2u32(c_1);
            const float _e7 = spvg_u32_to_f32_(whole);
            float frac_ = (c_1 - _e7);
            const float _e11 = spvg_to_unit_f32_(xi);
            return (whole + ((_e11 < frac_) ? 1u : 0u));
        }
        return 4294967295u;
    }
    return 0u;
}

spvg_FrameCount Constructspvg_FrameCount(uint arg0, float arg1) {
    spvg_FrameCount ret = (spvg_FrameCount)0;
    ret.count = arg0;
    ret.real = arg1;
    return ret;
}

spvg_FrameCount spvg_estimate_resolved(spvg_Params p_18, spvg_History history_5, uint age_1, float gamma_4, bool valid_1, uint xi_1, float input_1)
{
    bool local_4 = (bool)0;
    bool local_5 = (bool)0;

    if (!((p_18.fractional == 0u))) {
        local_4 = !(valid_1);
    } else {
        local_4 = true;
    }
    bool _e15 = local_4;
    if (!(_e15)) {
        const bool _e19 = spvg_samples_distant(p_18, gamma_4);
        local_5 = !(_e19);
    } else {
        local_5 = true;
    }
    bool _e22 = local_5;
    if (_e22) {
        const uint _e23 = spvg_estimate_count(p_18, history_5, gamma_4, valid_1);
        const spvg_FrameCount spvg_framecount = Constructspvg_FrameCount(_e23, -1.0);
        return spvg_framecount;
    }
    if ((p_18.policy == spvg_POLICY_FIXED)) {
        const float _e31 = spvg_u32_to_f32_(p_18.fixed_count);
        const spvg_FrameCount spvg_framecount_1 = Constructspvg_FrameCount(p_18.fixed_count, _e31);
        return spvg_framecount_1;
    }
    const float _e33 = spvg_resolve_weight(p_18, age_1, input_1);
    const float _e34 = spvg_real_count(p_18, history_5, _e33);
    const uint _e35 = spvg_realise_count(_e34, xi_1);
    const spvg_FrameCount spvg_framecount_2 = Constructspvg_FrameCount(_e35, _e34);
    return spvg_framecount_2;
}

spvg_FrameCount spvg_estimate_fractional(spvg_Params p_19, spvg_History history_6, float gamma_5, bool valid_2, uint xi_2)
{
    const spvg_FrameCount _e7 = spvg_estimate_resolved(p_19, history_6, spvg_AGE_CAP, gamma_5, valid_2, xi_2, -1.0);
    const spvg_FrameCount spvg_framecount_3 = _e7;
    return spvg_framecount_3;
}

spvg_FrameCount spvg_estimate_texel_resolved(spvg_Params p_20, float4 t_6, float gamma_6, uint xi_3, float input_2)
{
    const spvg_History _e5 = spvg_decode_history(p_20, t_6);
    const uint _e7 = spvg_read_age(t_6.w);
    const bool _e8 = spvg_history_written(t_6);
    const spvg_FrameCount _e9 = spvg_estimate_resolved(p_20, _e5, _e7, gamma_6, _e8, xi_3, input_2);
    const spvg_FrameCount spvg_framecount_4 = _e9;
    return spvg_framecount_4;
}

spvg_FrameCount spvg_estimate_texel_fractional(spvg_Params p_21, float4 t_7, float gamma_7, uint xi_4)
{
    const spvg_FrameCount _e5 = spvg_estimate_texel_resolved(p_21, t_7, gamma_7, xi_4, -1.0);
    const spvg_FrameCount spvg_framecount_5 = _e5;
    return spvg_framecount_5;
}

float spvg_firefly_clamp(spvg_Params p_22, float mean, float variance, float sample_)
{
    float floor_var = (float)0;

    floor_var = p_22.target_variance;
    if ((variance > p_22.target_variance)) {
        floor_var = variance;
    }
    float _e9 = floor_var;
    float reach = (p_22.firefly_k * sqrt(_e9));
    float lo = (mean - reach);
    float hi = (mean + reach);
    if ((sample_ < lo)) {
        return lo;
    }
    if ((sample_ > hi)) {
        return hi;
    }
    return sample_;
}

bool spvg_is_real(float real)
{
    bool local_6 = (bool)0;

    if ((real >= 0.0)) {
        local_6 = (real <= spvg_F32_MAX);
    } else {
        local_6 = false;
    }
    bool _e8 = local_6;
    return _e8;
}

bool spvg_skips(uint count, float real_1, bool valid_3)
{
    bool local_7 = (bool)0;
    bool local_8 = (bool)0;

    if (valid_3) {
        local_7 = (count == 0u);
    } else {
        local_7 = false;
    }
    bool _e8 = local_7;
    if (_e8) {
        const bool _e11 = spvg_is_real(real_1);
        local_8 = _e11;
    } else {
        local_8 = false;
    }
    bool _e13 = local_8;
    return _e13;
}

spvg_History spvg_read_for_update(spvg_History h_3)
{
    float mean_1 = (float)0;
    float variance_1 = (float)0;
    bool local_9 = (bool)0;
    float count_1 = (float)0;
    bool local_10 = (bool)0;

    mean_1 = h_3.mean;
    float _e3 = mean_1;
    const bool _e4 = spvg_is_finite(_e3);
    if (!(_e4)) {
        mean_1 = 0.0;
    }
    variance_1 = h_3.variance;
    float _e9 = variance_1;
    const bool _e10 = spvg_is_finite(_e9);
    if (_e10) {
        float _e13 = variance_1;
        local_9 = (_e13 > 0.0);
    } else {
        local_9 = false;
    }
    bool _e17 = local_9;
    if (!(_e17)) {
        variance_1 = 0.0;
    }
    count_1 = h_3.mean_count;
    float _e22 = count_1;
    const bool _e23 = spvg_is_finite(_e22);
    if (_e23) {
        float _e26 = count_1;
        local_10 = (_e26 > 0.0);
    } else {
        local_10 = false;
    }
    bool _e30 = local_10;
    if (!(_e30)) {
        count_1 = 0.0;
    }
    float _e33 = mean_1;
    float _e34 = variance_1;
    float _e35 = count_1;
    const spvg_History spvg_history_2 = Constructspvg_History(_e33, _e34, _e35);
    return spvg_history_2;
}

float spvg_recorded_count(float real_2, uint count_2)
{
    bool local_11 = (bool)0;

    const float _e2 = spvg_u32_to_f32_(count_2);
    const bool _e3 = spvg_is_real(real_2);
    if (_e3) {
        local_11 = (_e2 <= (real_2 + 1.0));
    } else {
        local_11 = false;
    }
    bool _e10 = local_11;
    if (_e10) {
        return real_2;
    }
    return _e2;
}

float spvg_sampling_variance_step(spvg_Params p_23, float3 w, float variance_2, float count_old, float count_new, float s2_)
{
    float v_4 = (float)0;
    float floor_var_1 = (float)0;

    const float _e7 = spvg_saturate((variance_2 * count_old));
    v_4 = s2_;
    if ((p_23.firefly_k > 0.0)) {
        floor_var_1 = p_23.target_variance;
        if ((_e7 > p_23.target_variance)) {
            floor_var_1 = _e7;
        }
        const float _e19 = spvg_saturate((p_23.firefly_k * p_23.firefly_k));
        float _e20 = floor_var_1;
        const float _e22 = spvg_saturate((_e19 * _e20));
        float _e23 = v_4;
        if ((_e23 > _e22)) {
            v_4 = _e22;
        }
    }
    float _e28 = v_4;
    const float _e31 = spvg_saturate(((w.y * _e7) + (w.x * _e28)));
    if ((count_new > 0.0)) {
        return (_e31 / count_new);
    }
    return 0.0;
}

spvg_HistoryUpdate Constructspvg_HistoryUpdate(spvg_History arg0, bool arg1) {
    spvg_HistoryUpdate ret = (spvg_HistoryUpdate)0;
    ret.history = arg0;
    ret.accepted = arg1;
    return ret;
}

spvg_HistoryUpdate spvg_update_history_weighted(spvg_Params p_24, spvg_History h_4, float sample_1, float guide, bool guided, uint count_3, float real_3, bool valid_4, float3 w_1, float3 wc, float frame_var)
{
    bool local_12 = (bool)0;
    float skipped = (float)0;
    float mean_2 = (float)0;
    float variance_3 = (float)0;
    bool local_13 = (bool)0;
    float old_count = (float)0;
    bool local_14 = (bool)0;
    float s = (float)0;
    float centre = (float)0;
    bool local_15 = (bool)0;
    float variance_new = (float)0;
    float count_new_1 = (float)0;

    if (!((count_3 == 0u))) {
        const bool _e16 = spvg_is_finite(sample_1);
        local_12 = !(_e16);
    } else {
        local_12 = true;
    }
    bool _e19 = local_12;
    if (_e19) {
        if (!(valid_4)) {
            const spvg_HistoryUpdate spvg_historyupdate = Constructspvg_HistoryUpdate(Constructspvg_History(0.0, 0.0, 0.0), false);
            return spvg_historyupdate;
        }
        const bool _e27 = spvg_skips(count_3, real_3, valid_4);
        if (_e27) {
            const spvg_History _e28 = spvg_read_for_update(h_4);
            skipped = real_3;
            if ((p_24.policy != spvg_POLICY_TWO_PHASE)) {
                const float _e39 = spvg_saturate(((wc.y * _e28.mean_count) + (wc.x * real_3)));
                skipped = _e39;
            }
            float _e42 = skipped;
            const spvg_HistoryUpdate spvg_historyupdate_1 = Constructspvg_HistoryUpdate(Constructspvg_History(_e28.mean, _e28.variance, _e42), false);
            return spvg_historyupdate_1;
        }
        const spvg_HistoryUpdate spvg_historyupdate_2 = Constructspvg_HistoryUpdate(h_4, false);
        return spvg_historyupdate_2;
    }
    const float _e48 = spvg_recorded_count(real_3, count_3);
    if (!(valid_4)) {
        const float _e51 = spvg_u32_to_f32_(count_3);
        const spvg_HistoryUpdate spvg_historyupdate_3 = Constructspvg_HistoryUpdate(Constructspvg_History(sample_1, p_24.target_variance, _e51), true);
        return spvg_historyupdate_3;
    }
    mean_2 = h_4.mean;
    float _e57 = mean_2;
    const bool _e58 = spvg_is_finite(_e57);
    if (!(_e58)) {
        mean_2 = 0.0;
    }
    variance_3 = h_4.variance;
    float _e63 = variance_3;
    const bool _e64 = spvg_is_finite(_e63);
    if (_e64) {
        float _e67 = variance_3;
        local_13 = (_e67 > 0.0);
    } else {
        local_13 = false;
    }
    bool _e71 = local_13;
    if (!(_e71)) {
        variance_3 = 0.0;
    }
    old_count = h_4.mean_count;
    float _e76 = old_count;
    const bool _e77 = spvg_is_finite(_e76);
    if (_e77) {
        float _e80 = old_count;
        local_14 = (_e80 > 0.0);
    } else {
        local_14 = false;
    }
    bool _e84 = local_14;
    if (!(_e84)) {
        old_count = 0.0;
    }
    s = sample_1;
    if ((p_24.firefly_k > 0.0)) {
        float _e91 = mean_2;
        float _e92 = variance_3;
        const float _e93 = spvg_firefly_clamp(p_24, _e91, _e92, sample_1);
        s = _e93;
    }
    float _e94 = mean_2;
    centre = _e94;
    if (guided) {
        const bool _e98 = spvg_is_finite(guide);
        local_15 = _e98;
    } else {
        local_15 = false;
    }
    bool _e100 = local_15;
    if (_e100) {
        centre = guide;
    }
    float _e101 = s;
    float _e102 = centre;
    const float _e104 = spvg_saturate((_e101 - _e102));
    float _e106 = variance_3;
    const float _e110 = spvg_saturate((_e104 * _e104));
    const float _e113 = spvg_saturate(((w_1.y * _e106) + (w_1.z * _e110)));
    variance_new = _e113;
    float _e116 = mean_2;
    float _e119 = s;
    const float _e122 = spvg_saturate(((w_1.y * _e116) + (w_1.x * _e119)));
    count_new_1 = _e48;
    if ((p_24.policy != spvg_POLICY_TWO_PHASE)) {
        float _e128 = old_count;
        const float _e133 = spvg_saturate(((wc.y * _e128) + (wc.x * _e48)));
        count_new_1 = _e133;
    }
    if ((frame_var >= 0.0)) {
        float _e136 = variance_3;
        float _e137 = old_count;
        float _e138 = count_new_1;
        const float _e139 = spvg_sampling_variance_step(p_24, w_1, _e136, _e137, _e138, frame_var);
        variance_new = _e139;
    }
    float _e140 = variance_new;
    float _e141 = count_new_1;
    const spvg_HistoryUpdate spvg_historyupdate_4 = Constructspvg_HistoryUpdate(Constructspvg_History(_e122, _e140, _e141), true);
    return spvg_historyupdate_4;
}

spvg_HistoryUpdate spvg_update_history(spvg_Params p_25, spvg_History h_5, float sample_2, uint count_4, bool valid_5)
{
    float3 w_4 = float3(p_25.eta, p_25.retain, p_25.eta_retain);
    const spvg_HistoryUpdate _e13 = spvg_update_history_weighted(p_25, h_5, sample_2, 0.0, false, count_4, -1.0, valid_5, w_4, w_4, -1.0);
    const spvg_HistoryUpdate spvg_historyupdate_5 = _e13;
    return spvg_historyupdate_5;
}

spvg_HistoryUpdate spvg_update_history_guided(spvg_Params p_26, spvg_History h_6, float sample_3, float guide_1, uint count_5, bool valid_6)
{
    float3 w_5 = float3(p_26.eta, p_26.retain, p_26.eta_retain);
    const spvg_HistoryUpdate _e13 = spvg_update_history_weighted(p_26, h_6, sample_3, guide_1, true, count_5, -1.0, valid_6, w_5, w_5, -1.0);
    const spvg_HistoryUpdate spvg_historyupdate_6 = _e13;
    return spvg_historyupdate_6;
}

float4 spvg_update_history_texel_centred(spvg_Params p_27, float4 t_8, float sample_4, float guide_2, bool guided_1, uint count_6, uint random_6)
{
    const bool _e7 = spvg_history_written(t_8);
    float3 w_6 = float3(p_27.eta, p_27.retain, p_27.eta_retain);
    const spvg_History _e12 = spvg_decode_history(p_27, t_8);
    const spvg_HistoryUpdate _e15 = spvg_update_history_weighted(p_27, _e12, sample_4, guide_2, guided_1, count_6, -1.0, _e7, w_6, w_6, -1.0);
    if (!(_e15.accepted)) {
        return (_e7 ? t_8 : (0.0).xxxx);
    }
    const float4 _e22 = spvg_encode_written_history(p_27, _e15.history, random_6);
    return _e22;
}

float4 spvg_update_history_texel(spvg_Params p_28, float4 t_9, float sample_5, uint count_7, uint random_7)
{
    const float4 _e7 = spvg_update_history_texel_centred(p_28, t_9, sample_5, 0.0, false, count_7, random_7);
    return _e7;
}

float4 spvg_update_history_texel_guided(spvg_Params p_29, float4 t_10, float sample_6, float guide_3, uint count_8, uint random_8)
{
    const float4 _e7 = spvg_update_history_texel_centred(p_29, t_10, sample_6, guide_3, true, count_8, random_8);
    return _e7;
}

uint spvg_next_age(uint age_2, bool valid_7, bool accepted)
{
    if (!(accepted)) {
        return (valid_7 ? min(age_2, spvg_AGE_CAP) : 0u);
    }
    if (!(valid_7)) {
        return 1u;
    }
    return min((age_2 + 1u), spvg_AGE_CAP);
}

float3 spvg_age_weight(spvg_Params p_30, uint age_3)
{
    float young_1 = (1.0 / (float(clamp(age_3, 1u, spvg_AGE_CAP)) + 1.0));
    if ((young_1 > p_30.eta)) {
        float retain = (1.0 - young_1);
        return float3(young_1, retain, (young_1 * retain));
    }
    return float3(p_30.eta, p_30.retain, p_30.eta_retain);
}

spvg_SpatialMoments Constructspvg_SpatialMoments(uint arg0, float arg1, float arg2) {
    spvg_SpatialMoments ret = (spvg_SpatialMoments)0;
    ret.count = arg0;
    ret.sum = arg1;
    ret.sum_sq = arg2;
    return ret;
}

spvg_SpatialMoments spvg_spatial_push(spvg_SpatialMoments m_1, float centre_1, float value)
{
    const bool _e3 = spvg_is_finite(value);
    if (!(_e3)) {
        const spvg_SpatialMoments spvg_spatialmoments = m_1;
        return spvg_spatialmoments;
    }
    const float _e6 = spvg_saturate((value - centre_1));
    const float _e14 = spvg_saturate((m_1.sum + _e6));
    const float _e17 = spvg_saturate((_e6 * _e6));
    const float _e19 = spvg_saturate((m_1.sum_sq + _e17));
    const spvg_SpatialMoments spvg_spatialmoments_1 = Constructspvg_SpatialMoments((min(m_1.count, 4294967294u) + 1u), _e14, _e19);
    return spvg_spatialmoments_1;
}

float spvg_spatial_variance(spvg_SpatialMoments m_2)
{
    const float _e2 = spvg_u32_to_f32_(m_2.count);
    const float _e7 = spvg_saturate((m_2.sum * m_2.sum));
    float v_12 = ((m_2.sum_sq - (_e7 / _e2)) / (_e2 - 1.0));
    if ((v_12 > 0.0)) {
        const float _e15 = spvg_saturate(v_12);
        return _e15;
    }
    return 0.0;
}

float3 spvg_span_weight(float3 w_2, uint count_9)
{
    bool local_16 = (bool)0;

    if (!((count_9 == 0u))) {
        local_16 = (count_9 >= spvg_SPAN_SAMPLES);
    } else {
        local_16 = true;
    }
    bool _e10 = local_16;
    if (_e10) {
        return w_2;
    }
    float e_1 = (w_2.x * (float(count_9) / 8.0));
    if (!((e_1 > 0.0))) {
        return w_2;
    }
    float retain_1 = (1.0 - e_1);
    return float3(e_1, retain_1, (e_1 * retain_1));
}

spvg_YoungUpdate Constructspvg_YoungUpdate(spvg_History arg0, uint arg1, bool arg2) {
    spvg_YoungUpdate ret = (spvg_YoungUpdate)0;
    ret.history = arg0;
    ret.age = arg1;
    ret.accepted = arg2;
    return ret;
}

spvg_YoungUpdate spvg_update_moment_centred(spvg_Params p_31, spvg_History h_7, float sample_7, float guide_4, bool guided_2, float frame_var_1, uint count_10, float real_4, bool valid_8, uint age_4, spvg_SpatialMoments spatial)
{
    float3 w_3 = (float3)0;
    bool local_17 = (bool)0;
    float3 ws = (float3)0;
    spvg_HistoryUpdate u_1 = (spvg_HistoryUpdate)0;
    bool local_18 = (bool)0;
    bool local_19 = (bool)0;
    bool local_20 = (bool)0;

    w_3 = float3(p_31.eta, p_31.retain, p_31.eta_retain);
    if (((p_31.young & spvg_YOUNG_AGE_WEIGHT) != 0u)) {
        local_17 = valid_8;
    } else {
        local_17 = false;
    }
    bool _e24 = local_17;
    if (_e24) {
        const float3 _e25 = spvg_age_weight(p_31, age_4);
        w_3 = _e25;
    }
    float3 _e26 = w_3;
    ws = _e26;
    const bool _e28 = spvg_is_real(real_4);
    if (_e28) {
        float3 _e29 = w_3;
        const float3 _e30 = spvg_span_weight(_e29, count_10);
        ws = _e30;
    }
    float3 _e31 = ws;
    float3 _e32 = w_3;
    const spvg_HistoryUpdate _e33 = spvg_update_history_weighted(p_31, h_7, sample_7, guide_4, guided_2, count_10, real_4, valid_8, _e31, _e32, frame_var_1);
    u_1 = _e33;
    bool _e36 = u_1.accepted;
    const uint _e37 = spvg_next_age(age_4, valid_8, _e36);
    uint frames = (p_31.young & spvg_YOUNG_SPATIAL_MASK);
    bool _e42 = u_1.accepted;
    if (_e42) {
        local_18 = (spatial.count >= 2u);
    } else {
        local_18 = false;
    }
    bool _e49 = local_18;
    if (_e49) {
        local_19 = (_e37 >= 1u);
    } else {
        local_19 = false;
    }
    bool _e55 = local_19;
    if (_e55) {
        local_20 = (_e37 <= frames);
    } else {
        local_20 = false;
    }
    bool _e60 = local_20;
    if (_e60) {
        const float _e63 = spvg_spatial_variance(spatial);
        u_1.history.variance = _e63;
    }
    spvg_History _e65 = u_1.history;
    bool _e67 = u_1.accepted;
    const spvg_YoungUpdate spvg_youngupdate = Constructspvg_YoungUpdate(_e65, _e37, _e67);
    return spvg_youngupdate;
}

spvg_YoungUpdate spvg_update_fractional_centred(spvg_Params p_32, spvg_History h_8, float sample_8, float guide_5, bool guided_3, uint count_11, float real_5, bool valid_9, uint age_5, spvg_SpatialMoments spatial_1)
{
    const spvg_YoungUpdate _e11 = spvg_update_moment_centred(p_32, h_8, sample_8, guide_5, guided_3, -1.0, count_11, real_5, valid_9, age_5, spatial_1);
    const spvg_YoungUpdate spvg_youngupdate_1 = _e11;
    return spvg_youngupdate_1;
}

spvg_YoungUpdate spvg_update_young_centred(spvg_Params p_33, spvg_History h_9, float sample_9, float guide_6, bool guided_4, uint count_12, bool valid_10, uint age_6, spvg_SpatialMoments spatial_2)
{
    const spvg_YoungUpdate _e10 = spvg_update_fractional_centred(p_33, h_9, sample_9, guide_6, guided_4, count_12, -1.0, valid_10, age_6, spatial_2);
    const spvg_YoungUpdate spvg_youngupdate_2 = _e10;
    return spvg_youngupdate_2;
}

spvg_YoungUpdate spvg_update_young(spvg_Params p_34, spvg_History h_10, float sample_10, uint count_13, bool valid_11, uint age_7, spvg_SpatialMoments spatial_3)
{
    const spvg_YoungUpdate _e9 = spvg_update_young_centred(p_34, h_10, sample_10, 0.0, false, count_13, valid_11, age_7, spatial_3);
    const spvg_YoungUpdate spvg_youngupdate_3 = _e9;
    return spvg_youngupdate_3;
}

spvg_YoungUpdate spvg_update_young_guided(spvg_Params p_35, spvg_History h_11, float sample_11, float guide_7, uint count_14, bool valid_12, uint age_8, spvg_SpatialMoments spatial_4)
{
    const spvg_YoungUpdate _e9 = spvg_update_young_centred(p_35, h_11, sample_11, guide_7, true, count_14, valid_12, age_8, spatial_4);
    const spvg_YoungUpdate spvg_youngupdate_4 = _e9;
    return spvg_youngupdate_4;
}

spvg_YoungUpdate spvg_update_fractional(spvg_Params p_36, spvg_History h_12, float sample_12, float guide_8, uint count_15, float real_6, bool valid_13, uint age_9, spvg_SpatialMoments spatial_5)
{
    const spvg_YoungUpdate _e10 = spvg_update_fractional_centred(p_36, h_12, sample_12, guide_8, true, count_15, real_6, valid_13, age_9, spatial_5);
    const spvg_YoungUpdate spvg_youngupdate_5 = _e10;
    return spvg_youngupdate_5;
}

float spvg_per_sample_variance(float sample_13, float second_moment, uint count_16)
{
    bool local_21 = (bool)0;
    bool local_22 = (bool)0;

    if (!((count_16 < 2u))) {
        const bool _e8 = spvg_is_finite(sample_13);
        local_21 = !(_e8);
    } else {
        local_21 = true;
    }
    bool _e11 = local_21;
    if (!(_e11)) {
        const bool _e15 = spvg_is_finite(second_moment);
        local_22 = !(_e15);
    } else {
        local_22 = true;
    }
    bool _e18 = local_22;
    if (_e18) {
        return -1.0;
    }
    const float _e20 = spvg_u32_to_f32_(count_16);
    const float _e22 = spvg_saturate((sample_13 * sample_13));
    const float _e24 = spvg_saturate((second_moment - _e22));
    const float _e26 = spvg_saturate((_e24 * _e20));
    float v_13 = (_e26 / (_e20 - 1.0));
    if ((v_13 > 0.0)) {
        return v_13;
    }
    return 0.0;
}

spvg_YoungUpdate spvg_update_moment(spvg_Params p_37, spvg_History h_13, float sample_14, float guide_9, float second_moment_1, uint count_17, float real_7, bool valid_14, uint age_10, spvg_SpatialMoments spatial_6)
{
    const float _e11 = spvg_per_sample_variance(sample_14, second_moment_1, count_17);
    const spvg_YoungUpdate _e12 = spvg_update_moment_centred(p_37, h_13, sample_14, guide_9, true, _e11, count_17, real_7, valid_14, age_10, spatial_6);
    const spvg_YoungUpdate spvg_youngupdate_6 = _e12;
    return spvg_youngupdate_6;
}

float4 spvg_update_moment_texel_centred(spvg_Params p_38, float4 t_11, float sample_15, float guide_10, bool guided_5, float frame_var_2, uint count_18, float real_8, spvg_SpatialMoments spatial_7, uint random_9)
{
    bool local_23 = (bool)0;
    float4 out_ = (float4)0;

    const bool _e10 = spvg_history_written(t_11);
    const spvg_History _e11 = spvg_decode_history(p_38, t_11);
    const uint _e13 = spvg_read_age(t_11.w);
    const spvg_YoungUpdate _e14 = spvg_update_moment_centred(p_38, _e11, sample_15, guide_10, guided_5, frame_var_2, count_18, real_8, _e10, _e13, spatial_7);
    if (!(_e14.accepted)) {
        const bool _e19 = spvg_skips(count_18, real_8, _e10);
        local_23 = !(_e19);
    } else {
        local_23 = false;
    }
    bool _e22 = local_23;
    if (_e22) {
        return (_e10 ? t_11 : (0.0).xxxx);
    }
    const float4 _e27 = spvg_encode_history(p_38, _e14.history, random_9);
    out_ = _e27;
    out_.w = float(_e14.age);
    float4 _e32 = out_;
    return _e32;
}

float4 spvg_update_fractional_texel_centred(spvg_Params p_39, float4 t_12, float sample_16, float guide_11, bool guided_6, uint count_19, float real_9, spvg_SpatialMoments spatial_8, uint random_10)
{
    const float4 _e10 = spvg_update_moment_texel_centred(p_39, t_12, sample_16, guide_11, guided_6, -1.0, count_19, real_9, spatial_8, random_10);
    return _e10;
}

float4 spvg_update_young_texel_centred(spvg_Params p_40, float4 t_13, float sample_17, float guide_12, bool guided_7, uint count_20, spvg_SpatialMoments spatial_9, uint random_11)
{
    const float4 _e9 = spvg_update_fractional_texel_centred(p_40, t_13, sample_17, guide_12, guided_7, count_20, -1.0, spatial_9, random_11);
    return _e9;
}

float4 spvg_update_young_texel(spvg_Params p_41, float4 t_14, float sample_18, uint count_21, spvg_SpatialMoments spatial_10, uint random_12)
{
    const float4 _e8 = spvg_update_young_texel_centred(p_41, t_14, sample_18, 0.0, false, count_21, spatial_10, random_12);
    return _e8;
}

float4 spvg_update_young_texel_guided(spvg_Params p_42, float4 t_15, float sample_19, float guide_13, uint count_22, spvg_SpatialMoments spatial_11, uint random_13)
{
    const float4 _e8 = spvg_update_young_texel_centred(p_42, t_15, sample_19, guide_13, true, count_22, spatial_11, random_13);
    return _e8;
}

float4 spvg_update_fractional_texel(spvg_Params p_43, float4 t_16, float sample_20, float guide_14, uint count_23, float real_10, spvg_SpatialMoments spatial_12, uint random_14)
{
    const float4 _e9 = spvg_update_fractional_texel_centred(p_43, t_16, sample_20, guide_14, true, count_23, real_10, spatial_12, random_14);
    return _e9;
}

float4 spvg_update_moment_texel(spvg_Params p_44, float4 t_17, float sample_21, float guide_15, float second_moment_2, uint count_24, float real_11, spvg_SpatialMoments spatial_13, uint random_15)
{
    const float _e10 = spvg_per_sample_variance(sample_21, second_moment_2, count_24);
    const float4 _e11 = spvg_update_moment_texel_centred(p_44, t_17, sample_21, guide_15, true, _e10, count_24, real_11, spatial_13, random_15);
    return _e11;
}

float spvg_raw_coefficient(spvg_Params p_45, spvg_CvHistory j_1)
{
    float a_8 = ((j_1.cov_fg + p_45.eps_a) / (j_1.var_g + p_45.eps_a));
    const bool _e9 = spvg_is_nan(a_8);
    if (_e9) {
        return 1.0;
    }
    const float _e11 = spvg_saturate(a_8);
    return _e11;
}

float spvg_clamp_to_bound(spvg_Params p_46, float alpha, float fbar, float g)
{
    float a_5 = (float)0;

    a_5 = alpha;
    if ((g > 0.0)) {
        float upper = (p_46.a_zero + (fbar / g));
        const bool _e10 = spvg_is_finite(upper);
        if (_e10) {
            float _e11 = a_5;
            const float _e12 = spvg_min(_e11, upper);
            a_5 = _e12;
        }
    }
    float _e13 = a_5;
    const float _e15 = spvg_max(_e13, 0.0);
    return _e15;
}

float spvg_cv_coefficient(spvg_Params p_47, spvg_CvHistory j_2, float fbar_1, float g_1)
{
    if ((p_47.model == spvg_MODEL_AS)) {
        return 0.0;
    }
    if ((p_47.model == spvg_MODEL_CCV)) {
        return 1.0;
    }
    const float _e12 = spvg_raw_coefficient(p_47, j_2);
    const float _e13 = spvg_clamp_to_bound(p_47, _e12, fbar_1, g_1);
    return _e13;
}

float2 spvg_update_inputs(spvg_Params p_48, float fbar_2, float g_2)
{
    if ((p_48.f16_inputs != 0u)) {
        const float _e7 = spvg_store_signed(fbar_2, spvg_F16_MAX);
        const float _e8 = spvg_round_f16_nearest(_e7);
        const float _e10 = spvg_store_signed(g_2, spvg_F16_MAX);
        const float _e11 = spvg_round_f16_nearest(_e10);
        return float2(_e8, _e11);
    }
    return float2(fbar_2, g_2);
}

float spvg_finite_or_zero(float v_5)
{
    const bool _e1 = spvg_is_finite(v_5);
    if (_e1) {
        return v_5;
    }
    return 0.0;
}

spvg_CvUpdate Constructspvg_CvUpdate(spvg_CvHistory arg0, bool arg1) {
    spvg_CvUpdate ret = (spvg_CvUpdate)0;
    ret.cv = arg0;
    ret.accepted = arg1;
    return ret;
}

spvg_CvUpdate spvg_update_cv(spvg_Params p_49, spvg_CvHistory j_3, float fbar_3, float g_in, bool valid_15)
{
    bool local_24 = (bool)0;

    if ((p_49.model != spvg_MODEL_OCV)) {
        const spvg_CvUpdate spvg_cvupdate = Constructspvg_CvUpdate(j_3, true);
        return spvg_cvupdate;
    }
    const bool _e10 = spvg_is_finite(fbar_3);
    if (_e10) {
        const bool _e13 = spvg_is_finite(g_in);
        local_24 = _e13;
    } else {
        local_24 = false;
    }
    bool _e15 = local_24;
    if (!(_e15)) {
        if (!(valid_15)) {
            const spvg_CvUpdate spvg_cvupdate_1 = Constructspvg_CvUpdate(Constructspvg_CvHistory(0.0, 0.0, 0.0, 0.0), false);
            return spvg_cvupdate_1;
        }
        const spvg_CvUpdate spvg_cvupdate_2 = Constructspvg_CvUpdate(j_3, false);
        return spvg_cvupdate_2;
    }
    const float2 _e27 = spvg_update_inputs(p_49, fbar_3, g_in);
    float f_1 = _e27.x;
    float g_3 = _e27.y;
    if (!(valid_15)) {
        const spvg_CvUpdate spvg_cvupdate_3 = Constructspvg_CvUpdate(Constructspvg_CvHistory(0.0, 0.0, f_1, g_3), true);
        return spvg_cvupdate_3;
    }
    const float _e37 = spvg_finite_or_zero(j_3.mean_f);
    const float _e39 = spvg_finite_or_zero(j_3.mean_g);
    const float _e41 = spvg_finite_or_zero(j_3.cov_fg);
    const float _e43 = spvg_finite_or_zero(j_3.var_g);
    const float _e45 = spvg_max(_e43, 0.0);
    const float _e47 = spvg_saturate((f_1 - _e37));
    const float _e49 = spvg_saturate((g_3 - _e39));
    const float _e54 = spvg_saturate((_e47 * _e49));
    const float _e57 = spvg_saturate(((p_49.retain_cv * _e41) + (p_49.eta_retain_cv * _e54)));
    const float _e62 = spvg_saturate((_e49 * _e49));
    const float _e65 = spvg_saturate(((p_49.retain_cv * _e45) + (p_49.eta_retain_cv * _e62)));
    const float _e71 = spvg_saturate(((p_49.retain_cv * _e37) + (p_49.eta_cv * f_1)));
    const float _e77 = spvg_saturate(((p_49.retain_cv * _e39) + (p_49.eta_cv * g_3)));
    const spvg_CvUpdate spvg_cvupdate_4 = Constructspvg_CvUpdate(Constructspvg_CvHistory(_e57, _e65, _e71, _e77), true);
    return spvg_cvupdate_4;
}

float2 spvg_split(float radiance, float preintegrated, float gamma_8)
{
    bool local_25 = (bool)0;
    bool local_26 = (bool)0;

    float fbar_4 = (radiance - ((1.0 - gamma_8) * preintegrated));
    float g_4 = (gamma_8 * preintegrated);
    const bool _e8 = spvg_is_finite(radiance);
    if (_e8) {
        const bool _e11 = spvg_is_finite(preintegrated);
        local_25 = _e11;
    } else {
        local_25 = false;
    }
    bool _e13 = local_25;
    if (_e13) {
        const bool _e16 = spvg_is_finite(gamma_8);
        local_26 = _e16;
    } else {
        local_26 = false;
    }
    bool _e18 = local_26;
    if (_e18) {
        const float _e19 = spvg_saturate(fbar_4);
        const float _e20 = spvg_saturate(g_4);
        return float2(_e19, _e20);
    }
    return float2(fbar_4, g_4);
}

spvg_PixelStep Constructspvg_PixelStep(spvg_History arg0, spvg_CvHistory arg1, float arg2, float arg3, bool arg4) {
    spvg_PixelStep ret = (spvg_PixelStep)0;
    ret.history = arg0;
    ret.cv = arg1;
    ret.alpha = arg2;
    ret.monitored = arg3;
    ret.accepted = arg4;
    return ret;
}

spvg_PixelStep spvg_update_pixel(spvg_Params p_50, spvg_History h_14, spvg_CvHistory j_4, float radiance_1, float preintegrated_1, float gamma_9, uint count_25, bool valid_16)
{
    float alpha_1 = (float)0;
    float monitored = (float)0;
    bool local_27 = (bool)0;
    spvg_CvHistory cv = (spvg_CvHistory)0;

    const float2 _e8 = spvg_split(radiance_1, preintegrated_1, gamma_9);
    float fbar_5 = _e8.x;
    float g_5 = _e8.y;
    spvg_CvHistory cold = Constructspvg_CvHistory(0.0, 0.0, 0.0, 0.0);
    if (valid_16) {
        const float _e17 = spvg_cv_coefficient(p_50, j_4, fbar_5, g_5);
        alpha_1 = _e17;
    } else {
        const float _e18 = spvg_cv_coefficient(p_50, cold, fbar_5, g_5);
        alpha_1 = _e18;
    }
    float _e19 = alpha_1;
    monitored = (fbar_5 - (_e19 * g_5));
    const bool _e23 = spvg_is_finite(fbar_5);
    if (_e23) {
        const bool _e26 = spvg_is_finite(g_5);
        local_27 = _e26;
    } else {
        local_27 = false;
    }
    bool _e28 = local_27;
    if (_e28) {
        float _e29 = monitored;
        const float _e30 = spvg_saturate(_e29);
        monitored = _e30;
    }
    float _e31 = monitored;
    const spvg_HistoryUpdate _e32 = spvg_update_history(p_50, h_14, _e31, count_25, valid_16);
    cv = j_4;
    if ((p_50.model == spvg_MODEL_OCV)) {
        if (_e32.accepted) {
            const spvg_CvUpdate _e38 = spvg_update_cv(p_50, j_4, fbar_5, g_5, valid_16);
            cv = _e38.cv;
        } else {
            if (!(valid_16)) {
                cv = cold;
            }
        }
    }
    spvg_CvHistory _e42 = cv;
    float _e43 = alpha_1;
    float _e44 = monitored;
    const spvg_PixelStep spvg_pixelstep = Constructspvg_PixelStep(_e32.history, _e42, _e43, _e44, _e32.accepted);
    return spvg_pixelstep;
}

float spvg_expm1_(float x_7)
{
    if ((abs(x_7) < 0.0625)) {
        return (x_7 * (1.0 + (x_7 * (0.5 + (x_7 * (0.16666667 + (x_7 * (0.041666668 + (x_7 * (0.008333334 + (x_7 * (0.0013888889 + (x_7 * 0.0001984127)))))))))))));
    }
    return (exp(x_7) - 1.0);
}

float spvg_ln1p(float x_8)
{
    if ((abs(x_8) < 0.0625)) {
        return (x_8 * (1.0 + (x_8 * (-0.5 + (x_8 * (0.33333334 + (x_8 * (-0.25 + (x_8 * (0.2 + (x_8 * (-0.16666667 + (x_8 * (0.14285715 + (x_8 * (-0.125 + (x_8 * 0.11111111)))))))))))))))));
    }
    return log((1.0 + x_8));
}

float spvg_asinh(float x_9)
{
    if ((abs(x_9) < 0.0625)) {
        float x2_ = (x_9 * x_9);
        return (x_9 * (1.0 + (x2_ * (-0.16666667 + (x2_ * (0.075 + (x2_ * -0.04464286)))))));
    }
    float a_9 = abs(x_9);
    return (sign(x_9) * log((a_9 + sqrt(((a_9 * a_9) + 1.0)))));
}

float spvg_sinh(float x_10)
{
    if ((abs(x_10) < 0.0625)) {
        float x2_1 = (x_10 * x_10);
        return (x_10 * (1.0 + (x2_1 * (0.16666667 + (x2_1 * (0.008333334 + (x2_1 * 0.0001984127)))))));
    }
    return ((exp(x_10) - exp(-(x_10))) * 0.5);
}

float spvg_burley_pdf(spvg_BurleyProfile b_2, float r_1)
{
    const bool _e2 = spvg_is_nan(r_1);
    if (_e2) {
        return r_1;
    }
    if ((r_1 < 0.0)) {
        return 0.0;
    }
    float x_12 = (r_1 * b_2.inv_d);
    return (((exp(-(x_12)) + exp((-(x_12) / 3.0))) * b_2.inv_d) * 0.25);
}

float spvg_burley_cdf(spvg_BurleyProfile b_3, float r_2)
{
    const bool _e2 = spvg_is_nan(r_2);
    if (_e2) {
        return r_2;
    }
    if ((r_2 <= 0.0)) {
        return 0.0;
    }
    float x_13 = (r_2 * b_3.inv_d);
    const float _e9 = spvg_expm1_(-(x_13));
    const float _e13 = spvg_expm1_((-(x_13) / 3.0));
    return (-((_e9 + (3.0 * _e13))) * 0.25);
}

float spvg_burley_distant_ratio(spvg_BurleyProfile b_4, float r0_)
{
    const bool _e2 = spvg_is_nan(r0_);
    if (_e2) {
        return r0_;
    }
    if ((r0_ <= 0.0)) {
        return 1.0;
    }
    float x_14 = (r0_ * b_4.inv_d);
    return ((exp(-(x_14)) + (3.0 * exp((-(x_14) / 3.0)))) * 0.25);
}

float spvg_burley_inverse_split(spvg_BurleyProfile b_5, float xi_5, float u_2)
{
    float x_11 = (float)0;

    if ((xi_5 <= u_2)) {
        float q_6 = (((2.0 * xi_5) * (1.0 + u_2)) / (sqrt((1.0 + ((4.0 * u_2) * u_2))) + (2.236068 * u_2)));
        const float _e21 = spvg_asinh(q_6);
        float h_15 = (_e21 / 6.0);
        const float _e28 = spvg_sinh(h_15);
        float e_2 = ((4.0 * cosh((0.4812118 - h_15))) * _e28);
        const float _e31 = spvg_ln1p(-(e_2));
        x_11 = (-3.0 * _e31);
    } else {
        const float _e35 = spvg_asinh((u_2 + u_2));
        const float _e38 = spvg_sinh((_e35 / 3.0));
        float y = (2.0 * _e38);
        x_11 = (-3.0 * log(y));
    }
    float _e44 = x_11;
    return (_e44 * b_5.d);
}

float spvg_burley_inverse_cdf(spvg_BurleyProfile b_6, float xi_6)
{
    const bool _e2 = spvg_is_nan(xi_6);
    if (_e2) {
        return xi_6;
    }
    if ((xi_6 <= 0.0)) {
        return 0.0;
    }
    if ((xi_6 >= 1.0)) {
        const float _e8 = spvg_inf();
        return _e8;
    }
    const float _e11 = spvg_burley_inverse_split(b_6, xi_6, (1.0 - xi_6));
    return _e11;
}

float spvg_burley_approx_inverse_cdf(spvg_BurleyProfile b_7, float xi_7, float c_2)
{
    bool local_28 = (bool)0;

    const bool _e3 = spvg_is_nan(xi_7);
    if (!(_e3)) {
        const bool _e7 = spvg_is_nan(c_2);
        local_28 = _e7;
    } else {
        local_28 = true;
    }
    bool _e9 = local_28;
    if (_e9) {
        const float _e10 = spvg_nan();
        return _e10;
    }
    if ((xi_7 <= 0.0)) {
        return 0.0;
    }
    if ((xi_7 >= 1.0)) {
        const float _e16 = spvg_inf();
        return _e16;
    }
    const float _e25 = spvg_ln1p(-(xi_7));
    return ((b_7.d * (((2.0 - c_2) * xi_7) - 2.0)) * _e25);
}

spvg_DistantSample Constructspvg_DistantSample(float arg0, float arg1) {
    spvg_DistantSample ret = (spvg_DistantSample)0;
    ret.radius = arg0;
    ret.pdf = arg1;
    return ret;
}

spvg_DistantSample spvg_burley_sample_distant(spvg_BurleyProfile b_8, float xi_in, float r0_in)
{
    bool local_29 = (bool)0;
    float radius = 0.0;

    const bool _e3 = spvg_is_nan(xi_in);
    if (!(_e3)) {
        const bool _e7 = spvg_is_nan(r0_in);
        local_29 = _e7;
    } else {
        local_29 = true;
    }
    bool _e9 = local_29;
    if (_e9) {
        const float _e10 = spvg_nan();
        const spvg_DistantSample spvg_distantsample = Constructspvg_DistantSample(_e10, _e10);
        return spvg_distantsample;
    }
    const float _e13 = spvg_max(r0_in, 0.0);
    const float _e14 = spvg_burley_distant_ratio(b_8, _e13);
    if ((_e14 <= 0.0)) {
        const spvg_DistantSample spvg_distantsample_1 = Constructspvg_DistantSample(_e13, 0.0);
        return spvg_distantsample_1;
    }
    if ((xi_in >= 1.0)) {
        const float _e21 = spvg_inf();
        const spvg_DistantSample spvg_distantsample_2 = Constructspvg_DistantSample(_e21, 0.0);
        return spvg_distantsample_2;
    }
    const float _e25 = spvg_max(xi_in, 0.0);
    const float _e26 = spvg_burley_cdf(b_8, _e13);
    float target_cdf = (_e26 + (_e25 * _e14));
    float complement = ((1.0 - _e25) * _e14);
    if ((target_cdf > 0.0)) {
        const float _e36 = spvg_burley_inverse_split(b_8, target_cdf, complement);
        radius = _e36;
    }
    float _e37 = radius;
    const float _e38 = spvg_max(_e37, _e13);
    radius = _e38;
    float _e39 = radius;
    float _e40 = radius;
    const float _e41 = spvg_burley_pdf(b_8, _e40);
    const spvg_DistantSample spvg_distantsample_3 = Constructspvg_DistantSample(_e39, (_e41 / _e14));
    return spvg_distantsample_3;
}

float spvg_burley_ratio_weight(spvg_BurleyProfile b_9, float r_3, float dz, float pdf)
{
    float x_15 = (sqrt(((r_3 * r_3) + (dz * dz))) * b_9.inv_d);
    float kernel = (((exp(-(x_15)) + exp((-(x_15) / 3.0))) * b_9.inv_d) / 25.132742);
    return (kernel / pdf);
}

spvg_RatioEstimator Constructspvg_RatioEstimator(float arg0, float arg1) {
    spvg_RatioEstimator ret = (spvg_RatioEstimator)0;
    ret.sum_weights = arg0;
    ret.mean = arg1;
    return ret;
}

spvg_RatioEstimator spvg_burley_ratio_add(spvg_BurleyProfile b_10, spvg_RatioEstimator acc, float r_4, float dz_1, float pdf_1, float lighting)
{
    bool local_30 = (bool)0;
    bool local_31 = (bool)0;
    bool local_32 = (bool)0;
    bool local_33 = (bool)0;
    bool local_34 = (bool)0;
    bool local_35 = (bool)0;

    const bool _e6 = spvg_is_finite(r_4);
    if (_e6) {
        const bool _e9 = spvg_is_finite(dz_1);
        local_30 = _e9;
    } else {
        local_30 = false;
    }
    bool _e11 = local_30;
    if (_e11) {
        const bool _e14 = spvg_is_finite(pdf_1);
        local_31 = _e14;
    } else {
        local_31 = false;
    }
    bool _e16 = local_31;
    if (_e16) {
        const bool _e19 = spvg_is_finite(lighting);
        local_32 = _e19;
    } else {
        local_32 = false;
    }
    bool finite = local_32;
    if (!(!(finite))) {
        local_33 = (r_4 < 0.0);
    } else {
        local_33 = true;
    }
    bool _e29 = local_33;
    if (!(_e29)) {
        local_34 = (pdf_1 <= 0.0);
    } else {
        local_34 = true;
    }
    bool _e36 = local_34;
    if (_e36) {
        const spvg_RatioEstimator spvg_ratioestimator = acc;
        return spvg_ratioestimator;
    }
    const float _e37 = spvg_burley_ratio_weight(b_10, r_4, dz_1, pdf_1);
    const bool _e38 = spvg_is_finite(_e37);
    if (!(!(_e38))) {
        local_35 = (_e37 == 0.0);
    } else {
        local_35 = true;
    }
    bool _e46 = local_35;
    if (_e46) {
        const spvg_RatioEstimator spvg_ratioestimator_1 = acc;
        return spvg_ratioestimator_1;
    }
    const float _e49 = spvg_saturate((acc.sum_weights + _e37));
    const float _e54 = spvg_saturate((lighting - acc.mean));
    const float _e57 = spvg_saturate((acc.mean + ((_e37 / _e49) * _e54)));
    const spvg_RatioEstimator spvg_ratioestimator_2 = Constructspvg_RatioEstimator(_e49, _e57);
    return spvg_ratioestimator_2;
}

float spvg_footprint_radius(float depth, float texel_diag)
{
    return ((abs(depth) * texel_diag) * 0.5);
}

float spvg_filtered_mip_level(float pdf_2, uint n_1, float lmax, float texel_area)
{
    float q_7 = ((pdf_2 * float(n_1)) / (((16.0 * lmax) * lmax) * texel_area));
    const bool _e11 = spvg_is_nan(q_7);
    if (_e11) {
        return 0.0;
    }
    if ((q_7 <= 0.0)) {
        const float _e15 = spvg_inf();
        return _e15;
    }
    const float _e19 = spvg_max(-(log2(q_7)), 0.0);
    return (0.5 * _e19);
}

uint spvg_filtered_mip_index(float pdf_3, uint n_2, float lmax_1, float texel_area_1, uint max_mip)
{
    uint k_1 = 0u;
    bool local_36 = (bool)0;
    bool local_37 = (bool)0;

    float q_8 = ((pdf_3 * float(n_2)) / (((16.0 * lmax_1) * lmax_1) * texel_area_1));
    const bool _e12 = spvg_is_nan(q_8);
    if (_e12) {
        return 0u;
    }
    uint2 loop_bound = uint2(4294967295u, 4294967295u);
    while(true) {
        if (all(loop_bound == uint2(0u, 0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        uint _e16 = k_1;
        if ((_e16 < max_mip)) {
            uint _e20 = k_1;
            local_36 = (_e20 < 62u);
        } else {
            local_36 = false;
        }
        bool _e24 = local_36;
        if (_e24) {
            uint _e29 = k_1;
            local_37 = (q_8 <= asfloat(((125u - (2u * _e29)) << 23u)));
        } else {
            local_37 = false;
        }
        bool _e37 = local_37;
        if (_e37) {
        } else {
            break;
        }
        {
            uint _e38 = k_1;
            k_1 = (_e38 + 1u);
        }
    }
    uint _e41 = k_1;
    return _e41;
}

spvg_FrameDemand Constructspvg_FrameDemand(float arg0, float arg1, float arg2) {
    spvg_FrameDemand ret = (spvg_FrameDemand)0;
    ret.scaled = arg0;
    ret.offset = arg1;
    ret.fixed = arg2;
    return ret;
}

spvg_FrameDemand spvg_frame_demand(spvg_Params p_51, spvg_History history_7, float gamma_10, bool valid_17)
{
    const bool _e4 = spvg_samples_distant(p_51, gamma_10);
    if (!(_e4)) {
        const spvg_FrameDemand spvg_framedemand = Constructspvg_FrameDemand(0.0, 0.0, 0.0);
        return spvg_framedemand;
    }
    if ((p_51.policy == spvg_POLICY_FIXED)) {
        const float _e14 = spvg_u32_to_f32_(p_51.fixed_count);
        const spvg_FrameDemand spvg_framedemand_1 = Constructspvg_FrameDemand(0.0, 0.0, _e14);
        return spvg_framedemand_1;
    }
    if (!(valid_17)) {
        const spvg_FrameDemand spvg_framedemand_2 = Constructspvg_FrameDemand(0.0, 0.0, p_51.min_samples_f);
        return spvg_framedemand_2;
    }
    const spvg_History _e23 = spvg_read_history(history_7);
    switch(p_51.policy) {
        case 1u: {
            const float _e28 = spvg_saturate((_e23.variance * _e23.mean_count));
            const spvg_FrameDemand spvg_framedemand_3 = Constructspvg_FrameDemand(_e28, 0.0, 0.0);
            return spvg_framedemand_3;
        }
        case 2u: {
            const spvg_FrameDemand spvg_framedemand_4 = Constructspvg_FrameDemand(_e23.variance, 0.0, 0.0);
            return spvg_framedemand_4;
        }
        default: {
            float b_14 = (p_51.kappa * p_51.k_minus_one);
            const float _e43 = spvg_saturate(((1.0 + b_14) * _e23.variance));
            const float _e46 = spvg_saturate((_e43 * _e23.mean_count));
            const float _e49 = spvg_saturate((b_14 * _e23.mean_count));
            const spvg_FrameDemand spvg_framedemand_5 = Constructspvg_FrameDemand(_e46, _e49, 0.0);
            return spvg_framedemand_5;
        }
    }
}

uint spvg_count_at(spvg_Params p_52, float sigma0_sq, spvg_History history_8, float gamma_11, bool valid_18)
{
    spvg_Params q_1 = (spvg_Params)0;

    q_1 = p_52;
    q_1.target_variance = ((sigma0_sq > 0.0) ? sigma0_sq : asfloat(8388608u));
    spvg_Params _e12 = q_1;
    const uint _e13 = spvg_estimate_count(_e12, history_8, gamma_11, valid_18);
    return _e13;
}

uint3 spvg_reproject_texel(uint2 pixel, float2 v_6, uint2 size)
{
    bool local_38 = (bool)0;
    bool local_39 = (bool)0;
    bool local_40 = (bool)0;

    float2 q_9 = floor(((float2(pixel) + (0.5).xx) - v_6));
    if ((q_9.x >= 0.0)) {
        local_38 = (q_9.y >= 0.0);
    } else {
        local_38 = false;
    }
    bool _e18 = local_38;
    if (_e18) {
        local_39 = (q_9.x < float(size.x));
    } else {
        local_39 = false;
    }
    bool _e26 = local_39;
    if (_e26) {
        local_40 = (q_9.y < float(size.y));
    } else {
        local_40 = false;
    }
    bool inside = local_40;
    if (!(inside)) {
        return (0u).xxx;
    }
    return uint3(naga_f2u32(q_9.x), naga_f2u32(q_9.y), 1u);
}

uint spvg_reproject_border_axis(float q_2, float v_7, uint n_3)
{
    uint inset = 4294967295u;

    uint last = (n_3 - 1u);
    float a_10 = ceil(abs(v_7));
    if ((a_10 < 4294967300.0)) {
        inset = naga_f2u32(a_10);
    }
    uint _e12 = inset;
    inset = min(_e12, last);
    if ((q_2 < 0.0)) {
        uint _e16 = inset;
        return _e16;
    }
    if ((q_2 >= float(n_3))) {
        uint _e19 = inset;
        return (last - _e19);
    }
    return min(naga_f2u32(q_2), last);
}

bool spvg_reproject_within_bound(float q_3, uint n_4)
{
    bool local_41 = (bool)0;

    float nf = float(n_4);
    if ((q_3 >= -(nf))) {
        local_41 = (q_3 < (nf + nf));
    } else {
        local_41 = false;
    }
    bool _e10 = local_41;
    return _e10;
}

uint3 spvg_reproject_border_texel(uint2 pixel_1, float2 v_8, uint2 size_1)
{
    bool local_42 = (bool)0;
    bool local_43 = (bool)0;
    bool local_44 = (bool)0;
    bool local_45 = (bool)0;

    float2 q_10 = floor(((float2(pixel_1) + (0.5).xx) - v_8));
    const bool _e10 = spvg_is_finite(q_10.x);
    if (!(!(_e10))) {
        const bool _e16 = spvg_is_finite(q_10.y);
        local_42 = !(_e16);
    } else {
        local_42 = true;
    }
    bool _e19 = local_42;
    if (!(_e19)) {
        local_43 = (size_1.x == 0u);
    } else {
        local_43 = true;
    }
    bool _e27 = local_43;
    if (!(_e27)) {
        local_44 = (size_1.y == 0u);
    } else {
        local_44 = true;
    }
    bool _e35 = local_44;
    if (_e35) {
        return (0u).xxx;
    }
    const bool _e40 = spvg_reproject_within_bound(q_10.x, size_1.x);
    if (!(!(_e40))) {
        const bool _e47 = spvg_reproject_within_bound(q_10.y, size_1.y);
        local_45 = !(_e47);
    } else {
        local_45 = true;
    }
    bool _e50 = local_45;
    if (_e50) {
        return (0u).xxx;
    }
    const uint _e56 = spvg_reproject_border_axis(q_10.x, v_8.x, size_1.x);
    const uint _e60 = spvg_reproject_border_axis(q_10.y, v_8.y, size_1.y);
    return uint3(_e56, _e60, 1u);
}

bool spvg_reproject_depth_agrees(float previous, float depth_1, float tolerance)
{
    bool local_46 = (bool)0;
    bool local_47 = (bool)0;
    bool local_48 = (bool)0;

    if ((depth_1 > 0.0)) {
        const bool _e7 = spvg_is_finite(depth_1);
        local_46 = _e7;
    } else {
        local_46 = false;
    }
    bool _e9 = local_46;
    if (_e9) {
        const bool _e12 = spvg_is_finite(previous);
        local_47 = _e12;
    } else {
        local_47 = false;
    }
    bool _e14 = local_47;
    if (_e14) {
        local_48 = (abs((previous - depth_1)) <= (tolerance * depth_1));
    } else {
        local_48 = false;
    }
    bool _e22 = local_48;
    return _e22;
}

uint2 spvg_reproject_footprint_axis(float f, uint q_4, uint n_5)
{
    bool local_49 = (bool)0;

    float d_2 = (f - floor(f));
    if ((d_2 < 0.5)) {
        if ((q_4 == 0u)) {
            return (0u).xx;
        }
        return uint2((q_4 - 1u), 1u);
    }
    if ((d_2 > 0.5)) {
        local_49 = ((q_4 + 1u) < n_5);
    } else {
        local_49 = false;
    }
    bool _e23 = local_49;
    if (_e23) {
        return uint2((q_4 + 1u), 1u);
    }
    return (0u).xx;
}

uint3 spvg_reproject_footprint_texel(uint2 pixel_2, float2 v_9, uint2 size_2, uint k_2)
{
    bool local_50 = (bool)0;
    bool local_51 = (bool)0;
    bool local_52 = (bool)0;
    bool local_53 = (bool)0;

    const uint3 _e4 = spvg_reproject_texel(pixel_2, v_9, size_2);
    if ((_e4.z == 0u)) {
        return (0u).xxx;
    }
    float2 f_2 = ((float2(pixel_2) + (0.5).xx) - v_9);
    const uint2 _e18 = spvg_reproject_footprint_axis(f_2.x, _e4.x, size_2.x);
    const uint2 _e22 = spvg_reproject_footprint_axis(f_2.y, _e4.y, size_2.y);
    if ((k_2 == 1u)) {
        local_50 = (_e18.y != 0u);
    } else {
        local_50 = false;
    }
    bool _e31 = local_50;
    if (_e31) {
        return uint3(_e18.x, _e4.y, 1u);
    }
    if ((k_2 == 2u)) {
        local_51 = (_e22.y != 0u);
    } else {
        local_51 = false;
    }
    bool _e44 = local_51;
    if (_e44) {
        return uint3(_e4.x, _e22.x, 1u);
    }
    if ((k_2 == 3u)) {
        local_52 = (_e18.y != 0u);
    } else {
        local_52 = false;
    }
    bool _e57 = local_52;
    if (_e57) {
        local_53 = (_e22.y != 0u);
    } else {
        local_53 = false;
    }
    bool _e64 = local_53;
    if (_e64) {
        return uint3(_e18.x, _e22.x, 1u);
    }
    return (0u).xxx;
}

spvg_Locate Constructspvg_Locate(uint arg0, uint2 arg1, uint arg2) {
    spvg_Locate ret = (spvg_Locate)0;
    ret.source = arg0;
    ret.texel = arg1;
    ret.candidate = arg2;
    return ret;
}

spvg_Locate spvg_reproject_locate_start(spvg_Reprojection rule, uint2 pixel_3, float2 v_10, uint2 size_3, uint2 previous_size)
{
    spvg_Locate none = Constructspvg_Locate(0u, (0u).xx, 0u);
    if (any((size_3 != previous_size))) {
        const spvg_Locate spvg_locate = none;
        return spvg_locate;
    }
    const uint3 _e12 = spvg_reproject_texel(pixel_3, v_10, previous_size);
    if ((_e12.z != 0u)) {
        const spvg_Locate spvg_locate_1 = Constructspvg_Locate(spvg_SOURCE_PENDING, _e12.xy, 0u);
        return spvg_locate_1;
    }
    if (((rule.flags & spvg_REPROJECT_BORDER_PRIOR) != 0u)) {
        const uint3 _e25 = spvg_reproject_border_texel(pixel_3, v_10, previous_size);
        if ((_e25.z != 0u)) {
            const spvg_Locate spvg_locate_2 = Constructspvg_Locate(spvg_SOURCE_PENDING, _e25.xy, 4u);
            return spvg_locate_2;
        }
    }
    const spvg_Locate spvg_locate_3 = none;
    return spvg_locate_3;
}

spvg_Locate spvg_reproject_locate(spvg_Reprojection rule_1, uint2 pixel_4, float2 v_11, uint2 previous_size_1, float depth_2, spvg_Locate l, spvg_PreviousTexel previous_1)
{
    bool local_54 = (bool)0;
    bool local_55 = (bool)0;
    uint k_3 = (uint)0;

    if ((l.source != spvg_SOURCE_PENDING)) {
        const spvg_Locate spvg_locate_4 = l;
        return spvg_locate_4;
    }
    spvg_Locate none_1 = Constructspvg_Locate(spvg_SOURCE_DISOCCLUDED, (0u).xx, l.candidate);
    if (previous_1.mask) {
        const bool _e20 = spvg_reproject_depth_agrees(previous_1.depth, depth_2, rule_1.depth_tolerance);
        local_54 = _e20;
    } else {
        local_54 = false;
    }
    bool _e22 = local_54;
    if (_e22) {
        if (!(previous_1.written)) {
            const spvg_Locate spvg_locate_5 = none_1;
            return spvg_locate_5;
        }
        uint source = ((l.candidate == 4u) ? spvg_SOURCE_BORDER_PRIOR : spvg_SOURCE_HISTORY);
        const spvg_Locate spvg_locate_6 = Constructspvg_Locate(source, l.texel, l.candidate);
        return spvg_locate_6;
    }
    if ((l.candidate < 3u)) {
        local_55 = ((rule_1.flags & spvg_REPROJECT_FOOTPRINT) != 0u);
    } else {
        local_55 = false;
    }
    bool _e45 = local_55;
    if (_e45) {
        k_3 = (l.candidate + 1u);
        uint2 loop_bound_1 = uint2(4294967295u, 4294967295u);
        bool loop_init = true;
        while(true) {
            if (all(loop_bound_1 == uint2(0u, 0u))) { break; }
            loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
            if (!loop_init) {
                uint _e63 = k_3;
                k_3 = (_e63 + 1u);
            }
            loop_init = false;
            uint _e50 = k_3;
            if ((_e50 <= 3u)) {
            } else {
                break;
            }
            {
                uint _e53 = k_3;
                const uint3 _e54 = spvg_reproject_footprint_texel(pixel_4, v_11, previous_size_1, _e53);
                if ((_e54.z != 0u)) {
                    uint _e60 = k_3;
                    const spvg_Locate spvg_locate_7 = Constructspvg_Locate(spvg_SOURCE_PENDING, _e54.xy, _e60);
                    return spvg_locate_7;
                }
            }
        }
    }
    const spvg_Locate spvg_locate_8 = none_1;
    return spvg_locate_8;
}

uint spvg_reproject_entering_count(spvg_Reprojection rule_2, uint estimate, uint max_samples)
{
    bool local_56 = (bool)0;

    if (((rule_2.flags & spvg_REPROJECT_BORDER_MAXIMUM) != 0u)) {
        local_56 = (estimate != 0u);
    } else {
        local_56 = false;
    }
    bool _e13 = local_56;
    if (_e13) {
        return max_samples;
    }
    return estimate;
}

spvg_Dilation Constructspvg_Dilation(uint arg0, uint2 arg1, uint2 arg2) {
    spvg_Dilation ret = (spvg_Dilation)0;
    ret.count = arg0;
    ret.lo = arg1;
    ret.hi = arg2;
    return ret;
}

spvg_Dilation spvg_dilation_window(uint own, uint2 pixel_5, uint2 size_4, uint radius_1)
{
    bool local_57 = (bool)0;
    bool local_58 = (bool)0;

    uint2 empty = uint2(1u, 1u);
    if (!((pixel_5.x >= size_4.x))) {
        local_57 = (pixel_5.y >= size_4.y);
    } else {
        local_57 = true;
    }
    bool _e17 = local_57;
    if (_e17) {
        const spvg_Dilation spvg_dilation = Constructspvg_Dilation(0u, empty, (0u).xx);
        return spvg_dilation;
    }
    if (!((own == 0u))) {
        local_58 = ((own & spvg_DILATION_KEEP) != 0u);
    } else {
        local_58 = true;
    }
    bool _e32 = local_58;
    if (_e32) {
        const spvg_Dilation spvg_dilation_1 = Constructspvg_Dilation((own & 2147483647u), empty, (0u).xx);
        return spvg_dilation_1;
    }
    uint2 lo_1 = (pixel_5 - min(pixel_5, (radius_1).xx));
    uint2 hi_1 = (pixel_5 + min((radius_1).xx, ((size_4 - (1u).xx) - pixel_5)));
    const spvg_Dilation spvg_dilation_2 = Constructspvg_Dilation(0u, lo_1, hi_1);
    return spvg_dilation_2;
}

uint spvg_dilation_take(uint count_26, uint neighbour)
{
    return max(count_26, (neighbour & 2147483647u));
}

spvg_DilationPrior Constructspvg_DilationPrior(uint arg0, uint arg1, uint arg2, uint2 arg3, uint2 arg4) {
    spvg_DilationPrior ret = (spvg_DilationPrior)0;
    ret.count = arg0;
    ret.sum = arg1;
    ret.n = arg2;
    ret.lo = arg3;
    ret.hi = arg4;
    return ret;
}

spvg_DilationPrior spvg_dilation_prior_window(uint own_1, uint2 pixel_6, uint2 size_5, uint radius_2)
{
    bool local_59 = (bool)0;
    bool local_60 = (bool)0;

    if (!(((own_1 & spvg_DILATION_KEEP) == 0u))) {
        local_59 = (pixel_6.x >= size_5.x);
    } else {
        local_59 = true;
    }
    bool _e15 = local_59;
    if (!(_e15)) {
        local_60 = (pixel_6.y >= size_5.y);
    } else {
        local_60 = true;
    }
    bool _e23 = local_60;
    if (_e23) {
        const spvg_Dilation _e24 = spvg_dilation_window(own_1, pixel_6, size_5, radius_2);
        const spvg_DilationPrior spvg_dilationprior = Constructspvg_DilationPrior(_e24.count, 0u, 0u, _e24.lo, _e24.hi);
        return spvg_dilationprior;
    }
    uint r_5 = max(radius_2, spvg_DILATION_PRIOR_RADIUS);
    uint2 lo_2 = (pixel_6 - min(pixel_6, (r_5).xx));
    uint2 hi_2 = (pixel_6 + min((r_5).xx, ((size_5 - (1u).xx) - pixel_6)));
    const spvg_DilationPrior spvg_dilationprior_1 = Constructspvg_DilationPrior((own_1 & 2147483647u), 0u, 0u, lo_2, hi_2);
    return spvg_dilationprior_1;
}

spvg_DilationPrior spvg_dilation_prior_take(spvg_DilationPrior d, uint own_2, uint neighbour_1, bool same_surface)
{
    spvg_DilationPrior out_1 = (spvg_DilationPrior)0;
    bool local_61 = (bool)0;
    bool local_62 = (bool)0;

    out_1 = d;
    if (((own_2 & spvg_DILATION_KEEP) == 0u)) {
        const uint _e11 = spvg_dilation_take(d.count, neighbour_1);
        out_1.count = _e11;
    } else {
        if (((neighbour_1 & spvg_DILATION_KEEP) == 0u)) {
            local_61 = (neighbour_1 != 0u);
        } else {
            local_61 = false;
        }
        bool _e21 = local_61;
        if (_e21) {
            local_62 = same_surface;
        } else {
            local_62 = false;
        }
        bool _e25 = local_62;
        if (_e25) {
            out_1.sum = (d.sum + neighbour_1);
            out_1.n = (d.n + 1u);
        }
    }
    spvg_DilationPrior _e33 = out_1;
    const spvg_DilationPrior spvg_dilationprior_2 = _e33;
    return spvg_dilationprior_2;
}

uint naga_div(uint lhs, uint rhs) {
    return lhs / (rhs == 0u ? 1u : rhs);
}

uint spvg_dilation_prior_count(spvg_DilationPrior d_1, uint own_3)
{
    bool local_63 = (bool)0;

    if (!(((own_3 & spvg_DILATION_KEEP) == 0u))) {
        local_63 = (d_1.n == 0u);
    } else {
        local_63 = true;
    }
    bool _e13 = local_63;
    if (_e13) {
        return d_1.count;
    }
    return max(naga_div((d_1.sum + naga_div(d_1.n, 2u)), d_1.n), d_1.count);
}

uint2 naga_div(uint2 lhs, uint2 rhs) {
    return lhs / (rhs == 0u ? 1u : rhs);
}

spvg_Region Constructspvg_Region(uint2 arg0, uint2 arg1) {
    spvg_Region ret = (spvg_Region)0;
    ret.lo = arg0;
    ret.hi = arg1;
    return ret;
}

spvg_Region spvg_tile_region(uint2 pixel_7, uint2 size_6, uint halo)
{
    uint2 t_18 = (naga_div(pixel_7, (8u).xx) * spvg_TILE);
    uint2 lo_3 = (t_18 - min(t_18, (halo).xx));
    uint2 far = (t_18 + (7u).xx);
    uint2 grown = (far + min((halo).xx, ((4294967295u).xx - far)));
    const spvg_Region spvg_region = Constructspvg_Region(lo_3, min(grown, (size_6 - min(size_6, (1u).xx))));
    return spvg_region;
}

spvg_Region spvg_spatial_window(uint2 pixel_8, uint2 size_7)
{
    const spvg_Region _e3 = spvg_tile_region(pixel_8, size_7, 0u);
    uint2 lo_4 = max((pixel_8 - min(pixel_8, (1u).xx)), _e3.lo);
    uint2 hi_3 = min((pixel_8 + min((1u).xx, ((4294967295u).xx - pixel_8))), _e3.hi);
    const spvg_Region spvg_region_1 = Constructspvg_Region(lo_4, hi_3);
    return spvg_region_1;
}


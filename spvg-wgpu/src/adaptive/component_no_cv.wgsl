// AS and CCV keep no control-variate history: component_cv.wgsl's interface without
// bindings.

const spvg_AD_OCV: bool = false;

fn spvg_ad_load_cv(link: u32) -> vec4<f32> {
    return vec4<f32>(0.0);
}

fn spvg_ad_store_cv(p: vec2<i32>, j: vec4<f32>) {
}

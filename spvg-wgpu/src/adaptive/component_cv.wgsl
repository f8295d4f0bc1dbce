// The control-variate history of OCV (component.wgsl): its bindings and its two helpers.
// component_no_cv.wgsl is the same interface for AS and CCV, which keep no such history.

const spvg_AD_OCV: bool = true;

@group(SPVG_AD_GROUP) @binding(16) var spvg_ad_cv_in: texture_2d<f32>;
@group(SPVG_AD_GROUP) @binding(17) var spvg_ad_cv_out: texture_storage_2d<rgba16float, write>;

// The J texel the update continues through `link` (zeros without one).
fn spvg_ad_load_cv(link: u32) -> vec4<f32> {
    if (link == 0u) {
        return vec4<f32>(0.0);
    }
    return textureLoad(spvg_ad_cv_in, spvg_ad_link_texel(link), 0);
}

fn spvg_ad_store_cv(p: vec2<i32>, j: vec4<f32>) {
    textureStore(spvg_ad_cv_out, p, j);
}

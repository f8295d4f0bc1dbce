// The subsurface-scattering pass: one invocation per pixel, three entry points.
// - sss_fixed: a fixed count per pixel, no history (baseline).
// - sss_gamma: the distant-energy ratio of the sampling profile per pixel, the `gamma`
//   input of the adaptive component's estimate (zero-sample rule, docs/algorithms.md §2.4).
// - sss_sample: the adaptive models' sampling between the component's two steps: reads the
//   count the estimate wrote, takes that many distant samples, and writes the result, the
//   monitored luminance fbar and the control luminance G that the update reads.
// The count control itself (history, validity, estimate, update, AS/CCV/OCV) is the
// reusable component `spvg_wgpu::adaptive::AdaptivePass` (shaders/adaptive/adaptive.wgsl):
// per frame sss_gamma -> adaptive_estimate -> sss_sample -> adaptive_update.
// CPU twins: `spvg_effects::sss::twin::{sss_fixed, sss_gamma, sss_sample}`, one per entry point.
// - sss_sample_classified: sss_sample under the component's count-classified dispatch
//   (`AdaptivePass::dispatch_classified`), once per class of tiles, each invocation taking
//   the pixel `adaptive_class_pixel` gives it (the component's `CLASSIFIED_WGSL`).
// - sss_gamma_tiles, sss_sample_tiles: the same over the listed 8 x 8 tiles only (the hybrid
//   pass's first step once its tags are settled; the list and its grid are the adaptive
//   component's, decoded as its tiles.wgsl does).
// The Burley sampling and texel rounding are the WGSL library's (spvg_shaders::WGSL).

@group(0) @binding(0) var<uniform> params: PassParams;
@group(0) @binding(1) var lighting: texture_2d<f32>;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var mask: texture_2d<u32>;
@group(0) @binding(4) var result_out: texture_storage_2d<rgba16float, write>;
// sss_fixed
@group(0) @binding(5) var count_out: texture_storage_2d<r32uint, write>;
// sss_sample: the component's count texture
@group(0) @binding(6) var count_in: texture_2d<u32>;
// sss_gamma
@group(0) @binding(7) var gamma_out: texture_storage_2d<r32float, write>;
// sss_sample: the component's update inputs
@group(0) @binding(8) var value_out: texture_storage_2d<r32float, write>;
@group(0) @binding(9) var control_out: texture_storage_2d<r32float, write>;
// sss_gamma_tiles, sss_sample_tiles: the component's tile list (spvg_wgpu::adaptive::AdaptiveTiles)
@group(1) @binding(0) var<storage, read> sss_tiles: array<u32>;

fn in_bounds(gid: vec3<u32>) -> bool {
    return gid.x < params.width && gid.y < params.height;
}

// The result texel as the library stores an f16 value (NaN to 0, clamped, rounded to
// nearest even: exact in the rgba16float store).
fn result_texel(v: vec3<f32>) -> vec4<f32> {
    let r = spvg_ROUNDING_NEAREST;
    return vec4<f32>(spvg_to_f16(v.x, r, 0u), spvg_to_f16(v.y, r, 0u), spvg_to_f16(v.z, r, 0u), 1.0);
}

@compute @workgroup_size(8, 8, 1)
fn sss_fixed(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (!in_bounds(gid)) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    if (textureLoad(mask, p, 0).x == 0u) {
        textureStore(result_out, p, vec4<f32>(0.0));
        textureStore(count_out, p, vec4<u32>(0u));
        return;
    }
    // Zero-sample rule (docs/algorithms.md §2.4): nothing scatters far enough to need samples.
    var n = params.fixed_count;
    if (!spvg_samples_distant(params.spvg, pixel_gamma_s(p))) {
        n = 0u;
    }
    textureStore(result_out, p, result_texel(estimate_pixel(p, n).result));
    textureStore(count_out, p, vec4<u32>(n, 0u, 0u, 0u));
}

@compute @workgroup_size(8, 8, 1)
fn sss_gamma(@builtin(global_invocation_id) gid: vec3<u32>) {
    sss_gamma_at(gid);
}

fn sss_gamma_at(gid: vec3<u32>) {
    if (!in_bounds(gid)) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    textureStore(gamma_out, p, vec4<f32>(pixel_gamma_s(p), 0.0, 0.0, 0.0));
}

@compute @workgroup_size(8, 8, 1)
fn sss_sample(@builtin(global_invocation_id) gid: vec3<u32>) {
    sss_sample_at(gid);
}

fn sss_sample_at(gid: vec3<u32>) {
    if (!in_bounds(gid)) {
        return;
    }
    let p = vec2<i32>(gid.xy);
    var e: PixelEstimate;
    if (textureLoad(mask, p, 0).x == 0u) {
        textureStore(result_out, p, vec4<f32>(0.0));
    } else {
        // Count 0 (the zero-sample rule) gives the near part alone.
        e = estimate_pixel(p, textureLoad(count_in, p, 0).x);
        textureStore(result_out, p, result_texel(e.result));
    }
    // Read by the update only where the count is not 0 (zero outside the mask).
    textureStore(value_out, p, vec4<f32>(dot(LUMA, e.fbar), 0.0, 0.0, 0.0));
    textureStore(control_out, p, vec4<f32>(dot(LUMA, e.g), 0.0, 0.0, 0.0));
}

// The pixel of invocation `lid` in the listed tile of workgroup `wg` (grid `groups`); z = 1
// past the list's end. The list's layout is the component's (shaders/adaptive/tiles.wgsl).
fn sss_tile_pixel(wg: vec3<u32>, groups: vec3<u32>, lid: vec3<u32>) -> vec3<u32> {
    let k = wg.y * groups.x + wg.x;
    if (k >= arrayLength(&sss_tiles)) {
        return vec3<u32>(0u, 0u, 1u);
    }
    let t = sss_tiles[k];
    return vec3<u32>((t & 0xffffu) * 8u + lid.x, (t >> 16u) * 8u + lid.y, 0u);
}

@compute @workgroup_size(8, 8, 1)
fn sss_gamma_tiles(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    let gid = sss_tile_pixel(wg, groups, lid);
    if (gid.z == 0u) {
        sss_gamma_at(gid);
    }
}

@compute @workgroup_size(8, 8, 1)
fn sss_sample_tiles(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
) {
    let gid = sss_tile_pixel(wg, groups, lid);
    if (gid.z == 0u) {
        sss_sample_at(gid);
    }
}

@compute @workgroup_size(8, 8, 1)
fn sss_sample_classified(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) index: u32,
) {
    let p = adaptive_class_pixel(wg, groups, index);
    if (p.z == 0u) {
        sss_sample_at(p);
    }
}

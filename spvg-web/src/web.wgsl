// The page's passes around the adaptive component, joined after the AO effect's module
// (`spvg_effects::ao::ao_source()`: the scene, its surface and its occlusion rays, and the
// bindings 0..10 it declares). Each entry point binds what it uses only, and none binds
// more than one storage texture beside the G-buffer's three: WebGPU's default limit is
// four per stage. (The effect's own `ao_gbuffer` writes five: depth, motion, position,
// normal, reprojected depth.)
// - web_gbuffer: depth, motion vector and reprojected depth of each pixel (the effect's
//   `ao_gbuffer` without its position and normal; Rust twin `ao::twin::gbuffer_pixel`);
// - web_sample: `count` occlusion rays from the pixel's surface, recomputed here rather
//   than stored (Rust twin `ao::twin::estimate` on `gbuffer_pixel`'s surface);
// - web_taa: a Karis-style resolve of the AO estimate (bilinear history along the motion
//   vector, clamped to the 3x3 neighbourhood's range, blended with `taa_alpha`);
// - web_reference: one pass of a converged reference, the running mean of passes of
//   `reference_rays` rays with frame seeds of their own;
// - web_compose: the three panels the page shows (after TAA, the count heat map, the
//   error against the reference) into one RGBA8 image; the first shades the resolved AO
//   with a key light for the shapes.

// Rust twin: `spvg_web::renderer::WebParams`; same field order and types.
struct WebParams {
    width: u32,
    height: u32,
    // 1 where the TAA has a history to blend, 0 on its first frame after a reset.
    taa_history: u32,
    // Reference passes accumulated so far.
    reference_passes: u32,
    // Rays per pixel of one reference pass.
    reference_rays: u32,
    // 1 where the reference is of the view on screen.
    has_reference: u32,
    // The weight of this frame in the TAA blend.
    taa_alpha: f32,
    // The count the heat map shows as its hottest colour.
    count_scale: f32,
    // The error panel's gain: an error of 1 / error_gain is its hottest colour.
    error_gain: f32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(11) var<uniform> web: WebParams;
// web_taa: this frame's AO estimate and motion vectors, the TAA history before and after.
@group(0) @binding(12) var value_in: texture_2d<f32>;
@group(0) @binding(13) var motion_in: texture_2d<f32>;
@group(0) @binding(14) var taa_in: texture_2d<f32>;
@group(0) @binding(15) var taa_out: texture_storage_2d<r32float, write>;
// web_reference: the mean of the passes so far, and with this one; web_compose reads it.
@group(0) @binding(16) var reference_in: texture_2d<f32>;
@group(0) @binding(17) var reference_out: texture_storage_2d<r32float, write>;
// web_compose: the three panels side by side, 3 width x height.
@group(0) @binding(18) var image_out: texture_storage_2d<rgba8unorm, write>;

// The visible surface at pixel `gid` of the frame `ao` describes.
fn web_surface(gid: vec2<u32>) -> AoSurface {
    let w = ao_world(vec2<f32>(gid) + 0.5, ao.camera, ao.lens);
    return ao_surface(w.x, w.y);
}

@compute @workgroup_size(8, 8, 1)
fn web_gbuffer(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= ao.width || gid.y >= ao.height) {
        return;
    }
    let p = vec2<f32>(gid.xy) + 0.5;
    let s = web_surface(gid.xy);
    let previous = s.position - s.velocity;
    let v = (p - ao_pixel(previous.xy, ao.previous_camera, ao.previous_lens)) + ao.motion_bias.xy;
    let i = vec2<i32>(gid.xy);
    textureStore(depth_out, i, vec4<f32>(ao.lens.x - s.position.z, 0.0, 0.0, 0.0));
    textureStore(reprojected_depth_out, i, vec4<f32>(ao.previous_lens.x - previous.z, 0.0, 0.0, 0.0));
    textureStore(motion_out, i, vec4<f32>(v, 0.0, 0.0));
}

@compute @workgroup_size(8, 8, 1)
fn web_sample(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= ao.width || gid.y >= ao.height) {
        return;
    }
    let i = vec2<i32>(gid.xy);
    let s = web_surface(gid.xy);
    let e = ao_estimate(gid.xy, s.position, s.normal, textureLoad(count_in, i, 0).x);
    textureStore(value_out, i, vec4<f32>(e.value, 0.0, 0.0, 0.0));
}

// Texel `p` of `t`, clamped to the frame.
fn web_load(t: texture_2d<f32>, p: vec2<i32>) -> f32 {
    let last = vec2<i32>(i32(web.width) - 1, i32(web.height) - 1);
    return textureLoad(t, clamp(p, vec2<i32>(0), last), 0).x;
}

// The TAA history at pixel position `q` (pixel centres at half-integers), bilinear.
fn web_history(q: vec2<f32>) -> f32 {
    let s = q - 0.5;
    let f = floor(s);
    let t = s - f;
    let b = vec2<i32>(f);
    let top = mix(web_load(taa_in, b), web_load(taa_in, b + vec2<i32>(1, 0)), t.x);
    let bottom = mix(web_load(taa_in, b + vec2<i32>(0, 1)), web_load(taa_in, b + vec2<i32>(1, 1)), t.x);
    return mix(top, bottom, t.y);
}

@compute @workgroup_size(8, 8, 1)
fn web_taa(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= web.width || gid.y >= web.height) {
        return;
    }
    let i = vec2<i32>(gid.xy);
    let c = textureLoad(value_in, i, 0).x;
    var lo = c;
    var hi = c;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let n = web_load(value_in, i + vec2<i32>(dx, dy));
            lo = min(lo, n);
            hi = max(hi, n);
        }
    }
    var out = c;
    if (web.taa_history != 0u) {
        // Where this pixel's surface was in the previous frame (motion: current - previous).
        let q = vec2<f32>(gid.xy) + 0.5 - textureLoad(motion_in, i, 0).xy;
        let size = vec2<f32>(f32(web.width), f32(web.height));
        if (all(q >= vec2<f32>(0.0)) && all(q < size)) {
            out = mix(clamp(web_history(q), lo, hi), c, web.taa_alpha);
        }
    }
    textureStore(taa_out, i, vec4<f32>(out, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(8, 8, 1)
fn web_reference(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= ao.width || gid.y >= ao.height) {
        return;
    }
    let i = vec2<i32>(gid.xy);
    let s = web_surface(gid.xy);
    let e = ao_estimate(gid.xy, s.position, s.normal, web.reference_rays);
    // The first pass starts the mean (whatever an earlier reference left in the texture).
    let mean = textureLoad(reference_in, i, 0).x;
    let k = f32(web.reference_passes);
    let next = select(mean + (e.value - mean) / (k + 1.0), e.value, web.reference_passes == 0u);
    textureStore(reference_out, i, vec4<f32>(next, 0.0, 0.0, 0.0));
}

// A heat colour for `t` in [0, 1]: dark blue, violet, red, orange, pale yellow.
fn web_heat(t: f32) -> vec3<f32> {
    let stops = array<vec3<f32>, 5>(
        vec3<f32>(0.05, 0.03, 0.25),
        vec3<f32>(0.40, 0.10, 0.60),
        vec3<f32>(0.85, 0.20, 0.30),
        vec3<f32>(1.00, 0.60, 0.10),
        vec3<f32>(1.00, 1.00, 0.70),
    );
    let x = clamp(t, 0.0, 1.0) * 4.0;
    let k = min(u32(x), 3u);
    return mix(stops[k], stops[k + 1u], x - f32(k));
}

@compute @workgroup_size(8, 8, 1)
fn web_compose(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= 3u * web.width || gid.y >= web.height) {
        return;
    }
    let panel = gid.x / web.width;
    let p = vec2<u32>(gid.x - panel * web.width, gid.y);
    let i = vec2<i32>(p);
    let resolved = textureLoad(taa_in, i, 0).x;
    // The resolved AO under a key light from the upper left, for the shapes only (seen
    // from above, an unoccluded sphere is as white as the ground), the floating objects
    // tinted; the measured signal stays the AO.
    let s = web_surface(p);
    let key = 0.55 + 0.45 * max(dot(s.normal, vec3<f32>(-0.45, -0.45, 0.77)), 0.0);
    var rgb = resolved * key * select(vec3<f32>(1.0), vec3<f32>(0.75, 0.85, 1.0), s.moving);
    if (panel == 1u) {
        let n = textureLoad(count_in, i, 0).x;
        rgb = select(web_heat(f32(n) / web.count_scale), vec3<f32>(0.0), n == 0u);
    } else if (panel == 2u) {
        if (web.has_reference != 0u) {
            rgb = web_heat(abs(resolved - textureLoad(reference_in, i, 0).x) * web.error_gain);
        } else {
            // No reference for this view: a dim checkerboard.
            let c = ((gid.x / 8u) + (gid.y / 8u)) % 2u;
            rgb = vec3<f32>(0.12 + 0.04 * f32(c));
        }
    }
    textureStore(image_out, vec2<i32>(gid.xy), vec4<f32>(rgb, 1.0));
}

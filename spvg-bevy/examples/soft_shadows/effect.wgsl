// A user-written stochastic effect: soft shadows from a rectangular area light onto the
// visible surfaces, occluded by a set of spheres. Per pixel it takes `n` shadow rays
// (n = spvg's count, or a fixed count), multiplies the main pass colour by the visibility
// and writes the visibility (the pass's Monte Carlo result) as spvg's monitored value.
// The light points come from spvg's R2 sequence (the library's `spvg_pixel_seed`,
// `spvg_r2_*`, `spvg_to_unit_f32`).

struct Effect {
    world_from_clip: mat4x4<f32>,
    light_corner: vec4<f32>,
    light_u: vec4<f32>,
    light_v: vec4<f32>,
    size: vec2<u32>,
    frame: u32,
    // 0: take spvg's count; otherwise this many samples everywhere.
    fixed_count: u32,
    sphere_count: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    spheres: array<vec4<f32>, 16>,
}

@group(0) @binding(0) var<uniform> e: Effect;
@group(0) @binding(1) var depth: texture_depth_2d;
@group(0) @binding(2) var count: texture_2d<u32>;
@group(0) @binding(3) var source: texture_2d<f32>;

@vertex
fn vertex(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // One triangle covering the viewport.
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

struct Out {
    @location(0) color: vec4<f32>,
    @location(1) value: f32,
}

// First hit distance of the ray `o + t d` (|d| = 1) with the sphere `s`, or a negative
// number.
fn hit(o: vec3<f32>, d: vec3<f32>, s: vec4<f32>) -> f32 {
    let oc = o - s.xyz;
    let b = dot(oc, d);
    let c = dot(oc, oc) - s.w * s.w;
    let h = b * b - c;
    if h < 0.0 {
        return -1.0;
    }
    let r = sqrt(h);
    let t0 = -b - r;
    if t0 > 1.0e-3 {
        return t0;
    }
    return -b + r;
}

@fragment
fn fragment(@builtin(position) position: vec4<f32>) -> Out {
    let p = vec2<i32>(position.xy);
    let src = textureLoad(source, p, 0);
    let d = textureLoad(depth, p, 0);
    var out: Out;
    if d <= 0.0 {
        // Background: nothing to shadow.
        out.color = src;
        out.value = 1.0;
        return out;
    }
    var n = e.fixed_count;
    if n == 0u {
        n = textureLoad(count, p, 0).x;
    }
    let uv = position.xy / vec2<f32>(e.size);
    let w = e.world_from_clip * vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, d, 1.0);
    let x = w.xyz / w.w;
    var visible = 0u;
    for (var i = 0u; i < n; i++) {
        // Independent samples (pcg3d16 of pixel, frame and sample index): the variance
        // the controller measures is then sigma^2 / n, the model its counts are built on.
        let r = spvg_pcg3d16(vec3<u32>(u32(p.x), u32(p.y), e.frame * 4096u + i)) << vec3<u32>(16u);
        let l = e.light_corner.xyz + e.light_u.xyz * spvg_to_unit_f32(r.x)
            + e.light_v.xyz * spvg_to_unit_f32(r.y);
        let to_light = l - x;
        let dist = length(to_light);
        let dir = to_light / dist;
        var blocked = false;
        for (var k = 0u; k < e.sphere_count; k++) {
            let t = hit(x, dir, e.spheres[k]);
            if t > 1.0e-3 && t < dist {
                blocked = true;
            }
        }
        visible += select(1u, 0u, blocked);
    }
    let vis = f32(visible) / f32(max(n, 1u));
    out.color = vec4<f32>(src.rgb * vis, src.a);
    out.value = vis;
    return out;
}

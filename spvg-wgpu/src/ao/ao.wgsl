// The second consumer of the adaptive component: stochastic ambient occlusion on a
// procedural height field (a plane with one jittered sphere per 32-pixel cell, plus one
// moving sphere), seen from above by an orthographic camera that pans, rotates and dollies
// (moves towards the plane, zooming with its height).
// Two entry points, each one pass of a renderer around the component:
// - ao_gbuffer: the visible surface per pixel: depth, motion vector (this frame's position
//   minus the previous frame's, in pixels), normal, position, and the reprojected depth
//   (the surface point's depth as the previous camera saw it);
// - ao_sample: `count` cosine-weighted occlusion rays per pixel (count from the component),
//   writes the AO estimate: the monitored value of the component's update; and the
//   estimates of the first `prefixes` samples, which are fixed-count runs for free.
// Uses the spvg-shaders library for the sample sequence (spvg_pixel_seed,
// spvg_r2_offset_from_seed, spvg_r2_point, spvg_to_unit_f32) and the pass's `unit_dir`.
// Rust twin: `spvg_wgpu::ao::twin` (one function per entry point, same op order).

// Rust twin: `spvg_wgpu::ao::AoParams`; same field order and types.
struct AoParams {
    width: u32,
    height: u32,
    frame: u32,
    pad: u32,
    // Camera: world xy of the frame centre, and cos/sin of its rotation; now and before.
    camera: vec4<f32>,
    previous_camera: vec4<f32>,
    // The moving sphere: centre and radius now, and its motion per frame (xyz).
    mover: vec4<f32>,
    mover_velocity: vec4<f32>,
    // The lens: camera height (the plane's depth), world units per pixel, pixels per world
    // unit; now and before.
    lens: vec4<f32>,
    previous_lens: vec4<f32>,
    // Added to every motion vector (0 unless a broken motion buffer is modelled).
    motion_bias: vec4<f32>,
    // Sample counts whose partial estimates ao_sample also writes (0: none).
    prefixes: vec4<u32>,
}

const AO_CELL: f32 = 64.0;
const AO_RANGE: f32 = 16.0;
const AO_OFFSET: f32 = 0.001;

@group(0) @binding(0) var<uniform> ao: AoParams;
// ao_gbuffer
@group(0) @binding(1) var depth_out: texture_storage_2d<r32float, write>;
@group(0) @binding(2) var motion_out: texture_storage_2d<rg32float, write>;
@group(0) @binding(3) var position_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(4) var normal_out: texture_storage_2d<rgba32float, write>;
// ao_sample
@group(0) @binding(5) var count_in: texture_2d<u32>;
@group(0) @binding(6) var position_in: texture_2d<f32>;
@group(0) @binding(7) var normal_in: texture_2d<f32>;
@group(0) @binding(8) var value_out: texture_storage_2d<r32float, write>;
// ao_gbuffer
@group(0) @binding(9) var reprojected_depth_out: texture_storage_2d<r32float, write>;
// ao_sample: the estimate of the first ao.prefixes[j] samples in channel j.
@group(0) @binding(10) var prefix_out: texture_storage_2d<rgba32float, write>;

// The sphere of cell (ix, iy): centre xy jittered inside the cell, radius 4..12, centre
// height from half buried to resting on the plane.
fn ao_cell_sphere(ix: i32, iy: i32) -> vec4<f32> {
    let h = spvg_pcg3d16(vec3<u32>(bitcast<u32>(ix) + 4096u, bitcast<u32>(iy) + 4096u, 7u));
    let fx = f32(h.x >> 8u) * (1.0 / 256.0);
    let fz = f32(h.x & 255u) * (1.0 / 256.0);
    let fy = f32(h.y) * (1.0 / 65536.0);
    let r = 4.0 + 8.0 * (f32(h.z) * (1.0 / 65536.0));
    let cx = (f32(ix) + (0.25 + 0.5 * fx)) * AO_CELL;
    let cy = (f32(iy) + (0.25 + 0.5 * fy)) * AO_CELL;
    return vec4<f32>(cx, cy, r * (1.5 * fz - 0.5), r);
}

struct AoSurface {
    position: vec3<f32>,
    normal: vec3<f32>,
    // 1 when the point is on the moving sphere.
    moving: bool,
}

// The top surface at world (x, y): the highest sphere cap over the plane z = 0.
fn ao_surface(x: f32, y: f32) -> AoSurface {
    var s: AoSurface;
    s.position = vec3<f32>(x, y, 0.0);
    s.normal = vec3<f32>(0.0, 0.0, 1.0);
    s.moving = false;
    let ix = i32(floor(x / AO_CELL));
    let iy = i32(floor(y / AO_CELL));
    for (var k = 0; k < 10; k++) {
        var c: vec4<f32>;
        if (k == 9) {
            c = ao.mover;
        } else {
            c = ao_cell_sphere(ix + k % 3 - 1, iy + k / 3 - 1);
        }
        let dx = x - c.x;
        let dy = y - c.y;
        let d2 = dx * dx + dy * dy;
        let r2 = c.w * c.w;
        if (d2 < r2) {
            let z = c.z + sqrt(r2 - d2);
            if (z > s.position.z) {
                s.position.z = z;
                s.normal = vec3<f32>(dx, dy, z - c.z) * (1.0 / c.w);
                s.moving = k == 9;
            }
        }
    }
    return s;
}

// World xy of pixel p (centre) under `camera` with `lens`.
fn ao_world(p: vec2<f32>, camera: vec4<f32>, lens: vec4<f32>) -> vec2<f32> {
    let q = (p - 0.5 * vec2<f32>(f32(ao.width), f32(ao.height))) * lens.y;
    return vec2<f32>(camera.x + (camera.z * q.x - camera.w * q.y),
                     camera.y + (camera.w * q.x + camera.z * q.y));
}

// Pixel position (not rounded) of world xy under `camera` with `lens`.
fn ao_pixel(w: vec2<f32>, camera: vec4<f32>, lens: vec4<f32>) -> vec2<f32> {
    let d = w - camera.xy;
    let q = vec2<f32>(camera.z * d.x + camera.w * d.y, camera.z * d.y - camera.w * d.x) * lens.z;
    return q + 0.5 * vec2<f32>(f32(ao.width), f32(ao.height));
}

@compute @workgroup_size(8, 8, 1)
fn ao_gbuffer(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= ao.width || gid.y >= ao.height) {
        return;
    }
    let p = vec2<f32>(gid.xy) + 0.5;
    let w = ao_world(p, ao.camera, ao.lens);
    let s = ao_surface(w.x, w.y);
    var previous = s.position;
    if (s.moving) {
        previous = previous - ao.mover_velocity.xyz;
    }
    let v = (p - ao_pixel(previous.xy, ao.previous_camera, ao.previous_lens)) + ao.motion_bias.xy;
    let i = vec2<i32>(gid.xy);
    textureStore(depth_out, i, vec4<f32>(ao.lens.x - s.position.z, 0.0, 0.0, 0.0));
    textureStore(reprojected_depth_out, i, vec4<f32>(ao.previous_lens.x - previous.z, 0.0, 0.0, 0.0));
    textureStore(motion_out, i, vec4<f32>(v, 0.0, 0.0));
    textureStore(position_out, i, vec4<f32>(s.position, 1.0));
    textureStore(normal_out, i, vec4<f32>(s.normal, 0.0));
}

// Whether the ray o + t d, 0 < t < AO_RANGE, hits a sphere near o or the plane.
fn ao_occluded(o: vec3<f32>, d: vec3<f32>) -> bool {
    if (d.z < 0.0 && -o.z / d.z < AO_RANGE) {
        return true;
    }
    let ix = i32(floor(o.x / AO_CELL));
    let iy = i32(floor(o.y / AO_CELL));
    for (var k = 0; k < 10; k++) {
        var c: vec4<f32>;
        if (k == 9) {
            c = ao.mover;
        } else {
            c = ao_cell_sphere(ix + k % 3 - 1, iy + k / 3 - 1);
        }
        let oc = o - c.xyz;
        let b = dot(oc, d);
        let disc = b * b - (dot(oc, oc) - c.w * c.w);
        if (disc >= 0.0) {
            let t = -b - sqrt(disc);
            if (t > 0.0 && t < AO_RANGE) {
                return true;
            }
        }
    }
    return false;
}

struct AoEstimate {
    value: f32,
    // The estimate of the first ao.prefixes[j] samples (0 where that prefix is 0 or
    // longer than n): the value a fixed count of ao.prefixes[j] gives, bit for bit, since
    // the sample sequence does not depend on the count.
    prefix: vec4<f32>,
}

// Fraction of `n` cosine-weighted directions around `normal` that escape.
fn ao_estimate(pixel: vec2<u32>, position: vec3<f32>, normal: vec3<f32>, n: u32) -> AoEstimate {
    var e: AoEstimate;
    e.value = 0.0;
    e.prefix = vec4<f32>(0.0);
    if (n == 0u) {
        return e;
    }
    let offset = spvg_r2_offset_from_seed(spvg_pixel_seed(pixel.x, pixel.y, ao.frame));
    // Orthonormal basis around the normal (Duff et al. 2017).
    let sgn = select(-1.0, 1.0, normal.z >= 0.0);
    let a = -1.0 / (sgn + normal.z);
    let b = normal.x * normal.y * a;
    let t = vec3<f32>(1.0 + sgn * normal.x * normal.x * a, sgn * b, -sgn * normal.x);
    let bt = vec3<f32>(b, sgn + normal.y * normal.y * a, -normal.y);
    let o = position + normal * AO_OFFSET;
    var open = 0u;
    for (var m = 0u; m < n; m++) {
        let u = spvg_r2_point(offset, m);
        let u1 = spvg_to_unit_f32(u.x);
        let disk = sqrt(u1) * unit_dir(u.y);
        let d = t * disk.x + bt * disk.y + normal * sqrt(1.0 - u1);
        if (!ao_occluded(o, d)) {
            open += 1u;
        }
        for (var j = 0; j < 4; j++) {
            if (ao.prefixes[j] == m + 1u) {
                e.prefix[j] = f32(open) / f32(m + 1u);
            }
        }
    }
    e.value = f32(open) / f32(n);
    return e;
}

@compute @workgroup_size(8, 8, 1)
fn ao_sample(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= ao.width || gid.y >= ao.height) {
        return;
    }
    let i = vec2<i32>(gid.xy);
    let n = textureLoad(count_in, i, 0).x;
    let position = textureLoad(position_in, i, 0).xyz;
    let normal = textureLoad(normal_in, i, 0).xyz;
    let e = ao_estimate(gid.xy, position, normal, n);
    textureStore(value_out, i, vec4<f32>(e.value, 0.0, 0.0, 0.0));
    textureStore(prefix_out, i, e.prefix);
}

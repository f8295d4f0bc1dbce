// The second consumer of the adaptive component: stochastic ambient occlusion on a
// procedural height field (a plane with one jittered sphere per 64-pixel cell, plus up to
// three moving spheres and a moving bar), seen from above by an orthographic camera that pans, rotates and dollies
// (moves towards the plane, zooming with its height).
// Two entry points, each one pass of a renderer around the component:
// - ao_gbuffer: the visible surface per pixel: depth, motion vector (this frame's position
//   minus the previous frame's, in pixels), normal, position, and the reprojected depth
//   (the surface point's depth as the previous camera saw it);
// - ao_sample: `count` cosine-weighted occlusion rays per pixel (count from the component),
//   writes the AO estimate: the monitored value of the component's update; and the
//   estimates of the first `prefixes` samples, which are fixed-count runs for free;
//   ao_sample_classified (ao_classified.wgsl) the same under the component's
//   count-classified dispatch, ao_sample_one_pass (ao_one_pass.wgsl) the same with the
//   component's estimate and update inside it (its one-pass form).
// Uses the spvg-shaders library for the sample sequence (spvg_pixel_seed,
// spvg_r2_offset_from_seed, spvg_r2_point, spvg_to_unit_f32) and the pass's `unit_dir`.
// Rust twin: `spvg_effects::ao::twin` (one function per entry point, same op order).

// Rust twin: `spvg_effects::ao::AoParams`; same field order and types.
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
    // Two more moving spheres (radius 0: none) and their motion per frame.
    extra_movers: array<vec4<f32>, 2>,
    extra_velocities: array<vec4<f32>, 2>,
    // The moving bar: an axis-aligned box (low and high corner; none unless high > low on
    // every axis) and its motion per frame.
    bar_min: vec4<f32>,
    bar_max: vec4<f32>,
    bar_velocity: vec4<f32>,
}

const AO_CELL: f32 = 64.0;
const AO_RANGE: f32 = 16.0;
const AO_OFFSET: f32 = 0.001;
// Beyond any ray parameter (the slab test of a ray parallel to a slab).
const AO_BIG: f32 = 1.0e30;

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

// Candidate sphere k near cell (ix, iy): 0..8 the 3x3 cells around it, 9 the mover,
// 10 and 11 the extra movers.
const AO_SPHERES: i32 = 12;

fn ao_sphere(k: i32, ix: i32, iy: i32) -> vec4<f32> {
    if (k == 9) {
        return ao.mover;
    }
    if (k >= 10) {
        return ao.extra_movers[k - 10];
    }
    return ao_cell_sphere(ix + k % 3 - 1, iy + k / 3 - 1);
}

// The motion per frame of candidate sphere k (0 for the static ones).
fn ao_sphere_velocity(k: i32) -> vec3<f32> {
    if (k == 9) {
        return ao.mover_velocity.xyz;
    }
    if (k >= 10) {
        return ao.extra_velocities[k - 10].xyz;
    }
    return vec3<f32>(0.0);
}

struct AoSurface {
    position: vec3<f32>,
    normal: vec3<f32>,
    // True when the point is on a moving object.
    moving: bool,
    // That object's motion per frame (0 when static).
    velocity: vec3<f32>,
}

// The top surface at world (x, y): the highest sphere cap or bar top over the plane z = 0.
fn ao_surface(x: f32, y: f32) -> AoSurface {
    var s: AoSurface;
    s.position = vec3<f32>(x, y, 0.0);
    s.normal = vec3<f32>(0.0, 0.0, 1.0);
    s.moving = false;
    s.velocity = vec3<f32>(0.0);
    let ix = i32(floor(x / AO_CELL));
    let iy = i32(floor(y / AO_CELL));
    for (var k = 0; k < AO_SPHERES; k++) {
        let c = ao_sphere(k, ix, iy);
        let dx = x - c.x;
        let dy = y - c.y;
        let d2 = dx * dx + dy * dy;
        let r2 = c.w * c.w;
        if (d2 < r2) {
            let z = c.z + sqrt(r2 - d2);
            if (z > s.position.z) {
                s.position.z = z;
                s.normal = vec3<f32>(dx, dy, z - c.z) * (1.0 / c.w);
                s.moving = k >= 9;
                s.velocity = ao_sphere_velocity(k);
            }
        }
    }
    // The bar's top face, where it is above everything else.
    let lo = ao.bar_min;
    let hi = ao.bar_max;
    if (x >= lo.x && x < hi.x && y >= lo.y && y < hi.y && hi.z > lo.z && hi.z > s.position.z) {
        s.position.z = hi.z;
        s.normal = vec3<f32>(0.0, 0.0, 1.0);
        s.moving = true;
        s.velocity = ao.bar_velocity.xyz;
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
    let previous = s.position - s.velocity;
    let v = (p - ao_pixel(previous.xy, ao.previous_camera, ao.previous_lens)) + ao.motion_bias.xy;
    let i = vec2<i32>(gid.xy);
    textureStore(depth_out, i, vec4<f32>(ao.lens.x - s.position.z, 0.0, 0.0, 0.0));
    textureStore(reprojected_depth_out, i, vec4<f32>(ao.previous_lens.x - previous.z, 0.0, 0.0, 0.0));
    textureStore(motion_out, i, vec4<f32>(v, 0.0, 0.0));
    textureStore(position_out, i, vec4<f32>(s.position, 1.0));
    textureStore(normal_out, i, vec4<f32>(s.normal, 0.0));
}

// The parameter interval (near, far) of the ray o + t d inside the slab lo <= x < hi of
// one axis (o, d, lo, hi that axis's components); empty (near > far) when it misses. A
// ray parallel to the slab is inside it everywhere or nowhere.
fn ao_slab(o: f32, d: f32, lo: f32, hi: f32) -> vec2<f32> {
    if (d == 0.0) {
        if (o >= lo && o < hi) {
            return vec2<f32>(-AO_BIG, AO_BIG);
        }
        return vec2<f32>(AO_BIG, -AO_BIG);
    }
    let a = (lo - o) / d;
    let b = (hi - o) / d;
    return vec2<f32>(min(a, b), max(a, b));
}

// Whether the ray o + t d, 0 < t < AO_RANGE, enters the bar.
fn ao_hits_bar(o: vec3<f32>, d: vec3<f32>) -> bool {
    let lo = ao.bar_min;
    let hi = ao.bar_max;
    if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) {
        return false;
    }
    let sx = ao_slab(o.x, d.x, lo.x, hi.x);
    let sy = ao_slab(o.y, d.y, lo.y, hi.y);
    let sz = ao_slab(o.z, d.z, lo.z, hi.z);
    let near = max(max(sx.x, sy.x), sz.x);
    let far = min(min(sx.y, sy.y), sz.y);
    return near <= far && far > 0.0 && near < AO_RANGE;
}

// Whether the ray o + t d, 0 < t < AO_RANGE, hits a sphere near o, the bar, or the plane.
fn ao_occluded(o: vec3<f32>, d: vec3<f32>) -> bool {
    if (d.z < 0.0 && -o.z / d.z < AO_RANGE) {
        return true;
    }
    if (ao_hits_bar(o, d)) {
        return true;
    }
    let ix = i32(floor(o.x / AO_CELL));
    let iy = i32(floor(o.y / AO_CELL));
    for (var k = 0; k < AO_SPHERES; k++) {
        let c = ao_sphere(k, ix, iy);
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
    ao_sample_at(gid);
}

// The body of `ao_sample` for the pixel `gid`: the whole-frame entry above and the
// classified one below run the same code.
fn ao_sample_at(gid: vec3<u32>) {
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

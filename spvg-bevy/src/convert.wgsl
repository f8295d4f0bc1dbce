// Bevy's prepass outputs to the component's inputs, one texel of the view per invocation.
//
// - Viewport: Bevy's prepass textures span the whole render target, while the component's
//   frame is the camera's viewport; invocation `id` converts the prepass texel
//   `id + origin`, so a viewport at any origin reads its own pixels.
// - Depth: Bevy's prepass depth is NDC depth (reverse-Z, 1 at the near plane, 0 at the far
//   plane or at infinity). The component compares linear depths with a relative tolerance,
//   so the NDC value is taken back to view space through the inverse projection and the
//   distance along the view axis (-z, Bevy's view space looks down -z) is stored.
// - Motion: Bevy stores current minus previous position in UV units of the viewport (+x
//   right, +y down); the component takes the same difference in pixels, so the vector is
//   scaled by the viewport size. The sign needs no change.
// - Mask: non-zero where the prepass wrote geometry (depth > 0). Background texels get the
//   far depth `FAR`, a finite stand-in for infinity so that no non-finite value reaches the
//   component.

// Twin of `ConvertBlock` in convert.rs.
struct Convert {
    view_from_clip: mat4x4<f32>,
    // The viewport's size and its origin on the render target, in pixels.
    size: vec2<u32>,
    origin: vec2<u32>,
    // 1: pixels without geometry are outside the mask; 0: every pixel is covered.
    skip_background: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

const FAR: f32 = 1.0e30;

@group(0) @binding(0) var<uniform> u: Convert;
@group(0) @binding(1) var depth: texture_depth_2d;
@group(0) @binding(2) var motion: texture_2d<f32>;
@group(0) @binding(3) var out_depth: texture_storage_2d<r32float, write>;
@group(0) @binding(4) var out_motion: texture_storage_2d<rg32float, write>;
@group(0) @binding(5) var out_mask: texture_storage_2d<r32uint, write>;

@compute @workgroup_size(8, 8)
fn convert(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= u.size) {
        return;
    }
    let p = vec2<i32>(id.xy);
    let t = vec2<i32>(id.xy + u.origin);
    let size = vec2<f32>(u.size);
    let d = textureLoad(depth, t, 0);
    let uv = (vec2<f32>(id.xy) + 0.5) / size;
    let view = u.view_from_clip * vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, d, 1.0);
    let linear = -view.z / view.w;
    // `linear == linear` rejects NaN; the bound rejects infinity.
    let geometry = d > 0.0 && linear > 0.0 && linear < FAR && linear == linear;
    textureStore(out_depth, p, vec4<f32>(select(FAR, linear, geometry), 0.0, 0.0, 0.0));
    // A non-finite or absurd vector passes through: the component takes it as a
    // disocclusion (the motion bound of `spvg::reproject`).
    let m = textureLoad(motion, t, 0).xy * size;
    textureStore(out_motion, p, vec4<f32>(m, 0.0, 0.0));
    let covered = geometry || u.skip_background == 0u;
    textureStore(out_mask, p, vec4<u32>(select(0u, 1u, covered), 0u, 0u, 0u));
}

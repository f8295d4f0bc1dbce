// ao_sample in the component's one-pass form (`AdaptivePass::one_pass_wgsl`, joined before
// this file with the component's group at 1): the estimate, the occlusion rays and the
// update in one dispatch. Each invocation asks the component for its pixel's count
// (`spvg_one_pass_begin`), takes that many rays (`ao_estimate` of ao.wgsl), writes the AO
// estimate and hands it to the component as the monitored value (`spvg_one_pass_end`).
// Both calls sit at the top level: every invocation reaches their workgroup barriers.
// Rust twin: `spvg_effects::ao::twin` (the component's twin, then `ao_sample`).

@compute @workgroup_size(8, 8, 1)
fn ao_sample_one_pass(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let s = spvg_one_pass_begin(gid, lid);
    var e: AoEstimate;
    if (s.inside) {
        let i = vec2<i32>(s.pixel);
        let position = textureLoad(position_in, i, 0).xyz;
        let normal = textureLoad(normal_in, i, 0).xyz;
        e = ao_estimate(s.pixel, position, normal, s.count);
        textureStore(value_out, i, vec4<f32>(e.value, 0.0, 0.0, 0.0));
        textureStore(prefix_out, i, e.prefix);
    }
    spvg_one_pass_end(s, e.value, 0.0);
}

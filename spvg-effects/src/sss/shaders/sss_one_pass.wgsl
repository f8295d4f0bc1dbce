// sss_sample in the component's one-pass form (`AdaptivePass::one_pass_wgsl`, joined after
// sss.wgsl with the component's group at 2; group 1 is the tile lists' of sss.wgsl): the
// estimate, the distant samples and the update in one dispatch. Each invocation asks the
// component for its pixel's count (`spvg_one_pass_begin`, which reads the distant-energy
// ratio sss_gamma wrote), takes that many samples (`estimate_pixel`), writes the result
// and hands the monitored and control luminances to the component (`spvg_one_pass_end`).
// Both calls sit at the top level: every invocation reaches their workgroup barriers.
// CPU twin: the component's twin around `spvg_effects::sss::twin::sss_sample`.

@compute @workgroup_size(8, 8, 1)
fn sss_sample_one_pass(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let s = spvg_one_pass_begin(gid, lid);
    var e: PixelEstimate;
    if (s.inside) {
        let p = vec2<i32>(s.pixel);
        if (textureLoad(mask, p, 0).x == 0u) {
            textureStore(result_out, p, vec4<f32>(0.0));
        } else {
            // Count 0 (the zero-sample rule) gives the near part alone.
            e = estimate_pixel(p, s.count);
            textureStore(result_out, p, result_texel(e.result));
        }
    }
    spvg_one_pass_end(s, dot(LUMA, e.fbar), dot(LUMA, e.g));
}

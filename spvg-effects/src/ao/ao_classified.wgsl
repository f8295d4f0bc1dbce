// ao_sample under the component's count-classified dispatch
// (`AdaptivePass::dispatch_classified`), joined after ao.wgsl: recorded once per class of
// tiles, each invocation taking the pixel `adaptive_class_pixel` (the component's
// `AdaptivePass::CLASSIFIED_WGSL`) gives it: the pixels of a tile by the class of their
// counts.
@compute @workgroup_size(8, 8, 1)
fn ao_sample_classified(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) index: u32,
) {
    let p = adaptive_class_pixel(wg, groups, index);
    if (p.z == 0u) {
        ao_sample_at(p);
    }
}

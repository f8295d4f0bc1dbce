// Per-frame parameters shared by every entry point of the subsurface pass: the WGSL
// library's block (spvg_Params, from spvg_shaders::WGSL) and the pass's own fields.
// Rust twin: `spvg_effects::sss::PassParams` (spvg-wgpu/src/sss/params.rs). Keep the field order,
// types and count identical; `tests/layout.rs` round-trips every field through a GPU buffer.
struct PassParams {
    spvg: spvg_Params,
    width: u32,
    height: u32,
    frame: u32,
    fixed_count: u32,
    texel_diag: f32,
    w_px: f32,
    h_px: f32,
    d_r: f32,
    d_g: f32,
    d_b: f32,
    d_s: f32,
    inv_d_r: f32,
    inv_d_g: f32,
    inv_d_b: f32,
    inv_d_s: f32,
    afis: u32,
    max_mip: u32,
    lmax: f32,
    reserved0: u32,
    reserved1: u32,
}

//! The effects' wgpu helpers: the component's public ones ([`spvg_wgpu::util`]), and
//! their own WGSL assembly and texture uploads.

pub(crate) use spvg_wgpu::util::{
    bind_group, compute_pipeline, dispatch_8x8, read_buffer, read_texture, shader_module,
    texture_2d, texture_2d_desc, view,
};

/// Uploads `data`, tightly packed rows of `texel_bytes`-byte texels, to the whole of mip
/// `mip_level` of `texture`, which is `[w, h]` texels.
pub(crate) fn write_texture_level(
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    mip_level: u32,
    data: &[u8],
    texel_bytes: u32,
    [w, h]: [u32; 2],
) {
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        data,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * texel_bytes),
            rows_per_image: Some(h),
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
}

/// One WGSL module source from its parts, in order (a plain concatenation: the library
/// first, then the files that call it), each preceded by a comment naming it.
pub(crate) fn assemble(parts: &[(&str, &str)]) -> String {
    let mut s = String::new();
    for (name, src) in parts {
        s.push_str("// ---- ");
        s.push_str(name);
        s.push('\n');
        s.push_str(src);
    }
    s
}

/// Writes one `R32Float` image of `size`.
pub(crate) fn write_scalar(
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    size: [u32; 2],
    data: &[f32],
) {
    write_texture_level(queue, texture, 0, bytemuck::cast_slice(data), 4, size);
}

//! The bind group layouts of the component's three entry points (group 0, compute stage,
//! float textures unfilterable; the module docs' table).

use wgpu::TextureFormat as Tf;

use super::inputs::{COUNT_FORMAT, HISTORY_FORMAT};

fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

const FLOAT: wgpu::TextureSampleType = wgpu::TextureSampleType::Float { filterable: false };
const UINT: wgpu::TextureSampleType = wgpu::TextureSampleType::Uint;

fn storage_entry(binding: u32, format: Tf) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        count: None,
    }
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The estimate step's bind group layout (group 0); see the module docs' table.
pub(super) fn estimate_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    vec![
        uniform_entry(0),
        uniform_entry(1),
        texture_entry(2, FLOAT),
        texture_entry(3, FLOAT),
        texture_entry(4, FLOAT),
        texture_entry(5, FLOAT),
        texture_entry(6, UINT),
        texture_entry(7, UINT),
        texture_entry(8, FLOAT),
        storage_entry(9, COUNT_FORMAT),
        storage_entry(10, Tf::R32Uint),
        texture_entry(18, FLOAT),
        storage_entry(19, Tf::R32Float),
        uniform_entry(22),
        storage_entry(23, Tf::R32Float),
        texture_entry(25, FLOAT),
    ]
}

/// The dilation's bind group layout: the estimate's counts in (13), the dilated out (9).
pub(super) fn dilate_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    vec![
        uniform_entry(0),
        uniform_entry(1),
        texture_entry(13, UINT),
        storage_entry(9, COUNT_FORMAT),
        texture_entry(20, FLOAT),
    ]
}

/// The update step's bind group layout (group 0); bindings 16 and 17 for OCV only.
pub(super) fn update_entries(ocv: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
    let mut e = vec![
        uniform_entry(0),
        uniform_entry(1),
        texture_entry(2, FLOAT),
        texture_entry(11, FLOAT),
        texture_entry(12, FLOAT),
        texture_entry(13, UINT),
        texture_entry(14, UINT),
        storage_entry(15, HISTORY_FORMAT),
        texture_entry(20, FLOAT),
        texture_entry(21, FLOAT),
        texture_entry(24, FLOAT),
        texture_entry(26, FLOAT),
    ];
    if ocv {
        e.push(texture_entry(16, FLOAT));
        e.push(storage_entry(17, HISTORY_FORMAT));
    }
    e
}

/// The one-pass form's bind group layout (the renderer's choice of group): the
/// controller, the component's block, the history read, the estimate's inputs, the count
/// (stored where asked), the history write, the frame index, and for OCV the CV history
/// read and write. Three storage textures with OCV, two without: a renderer under
/// WebGPU's default limit of four per stage keeps one or two for its own outputs.
pub(super) fn one_pass_entries(ocv: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
    let mut e = vec![
        uniform_entry(0),
        uniform_entry(1),
        texture_entry(2, FLOAT),
        texture_entry(3, FLOAT),
        texture_entry(4, FLOAT),
        texture_entry(5, FLOAT),
        texture_entry(6, UINT),
        texture_entry(7, UINT),
        texture_entry(8, FLOAT),
        storage_entry(9, COUNT_FORMAT),
        storage_entry(15, HISTORY_FORMAT),
        texture_entry(18, FLOAT),
        uniform_entry(22),
        texture_entry(25, FLOAT),
    ];
    if ocv {
        e.push(texture_entry(16, FLOAT));
        e.push(storage_entry(17, HISTORY_FORMAT));
    }
    e
}

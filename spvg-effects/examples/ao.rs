//! The smallest renderer that uses the adaptive component: ambient occlusion on a
//! procedural height field (`src/ao/ao.wgsl`), a camera panning 2 px per frame, the
//! component deciding the samples per pixel. Writes `ao.png` (the AO of the last frame),
//! `ao-spp.png` (its samples per pixel, white = 64) and `ao-link.png` (a debug view of the
//! component's link texture: white where the pixel continued a reprojected history, black
//! where it had none: the strip the pan uncovered at the right edge, disocclusions).
//!
//! `cargo run --release -p spvg-wgpu --example ao -- [OUT_DIR]`

use spvg::SpvgConfig;
use spvg_effects::ao::{AoParams, AoScene, Motion, ao_source};
use spvg_wgpu::adaptive::{AdaptivePass, AdaptiveSettings, EstimateInputs, UpdateInputs};
use spvg_wgpu::util::read_texture;
use wgpu::{TextureFormat as Tf, TextureUsages as Tu};

const W: u32 = 256;
const H: u32 = 160;
const FRAMES: u32 = 30;

fn texture(device: &wgpu::Device, format: Tf) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width: W,
            height: H,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: Tu::STORAGE_BINDING | Tu::TEXTURE_BINDING | Tu::COPY_SRC,
        view_formats: &[],
    })
}

fn bind(
    device: &wgpu::Device,
    pipeline: &wgpu::ComputePipeline,
    params: &wgpu::Buffer,
    textures: &[(u32, &wgpu::Texture)],
) -> wgpu::BindGroup {
    let views: Vec<_> = textures
        .iter()
        .map(|(b, t)| (*b, t.create_view(&Default::default())))
        .collect();
    let mut entries = vec![wgpu::BindGroupEntry {
        binding: 0,
        resource: params.as_entire_binding(),
    }];
    entries.extend(views.iter().map(|(b, v)| wgpu::BindGroupEntry {
        binding: *b,
        resource: wgpu::BindingResource::TextureView(v),
    }));
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    })
}

fn dispatch(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    group: &wgpu::BindGroup,
) {
    let mut pass = encoder.begin_compute_pass(&Default::default());
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, group, &[]);
    pass.dispatch_workgroups(W.div_ceil(8), H.div_ceil(8), 1);
}

fn write_png(path: &std::path::Path, gray: &[u8]) -> Result<(), Box<dyn std::error::Error>> {
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), W, H);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header()?.write_image_data(gray)?;
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "out".into()));
    let gpu = spvg_wgpu::util::acquire_device()?;
    let (device, queue) = (&gpu.device, &gpu.queue);
    eprintln!("running on {}", gpu.describe());

    // The component: AS, target variance 1e-4, budget [8, 64].
    let settings = AdaptiveSettings {
        config: SpvgConfig::<f32>::builder().target_variance(1e-4).build()?,
        // Occlusion is a rare event at the rim of an occluder: spend the largest count
        // within 1 px (docs/algorithms.md §2.5).
        dilation: 1,
        ..AdaptiveSettings::default()
    };
    let mut adaptive = AdaptivePass::new(device, settings, W, H)?;

    // The renderer's own passes and targets.
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("ao"),
        source: wgpu::ShaderSource::Wgsl(ao_source().into()),
    });
    let pipeline = |entry: &str| {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: None,
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    };
    let (gbuffer, sample) = (pipeline("ao_gbuffer"), pipeline("ao_sample"));
    let params = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("AoParams"),
        size: size_of::<AoParams>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let depth = [texture(device, Tf::R32Float), texture(device, Tf::R32Float)];
    let motion = texture(device, Tf::Rg32Float);
    let position = texture(device, Tf::Rgba32Float);
    let normal = texture(device, Tf::Rgba32Float);
    let value = texture(device, Tf::R32Float);

    let scene = AoScene {
        width: W,
        height: H,
        motion: Motion::Pan { speed: 2.0 },
    };
    for t in 0..FRAMES {
        let (cur, prev) = ((t % 2) as usize, ((t + 1) % 2) as usize);
        queue.write_buffer(&params, 0, bytemuck::bytes_of(&scene.params(t)));
        let mut encoder = device.create_command_encoder(&Default::default());
        // 1. G-buffer: depth, motion vectors (pixels, current - previous), position, normal.
        let g = [(1, &depth[cur]), (2, &motion), (3, &position), (4, &normal)];
        dispatch(&mut encoder, &gbuffer, &bind(device, &gbuffer, &params, &g));
        // 2. The component decides the counts from the reprojected history.
        adaptive.record_estimate(
            &mut encoder,
            &EstimateInputs::new(&motion, &depth[cur], &depth[prev]),
        )?;
        // 3. The renderer samples: `count` occlusion rays per pixel.
        let s = [
            (5, adaptive.count_texture()),
            (6, &position),
            (7, &normal),
            (8, &value),
        ];
        dispatch(&mut encoder, &sample, &bind(device, &sample, &params, &s));
        // 4. The component folds the AO estimate into the history.
        adaptive.record_update(&mut encoder, &UpdateInputs::new(&value))?;
        queue.submit([encoder.finish()]);
    }

    write_images(&out, device, queue, &adaptive, &value)
}

/// Reads back the last frame and writes its AO, its samples per pixel and the
/// component's link (the debug view of the reprojection) as PNGs in `out`.
fn write_images(
    out: &std::path::Path,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    adaptive: &AdaptivePass,
    value: &wgpu::Texture,
) -> Result<(), Box<dyn std::error::Error>> {
    let ao: Vec<f32> = read_texture(device, queue, value)?;
    let spp: Vec<u32> = read_texture(device, queue, adaptive.count_texture())?;
    let mean = spp.iter().map(|&n| f64::from(n)).sum::<f64>() / spp.len() as f64;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let to_byte = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    write_png(
        &out.join("ao.png"),
        &ao.iter().map(|&a| to_byte(a)).collect::<Vec<_>>(),
    )?;
    let spp_img: Vec<u8> = spp.iter().map(|&n| to_byte(n as f32 / 64.0)).collect();
    write_png(&out.join("ao-spp.png"), &spp_img)?;
    // The link: the previous frame's texel index + 1 whose history the pixel continued, or
    // 0 (no valid history).
    let link: Vec<u32> = read_texture(device, queue, adaptive.link_texture())?;
    let link_img: Vec<u8> = link.iter().map(|&l| if l == 0 { 0 } else { 255 }).collect();
    write_png(&out.join("ao-link.png"), &link_img)?;
    let fresh = link.iter().filter(|&&l| l == 0).count();
    println!(
        "wrote {}/ao.png, ao-spp.png and ao-link.png: frame {}, mean {mean:.1} spp (fixed: \
         64), {fresh} pixels without history",
        out.display(),
        FRAMES - 1
    );
    Ok(())
}

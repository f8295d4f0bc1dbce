//! `PassParams` (Rust) and `struct PassParams` (WGSL) hold the same fields at the same
//! offsets: every field is written with a distinct value, read in the shader by name and
//! copied out as raw bits in declaration order.

mod common;

use spvg_effects::sss::{PARAMS_WGSL, PassParams};

/// The `(name, type)` fields of `struct name` in a WGSL source (comment lines skipped).
fn struct_fields(src: &str, name: &str) -> Vec<(String, String)> {
    let body = src
        .split(&format!("struct {name} {{"))
        .nth(1)
        .unwrap_or_default();
    let body = body.split('}').next().unwrap_or_default();
    body.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .filter_map(|l| {
            let l = l.trim().trim_end_matches(',');
            let (name, ty) = l.split_once(':')?;
            Some((name.trim().to_string(), ty.trim().to_string()))
        })
        .collect()
}

/// The scalar fields of `struct PassParams`, the library's `spvg_Params` member expanded
/// (`spvg.eta`, ...), in declaration order.
fn wgsl_fields() -> Vec<(String, String)> {
    let src = PARAMS_WGSL;
    let mut out = Vec::new();
    for (name, ty) in struct_fields(src, "PassParams") {
        if ty == "spvg_Params" {
            for (inner, ity) in struct_fields(spvg_shaders::PARAMS, "spvg_Params") {
                out.push((format!("{name}.{inner}"), ity));
            }
        } else {
            out.push((name, ty));
        }
    }
    out
}

#[test]
fn rust_and_wgsl_param_layouts_match() {
    let fields = wgsl_fields();
    assert_eq!(
        fields.len() * 4,
        size_of::<PassParams>(),
        "WGSL field count {} does not match the Rust struct size {}",
        fields.len(),
        size_of::<PassParams>()
    );
    let Some(dev) = spvg_gpu_test::GpuTest::new("rust_and_wgsl_param_layouts_match").device()
    else {
        return;
    };
    // Distinct bit patterns that are also ordinary floats (no NaN canonicalisation).
    let words: Vec<u32> = (0..fields.len() as u32)
        .map(|i| (1.5_f32 + i as f32).to_bits())
        .collect();
    let params: PassParams = bytemuck::pod_read_unaligned(bytemuck::cast_slice(&words));
    assert_eq!(
        bytemuck::cast_slice::<PassParams, u32>(core::slice::from_ref(&params)),
        words.as_slice(),
        "bytemuck round trip"
    );

    let mut body = String::new();
    for (i, (name, ty)) in fields.iter().enumerate() {
        let expr = if ty == "u32" {
            format!("params.{name}")
        } else {
            format!("bitcast<u32>(params.{name})")
        };
        body.push_str(&format!("    out[{i}] = {expr};\n"));
    }
    let params_src = PARAMS_WGSL;
    let src = format!(
        "{}{params_src}\n@group(0) @binding(0) var<uniform> params: PassParams;\n\
         @group(0) @binding(1) var<storage, read_write> out: array<u32>;\n\
         @compute @workgroup_size(1)\nfn main() {{\n{body}}}\n",
        spvg_shaders::PARAMS
    );
    let d = &dev.device;
    let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("layout"),
        source: wgpu::ShaderSource::Wgsl(src.into()),
    });
    let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: None,
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let size = (words.len() * 4) as u64;
    let uniform = d.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    dev.queue
        .write_buffer(&uniform, 0, bytemuck::bytes_of(&params));
    let storage = d.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = d.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bg = d.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: storage.as_entire_binding(),
            },
        ],
    });
    let mut enc = d.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bg, &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }
    enc.copy_buffer_to_buffer(&storage, 0, &read, 0, size);
    dev.queue.submit([enc.finish()]);
    read.slice(..)
        .map_async(wgpu::MapMode::Read, |r| assert!(r.is_ok(), "map failed"));
    d.poll(wgpu::PollType::wait_indefinitely()).expect("poll");
    let got: Vec<u32> =
        bytemuck::pod_collect_to_vec(&read.slice(..).get_mapped_range().expect("mapped"));
    for (i, ((name, _), (g, w))) in fields.iter().zip(got.iter().zip(&words)).enumerate() {
        assert_eq!(
            g, w,
            "field {i} `{name}`: WGSL read {g:#x}, Rust wrote {w:#x}"
        );
    }
}

//! The one-pass form at zero samples: a renderer's dispatch that asks the component for
//! its counts and hands back a value without taking a sample, so that its time is the
//! component's own inside the renderer's dispatch (its reads and writes, its workgroup
//! barriers), against a copy kernel moving the bytes the component adds.

use crate::error::ReportError;
use crate::wgpu_api::{AdaptivePass, EstimateInputs, GpuDevice};

/// The renderer's entry point: the component's group is 0, the renderer binds nothing of
/// its own; its "value" is a pattern of the pixel (no load, no sample).
const CONSUMER: &str = "
@compute @workgroup_size(8, 8, 1)
fn zero_samples(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let s = spvg_one_pass_begin(gid, lid);
    let value = 0.25 + 0.125 * f32((s.pixel.x ^ s.pixel.y) & 3u) + 0.01 * f32(s.count);
    spvg_one_pass_end(s, value, 0.0);
}
";

/// The zero-sample renderer of one component.
pub(super) struct ZeroSamples {
    pipeline: wgpu::ComputePipeline,
    size: [u32; 2],
}

impl ZeroSamples {
    pub(super) fn new(d: &GpuDevice, pass: &AdaptivePass) -> Self {
        let source = format!("{}{}{CONSUMER}", spvg_shaders::WGSL, pass.one_pass_wgsl(0));
        let module = d.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("one pass at zero samples"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let layout = d
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("one pass at zero samples"),
                bind_group_layouts: &[Some(pass.one_pass_layout())],
                immediate_size: 0,
            });
        let pipeline = d
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("one pass at zero samples"),
                layout: Some(&layout),
                module: &module,
                entry_point: Some("zero_samples"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            });
        Self {
            pipeline,
            size: pass.size(),
        }
    }

    /// Records one frame of `pass` in one pass.
    pub(super) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pass: &mut AdaptivePass,
        inputs: &EstimateInputs<'_>,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), ReportError> {
        let group = pass.one_pass_group(inputs)?;
        let mut c = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("one pass at zero samples"),
            timestamp_writes,
        });
        c.set_pipeline(&self.pipeline);
        c.set_bind_group(0, &group, &[]);
        c.dispatch_workgroups(self.size[0].div_ceil(8), self.size[1].div_ceil(8), 1);
        Ok(())
    }
}

//! The copy kernel: a compute shader that reads and writes a step's bytes per pixel as
//! `R32Uint` planes, the floor the step's time is compared with.

use std::fmt::Write as _;

use wgpu::{TextureFormat as Tf, TextureUsages as Tu};

use super::bytes::{StepBytes, texel};
use super::inputs::{noise, texture, upload};
use crate::error::ReportError;
use crate::wgpu_api::GpuDevice;

/// The copy kernel of one step: `read / 4` source planes and `written / 4` destination
/// planes, `R32Uint`, the frame size; each invocation loads its texel of every source,
/// folds them (so no load is dead) and stores into every destination.
pub(super) struct CopyKernel {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    size: [u32; 2],
    /// The destination planes, for the test to read back.
    #[cfg(test)]
    destinations: Vec<wgpu::Texture>,
}

/// Source plane `k`'s word at pixel `(x, y)`: noise, a different pattern per plane.
fn source_word(x: u32, y: u32, k: u32) -> u32 {
    noise(x, y, 7 + k).to_bits()
}

/// The copy kernel's WGSL for `sources` and `destinations` planes.
pub(super) fn copy_wgsl(sources: u32, destinations: u32) -> String {
    let mut s = String::new();
    for k in 0..sources {
        let _ = writeln!(s, "@group(0) @binding({k}) var src{k}: texture_2d<u32>;");
    }
    for k in 0..destinations {
        let _ = writeln!(
            s,
            "@group(0) @binding({}) var dst{k}: texture_storage_2d<r32uint, write>;",
            sources + k
        );
    }
    s.push_str(
        "@compute @workgroup_size(8, 8)\nfn copy(@builtin(global_invocation_id) id: vec3<u32>) {\n\
         \x20   let size = textureDimensions(dst0);\n\
         \x20   if (id.x >= size.x || id.y >= size.y) { return; }\n\
         \x20   let p = vec2<i32>(id.xy);\n\
         \x20   var acc = 0u;\n",
    );
    for k in 0..sources {
        let _ = writeln!(s, "    acc ^= textureLoad(src{k}, p, 0).x;");
    }
    for k in 0..destinations {
        let _ = writeln!(
            s,
            "    textureStore(dst{k}, p, vec4<u32>(acc + {k}u, 0u, 0u, 0u));"
        );
    }
    s.push_str("}\n");
    s
}

impl CopyKernel {
    pub(super) fn new(
        d: &GpuDevice,
        size: [u32; 2],
        bytes: StepBytes,
    ) -> Result<Self, ReportError> {
        let word = texel(Tf::R32Uint);
        if !bytes.read.is_multiple_of(word)
            || !bytes.written.is_multiple_of(word)
            || bytes.written == 0
        {
            return Err(ReportError::Usage(format!(
                "copy kernel: {} bytes read and {} written per pixel are not whole, non-zero \
                 4-byte words",
                bytes.read, bytes.written
            )));
        }
        let (sources, destinations) = ((bytes.read / word) as u32, (bytes.written / word) as u32);
        let module = d.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("readiness copy"),
            source: wgpu::ShaderSource::Wgsl(copy_wgsl(sources, destinations).into()),
        });
        let pipeline = d
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("readiness copy"),
                layout: None,
                module: &module,
                entry_point: Some("copy"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            });
        // Sources filled with noise, so a GPU cannot skip the reads of cleared memory.
        let [w, h] = size;
        let plane = |k: u32| -> Vec<u8> {
            (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .flat_map(|(x, y)| source_word(x, y, k).to_le_bytes())
                .collect()
        };
        #[cfg_attr(
            not(test),
            expect(unused_mut, reason = "the test takes the destinations")
        )]
        let mut planes: Vec<wgpu::Texture> = (0..sources)
            .map(|k| upload(d, "readiness copy source", Tf::R32Uint, size, &plane(k)))
            .chain((0..destinations).map(|_| {
                texture(
                    d,
                    "readiness copy destination",
                    Tf::R32Uint,
                    size,
                    // COPY_SRC: the test reads what the kernel wrote.
                    Tu::STORAGE_BINDING | Tu::COPY_SRC,
                )
            }))
            .collect();
        let views: Vec<wgpu::TextureView> = planes
            .iter()
            .map(|t| t.create_view(&wgpu::TextureViewDescriptor::default()))
            .collect();
        let entries: Vec<wgpu::BindGroupEntry<'_>> = views
            .iter()
            .zip(0..)
            .map(|(v, binding)| wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(v),
            })
            .collect();
        let group = d.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("readiness copy"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        Ok(Self {
            pipeline,
            group,
            size,
            #[cfg(test)]
            destinations: planes.split_off(sources as usize),
        })
    }

    pub(super) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let [w, h] = self.size;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("readiness copy"),
            timestamp_writes,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wgpu_api::acquire_device;

    /// The kernel reads every source plane and writes every destination: each destination
    /// word is the XOR of the sources' words plus the plane's index, computed here on the
    /// host.
    #[test]
    fn copy_kernel_reads_every_source_and_writes_every_destination() {
        let Ok(d) = acquire_device() else {
            eprintln!("copy kernel test: SKIPPED, no wgpu adapter");
            return;
        };
        let size = [13, 7];
        let bytes = StepBytes {
            read: 12,
            written: 8,
        };
        let kernel = CopyKernel::new(&d, size, bytes).expect("whole words");
        let mut encoder = d.device.create_command_encoder(&Default::default());
        kernel.record(&mut encoder, None);
        d.queue.submit([encoder.finish()]);
        assert_eq!(
            kernel.destinations.len(),
            2,
            "8 bytes = 2 destination planes"
        );
        for (k, t) in (0u32..).zip(&kernel.destinations) {
            let got: Vec<u32> =
                crate::wgpu_api::read_texture(&d.device, &d.queue, t).expect("readback");
            for (i, g) in got.iter().enumerate() {
                let (x, y) = (i as u32 % size[0], i as u32 / size[0]);
                let want = (0..3)
                    .fold(0, |a, s| a ^ source_word(x, y, s))
                    .wrapping_add(k);
                assert_eq!(*g, want, "destination {k} at ({x}, {y})");
            }
        }
        assert!(
            CopyKernel::new(
                &d,
                size,
                StepBytes {
                    read: 6,
                    written: 8
                }
            )
            .is_err(),
            "6 bytes are not whole words"
        );
    }
}

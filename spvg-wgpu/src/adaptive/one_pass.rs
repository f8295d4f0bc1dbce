//! The one-pass form of the component: the estimate and the update inside the renderer's
//! own compute dispatch (`one_pass.wgsl`), as the seeds ran them. The component keeps the
//! histories, the reprojection, the settings and the bind group; the renderer's shader
//! joins the module, calls `spvg_one_pass_begin` before its samples and
//! `spvg_one_pass_end` after them, and its pipeline layout holds
//! [`AdaptivePass::one_pass_layout`] at the group it chose.

use wgpu::util::DeviceExt as _;

use super::params::{FLAG_COUNT_ORDER, FLAG_STORE_COUNTS};
use super::pass::params_block;
use super::{AdaptiveError, AdaptivePass, EstimateInputs, one_pass_source};
use crate::util::{bind_group, view};

impl AdaptivePass {
    /// The one-pass module for this component's control model: WGSL that a renderer's
    /// compute shader joins after [`spvg_shaders::WGSL`], with the component's bindings at
    /// group `group` (choose one the shader leaves free). It declares, besides its
    /// bindings and workgroup arrays (every name prefixed `spvg_ad_`):
    ///
    /// - `spvg_one_pass_begin(gid, lid) -> spvg_OnePass`: this invocation's decision
    ///   (`.pixel`, the pixel; `.count`, its samples this frame);
    /// - `spvg_one_pass_end(s, value, control)`: the new history from the monitored value
    ///   (`fbar`) and the control value (`G`; CCV and OCV, any value for AS);
    /// - `spvg_one_pass_end_guided(s, value, control, guide)`: with the renderer's TAA
    ///   guide (its resolved history `C_t` at the pixel; a non-finite guide is the unguided
    ///   update).
    ///
    /// The entry point is `@workgroup_size(8, 8, 1)`, dispatched over the frame's 8 x 8
    /// tiles ([`util::dispatch_8x8`](crate::util::dispatch_8x8)), and calls both functions
    /// at its top level, from every invocation (both hold a workgroup barrier):
    ///
    /// ```wgsl
    /// @compute @workgroup_size(8, 8, 1)
    /// fn my_sample(@builtin(global_invocation_id) gid: vec3<u32>,
    ///              @builtin(local_invocation_id) lid: vec3<u32>) {
    ///     let s = spvg_one_pass_begin(gid, lid);
    ///     var value = 0.0;
    ///     for (var k = 0u; k < s.count; k++) { value += my_sample_at(s.pixel, k); }
    ///     if (s.count != 0u) { value /= f32(s.count); }
    ///     spvg_one_pass_end(s, value, 0.0);
    /// }
    /// ```
    ///
    /// The module depends on the control model (OCV binds its control-variate history):
    /// build the renderer's pipeline again after a
    /// [`set_settings`](Self::set_settings) that changes the model.
    #[must_use]
    pub fn one_pass_wgsl(&self, group: u32) -> String {
        one_pass_source(group, self.frame.cv.is_some())
    }

    /// The layout of the one-pass module's group: the renderer's pipeline layout holds it
    /// at the group it gave [`one_pass_wgsl`](Self::one_pass_wgsl). Two storage textures
    /// (the count, the history), three with OCV (its history): under WebGPU's default
    /// limit of four per stage the renderer keeps the others for its own outputs.
    #[must_use]
    pub fn one_pass_layout(&self) -> &wgpu::BindGroupLayout {
        &self.one_pass_layout
    }

    /// Whether the one-pass form writes each frame's counts to
    /// [`count_texture`](Self::count_texture) (off by default: nothing goes to memory but
    /// the histories). Turn it on for a debug view of the counts, or to read them back.
    pub fn set_one_pass_counts(&mut self, on: bool) {
        self.one_pass_counts = on;
    }

    /// Whether the one-pass form's invocations take the pixels of their tile by rank of
    /// count (on by default): a SIMD group runs consecutive invocations together, and with
    /// the order its lanes hold similar counts, so its sampling loop runs about as long as
    /// its pixels need rather than as long as the largest count among them. The counts,
    /// the samples of each pixel and the histories are the same either way; the renderer
    /// takes its pixel from the decision's `.pixel`, never from its invocation id. It costs
    /// two workgroup barriers and 64 reads of workgroup memory per invocation.
    pub fn set_one_pass_order(&mut self, on: bool) {
        self.one_pass_order = on;
    }

    /// The bind group of one frame in the one-pass form: the renderer sets it at its
    /// group and records its dispatch of the one-pass entry point (once) before it asks
    /// for the next frame's. The frame then counts as updated: the next estimate (of
    /// either form) continues the history this dispatch writes, so the two forms can
    /// alternate frame by frame (they run the same rules).
    ///
    /// # Errors
    ///
    /// As [`record_estimate`](Self::record_estimate) for the inputs;
    /// [`AdaptiveError::OnePassBetweenSteps`] between a two-pass frame's estimate and its
    /// update. Nothing changes then.
    pub fn one_pass_group(
        &mut self,
        inputs: &EstimateInputs<'_>,
    ) -> Result<wgpu::BindGroup, AdaptiveError> {
        if self.estimated {
            return Err(AdaptiveError::OnePassBetweenSteps);
        }
        let (mut flags, mut views) = self.estimate_views(inputs)?;
        if self.one_pass_counts {
            flags |= FLAG_STORE_COUNTS;
        }
        if self.one_pass_order {
            flags |= FLAG_COUNT_ORDER;
        }
        let (r, w) = (self.read, 1 - self.read);
        views.extend([
            (9, view(&self.frame.count)),
            (15, view(&self.frame.history[w])),
        ]);
        if let Some(cv) = &self.frame.cv {
            views.push((16, view(&cv[r])));
            views.push((17, view(&cv[w])));
        }
        // The frame's blocks: new buffers rather than queue writes, so recording needs no
        // queue (the one-pass switches would double the prebuilt blocks twice).
        let block = params_block(&self.settings, self.size(), flags);
        let block = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("AdaptiveParams one pass"),
                contents: bytemuck::bytes_of(&block),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let frame = self.frame_index_buffer();
        let group = bind_group(
            &self.device,
            Some("adaptive one pass"),
            &self.one_pass_layout,
            &[(0, &self.controller), (1, &block), (22, &frame)],
            &views,
        );
        self.read = w;
        self.resized_between_steps = false;
        self.frame_index = self.frame_index.wrapping_add(1);
        Ok(group)
    }
}

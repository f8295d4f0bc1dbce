//! The two recorded steps of [`AdaptivePass`]: the estimate (with the count dilation
//! when it is on) and the update, each checking its inputs before it binds them.

use super::inputs::{MASK_FORMATS, MOTION_FORMATS, SCALAR_FORMATS, check};
use super::params::{
    FLAG_GAMMA, FLAG_GUIDE, FLAG_MASKS, FLAG_MOMENT, FLAG_REPROJECTED_DEPTH, params_index,
};
use super::{AdaptiveError, AdaptivePass, AdaptiveTiles, EstimateInputs, UpdateInputs};
use wgpu::util::DeviceExt as _;

use crate::util::{bind_group, dispatch_8x8, view};

impl AdaptivePass {
    fn params(&self, flags: u32) -> &wgpu::Buffer {
        &self.frame.params[params_index(flags)]
    }

    fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        group: &wgpu::BindGroup,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let size = self.size();
        dispatch_8x8(encoder, label, pipeline, group, timestamp_writes, size);
    }

    /// Records the estimate step into `encoder`: reprojects the history, decides its
    /// validity once per pixel, and writes [`count_texture`](Self::count_texture) (0
    /// outside the mask and where the zero-sample rule holds) and the link the update reads.
    ///
    /// A second estimate before the frame's update replaces the first (documented, not an
    /// error): it reads the same history, since only the update advances it, and
    /// overwrites the count and link textures, so the update continues what the last
    /// recorded estimate decided (in submission order). A renderer that drops an encoder
    /// after recording the estimate can simply record it again.
    ///
    /// # Errors
    ///
    /// An input of the wrong size, format, usage or kind; nothing is recorded then.
    pub fn record_estimate(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &EstimateInputs<'_>,
    ) -> Result<(), AdaptiveError> {
        self.record_estimate_timed(encoder, inputs, None)
    }

    /// [`record_estimate`](Self::record_estimate) with timestamp writes on its compute
    /// pass (the device needs `wgpu::Features::TIMESTAMP_QUERY`), for a renderer that
    /// times its passes.
    ///
    /// # Errors
    ///
    /// As [`record_estimate`](Self::record_estimate).
    pub fn record_estimate_timed(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &EstimateInputs<'_>,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), AdaptiveError> {
        self.record_estimate_in(encoder, inputs, timestamp_writes, None)
    }

    /// The estimate over the whole frame, or over the listed tiles of `tiles` (without
    /// the count dilation: it moves counts across tiles).
    pub(super) fn record_estimate_in(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &EstimateInputs<'_>,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
        tiles: Option<&AdaptiveTiles>,
    ) -> Result<(), AdaptiveError> {
        let (flags, mut views) = self.estimate_views(inputs)?;
        views.extend([
            (
                9,
                view(self.frame.raw_count.as_ref().unwrap_or(&self.frame.count)),
            ),
            (10, view(&self.frame.link)),
            (19, view(&self.frame.surface)),
            (23, view(&self.frame.real)),
        ]);
        let frame = self.frame_index_buffer();
        let group = self.bind_group_with(
            "adaptive estimate",
            &self.estimate_layout,
            flags,
            &[(22, &frame)],
            &views,
        );
        // The step's passes: the estimate, the dilation, the classification's two; the
        // timestamps bracket them all (the first begins, the last ends).
        let dilated = self.frame.raw_count.is_some();
        let passes = 1 + usize::from(dilated) + 2 * usize::from(self.frame.classes.is_some());
        let mut stamps = bracket(timestamp_writes, passes).into_iter();
        let mut next = || stamps.next().flatten();
        match tiles.filter(|_| !dilated) {
            Some(t) => t.dispatch(
                encoder,
                "adaptive estimate tiles",
                t.estimate_pipeline(),
                &group,
                next(),
            ),
            None => self.dispatch(encoder, "adaptive estimate", &self.estimate, &group, next()),
        }
        if let Some(raw) = &self.frame.raw_count {
            let views = [
                (13, view(raw)),
                (9, view(&self.frame.count)),
                (20, view(&self.frame.surface)),
            ];
            let group = self.bind_group("adaptive dilate", &self.dilate_layout, 0, &views);
            self.dispatch(encoder, "adaptive dilate", &self.dilate, &group, next());
        }
        let classify = [next(), next()];
        self.record_classification(encoder, self.params(0), classify);
        (self.estimated, self.resized_between_steps) = (true, false);
        Ok(())
    }

    /// Records the update step into `encoder`: folds the renderer's monitored value (and
    /// for CCV/OCV the control value) into the history read through the estimate's link,
    /// writes the other ping-pong texture, and makes it the current history.
    ///
    /// The monitored value is taken as it is, negative values included (no clamp): the
    /// controller follows its variance, which does not depend on the sign, and the
    /// monitored quantity of CCV and OCV, `fbar - alpha G`, is signed anyway. A value of
    /// `-x` gives the counts of `x` and the history with the mean negated. A non-finite
    /// value is refused per pixel (the history is kept, or cleared where it was invalid:
    /// `spvg::SpvgConfig::update`).
    ///
    /// With [`UpdateInputs::guide`] the variance follows the deviation of the monitored
    /// value from the renderer's resolved TAA history instead of from the history's own
    /// mean (`spvg::SpvgConfig::update_guided`, docs/algorithms.md §8.5); the mean and the
    /// mean count are unchanged, and a non-finite guide texel gives the unguided update.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::UpdateWithoutEstimate`] (or
    /// [`AdaptiveError::ResizedBetweenSteps`] where a resize discarded the frame's
    /// estimate), [`AdaptiveError::MissingInput`] for CCV or
    /// OCV without a control value, or an input (`value`, `control`, `guide`) of the wrong
    /// size, format, usage or kind; nothing is recorded then.
    pub fn record_update(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &UpdateInputs<'_>,
    ) -> Result<(), AdaptiveError> {
        self.record_update_timed(encoder, inputs, None)
    }

    /// [`record_update`](Self::record_update) with timestamp writes on its compute pass
    /// (the device needs `wgpu::Features::TIMESTAMP_QUERY`), for a renderer that times
    /// its passes.
    ///
    /// # Errors
    ///
    /// As [`record_update`](Self::record_update).
    pub fn record_update_timed(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &UpdateInputs<'_>,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), AdaptiveError> {
        self.record_update_in(encoder, inputs, timestamp_writes, None, None)
    }

    /// [`record_update`](Self::record_update) with the frame's second moment: per pixel
    /// the mean of the squares of the samples whose mean is the monitored value
    /// (`sum(x * x) / n` beside `sum(x) / n`; `R32Float` or `R16Float`, the size of the
    /// frame). Where a pixel took at least 2 samples and its moment is finite, its
    /// variance follows the in-frame variance of its mean rather than its deviation from
    /// frame to frame (`spvg::SpvgConfig::update_moment`, docs/algorithms.md §8.8), so
    /// variance that samples cannot remove (sub-pixel jitter at edges, motion, a clamp
    /// in the resolve) buys no samples. With CCV and OCV (whose monitored value is not
    /// the samples' mean) the moment is ignored. The twin is
    /// [`AdaptiveTwin::update_with_moment`](super::AdaptiveTwin::update_with_moment).
    ///
    /// # Errors
    ///
    /// As [`record_update`](Self::record_update), and the input errors for `moment`.
    pub fn record_update_with_moment(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &UpdateInputs<'_>,
        moment: &wgpu::Texture,
    ) -> Result<(), AdaptiveError> {
        self.record_update_in(encoder, inputs, None, None, Some(moment))
    }

    /// The update over the whole frame, or over the listed tiles of `tiles` (the whole
    /// frame with the count dilation on, as the estimate).
    pub(super) fn record_update_in(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &UpdateInputs<'_>,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
        tiles: Option<&AdaptiveTiles>,
        moment: Option<&wgpu::Texture>,
    ) -> Result<(), AdaptiveError> {
        if !self.estimated {
            return Err(if self.resized_between_steps {
                AdaptiveError::ResizedBetweenSteps
            } else {
                AdaptiveError::UpdateWithoutEstimate
            });
        }
        let size = self.size();
        check("value", inputs.value, size, SCALAR_FORMATS)?;
        let control = match (inputs.control, self.settings.control.needs_control()) {
            (Some(c), true) => {
                check("control", c, size, SCALAR_FORMATS)?;
                c
            }
            (None, true) => {
                return Err(AdaptiveError::MissingInput {
                    input: "control",
                    reason: "CCV and OCV monitor fbar - alpha G",
                });
            }
            (_, false) => &self.dummy_float,
        };
        let mut flags = 0;
        if let Some(g) = inputs.guide {
            check("guide", g, size, SCALAR_FORMATS)?;
            flags |= FLAG_GUIDE;
        }
        if let Some(m) = moment {
            check("moment", m, size, SCALAR_FORMATS)?;
            flags |= FLAG_MOMENT;
        }
        let (r, w) = (self.read, 1 - self.read);
        let mut views = vec![
            (2, view(&self.frame.history[r])),
            (11, view(inputs.value)),
            (12, view(control)),
            (13, view(&self.frame.count)),
            (14, view(&self.frame.link)),
            (15, view(&self.frame.history[w])),
            (20, view(&self.frame.surface)),
            (21, view(inputs.guide.unwrap_or(&self.dummy_float))),
            (24, view(&self.frame.real)),
            (26, view(moment.unwrap_or(&self.dummy_float))),
        ];
        if let Some(cv) = &self.frame.cv {
            views.push((16, view(&cv[r])));
            views.push((17, view(&cv[w])));
        }
        let group = self.bind_group("adaptive update", &self.update_layout, flags, &views);
        match tiles.filter(|_| self.frame.raw_count.is_none()) {
            Some(t) => t.dispatch(
                encoder,
                "adaptive update tiles",
                t.update_pipeline(),
                &group,
                timestamp_writes,
            ),
            None => self.dispatch(
                encoder,
                "adaptive update",
                &self.update,
                &group,
                timestamp_writes,
            ),
        }
        self.read = w;
        self.estimated = false;
        self.frame_index = self.frame_index.wrapping_add(1);
        Ok(())
    }

    /// Checks the estimate's inputs and returns the flags of the optional ones bound and
    /// the views both forms bind for them: the history read (2), the motion, the depths,
    /// the masks, the distant-energy ratio and the reprojected depth (3 to 8, 18), and the
    /// resolve's weight (25).
    pub(super) fn estimate_views(
        &self,
        inputs: &EstimateInputs<'_>,
    ) -> Result<(u32, Vec<(u32, wgpu::TextureView)>), AdaptiveError> {
        let size = self.size();
        check("motion", inputs.motion, size, MOTION_FORMATS)?;
        check("depth", inputs.depth, size, SCALAR_FORMATS)?;
        check(
            "previous_depth",
            inputs.previous_depth,
            size,
            SCALAR_FORMATS,
        )?;
        let mut flags = 0;
        if let Some(m) = &inputs.masks {
            check("masks.current", m.current, size, MASK_FORMATS)?;
            check("masks.previous", m.previous, size, MASK_FORMATS)?;
            flags |= FLAG_MASKS;
        }
        if let Some(g) = inputs.gamma {
            check("gamma", g, size, SCALAR_FORMATS)?;
            flags |= FLAG_GAMMA;
        }
        if let Some(r) = inputs.reprojected_depth {
            check("reprojected_depth", r, size, SCALAR_FORMATS)?;
            flags |= FLAG_REPROJECTED_DEPTH;
        }
        if let Some(r) = inputs.resolve_weight {
            check("resolve_weight", r, size, SCALAR_FORMATS)?;
        }
        let (mask, prev_mask) = match &inputs.masks {
            Some(m) => (m.current, m.previous),
            None => (&self.dummy_uint, &self.dummy_uint),
        };
        let views = vec![
            (2, view(&self.frame.history[self.read])),
            (3, view(inputs.motion)),
            (4, view(inputs.depth)),
            (5, view(inputs.previous_depth)),
            (6, view(mask)),
            (7, view(prev_mask)),
            (8, view(inputs.gamma.unwrap_or(&self.dummy_float))),
            (
                18,
                view(inputs.reprojected_depth.unwrap_or(&self.dummy_float)),
            ),
            // Without an input, the 1x1 texel of zero: "none" wherever the shader's
            // clamped load lands (no flag, no uniform block of its own).
            (25, view(inputs.resolve_weight.unwrap_or(&self.dummy_float))),
        ];
        Ok((flags, views))
    }

    /// The frame index of the dither threshold (fractional counts): a new buffer rather
    /// than a queue write, as for the controller's block, so recording needs no queue.
    pub(super) fn frame_index_buffer(&self) -> wgpu::Buffer {
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("adaptive frame index"),
                contents: bytemuck::bytes_of(&[self.frame_index, 0, 0, 0]),
                usage: wgpu::BufferUsages::UNIFORM,
            })
    }

    fn bind_group(
        &self,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        flags: u32,
        views: &[(u32, wgpu::TextureView)],
    ) -> wgpu::BindGroup {
        self.bind_group_with(label, layout, flags, &[], views)
    }

    /// [`bind_group`](Self::bind_group) with more uniform buffers than the two blocks.
    pub(super) fn bind_group_with(
        &self,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        flags: u32,
        buffers: &[(u32, &wgpu::Buffer)],
        views: &[(u32, wgpu::TextureView)],
    ) -> wgpu::BindGroup {
        let params = self.params(flags);
        let mut all = vec![(0, &self.controller), (1, params)];
        all.extend_from_slice(buffers);
        bind_group(&self.device, Some(label), layout, &all, views)
    }
}

/// `writes` spread over `passes` compute passes recorded in a row: the first pass writes
/// the beginning, the last the end, the others nothing.
fn bracket(
    writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    passes: usize,
) -> Vec<Option<wgpu::ComputePassTimestampWrites<'_>>> {
    let Some(t) = writes else {
        return vec![None; passes];
    };
    (0..passes)
        .map(|k| {
            let begin = if k == 0 {
                t.beginning_of_pass_write_index
            } else {
                None
            };
            let end = if k + 1 == passes {
                t.end_of_pass_write_index
            } else {
                None
            };
            (begin.is_some() || end.is_some()).then_some(wgpu::ComputePassTimestampWrites {
                query_set: t.query_set,
                beginning_of_pass_write_index: begin,
                end_of_pass_write_index: end,
            })
        })
        .collect()
}

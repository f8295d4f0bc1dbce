//! The separable filter on a wgpu device: `sep_horizontal` then `sep_vertical`
//! (`shaders/separable.wgsl`), and their textures.

use half::f16;

use super::separable_tiles::SeparableTiles;
use super::twin::{HybridSources, check_sizes};
use crate::error::PassError;
use crate::gpu::{
    assemble, bind_group, compute_pipeline, dispatch_8x8, read_texture, shader_module, texture_2d,
    view, write_texture_level,
};
use crate::sss::{FrameInputs, FrameOutput, SeparableParams, TECHNIQUE_AFIS, Timer};
use spvg_wgpu::adaptive::AdaptiveTiles;

/// The separable passes (`shaders/separable.wgsl`).
pub const SEPARABLE_WGSL: &str = include_str!("shaders/separable.wgsl");

/// What a hybrid frame's separable passes share with its subsurface pass (the textures of
/// the frame just recorded there): its lighting (mip 0 becomes the first pass's input once
/// `sep_compose` has written the AFIS result into it), depth and mask, and its result
/// texture, which holds the AFIS result at the tagged pixels and into which the second
/// pass writes the others.
#[derive(Clone, Copy, Debug)]
pub(super) struct SharedTextures<'a> {
    pub(super) afis: &'a wgpu::Texture,
    pub(super) lighting: &'a wgpu::Texture,
    pub(super) depth: &'a wgpu::Texture,
    pub(super) mask: &'a wgpu::Texture,
}

/// The assembled separable passes: the WGSL library (for its f16 rounding) and the passes.
#[must_use]
pub fn separable_source() -> String {
    assemble(&[
        ("spvg_shaders::WGSL", spvg_shaders::WGSL),
        ("sss/shaders/separable.wgsl", SEPARABLE_WGSL),
    ])
}

/// The separable filter bound to one device and image size. A hybrid frame also uploads
/// the technique per pixel, and its first pass reads the AFIS result at the tagged pixels
/// ([`HybridSources`]): composed into the lighting on the host by
/// [`SeparablePass::run_frame`] (both passes over the whole frame), on the device by the
/// hybrid pass (both passes over the tiles that hold an untagged pixel: the same image).
#[derive(Debug)]
pub struct SeparablePass {
    device: wgpu::Device,
    queue: wgpu::Queue,
    size: [u32; 2],
    horizontal: wgpu::ComputePipeline,
    vertical: wgpu::ComputePipeline,
    /// `sep_horizontal_tiles` and `sep_vertical_tiles`: a hybrid frame's passes over
    /// [`SeparablePass::tiles`].
    horizontal_tiles: wgpu::ComputePipeline,
    vertical_tiles: wgpu::ComputePipeline,
    /// `sep_compose`: the AFIS result into a hybrid frame's lighting (the subsurface
    /// pass's) and the first pass's output at the tagged pixels.
    compose: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    lighting: wgpu::Texture,
    depth: wgpu::Texture,
    mask: wgpu::Texture,
    technique: wgpu::Texture,
    blurred: wgpu::Texture,
    result: wgpu::Texture,
    /// The technique ids last uploaded by [`SeparablePass::record_hybrid_inputs`]: the
    /// caller's tags change rarely, so they are uploaded when they change, not every frame.
    technique_ids: Vec<u8>,
    /// The tiles of those ids that hold an untagged pixel (rebuilt with them).
    tiles: SeparableTiles,
}

impl SeparablePass {
    /// Builds the pipelines and textures for a `width x height` image on the caller's
    /// device. wgpu panics on a frame beyond the device's limits: check sizes you did not
    /// choose with [`crate::check_frame_size`] first.
    #[must_use]
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, width: u32, height: u32) -> Self {
        let module = shader_module(device, "separable.wgsl", separable_source());
        let size = [width.max(1), height.max(1)];
        let tex = |label: &str, format, usage| texture_2d(device, label, format, size, usage);
        let input = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
        let output = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC;
        let rgba16 = wgpu::TextureFormat::Rgba16Float;
        Self {
            device: device.clone(),
            queue: queue.clone(),
            size: [width, height],
            horizontal: compute_pipeline(device, &module, "sep_horizontal", None),
            vertical: compute_pipeline(device, &module, "sep_vertical", None),
            horizontal_tiles: compute_pipeline(device, &module, "sep_horizontal_tiles", None),
            vertical_tiles: compute_pipeline(device, &module, "sep_vertical_tiles", None),
            compose: compute_pipeline(device, &module, "sep_compose", None),
            params: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("SeparableParams"),
                size: size_of::<SeparableParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            // A hybrid frame reads the subsurface pass's lighting instead.
            lighting: tex("separable lighting", rgba16, input),
            depth: tex("separable depth", wgpu::TextureFormat::R32Float, input),
            mask: tex("separable mask", wgpu::TextureFormat::R8Uint, input),
            technique: tex("separable technique", wgpu::TextureFormat::R8Uint, input),
            blurred: tex(
                "separable blurred",
                wgpu::TextureFormat::Rgba32Float,
                output | wgpu::TextureUsages::TEXTURE_BINDING,
            ),
            result: tex("separable result", rgba16, output),
            technique_ids: Vec::new(),
            tiles: SeparableTiles::new(device, [width, height]),
        }
    }

    /// Runs one frame: uploads the inputs (and the hybrid sources), records
    /// `sep_horizontal` and `sep_vertical`, reads back the result. Counts are all 0; the
    /// time is the wall time from submit to the wait's return.
    ///
    /// # Errors
    ///
    /// [`PassError::InputSize`] for inputs of another size than the pass (or a hybrid
    /// block without sources), [`PassError::Device`] when the device fails.
    pub fn run_frame(
        &mut self,
        params: &SeparableParams,
        inputs: &FrameInputs,
        hybrid: Option<HybridSources<'_>>,
    ) -> Result<FrameOutput, PassError> {
        let mut p = *params;
        [p.width, p.height] = self.size;
        check_sizes(&p, inputs, hybrid)?;
        if p.hybrid != 0 && hybrid.is_none() {
            return Err(PassError::InputSize {
                expected: inputs.len(),
                got: 0,
            });
        }
        if inputs.is_empty() {
            return Ok(FrameOutput::default());
        }
        self.upload(&p, inputs, hybrid);
        if hybrid.is_some() {
            // Uploaded by this frame: the ids of `record_hybrid` are no longer current.
            self.technique_ids.clear();
        }
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("separable"),
            });
        self.record_horizontal(&mut encoder, None);
        self.record_vertical(&mut encoder, None);
        let time_ms = super::pass::wait(&self.device, &self.queue, encoder)?;
        let result: Vec<[f16; 4]> = read_texture(&self.device, &self.queue, &self.result)?;
        Ok(FrameOutput {
            result,
            count: vec![0; inputs.len()],
            time_ms,
            timer: Timer::WallClock,
        })
    }

    /// Prepares a hybrid frame's two passes in `encoder` after the AFIS result of the
    /// same encoder: queues the frame's uploads (the block; the lighting, depth and mask
    /// are the subsurface pass's, `shared`; the technique ids, and the list of the tiles
    /// holding an untagged pixel, only when they changed) and records `sep_compose`
    /// over the listed `tiles` (those holding a tagged pixel), which writes the AFIS result
    /// into the first pass's input and output at the tagged pixels. The passes follow over
    /// the tiles holding an untagged pixel ([`SeparablePass::record_horizontal`] and
    /// [`SeparablePass::record_vertical`] with `shared`).
    ///
    /// # Errors
    ///
    /// [`PassError::InputSize`] for inputs or ids of another size than the pass,
    /// [`PassError::Param`] for a block not built for a hybrid frame.
    pub(super) fn record_hybrid_inputs(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        params: &SeparableParams,
        inputs: &FrameInputs,
        technique: &[u8],
        shared: &SharedTextures<'_>,
        tiles: &AdaptiveTiles,
    ) -> Result<(), PassError> {
        let mut p = *params;
        [p.width, p.height] = self.size;
        let n = self.size[0] as usize * self.size[1] as usize;
        if inputs.len() != n || technique.len() != n || !inputs.is_consistent() {
            return Err(PassError::InputSize {
                expected: n,
                got: inputs.len().min(technique.len()),
            });
        }
        self.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        if self.technique_ids != technique {
            write_texture_level(&self.queue, &self.technique, 0, technique, 1, self.size);
            technique.clone_into(&mut self.technique_ids);
            self.tiles.set(technique);
        }
        let views = [
            (4, view(&self.technique)),
            (5, view(shared.afis)),
            (6, view(&self.blurred)),
            (9, view(shared.lighting)),
        ];
        let layout = self.compose.get_bind_group_layout(0);
        let group = bind_group(
            &self.device,
            Some("sep_compose"),
            &layout,
            &[(0, &self.params)],
            &views,
        );
        tiles.dispatch(encoder, "sep_compose", &self.compose, &group, None);
        Ok(())
    }

    /// The bind group of one pass's `pipeline`: what its entry point reads (the layouts
    /// are derived from the shader): the first the lighting, the second the first's
    /// output; in a hybrid frame (`shared`) the subsurface pass's depth and mask, and the
    /// second writes into the AFIS result's texture.
    fn group(
        &self,
        vertical: bool,
        pipeline: &wgpu::ComputePipeline,
        shared: Option<&SharedTextures<'_>>,
    ) -> wgpu::BindGroup {
        let (lighting, depth, mask, result) = match shared {
            Some(s) => (s.lighting, s.depth, s.mask, s.afis),
            None => (&self.lighting, &self.depth, &self.mask, &self.result),
        };
        let mut views = vec![
            (2, view(depth)),
            (3, view(mask)),
            (4, view(&self.technique)),
        ];
        if vertical {
            views.push((7, view(&self.blurred)));
            views.push((8, view(result)));
        } else {
            views.push((1, view(lighting)));
            views.push((6, view(&self.blurred)));
        }
        let layout = pipeline.get_bind_group_layout(0);
        bind_group(
            &self.device,
            Some("separable"),
            &layout,
            &[(0, &self.params)],
            &views,
        )
    }

    /// Records `sep_horizontal` over the frame, or for a hybrid frame (`shared`, after
    /// [`SeparablePass::record_hybrid_inputs`]) `sep_horizontal_tiles` over the tiles
    /// holding an untagged pixel.
    pub(super) fn record_horizontal(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        shared: Option<&SharedTextures<'_>>,
    ) {
        if shared.is_some() {
            let h = &self.horizontal_tiles;
            let group = self.group(false, h, shared);
            self.tiles
                .dispatch(encoder, "sep_horizontal_tiles", h, &group);
        } else {
            let h = &self.horizontal;
            let group = self.group(false, h, None);
            dispatch_8x8(encoder, "sep_horizontal", h, &group, None, self.size);
        }
    }

    /// Records `sep_vertical` over the frame, or for a hybrid frame `sep_vertical_tiles`
    /// over the tiles holding an untagged pixel, into the AFIS result's texture (as
    /// [`SeparablePass::record_horizontal`]).
    pub(super) fn record_vertical(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        shared: Option<&SharedTextures<'_>>,
    ) {
        if shared.is_some() {
            let v = &self.vertical_tiles;
            let group = self.group(true, v, shared);
            self.tiles
                .dispatch(encoder, "sep_vertical_tiles", v, &group);
        } else {
            let v = &self.vertical;
            let group = self.group(true, v, None);
            dispatch_8x8(encoder, "sep_vertical", v, &group, None, self.size);
        }
    }

    fn upload(&self, p: &SeparableParams, inputs: &FrameInputs, hybrid: Option<HybridSources<'_>>) {
        self.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(p));
        let write = |texture: &wgpu::Texture, data: &[u8], texel_bytes: u32| {
            write_texture_level(&self.queue, texture, 0, data, texel_bytes, self.size);
        };
        write(&self.depth, bytemuck::cast_slice(&inputs.depth), 4);
        write(&self.mask, &inputs.mask, 1);
        let Some(hy) = hybrid else {
            write(&self.lighting, bytemuck::cast_slice(&inputs.lighting), 8);
            return;
        };
        // The first pass's input composed on the host: the AFIS result where tagged.
        let source: Vec<[f16; 4]> = inputs
            .lighting
            .iter()
            .zip(hy.technique.iter().zip(hy.afis))
            .map(|(&l, (&t, &a))| if t == TECHNIQUE_AFIS { a } else { l })
            .collect();
        write(&self.lighting, bytemuck::cast_slice(&source), 8);
        write(&self.technique, hy.technique, 1);
    }
}

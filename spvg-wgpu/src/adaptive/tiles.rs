//! The component's steps restricted to a list of 8 x 8 tiles ([`AdaptiveTiles`]): a
//! renderer that runs the adaptive count on part of the frame only (a focus region, the
//! hybrid pass's tagged pixels) pays for the listed tiles, not for the whole frame.
//!
//! The list is built on the CPU from a per-pixel region the caller provides, and uploaded
//! only when that region changes: the region is the caller's (it tags the frame), so it is
//! known on the CPU before the frame is recorded, and a list built there needs no GPU
//! compaction pass and no indirect dispatch. Each listed tile runs the same per-pixel body
//! as the whole-frame entry points (`tiles.wgsl`); unlisted pixels are not
//! written at all.

use wgpu::util::DeviceExt as _;

use super::{AdaptiveError, AdaptivePass, EstimateInputs, UpdateInputs, shader_source};
use crate::util::shader_module;

/// Side of a tile in pixels: the component's 8 x 8 workgroup.
const TILE: u32 = 8;

/// The tile-list entry points (`tiles.wgsl`), compiled after the component's module.
const TILES_WGSL: &str = include_str!("tiles.wgsl");

/// Most workgroups along one dispatch dimension (wgpu's default limit): a longer list is
/// dispatched on a 2-D grid.
const MAX_GROUPS: u32 = 65_535;

/// A list of the 8 x 8 tiles of a frame that hold a region pixel, and the component's
/// estimate and update compiled to run over it
/// ([`AdaptivePass::record_estimate_tiles`], [`AdaptivePass::record_update_tiles`]).
///
/// The restricted steps write the listed tiles only. They give a listed pixel exactly
/// what the whole-frame steps give it as long as what they would write elsewhere is what
/// is already there: a renderer whose unlisted pixels are outside the component's mask
/// (count 0, no history) runs the whole-frame steps for two frames after the region
/// changes (the history is a ping-pong pair, so both halves then hold the zeros of the
/// unlisted pixels), and the restricted ones from then on. With the count dilation on, the
/// restricted steps run over the whole frame: the dilation moves counts across tiles.
#[derive(Debug)]
pub struct AdaptiveTiles {
    device: wgpu::Device,
    size: [u32; 2],
    estimate: wgpu::ComputePipeline,
    update: wgpu::ComputePipeline,
    /// Whether the update is OCV's (it writes the CV history too).
    ocv: bool,
    tiles: Vec<u32>,
    /// The list on the device (`None` while it is empty: a storage binding cannot be
    /// empty, and an empty list dispatches nothing).
    buffer: Option<wgpu::Buffer>,
}

impl AdaptiveTiles {
    /// Side of a tile in pixels: the component's 8 x 8 workgroup.
    pub const TILE: u32 = TILE;

    /// The component's tile-list entry points (`tiles.wgsl`): how a listed tile is
    /// decoded (`x | y << 16` in tile units at group 1, binding 0, on the 2-D grid of
    /// [`dispatch`](Self::dispatch)). A renderer's own tile-list entry point decodes its
    /// tile the same way.
    pub const WGSL: &str = TILES_WGSL;

    /// The tile-list steps of `pass` (its size, its control model), with an empty list.
    #[must_use]
    pub fn new(pass: &AdaptivePass) -> Self {
        let device = &pass.device;
        let module = shader_module(
            device,
            "adaptive tiles.wgsl",
            format!("{}{TILES_WGSL}", shader_source(pass.frame.cv.is_some())),
        );
        let list = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("adaptive tile list"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let pipeline = |step: &wgpu::BindGroupLayout, entry: &str| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(entry),
                bind_group_layouts: &[Some(step), Some(&list)],
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            })
        };
        let ocv = pass.frame.cv.is_some();
        Self {
            device: device.clone(),
            size: pass.size(),
            estimate: pipeline(&pass.estimate_layout, "adaptive_estimate_tiles"),
            update: pipeline(&pass.update_layout, "adaptive_update_tiles"),
            ocv,
            tiles: Vec::new(),
            buffer: None,
        }
    }

    /// Lists the tiles that hold a nonzero pixel of `region` (row-major, one byte per
    /// pixel of the frame) and uploads the list if it differs from the current one.
    /// Returns whether it changed.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::SliceLength`] naming `region` when it is not `width * height`
    /// long; the list is kept then.
    pub fn set_region(&mut self, region: &[u8]) -> Result<bool, AdaptiveError> {
        let tiles = tile_list(region, self.size)?;
        if tiles == self.tiles {
            return Ok(false);
        }
        self.buffer = (!tiles.is_empty()).then(|| {
            self.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("adaptive tile list"),
                    contents: bytemuck::cast_slice(&tiles),
                    usage: wgpu::BufferUsages::STORAGE,
                })
        });
        self.tiles = tiles;
        Ok(true)
    }

    /// The listed tiles, each `x | y << 16` in tile units, in row-major order.
    #[must_use]
    pub fn tiles(&self) -> &[u32] {
        &self.tiles
    }

    /// The frame size the list was built for.
    #[must_use]
    pub fn size(&self) -> [u32; 2] {
        self.size
    }

    /// Records `pipeline` over the listed tiles: `group` at group 0 and the list at
    /// group 1 (binding 0, `var<storage, read> array<u32>`), one workgroup per tile on the
    /// grid `tiles.wgsl` reads back. For a renderer's own tile-list entry points (a
    /// `@workgroup_size(8, 8, 1)` entry that decodes its tile as `tiles.wgsl` does); an
    /// empty list records nothing.
    pub fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        group: &wgpu::BindGroup,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let Some(buffer) = &self.buffer else {
            return;
        };
        let list = TileList {
            buffer,
            tiles: self.tiles.len(),
        };
        list.record(
            &self.device,
            encoder,
            label,
            pipeline,
            group,
            timestamp_writes,
        );
    }

    /// Records `pipeline` over another list of `tiles` tiles in the component's encoding
    /// (`list`, a storage buffer of `x | y << 16` per tile, in tile units; the upper bit
    /// of each half is free for the caller's flags): `group` at group 0, the list at group
    /// 1, on the grid [`dispatch`](Self::dispatch) uses. For a renderer's second list over
    /// the same frame (the tiles a hybrid pass filters rather than samples).
    #[allow(
        clippy::too_many_arguments,
        reason = "the arguments of `dispatch` plus the list it would own"
    )]
    pub fn dispatch_list(
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        group: &wgpu::BindGroup,
        list: &wgpu::Buffer,
        tiles: usize,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        if tiles == 0 {
            return;
        }
        let list = TileList {
            buffer: list,
            tiles,
        };
        list.record(device, encoder, label, pipeline, group, timestamp_writes);
    }

    /// The estimate's tile-list pipeline.
    pub(super) fn estimate_pipeline(&self) -> &wgpu::ComputePipeline {
        &self.estimate
    }

    /// The update's tile-list pipeline.
    pub(super) fn update_pipeline(&self) -> &wgpu::ComputePipeline {
        &self.update
    }
}

impl AdaptivePass {
    /// [`record_estimate_timed`](Self::record_estimate_timed) over the listed tiles of
    /// `tiles` only (see [`AdaptiveTiles`] for when that equals the whole frame).
    ///
    /// # Errors
    ///
    /// As [`record_estimate`](Self::record_estimate); [`AdaptiveError::TextureSize`] or
    /// [`AdaptiveError::TextureKind`] naming `tiles` for a list built for another size or
    /// control model. Nothing is recorded then.
    pub fn record_estimate_tiles(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &EstimateInputs<'_>,
        tiles: &AdaptiveTiles,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), AdaptiveError> {
        self.check_tiles(tiles)?;
        self.record_estimate_in(encoder, inputs, timestamp_writes, Some(tiles))
    }

    /// [`record_update_timed`](Self::record_update_timed) over the listed tiles of `tiles`
    /// only; the history advances as after the whole-frame update.
    ///
    /// # Errors
    ///
    /// As [`record_update`](Self::record_update) and
    /// [`record_estimate_tiles`](Self::record_estimate_tiles).
    pub fn record_update_tiles(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &UpdateInputs<'_>,
        tiles: &AdaptiveTiles,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), AdaptiveError> {
        self.check_tiles(tiles)?;
        self.record_update_in(encoder, inputs, timestamp_writes, Some(tiles), None)
    }

    fn check_tiles(&self, tiles: &AdaptiveTiles) -> Result<(), AdaptiveError> {
        if tiles.size != self.size() {
            let [w, h] = tiles.size;
            return Err(AdaptiveError::TextureSize {
                input: "tiles",
                expected: self.size(),
                got: [w, h, 1],
            });
        }
        if tiles.ocv != self.frame.cv.is_some() {
            return Err(AdaptiveError::TextureKind {
                input: "tiles",
                reason: "built for a pass of another control model (OCV's update differs)",
            });
        }
        Ok(())
    }
}

/// The tiles of a `size` frame holding a nonzero pixel of `region`, `x | y << 16`.
fn tile_list(region: &[u8], [width, height]: [u32; 2]) -> Result<Vec<u32>, AdaptiveError> {
    let (w, h) = (width as usize, height as usize);
    if region.len() != w * h {
        return Err(AdaptiveError::SliceLength {
            input: "region",
            expected: w * h,
            got: region.len(),
        });
    }
    let t = TILE as usize;
    let tw = w.div_ceil(t);
    let mut hit = vec![false; tw * h.div_ceil(t)];
    for (i, _) in region.iter().enumerate().filter(|(_, r)| **r != 0) {
        hit[(i / w / t) * tw + (i % w) / t] = true;
    }
    // A tile coordinate fits 16 bits: the frame side is at most the device's texture
    // limit (16384 at most on the adapters wgpu targets), 2048 tiles.
    Ok(hit
        .iter()
        .enumerate()
        .filter(|(_, h)| **h)
        .map(|(k, _)| ((k / tw) as u32) << 16 | (k % tw) as u32)
        .collect())
}

/// The workgroup grid of a list of `n` tiles: one row while it fits, else rows of
/// [`MAX_GROUPS`] (the shader skips the workgroups past the end). The subsurface pass's
/// separable tile list dispatches on the same grid.
pub(crate) fn grid(n: usize) -> [u32; 2] {
    let n = u32::try_from(n).unwrap_or(u32::MAX);
    if n <= MAX_GROUPS {
        [n, 1]
    } else {
        [MAX_GROUPS, n.div_ceil(MAX_GROUPS)]
    }
}

/// A tile list on the device (`x | y << 16` per tile) and its length: what a tile-list
/// entry point reads at group 1, binding 0.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TileList<'a> {
    /// The list (a storage buffer; not empty).
    pub(crate) buffer: &'a wgpu::Buffer,
    /// Tiles listed.
    pub(crate) tiles: usize,
}

impl TileList<'_> {
    /// Records `pipeline` over the listed tiles: `group` at group 0 and the list at group
    /// 1, one workgroup per tile on the grid of [`grid`].
    pub(crate) fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        group: &wgpu::BindGroup,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let list = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("tile list"),
            layout: &pipeline.get_bind_group_layout(1),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: self.buffer.as_entire_binding(),
            }],
        });
        let [x, y] = grid(self.tiles);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(1, &list, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_the_tiles_holding_a_region_pixel() {
        // 20 x 10: tiles 3 x 2. Pixels (0, 0), (17, 9) and (9, 3).
        let mut region = vec![0_u8; 200];
        region[0] = 1;
        region[9 * 20 + 17] = 1;
        region[3 * 20 + 9] = 1;
        let tiles = tile_list(&region, [20, 10]).unwrap();
        assert_eq!(tiles, vec![0, 1, 1 << 16 | 2]);
        assert!(tile_list(&region, [20, 9]).is_err());
    }

    #[test]
    fn grid_covers_long_lists() {
        assert_eq!(grid(0), [0, 1]);
        assert_eq!(grid(7), [7, 1]);
        let [x, y] = grid(200_000);
        assert!(u64::from(x) * u64::from(y) >= 200_000 && x <= MAX_GROUPS);
    }
}

//! Count-classified dispatch ([`AdaptiveSettings::classified_dispatch`]): the classes of
//! the frame's 8 x 8 tiles by their largest count, built on the device after the estimate
//! (`classify.wgsl`), and the consumer's sampling pass recorded once per class with
//! indirect arguments ([`AdaptivePass::dispatch_classified`]).
//!
//! Why: a compute invocation's loop runs as long as the longest count in its SIMD group
//! (32 or 64 lanes on a GPU, 8 on llvmpipe's 256-bit build), so a group that holds counts
//! of 8 and 64 runs 64 iterations on every lane. Two things are sorted:
//! - the tiles, into classes of similar largest count: workgroups of one class take
//!   similar times, and a consumer may specialise per class;
//! - the pixels of each tile, by the class of their counts (a stable counting sort the
//!   classification writes, in the tiles' bins): the invocations of one SIMD group take
//!   neighbouring ranks, so a tile with a few pixels
//!   at 64 and the rest at 8 runs one or two groups at 64 instead of every row that
//!   holds one.
//!
//! The classes and orders are deterministic (their positions come from prefix sums in
//! row-major tile order, never from the order atomics complete in), and the twin
//! ([`classify`], run by [`AdaptiveTwin::estimate`](super::AdaptiveTwin::estimate))
//! builds the same lists bit for bit. Every tile is listed in exactly one class, count-0
//! tiles included, so a consumer that samples through the classes writes every pixel the
//! whole-frame dispatch writes, with the same values.
//!
//! [`AdaptiveSettings::classified_dispatch`]: super::AdaptiveSettings::classified_dispatch

use super::{AdaptiveError, AdaptivePass};
use crate::util::{compute_pipeline, read_buffer};

/// The upper bounds of the classes but the last, by a tile's largest count: class `k`
/// holds the tiles whose largest count is above `CLASS_BOUNDS[k - 1]` and at most
/// `CLASS_BOUNDS[k]` (class 0: every count 0; 1: 1; 2: 2 to 4; 3: 5 to 8; 4: 9 to 16; 5:
/// 17 to 32; 6: 33 to 64; 7: above 64).
pub(crate) const CLASS_BOUNDS: [u32; 7] = [0, 1, 4, 8, 16, 32, 64];

/// The number of classes.
pub(crate) const CLASSES: usize = CLASS_BOUNDS.len() + 1;

/// Side of a tile in pixels (the consumer's 8 x 8 workgroup).
const TILE: u32 = 8;

/// Words of a list's header (tile count, tiles per row, 0, 0).
const HEADER: u64 = 4;

/// The class of a tile whose largest count is `m`: the number of bounds below it
/// (`adaptive_class_of`).
#[must_use]
pub(crate) fn class_of(m: u32) -> usize {
    CLASS_BOUNDS.iter().filter(|&&b| m > b).count()
}

/// The WGSL constants the classification is compiled with, from [`CLASS_BOUNDS`].
pub(crate) fn wgsl_constants() -> String {
    let bounds: Vec<String> = CLASS_BOUNDS.iter().map(|b| format!("{b}u")).collect();
    format!(
        "const ADAPTIVE_CLASSES: u32 = {CLASSES}u;\n\
         const ADAPTIVE_CLASS_BOUNDS = array<u32, {}>({});\n",
        CLASS_BOUNDS.len(),
        bounds.join(", ")
    )
}

/// The classes of a frame: per class its tiles (`x | y << 16`, row-major), and per tile
/// (row-major) the order its 64 pixels are taken in.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Classes {
    pub(crate) lists: Vec<Vec<u32>>,
    pub(crate) orders: Vec<[u8; 64]>,
}

/// The twin of `adaptive_classify` and `adaptive_class_scatter`: the classes of the
/// counts of a `size` frame (row-major).
#[must_use]
pub(crate) fn classify(counts: &[u32], [width, height]: [u32; 2]) -> Classes {
    let (tx, ty) = (width.div_ceil(TILE), height.div_ceil(TILE));
    let mut out = Classes {
        lists: vec![Vec::new(); CLASSES],
        orders: Vec::with_capacity((tx * ty) as usize),
    };
    for y in 0..ty {
        for x in 0..tx {
            let tile: [u32; 64] = core::array::from_fn(|k| {
                let (px, py) = (x * TILE + k as u32 % TILE, y * TILE + k as u32 / TILE);
                if px < width && py < height {
                    counts.get((py * width + px) as usize).copied().unwrap_or(0)
                } else {
                    0
                }
            });
            let mut order: [u8; 64] = core::array::from_fn(|k| k as u8);
            // Stable: equal counts keep the pixel order, as the shader's rank does.
            order.sort_by_key(|&k| class_of(tile[k as usize]));
            out.orders.push(order);
            let max = tile.iter().copied().max().unwrap_or(0);
            out.lists[class_of(max)].push(y << 16 | x);
        }
    }
    out
}

/// The classification's buffers on the device.
#[derive(Debug)]
pub(super) struct ClassBuffers {
    /// Per tile its class.
    tile: wgpu::Buffer,
    /// Per tile row and class, the row's tiles of that class (cleared every frame).
    row_counts: wgpu::Buffer,
    /// Per tile, 16 words: the pixel order, a byte per pixel.
    pub(super) order: wgpu::Buffer,
    /// The lists, one region of `stride` bytes per class.
    pub(super) lists: wgpu::Buffer,
    /// The dispatch arguments, three words per class.
    pub(super) args: wgpu::Buffer,
    /// Bytes per class region (a multiple of 256).
    pub(super) stride: u64,
    /// Tile rows (workgroups of the scatter pass) and columns.
    tiles: [u32; 2],
}

impl ClassBuffers {
    pub(super) fn new(device: &wgpu::Device, [width, height]: [u32; 2]) -> Self {
        let tiles = [width.div_ceil(TILE), height.div_ceil(TILE)];
        let n = u64::from(tiles[0]) * u64::from(tiles[1]);
        // `adaptive_class_stride`: the header and every tile, in 64-word steps.
        let stride = (HEADER + n).div_ceil(64) * 64 * 4;
        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        let none = wgpu::BufferUsages::empty();
        let copy = wgpu::BufferUsages::COPY_SRC;
        Self {
            tile: buffer("adaptive class per tile", 4 * n, none),
            row_counts: buffer(
                "adaptive class row counts",
                4 * u64::from(tiles[1]) * CLASSES as u64,
                wgpu::BufferUsages::COPY_DST,
            ),
            order: buffer("adaptive class pixel order", 64 * n, copy),
            lists: buffer("adaptive class lists", stride * CLASSES as u64, copy),
            args: buffer(
                "adaptive class dispatch arguments",
                12 * CLASSES as u64,
                copy | wgpu::BufferUsages::INDIRECT,
            ),
            stride,
            tiles,
        }
    }
}

/// The classification's two pipelines and their layouts.
#[derive(Debug)]
pub(super) struct ClassPipelines {
    classify: wgpu::ComputePipeline,
    scatter: wgpu::ComputePipeline,
    classify_layout: wgpu::BindGroupLayout,
    scatter_layout: wgpu::BindGroupLayout,
}

fn storage(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl ClassPipelines {
    pub(super) fn new(device: &wgpu::Device, module: &wgpu::ShaderModule) -> Self {
        let uniform = wgpu::BindGroupLayoutEntry {
            binding: 1,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let count = wgpu::BindGroupLayoutEntry {
            binding: 13,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Uint,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let classify_layout = layout(
            "adaptive classify",
            &[
                uniform,
                count,
                storage(32, false),
                storage(33, false),
                storage(34, false),
            ],
        );
        let scatter_layout = layout(
            "adaptive class scatter",
            &[
                uniform,
                storage(35, true),
                storage(36, true),
                storage(37, false),
                storage(38, false),
            ],
        );
        Self {
            classify: compute_pipeline(device, module, "adaptive_classify", Some(&classify_layout)),
            scatter: compute_pipeline(
                device,
                module,
                "adaptive_class_scatter",
                Some(&scatter_layout),
            ),
            classify_layout,
            scatter_layout,
        }
    }
}

impl AdaptivePass {
    /// Records the classification of the count texture into `encoder`: two compute
    /// passes, the first with `first`'s timestamp writes, the second with `last`'s.
    pub(super) fn record_classification(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        params: &wgpu::Buffer,
        timestamps: [Option<wgpu::ComputePassTimestampWrites<'_>>; 2],
    ) {
        let (Some(b), Some(p)) = (&self.frame.classes, &self.classify) else {
            return;
        };
        let [first, last] = timestamps;
        encoder.clear_buffer(&b.row_counts, 0, None);
        let count = crate::util::view(&self.frame.count);
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("adaptive classify"),
            layout: &p.classify_layout,
            entries: &[
                entry(1, params),
                wgpu::BindGroupEntry {
                    binding: 13,
                    resource: wgpu::BindingResource::TextureView(&count),
                },
                entry(32, &b.tile),
                entry(33, &b.row_counts),
                entry(34, &b.order),
            ],
        });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("adaptive classify"),
                timestamp_writes: first,
            });
            pass.set_pipeline(&p.classify);
            pass.set_bind_group(0, &group, &[]);
            // One invocation per tile, 64 tiles of a row per workgroup.
            pass.dispatch_workgroups(b.tiles[0].div_ceil(64), b.tiles[1], 1);
        }
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("adaptive class scatter"),
            layout: &p.scatter_layout,
            entries: &[
                entry(1, params),
                entry(35, &b.tile),
                entry(36, &b.row_counts),
                entry(37, &b.lists),
                entry(38, &b.args),
            ],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("adaptive class scatter"),
            timestamp_writes: last,
        });
        pass.set_pipeline(&p.scatter);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(b.tiles[1], 1, 1);
    }

    /// Records `pipeline` once per class of tiles, each with
    /// `dispatch_workgroups_indirect` on the arguments the last recorded estimate's
    /// classification wrote, in one compute pass (the timestamp writes bracket every
    /// class): `group` at group 0 and the class's list and the tiles' pixel orders at
    /// group 1 (bindings 0 and 1, as [`CLASSIFIED_WGSL`](Self::CLASSIFIED_WGSL) declares
    /// them). `pipeline` is a renderer's `@workgroup_size(8, 8, 1)` entry point that
    /// decodes its pixel with `adaptive_class_pixel` of that WGSL and otherwise does
    /// what its whole-frame entry does per pixel; every tile of the frame is in one class,
    /// so it writes what the whole-frame dispatch writes. Record it after the frame's
    /// estimate (in submission order); before the first estimate the arguments are zero
    /// and nothing runs.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::MissingInput`] naming `settings.classified_dispatch` when the
    /// classification is off; nothing is recorded then.
    pub fn dispatch_classified(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        group: &wgpu::BindGroup,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), AdaptiveError> {
        let Some(b) = &self.frame.classes else {
            return Err(classification_off());
        };
        let layout = pipeline.get_bind_group_layout(1);
        let groups: Vec<wgpu::BindGroup> = (0..CLASSES as u64)
            .map(|c| {
                self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("adaptive class"),
                    layout: &layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                                buffer: &b.lists,
                                offset: c * b.stride,
                                size: wgpu::BufferSize::new(b.stride),
                            }),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: b.order.as_entire_binding(),
                        },
                    ],
                })
            })
            .collect();
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        for (c, class) in groups.iter().enumerate() {
            pass.set_bind_group(1, class, &[]);
            pass.dispatch_workgroups_indirect(&b.args, 12 * c as u64);
        }
        Ok(())
    }

    /// Reads back the classes the last submitted estimate wrote: per class (by
    /// [`CLASS_BOUNDS`](Self::CLASS_BOUNDS)) its tiles, `x | y << 16` in tile units, in
    /// row-major order, and per tile (row-major) the order its 64 pixels are taken in
    /// (the index in the tile, `x + 8 y`, of the pixel taken k-th). Their twins are
    /// [`AdaptiveTwin::classes`](super::AdaptiveTwin::classes) and
    /// [`AdaptiveTwin::pixel_orders`](super::AdaptiveTwin::pixel_orders). Waits for the
    /// device.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::MissingInput`] when the classification is off,
    /// [`AdaptiveError::Device`] when the readback fails.
    #[allow(
        clippy::type_complexity,
        reason = "two plain lists, the twin's two accessors; a named type would be one more public item for a debug readback"
    )]
    pub fn read_classes(
        &self,
        queue: &wgpu::Queue,
    ) -> Result<(Vec<Vec<u32>>, Vec<[u8; 64]>), AdaptiveError> {
        let Some(b) = &self.frame.classes else {
            return Err(classification_off());
        };
        let lists: Vec<u32> = self.read(queue, &b.lists)?;
        let words = (b.stride / 4) as usize;
        let classes = lists
            .chunks(words)
            .map(|region| {
                let n = region.first().copied().unwrap_or(0) as usize;
                region
                    .get(HEADER as usize..HEADER as usize + n)
                    .unwrap_or(&[])
                    .to_vec()
            })
            .collect();
        let order: Vec<u32> = self.read(queue, &b.order)?;
        let orders = order
            .chunks(16)
            .map(|w| core::array::from_fn(|k| (w[k / 4] >> (8 * (k % 4))) as u8))
            .collect();
        Ok((classes, orders))
    }

    /// Copies `buffer` (with `COPY_SRC`) to a mappable one and reads it.
    fn read(&self, queue: &wgpu::Queue, buffer: &wgpu::Buffer) -> Result<Vec<u32>, AdaptiveError> {
        let size = buffer.size();
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("adaptive class readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("adaptive class readback"),
            });
        encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        queue.submit([encoder.finish()]);
        read_buffer(&self.device, &staging, size)
    }
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

fn classification_off() -> AdaptiveError {
    AdaptiveError::MissingInput {
        input: "settings.classified_dispatch",
        reason: "the estimate classifies the tiles only with the setting on",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_follow_the_bounds() {
        let got: Vec<usize> = [0, 1, 2, 4, 5, 8, 9, 16, 17, 32, 33, 64, 65, 512]
            .iter()
            .map(|&m| class_of(m))
            .collect();
        assert_eq!(got, [0, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7]);
    }

    /// A 12 x 9 frame: 2 x 2 tiles, the partial ones padded with zeros; each tile in the
    /// class of its largest count, and its pixels ordered by the class of their counts, ties
    /// in pixel order.
    #[test]
    fn the_twin_lists_every_tile_once_and_orders_pixels_by_count() {
        let (w, h) = (12_u32, 9_u32);
        let mut counts = vec![8_u32; (w * h) as usize];
        counts[(2 * w + 3) as usize] = 64; // tile (0, 0)
        counts[(8 * w + 11) as usize] = 20; // tile (1, 1), its only pixel in row 8
        for c in &mut counts[(w as usize * 8)..(w as usize * 8 + 8)] {
            *c = 0; // tile (0, 1): all zero
        }
        let c = classify(&counts, [w, h]);
        assert_eq!(c.lists[6], vec![0], "64 in tile (0, 0)");
        assert_eq!(c.lists[3], vec![1], "8 in tile (1, 0)");
        assert_eq!(c.lists[0], vec![1 << 16], "zeros in tile (0, 1)");
        assert_eq!(c.lists[5], vec![1 << 16 | 1], "20 in tile (1, 1)");
        let listed: usize = c.lists.iter().map(Vec::len).sum();
        assert_eq!(listed, 4, "every tile once");
        // Tile (0, 0): the 64 at (3, 2) is taken last, the rest in pixel order.
        assert_eq!(c.orders[0][63], 19);
        assert_eq!(c.orders[0][..3], [0, 1, 2]);
        // Tile (1, 1): 4 columns and 1 row inside; the 60 padded zeros first, then the
        // three 8s, then the 20 at (3, 0).
        let o = c.orders[3];
        assert_eq!(o[60..], [0, 1, 2, 3]);
        assert_eq!(o[0], 4, "the first padded pixel");
        let mut sorted = o;
        sorted.sort_unstable();
        assert_eq!(sorted, core::array::from_fn(|k| k as u8), "a permutation");
    }
}

//! The tile list of a hybrid frame's separable passes: the 8 x 8 tiles that hold a pixel
//! the separable filter renders (one not tagged AFIS). The passes run over these tiles only
//! (`sep_horizontal_tiles`, `sep_vertical_tiles` in `shaders/separable.wgsl`): a tile whose
//! pixels are all tagged gets the first pass's values from `sep_compose` and keeps the
//! AFIS result as the second's (it writes into that texture), so the filter's cost follows
//! the untagged part of the frame.
//!
//! Like the first step's list ([`spvg_wgpu::adaptive::AdaptiveTiles`], the tiles holding a
//! tagged pixel, in the same encoding plus a flag on the tiles holding both kinds) it is
//! built on the CPU from the caller's tags and uploaded only when they change; the two
//! lists together cover the frame.

use wgpu::util::DeviceExt as _;

use spvg_wgpu::adaptive::AdaptiveTiles;

use crate::sss::TECHNIQUE_AFIS;

/// Side of a tile: the component's.
const TILE: u32 = AdaptiveTiles::TILE;

/// The flag of a listed tile that holds a tagged pixel too (`SEP_TILE_MIXED` in the
/// shader): only such a tile's pixels read their technique id.
const MIXED: u32 = 0x8000;

/// The tiles of a frame that hold an untagged pixel, on the CPU and on the device.
#[derive(Debug)]
pub(super) struct SeparableTiles {
    device: wgpu::Device,
    size: [u32; 2],
    tiles: Vec<u32>,
    /// The list on the device (`None` while it is empty: a storage binding cannot be
    /// empty, and an empty list dispatches nothing).
    buffer: Option<wgpu::Buffer>,
}

impl SeparableTiles {
    /// An empty list for a `size` frame.
    pub(super) fn new(device: &wgpu::Device, size: [u32; 2]) -> Self {
        Self {
            device: device.clone(),
            size,
            tiles: Vec::new(),
            buffer: None,
        }
    }

    /// Lists the tiles holding a pixel of `technique` (one id per pixel, checked by the
    /// caller to be the frame's size) that is not [`TECHNIQUE_AFIS`], and uploads the list
    /// when it differs from the current one.
    pub(super) fn set(&mut self, technique: &[u8]) {
        let tiles = untagged_tiles(technique, self.size);
        if tiles == self.tiles {
            return;
        }
        self.buffer = (!tiles.is_empty()).then(|| {
            self.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("separable tile list"),
                    contents: bytemuck::cast_slice(&tiles),
                    usage: wgpu::BufferUsages::STORAGE,
                })
        });
        self.tiles = tiles;
    }

    /// Records `pipeline` (a `*_tiles` entry point) over the listed tiles: `group` at
    /// group 0, the list at group 1. An empty list records nothing.
    pub(super) fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        group: &wgpu::BindGroup,
    ) {
        let Some(buffer) = &self.buffer else {
            return;
        };
        // The component's recording of a tile list (its 2-D workgroup grid, the list at
        // group 1).
        AdaptiveTiles::dispatch_list(
            &self.device,
            encoder,
            label,
            pipeline,
            group,
            buffer,
            self.tiles.len(),
            None,
        );
    }
}

/// The tiles of a `size` frame holding a pixel whose id is not [`TECHNIQUE_AFIS`],
/// `x | y << 16` in tile units, row-major, with [`MIXED`] set on those that hold a tagged
/// pixel too. (A tile coordinate fits 15 bits: a frame side is at most the device's
/// texture limit, 16384 on the adapters wgpu targets, 2048 tiles.)
fn untagged_tiles(technique: &[u8], [width, height]: [u32; 2]) -> Vec<u32> {
    let (w, h, t) = (width as usize, height as usize, TILE as usize);
    let tw = w.div_ceil(t);
    // Per tile: whether it holds an untagged pixel, and a tagged one.
    let mut hit = vec![(false, false); tw * h.div_ceil(t)];
    for (i, &id) in technique.iter().enumerate().take(w * h) {
        let tile = &mut hit[(i / w / t) * tw + (i % w) / t];
        if id == TECHNIQUE_AFIS {
            tile.1 = true;
        } else {
            tile.0 = true;
        }
    }
    hit.iter()
        .enumerate()
        .filter(|(_, h)| h.0)
        .map(|(k, h)| {
            let flag = if h.1 { MIXED } else { 0 };
            ((k / tw) as u32) << 16 | (k % tw) as u32 | flag
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_the_tiles_holding_an_untagged_pixel() {
        // 20 x 10: tiles 3 x 2. Tagged: the whole of tile (0, 0), all of tile (2, 1)
        // (columns 16..20, rows 8..10) but pixel (19, 9), and one pixel of tile (1, 0).
        let mut technique = vec![0_u8; 200];
        for y in 0..8 {
            for x in 0..8 {
                technique[y * 20 + x] = TECHNIQUE_AFIS;
            }
        }
        for y in 8..10 {
            for x in 16..20 {
                technique[y * 20 + x] = TECHNIQUE_AFIS;
            }
        }
        technique[9 * 20 + 19] = 0;
        technique[3 * 20 + 9] = TECHNIQUE_AFIS;
        // Brute force: a tile is listed iff some pixel inside it is untagged, marked
        // mixed iff some other is tagged.
        let in_tile = |tx: u32, ty: u32, tagged: bool| {
            (0..200_u32).any(|i| {
                let (x, y) = (i % 20, i / 20);
                x / 8 == tx && y / 8 == ty && (technique[i as usize] == TECHNIQUE_AFIS) == tagged
            })
        };
        let expected: Vec<u32> = (0..2_u32)
            .flat_map(|ty| (0..3_u32).map(move |tx| (tx, ty)))
            .filter(|&(tx, ty)| in_tile(tx, ty, false))
            .map(|(tx, ty)| ty << 16 | tx | if in_tile(tx, ty, true) { MIXED } else { 0 })
            .collect();
        let tiles = untagged_tiles(&technique, [20, 10]);
        assert_eq!(tiles, expected, "against the brute force");
        assert_eq!(
            tiles,
            vec![1 | MIXED, 2, 1 << 16, 1 << 16 | 1, 1 << 16 | 2 | MIXED]
        );
        assert!(untagged_tiles(&[TECHNIQUE_AFIS; 200], [20, 10]).is_empty());
        assert_eq!(untagged_tiles(&[0; 200], [20, 10]).len(), 6);
    }
}

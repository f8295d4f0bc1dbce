//! Count dilation: each pixel spends the largest count of its neighbourhood
//! (docs/algorithms.md §2.5).
//!
//! The controller estimates a pixel's count from that pixel's own history. Two cases
//! defeat a per-pixel estimate, and a neighbour's history knows better in both:
//! - **Rare events.** A pixel that sees a small occluder, a thin light or a caustic with
//!   probability `q` per sample has a per-sample variance `q (1 - q)`, but at `beta_min`
//!   samples most frames see no hit at all, so its moving variance is near zero for most
//!   frames and its count stays at `beta_min`. Its neighbours further into the feature
//!   see it every frame. On the ambient-occlusion consumer of `spvg-wgpu` (static camera,
//!   `sigma0^2 = 1e-4`), pixels with `q < 0.01` were 5% of the pixel-frames at `beta_min`
//!   and carried 23% of the squared error.
//! - **Sub-pixel motion.** Reprojection reads the nearest texel, never a filtered
//!   history (see [`crate::reproject`]); under rotation or sub-pixel pans a pixel can
//!   inherit, for a frame or two, the history of the neighbouring surface point across a
//!   variance edge.
//!
//! Dilation takes the maximum count over the `(2r + 1)^2` window around the pixel,
//! clipped to the frame. The histories themselves are neither read nor mixed: each pixel
//! still updates its own history with the count it really spent, so the statistics stay
//! point-sampled. A pixel whose own count is 0 (outside the pass's mask, or the
//! zero-sample rule) keeps 0, and so does a pixel marked [`KEEP`]: a pixel without
//! history (disoccluded: the surface was hidden or the history rejected) takes its
//! first-observation count (docs/algorithms.md §2.3), not its neighbours', which belong to
//! the occluder or to surfaces it no longer sees. Radius 0 is the papers' per-pixel
//! rule.
//!
//! What it costs: the counts of a neighbourhood's maximum along every variance edge, `r`
//! pixels wide. The report's motion section measures it against radius 0.
//!
//! # Examples
//!
//! ```
//! use spvg::dilation::dilate_counts;
//! use spvg::dilation::KEEP;
//! let counts = [8, 8, 8, 8, 64, 8, 8 | KEEP, 0, 8];
//! let mut out = [0; 9];
//! dilate_counts(&counts, &mut out, [3, 3], 1).unwrap();
//! // Every covered pixel is next to the 64; the masked pixel stays 0, the disoccluded
//! // (KEEP) pixel keeps its own count.
//! assert_eq!(out, [64, 64, 64, 64, 64, 64, 8, 0, 64]);
//! ```

use crate::Error;

/// Marks a count of the input of [`dilate_counts`] as one the pixel keeps (a pixel
/// without history); the mark is cleared in the output and ignored in a neighbour's
/// window. Counts never reach it (the budget's maximum is at most 1024).
pub const KEEP: u32 = 1 << 31;

/// The largest radius [`dilate_counts`] accepts: a 17x17 window. A renderer wanting more
/// would be better served by a lower target variance.
pub const MAX_RADIUS: u32 = 8;

/// The dilated count of `pixel`: its own count where that is 0 or marked [`KEEP`] (the
/// mark cleared), else the maximum of `counts` (marks cleared) over the window of
/// `radius` around it, clipped to the `size[0] x size[1]` frame (`counts` row-major). A
/// pixel outside the frame, or a `counts` shorter than the frame, reads as 0.
#[inline]
#[must_use]
pub fn dilated_count(counts: &[u32], size: [u32; 2], pixel: [u32; 2], radius: u32) -> u32 {
    let [w, h] = size.map(|s| s as usize);
    let [x, y] = pixel.map(|p| p as usize);
    if x >= w || y >= h {
        return 0;
    }
    let at = |x: usize, y: usize| counts.get(y * w + x).map_or(0, |&c| c & !KEEP);
    let own = counts.get(y * w + x).copied().unwrap_or(0);
    if own == 0 || own & KEEP != 0 {
        return own & !KEEP;
    }
    let r = radius as usize;
    let (x0, x1) = (x.saturating_sub(r), x.saturating_add(r).min(w - 1));
    let (y0, y1) = (y.saturating_sub(r), y.saturating_add(r).min(h - 1));
    let mut m = 0;
    for yy in y0..=y1 {
        for xx in x0..=x1 {
            m = m.max(at(xx, yy));
        }
    }
    m
}

/// The radius of the window in which the depth-aware neighbour prior
/// ([`dilated_count_with_prior`]) looks for a disoccluded pixel's same-surface neighbours
/// with history, when the dilation's radius is smaller: a 9x9 window. A surface uncovered
/// by an object moving `v` pixels per frame opens a strip `v` pixels wide whose pixels all
/// lack history; within the dilation's usual radius (1) only the strip's outer column
/// finds a neighbour that has one. Radius 4 reaches across the strips of objects moving up
/// to 4 pixels per frame from both sides and 8 from one; measured in docs/algorithms.md
/// §8.4 against the dilation's own radius.
pub const PRIOR_RADIUS: u32 = 4;

/// The side of the square tile that a one-pass dispatch holds in workgroup memory: an
/// 8 x 8 workgroup, the tiles of a frame aligned to its origin. The neighbourhood rules
/// read what such a workgroup holds: the spatial moments of young histories are clipped
/// to the tile ([`spatial_window`](crate::controller::young::spatial_window)); the count
/// dilation and the neighbour prior read a halo of their radius around it, which the
/// workgroup recomputes (an estimate is one history read).
pub const TILE: u32 = 8;

/// The region of the frame a workgroup of the one-pass dispatch holds for `pixel`: the
/// [`TILE`] x [`TILE`] tile holding it, grown by `halo` pixels on every side, clipped to
/// the `size[0] x size[1]` frame; `[low corner, high corner]`, both inclusive, holding
/// `pixel` where it lies in the frame.
///
/// # Examples
///
/// ```
/// use spvg::dilation::tile_region;
/// // Pixel (9, 3) lies in the tile [8, 15] x [0, 7].
/// assert_eq!(tile_region([9, 3], [100, 100], 0), [[8, 0], [15, 7]]);
/// // A halo of 2, clipped to the frame at the top and on the right.
/// assert_eq!(tile_region([9, 3], [12, 100], 2), [[6, 0], [11, 9]]);
/// ```
#[inline]
#[must_use]
pub fn tile_region(pixel: [u32; 2], size: [u32; 2], halo: u32) -> [[u32; 2]; 2] {
    let lo = pixel.map(|p| (p / TILE * TILE).saturating_sub(halo));
    let hi: [u32; 2] = core::array::from_fn(|k| {
        (pixel[k] / TILE * TILE)
            .saturating_add(TILE - 1)
            .saturating_add(halo)
            .min(size[k].saturating_sub(1))
    });
    [lo, hi]
}

/// [`dilated_count`] with the depth-aware neighbour prior (docs/algorithms.md §2.5): a
/// pixel marked [`KEEP`] (no history) takes the mean, rounded to the nearest integer
/// (halves up), of the counts of the pixels that have history (not marked, not 0) and lie
/// on its surface (`same_surface(q)`, e.g.
/// [`Reprojection::depth_agrees`](crate::reproject::Reprojection::depth_agrees) of `q`'s
/// depth against the pixel's) within the window of `radius.max(`[`PRIOR_RADIUS`]`)`
/// around it, clipped to the frame; never less than its own count, which it keeps where
/// no such neighbour exists. Every other pixel is [`dilated_count`] with `radius`.
/// `same_surface` is called only for such neighbours.
///
/// A disoccluded pixel's own count is `beta_min` (§2.3); its neighbours on the same
/// surface that kept their history know what that surface needs. The mean, not the
/// maximum: the prior stands for the surface, not for its most demanding point (the count
/// dilation already spreads the maximum once the pixel has history).
///
/// The window is whole in both forms of the component: a one-pass dispatch, which holds
/// the estimates of its [`TILE`] x [`TILE`] tile and a halo in workgroup memory, takes a
/// halo of `radius.max(`[`PRIOR_RADIUS`]`)` where the prior acts (16 x 16 estimates for
/// 64 pixels at the default radius). Clipping the window to a halo of `radius` instead
/// was measured: the report's disocclusion line on a moving object failed with it (a
/// disoccluded pixel at a tile's edge finds too few neighbours with history).
///
/// # Examples
///
/// ```
/// use spvg::dilation::{KEEP, dilated_count_with_prior};
/// let counts = [30, 20, 30, 8 | KEEP, 8 | KEEP, 64, 30, 31, 30];
/// // The pixel at (1, 1) has no history; the 64 at (2, 1) is another surface.
/// let other = |q: [u32; 2]| q != [2, 1];
/// // (30 + 20 + 30 + 30 + 31 + 30) / 6 = 28.5, rounded up.
/// assert_eq!(dilated_count_with_prior(&counts, [3, 3], [1, 1], 1, other), 29);
/// assert_eq!(dilated_count_with_prior(&counts, [3, 3], [1, 1], 1, |_| false), 8);
/// ```
#[inline]
#[must_use]
pub fn dilated_count_with_prior(
    counts: &[u32],
    size: [u32; 2],
    pixel: [u32; 2],
    radius: u32,
    same_surface: impl Fn([u32; 2]) -> bool,
) -> u32 {
    let [w, h] = size.map(|s| s as usize);
    let [x, y] = pixel.map(|p| p as usize);
    if x >= w || y >= h {
        return 0;
    }
    let own = counts.get(y * w + x).copied().unwrap_or(0);
    if own & KEEP == 0 {
        return dilated_count(counts, size, pixel, radius);
    }
    let own = own & !KEEP;
    let r = radius.max(PRIOR_RADIUS) as usize;
    let (x0, x1) = (x.saturating_sub(r), x.saturating_add(r).min(w - 1));
    let (y0, y1) = (y.saturating_sub(r), y.saturating_add(r).min(h - 1));
    // u64: a window of unmarked counts near 2^31 would overflow a u32 sum.
    let (mut sum, mut n) = (0_u64, 0_u64);
    for yy in y0..=y1 {
        for xx in x0..=x1 {
            let c = counts.get(yy * w + xx).copied().unwrap_or(0);
            if c & KEEP == 0 && c > 0 && same_surface([xx as u32, yy as u32]) {
                sum += u64::from(c);
                n += 1;
            }
        }
    }
    if n == 0 {
        return own;
    }
    // The mean of counts below 2^31 is below 2^31.
    (((sum + n / 2) / n) as u32).max(own)
}

/// [`dilated_count`] of every pixel of a `size[0] x size[1]` frame, from `src` into `dst`
/// (both row-major, one count per pixel).
///
/// # Errors
///
/// [`Error::InvalidParameter`] naming `radius` above [`MAX_RADIUS`];
/// [`Error::InconsistentParameters`] when `src` or `dst` does not hold one count per pixel.
pub fn dilate_counts(
    src: &[u32],
    dst: &mut [u32],
    size: [u32; 2],
    radius: u32,
) -> Result<(), Error> {
    check_radius(radius)?;
    let n = size[0] as usize * size[1] as usize;
    if src.len() != n || dst.len() != n {
        return Err(Error::InconsistentParameters {
            names: "src, dst, size",
            expected: "src and dst hold size[0] * size[1] counts each",
        });
    }
    for (i, d) in dst.iter_mut().enumerate() {
        let pixel = [(i % size[0] as usize) as u32, (i / size[0] as usize) as u32];
        *d = dilated_count(src, size, pixel, radius);
    }
    Ok(())
}

/// Checks a dilation radius: at most [`MAX_RADIUS`].
///
/// # Errors
///
/// [`Error::InvalidParameter`] naming `radius`.
pub fn check_radius(radius: u32) -> Result<(), Error> {
    if radius > MAX_RADIUS {
        return Err(Error::invalid(
            "radius",
            f64::from(radius),
            "the count dilation radius must be at most spvg::dilation::MAX_RADIUS = 8",
        ));
    }
    Ok(())
}

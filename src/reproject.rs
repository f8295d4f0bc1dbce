//! Reprojection of the per-pixel history along motion vectors (docs/algorithms.md §2.3a).
//!
//! With a moving camera or moving objects, the history of pixel `x` in this frame is the
//! previous frame's history at the position the surface point had then. This module is the
//! one definition of that rule; the GPU component in `spvg-wgpu` mirrors it operation by
//! operation, and its CPU twin calls it.
//!
//! # Motion-vector convention
//!
//! `v` is the motion of the surface point in **pixels**, from the previous frame to this
//! one: this frame's position minus the previous frame's, `+x` to the right, `+y` down
//! (texel rows, the texture's own orientation). So the previous position of the centre of
//! pixel `(x, y)` is
//!
//! ```text
//! x_prev = (x + 0.5) - v.x,    y_prev = (y + 0.5) - v.y
//! ```
//!
//! and the history is read at the texel that contains it, `floor(x_prev)`. A renderer that
//! stores motion in UV units multiplies by the frame size first; one that stores the offset
//! the other way round (previous minus current) negates it.
//!
//! # Why point sampling
//!
//! The history is read at one texel, never filtered. A bilinear blend of neighbouring
//! texels mixes the statistics of different surfaces or lighting across an edge: a blended
//! variance is not the variance of anything, a blended mean across an edge looks like
//! temporal change to the next update (the controller then over-samples the edge for
//! frames), and a blended mean count drifts between the two budgets. Nearest-texel reads
//! keep every history one that some pixel really had; sub-pixel motion only shifts which
//! pixel's history is inherited, and `eta` forgets it within a few frames.
//!
//! # Validity
//!
//! The reprojected history is valid only when all of these hold (otherwise the pixel takes
//! the disocclusion path of docs/algorithms.md §2.3, first-observation seeding; with the
//! footprint search, below, the mask and depth tests may pass at a neighbouring texel
//! instead):
//! - the frame size did not change since the previous frame;
//! - `floor(x_prev)` lies inside the previous frame (a NaN or infinite motion vector never
//!   does);
//! - both depths are finite (an infinite or NaN depth on either side fails the depth test
//!   whatever the tolerance);
//! - the previous frame's mask (the pass's own coverage, e.g. the subsurface mask) is set
//!   there;
//! - the relative depth test passes: `|d_prev - d| <= tol * d`, with `d_prev` the previous
//!   frame's depth at `floor(x_prev)` and `d` this pixel's depth (positive and finite).
//!
//! # Which depth the test compares
//!
//! `d` is compared with a depth the *previous* camera measured, so the right `d` is the
//! **reprojected depth**: the depth of this pixel's surface point as the previous camera
//! saw it (the previous frame's view matrix applied to this frame's world position, the
//! point first moved back along its own motion where it moves). Then a surface that stayed
//! visible passes whatever the camera did, and only an occluder or a surface that was
//! hidden fails. A renderer without it passes its current depth instead; that is exact for
//! a camera that moves sideways or rotates about its view axis, but a dolly or a zoom
//! changes every depth by the camera's motion along its view direction, and at more than
//! `tol` per frame (2% by default) every history fails the test. Objects moving towards
//! the camera do the same to their own pixels. The rule itself is the same either way:
//! [`Reprojection::locate`] takes whichever depth the caller has as `depth`, and the GPU
//! component takes an optional reprojected-depth input and passes it in its place.
//!
//! The default tolerance, [`DEFAULT_DEPTH_TOLERANCE`] = 2%, covers the depth slope across
//! the half texel that nearest-texel rounding can move on a surface up to about 88 degrees
//! from the view direction with 1-milliradian pixels (half a pixel of a plane at angle
//! `theta` changes the depth by `0.5e-3 tan(theta)` of itself), while an occluder in front
//! of the surface, or the surface behind it, is rejected whenever the two are more than 2%
//! of the depth apart.
//!
//! # The border prior
//!
//! A pixel whose position lies outside the previous frame (it enters the screen in a pan or
//! a rotation) has no history, and the disocclusion rule alone gives it `beta_min` samples
//! and then, from the seeded variance `sigma0^2`, about `beta_min` again, until its own
//! variance estimate has built up over several frames. A fast pan thereby keeps a band of
//! under-sampled pixels along the entering edge several frames wide. The border prior
//! takes the count, not the history, from a texel of the previous frame near the edge,
//! [`border_texel`]: the nearest one that, under steady motion, was not itself entering
//! then (those hold only a seed), subject to the same mask and depth tests against this
//! pixel. The
//! pixel still takes the disocclusion path in its update (first-observation seeding), so
//! nothing of the neighbour's statistics is stored as its own; but with `nbar` seeded to
//! that count and the variance to `sigma0^2`, its next estimate asks for about the same
//! count, and its own variance takes over at the rate `eta`. Pixels disoccluded inside the
//! frame (behind a moving object, a mask or depth rejection) keep `beta_min`: the texel next
//! to them belongs to the occluder. [`Reprojection::with_border_prior`] turns the prior
//! off (the papers' rule: every pixel without history starts at `beta_min`). Where the
//! border texel passes, the entering pixel's count is [`BorderCount::Maximum`] by default
//! (`beta_max`, then about `beta_max` again from the seed while its own variance builds
//! up), or the estimate from the border texel's history ([`BorderCount::Texel`]).
//! [`Reprojection::entering_count`] is that rule.
//!
//! # The motion bound
//!
//! A position more than the frame size past an edge of the previous frame (`x_prev <
//! -width` or `x_prev >= 2 width`, the same for `y`) takes no border prior: it is a
//! disocclusion, like a NaN motion vector. No camera pans by more than a frame in one
//! frame; such a vector (`1e30`, `3e9`, `f32::MAX`) is a broken motion buffer, and taking
//! it for a pan would give every pixel the border prior's `beta_max` and seed it there.
//!
//! # The footprint search
//!
//! Nearest-texel rounding moves the read position by up to half a texel. Next to a depth
//! edge (the silhouette of an object over the ground) the texel containing `x_prev` can
//! belong to the other surface although the point itself was visible, and the depth test
//! then rejects a history that exists one texel away. When the texel containing `x_prev`
//! fails the mask or depth test, the rule tries the other three texels of the 2x2
//! footprint around `x_prev` ([`footprint_texel`]: the horizontal neighbour on the side
//! `x_prev` lies towards, the vertical one, then the diagonal one) and continues the
//! first that passes. It is still one texel's history, never a blend. A surface that was
//! really hidden (behind a moving object) fails on all four and is disoccluded as before.
//! [`Reprojection::with_footprint_search`] turns it off.
//!
//! # Examples
//!
//! ```
//! use spvg::reproject::{PreviousSample, Reprojection, previous_texel};
//! // The camera pans 2.5 pixels to the right per frame: the scene moves left on screen.
//! let v = [-2.5_f32, 0.0];
//! // Pixel (10, 4) was at x = 10.5 + 2.5 = 13.0 last frame: texel 13.
//! assert_eq!(previous_texel([10, 4], v, [16, 8]), Some([13, 4]));
//! // Pixel (14, 4) was outside the previous frame: disoccluded by the pan.
//! assert_eq!(previous_texel([14, 4], v, [16, 8]), None);
//!
//! let r = Reprojection::<f32>::default();
//! let surface = PreviousSample { mask: true, depth: 1.0 };
//! let occluder = PreviousSample { mask: true, depth: 0.6 };
//! assert!(r.accepts(surface, 1.01));
//! assert!(!r.accepts(occluder, 1.0)); // the surface was hidden last frame
//! ```

use num_traits::Float;

use crate::Error;

/// The default relative depth tolerance of [`Reprojection`]: 2% of the depth (see the
/// module docs for the reasoning).
pub const DEFAULT_DEPTH_TOLERANCE: f64 = 0.02;

/// What the previous frame holds at the reprojected texel: its mask and its depth.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PreviousSample<T> {
    /// Whether the previous frame's mask (the pass's coverage) was set there.
    pub mask: bool,
    /// The previous frame's depth there (same units as the current depth).
    pub depth: T,
}

/// The texel of the previous frame that holds the history of pixel `pixel`, or `None` when
/// the reprojected position lies outside the previous frame (`previous_size` = width,
/// height) or the motion vector is not finite.
///
/// Exact operation order in `T` (a GPU port follows it, and agrees bit for bit because
/// addition and subtraction are correctly rounded on every conforming device):
///
/// ```text
/// p = (T(x) + 0.5) - v.x          // T(x) and + 0.5 are exact below 2^23 in f32
/// q = floor(p)
/// inside when q >= 0 && q < T(width)   (NaN fails both)
/// ```
///
/// and the same for `y`. See the module docs for the motion-vector convention.
///
/// # Examples
///
/// ```
/// use spvg::reproject::previous_texel;
/// assert_eq!(previous_texel([3, 3], [0.0_f32, 0.0], [8, 8]), Some([3, 3])); // static
/// assert_eq!(previous_texel([3, 3], [0.5_f32, -0.49], [8, 8]), Some([3, 3]));
/// assert_eq!(previous_texel([3, 3], [0.51_f32, 0.0], [8, 8]), Some([2, 3]));
/// assert_eq!(previous_texel([0, 3], [0.51_f32, 0.0], [8, 8]), None); // off the left edge
/// assert_eq!(previous_texel([3, 3], [f32::NAN, 0.0], [8, 8]), None);
/// ```
#[inline]
#[must_use]
pub fn previous_texel<T: Float>(
    pixel: [u32; 2],
    motion: [T; 2],
    previous_size: [u32; 2],
) -> Option<[u32; 2]> {
    per_axis(pixel, motion, previous_size, previous_coordinate)
}

/// `axis` applied to x and y; `None` if either is.
#[inline]
fn per_axis<T>(
    pixel: [u32; 2],
    motion: [T; 2],
    size: [u32; 2],
    axis: impl Fn(u32, T, u32) -> Option<u32>,
) -> Option<[u32; 2]>
where
    T: Copy,
{
    Some([
        axis(pixel[0], motion[0], size[0])?,
        axis(pixel[1], motion[1], size[1])?,
    ])
}

/// `floor((p + 0.5) - v)`, the texel coordinate that contains the previous position.
#[inline]
fn floor_position<T: Float>(p: u32, v: T) -> Option<T> {
    let half = T::one() / (T::one() + T::one());
    Some(((T::from(p)? + half) - v).floor())
}

/// One axis of [`previous_texel`].
#[inline]
fn previous_coordinate<T: Float>(p: u32, v: T, size: u32) -> Option<u32> {
    let q = floor_position(p, v)?;
    if q >= T::zero() && q < T::from(size)? {
        q.to_u32()
    } else {
        None
    }
}

/// The texel of the previous frame whose history the border prior (module docs) reads for
/// `pixel`: per axis, the position of [`previous_texel`] where it lies inside the frame;
/// where it lies past an edge, the texel `ceil(|v|)` in from that edge (the whole frame at
/// most). With steady motion the previous frame's last `|v|` texels along an entering edge
/// had themselves entered in that frame, so they hold only a seed; the inset reaches the
/// nearest texel with statistics of its own. `None` when the motion vector is not finite,
/// the previous frame is empty, or the position lies beyond the motion bound: more than
/// the frame size past an edge (`x_prev < -width` or `x_prev >= 2 width`, and the same
/// for `y`). No pan moves a surface point by more than the whole frame in one frame; such
/// motion is garbage (an uninitialised or mis-scaled motion buffer), and the pixel is a
/// disocclusion rather than a pan that takes the border prior. Otherwise `Some`, inside
/// the previous frame for every `u32` frame size. Equal to [`previous_texel`] where that is
/// `Some`.
///
/// Exact operation order, per axis (`n = T(width)`; the inset and the clamp in `u32`, so
/// that no rounding of `width - 1` in `T` can name a texel past the last one):
///
/// ```text
/// q = floor((T(x) + 0.5) - v.x)          // as previous_texel
/// not finite, q < -n or q >= n + n -> None   // the motion bound
/// inset = min(u32(ceil(|v.x|)), width - 1)   // u32::MAX where ceil(|v.x|) >= T(u32::MAX)
/// q < 0   -> inset
/// q >= n  -> (width - 1) - inset
/// else    -> min(u32(q), width - 1)
/// ```
///
/// # Examples
///
/// ```
/// use spvg::reproject::border_texel;
/// // Entering from the right edge of an 8-wide frame at 3 px per frame: last frame's
/// // texels 5..8 entered then too; texel 4 is the nearest with a history of its own.
/// assert_eq!(border_texel([6, 2], [-3.0_f32, 0.0], [8, 8]), Some([4, 2]));
/// // Inside the frame it is the reprojected texel itself.
/// assert_eq!(border_texel([6, 2], [2.0_f32, 0.0], [8, 8]), Some([4, 2]));
/// assert_eq!(border_texel([6, 2], [f32::NAN, 0.0], [8, 8]), None);
/// ```
#[inline]
#[must_use]
pub fn border_texel<T: Float>(
    pixel: [u32; 2],
    motion: [T; 2],
    previous_size: [u32; 2],
) -> Option<[u32; 2]> {
    per_axis(pixel, motion, previous_size, border_coordinate)
}

/// One axis of [`border_texel`].
#[inline]
fn border_coordinate<T: Float>(p: u32, v: T, size: u32) -> Option<u32> {
    let last = size.checked_sub(1)?;
    let q = floor_position(p, v)?;
    let n = T::from(size)?;
    // Not finite, or beyond the motion bound (more than `size` texels past an edge):
    // absurd motion, a disocclusion rather than a pan.
    if !q.is_finite() || q < -n || q >= n + n {
        return None;
    }
    // The inset: `ceil(|v|)` texels in from the edge, at most the whole frame, clamped in
    // integers so that no rounding of `size - 1` in `T` can carry it past the last texel.
    let inset = || {
        let a = v.abs().ceil();
        let a = if a < T::from(u32::MAX)? {
            a.to_u32()?
        } else {
            u32::MAX
        };
        Some(a.min(last))
    };
    if q < T::zero() {
        inset()
    } else if q >= n {
        Some(last - inset()?)
    } else {
        // `q < T(size)` and `q` an integer: `q < size` (`T(size)` is the nearest value to
        // `size`); the clamp only restates it.
        Some(q.to_u32()?.min(last))
    }
}

/// Where the estimate of a pixel takes its history from: the outcome of
/// [`Reprojection::locate`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HistorySource {
    /// The reprojected history is valid: estimate from it and update it (weight `eta`).
    History([u32; 2]),
    /// The pixel entered the frame: estimate from this border texel's history (the border
    /// prior, module docs), then update as a disocclusion (first-observation seeding).
    BorderPrior([u32; 2]),
    /// No history: the disocclusion path of docs/algorithms.md §2.3 (`beta_min`).
    Disoccluded,
}

impl HistorySource {
    /// The texel whose history the estimate reads, if any.
    #[inline]
    #[must_use]
    pub fn estimate_texel(self) -> Option<[u32; 2]> {
        match self {
            Self::History(q) | Self::BorderPrior(q) => Some(q),
            Self::Disoccluded => None,
        }
    }

    /// The texel whose history the update continues (only a valid history).
    #[inline]
    #[must_use]
    pub fn update_texel(self) -> Option<[u32; 2]> {
        match self {
            Self::History(q) => Some(q),
            Self::BorderPrior(_) | Self::Disoccluded => None,
        }
    }
}

/// The count of a pixel that enters the frame under the border prior (module docs):
/// [`Reprojection::entering_count`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BorderCount {
    /// The estimate from the border texel's history.
    Texel,
    /// `beta_max` (the estimate where it is 0: the zero-sample rule still holds). Its own
    /// variance takes about `1 / eta` frames to build up after the seeding, and the border
    /// texel, `ceil(|v|)` pixels away, is a guess at its needs; sampling it fully meanwhile
    /// is the conservative choice (docs/algorithms.md §2.3a measures both).
    Maximum,
}

/// The validity rule of the reprojected history: the relative depth tolerance, validated
/// once, and whether the border prior (module docs) is on. See the module docs for the rule and the motion-vector convention.
///
/// # Examples
///
/// ```
/// use spvg::reproject::Reprojection;
/// let r = Reprojection::new(0.05_f64).unwrap();
/// assert!(r.depth_agrees(1.04, 1.0));
/// assert!(!r.depth_agrees(1.06, 1.0));
/// assert!(Reprojection::new(-0.1_f64).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reprojection<T> {
    depth_tolerance: T,
    border_prior: bool,
    border_count: BorderCount,
    footprint_search: bool,
}

impl<T: Float> Default for Reprojection<T> {
    /// The default tolerance, [`DEFAULT_DEPTH_TOLERANCE`], with the border prior (count
    /// [`BorderCount::Maximum`]) and the footprint search on.
    fn default() -> Self {
        Self {
            depth_tolerance: T::from(DEFAULT_DEPTH_TOLERANCE).unwrap_or_else(T::one),
            border_prior: true,
            border_count: BorderCount::Maximum,
            footprint_search: true,
        }
    }
}

/// The `k`-th other texel (`k` = 1, 2, 3) of the 2x2 footprint around the previous
/// position of `pixel` (module docs, the footprint search): 1 the horizontal neighbour of
/// [`previous_texel`] on the side the position lies towards (left when its fraction is
/// below one half), 2 the vertical neighbour likewise, 3 the diagonal one. `None` where
/// [`previous_texel`] is `None`, where that neighbour lies outside the previous frame, on
/// an axis where the position is at the texel's centre (fraction exactly one half:
/// rounding moved nothing, as for a static camera or a pan by whole pixels, so a pixel
/// hidden behind a moving object is not handed its neighbour's history), and for any
/// other `k`.
///
/// Exact operation order in `T`, per axis: `f = (T(x) + 0.5) - v.x`,
/// `q = floor(f)`, `d = f - q` (exact): the lower neighbour when `d < 0.5`, the upper
/// one when `d > 0.5`, none when `d = 0.5`.
///
/// # Examples
///
/// ```
/// use spvg::reproject::footprint_texel;
/// // Pixel (4, 4) was at (3.3, 4.8) last frame: texel (3, 4); the point lies towards
/// // texel 2 in x and texel 5 in y.
/// let v = [1.2_f32, -0.3];
/// assert_eq!(footprint_texel([4, 4], v, [8, 8], 1), Some([2, 4]));
/// assert_eq!(footprint_texel([4, 4], v, [8, 8], 2), Some([3, 5]));
/// assert_eq!(footprint_texel([4, 4], v, [8, 8], 3), Some([2, 5]));
/// assert_eq!(footprint_texel([4, 4], v, [8, 5], 2), None); // row 5 is outside
/// ```
#[inline]
#[must_use]
pub fn footprint_texel<T: Float>(
    pixel: [u32; 2],
    motion: [T; 2],
    previous_size: [u32; 2],
    k: u32,
) -> Option<[u32; 2]> {
    let q = previous_texel(pixel, motion, previous_size)?;
    let side =
        |axis: usize| footprint_coordinate(pixel[axis], motion[axis], q[axis], previous_size[axis]);
    match k {
        1 => Some([side(0)?, q[1]]),
        2 => Some([q[0], side(1)?]),
        3 => Some([side(0)?, side(1)?]),
        _ => None,
    }
}

/// One axis of [`footprint_texel`]: the neighbour of texel `q` on the side the position
/// lies towards, if inside `[0, size)`.
#[inline]
fn footprint_coordinate<T: Float>(p: u32, v: T, q: u32, size: u32) -> Option<u32> {
    let half = T::one() / (T::one() + T::one());
    let f = (T::from(p)? + half) - v;
    let fraction = f - f.floor();
    if fraction < half {
        q.checked_sub(1)
    } else if fraction > half {
        q.checked_add(1).filter(|&n| n < size)
    } else {
        // At the texel's centre: rounding moved nothing on this axis.
        None
    }
}

impl<T: Float> Reprojection<T> {
    /// A rule with relative depth tolerance `depth_tolerance` (`|d_prev - d| <= tol * d`),
    /// the border prior (count [`BorderCount::Maximum`]) and the footprint search on.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `depth_tolerance` when it is negative or not
    /// finite. Zero is accepted: only exactly equal depths pass.
    pub fn new(depth_tolerance: T) -> Result<Self, Error> {
        if depth_tolerance.is_finite() && depth_tolerance >= T::zero() {
            Ok(Self {
                depth_tolerance,
                border_prior: true,
                border_count: BorderCount::Maximum,
                footprint_search: true,
            })
        } else {
            Err(Error::invalid(
                "depth_tolerance",
                depth_tolerance.to_f64().unwrap_or(f64::NAN),
                "must be finite and >= 0",
            ))
        }
    }

    /// The relative depth tolerance.
    #[inline]
    #[must_use]
    pub fn depth_tolerance(&self) -> T {
        self.depth_tolerance
    }

    /// The same rule with the border prior (module docs) on or off.
    ///
    /// ```
    /// use spvg::reproject::{HistorySource, PreviousSample, Reprojection};
    /// let at = |_: [u32; 2]| PreviousSample { mask: true, depth: 1.0 };
    /// let on = Reprojection::<f32>::default();
    /// let off = on.with_border_prior(false);
    /// // Pixel 7 of an 8-wide frame panning 2 px per frame was off screen last frame.
    /// let go = |r: Reprojection<f32>| r.locate([7, 0], [-2.0, 0.0], 1.0, [8, 1], [8, 1], at);
    /// assert_eq!(go(on), HistorySource::BorderPrior([5, 0]));
    /// assert_eq!(go(off), HistorySource::Disoccluded);
    /// ```
    #[inline]
    #[must_use]
    pub fn with_border_prior(self, on: bool) -> Self {
        Self {
            border_prior: on,
            ..self
        }
    }

    /// Whether the border prior is on.
    #[inline]
    #[must_use]
    pub fn border_prior(&self) -> bool {
        self.border_prior
    }

    /// The same rule with the count `count` for pixels entering the frame under the border
    /// prior.
    #[inline]
    #[must_use]
    pub fn with_border_count(self, count: BorderCount) -> Self {
        Self {
            border_count: count,
            ..self
        }
    }

    /// The count rule for pixels entering the frame under the border prior.
    #[inline]
    #[must_use]
    pub fn border_count(&self) -> BorderCount {
        self.border_count
    }

    /// The count of a pixel whose history source is [`HistorySource::BorderPrior`], from
    /// `estimate` (the controller's count from the border texel's history) and the
    /// budget's `max_samples`: `estimate` for [`BorderCount::Texel`]; for
    /// [`BorderCount::Maximum`], `max_samples` unless `estimate` is 0 (the zero-sample
    /// rule, docs/algorithms.md §2.4).
    ///
    /// ```
    /// use spvg::reproject::{BorderCount, Reprojection};
    /// let r = Reprojection::<f32>::default();
    /// assert_eq!(r.entering_count(12, 64), 64);
    /// assert_eq!(r.entering_count(0, 64), 0);
    /// assert_eq!(r.with_border_count(BorderCount::Texel).entering_count(12, 64), 12);
    /// ```
    #[inline]
    #[must_use]
    pub fn entering_count(&self, estimate: u32, max_samples: u32) -> u32 {
        match self.border_count {
            BorderCount::Maximum if estimate != 0 => max_samples,
            _ => estimate,
        }
    }

    /// The same rule with the footprint search (module docs) on or off.
    ///
    /// ```
    /// use spvg::reproject::{HistorySource, PreviousSample, Reprojection};
    /// // Last frame a sphere (depth 0.5) covered texel 3; pixel 4 sees the ground (depth 1)
    /// // that was at x = 3.9, in texel 3 but towards texel 4, which saw the ground.
    /// let at = |q: [u32; 2]| PreviousSample { mask: true, depth: if q[0] == 3 { 0.5 } else { 1.0 } };
    /// let on = Reprojection::<f32>::default();
    /// let go = |r: Reprojection<f32>| r.locate([4, 0], [0.6, 0.0], 1.0, [8, 1], [8, 1], at);
    /// assert_eq!(go(on), HistorySource::History([4, 0]));
    /// assert_eq!(go(on.with_footprint_search(false)), HistorySource::Disoccluded);
    /// ```
    #[inline]
    #[must_use]
    pub fn with_footprint_search(self, on: bool) -> Self {
        Self {
            footprint_search: on,
            ..self
        }
    }

    /// Whether the footprint search is on.
    #[inline]
    #[must_use]
    pub fn footprint_search(&self) -> bool {
        self.footprint_search
    }

    /// The relative depth test: `depth` positive and finite, and
    /// `|previous - depth| <= tol * depth`.
    ///
    /// Exact operation order in `T`: `abs(previous - depth) <= (tol * depth)`, each
    /// operation rounded once, after checking that both depths are finite: a NaN or
    /// infinite depth on either side fails, even where `tol * depth` overflows to
    /// infinity, and so does a non-positive current depth (no surface).
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::reproject::Reprojection;
    /// let r = Reprojection::<f32>::default(); // 2%
    /// assert!(r.depth_agrees(0.985, 1.0));
    /// assert!(!r.depth_agrees(0.97, 1.0));
    /// assert!(!r.depth_agrees(f32::INFINITY, 1.0));
    /// assert!(!r.depth_agrees(0.0, 0.0));
    /// ```
    #[inline]
    #[must_use]
    pub fn depth_agrees(&self, previous: T, depth: T) -> bool {
        depth > T::zero()
            && depth.is_finite()
            && previous.is_finite()
            && (previous - depth).abs() <= self.depth_tolerance * depth
    }

    /// Whether the previous frame's sample at the reprojected texel continues this pixel:
    /// its mask is set and [`depth_agrees`](Self::depth_agrees).
    #[inline]
    #[must_use]
    pub fn accepts(&self, previous: PreviousSample<T>, depth: T) -> bool {
        previous.mask && self.depth_agrees(previous.depth, depth)
    }

    /// The whole rule: the previous frame's texel whose history pixel `pixel` continues, or
    /// `None` when the history is invalid (the frame size changed, the position is outside
    /// the previous frame, the motion vector is not finite, or the previous mask or the
    /// depth test fails at the texel containing the position and, with the footprint
    /// search, at the other texels of its footprint). `previous` reads the previous frame
    /// at a texel (called only for texels inside the previous frame). The same as
    /// [`locate`](Self::locate)`(..).update_texel()` with the border prior off.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::reproject::{PreviousSample, Reprojection};
    /// let r = Reprojection::<f32>::default();
    /// let at = |_: [u32; 2]| PreviousSample { mask: true, depth: 2.0 };
    /// assert_eq!(r.reproject([5, 5], [1.0, 0.0], 2.0, [8, 8], [8, 8], at), Some([4, 5]));
    /// // A resize invalidates every history.
    /// assert_eq!(r.reproject([5, 5], [1.0, 0.0], 2.0, [8, 8], [9, 8], at), None);
    /// ```
    #[inline]
    pub fn reproject(
        &self,
        pixel: [u32; 2],
        motion: [T; 2],
        depth: T,
        size: [u32; 2],
        previous_size: [u32; 2],
        previous: impl Fn([u32; 2]) -> PreviousSample<T>,
    ) -> Option<[u32; 2]> {
        // The border prior gives no history to continue; skip its read.
        self.with_border_prior(false)
            .locate(pixel, motion, depth, size, previous_size, previous)
            .update_texel()
    }

    /// The whole rule with the border prior: [`HistorySource::History`] where
    /// [`reproject`](Self::reproject) finds a valid history; where the position lies
    /// outside the previous frame (and the sizes match, the motion is finite, the prior is
    /// on), [`HistorySource::BorderPrior`] at [`border_texel`] when that texel passes the
    /// same mask and depth tests; [`HistorySource::Disoccluded`] otherwise. Where the
    /// texel containing the position fails those tests and the footprint search is on, the
    /// first of [`footprint_texel`]`(.., 1..=3)` that passes them gives the history.
    /// `previous` is called at most four times, at texels inside the previous frame.
    ///
    /// `depth` is the depth the test compares with the previous frame's: the reprojected
    /// depth (this pixel's surface point as the previous camera saw it, module docs) where
    /// the renderer has it, else this frame's depth.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::reproject::{HistorySource, PreviousSample, Reprojection};
    /// // A dolly: the camera moved 3 units closer to a plane that was 100 units away.
    /// let before = |_: [u32; 2]| PreviousSample { mask: true, depth: 100.0_f32 };
    /// let r = Reprojection::<f32>::default(); // 2%
    /// // This frame's depth, 97, is 3% off the previous frame's: the history is dropped.
    /// assert_eq!(r.locate([2, 0], [0.0, 0.0], 97.0, [8, 1], [8, 1], before), HistorySource::Disoccluded);
    /// // The reprojected depth (the same point seen from the previous camera) is 100.
    /// assert_eq!(r.locate([2, 0], [0.0, 0.0], 100.0, [8, 1], [8, 1], before), HistorySource::History([2, 0]));
    /// ```
    ///
    /// ```
    /// use spvg::reproject::{HistorySource, PreviousSample, Reprojection};
    /// let r = Reprojection::<f32>::default();
    /// let at = |q: [u32; 2]| PreviousSample { mask: true, depth: if q[0] == 3 { 5.0 } else { 1.0 } };
    /// let go = |x: u32, vx: f32| r.locate([x, 0], [vx, 0.0], 1.0, [8, 1], [8, 1], at);
    /// assert_eq!(go(5, 1.0), HistorySource::History([4, 0]));
    /// assert_eq!(go(1, 3.0), HistorySource::Disoccluded); // inset texel 3 is farther away
    /// assert_eq!(go(6, -3.0), HistorySource::BorderPrior([4, 0]));
    /// ```
    #[inline]
    pub fn locate(
        &self,
        pixel: [u32; 2],
        motion: [T; 2],
        depth: T,
        size: [u32; 2],
        previous_size: [u32; 2],
        previous: impl Fn([u32; 2]) -> PreviousSample<T>,
    ) -> HistorySource {
        if size != previous_size {
            return HistorySource::Disoccluded;
        }
        let passes = |q: [u32; 2]| self.accepts(previous(q), depth);
        if let Some(q) = previous_texel(pixel, motion, previous_size) {
            if passes(q) {
                return HistorySource::History(q);
            }
            if self.footprint_search {
                for k in 1..=3 {
                    if let Some(q) = footprint_texel(pixel, motion, previous_size, k)
                        && passes(q)
                    {
                        return HistorySource::History(q);
                    }
                }
            }
            HistorySource::Disoccluded
        } else if self.border_prior
            && let Some(q) = border_texel(pixel, motion, previous_size)
            && passes(q)
        {
            HistorySource::BorderPrior(q)
        } else {
            HistorySource::Disoccluded
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_computed_positions() {
        // (x + 0.5 - v) by hand for f32 and f64.
        type Case = ([u32; 2], [f64; 2], Option<[u32; 2]>);
        let cases: [Case; 9] = [
            ([0, 0], [0.0, 0.0], Some([0, 0])),
            ([7, 5], [0.0, 0.0], Some([7, 5])),
            ([4, 4], [1.0, -1.0], Some([3, 5])),      // 3.5, 5.5
            ([4, 4], [0.5, 0.5], Some([4, 4])),       // 4.0 exactly: floor 4
            ([4, 4], [0.500_001, 0.0], Some([3, 4])), // 3.999999
            ([4, 4], [-3.49, 0.0], Some([7, 4])),     // 7.99
            ([4, 4], [-3.5, 0.0], None),              // 8.0 == width
            ([0, 4], [0.5, 0.0], Some([0, 4])),       // 0.0 is inside
            ([0, 4], [0.500_001, 0.0], None),         // -0.000001
        ];
        for (pixel, v, want) in cases {
            let got64 = previous_texel(pixel, v, [8, 8]);
            let got32 = previous_texel(pixel, [v[0] as f32, v[1] as f32], [8, 8]);
            assert_eq!(got64, want, "f64 {pixel:?} {v:?}");
            assert_eq!(got32, want, "f32 {pixel:?} {v:?}");
        }
    }

    #[test]
    fn non_finite_and_huge_motion_is_outside() {
        for bad in [
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            f32::MIN,
        ] {
            assert_eq!(previous_texel([3, 3], [bad, 0.0], [8, 8]), None, "x {bad}");
            assert_eq!(previous_texel([3, 3], [0.0, bad], [8, 8]), None, "y {bad}");
        }
        // Subnormal motion is below the rounding of x + 0.5: the pixel itself.
        let tiny = f32::from_bits(1);
        assert_eq!(previous_texel([3, 3], [tiny, -tiny], [8, 8]), Some([3, 3]));
    }

    #[test]
    fn empty_previous_frame_has_no_texel() {
        assert_eq!(previous_texel([0, 0], [0.0_f32, 0.0], [0, 8]), None);
        assert_eq!(previous_texel([0, 0], [0.0_f32, 0.0], [8, 0]), None);
    }

    #[test]
    fn largest_frames_round_exactly() {
        // Last column of a 16384-wide frame, moved by a quarter pixel: 16383.75 - 0.25.
        let w = 16_384;
        assert_eq!(
            previous_texel([w - 1, 0], [0.25_f32, 0.0], [w, 1]),
            Some([w - 1, 0])
        );
        assert_eq!(previous_texel([w - 1, 0], [-0.5_f32, 0.0], [w, 1]), None);
    }

    #[test]
    fn depth_test_hand_cases() {
        // Exactly representable operands: the boundary is inclusive.
        let quarter = Reprojection::new(0.25_f64).unwrap();
        assert!(
            quarter.depth_agrees(2.5, 2.0),
            "at the tolerance: 0.5 <= 0.25 * 2"
        );
        assert!(
            quarter.depth_agrees(1.5, 2.0),
            "at the tolerance from below"
        );
        assert!(
            !quarter.depth_agrees(2.5 + 2.0 * f64::EPSILON, 2.0),
            "one ulp past the tolerance"
        );
        let r = Reprojection::new(0.02_f64).unwrap();
        assert!(r.depth_agrees(1.0, 1.0), "equal depths");
        assert!(r.depth_agrees(1.019, 1.0), "1.9% off");
        assert!(!r.depth_agrees(1.021, 1.0), "2.1% off");
        assert!(r.depth_agrees(98.1, 100.0), "relative to the current depth");
        assert!(!r.depth_agrees(97.9, 100.0), "2.1% off at depth 100");
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(!r.depth_agrees(bad, 1.0), "previous {bad}");
            assert!(!r.depth_agrees(1.0, bad), "current {bad}");
        }
        assert!(!r.depth_agrees(0.0, 0.0), "no surface");
        assert!(!r.depth_agrees(-1.0, -1.0), "negative depth");
        let exact = Reprojection::new(0.0_f32).unwrap();
        assert!(exact.depth_agrees(0.5, 0.5), "tolerance 0, equal");
        assert!(
            !exact.depth_agrees(0.5 + f32::EPSILON, 0.5),
            "tolerance 0, one ulp"
        );
    }

    #[test]
    fn tolerance_validation_names_the_field() {
        for bad in [-1e-9_f32, f32::NAN, f32::INFINITY] {
            match Reprojection::new(bad) {
                Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, "depth_tolerance"),
                other => panic!("{bad}: expected an error, got {other:?}"),
            }
        }
        assert_eq!(
            Reprojection::<f32>::default().depth_tolerance(),
            0.02,
            "documented default"
        );
    }

    /// A previous frame: a surface at depth 1 with an occluder at depth 0.5 over columns
    /// 2..4 and the mask off in column `hole`.
    fn occluded_surface(hole: u32) -> impl Fn([u32; 2]) -> PreviousSample<f32> + Copy {
        move |q: [u32; 2]| PreviousSample {
            mask: q[0] != hole,
            depth: if (2..4).contains(&q[0]) { 0.5 } else { 1.0 },
        }
    }

    #[test]
    fn whole_rule() {
        let r = Reprojection::<f32>::default();
        let prev = occluded_surface(7);
        let size = [8, 4];
        let go = |x: u32, vx: f32| r.reproject([x, 1], [vx, 0.0], 1.0, size, size, prev);
        assert_eq!(go(5, 0.0), Some([5, 1]), "static, steady");
        assert_eq!(go(3, 0.0), None, "behind the occluder last frame");
        assert_eq!(go(5, 2.0), None, "moved from under the occluder");
        assert_eq!(go(6, 2.0), Some([4, 1]), "moved from the open surface");
        assert_eq!(go(6, -1.0), None, "previous mask off");
        assert_eq!(go(1, 2.0), None, "entered from off screen");
        let calls = core::cell::Cell::new(0);
        let counting = |q: [u32; 2]| {
            calls.set(calls.get() + 1);
            prev(q)
        };
        assert_eq!(
            r.reproject([1, 1], [5.0, 0.0], 1.0, size, size, counting),
            None,
            "outside"
        );
        assert_eq!(calls.get(), 0, "the previous frame is not read outside it");
        assert_eq!(
            r.reproject([5, 1], [0.0, 0.0], 1.0, size, [8, 5], prev),
            None,
            "resized"
        );
    }

    #[test]
    fn footprint_texels_are_the_bilinear_footprint() {
        // Against the bilinear footprint in f64: per axis the texels floor(x_prev - 0.5)
        // and that + 1 (the two whose centres bracket x_prev); the neighbour is the one of
        // them that is not the texel containing x_prev, and there is none when x_prev is
        // at a centre (both bilinear weights on the other texel are 0 there).
        let size = [6_u32, 5];
        let motions = [
            -7.5, -2.25, -0.75, -0.5, -0.1, 0.0, 0.3, 0.5, 1.0, 1.6, 4.9, 9.0,
        ];
        let other = |p: u32, v: f64, n: u32| -> Option<u32> {
            let x = f64::from(p) + 0.5 - v;
            let (q, lo) = (x.floor(), (x - 0.5).floor());
            if x - q == 0.5 {
                return None;
            }
            let o = if lo == q { lo + 1.0 } else { lo };
            (o >= 0.0 && o < f64::from(n)).then_some(o as u32)
        };
        for (x, y) in (0..size[0]).flat_map(|x| (0..size[1]).map(move |y| (x, y))) {
            for &vx in &motions {
                for &vy in &motions {
                    let v = [vx as f32, vy as f32];
                    let q = previous_texel([x, y], v, size);
                    let got: [Option<[u32; 2]>; 3] =
                        core::array::from_fn(|k| footprint_texel([x, y], v, size, k as u32 + 1));
                    let want = q.map_or([None; 3], |q| {
                        let (ox, oy) = (other(x, vx, size[0]), other(y, vy, size[1]));
                        [
                            ox.map(|o| [o, q[1]]),
                            oy.map(|o| [q[0], o]),
                            ox.zip(oy).map(|(a, b)| [a, b]),
                        ]
                    });
                    assert_eq!(got, want, "({x},{y}) v ({vx},{vy})");
                    assert_eq!(footprint_texel([x, y], v, size, 0), None, "k = 0");
                    assert_eq!(footprint_texel([x, y], v, size, 4), None, "k = 4");
                }
            }
        }
    }

    #[test]
    fn footprint_search_finds_the_surface_next_to_a_silhouette() {
        let r = Reprojection::<f32>::default();
        // Occluder over columns 2..4 last frame (texels 2 and 3).
        let prev = occluded_surface(99);
        let size = [8, 1];
        let go = |r: Reprojection<f32>, x: u32, vx: f32| {
            r.locate([x, 0], [vx, 0.0], 1.0, size, size, prev)
        };
        // x_prev = 4.5 - 0.7 = 3.8: texel 3 (occluder) contains it; texel 4 saw the surface.
        assert_eq!(
            go(r, 4, 0.7),
            HistorySource::History([4, 0]),
            "one texel away"
        );
        assert_eq!(
            go(r.with_footprint_search(false), 4, 0.7),
            HistorySource::Disoccluded,
            "nearest texel only"
        );
        // x_prev = 3.5 - 0.7 = 2.8: texels 2 and 3 both saw the occluder.
        assert_eq!(
            go(r, 3, 0.7),
            HistorySource::Disoccluded,
            "hidden on the whole footprint"
        );
        // A static camera: the position is at a texel centre, no neighbour is tried.
        assert_eq!(go(r, 3, 0.0), HistorySource::Disoccluded, "static, hidden");
    }

    #[test]
    fn border_texel_is_the_clamped_position() {
        // Against a brute-force reference in f64: the in-frame texel nearest to the real
        // position (x + 0.5 - v), which is the clamp of its floor.
        let size = [8_u32, 5];
        let motions = [
            -20.25, -16.5, -7.5, -3.0, -0.5, 0.0, 0.49, 1.0, 2.75, 9.0, 13.0, 100.0,
        ];
        for x in 0..size[0] {
            for y in 0..size[1] {
                for &vx in &motions {
                    for &vy in &motions {
                        let px = (f64::from(x) + 0.5 - vx).floor();
                        let py = (f64::from(y) + 0.5 - vy).floor();
                        // Inside: the texel; past an edge: ceil(|v|) texels in from it.
                        let pick = |p: f64, v: f64, n: u32| {
                            let last = f64::from(n - 1);
                            let inset = v.abs().ceil().min(last);
                            if p < 0.0 {
                                inset as u32
                            } else if p > last {
                                (last - inset) as u32
                            } else {
                                p as u32
                            }
                        };
                        // The motion bound: more than the frame size past an edge.
                        let bounded = |p: f64, n: u32| p >= -f64::from(n) && p < 2.0 * f64::from(n);
                        let want = (bounded(px, size[0]) && bounded(py, size[1]))
                            .then(|| [pick(px, vx, size[0]), pick(py, vy, size[1])]);
                        let got = border_texel([x, y], [vx as f32, vy as f32], size);
                        assert_eq!(got, want, "({x},{y}) v ({vx},{vy})");
                        if let Some(q) = previous_texel([x, y], [vx as f32, vy as f32], size) {
                            assert_eq!(got, Some(q), "inside: the reprojected texel");
                        }
                    }
                }
            }
        }
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            assert_eq!(border_texel([1, 1], [bad, 0.0], size), None, "x {bad}");
            assert_eq!(border_texel([1, 1], [0.0, bad], size), None, "y {bad}");
        }
        assert_eq!(
            border_texel([0, 0], [8.5_f32, 0.0], size),
            Some([7, 0]),
            "a frame's width past the edge: the inset spans the frame"
        );
        for huge in [8.6_f32, 1e30, f32::MAX, -3e9, f32::MIN] {
            assert_eq!(border_texel([0, 0], [huge, 0.0], size), None, "x {huge}");
            assert_eq!(border_texel([0, 0], [0.0, huge], size), None, "y {huge}");
        }
        assert_eq!(
            border_texel([0, 0], [0.0_f32, 0.0], [0, 5]),
            None,
            "empty frame"
        );
    }

    #[test]
    fn locate_follows_the_rule() {
        let r = Reprojection::<f32>::default();
        let prev = occluded_surface(0);
        let size = [8, 1];
        let go = |x: u32, vx: f32| r.locate([x, 0], [vx, 0.0], 1.0, size, size, prev);
        assert_eq!(go(6, 1.0), HistorySource::History([5, 0]), "valid history");
        assert_eq!(
            go(3, 0.0),
            HistorySource::Disoccluded,
            "behind the occluder"
        );
        assert_eq!(
            go(6, -3.0),
            HistorySource::BorderPrior([4, 0]),
            "entered at the right: 3 texels in from texel 7"
        );
        assert_eq!(
            go(1, 4.0),
            HistorySource::BorderPrior([4, 0]),
            "entered at the left: 4 texels in from texel 0"
        );
        assert_eq!(
            go(1, 2.0),
            HistorySource::Disoccluded,
            "inset texel 2 is under the occluder"
        );
        let deep = |q: [u32; 2]| PreviousSample {
            mask: true,
            depth: if q[0] == 4 { 2.0 } else { 1.0 },
        };
        assert_eq!(
            r.locate([6, 0], [-3.0, 0.0], 1.0, size, size, deep),
            HistorySource::Disoccluded,
            "border texel fails the depth test"
        );
        assert_eq!(
            r.locate([6, 0], [-3.0, 0.0], 1.0, size, [8, 2], prev),
            HistorySource::Disoccluded,
            "resized"
        );
        assert_eq!(
            r.with_border_prior(false)
                .locate([6, 0], [-3.0, 0.0], 1.0, size, size, prev),
            HistorySource::Disoccluded,
            "prior off"
        );
        // Where locate finds a history, it is reproject's.
        for x in 0..8 {
            for vx in [-9.0, -2.5, -1.0, 0.0, 0.7, 3.0, 8.0] {
                let a = go(x, vx).update_texel();
                let b = r.reproject([x, 0], [vx, 0.0], 1.0, size, size, prev);
                assert_eq!(a, b, "x {x} v {vx}");
            }
        }
    }
}

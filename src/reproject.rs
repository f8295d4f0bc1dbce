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
//! the disocclusion path of docs/algorithms.md §2.3, first-observation seeding):
//! - the frame size did not change since the previous frame;
//! - `floor(x_prev)` lies inside the previous frame (a NaN or infinite motion vector never
//!   does);
//! - the previous frame's mask (the pass's own coverage, e.g. the subsurface mask) is set
//!   there;
//! - the relative depth test passes: `|d_prev - d| <= tol * d`, with `d_prev` the previous
//!   frame's depth at `floor(x_prev)` and `d` this pixel's depth (positive and finite; the
//!   depth of the surface point as the previous camera saw it where the renderer has it,
//!   otherwise its current depth, in which case `tol` must also cover the per-frame depth
//!   change of objects moving towards the camera).
//!
//! The default tolerance, [`DEFAULT_DEPTH_TOLERANCE`] = 2%, covers the depth slope across
//! the half texel that nearest-texel rounding can move on a surface up to about 88 degrees
//! from the view direction with 1-milliradian pixels (half a pixel of a plane at angle
//! `theta` changes the depth by `0.5e-3 tan(theta)` of itself), while an occluder in front
//! of the surface, or the surface behind it, is rejected whenever the two are more than 2%
//! of the depth apart.
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
    let x = previous_coordinate(pixel[0], motion[0], previous_size[0])?;
    let y = previous_coordinate(pixel[1], motion[1], previous_size[1])?;
    Some([x, y])
}

/// One axis of [`previous_texel`].
#[inline]
fn previous_coordinate<T: Float>(p: u32, v: T, size: u32) -> Option<u32> {
    let half = T::one() / (T::one() + T::one());
    let q = ((T::from(p)? + half) - v).floor();
    if q >= T::zero() && q < T::from(size)? {
        q.to_u32()
    } else {
        None
    }
}

/// The validity rule of the reprojected history: the relative depth tolerance, validated
/// once. See the module docs for the rule and the motion-vector convention.
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
}

impl<T: Float> Default for Reprojection<T> {
    /// The default tolerance, [`DEFAULT_DEPTH_TOLERANCE`].
    fn default() -> Self {
        Self {
            depth_tolerance: T::from(DEFAULT_DEPTH_TOLERANCE).unwrap_or_else(T::one),
        }
    }
}

impl<T: Float> Reprojection<T> {
    /// A rule with relative depth tolerance `depth_tolerance` (`|d_prev - d| <= tol * d`).
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `depth_tolerance` when it is negative or not
    /// finite. Zero is accepted: only exactly equal depths pass.
    pub fn new(depth_tolerance: T) -> Result<Self, Error> {
        if depth_tolerance.is_finite() && depth_tolerance >= T::zero() {
            Ok(Self { depth_tolerance })
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

    /// The relative depth test: `depth` positive and finite, and
    /// `|previous - depth| <= tol * depth`.
    ///
    /// Exact operation order in `T`: `abs(previous - depth) <= (tol * depth)`, each
    /// operation rounded once. A NaN or infinite depth on either side fails (an infinite
    /// `previous` gives an infinite difference, NaN compares false), and so does a
    /// non-positive current depth (no surface).
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
    /// the previous frame, the motion vector is not finite, the previous mask is not set
    /// there, or the depth test fails). `previous` reads the previous frame at a texel
    /// (called only for a texel inside the previous frame).
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
        previous: impl FnOnce([u32; 2]) -> PreviousSample<T>,
    ) -> Option<[u32; 2]> {
        if size != previous_size {
            return None;
        }
        let q = previous_texel(pixel, motion, previous_size)?;
        self.accepts(previous(q), depth).then_some(q)
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

    #[test]
    fn whole_rule() {
        let r = Reprojection::<f32>::default();
        // Previous frame: an 8x4 surface at depth 1 with an occluder at depth 0.5 over
        // columns 2..4 and the mask off in column 7.
        let prev = |q: [u32; 2]| PreviousSample {
            mask: q[0] != 7,
            depth: if (2..4).contains(&q[0]) { 0.5 } else { 1.0 },
        };
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
}

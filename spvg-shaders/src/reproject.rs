//! The reprojection rule as the library's functions take it: `spvg_Reprojection` in WGSL.

use bytemuck::{Pod, Zeroable};
use spvg::reproject::{BorderCount, Reprojection};

/// [`ReprojectionRule::flags`] bit: the border prior
/// ([`Reprojection::border_prior`]); `spvg_REPROJECT_BORDER_PRIOR` in WGSL.
pub const REPROJECT_BORDER_PRIOR: u32 = 1;
/// [`ReprojectionRule::flags`] bit: the footprint search
/// ([`Reprojection::footprint_search`]); `spvg_REPROJECT_FOOTPRINT` in WGSL.
pub const REPROJECT_FOOTPRINT: u32 = 2;
/// [`ReprojectionRule::flags`] bit: pixels entering under the border prior take `beta_max`
/// ([`BorderCount::Maximum`]; without it [`BorderCount::Texel`]);
/// `spvg_REPROJECT_BORDER_MAXIMUM` in WGSL.
pub const REPROJECT_BORDER_MAXIMUM: u32 = 4;

/// A [`Reprojection`] rule as `spvg_reproject_locate_start`, `spvg_reproject_locate` and
/// `spvg_reproject_entering_count` take it: the relative depth tolerance and the
/// `spvg_REPROJECT_*` switches. Upload it in your own uniform block (8 bytes; as a member
/// of a WGSL uniform struct it sits at a 16-byte aligned offset) or pass its two fields to
/// the WGSL constructor `spvg_Reprojection(depth_tolerance, flags)`.
///
/// WGSL twin: `struct spvg_Reprojection` in `wgsl/reproject.wgsl`, same field order;
/// `tests/naga.rs` checks the layout and the flag values against the WGSL.
///
/// # Examples
///
/// ```
/// use spvg::reproject::{BorderCount, Reprojection};
/// use spvg_shaders::{REPROJECT_BORDER_PRIOR, REPROJECT_FOOTPRINT, ReprojectionRule};
///
/// // The default rule: 2% depth tolerance, every switch on (`spvg_REPROJECT_DEFAULT_FLAGS`).
/// let rule = ReprojectionRule::new(&Reprojection::default());
/// assert_eq!((rule.depth_tolerance, rule.flags), (0.02, 7));
///
/// // The border prior with the border texel's own count, no footprint search.
/// let texel = Reprojection::new(0.05)?
///     .with_border_count(BorderCount::Texel)
///     .with_footprint_search(false);
/// let rule = ReprojectionRule::new(&texel);
/// assert_eq!(rule.flags, REPROJECT_BORDER_PRIOR);
/// assert_eq!(rule.flags & REPROJECT_FOOTPRINT, 0);
/// assert_eq!(bytemuck::bytes_of(&rule).len(), 8);
/// # Ok::<(), spvg::Error>(())
/// ```
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ReprojectionRule {
    /// The relative depth tolerance `tol` of `|d_prev - d| <= tol * d`
    /// ([`Reprojection::depth_tolerance`]).
    pub depth_tolerance: f32,
    /// [`REPROJECT_BORDER_PRIOR`], [`REPROJECT_FOOTPRINT`] and [`REPROJECT_BORDER_MAXIMUM`],
    /// each set where the rule has that switch on.
    pub flags: u32,
}

const _: () = assert!(
    size_of::<ReprojectionRule>() == 8,
    "ReprojectionRule must match the 8-byte WGSL struct spvg_Reprojection"
);

impl ReprojectionRule {
    /// The block of `rule`: its depth tolerance, and a flag for each switch that is on.
    #[inline]
    #[must_use]
    pub fn new(rule: &Reprojection<f32>) -> Self {
        let bit = |on: bool, flag: u32| if on { flag } else { 0 };
        Self {
            depth_tolerance: rule.depth_tolerance(),
            flags: bit(rule.border_prior(), REPROJECT_BORDER_PRIOR)
                | bit(rule.footprint_search(), REPROJECT_FOOTPRINT)
                | bit(
                    rule.border_count() == BorderCount::Maximum,
                    REPROJECT_BORDER_MAXIMUM,
                ),
        }
    }
}

impl From<&Reprojection<f32>> for ReprojectionRule {
    #[inline]
    fn from(rule: &Reprojection<f32>) -> Self {
        Self::new(rule)
    }
}

impl Default for ReprojectionRule {
    /// The block of [`Reprojection::default`].
    fn default() -> Self {
        Self::new(&Reprojection::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every combination of the three switches: each sets its own bit and no other, and
    /// the tolerance passes through unchanged.
    #[test]
    fn each_switch_sets_its_own_bit() {
        for k in 0..8_u32 {
            let (prior, footprint, maximum) = (k & 1 != 0, k & 2 != 0, k & 4 != 0);
            let count = if maximum {
                BorderCount::Maximum
            } else {
                BorderCount::Texel
            };
            let tolerance = 0.01 + 0.01 * k as f32;
            let rule = Reprojection::new(tolerance)
                .expect("valid tolerance")
                .with_border_prior(prior)
                .with_footprint_search(footprint)
                .with_border_count(count);
            let block = ReprojectionRule::new(&rule);
            assert_eq!(
                block.depth_tolerance, tolerance,
                "tolerance of switches {k:03b}"
            );
            assert_eq!(
                block.flags & REPROJECT_BORDER_PRIOR != 0,
                prior,
                "border prior of switches {k:03b}: flags {:03b}",
                block.flags
            );
            assert_eq!(
                block.flags & REPROJECT_FOOTPRINT != 0,
                footprint,
                "footprint search of switches {k:03b}: flags {:03b}",
                block.flags
            );
            assert_eq!(
                block.flags & REPROJECT_BORDER_MAXIMUM != 0,
                maximum,
                "border count of switches {k:03b}: flags {:03b}",
                block.flags
            );
            assert_eq!(
                block.flags
                    & !(REPROJECT_BORDER_PRIOR | REPROJECT_FOOTPRINT | REPROJECT_BORDER_MAXIMUM),
                0,
                "no other bit: flags {:03b}",
                block.flags
            );
            assert_eq!(
                ReprojectionRule::from(&rule),
                block,
                "From is new for switches {k:03b}"
            );
        }
    }
}

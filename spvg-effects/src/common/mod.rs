//! What both consumers ([`crate::sss`] and [`crate::ao`]) use and the component does not:
//! the polynomial sample direction `unit_dir` (`src/common/direction.wgsl`) and its CPU
//! twin.

/// The WGSL of `unit_dir` (`src/common/direction.wgsl`), joined after the library by each
/// consumer that turns a random word into a direction.
pub(crate) const DIRECTION_WGSL: &str = include_str!("direction.wgsl");

/// WGSL twin: `unit_dir`: unit vector at angle `2 pi x / 2^32` by quadrant and Taylor
/// polynomials (same op order as the WGSL; the built-in sin/cos differ between drivers:
/// Vulkan allows an absolute error of 2^-11).
#[inline]
#[must_use]
pub(crate) fn unit_dir(x: u32) -> [f32; 2] {
    let t = ((x >> 6) & 0x00ff_ffff) as f32 * (1.0 / 16_777_216.0) * core::f32::consts::FRAC_PI_2;
    let t2 = t * t;
    let s = t
        * (1.0
            + t2 * (-1.0 / 6.0
                + t2 * (1.0 / 120.0
                    + t2 * (-1.0 / 5040.0 + t2 * (1.0 / 362_880.0 + t2 * (-1.0 / 39_916_800.0))))));
    let c = 1.0
        + t2 * (-0.5
            + t2 * (1.0 / 24.0
                + t2 * (-1.0 / 720.0
                    + t2 * (1.0 / 40320.0
                        + t2 * (-1.0 / 3_628_800.0 + t2 * (1.0 / 479_001_600.0))))));
    match x >> 30 {
        0 => [c, s],
        1 => [-s, c],
        2 => [-c, -s],
        _ => [s, -c],
    }
}

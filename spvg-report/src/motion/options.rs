//! What the motion section runs: frame sizes, frames, the controller, the reference's
//! quadrature and the suite.

use spvg::SpvgConfig;

/// The AO consumer's target variance when `--ao-sigma0-sq` is not given: the library's
/// published default.
pub const DEFAULT_TARGET: f32 = 1e-4;

/// Settings of the motion section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionOptions {
    /// Frame size of the pans and their static camera (wide, so that the pixels entering
    /// at 8 px per frame are a small part of the frame, as at real resolutions).
    pub pan_size: [u32; 2],
    /// Frame size of the rotation, the moving objects, the dolly and their static camera.
    pub size: [u32; 2],
    /// Frame size of the mesh scene (`crate::motion::mesh`).
    pub mesh_size: [u32; 2],
    /// Run the mesh scene alone (`spvg-report motion --only-mesh`).
    pub only_mesh: bool,
    /// Frames per run.
    pub frames: u32,
    /// The controller (AS).
    pub config: SpvgConfig<f32>,
    /// Directions per axis of the reference quadrature (`grid^2` per pixel).
    pub grid: u32,
    /// Count dilation radius of the AS runs (`spvg::dilation`).
    pub dilation: u32,
    /// The whole suite ([`crate::motion::scenes::variants`]): every pan, every knob row and
    /// young-history row, the TAA-guided update, and every frame scored
    /// ([`crate::motion::frames::scored`]).
    pub full: bool,
}

impl MotionOptions {
    /// The defaults: pans at 384x192, the mesh at 64x48, the rest at 128x96, 48 frames, `sigma0^2 = 1e-4`
    /// (the library's published default), budget [8, 64], a 32x32 reference grid, count
    /// dilation radius 1, the default suite (not [`full`](Self::full)).
    ///
    /// # Errors
    ///
    /// Never with these constants; typed for a caller that changes them.
    pub fn new() -> Result<Self, spvg::Error> {
        Ok(Self {
            pan_size: [384, 192],
            size: [128, 96],
            mesh_size: [64, 48],
            only_mesh: false,
            frames: 48,
            config: SpvgConfig::builder()
                .target_variance(DEFAULT_TARGET)
                .build()?,
            grid: 32,
            dilation: 1,
            full: false,
        })
    }

    /// The whole suite ([`new`](Self::new) with [`full`](Self::full) set).
    ///
    /// # Errors
    ///
    /// As [`new`](Self::new).
    pub fn full() -> Result<Self, spvg::Error> {
        Ok(Self {
            full: true,
            ..Self::new()?
        })
    }
}

//! Separable subsurface scattering (docs/algorithms.md §5.1): the configuration, the kernel
//! built from the material's Burley profiles, and the uniform block of
//! `shaders/separable.wgsl`.
//!
//! Per channel, the material's Burley profile gives the falloff of the separable profile
//! nearest it in shape ([`spvg::burley::fit_falloff`] with [`FalloffMatch::Shape`]); the
//! falloff gives the pre-integrated rank-1 kernel
//! ([`spvg::burley::SeparableProfile::fill_kernel`]), offsets in mm shared by the three
//! channels, weights per channel normalised to 1. Only the rank-1 form is offered (see
//! docs/algorithms.md §5.1 for why not rank r).

use spvg::Error;
use spvg::burley::{
    FalloffMatch, MaterialPreset, SeparableProfile, ShapeFit, fit_falloff, kernel_range,
};

use super::Model;

/// Most taps the separable kernel may have (the WGSL block's array length,
/// `SEP_MAX_SAMPLES` in `shaders/separable.wgsl`).
pub const MAX_SEPARABLE_SAMPLES: usize = 33;

/// How a frame renders its subsurface scattering: Monte Carlo sampling of Burley's profile
/// under a sample-count [`Model`], the separable filter, or both in one frame (the hybrid
/// pass: Monte Carlo where the caller tags the pixels, the separable filter elsewhere).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Technique {
    /// Burley sampling with a sample-count model (the [`crate::sss::SssPass`]).
    Sampled(Model),
    /// The separable filter everywhere ([`crate::sss::SeparablePass`]).
    Separable,
}

impl Technique {
    /// Short name for tables (`separable`, or the model's name).
    #[must_use]
    pub fn name(&self) -> String {
        match self {
            Self::Sampled(m) => m.name(),
            Self::Separable => "separable".into(),
        }
    }
}

/// Settings of the separable filter, validated when the block is built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeparableConfig {
    /// Taps per direction: odd, 3 to [`MAX_SEPARABLE_SAMPLES`] (default 17). The kernel spans
    /// 2 mm on each side, 3 mm above 20 taps.
    pub samples: u32,
    /// Blend with the unfiltered pixel, in `[0, 1]` (1: the kernel alone). The separable
    /// profile leaves out the narrowest Gaussian of the skin fit and lets this blend stand
    /// for it; the centre tap's weight becomes `1 - strength + strength w_c`, the others
    /// `strength w_i`, in each direction.
    pub strength: f32,
    /// What the falloff fit compares ([`FalloffMatch::Shape`]: the normalised kernel's
    /// width, which is what the filter uses).
    pub matching: FalloffMatch,
    /// Texel width at unit depth (as `PassConfig::w_px`).
    pub w_px: f32,
    /// Texel height at unit depth (as `PassConfig::h_px`).
    pub h_px: f32,
}

impl Default for SeparableConfig {
    fn default() -> Self {
        Self {
            samples: 17,
            strength: 1.0,
            matching: FalloffMatch::Shape,
            w_px: 1e-3,
            h_px: 1e-3,
        }
    }
}

/// The uniform block of the separable passes.
///
/// WGSL twin: `struct SeparableParams` in `sss/shaders/separable.wgsl`; same field order
/// and types, 560 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SeparableParams {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Taps in use (the first `samples` entries of `kernel`).
    pub samples: u32,
    /// 1 in a hybrid frame: pixels tagged 1 hold the AFIS result (see the shader).
    pub hybrid: u32,
    /// Texel width at unit depth.
    pub w_px: f32,
    /// Texel height at unit depth.
    pub h_px: f32,
    /// Spare, 0 (aligns the kernel to 16 bytes, as WGSL places it).
    pub reserved: [u32; 2],
    /// `(offset mm, weight R, weight G, weight B)` per tap; unused taps are 0.
    pub kernel: [[f32; 4]; MAX_SEPARABLE_SAMPLES],
}

const _: () = assert!(
    size_of::<SeparableParams>() == 32 + 16 * MAX_SEPARABLE_SAMPLES,
    "SeparableParams must match the WGSL struct"
);

impl SeparableConfig {
    /// The default filter on the texel size of a subsurface pass's configuration, so that
    /// the two techniques of a hybrid frame measure millimetres alike.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg_effects::sss::{PassConfig, SeparableConfig};
    /// let pass = PassConfig { w_px: 2e-3, ..PassConfig::default() };
    /// assert_eq!(SeparableConfig::for_pass(&pass).w_px, 2e-3);
    /// ```
    #[must_use]
    pub fn for_pass(pass: &super::PassConfig) -> Self {
        Self {
            w_px: pass.w_px,
            h_px: pass.h_px,
            ..Self::default()
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `samples` (even, below 3 or above
    /// [`MAX_SEPARABLE_SAMPLES`]), `strength` (outside `[0, 1]` or NaN), `w_px` or `h_px`
    /// (not finite and positive).
    pub fn validate(&self) -> Result<(), Error> {
        let n = self.samples as usize;
        if !(3..=MAX_SEPARABLE_SAMPLES).contains(&n) || n.is_multiple_of(2) {
            return Err(Error::invalid(
                "samples",
                f64::from(self.samples),
                "must be odd, from 3 to 33",
            ));
        }
        if !(0.0..=1.0).contains(&self.strength) {
            return Err(Error::invalid(
                "strength",
                f64::from(self.strength),
                "must be in [0, 1]",
            ));
        }
        for (name, v) in [("w_px", self.w_px), ("h_px", self.h_px)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::invalid(name, f64::from(v), "must be finite and > 0"));
            }
        }
        Ok(())
    }

    /// The falloff per channel of `material` (default shape fit), as the kernel uses it.
    ///
    /// # Errors
    ///
    /// As [`MaterialPreset::profiles`].
    pub fn falloffs(&self, material: &MaterialPreset) -> Result<[f64; 3], Error> {
        let p = material.profiles::<f64>(ShapeFit::DiffuseMeanFreePath)?;
        Ok(p.map(|c| fit_falloff(&c, self.matching).falloff))
    }

    /// The kernel of `material`: `(offset mm, w_r, w_g, w_b)` per tap, `samples` taps,
    /// weights per channel summing to 1 (after the strength blend).
    ///
    /// # Errors
    ///
    /// As [`SeparableConfig::validate`] and [`SeparableConfig::falloffs`].
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::burley::presets::SKIN1;
    /// use spvg_effects::sss::SeparableConfig;
    /// let k = SeparableConfig::default().kernel(&SKIN1).unwrap();
    /// assert_eq!(k.len(), 17);
    /// for c in 1..4 {
    ///     let sum: f32 = k.iter().map(|t| t[c]).sum();
    ///     assert!((sum - 1.0).abs() < 1e-5, "{sum}");
    /// }
    /// // The red profile of skin is the widest: its centre tap weighs least.
    /// assert!(k[8][1] < k[8][3]);
    /// ```
    pub fn kernel(&self, material: &MaterialPreset) -> Result<Vec<[f32; 4]>, Error> {
        self.validate()?;
        let n = self.samples as usize;
        let mut offsets = vec![0.0_f64; n];
        let mut weights = [vec![0.0_f64; n], vec![0.0_f64; n], vec![0.0_f64; n]];
        for (c, f) in self.falloffs(material)?.into_iter().enumerate() {
            SeparableProfile::new(f)?.fill_kernel(&mut offsets, &mut weights[c])?;
        }
        let s = f64::from(self.strength);
        let centre = n / 2;
        debug_assert_eq!(offsets[centre], 0.0, "the centre tap sits at offset 0");
        debug_assert_eq!(
            offsets[n - 1],
            kernel_range(n),
            "the kernel spans its range"
        );
        Ok((0..n)
            .map(|i| {
                let w = |c: usize| {
                    let base = s * weights[c][i];
                    (if i == centre { 1.0 - s + base } else { base }) as f32
                };
                [offsets[i] as f32, w(0), w(1), w(2)]
            })
            .collect())
    }

    /// The uniform block for a `width x height` frame of `material`; `hybrid` marks a
    /// hybrid frame (pixels tagged AFIS hold the Monte Carlo result).
    ///
    /// # Errors
    ///
    /// As [`SeparableConfig::kernel`].
    pub fn params(
        &self,
        material: &MaterialPreset,
        width: u32,
        height: u32,
        hybrid: bool,
    ) -> Result<SeparableParams, Error> {
        let taps = self.kernel(material)?;
        let mut kernel = [[0.0_f32; 4]; MAX_SEPARABLE_SAMPLES];
        kernel[..taps.len()].copy_from_slice(&taps);
        Ok(SeparableParams {
            width,
            height,
            samples: self.samples,
            hybrid: u32::from(hybrid),
            w_px: self.w_px,
            h_px: self.h_px,
            reserved: [0; 2],
            kernel,
        })
    }
}

//! Parameters of the subsurface pass: the validated host-side configuration and the uniform
//! block shared with WGSL.

use spvg::Error;
use spvg::SpvgConfig;
use spvg::burley::{BurleyProfile, MaterialPreset, ShapeFit};
use spvg::cv::Ocv;
use spvg::texel::{Layout, TexelEncoding};
use spvg_shaders::{Control, Params, Storage, StoreRounding};

use crate::adaptive::Controller;

/// The sample-count model a pass runs: the fixed-count baseline, or one of the
/// component's control models ([`Control`]; [`PassConfig::control`] gives the model's
/// `Control` with the configuration's OCV parameters, which `Model` does not carry so that
/// it stays `Eq` and `Hash` for tables).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Model {
    /// A fixed number of distant samples per pixel, no history (baseline).
    Fixed(u32),
    /// Plain adaptive sampling: SPVG monitoring the distant estimate (`alpha = 0`).
    As,
    /// Constant control variate (`alpha = 1`), one history texel like AS.
    Ccv,
    /// Online control variate: a second history texel `J` and a per-pixel `alpha`.
    Ocv,
}

impl Model {
    /// Short name used in tables and file names (`fixed16`, `as`, `ccv`, `ocv`).
    #[must_use]
    pub fn name(&self) -> String {
        match self {
            Self::Fixed(n) => format!("fixed{n}"),
            Self::As => "as".into(),
            Self::Ccv => "ccv".into(),
            Self::Ocv => "ocv".into(),
        }
    }

    /// Number of RGBA16F history texels the model keeps per pixel (each 8 bytes).
    #[inline]
    #[must_use]
    pub fn history_texels(&self) -> u32 {
        match self {
            Self::Fixed(_) => 0,
            Self::As | Self::Ccv => 1,
            Self::Ocv => 2,
        }
    }

    /// Bytes of history per pixel that the model keeps between frames (the read/write
    /// ping-pong copy not counted: a renderer can alias it with other transient targets):
    /// its control model's [`Control::history_bytes_per_pixel`], 0 for the fixed count.
    #[inline]
    #[must_use]
    pub fn history_bytes_per_pixel(&self) -> u32 {
        8 * self.history_texels()
    }
}

/// Controller and estimator settings, validated once (docs/algorithms.md §2, §3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PassConfig {
    /// History weight `eta` (0.2).
    pub eta: f32,
    /// OCV covariance weight `eta_cv` (0.2).
    pub eta_cv: f32,
    /// Target variance of the monitored distant part, `sigma0^2` (1e-4). It may change
    /// from frame to frame (a budget governor, `spvg::budget`); the stored variances keep
    /// the encoding of [`encoding_target`](Self::encoding_target).
    pub sigma0_sq: f32,
    /// The target that fixes the history texels' variance scale (the power of two
    /// nearest it, [`PassConfig::encoding`]); `None` takes `sigma0_sq`. Keep it fixed for
    /// the whole run of a pass when `sigma0_sq` moves: a scale derived from each frame's
    /// `sigma0^2` would reread the stored variances at another scale whenever the target
    /// crosses a power of two (docs/algorithms.md §8.2).
    pub encoding_target: Option<f32>,
    /// Control factor `kappa` in [0, 1] (0.2).
    pub kappa: f32,
    /// Sample budget lower bound `beta_min` (8).
    pub beta_min: u32,
    /// Sample budget upper bound `beta_max` (64).
    pub beta_max: u32,
    /// Zero-sample threshold on the distant ratio `eps_u` (0.01).
    pub eps_u: f32,
    /// OCV coefficient regulariser `eps_a` (1e-6).
    pub eps_a: f32,
    /// OCV clamp offset `a0` (1).
    pub a0: f32,
    /// Texel width at unit depth (world units per depth unit; 0.001 = 0.5 mm at 500 mm).
    pub w_px: f32,
    /// Texel height at unit depth.
    pub h_px: f32,
    /// Filtered sampling (AFIS, docs/algorithms.md §5): read the lighting from the mip level that
    /// `spvg::burley::filtered_mip_level` gives for each sample (off by default: the
    /// report's references are unfiltered).
    pub afis: bool,
    /// The firefly clamp's `k` (`SpvgConfig::firefly_clamp`, docs/algorithms.md §8.3):
    /// `Some(k)` clamps each frame's monitored value to `mean +- k sigma` of its history
    /// before the update; `None` (the default) leaves the published update.
    pub firefly_clamp: Option<f32>,
}

impl Default for PassConfig {
    fn default() -> Self {
        Self {
            eta: 0.2,
            eta_cv: 0.2,
            sigma0_sq: 1e-4,
            encoding_target: None,
            kappa: 0.2,
            beta_min: 8,
            beta_max: 64,
            eps_u: 0.01,
            eps_a: 1e-6,
            a0: 1.0,
            w_px: 1e-3,
            h_px: 1e-3,
            afis: false,
            firefly_clamp: None,
        }
    }
}

fn positive(name: &'static str, v: f32) -> Result<(), Error> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(name, f64::from(v), "must be finite and > 0"))
    }
}

impl PassConfig {
    /// Checks every field.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] for a field out of range, and
    /// [`Error::InconsistentParameters`] when `beta_min > beta_max`.
    pub fn validate(&self) -> Result<(), Error> {
        self.spvg().map(|_| ())?;
        self.ocv().map(|_| ())?;
        positive("w_px", self.w_px)?;
        positive("h_px", self.h_px)?;
        if let Some(t) = self.encoding_target {
            positive("encoding_target", t)?;
        }
        self.encoding().map(|_| ())
    }

    /// The core crate's controller configuration for these settings.
    ///
    /// # Errors
    ///
    /// As [`SpvgConfig::builder`]'s `build`.
    pub fn spvg(&self) -> Result<SpvgConfig<f32>, Error> {
        SpvgConfig::builder()
            .eta(self.eta)
            .target_variance(self.sigma0_sq)
            .kappa(self.kappa)
            .budget(self.beta_min, self.beta_max)
            .eps_u(self.eps_u)
            .firefly_clamp(self.firefly_clamp)
            .build()
    }

    /// The history texel encoding (`spvg::texel`): variance stored times `2^-k` with `2^k`
    /// the power of two nearest [`encoding_target`](Self::encoding_target) (by default
    /// `sigma0^2`), the OCV moments times `2^-c` with `2^c` nearest
    /// `4096 eps_a`. Scaling by powers of two is exact, so the shader applies the same
    /// factors bit for bit.
    ///
    /// # Errors
    ///
    /// As [`TexelEncoding::for_config`] / [`TexelEncoding::for_ocv`].
    pub fn encoding(&self) -> Result<TexelEncoding, Error> {
        let target = self.encoding_target.unwrap_or(self.sigma0_sq);
        TexelEncoding::new(target)
            .map_err(|_| {
                Error::invalid(
                    "encoding_target",
                    f64::from(target),
                    "must be finite and in [1e-30, 1e30]",
                )
            })?
            .for_ocv(&self.ocv()?)
    }

    /// The core crate's online control variate for these settings.
    ///
    /// # Errors
    ///
    /// As [`Ocv::new`].
    pub fn ocv(&self) -> Result<Ocv<f32>, Error> {
        Ocv::new(self.eta_cv, self.eps_a, self.a0)
    }

    /// The control model of `model` for the WGSL library: AS for the fixed-count
    /// baseline (it reads no history) and AS, CCV or the f16-input OCV (the J texel is
    /// f16; see `Ocv::with_f16_inputs`).
    ///
    /// # Errors
    ///
    /// As [`Ocv::new`].
    pub fn control(&self, model: Model) -> Result<Control, Error> {
        Ok(match model {
            Model::Fixed(_) | Model::As => Control::As,
            Model::Ccv => Control::Ccv,
            Model::Ocv => Control::Ocv(self.ocv()?.with_f16_inputs(true)),
        })
    }

    /// Builds the uniform block for one frame of `model` on a `width x height` image.
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::burley::presets::SKIN1;
    /// use spvg_wgpu::sss::{Model, PassConfig};
    /// let p = PassConfig::default().params(Model::Ocv, &SKIN1, 64, 48, 7).unwrap();
    /// assert_eq!((p.width, p.height, p.frame), (64, 48, 7));
    /// // k - 1 = 2 / eta - 2 for eta = 0.2.
    /// assert!((p.spvg.k_minus_1 - 8.0).abs() < 1e-5);
    /// // The variance is stored relative to the power of two nearest sigma0^2 = 1e-4.
    /// assert_eq!(p.spvg.var_scale, 2.0_f32.powi(-13));
    /// // A moving target with a fixed encoding: sigma0^2 = 1e-3 is read and stored at
    /// // the scale of 1e-4.
    /// let moved = PassConfig { sigma0_sq: 1e-3, encoding_target: Some(1e-4), ..PassConfig::default() };
    /// let q = moved.params(Model::Ccv, &SKIN1, 64, 48, 8).unwrap();
    /// assert_eq!(q.spvg.var_scale, 2.0_f32.powi(-13));
    /// // The target as the f16 texel stores it (a seed then asks exactly its count):
    /// // at most one f16 step below sigma0^2.
    /// let t = q.spvg.target_variance;
    /// assert!(t <= 1e-3 && t >= 1e-3 * (1.0 - 2.0_f32.powi(-10)));
    /// let bad = PassConfig { kappa: 2.0, ..PassConfig::default() };
    /// assert!(bad.params(Model::As, &SKIN1, 64, 48, 0).is_err());
    /// ```
    ///
    /// # Errors
    ///
    /// As [`PassConfig::validate`].
    pub fn params(
        &self,
        model: Model,
        material: &MaterialPreset,
        width: u32,
        height: u32,
        frame: u32,
    ) -> Result<PassParams, Error> {
        self.validate()?;
        let config = self.spvg()?;
        let fixed_count = match model {
            Model::Fixed(n) => n,
            Model::As | Model::Ccv | Model::Ocv => 0,
        };
        let storage = Storage {
            encoding: self.encoding()?,
            layout: Layout::F16,
            rounding: StoreRounding::Nearest,
        };
        // The target as the f16 history stores it, as the adaptive component runs it
        // (`TexelEncoding::storable_config`): the block and the component agree.
        let config = storage.encoding.storable_config(&config, Layout::F16)?;
        let [pr, pg, pb] = material.profiles::<f32>(ShapeFit::DiffuseMeanFreePath)?;
        let ps = sampling_profile(&[pr, pg, pb]);
        Ok(PassParams {
            spvg: Params::new(&config, self.control(model)?, &storage),
            width,
            height,
            frame,
            fixed_count,
            texel_diag: self.w_px.hypot(self.h_px),
            w_px: self.w_px,
            h_px: self.h_px,
            d_r: pr.shape(),
            d_g: pg.shape(),
            d_b: pb.shape(),
            d_s: ps.shape(),
            inv_d_r: pr.inv_shape(),
            inv_d_g: pg.inv_shape(),
            inv_d_b: pb.inv_shape(),
            inv_d_s: ps.inv_shape(),
            afis: u32::from(self.afis),
            max_mip: (32 - width.max(height).max(1).leading_zeros()).saturating_sub(1),
            lmax: material.max_mean_free_path_mm() as f32,
            reserved: [0; 2],
        })
    }
}

/// The sampling profile: the widest channel, so the samples cover every channel's profile.
#[must_use]
pub fn sampling_profile(p: &[BurleyProfile<f32>; 3]) -> BurleyProfile<f32> {
    let mut best = p[0];
    for q in &p[1..] {
        if q.shape() > best.shape() {
            best = *q;
        }
    }
    best
}

/// The uniform block of the subsurface pass: the WGSL library's parameter block
/// (`spvg_shaders::Params`: controller, control variate, texel storage) followed by the
/// pass's own fields.
///
/// WGSL twin: `struct PassParams` in `sss/shaders/params.wgsl`; same field order and
/// types. The library block sits first and is 128 bytes (a multiple of 16, as WGSL's
/// uniform layout wants for a struct member), the whole block 208 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PassParams {
    /// The WGSL library's parameters (`spvg_Params`), built by `spvg_shaders::Params::new`.
    pub spvg: Params,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Frame index (seeds the per-pixel sequences).
    pub frame: u32,
    /// Distant samples per pixel of the fixed-count baseline (0 for the adaptive models).
    pub fixed_count: u32,
    /// `hypot(w_px, h_px)`, computed once on the host.
    pub texel_diag: f32,
    /// Texel width at unit depth.
    pub w_px: f32,
    /// Texel height at unit depth.
    pub h_px: f32,
    /// Shape `d` of the red, green, blue and sampling profiles (mm).
    pub d_r: f32,
    #[allow(missing_docs, reason = "see d_r")]
    pub d_g: f32,
    #[allow(missing_docs, reason = "see d_r")]
    pub d_b: f32,
    #[allow(missing_docs, reason = "see d_r")]
    pub d_s: f32,
    /// `1 / d` of the same profiles, computed by the core crate.
    pub inv_d_r: f32,
    #[allow(missing_docs, reason = "see inv_d_r")]
    pub inv_d_g: f32,
    #[allow(missing_docs, reason = "see inv_d_r")]
    pub inv_d_b: f32,
    #[allow(missing_docs, reason = "see inv_d_r")]
    pub inv_d_s: f32,
    /// 1 where filtered sampling (AFIS) reads the lighting mips.
    pub afis: u32,
    /// The coarsest mip level of the lighting texture.
    pub max_mip: u32,
    /// The material's largest mean free path (mm), for AFIS.
    pub lmax: f32,
    /// Spare, 0 (pads the block to the 16-byte multiple WGSL gives the struct).
    pub reserved: [u32; 2],
}

const _: () = assert!(
    size_of::<PassParams>() == 208,
    "PassParams must match the 208-byte WGSL struct"
);

/// What the subsurface pass hands the adaptive component ([`crate::adaptive`]) for one
/// frame's block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ComponentSetup {
    /// The controller with its target at the block's variance scale
    /// ([`Controller::at_encoding_scale`]): built with it, the component stores the
    /// variance exactly as the block says, whatever the frame's target.
    pub(crate) config: SpvgConfig<f32>,
    /// The control model.
    pub(crate) control: Control,
    /// The frame's target variance `sigma0^2`.
    pub(crate) target: f32,
}

impl PassParams {
    /// The adaptive component's settings for this block and `model`, decoded by
    /// [`Controller::new`] as the twin decodes the block. Only the adaptive models run the
    /// component; the fixed count, which has none, reads as AS here (as in
    /// [`PassConfig::control`]).
    pub(crate) fn component_setup(&self, model: Model) -> Result<ComponentSetup, Error> {
        let decoded = Controller::new(&self.spvg)?;
        let control = match model {
            Model::Ocv => Control::Ocv(decoded.ocv.with_f16_inputs(false)),
            Model::Ccv => Control::Ccv,
            Model::As | Model::Fixed(_) => Control::As,
        };
        Ok(ComponentSetup {
            config: decoded.at_encoding_scale()?,
            control,
            target: self.spvg.target_variance,
        })
    }
}

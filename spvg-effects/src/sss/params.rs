//! Parameters of the subsurface pass: the validated host-side configuration and the uniform
//! block shared with WGSL.

use spvg::Error;
use spvg::SpvgConfig;
use spvg::burley::{BurleyProfile, MaterialPreset, ShapeFit};
use spvg::cv::Ocv;
use spvg::texel::{Layout, TexelEncoding};
use spvg_shaders::{Control, Params, Storage};
use spvg_wgpu::adaptive::{AdaptivePass, AdaptiveSettings};

use crate::error::PassError;

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

/// The subsurface pass's settings: its controller and OCV parameters (for the adaptive
/// component it runs, [`PassConfig::settings`]) and its own sampling settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PassConfig {
    /// The controller of the adaptive models (docs/algorithms.md §2): `eta`, the target
    /// variance of the monitored distant part `sigma0^2`, `kappa`, the budget, `eps_u` (the
    /// zero-sample threshold on the distant ratio, which the fixed count obeys too), the
    /// young-history rules and the firefly clamp. The target may move from frame to frame
    /// (a budget governor, `spvg::budget`): the component keeps the texel encoding of the
    /// first frame's target.
    pub spvg: SpvgConfig<f32>,
    /// The online control variate of the OCV model (`eta_cv`, `eps_a`, `a0`).
    pub ocv: Ocv<f32>,
    /// Texel width at unit depth (world units per depth unit; 0.001 = 0.5 mm at 500 mm).
    pub w_px: f32,
    /// Texel height at unit depth.
    pub h_px: f32,
    /// Filtered sampling (AFIS, docs/algorithms.md §5): read the lighting from the mip
    /// level that `spvg::burley::filtered_mip_level` gives for each sample (off by
    /// default: the report's references are unfiltered).
    pub afis: bool,
    /// The adaptive component's count-classified dispatch
    /// (`AdaptiveSettings::classified_dispatch`): `sss_sample` runs once per class of
    /// tiles, each tile's pixels taken by the class of their counts, with the same results (off by default).
    pub classified_dispatch: bool,
}

impl Default for PassConfig {
    /// The published controller (`SpvgConfig::published`), OCV with `eta_cv` 0.2, `eps_a`
    /// 1e-6 and `a0` 1, texels of 0.001 at unit depth, no AFIS, no classified dispatch.
    fn default() -> Self {
        Self {
            spvg: SpvgConfig::published(),
            ocv: Ocv::published(),
            w_px: 1e-3,
            h_px: 1e-3,
            afis: false,
            classified_dispatch: false,
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
    /// Checks the pass's own fields and that the adaptive component accepts the
    /// settings of every model ([`AdaptiveSettings::validate`]).
    ///
    /// # Errors
    ///
    /// [`PassError::Param`] naming a texel size that is not finite and positive,
    /// [`PassError::Adaptive`] for settings the component refuses.
    pub fn validate(&self) -> Result<(), PassError> {
        positive("w_px", self.w_px)?;
        positive("h_px", self.h_px)?;
        self.settings(Model::Ocv).validate()?;
        Ok(())
    }

    /// The adaptive component's settings for `model`: this controller, the model's
    /// control ([`PassConfig::control`]), the default reprojection (the subsurface scenes'
    /// camera is static), no count dilation, and this configuration's classified dispatch.
    #[must_use]
    pub fn settings(&self, model: Model) -> AdaptiveSettings {
        AdaptiveSettings {
            config: self.spvg,
            control: self.control(model),
            classified_dispatch: self.classified_dispatch,
            ..AdaptiveSettings::default()
        }
    }

    /// The control model of `model`: AS for the fixed-count baseline (it reads no
    /// history), and AS, CCV or OCV with this configuration's OCV parameters.
    #[must_use]
    pub fn control(&self, model: Model) -> Control {
        match model {
            Model::Fixed(_) | Model::As => Control::As,
            Model::Ccv => Control::Ccv,
            Model::Ocv => Control::Ocv(self.ocv),
        }
    }

    /// The uniform block of one frame of `model` on a `width x height` image of
    /// `material`, with `block` as its controller: the adaptive component's
    /// ([`AdaptivePass::params_block`](spvg_wgpu::adaptive::AdaptivePass::params_block)),
    /// or for the fixed count [`PassConfig::fixed_block`].
    ///
    /// # Errors
    ///
    /// [`PassError::Param`] for texel sizes or a material the core crate rejects.
    pub fn params(
        &self,
        model: Model,
        material: &MaterialPreset,
        [width, height]: [u32; 2],
        frame: u32,
        block: Params,
    ) -> Result<PassParams, PassError> {
        positive("w_px", self.w_px)?;
        positive("h_px", self.h_px)?;
        let fixed_count = match model {
            Model::Fixed(n) => n,
            Model::As | Model::Ccv | Model::Ocv => 0,
        };
        let [pr, pg, pb] = material.profiles::<f32>(ShapeFit::DiffuseMeanFreePath)?;
        let ps = sampling_profile(&[pr, pg, pb]);
        Ok(PassParams {
            spvg: block,
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

    /// The controller block of the fixed-count baseline, which has no component: the
    /// library's block of this controller with AS (the fixed count reads only `eps_u` of
    /// it, for the zero-sample rule), its target as the f16 texel stores it, as the
    /// component's are.
    ///
    /// # Errors
    ///
    /// [`PassError::Param`] for a target the texel encoding cannot hold.
    pub fn fixed_block(&self) -> Result<Params, PassError> {
        let encoding = TexelEncoding::new(self.spvg.target_variance())?;
        let storage = Storage {
            encoding,
            layout: Layout::F16,
            rounding: AdaptivePass::STORE_ROUNDING,
        };
        let config = encoding.storable_config(&self.spvg, Layout::F16)?;
        Ok(Params::new(&config, Control::As, &storage))
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
/// types. The library block sits first and is 144 bytes (a multiple of 16, as WGSL's
/// uniform layout wants for a struct member), the whole block 224 bytes.
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
    size_of::<PassParams>() == 224,
    "PassParams must match the 224-byte WGSL struct"
);

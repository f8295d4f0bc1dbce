//! # spvg-shaders: the spvg controller as a WGSL library
//!
//! The per-pixel rules of the [`spvg`] core crate (the sample-count estimate, the history
//! update, the control-variate coefficient and state update, the texel encodings, the
//! sequences and Burley sampling) as WGSL functions that any renderer's shader can call.
//! The crate leaves every API interaction to the caller: it hands out shader text
//! ([`WGSL`], or one module at a time) and the parameter blocks to upload: [`Params`]
//! (`spvg_Params`) and the reprojection rule [`ReprojectionRule`] (`spvg_Reprojection`,
//! built from a `spvg::reproject::Reprojection`).
//!
//! The library declares no global variables, no bindings and no entry points: every
//! function takes what it needs as arguments (the parameters as an [`Params`] /
//! `spvg_Params` value), and every public WGSL name starts with `spvg_`, so it joins any
//! host shader without clashes. Append your own bindings and entry points to [`WGSL`]:
//!
//! ```
//! let host = r#"
//! @group(0) @binding(0) var<uniform> params: spvg_Params;
//! @group(0) @binding(1) var history: texture_2d<f32>;
//! @group(0) @binding(2) var<storage, read_write> counts: array<u32>;
//!
//! @compute @workgroup_size(8, 8)
//! fn main(@builtin(global_invocation_id) id: vec3<u32>) {
//!     let h = spvg_decode_history(params, textureLoad(history, id.xy, 0));
//!     counts[id.y * 64u + id.x] = spvg_estimate_count(params, h, 1.0, true);
//! }
//! "#;
//! let source = format!("{}{host}", spvg_shaders::WGSL);
//! assert!(source.contains("fn spvg_estimate_count("));
//! ```
//!
//! Every function mirrors one core function operation by operation in `f32` (the table in
//! the crate README names each twin, with the permitted differences and their bounds);
//! `tests/equality.rs` runs each one on the hard cases of `spvg::arbitrary` on a wgpu
//! adapter and compares bit for bit, and `tests/naga.rs` validates the text with naga,
//! alone and joined to a host shader, without a GPU.
//!
//! HLSL and MSL translations made by naga are committed in `generated/` (see the README
//! for how to include them); [`HLSL`] and [`MSL`] hold them.
//!
//! Renderers that compose shaders with naga_oil (Bevy before 0.20) import the library as
//! the module `spvg` ([`COMPOSABLE_WGSL`]; `composable_module` with the `naga_oil`
//! feature). Bevy 0.20 composes with WESL, of which [`WGSL`] is a module as it is (see the
//! README; `spvg-bevy` registers it as `spvg_bevy::spvg`).
//!
//! # Features
//!
//! - `naga_oil` (off by default): `composable_module`, the library as a naga_oil 0.23
//!   composable module.
//!
//! # Modules
//!
//! [`WGSL`] is the concatenation of the modules below in dependency order; a shader that
//! needs only part of the library can join a module with its dependencies instead
//! ([`MODULES`] lists them). WGSL resolves names module-wide, so the order inside the
//! joined text does not matter.

#![forbid(unsafe_code)]

mod params;
mod reproject;

// The README's example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

pub use params::{Control, Params, Storage, StoreRounding, YOUNG_AGE_WEIGHT, YOUNG_SPATIAL_MASK};
pub use reproject::{
    REPROJECT_BORDER_MAXIMUM, REPROJECT_BORDER_PRIOR, REPROJECT_FOOTPRINT, ReprojectionRule,
};

/// `float.wgsl`: `spvg_is_finite`, `spvg_is_nan`, `spvg_saturate` (the overflow policy),
/// `spvg_min`/`spvg_max` with Rust's NaN rule, `spvg_F32_MAX`, `spvg_F16_MAX`, and
/// `spvg_inf`/`spvg_nan` (`spvg_f32_from_bits`: non-finite values made at run time, which
/// WGSL requires).
/// Depends on nothing.
pub const FLOAT: &str = include_str!("../wgsl/float.wgsl");
/// `params.wgsl`: `struct spvg_Params` (the twin of [`Params`]), `spvg_History`,
/// `spvg_CvHistory` and the `spvg_POLICY_*`, `spvg_MODEL_*`, `spvg_LAYOUT_*`,
/// `spvg_ROUNDING_*` constants. Depends on nothing.
pub const PARAMS: &str = include_str!("../wgsl/params.wgsl");
/// `sequence.wgsl`: `spvg_pcg3d16`, `spvg_pixel_seed`, `spvg_r2_offset_from_seed`,
/// `spvg_r2_point`, `spvg_to_unit_f32`, `spvg_channel_bits`. Depends on nothing.
pub const SEQUENCE: &str = include_str!("../wgsl/sequence.wgsl");
/// `texel.wgsl`: f16 rounding (nearest and stochastic), the per-channel store and load
/// rules, `spvg_decode_history`, `spvg_encode_history` (the core's encoding, spare
/// channel 0), `spvg_encode_written_history` (spare channel 1, the written mark that
/// reprojection checks), `spvg_history_written`, `spvg_decode_cv`, `spvg_encode_cv` for
/// RGBA16F and RGBA32F; the history's age in the spare channel, `spvg_read_age` and
/// `spvg_AGE_CAP`. Depends on [`FLOAT`], [`PARAMS`], [`SEQUENCE`].
pub const TEXEL: &str = include_str!("../wgsl/texel.wgsl");
/// `estimate.wgsl`: `spvg_samples_distant`, `spvg_raw_estimate`, `spvg_round_count`,
/// `spvg_estimate`, `spvg_estimate_count`, `spvg_estimate_texel` (from a history texel
/// with the written mark), `spvg_u32_to_f32`; fractional counts
/// (`spvg::controller::fractional`): `spvg_fractional_raw_count`, `spvg_resolved_factor`,
/// `spvg_resolve_weight` (the resolved-image rule), `spvg_clamp_real`,
/// `spvg_real_count`, `spvg_realise_count`, `spvg_estimate_resolved`,
/// `spvg_estimate_fractional`, `spvg_estimate_texel_resolved`,
/// `spvg_estimate_texel_fractional` (and `struct spvg_FrameCount`). Depends on
/// [`FLOAT`], [`PARAMS`], [`TEXEL`].
pub const ESTIMATE: &str = include_str!("../wgsl/estimate.wgsl");
/// `update.wgsl`: `spvg_firefly_clamp`, `spvg_update_history` (and
/// `struct spvg_HistoryUpdate`), `spvg_update_history_guided` (the TAA-guided variance,
/// `spvg::SpvgConfig::update_guided`) and `spvg_update_history_texel`,
/// `spvg_update_history_texel_guided` (texel in, texel with the written mark out); the
/// young-history rules (`spvg::controller::young`): `spvg_next_age`,
/// `spvg_age_weight`, `spvg_spatial_push`, `spvg_spatial_variance` (and `struct
/// spvg_SpatialMoments`), `spvg_update_young`, `spvg_update_young_guided` (and `struct
/// spvg_YoungUpdate`) and `spvg_update_young_texel`, `spvg_update_young_texel_guided`
/// (texel in, texel with the history's age out). Depends on
/// [`FLOAT`], [`PARAMS`], [`TEXEL`], [`ESTIMATE`].
pub const UPDATE: &str = include_str!("../wgsl/update.wgsl");
/// `cv.wgsl`: `spvg_raw_coefficient`, `spvg_clamp_to_bound`, `spvg_cv_coefficient`,
/// `spvg_update_inputs`, `spvg_update_cv` (and `struct spvg_CvUpdate`). Depends on
/// [`FLOAT`], [`PARAMS`], [`TEXEL`].
pub const CV: &str = include_str!("../wgsl/cv.wgsl");
/// `pixel.wgsl`: `spvg_split`, `spvg_update_pixel` (and `struct spvg_PixelStep`): the
/// whole per-pixel step after sampling. Depends on [`FLOAT`], [`PARAMS`], [`TEXEL`],
/// [`ESTIMATE`], [`UPDATE`], [`CV`].
pub const PIXEL: &str = include_str!("../wgsl/pixel.wgsl");
/// `burley.wgsl`: `spvg_burley_pdf`, `_cdf`, `_distant_ratio`, `_inverse_cdf`,
/// `_approx_inverse_cdf`, `_sample_distant`, `_ratio_weight`, `_ratio_add`,
/// `spvg_footprint_radius`, `spvg_filtered_mip_level`, `spvg_filtered_mip_index`.
/// Depends on [`FLOAT`].
pub const BURLEY: &str = include_str!("../wgsl/burley.wgsl");

/// `budget.wgsl`: one pixel's terms of the demand that a frame budget governor reduces
/// over a frame: `spvg_count_at`, its count at a candidate target (one point of the
/// clamped demand curve, [`spvg::budget::count_at`]), and `spvg_frame_demand` (and
/// `struct spvg_FrameDemand`), the unclamped sums
/// ([`spvg::budget::FrameDemand::pixel`]). Depends on [`FLOAT`], [`PARAMS`],
/// [`ESTIMATE`].
pub const BUDGET: &str = include_str!("../wgsl/budget.wgsl");

/// `reproject.wgsl`: where a pixel's history is under motion ([`spvg::reproject`]). The
/// whole decision of [`spvg::reproject::Reprojection::locate`] (nearest texel, mask and
/// depth tests, footprint search, border prior) plus the written check is
/// `spvg_reproject_locate_start` and `spvg_reproject_locate` (one step per texel the
/// caller reads; `struct spvg_Reprojection`, `spvg_PreviousTexel`, `spvg_Locate`, the
/// `spvg_SOURCE_*` and `spvg_REPROJECT_*` constants), with
/// `spvg_reproject_entering_count` (build the `spvg_Reprojection` value from a Rust rule
/// with [`ReprojectionRule::new`]); its parts are `spvg_reproject_texel`,
/// `spvg_reproject_border_texel`, `spvg_reproject_footprint_texel` and
/// `spvg_reproject_depth_agrees`. Depends on [`FLOAT`].
pub const REPROJECT: &str = include_str!("../wgsl/reproject.wgsl");

/// `dilation.wgsl`: count dilation ([`spvg::dilation`]): `spvg_dilation_window` and
/// `spvg_dilation_take` (the caller folds the window of counts it holds), the mark
/// `spvg_DILATION_KEEP` (and `struct spvg_Dilation`), and the depth-aware neighbour
/// prior `spvg_dilation_prior_window` / `spvg_dilation_prior_take` /
/// `spvg_dilation_prior_count` (`struct spvg_DilationPrior`, `spvg_DILATION_PRIOR_RADIUS`);
/// the tile of a one-pass dispatch, `spvg_TILE`, `spvg_tile_region` and
/// `spvg_spatial_window` (`struct spvg_Region`; [`spvg::dilation::tile_region`],
/// [`spvg::controller::young::spatial_window`]). Depends on nothing.
pub const DILATION: &str = include_str!("../wgsl/dilation.wgsl");

/// The library's modules concatenated in dependency order, after an optional prefix.
macro_rules! library_text {
    ($($prefix:expr)?) => {
        concat!(
            $($prefix,)?
            include_str!("../wgsl/float.wgsl"),
            include_str!("../wgsl/params.wgsl"),
            include_str!("../wgsl/sequence.wgsl"),
            include_str!("../wgsl/texel.wgsl"),
            include_str!("../wgsl/estimate.wgsl"),
            include_str!("../wgsl/update.wgsl"),
            include_str!("../wgsl/cv.wgsl"),
            include_str!("../wgsl/pixel.wgsl"),
            include_str!("../wgsl/burley.wgsl"),
            include_str!("../wgsl/budget.wgsl"),
            include_str!("../wgsl/reproject.wgsl"),
            include_str!("../wgsl/dilation.wgsl"),
        )
    };
}

/// The whole library as one self-contained WGSL text: every module in dependency order.
pub const WGSL: &str = library_text!();

/// The import path of the library as a composable module: `#import spvg::...`.
pub const IMPORT_PATH: &str = "spvg";

/// The library as a composable module for naga_oil's and Bevy's shader imports: [`WGSL`]
/// after the line `#define_import_path spvg`. A host shader then imports its names, for
/// example `#import spvg::{spvg_Params, spvg_estimate_texel}`, or the module and
/// qualifies them (`spvg::spvg_estimate_texel`). With the `naga_oil` feature,
/// `composable_module` wraps it for `naga_oil::compose::Composer`; in Bevy before 0.20,
/// add it as a `Shader` asset (`Shader::from_wgsl(COMPOSABLE_WGSL, "spvg.wgsl")`), which
/// registers the import path; Bevy 0.20 composes with WESL instead (see the README).
pub const COMPOSABLE_WGSL: &str = library_text!("#define_import_path spvg\n\n");

/// [`COMPOSABLE_WGSL`] as naga_oil 0.23 takes a composable module: WGSL, file path
/// `spvg.wgsl`, import path `spvg` (from its `#define_import_path` line), no shader defs.
/// Add it with `Composer::add_composable_module` before any shader that imports it.
#[cfg(feature = "naga_oil")]
#[must_use]
pub fn composable_module() -> naga_oil::compose::ComposableModuleDescriptor<'static> {
    naga_oil::compose::ComposableModuleDescriptor {
        source: COMPOSABLE_WGSL,
        file_path: "spvg.wgsl",
        language: naga_oil::compose::ShaderLanguage::Wgsl,
        ..Default::default()
    }
}

/// A WGSL module of the library: its file name, its text and the modules it needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Module {
    /// File name under `wgsl/`.
    pub name: &'static str,
    /// The WGSL text.
    pub source: &'static str,
    /// The file names of the modules it calls or whose types it uses (not transitive).
    pub depends_on: &'static [&'static str],
}

/// Every module of [`WGSL`] in its order, with its direct dependencies.
pub const MODULES: [Module; 12] = [
    Module {
        name: "float.wgsl",
        source: FLOAT,
        depends_on: &[],
    },
    Module {
        name: "params.wgsl",
        source: PARAMS,
        depends_on: &[],
    },
    Module {
        name: "sequence.wgsl",
        source: SEQUENCE,
        depends_on: &[],
    },
    Module {
        name: "texel.wgsl",
        source: TEXEL,
        depends_on: &["float.wgsl", "params.wgsl", "sequence.wgsl"],
    },
    Module {
        name: "estimate.wgsl",
        source: ESTIMATE,
        depends_on: &["float.wgsl", "params.wgsl", "sequence.wgsl", "texel.wgsl"],
    },
    Module {
        name: "update.wgsl",
        source: UPDATE,
        depends_on: &["float.wgsl", "params.wgsl", "texel.wgsl", "estimate.wgsl"],
    },
    Module {
        name: "cv.wgsl",
        source: CV,
        depends_on: &["float.wgsl", "params.wgsl", "texel.wgsl"],
    },
    Module {
        name: "pixel.wgsl",
        source: PIXEL,
        depends_on: &[
            "float.wgsl",
            "params.wgsl",
            "texel.wgsl",
            "estimate.wgsl",
            "update.wgsl",
            "cv.wgsl",
        ],
    },
    Module {
        name: "burley.wgsl",
        source: BURLEY,
        depends_on: &["float.wgsl"],
    },
    Module {
        name: "budget.wgsl",
        source: BUDGET,
        depends_on: &["float.wgsl", "params.wgsl", "estimate.wgsl"],
    },
    Module {
        name: "reproject.wgsl",
        source: REPROJECT,
        depends_on: &["float.wgsl"],
    },
    Module {
        name: "dilation.wgsl",
        source: DILATION,
        depends_on: &[],
    },
];

/// The library translated to HLSL (shader model 5.1) by naga 30 (`generated/spvg.hlsl`).
/// naga's HLSL and MSL backends write every function of a module, entry point or not, so
/// this is the library alone: no bindings, no entry points.
pub const HLSL: &str = include_str!("../generated/spvg.hlsl");
/// The library translated to MSL (language version 2.0) by naga 30
/// (`generated/spvg.metal`).
pub const MSL: &str = include_str!("../generated/spvg.metal");

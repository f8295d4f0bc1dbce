//! # The adaptive-sampling component: SPVG count control for any wgpu pass
//!
//! [`AdaptivePass`] owns the per-pixel history of the SPVG controller (docs/algorithms.md
//! §2, §3), its reprojection, its settings and its bind groups. It runs in one of two
//! forms, frame by frame (both run the same rules, so they can alternate on one
//! component):
//!
//! **One pass** (the seeds' form): the renderer's own compute shader joins
//! [`AdaptivePass::one_pass_wgsl`] and calls two functions around its samples, in one
//! dispatch; the component hands it the bind group of the frame
//! ([`AdaptivePass::one_pass_group`]):
//!
//! ```text
//! let s = spvg_one_pass_begin(gid, lid);   // s.count: this pixel's samples
//! <the renderer takes s.count samples at s.pixel>
//! spvg_one_pass_end(s, value, control);    // the new history
//! ```
//!
//! Per pixel the controller then costs one history read, one history write and the
//! reprojection's reads; no count, link or other intermediate goes through memory (the
//! counts only where asked, [`AdaptivePass::set_one_pass_counts`]), and the neighbourhood
//! rules read their neighbours from workgroup memory ("The one-pass tile" below).
//!
//! **Two passes** (the form for a renderer that cannot host the component's WGSL, and for
//! the count-classified dispatch, which needs the counts before the sampling dispatch):
//! the component records two compute steps into the caller's [`wgpu::CommandEncoder`],
//! around the renderer's own Monte Carlo pass:
//!
//! ```text
//! record_estimate(motion, depth, previous depth, [reprojected depth], [masks], [gamma])
//!                                                                     -> count texture
//! <the renderer's sampling pass: reads count_texture(), takes that many samples,
//!  writes its per-pixel monitored value (and control value for CCV/OCV)>
//! record_update(value, [control], [guide])                          -> new history
//! ```
//!
//! Both steps are recorded into one encoder (or several submitted in that order); wgpu
//! inserts the barriers between the compute passes. [`AdaptiveTwin`] is the same component
//! on host slices, bit-identical to both forms on lavapipe (`tests/adaptive.rs`,
//! `tests/one_pass.rs`).
//!
//! ## The one-pass tile
//!
//! A one-pass workgroup is an 8 x 8 tile (`spvg::dilation::TILE`). Its invocations first
//! estimate their pixels and, shared out among them, the pixels of a halo of the
//! dilation radius `r` around the tile (an estimate is one history read: recomputing it
//! is cheaper than a pass that stores it), then read the neighbourhoods from workgroup
//! memory after a barrier. Two rules stop at what the workgroup holds, in both forms and
//! in the twin (docs/algorithms.md §2.5, §8.4): the neighbour prior's window at the tile
//! grown by `r` (`spvg::dilation::tile_region`), and the spatial moments of young
//! histories at the tile (`spvg::controller::young::spatial_window`), since this frame's
//! values exist only inside it.
//!
//! ## Reprojection and disocclusion
//!
//! The estimate reads the history at the reprojected texel of `spvg::reproject` (the rule
//! is written once in the core crate; the library's `spvg_reproject_*` (spvg-shaders'
//! `reproject.wgsl`) mirrors it
//! operation by operation). **Motion vectors are in pixels, this frame's position minus
//! the previous frame's** (`x_prev = x + 0.5 - v`, nearest texel `floor(x_prev)`, `+y`
//! down). The history is point-sampled, never filtered: a filtered variance is not the
//! variance of anything (see `spvg::reproject` for the full argument). The history is
//! valid when the reprojected texel is inside the frame, the previous mask is set there,
//! `|d_prev - d| <= tol d` (default `tol` = 2%, [`AdaptiveSettings::reprojection`]; `d`
//! is the reprojected depth where [`EstimateInputs::reprojected_depth`] is given, else
//! this frame's depth), the
//! previous frame wrote that texel, and the frame was not resized (where the texel fails
//! the mask or depth test, the first of the other texels of its 2x2 footprint that passes
//! is continued instead: the footprint search of `spvg::reproject`, on by default); invalid
//! pixels take the disocclusion path (first-observation seeding, docs/algorithms.md §2.3). A pixel that
//! enters the frame takes `beta_max` samples when the previous frame's texel `ceil(|v|)`
//! in from the edge passes the same tests (the border prior of `spvg::reproject`, on by
//! default; `BorderCount::Texel` takes that texel's count instead), and is then seeded like
//! any disoccluded pixel. A position more than the frame size outside the previous frame
//! (absurd motion: `1e30`, `3e9`, `f32::MAX`) is a disocclusion like NaN motion, never a
//! border prior (the motion bound of `spvg::reproject`). The estimate
//! stores the decision as a link (the previous texel's index + 1, or 0), so the update
//! reads exactly the history the estimate used.
//!
//! ## Count dilation
//!
//! [`AdaptiveSettings::dilation`] `= r` (0, off, by default) lets each pixel with history
//! spend the largest count within `r` pixels (`spvg::dilation`, docs/algorithms.md §2.5):
//! a pixel's own moving variance misses rare events (a small occluder that `beta_min`
//! samples rarely hit) and sub-pixel reprojection drift, which its neighbours see. The
//! two-pass estimate step then records a second compute pass (`adaptive_dilate`, reading
//! the estimate's counts from a component-owned `R32Uint` texture, and with the neighbour
//! prior the kept depth at binding 20); the one-pass form reads the counts of the tile
//! and its halo from workgroup memory. Pixels without history keep their
//! first-observation count, or with [`AdaptiveSettings::neighbour_prior`] (on by default)
//! the mean count of their same-surface neighbours that have history within the tile
//! grown by `r`. The histories are not mixed: each pixel updates its own with the count it
//! spent.
//!
//! ## A moving target
//!
//! The history stores the variance relative to the power of two nearest the
//! configuration's target at construction ([`AdaptivePass::encoding`]).
//! [`AdaptivePass::set_target_variance`] changes `sigma0^2` for the steps recorded after it
//! (a frame budget governor, `spvg::budget::Governor`, sets it every frame) and keeps that
//! encoding, so the stored variances keep their meaning when the target crosses a power of
//! two (docs/algorithms.md §8.2). Between a frame's estimate and its update it is refused
//! ([`AdaptiveError::SettingsBetweenSteps`]): both steps of a frame run one setting.
//!
//! ## The TAA guide
//!
//! A renderer that resolves the pass through TAA can give the update its resolved history
//! `C_t` ([`UpdateInputs::guide`], the twin's [`UpdateData::guide`]): the dissertation's
//! Eq. 4.4 monitors the variance of this frame's value against that context instead of
//! the pixel's own moving mean (`spvg::SpvgConfig::update_guided`, docs/algorithms.md
//! §8.5; docs/integrating.md says where `C_t` comes from and the order of the passes).
//! The mean and the mean count are unchanged, and a non-finite guide texel gives the
//! unguided update at that pixel.
//!
//! ## Fractional counts
//!
//! With `SpvgConfig::fractional_floor` set in [`AdaptiveSettings::config`] (a real floor in
//! `[0, 8]`; docs/algorithms.md §8.6), a pixel that continues a history takes a real count
//! `c >= floor`, realised per pixel and frame by dithered rounding
//! (`spvg::controller::fractional`, the threshold `spvg::sequence::dither_threshold` of
//! the pixel and of the component's frame index, the number of updates it has recorded):
//! `c = 0.25` is one sample one frame in four, spread over neighbours. The count texture
//! then holds 0 at pixels that skip this frame; the renderer takes no sample there (its
//! TAA keeps the pixel's history), and the update carries their histories with a new mean
//! count. Pixels without a continued history (disoccluded, entering) keep the integer
//! rule and `min_samples`. The count dilation acts on the realised counts: a pixel whose
//! dither gave 0 keeps 0, one that samples takes its window's maximum. The estimate
//! writes each pixel's real count to a component-owned `R32Float` texture that the update
//! reads (1x1 while fractional counts are off); [`AdaptiveTwin::real_counts`] is its
//! twin.
//!
//! ## Settings
//!
//! One [`AdaptiveSettings`] value configures the component: [`AdaptivePass`] and
//! [`AdaptiveTwin`] take it at construction and from `set_settings` between frames, and a
//! renderer that wraps the component hands it through. It is validated once, when it is
//! handed over; the controller's uniform block is derived from it then, not per frame.
//!
//! ## Effects built on it
//!
//! The `spvg-effects` crate builds two renderers on this public API: ambient occlusion
//! with moving cameras and objects, and subsurface scattering (static camera, the
//! subsurface mask, the distant-energy ratio as `gamma`, CCV and OCV with the near-field
//! lighting as control, a moving target under the budget governor).
//!
//! ## Textures
//!
//! | input | step | format | meaning |
//! | --- | --- | --- | --- |
//! | `motion` | estimate | `Rg32Float`, `Rg16Float` | the convention of `spvg::reproject` (pixels) |
//! | `depth`, `previous_depth` | estimate | `R32Float`, `R16Float` | linear depth, positive |
//! | `reprojected_depth` (optional) | estimate | `R32Float`, `R16Float` | this pixel's surface point's depth as the previous camera saw it; the depth test compares it instead of `depth` |
//! | `masks` (optional) | estimate | `R8Uint`, `R16Uint`, `R32Uint` | non-zero where the pass runs |
//! | `gamma` (optional) | estimate | `R32Float`, `R16Float` | distant-energy ratio (§2.4); 1 if absent |
//! | `resolve_weight` (optional) | estimate | `R32Float`, `R16Float` | the renderer's resolve weight on this frame, for the resolved-image rule (docs/algorithms.md §8.7); NaN, 0 or less: none there, the history's age stands in |
//! | `value` | update | `R32Float`, `R16Float` | monitored luminance `fbar` |
//! | `control` (CCV, OCV) | update | `R32Float`, `R16Float` | control value `G` |
//! | `guide` (optional) | update | `R32Float`, `R16Float` | the renderer's resolved TAA history `C_t` in the monitored value's space; the variance then follows `value - guide` (docs/algorithms.md §8.5) |
//!
//! Every input is the frame size with `TEXTURE_BINDING` usage, 2D, single-sampled (mip 0
//! is read). A wrong size, format, usage or kind is an [`AdaptiveError`] naming the input,
//! checked before any bind group exists. Owned by the component: the count texture
//! (`R32Uint`, `TEXTURE_BINDING | COPY_SRC`; 0 outside the mask, under the zero-sample
//! rule and at pixels that skip the frame under fractional counts, else in
//! `[beta_min, beta_max]`; under fractional counts `floor(c)` or `floor(c) + 1` of a real
//! count `c` in `[floor, beta_max]`), the link ([`AdaptivePass::link_texture`],
//! `R32Uint`), the history ping-pong (`Rgba16Float`, `spvg::texel::SpvgTexel16`, spare
//! channel the history's age, every `f16` rounded to nearest: [`AdaptivePass::STORE_ROUNDING`]), for OCV
//! only the CV history ping-pong (`spvg::texel::CvTexel16`), and with a count dilation
//! radius the estimate's counts before dilation (`R32Uint`).
//!
//! ## Bind group layouts (compute stage; float textures unfilterable)
//!
//! The two-pass steps bind group 0; the one-pass module the group the renderer chose.
//!
//! | binding | estimate | update (AS, CCV) | update (OCV) | one pass |
//! | --- | --- | --- | --- | --- |
//! | 0 | uniform `spvg_Params` (spvg-shaders) | same | same | same |
//! | 1 | uniform `AdaptiveParams` (the component's own: frame size, flags, depth tolerance, dilation radius) | same | same | same |
//! | 2 | history read (`texture_2d<f32>`) | same | same | same |
//! | 3 | motion | | | motion |
//! | 4, 5 | depth, previous depth | | | same |
//! | 6, 7 | mask, previous mask (`texture_2d<u32>`) | | | same |
//! | 8 | gamma | | | gamma |
//! | 9 | count (storage `r32uint`, write) | | | count (written where asked) |
//! | 10 | link (storage `r32uint`, write) | | | |
//! | 11, 12 | | value, control | value, control | |
//! | 13, 14 | | count, link (`texture_2d<u32>`) | same | |
//! | 15 | | history write (storage `rgba16float`) | same | same |
//! | 16, 17 | | | CV history read, CV history write | same (OCV) |
//! | 18 | reprojected depth | | | same |
//! | 19 | this frame's depth kept (storage `r32float`, write; written only with the spatial variance of young histories or the neighbour prior) | | | |
//! | 20 | | the kept depth (spatial variance) | same | |
//! | 21 | | guide | guide | |
//! | 22 | uniform frame index (fractional counts' dither threshold) | | | same |
//! | 23 | real count (storage `r32float`, write; written only with fractional counts) | | | |
//! | 24 | | real count | real count | |
//! | 25 | resolve weight | | | same |
//!
//! Absent optional inputs are bound to a 1x1 placeholder and switched off by a flag (the
//! resolve weight by its placeholder's zero texel, which reads "none").
//!
//! # Examples
//!
//! The twin on a 4x1 frame panning one pixel per frame: the pixel that enters at the left
//! edge has no history; the previous frame's texel 1 (the border prior: texel 0 had itself
//! just entered) is on the same surface, so it takes `beta_max` samples, and is then
//! seeded. With `BorderCount::Texel` it would take texel 1's count, which pixel 2
//! continues.
//!
//! ```
//! use spvg::SpvgConfig;
//! use spvg::reproject::{BorderCount, Reprojection};
//! use spvg_wgpu::adaptive::{AdaptiveSettings, AdaptiveTwin, EstimateData, UpdateData};
//!
//! let config = SpvgConfig::<f32>::builder().target_variance(1e-4).build().unwrap();
//! let settings = AdaptiveSettings { config, ..AdaptiveSettings::default() };
//! let mut twin = AdaptiveTwin::new(settings, 4, 1).unwrap();
//! let texel_rule = Reprojection::default().with_border_count(BorderCount::Texel);
//! let mut texel =
//!     AdaptiveTwin::new(AdaptiveSettings { reprojection: texel_rule, ..settings }, 4, 1).unwrap();
//! let (depth, motion) = ([1.0_f32; 4], [[1.0_f32, 0.0]; 4]);
//! for t in 0..6 {
//!     let d = EstimateData::new(&motion, &depth, &depth);
//!     let n = twin.estimate(&d).unwrap().to_vec();
//!     let m = texel.estimate(&d).unwrap().to_vec();
//!     if t > 0 {
//!         assert_eq!(n[0], 64, "entered the frame: beta_max");
//!         assert_eq!(m[0], m[2], "entered the frame: texel 1's count");
//!         assert_eq!(twin.valid(), [false, true, true, true]);
//!     }
//!     // Noisy pixels: the controller asks for more than the minimum once it has history.
//!     let value = [0.3, 0.5, 0.3, 0.5].map(|v| v + 0.1 * (t % 2) as f32);
//!     twin.update(&UpdateData::new(&value)).unwrap();
//!     texel.update(&UpdateData::new(&value)).unwrap();
//! }
//! ```
//!
//! On a device:
//!
//! ```no_run
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue,
//! #          t: &[wgpu::Texture; 4], value: &wgpu::Texture) -> Result<(), Box<dyn std::error::Error>> {
//! use spvg_wgpu::adaptive::{AdaptivePass, AdaptiveSettings, EstimateInputs, UpdateInputs};
//! let mut pass = AdaptivePass::new(device, AdaptiveSettings::default(), 1920, 1080)?;
//! let mut encoder = device.create_command_encoder(&Default::default());
//! // The required textures, then each optional input that this renderer has.
//! let inputs = EstimateInputs::new(&t[0], &t[1], &t[2]).with_reprojected_depth(Some(&t[3]));
//! pass.record_estimate(&mut encoder, &inputs)?;
//! // ... your sampling pass reads pass.count_texture() and writes `value` ...
//! pass.record_update(&mut encoder, &UpdateInputs::new(value))?;
//! queue.submit([encoder.finish()]);
//! # Ok(()) }
//! ```

mod classify;
mod controller;
mod error;
mod inputs;
mod layout;
mod one_pass;
mod params;
mod pass;
mod record;
mod settings;
mod tiles;
mod twin;

pub use error::AdaptiveError;
pub use inputs::{EstimateInputs, Masks, UpdateInputs};
pub use pass::AdaptivePass;
pub use settings::AdaptiveSettings;
/// The control model of the monitored value (docs/algorithms.md §3): the library's own
/// type, one for the library's block and the component. The component runs OCV with
/// [`Ocv::with_f16_inputs`](spvg::cv::Ocv::with_f16_inputs)`(true)` whatever it was built
/// with, because the CV history is stored in f16 (see that method for why).
pub use spvg_shaders::Control;
pub use tiles::AdaptiveTiles;
pub use twin::{AdaptiveTwin, EstimateData, UpdateData};

/// What both forms run (`component.wgsl` beside this module): the bindings at group
/// `SPVG_AD_GROUP`, the controller's wrappers, the per-pixel estimate and update.
const COMPONENT_WGSL: &str = include_str!("component.wgsl");

/// The control-variate history of OCV (`component_cv.wgsl`), and the same interface
/// without bindings for AS and CCV (`component_no_cv.wgsl`).
const COMPONENT_CV_WGSL: &str = include_str!("component_cv.wgsl");
const COMPONENT_NO_CV_WGSL: &str = include_str!("component_no_cv.wgsl");

/// The two-pass form's entry points, `adaptive.wgsl` beside this module.
const ADAPTIVE_WGSL: &str = include_str!("adaptive.wgsl");

/// The one-pass form's functions, `one_pass.wgsl` beside this module.
const ONE_PASS_WGSL: &str = include_str!("one_pass.wgsl");

/// The count classification's passes, `classify.wgsl` beside this module.
const CLASSIFY_WGSL: &str = include_str!("classify.wgsl");

/// The consumer's decoder of a classified dispatch, `classified.wgsl` beside this module
/// ([`AdaptivePass::CLASSIFIED_WGSL`]).
const CLASSIFIED_WGSL: &str = include_str!("classified.wgsl");

/// `component.wgsl` with its bindings at `group`, for a model with the control-variate
/// history (`ocv`, OCV) or without (AS, CCV).
fn component_source(group: u32, ocv: bool) -> String {
    let cv = if ocv {
        COMPONENT_CV_WGSL
    } else {
        COMPONENT_NO_CV_WGSL
    };
    format!("{COMPONENT_WGSL}{cv}").replace("SPVG_AD_GROUP", &group.to_string())
}

/// The whole module the component compiles for its own dispatches (the two-pass form):
/// the library ([`spvg_shaders::WGSL`]: the reprojection rule `spvg_reproject_*`, and the
/// controller, called only through the `spvg_ad_ctl_*` wrappers of `component.wgsl`), the
/// shared part at group 0, the two-pass entry points and the count classification's (with
/// its class bounds from `classify.rs`).
fn shader_source(ocv: bool) -> String {
    let mut s = String::from(spvg_shaders::WGSL);
    s.push_str(&component_source(0, ocv));
    s.push_str(ADAPTIVE_WGSL);
    s.push_str(&classify::wgsl_constants());
    s.push_str(CLASSIFY_WGSL);
    s
}

/// The one-pass module a renderer's shader joins after [`spvg_shaders::WGSL`]: the shared
/// part with its bindings at `group`, and `one_pass.wgsl`.
fn one_pass_source(group: u32, ocv: bool) -> String {
    let mut s = component_source(group, ocv);
    s.push_str(ONE_PASS_WGSL);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn validate(src: &str) -> naga::Module {
        let module = naga::front::wgsl::parse_str(src).expect("the component's WGSL parses");
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .expect("the component's WGSL validates");
        module
    }

    /// The component's WGSL and its tile-list entry points validate (no GPU needed), for
    /// each control model, and hold every entry point the component compiles.
    #[test]
    fn wgsl_validates_without_a_gpu() {
        for ocv in [false, true] {
            let whole = validate(&shader_source(ocv));
            let tiles = validate(&format!("{}{}", shader_source(ocv), AdaptiveTiles::WGSL));
            for (module, entries) in [
                (
                    &whole,
                    &[
                        "adaptive_estimate",
                        "adaptive_dilate",
                        "adaptive_update",
                        "adaptive_classify",
                        "adaptive_class_scatter",
                    ][..],
                ),
                (
                    &tiles,
                    &["adaptive_estimate_tiles", "adaptive_update_tiles"][..],
                ),
            ] {
                for entry in entries {
                    assert!(
                        module.entry_points.iter().any(|e| e.name == *entry),
                        "entry point {entry} missing"
                    );
                }
            }
        }
    }

    /// The one-pass module validates inside a renderer's shader that uses group 0 for its
    /// own bindings and names of its own that the component's prefix keeps apart (`depth`,
    /// `count_in`, `params`), for each control model.
    #[test]
    fn one_pass_module_validates_in_a_consumer() {
        for ocv in [false, true] {
            let consumer = format!(
                "{}{}\n\
                 @group(0) @binding(0) var<uniform> params: vec4<u32>;\n\
                 @group(0) @binding(1) var depth: texture_2d<f32>;\n\
                 @group(0) @binding(2) var count_in: texture_2d<u32>;\n\
                 @group(0) @binding(3) var out: texture_storage_2d<r32float, write>;\n\
                 @compute @workgroup_size(8, 8, 1)\n\
                 fn sample(@builtin(global_invocation_id) gid: vec3<u32>, \
                 @builtin(local_invocation_id) lid: vec3<u32>) {{\n\
                 let s = spvg_one_pass_begin(gid, lid);\n\
                 var v = 0.0;\n\
                 for (var m = 0u; m < s.count; m++) {{ v += textureLoad(depth, s.pixel, 0).x; }}\n\
                 if (s.count != 0u) {{ textureStore(out, s.pixel, vec4<f32>(v, 0.0, 0.0, 0.0)); }}\n\
                 spvg_one_pass_end(s, v, 0.0);\n\
                 }}\n",
                spvg_shaders::WGSL,
                one_pass_source(1, ocv)
            );
            let module = validate(&consumer);
            assert!(
                module.entry_points.iter().any(|e| e.name == "sample"),
                "entry point"
            );
        }
    }

    /// The consumer's decoder of a classified dispatch validates inside a consumer's
    /// module, next to a whole-frame entry's bindings at group 0.
    #[test]
    fn classified_decoder_validates_in_a_consumer() {
        let consumer = format!(
            "{CLASSIFIED_WGSL}\n\
             @group(0) @binding(0) var out: texture_storage_2d<r32uint, write>;\n\
             @compute @workgroup_size(8, 8, 1)\n\
             fn sample(@builtin(workgroup_id) wg: vec3<u32>, \
             @builtin(num_workgroups) groups: vec3<u32>, \
             @builtin(local_invocation_index) li: u32) {{\n\
             let p = adaptive_class_pixel(wg, groups, li);\n\
             if (p.z == 0u) {{ textureStore(out, vec2<i32>(p.xy), vec4<u32>(li)); }}\n\
             }}\n"
        );
        let module = validate(&consumer);
        assert!(
            module.entry_points.iter().any(|e| e.name == "sample"),
            "entry point"
        );
    }
}

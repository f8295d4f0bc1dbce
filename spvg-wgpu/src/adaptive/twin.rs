//! The CPU twin of the component: the same two steps on host slices, calling the core
//! crate (`spvg::reproject` for the reprojection, the controller and OCV the GPU's block
//! was built from, through `controller.rs`). It is the oracle of the GPU-vs-twin tests
//! and a CPU backend.

use half::f16;
use spvg::controller::young::{SpatialMoments, next_age, read_age, spatial_window};
use spvg::reproject::PreviousSample;

use super::classify::{Classes, classify};
use super::controller::{
    estimate_count, estimate_fractional, from_texel, ocv_alpha, to_texel, update_cv, update_history,
};
use super::inputs::{Masks, check_size};
use super::params::retargeted;
use super::settings::{Derived, derive};
use super::{AdaptiveError, AdaptiveSettings, Control};

/// Inputs of [`AdaptiveTwin::estimate`]: one value per pixel, row-major, the twins of the
/// textures of [`EstimateInputs`](super::EstimateInputs). Built like them: [`new`](Self::new)
/// with the required slices, `with_*` for each optional one (`#[non_exhaustive]`, so a
/// later optional input breaks no caller).
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct EstimateData<'a> {
    /// Motion vectors in the convention of `spvg::reproject`.
    pub motion: &'a [[f32; 2]],
    /// This frame's linear depth.
    pub depth: &'a [f32],
    /// The previous frame's linear depth.
    pub previous_depth: &'a [f32],
    /// This pixel's surface point's depth as the previous camera saw it, or `None`: where
    /// given, the depth test compares it instead of `depth`.
    pub reprojected_depth: Option<&'a [f32]>,
    /// The pass masks (non-zero = set), or `None` when every pixel is covered.
    pub masks: Option<Masks<&'a [u8]>>,
    /// The distant-energy ratio, or `None` for `gamma = 1`.
    pub gamma: Option<&'a [f32]>,
    /// The resolve's weight on this frame per pixel, or `None` (the twin of
    /// [`EstimateInputs::resolve_weight`](super::EstimateInputs::resolve_weight)).
    pub resolve_weight: Option<&'a [f32]>,
}

/// Inputs of [`AdaptiveTwin::update`]: the twins of [`UpdateInputs`](super::UpdateInputs),
/// built like them ([`new`](Self::new), then `with_*`; `#[non_exhaustive]`).
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct UpdateData<'a> {
    /// The monitored value `fbar` per pixel.
    pub value: &'a [f32],
    /// The control value `G` per pixel (CCV and OCV).
    pub control: Option<&'a [f32]>,
    /// The TAA guide `C_t` per pixel, or `None` (the twin of
    /// [`UpdateInputs::guide`](super::UpdateInputs::guide)).
    pub guide: Option<&'a [f32]>,
}

impl<'a> EstimateData<'a> {
    /// The required slices: the motion vectors, this frame's and the previous frame's
    /// linear depth; every optional input is `None`.
    #[must_use]
    pub fn new(motion: &'a [[f32; 2]], depth: &'a [f32], previous_depth: &'a [f32]) -> Self {
        Self {
            motion,
            depth,
            previous_depth,
            reprojected_depth: None,
            masks: None,
            gamma: None,
            resolve_weight: None,
        }
    }

    /// Sets [`reprojected_depth`](Self::reprojected_depth) (default `None`).
    #[must_use]
    pub fn with_reprojected_depth(mut self, reprojected_depth: Option<&'a [f32]>) -> Self {
        self.reprojected_depth = reprojected_depth;
        self
    }

    /// Sets [`masks`](Self::masks) (default `None`: every pixel is covered).
    #[must_use]
    pub fn with_masks(mut self, masks: Option<Masks<&'a [u8]>>) -> Self {
        self.masks = masks;
        self
    }

    /// Sets [`gamma`](Self::gamma) (default `None`: `gamma = 1`).
    #[must_use]
    pub fn with_gamma(mut self, gamma: Option<&'a [f32]>) -> Self {
        self.gamma = gamma;
        self
    }

    /// Sets [`resolve_weight`](Self::resolve_weight) (default `None`).
    #[must_use]
    pub fn with_resolve_weight(mut self, resolve_weight: Option<&'a [f32]>) -> Self {
        self.resolve_weight = resolve_weight;
        self
    }
}

impl<'a> UpdateData<'a> {
    /// The required slice: the monitored [`value`](Self::value); every optional input is
    /// `None`.
    #[must_use]
    pub fn new(value: &'a [f32]) -> Self {
        Self {
            value,
            control: None,
            guide: None,
        }
    }

    /// Sets [`control`](Self::control) (default `None`; CCV and OCV need it).
    #[must_use]
    pub fn with_control(mut self, control: Option<&'a [f32]>) -> Self {
        self.control = control;
        self
    }

    /// Sets [`guide`](Self::guide) (default `None`: the unguided update).
    #[must_use]
    pub fn with_guide(mut self, guide: Option<&'a [f32]>) -> Self {
        self.guide = guide;
        self
    }
}

/// The CPU twin of [`AdaptivePass`](super::AdaptivePass): same configuration, same
/// histories (f16 texels), same counts, bit for bit on a conforming device.
#[derive(Clone, Debug)]
pub struct AdaptiveTwin {
    settings: AdaptiveSettings,
    /// The block and controller derived from `settings`.
    derived: Derived,
    /// The target that fixed the variance encoding (the settings' at construction).
    encoding_target: f32,
    width: u32,
    height: u32,
    history: [Vec<[f16; 4]>; 2],
    cv: Option<[Vec<[f16; 4]>; 2]>,
    count: Vec<u32>,
    /// The per-pixel counts before dilation (scratch of `estimate`).
    raw_count: Vec<u32>,
    link: Vec<u32>,
    /// The real count of each pixel's fractional decision, -1 where the integer rule
    /// decided (`spvg::controller::fractional`; only with fractional counts on).
    real: Vec<f32>,
    /// The frames updated so far: the frame index of the dither threshold.
    frame: u32,
    /// This frame's depth, kept by the estimate for the update's same-surface test of
    /// the spatial variance (only while that rule is on; the device keeps it in a texture).
    surface: Vec<f32>,
    /// The classes of the last estimate's counts (only with the classified dispatch).
    classes: Classes,
    read: usize,
    estimated: bool,
    /// A resize discarded this frame's estimate (the update then names the resize).
    resized_between_steps: bool,
}

fn check_len<T>(input: &'static str, s: &[T], n: usize) -> Result<(), AdaptiveError> {
    if s.len() == n {
        Ok(())
    } else {
        Err(AdaptiveError::SliceLength {
            input,
            expected: n,
            got: s.len(),
        })
    }
}

const ZERO: [f16; 4] = [f16::ZERO; 4];

/// The (read, write) halves of a ping-pong pair.
fn split<T>(pair: &mut [Vec<T>; 2], read: usize) -> (&[T], &mut [T]) {
    let [a, b] = pair;
    if read == 0 { (a, b) } else { (b, a) }
}

impl AdaptiveTwin {
    /// The twin of [`AdaptivePass::new`](super::AdaptivePass::new) (frame sides up to
    /// `u16::MAX`).
    ///
    /// # Errors
    ///
    /// As `AdaptivePass::new`.
    pub fn new(settings: AdaptiveSettings, width: u32, height: u32) -> Result<Self, AdaptiveError> {
        let encoding_target = settings.config.target_variance();
        let derived = derive(&settings, encoding_target)?;
        check_size(width, height, u32::from(u16::MAX))?;
        let n = (width * height) as usize;
        Ok(Self {
            settings,
            derived,
            encoding_target,
            width,
            height,
            history: [vec![ZERO; n], vec![ZERO; n]],
            cv: matches!(settings.control, Control::Ocv(_)).then(|| [vec![ZERO; n], vec![ZERO; n]]),
            count: vec![0; n],
            raw_count: Vec::new(),
            link: vec![0; n],
            real: Vec::new(),
            frame: 0,
            surface: Vec::new(),
            classes: Classes::default(),
            read: 0,
            estimated: false,
            resized_between_steps: false,
        })
    }

    /// The settings the twin runs.
    #[must_use]
    pub fn settings(&self) -> &AdaptiveSettings {
        &self.settings
    }

    /// The twin of [`AdaptivePass::set_settings`](super::AdaptivePass::set_settings).
    ///
    /// # Errors
    ///
    /// As `set_settings`.
    pub fn set_settings(&mut self, settings: AdaptiveSettings) -> Result<(), AdaptiveError> {
        settings.validate()?;
        if self.estimated {
            return Err(AdaptiveError::SettingsBetweenSteps);
        }
        if settings.control != self.settings.control {
            *self = Self::new(settings, self.width, self.height)?;
            return Ok(());
        }
        self.derived = derive(&settings, self.encoding_target)?;
        self.settings = settings;
        Ok(())
    }

    /// The twin of [`AdaptivePass::set_target_variance`](super::AdaptivePass::set_target_variance).
    ///
    /// # Errors
    ///
    /// As `set_target_variance`.
    pub fn set_target_variance(&mut self, sigma0_sq: f32) -> Result<(), AdaptiveError> {
        let config = retargeted(&self.settings.config, sigma0_sq)?;
        self.set_settings(AdaptiveSettings {
            config,
            ..self.settings
        })
    }

    /// The history's texel encoding (the twin of
    /// [`AdaptivePass::encoding`](super::AdaptivePass::encoding)).
    #[must_use]
    pub fn encoding(&self) -> spvg::texel::TexelEncoding {
        self.derived.controller.enc
    }

    /// The controller block the GPU steps read (the twin of
    /// [`AdaptivePass::params_block`](super::AdaptivePass::params_block)).
    #[must_use]
    pub fn params_block(&self) -> &spvg_shaders::Params {
        &self.derived.block
    }

    /// Resizes; every history is invalid afterwards. Between a frame's estimate and its
    /// update it discards the estimate, as
    /// [`AdaptivePass::resize`](super::AdaptivePass::resize) does.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::FrameSize`].
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), AdaptiveError> {
        check_size(width, height, u32::from(u16::MAX))?;
        let fresh = Self::new(self.settings, width, height)?;
        *self = Self {
            encoding_target: self.encoding_target,
            derived: self.derived,
            frame: self.frame,
            resized_between_steps: self.estimated || self.resized_between_steps,
            ..fresh
        };
        Ok(())
    }

    /// Frame size `[width, height]`.
    #[must_use]
    pub fn size(&self) -> [u32; 2] {
        [self.width, self.height]
    }

    /// The counts of the last estimate.
    #[must_use]
    pub fn counts(&self) -> &[u32] {
        &self.count
    }

    /// The latest history texels (`spvg::texel::SpvgTexel16`, spare channel = the
    /// history's age, `spvg::controller::young`; 0 = never written).
    #[must_use]
    pub fn history(&self) -> &[[f16; 4]] {
        &self.history[self.read]
    }

    /// The latest CV history texels (OCV only).
    #[must_use]
    pub fn cv_history(&self) -> Option<&[[f16; 4]]> {
        self.cv.as_ref().map(|c| c[self.read].as_slice())
    }

    /// The classes of the last estimate's counts with the classified dispatch on (the
    /// twin of [`AdaptivePass::read_classes`](super::AdaptivePass::read_classes)'s first
    /// part): per class of [`AdaptivePass::CLASS_BOUNDS`](super::AdaptivePass::CLASS_BOUNDS)
    /// its tiles, `x | y << 16` in tile units, row-major. Empty with it off.
    #[must_use]
    pub fn classes(&self) -> &[Vec<u32>] {
        &self.classes.lists
    }

    /// The pixel order of every tile (row-major) of the last estimate with the
    /// classified dispatch on (the twin of the second part of
    /// [`AdaptivePass::read_classes`](super::AdaptivePass::read_classes)): byte `k` the
    /// index in the tile (`x + 8 y`) of the pixel taken `k`-th, by the class of its count
    /// ([`AdaptivePass::CLASS_BOUNDS`](super::AdaptivePass::CLASS_BOUNDS)), ties in pixel
    /// order. Empty with it off.
    #[must_use]
    pub fn pixel_orders(&self) -> &[[u8; 64]] {
        &self.classes.orders
    }

    /// The real counts of the last estimate's fractional decisions
    /// (`spvg::controller::fractional`, docs/algorithms.md §8.6): per pixel the real count
    /// `c` that its count realises, -1 where the integer rule decided (no continued
    /// history, the zero-sample rule); empty with fractional counts off.
    #[must_use]
    pub fn real_counts(&self) -> &[f32] {
        &self.real
    }

    /// Whether the last estimate found a valid reprojected history at each pixel.
    #[must_use]
    pub fn valid(&self) -> Vec<bool> {
        self.link.iter().map(|&l| l != 0).collect()
    }

    /// The links of the last estimate (the twin of
    /// [`AdaptivePass::link_texture`](super::AdaptivePass::link_texture)): per pixel the
    /// index + 1 of the previous frame's texel whose history the update continues, or 0.
    #[must_use]
    pub fn links(&self) -> &[u32] {
        &self.link
    }

    /// The twin of `record_estimate`: returns the counts. A second estimate before the
    /// update replaces the first, as on the device.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::SliceLength`] for an input of the wrong length.
    pub fn estimate(&mut self, d: &EstimateData<'_>) -> Result<&[u32], AdaptiveError> {
        let n = self.count.len();
        check_len("motion", d.motion, n)?;
        check_len("depth", d.depth, n)?;
        check_len("previous_depth", d.previous_depth, n)?;
        if let Some(r) = d.reprojected_depth {
            check_len("reprojected_depth", r, n)?;
        }
        if let Some(m) = &d.masks {
            check_len("masks.current", m.current, n)?;
            check_len("masks.previous", m.previous, n)?;
        }
        if let Some(g) = d.gamma {
            check_len("gamma", g, n)?;
        }
        if let Some(r) = d.resolve_weight {
            check_len("resolve_weight", r, n)?;
        }
        let size = self.size();
        let w = self.width as usize;
        let hist = &self.history[self.read];
        let fractional = self.settings.config.fractional_floor().is_some();
        self.real.clear();
        if fractional {
            self.real.resize(n, -1.0);
        }
        for i in 0..n {
            let pixel = [(i % w) as u32, (i / w) as u32];
            if d.masks.is_some_and(|m| m.current[i] == 0) {
                (self.count[i], self.link[i]) = (0, 0);
                continue;
            }
            let previous = |q: [u32; 2]| {
                let k = q[1] as usize * w + q[0] as usize;
                PreviousSample {
                    mask: d.masks.is_none_or(|m| m.previous[k] != 0),
                    depth: d.previous_depth[k],
                }
            };
            // The depth the test compares: the reprojected one where given.
            let depth = d.reprojected_depth.map_or(d.depth[i], |r| r[i]);
            let source =
                self.settings
                    .reprojection
                    .locate(pixel, d.motion[i], depth, size, size, previous);
            let (h, link, history) = match source.estimate_texel() {
                Some(q) => {
                    let k = q[1] as usize * w + q[0] as usize;
                    let stored = from_texel(hist[k]);
                    // A texel the previous frame did not write is no history either.
                    if stored[3] < 0.5 {
                        ([0.0; 4], 0, false)
                    } else if source.update_texel().is_some() {
                        (stored, 1 + k as u32, true)
                    } else {
                        // The border prior: the count only; the update seeds.
                        (stored, 0, true)
                    }
                }
                None => ([0.0; 4], 0, false),
            };
            let gamma = d.gamma.map_or(1.0, |g| g[i]);
            if fractional && link != 0 {
                // A continued history: the fractional decision with this pixel's and
                // frame's dither threshold.
                let xi = spvg::sequence::dither_threshold(pixel[0], pixel[1], self.frame);
                // The shader reads an R16Float input as f32 too; "none" is NaN here and
                // the zero texel there, both "none" to the rule.
                let input = d.resolve_weight.map_or(f32::NAN, |r| r[i]);
                (self.count[i], self.real[i]) =
                    estimate_fractional(&self.derived.controller, h, gamma, xi, input);
            } else {
                self.count[i] = estimate_count(&self.derived.controller, h, gamma);
            }
            if history && link == 0 {
                // Entered the frame under the border prior.
                self.count[i] = self
                    .settings
                    .reprojection
                    .entering_count(self.count[i], self.settings.config.max_samples());
            }
            // A pixel without history keeps its first-observation count under dilation.
            if self.settings.dilation > 0 && !history {
                self.count[i] |= spvg::dilation::KEEP;
            }
            self.link[i] = link;
        }
        if self.derived.controller.spvg.spatial_variance() > 0 {
            self.surface.clear();
            self.surface.extend_from_slice(d.depth);
        }
        let dilation = self.settings.dilation;
        if dilation > 0 && self.settings.neighbour_prior {
            self.raw_count.clone_from(&self.count);
            let (raw, r) = (&self.raw_count, &self.settings.reprojection);
            for (i, c) in self.count.iter_mut().enumerate() {
                let pixel = [(i % w) as u32, (i / w) as u32];
                // Same surface: the reprojection's depth test of the neighbour's depth
                // against this pixel's, this frame.
                let same = |q: [u32; 2]| {
                    r.depth_agrees(d.depth[q[1] as usize * w + q[0] as usize], d.depth[i])
                };
                *c = spvg::dilation::dilated_count_with_prior(raw, size, pixel, dilation, same);
            }
        } else if dilation > 0 {
            self.raw_count.clone_from(&self.count);
            spvg::dilation::dilate_counts(&self.raw_count, &mut self.count, size, dilation)?;
        }
        self.classes = if self.settings.classified_dispatch {
            classify(&self.count, size)
        } else {
            Classes::default()
        };
        (self.estimated, self.resized_between_steps) = (true, false);
        Ok(&self.count)
    }

    /// The twin of `record_update` (negative values taken as they are, as there).
    ///
    /// # Errors
    ///
    /// As `record_update`, with [`AdaptiveError::SliceLength`] for the slices.
    pub fn update(&mut self, d: &UpdateData<'_>) -> Result<(), AdaptiveError> {
        self.update_in(d, None)
    }

    /// [`update`](Self::update) with the frame's second moment per pixel (the twin of
    /// [`AdaptivePass::record_update_with_moment`](super::AdaptivePass::record_update_with_moment)):
    /// `moment[i]` is the mean of the squares of the samples whose mean is `value[i]`.
    /// Where a pixel took at least 2 samples and its moment is finite, its variance
    /// follows the in-frame variance of its mean (`spvg::SpvgConfig::update_moment`,
    /// docs/algorithms.md §8.8). With CCV and OCV (whose monitored value is not the
    /// samples' mean) the moment is ignored.
    ///
    /// # Errors
    ///
    /// As [`update`](Self::update), and [`AdaptiveError::SliceLength`] for `moment`.
    pub fn update_with_moment(
        &mut self,
        d: &UpdateData<'_>,
        moment: &[f32],
    ) -> Result<(), AdaptiveError> {
        self.update_in(d, Some(moment))
    }

    fn update_in(
        &mut self,
        d: &UpdateData<'_>,
        moment: Option<&[f32]>,
    ) -> Result<(), AdaptiveError> {
        if !self.estimated {
            return Err(if self.resized_between_steps {
                AdaptiveError::ResizedBetweenSteps
            } else {
                AdaptiveError::UpdateWithoutEstimate
            });
        }
        let n = self.count.len();
        check_len("value", d.value, n)?;
        let control = match (d.control, self.settings.control.needs_control()) {
            (Some(c), true) => {
                check_len("control", c, n)?;
                c
            }
            (None, true) => {
                return Err(AdaptiveError::MissingInput {
                    input: "control",
                    reason: "CCV and OCV monitor fbar - alpha G",
                });
            }
            (_, false) => &[][..],
        };
        if let Some(g) = d.guide {
            check_len("guide", g, n)?;
        }
        if let Some(m) = moment {
            check_len("moment", m, n)?;
        }
        // The second moment applies where the monitored value is the samples' mean (AS).
        let moment =
            moment.filter(|_| control.is_empty() && !matches!(self.settings.control, Control::Ccv));
        let tw = &self.derived.controller;
        let spatial = tw.spvg.spatial_variance() > 0;
        let (width, height) = (self.width as usize, self.height as usize);
        let reprojection = &self.settings.reprojection;
        let (count, surface, real) = (&self.count, &self.surface, &self.real);
        let ccv = matches!(self.settings.control, Control::Ccv);
        // The monitored value of pixel `j` for a neighbourhood whose centre uses the
        // coefficient `alpha` (AS: fbar; CCV: each pixel's own constant coefficient; OCV:
        // the centre's coefficient).
        let monitored = |j: usize, alpha: f32| {
            let f = d.value[j];
            if ccv {
                let g = control[j];
                f - tw.constant_alpha(f, g) * g
            } else if control.is_empty() {
                f
            } else {
                f - alpha * control[j]
            }
        };
        // The spatial moments of pixel `i` with the read texel `h` (docs/algorithms.md
        // §8.4): the pixels of its spatial window (3x3 clipped to its tile), itself
        // included, in row-major order, that took samples and whose depth passes the
        // reprojection's depth test against its own. As in both forms on the device, only
        // a history that is young after the frame gathers them (no other uses them).
        let limit = tw.spvg.spatial_variance();
        let moments = |i: usize, h: [f32; 4], centre: f32, alpha: f32| {
            let mut m = SpatialMoments::default();
            let age = read_age(h[3]);
            if !spatial || next_age(age, age >= 1, true) > limit {
                return m;
            }
            let pixel = [(i % width) as u32, (i / width) as u32];
            let [lo, hi] = spatial_window(pixel, [width as u32, height as u32]);
            for ny in lo[1] as usize..=hi[1] as usize {
                for nx in lo[0] as usize..=hi[0] as usize {
                    let j = ny * width + nx;
                    if count[j] != 0 && reprojection.depth_agrees(surface[j], surface[i]) {
                        m = m.push(centre, monitored(j, alpha));
                    }
                }
            }
            m
        };
        let (h_in, h_out) = split(&mut self.history, self.read);
        let mut cv = self.cv.as_mut().map(|c| split(c, self.read));
        for i in 0..n {
            let (cnt, link) = (count[i], self.link[i]);
            let at = |v: &[[f16; 4]]| {
                if link == 0 {
                    [0.0; 4]
                } else {
                    from_texel(v[(link - 1) as usize])
                }
            };
            let r = real.get(i).copied().unwrap_or(-1.0);
            if cnt == 0 {
                // A skipped frame of a fractional count carries the history (its mean
                // count updated) and the CV state; any other pixel without samples is
                // cleared.
                let skipped = link != 0 && r >= 0.0;
                h_out[i] = if skipped {
                    let none = SpatialMoments::default();
                    to_texel(update_history(
                        tw,
                        at(h_in),
                        f32::NAN,
                        None,
                        0,
                        r,
                        &none,
                        f32::NAN,
                    ))
                } else {
                    ZERO
                };
                if let Some((j_in, j_out)) = &mut cv {
                    j_out[i] = if skipped { to_texel(at(j_in)) } else { ZERO };
                }
                continue;
            }
            let h = at(h_in);
            let f = d.value[i];
            let guide = d.guide.map(|g| g[i]);
            h_out[i] = match (&self.settings.control, &mut cv) {
                (Control::Ocv(_), Some((j_in, j_out))) => {
                    let valid = link != 0;
                    let j = at(j_in);
                    let g = control[i];
                    let alpha = ocv_alpha(tw, j, valid, f, g);
                    j_out[i] = to_texel(update_cv(tw, j, valid, f, g));
                    let s = f - alpha * g;
                    to_texel(update_history(
                        tw,
                        h,
                        s,
                        guide,
                        cnt,
                        r,
                        &moments(i, h, s, alpha),
                        f32::NAN,
                    ))
                }
                (Control::Ccv, _) => {
                    let s = monitored(i, 0.0);
                    to_texel(update_history(
                        tw,
                        h,
                        s,
                        guide,
                        cnt,
                        r,
                        &moments(i, h, s, 0.0),
                        f32::NAN,
                    ))
                }
                _ => to_texel(update_history(
                    tw,
                    h,
                    f,
                    guide,
                    cnt,
                    r,
                    &moments(i, h, f, 0.0),
                    moment.map_or(f32::NAN, |m| m[i]),
                )),
            };
        }
        let w = 1 - self.read;
        self.read = w;
        self.estimated = false;
        self.frame = self.frame.wrapping_add(1);
        Ok(())
    }
}

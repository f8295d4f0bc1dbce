//! The AO renderer of every motion run, on the GPU or the CPU twin, and the check of each
//! GPU frame against the twin that decides whether a run may be scored.
//!
//! A GPU run is held against the twin on every frame, at a cost that keeps the check in
//! the default run (the twin's full frame at 64 spp costs about as much as the GPU's on a
//! software adapter):
//!
//! - **every pixel**: the counts, and for the adaptive component the history texels after
//!   the update. A shadow [`AdaptiveTwin`] with the run's configuration is fed the
//!   G-buffer of the frame (the twin's, `ao_twin::gbuffer`) and the GPU's own AO values
//!   (and TAA guide), so it casts no ray: its counts must equal the GPU's and its history
//!   the GPU's history texels, bit for bit. A fixed count's counts must all be its count.
//! - **a lattice**: the AO values, and the prefix estimates of a fixed run's ladder, at
//!   the pixels with `(x + 3 y + 7 t) mod 29 = 0` (frame `t`), recomputed by the twin's
//!   sampler (`ao_twin::estimate_with_prefixes`) with the GPU's count at that pixel. 29 is
//!   prime and coprime to 8, so every frame's lattice holds every row and every `x mod 8`
//!   (the SIMD lane of a software rasterizer's 8-wide rows, where a fault of one lane
//!   corrupts a whole dispatch at `x = 5 mod 8`), and it moves from frame to frame.
//!
//! A frame that differs makes the run corrupt: it is reported with the scene, the run and
//! the frame and is not scored ([`super::data::TwinCheck`]).

use half::f16;
use spvg::reproject::Reprojection;

use super::data::{Difference, TwinCheck};
use super::options::MotionOptions;
use super::scenes::Variant;
use crate::error::ReportError;
use crate::wgpu_api::{
    AdaptiveError, AdaptiveSettings, AdaptiveTwin, AoFrame, AoGuide, AoMode, AoParams, AoPass,
    AoTwin, Control, EstimateData, GpuDevice, UpdateData, ao_twin as twin, read_texture,
};

/// The lattice's period: the pixels with `(x + 3 y + 7 t) mod LATTICE = 0` (about 3.4%).
pub const LATTICE: u64 = 29;

/// Whether pixel `(x, y)` of frame `t` is on the lattice.
#[must_use]
pub fn on_lattice(x: u32, y: u32, t: u32) -> bool {
    (u64::from(x) + 3 * u64::from(y) + 7 * u64::from(t)) % LATTICE == 0
}

/// How a run renders.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Setup {
    pub(crate) config: spvg::SpvgConfig<f32>,
    pub(crate) mode: AoMode,
    pub(crate) reprojection: Reprojection<f32>,
    pub(crate) dilation: u32,
    pub(crate) reprojected_depth: bool,
    pub(crate) neighbour_prior: bool,
    pub(crate) prefixes: [u32; 4],
}

impl Setup {
    /// The component's settings of the run (AS control: the AO effect's adaptive modes).
    pub(crate) fn settings(&self) -> AdaptiveSettings {
        AdaptiveSettings {
            config: self.config,
            control: Control::As,
            reprojection: self.reprojection,
            dilation: self.dilation,
            neighbour_prior: self.neighbour_prior,
            classified_dispatch: false,
        }
    }

    /// The setup of `v` under `opts`.
    pub(crate) fn of(opts: &MotionOptions, v: &Variant) -> Result<Self, spvg::Error> {
        Ok(Self {
            config: v.config(&opts.config)?,
            mode: v.mode,
            reprojection: v.reprojection,
            dilation: v.dilation,
            reprojected_depth: v.reprojected_depth,
            neighbour_prior: v.neighbour_prior,
            prefixes: v.prefixes,
        })
    }
}

/// The AO renderer on the GPU (checked against the twin) or the CPU twin.
pub(crate) struct Renderer {
    kind: Kind,
    /// Whether the run's counts are fractional: a pixel of 0 samples skipped the frame and
    /// shows its history's mean ([`show_history_where_skipped`]).
    fractional: bool,
}

/// A fractional count's skipped pixels (0 samples) have no AO value of their own: each
/// shows the mean of its history texel after the update (`history`, decoded with `enc`;
/// a skipped frame keeps the history's mean), the value a renderer shows there. Ambient
/// occlusion has no zero-sample rule, so every pixel of 0 samples skipped.
pub(crate) fn show_history_where_skipped(
    f: &mut AoFrame,
    history: &[[f16; 4]],
    enc: &spvg::texel::TexelEncoding,
) {
    for ((v, &n), h) in f.value.iter_mut().zip(&f.count).zip(history) {
        if n == 0 {
            *v = enc.decode(spvg::texel::SpvgTexel16(*h)).mean;
        }
    }
}

enum Kind {
    Gpu(Box<Gpu>),
    Cpu(Box<AoTwin>),
}

/// A GPU renderer and its check against the twin.
struct Gpu {
    pass: AoPass,
    device: GpuDevice,
    guard: Guard,
}

impl Renderer {
    /// The renderer of `setup` at `size` on `dev` (the CPU twin without one); a GPU
    /// run's check is named `scene` / `run`.
    pub(crate) fn new(
        dev: Option<&GpuDevice>,
        setup: &Setup,
        size: [u32; 2],
        scene: &str,
        run: &str,
    ) -> Result<Self, ReportError> {
        let [w, h] = size;
        let s = setup;
        let kind = match dev {
            Some(d) => {
                let mut g = AoPass::new(&d.device, &d.queue, w, h, s.mode, s.settings())
                    .map_err(adaptive)?;
                g.set_reprojected_depth(s.reprojected_depth);
                g.set_prefix_counts(s.prefixes);
                Kind::Gpu(Box::new(Gpu {
                    pass: g,
                    device: d.clone(),
                    guard: Guard::new(setup, size, scene, run)?,
                }))
            }
            None => {
                let mut c = AoTwin::new(w, h, s.mode, s.settings()).map_err(adaptive)?;
                c.set_reprojected_depth(s.reprojected_depth);
                c.set_prefix_counts(s.prefixes);
                Kind::Cpu(Box::new(c))
            }
        };
        Ok(Self {
            kind,
            fractional: !matches!(s.mode, AoMode::Fixed(_))
                && s.config.fractional_floor().is_some(),
        })
    }

    /// Renders frame `p` (its G-buffer `g`, the twin's) and, on the GPU, checks it.
    pub(crate) fn frame(
        &mut self,
        p: &AoParams,
        g: &[twin::GPixel],
    ) -> Result<AoFrame, ReportError> {
        self.frame_guided(p, g, None, None)
    }

    /// [`frame`](Self::frame) with the renderer's TAA guide (an adaptive run's update
    /// takes what `guide` returns) and its resolve weight (the estimate's
    /// `resolve_weight`: `AoPass::set_resolve_weight`).
    pub(crate) fn frame_guided(
        &mut self,
        p: &AoParams,
        g: &[twin::GPixel],
        guide: Option<&mut AoGuide<'_>>,
        resolve_weight: Option<&[f32]>,
    ) -> Result<AoFrame, ReportError> {
        let fractional = self.fractional;
        match &mut self.kind {
            Kind::Cpu(c) => {
                c.set_resolve_weight(resolve_weight).map_err(adaptive)?;
                let mut f = c.run_frame_guided(p, guide).map_err(adaptive)?;
                if let (true, Some(a)) = (fractional, c.adaptive()) {
                    show_history_where_skipped(&mut f, a.history(), &a.encoding());
                }
                Ok(f)
            }
            Kind::Gpu(gpu) => {
                let Gpu {
                    pass,
                    device,
                    guard,
                } = gpu.as_mut();
                pass.set_resolve_weight(resolve_weight).map_err(adaptive)?;
                // The guide the GPU's update took, for the shadow twin's update.
                let mut given: Option<Vec<f32>> = None;
                let f = match guide {
                    Some(user) => {
                        let mut keep = |value: &[f32]| {
                            let c = user(value);
                            given = Some(c.clone());
                            c
                        };
                        pass.run_frame_guided(p, Some(&mut keep))
                    }
                    None => pass.run_frame(p),
                }
                .map_err(adaptive)?;
                let history: Option<Vec<[f16; 4]>> = match pass.adaptive() {
                    Some(a) => Some(
                        read_texture(&device.device, &device.queue, a.history_texture())
                            .map_err(adaptive)?,
                    ),
                    None => None,
                };
                guard.check(
                    p,
                    g,
                    &f,
                    history.as_deref(),
                    given.as_deref(),
                    resolve_weight,
                )?;
                let mut f = f;
                if let (true, Some(h), Some(a)) = (fractional, &history, pass.adaptive()) {
                    show_history_where_skipped(&mut f, h, &a.encoding());
                }
                Ok(f)
            }
        }
    }

    /// The run's check against the twin (`None` on the CPU twin).
    pub(crate) fn twin_check(&self) -> Option<TwinCheck> {
        match &self.kind {
            Kind::Gpu(gpu) => Some(gpu.guard.record.clone()),
            Kind::Cpu(_) => None,
        }
    }
}

/// A component or renderer error as the report's.
pub(crate) fn adaptive(e: AdaptiveError) -> ReportError {
    ReportError::Pass(e.into())
}

/// The check of one GPU run against the twin.
struct Guard {
    /// The component's twin fed the GPU's values (`None` for a fixed count).
    shadow: Option<AdaptiveTwin>,
    mode: AoMode,
    reprojected_depth: bool,
    prefixes: [u32; 4],
    previous_depth: Option<Vec<f32>>,
    record: TwinCheck,
}

impl Guard {
    fn new(s: &Setup, size: [u32; 2], scene: &str, run: &str) -> Result<Self, ReportError> {
        let shadow = match s.mode {
            AoMode::Fixed(_) => None,
            AoMode::Adaptive | AoMode::Identity => {
                Some(AdaptiveTwin::new(s.settings(), size[0], size[1]).map_err(adaptive)?)
            }
        };
        Ok(Self {
            record: TwinCheck {
                scene: scene.to_owned(),
                run: run.to_owned(),
                adaptive: shadow.is_some(),
                ..TwinCheck::default()
            },
            shadow,
            mode: s.mode,
            reprojected_depth: s.reprojected_depth,
            prefixes: s.prefixes,
            previous_depth: None,
        })
    }

    /// Checks the GPU's frame `f` of `p` (G-buffer `g`; `history` the GPU's history
    /// texels after the update, `guide` the guide its update took, `resolve_weight` the
    /// resolve weight its estimate took).
    fn check(
        &mut self,
        p: &AoParams,
        g: &[twin::GPixel],
        f: &AoFrame,
        history: Option<&[[f16; 4]]>,
        guide: Option<&[f32]>,
        resolve_weight: Option<&[f32]>,
    ) -> Result<(), ReportError> {
        let t = p.frame;
        let w = p.width;
        let depth: Vec<f32> = g.iter().map(|x| x.depth).collect();
        let mut differences: Vec<(&'static str, Vec<usize>)> = Vec::new();
        // Every pixel: the counts (and the history texels after the update).
        let want_count: Vec<u32> = match (&mut self.shadow, self.mode) {
            (Some(a), mode) => {
                let identity = mode == AoMode::Identity;
                let motion: Vec<[f32; 2]> = if identity {
                    vec![[0.0; 2]; g.len()]
                } else {
                    g.iter().map(|x| x.motion).collect()
                };
                let reprojected: Vec<f32> = g.iter().map(|x| x.reprojected_depth).collect();
                // The GPU's first frame reads a zeroed previous depth.
                let zero = vec![0.0; g.len()];
                let previous = if identity {
                    &depth
                } else {
                    self.previous_depth.as_ref().unwrap_or(&zero)
                };
                a.estimate(
                    &EstimateData::new(&motion, &depth, previous)
                        .with_reprojected_depth(
                            (self.reprojected_depth && !identity).then_some(&reprojected),
                        )
                        .with_resolve_weight(resolve_weight),
                )
                .map_err(adaptive)?
                .to_vec()
            }
            (None, AoMode::Fixed(n)) => vec![n; g.len()],
            (None, _) => vec![0; g.len()],
        };
        differences.push(("count", differing(&want_count, &f.count)));
        if let Some(a) = &mut self.shadow {
            a.update(&UpdateData::new(&f.value).with_guide(guide))
                .map_err(adaptive)?;
            let bits = |h: &[[f16; 4]]| -> Vec<[u16; 4]> {
                h.iter().map(|x| x.map(f16::to_bits)).collect()
            };
            let gpu = history.map(bits).unwrap_or_default();
            differences.push(("history", differing(&bits(a.history()), &gpu)));
        }
        // The lattice: the AO value and the prefix estimates from the GPU's own count.
        let q = AoParams {
            prefixes: self.prefixes,
            ..*p
        };
        let ladder = self.prefixes != [0; 4];
        let (mut value, mut prefix) = (Vec::new(), Vec::new());
        for (i, gp) in g.iter().enumerate() {
            let (x, y) = (i as u32 % w, i as u32 / w);
            if !on_lattice(x, y, t) {
                continue;
            }
            self.record.lattice += 1;
            let n = f.count.get(i).copied().unwrap_or(0);
            let (v, pre) = twin::estimate_with_prefixes(&q, [x, y], &gp.surface, n);
            if f.value.get(i).map(|a| a.to_bits()) != Some(v.to_bits()) {
                value.push(i);
            }
            if ladder
                && f.prefixes.get(i).map(|a| a.map(f32::to_bits)) != Some(pre.map(f32::to_bits))
            {
                prefix.push(i);
            }
        }
        differences.push(("value", value));
        differences.push(("prefix", prefix));
        self.previous_depth = Some(depth);
        record_frame(&mut self.record, t, w, differences);
        Ok(())
    }
}

/// Records frame `t` (width `w`) of a GPU run in `record`: the frame differs where the
/// first of `differences` (a quantity and the pixels where it differs) is not empty, and
/// the first differing frame is named with its pixels and lanes.
pub(crate) fn record_frame(
    record: &mut TwinCheck,
    t: u32,
    w: u32,
    differences: Vec<(&'static str, Vec<usize>)>,
) {
    record.frames += 1;
    if let Some((what, bad)) = differences.into_iter().find(|(_, d)| !d.is_empty()) {
        record.frames_differing += 1;
        if record.corrupt.is_none() {
            let mut lanes = [0_usize; 8];
            for &i in &bad {
                lanes[i % w.max(1) as usize % 8] += 1;
            }
            let first = bad
                .first()
                .map_or([0, 0], |&i| [i as u32 % w.max(1), i as u32 / w.max(1)]);
            record.corrupt = Some(Difference {
                frame: t,
                what,
                pixels: bad.len(),
                first,
                lanes,
            });
        }
    }
}

/// The indices where `want` and `got` differ (every index past the shorter one too).
pub(crate) fn differing<T: PartialEq>(want: &[T], got: &[T]) -> Vec<usize> {
    let n = want.len().max(got.len());
    (0..n).filter(|&i| want.get(i) != got.get(i)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lattice_holds_every_lane_and_row_of_every_frame() {
        for (w, h) in [(384_u32, 192_u32), (128, 96)] {
            for t in 0..40 {
                let mut lanes = [0_u32; 8];
                let mut rows = vec![0_u32; h as usize];
                let mut n = 0;
                for y in 0..h {
                    for x in 0..w {
                        if on_lattice(x, y, t) {
                            lanes[(x % 8) as usize] += 1;
                            rows[y as usize] += 1;
                            n += 1;
                        }
                    }
                }
                assert!(
                    lanes.iter().all(|&k| k > 0),
                    "{w}x{h} frame {t}: lanes {lanes:?}"
                );
                assert!(
                    rows.iter().all(|&k| k > 0),
                    "{w}x{h} frame {t}: a row is missing"
                );
                let share = f64::from(n) / f64::from(w * h);
                assert!(
                    (share - 1.0 / 29.0).abs() < 0.002,
                    "{w}x{h} frame {t}: {share}"
                );
            }
        }
        // The lattice moves: a pixel is on it one frame in 29.
        let on: usize = (0..29).filter(|&t| on_lattice(5, 7, t)).count();
        assert_eq!(on, 1, "pixel (5, 7) over 29 frames");
    }

    /// One twin frame: its parameters, G-buffer, output and history texels after it.
    type TwinFrame = (AoParams, Vec<twin::GPixel>, AoFrame, Vec<[f16; 4]>);

    /// A change made to frame 2 before the guard sees it.
    type Corruption<'a> = &'a dyn Fn(&mut AoFrame, &mut Vec<[f16; 4]>, &AoParams);

    /// The twin's frames of `variant` on `motion`, with the history texels after each.
    fn twin_frames(
        opts: &MotionOptions,
        motion: crate::wgpu_api::Motion,
        v: &Variant,
    ) -> Vec<TwinFrame> {
        let setup = Setup::of(opts, v).expect("valid variant");
        let mut r = Renderer::new(None, &setup, opts.size, "test", "test").expect("twin");
        let scene = crate::wgpu_api::AoScene {
            width: opts.size[0],
            height: opts.size[1],
            motion,
        };
        (0..opts.frames)
            .map(|t| {
                let p = scene.params(t);
                let g = twin::gbuffer(&p);
                // The twin's raw frame: what the guard checks (a fractional run's skipped
                // pixels show their history's mean only after the check).
                let Kind::Cpu(c) = &mut r.kind else {
                    panic!("a twin renderer");
                };
                let f = c.run_frame_guided(&p, None).expect("twin frame");
                let history = c.adaptive().map_or_else(Vec::new, |a| a.history().to_vec());
                (p, g, f, history)
            })
            .collect()
    }

    /// The guard passes the twin's own frames, and names the first frame, the quantity
    /// and the lane of a corruption of one lane's pixels: an AO value on the lattice at
    /// x = 5 mod 8, a count, a history texel.
    #[test]
    fn the_guard_passes_the_twin_and_names_a_corrupt_frame() {
        use crate::motion::scenes::variants;
        use crate::wgpu_api::Motion;
        let opts = MotionOptions {
            size: [40, 24],
            frames: 3,
            ..MotionOptions::new().expect("defaults")
        };
        let motion = Motion::Pan { speed: 4.0 };
        for v in variants(motion, &opts) {
            let setup = Setup::of(&opts, &v).expect("valid variant");
            let frames = twin_frames(&opts, motion, &v);
            let check = |corrupt: Corruption<'_>| {
                let mut guard = Guard::new(&setup, opts.size, "pan4", "run").expect("guard");
                for (k, (p, g, f, h)) in frames.iter().enumerate() {
                    let (mut f, mut h) = (f.clone(), h.clone());
                    if k == 2 {
                        corrupt(&mut f, &mut h, p);
                    }
                    let history = (!h.is_empty()).then_some(h.as_slice());
                    guard.check(p, g, &f, history, None, None).expect("check");
                }
                guard.record
            };
            let clean = check(&|_, _, _| {});
            assert_eq!(
                clean.corrupt,
                None,
                "{}: the twin's own frames",
                v.name(&opts)
            );
            assert_eq!(clean.frames, 3);
            assert!(clean.lattice > 0, "{clean:?}");
            // One count anywhere.
            let count = check(&|f, _, _| f.count[7] += 1);
            assert_eq!(count.corrupt.map(|d| (d.frame, d.what)), Some((2, "count")));
            if clean.adaptive {
                let history = check(&|_, h, _| h[9][1] = f16::from_f32(h[9][1].to_f32() + 1.0));
                assert_eq!(
                    history.corrupt.map(|d| (d.frame, d.what, d.first)),
                    Some((2, "history", [9, 0]))
                );
                // (A wrong AO value reaches an adaptive run's history through the update;
                // a fixed run shows it as the value itself.)
                continue;
            }
            // One AO value at a lattice pixel in lane 5 of frame 2.
            let lane5 = check(&|f, _, p| {
                let w = p.width;
                let i = (0..f.value.len())
                    .find(|&i| {
                        on_lattice(i as u32 % w, i as u32 / w, p.frame) && i as u32 % w % 8 == 5
                    })
                    .expect("the lattice holds lane 5");
                f.value[i] += 1.0 / 64.0;
            });
            let d = lane5.corrupt.expect("a corrupt value is found");
            assert_eq!((d.frame, d.what, d.pixels), (2, "value", 1), "{d:?}");
            assert_eq!(d.lanes, [0, 0, 0, 0, 0, 1, 0, 0], "{d:?}");
            // The ladder's prefix estimate at the same pixel.
            let prefix = check(&|f, _, p| {
                let w = p.width;
                let i = (0..f.value.len())
                    .find(|&i| on_lattice(i as u32 % w, i as u32 / w, p.frame))
                    .expect("a lattice pixel");
                f.prefixes[i][0] += 1.0 / 16.0;
            });
            assert_eq!(
                prefix.corrupt.map(|d| (d.frame, d.what)),
                Some((2, "prefix"))
            );
        }
    }

    #[test]
    fn differing_names_every_index_that_differs() {
        assert_eq!(differing(&[1, 2, 3], &[1, 0, 3]), vec![1]);
        assert_eq!(differing(&[1, 2], &[1, 2, 3]), vec![2]);
        assert!(differing::<u32>(&[], &[]).is_empty());
    }
}

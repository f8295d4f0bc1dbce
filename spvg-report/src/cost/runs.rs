//! One effect's interleaved runs: the configurations a cost table compares, each its own
//! pass with its own history, rendered one frame each in turn.

use spvg::burley::presets;

use crate::error::ReportError;
use crate::metrics::mean_spp;
use crate::scene::{Scene, SceneKind};
use crate::wgpu_api::{
    AdaptiveSettings, AoMode, AoPass, AoScene, GpuDevice, Model, Motion, PassConfig, SssPass,
};

/// The two effects the cost is judged on, each on its static scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect {
    /// The subsurface pass on the report's static scene (AFIS off, skin1, the published
    /// controller).
    Subsurface,
    /// Ambient occlusion with a static camera (the component's default settings).
    Ao,
}

impl Effect {
    /// Short name (`sss static`, `ao static`).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Subsurface => "sss static",
            Self::Ao => "ao static",
        }
    }
}

/// How an adaptive configuration runs the component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// Two passes around the sampling (the effects' default: the fastest form measured
    /// on software Vulkan after the classified one, BENCHMARKS.md).
    Split,
    /// One pass, the invocations of a tile ordered by count (the component's one-pass
    /// default).
    OnePass,
    /// One pass without the count order.
    OnePassUnordered,
    /// Two passes with the count-classified dispatch of the sampling.
    Classified,
}

impl Form {
    /// Every form, the default first.
    pub const ALL: [Self; 4] = [
        Self::Split,
        Self::OnePass,
        Self::OnePassUnordered,
        Self::Classified,
    ];

    /// The name of its row (`as`, `as one-pass`, `as one-pass unordered`,
    /// `as classified`).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Split => "as",
            Self::OnePass => "as one-pass",
            Self::OnePassUnordered => "as one-pass unordered",
            Self::Classified => "as classified",
        }
    }
}

/// One configuration of a cost run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Config {
    /// A fixed count everywhere.
    Fixed(u32),
    /// The adaptive component (AS) in a form.
    Adaptive(Form),
}

impl Config {
    /// The row's name (`fixed16`, or the form's).
    #[must_use]
    pub fn name(&self) -> String {
        match self {
            Self::Fixed(n) => format!("fixed{n}"),
            Self::Adaptive(f) => f.name().into(),
        }
    }
}

/// One frame of one configuration: its time and its mean samples per pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameCost {
    /// The frame's time in ms (the pass's own: GPU timestamps where it has them, else wall
    /// time from submit to completion).
    pub ms: f64,
    /// Mean samples per pixel (over the subsurface mask, or the frame).
    pub spp: f64,
    /// What a SIMD group of [`LANES`] lanes runs per pixel: the mean over the frame's
    /// groups of their largest count, the groups being the rows of each 8 x 8 tile in
    /// pixel order (`[0]`) and in the count order of the one-pass form (`[1]`).
    pub lanes_spp: [f64; 2],
}

/// The lanes of a SIMD group on the software rasterizer (lavapipe, 256-bit vectors of
/// 32-bit values), each running one invocation.
pub const LANES: usize = 8;

/// [`FrameCost::lanes_spp`] of a `w x h` frame's counts.
#[must_use]
pub fn lanes_spp(count: &[u32], [w, h]: [u32; 2]) -> [f64; 2] {
    let (w, h) = (w as usize, h as usize);
    let (mut plain, mut ordered, mut groups) = (0.0, 0.0, 0_usize);
    for ty in (0..h).step_by(8) {
        for tx in (0..w).step_by(8) {
            // The tile's 64 counts (0 outside the frame), row by row.
            let tile: Vec<u32> = (0..64)
                .map(|k| {
                    let (x, y) = (tx + k % 8, ty + k / 8);
                    if x < w && y < h { count[y * w + x] } else { 0 }
                })
                .collect();
            let mut sorted = tile.clone();
            sorted.sort_unstable();
            for g in 0..64 / LANES {
                let lanes = g * LANES..(g + 1) * LANES;
                plain += f64::from(*tile[lanes.clone()].iter().max().unwrap_or(&0));
                ordered += f64::from(*sorted[lanes].iter().max().unwrap_or(&0));
                groups += 1;
            }
        }
    }
    let per_pixel = (groups * LANES).max(1) as f64 / (w * h).max(1) as f64;
    let n = groups.max(1) as f64;
    [plain / n * per_pixel, ordered / n * per_pixel]
}

/// A configuration's pass.
enum Runner {
    Sss {
        pass: Box<SssPass>,
        cfg: PassConfig,
        unordered: bool,
    },
    Ao(Box<AoPass>),
}

/// An effect's passes, one per configuration, on one device and frame size.
pub struct EffectRuns {
    effect: Effect,
    size: [u32; 2],
    scene: Scene,
    ao: AoScene,
    runners: Vec<Runner>,
}

impl core::fmt::Debug for EffectRuns {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("EffectRuns")
            .field("effect", &self.effect)
            .field("configs", &self.runners.len())
            .finish_non_exhaustive()
    }
}

impl EffectRuns {
    /// The passes of `configs` for `effect` at `size` on `device`.
    ///
    /// # Errors
    ///
    /// A pass the device refuses.
    pub fn new(
        device: &GpuDevice,
        effect: Effect,
        size: [u32; 2],
        configs: &[Config],
    ) -> Result<Self, ReportError> {
        let [w, h] = size;
        let mut runners = Vec::new();
        for c in configs {
            runners.push(match (effect, c) {
                (Effect::Subsurface, _) => {
                    let (model, form) = match c {
                        Config::Fixed(n) => (Model::Fixed(*n), None),
                        Config::Adaptive(f) => (Model::As, Some(*f)),
                    };
                    let mut pass = SssPass::for_device(device, model, w, h);
                    pass.set_one_pass(!matches!(form, Some(Form::Split | Form::Classified)));
                    Runner::Sss {
                        pass: Box::new(pass),
                        cfg: PassConfig {
                            classified_dispatch: form == Some(Form::Classified),
                            ..PassConfig::default()
                        },
                        unordered: form == Some(Form::OnePassUnordered),
                    }
                }
                (Effect::Ao, Config::Fixed(n)) => Runner::Ao(Box::new(AoPass::new(
                    &device.device,
                    &device.queue,
                    w,
                    h,
                    AoMode::Fixed(*n),
                    AdaptiveSettings::default(),
                )?)),
                (Effect::Ao, Config::Adaptive(f)) => {
                    let settings = AdaptiveSettings {
                        classified_dispatch: *f == Form::Classified,
                        ..AdaptiveSettings::default()
                    };
                    let mut pass = AoPass::new(
                        &device.device,
                        &device.queue,
                        w,
                        h,
                        AoMode::Adaptive,
                        settings,
                    )?;
                    pass.set_one_pass(!matches!(f, Form::Split | Form::Classified));
                    if let Some(a) = pass.adaptive_mut() {
                        a.set_one_pass_order(*f != Form::OnePassUnordered);
                    }
                    Runner::Ao(Box::new(pass))
                }
            });
        }
        Ok(Self {
            effect,
            size,
            scene: Scene::new(SceneKind::Static, w, h),
            ao: AoScene {
                width: w,
                height: h,
                motion: Motion::Static,
            },
            runners,
        })
    }

    /// Renders frame `t` of configuration `k`.
    ///
    /// # Errors
    ///
    /// A pass error.
    pub fn frame(&mut self, k: usize, t: u32) -> Result<FrameCost, ReportError> {
        match &mut self.runners[k] {
            Runner::Sss {
                pass,
                cfg,
                unordered,
            } => {
                let inputs = self.scene.inputs(t);
                let p = pass.frame_params(cfg, &presets::SKIN1, t)?;
                if let Some(a) = pass.adaptive_mut() {
                    a.set_one_pass_order(!*unordered);
                }
                let o = pass.run_frame(&p, &inputs)?;
                Ok(FrameCost {
                    ms: o.time_ms,
                    spp: mean_spp(&o.count, &inputs.mask),
                    lanes_spp: lanes_spp(&o.count, self.size),
                })
            }
            Runner::Ao(pass) => {
                let f = pass.run_frame(&self.ao.params(t))?;
                let n = f.count.len().max(1) as f64;
                Ok(FrameCost {
                    ms: pass.last_frame_ms(),
                    spp: f.count.iter().map(|&c| f64::from(c)).sum::<f64>() / n,
                    lanes_spp: lanes_spp(&f.count, self.size),
                })
            }
        }
    }

    /// The effect.
    #[must_use]
    pub fn effect(&self) -> Effect {
        self.effect
    }
}

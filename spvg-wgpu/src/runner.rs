//! One interface over the two implementations of the pass: the wgpu pass and its CPU twin.

use half::f16;

use crate::adaptive::{AdaptiveTwin, Control, EstimateData, Masks, UpdateData};
use crate::device::{BackendChoice, GpuDevice, acquire_device, check_frame_size};
use crate::error::PassError;
use crate::frame::{FrameInputs, FrameOutput, History, Timer};
use crate::gpu::GpuPass;
use crate::params::{ComponentSetup, Model, PassParams};
use crate::twin;

/// The CPU twin of [`GpuPass`]: a fixed count runs the twin of `sss_fixed`; AS, CCV and
/// OCV run the adaptive component's twin ([`AdaptiveTwin`], built at the first frame from
/// its block, which owns the history) around the twins of `sss_gamma` and `sss_sample`.
#[derive(Clone, Debug)]
pub struct CpuPass {
    model: Model,
    pixels: usize,
    /// Boxed: the twin holds two uniform blocks, and a `PassRunner` should stay small.
    component: Option<Box<(ComponentSetup, AdaptiveTwin)>>,
    /// The previous frame's depth and mask (the component's previous inputs).
    previous: Option<(Vec<f32>, Vec<u8>)>,
}

impl CpuPass {
    /// A CPU pass for `model` on frames of `pixels` pixels, with a cold (all-zero)
    /// history.
    #[must_use]
    pub fn new(model: Model, pixels: usize) -> Self {
        Self {
            model,
            pixels,
            component: None,
            previous: None,
        }
    }

    /// Runs one frame through the twins of the model's entry points (and of the adaptive
    /// component's steps), as [`GpuPass::run_frame`] records them.
    ///
    /// # Errors
    ///
    /// [`PassError::InputSize`] for inconsistent inputs or another frame size than
    /// `pixels` (or than the first frame's), else as [`GpuPass::run_frame`].
    pub fn run_frame(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
    ) -> Result<FrameOutput, PassError> {
        let size_changed = self
            .component
            .as_ref()
            .is_some_and(|c| c.1.size() != [inputs.width, inputs.height]);
        if !inputs.is_consistent() || inputs.len() != self.pixels || size_changed {
            return Err(PassError::InputSize {
                expected: self.pixels,
                got: inputs.lighting.len(),
            });
        }
        let mut p = *params;
        p.width = inputs.width;
        p.height = inputs.height;
        let tw = twin::Twin::new(&p)?;
        let setup = p.component_setup(self.model)?;
        let start = std::time::Instant::now();
        let (result, count) = match setup {
            None => twin::sss_fixed(&tw, inputs),
            Some(_) if inputs.is_empty() => (Vec::new(), Vec::new()),
            Some(setup) => self.adaptive_frame(&tw, &setup, inputs)?,
        };
        Ok(FrameOutput {
            result,
            count,
            time_ms: start.elapsed().as_secs_f64() * 1e3,
            timer: Timer::WallClock,
        })
    }

    /// `sss_gamma` -> estimate -> `sss_sample` -> update, on the twins.
    fn adaptive_frame(
        &mut self,
        tw: &twin::Twin,
        setup: &ComponentSetup,
        inputs: &FrameInputs,
    ) -> Result<(Vec<[f16; 4]>, Vec<u32>), PassError> {
        let component = match self.component.as_deref_mut() {
            Some((s, a)) if s.config == setup.config && s.control == setup.control => a,
            Some(_) => return Err(PassError::ControllerChanged),
            None => {
                let a =
                    AdaptiveTwin::new(setup.config, setup.control, inputs.width, inputs.height)?;
                let enc = a.encoding();
                let ocv = matches!(setup.control, Control::Ocv(_));
                if enc.variance_scale() != tw.enc.variance_scale()
                    || (ocv && enc.cv_scale() != tw.enc.cv_scale())
                {
                    return Err(PassError::ControllerChanged);
                }
                &mut self.component.insert(Box::new((*setup, a))).1
            }
        };
        component.set_target_variance(setup.target)?;
        let gamma = twin::sss_gamma(tw, inputs);
        let motion = vec![[0.0_f32; 2]; inputs.len()];
        // Before the first frame the history is cold: the previous inputs do not matter.
        let (prev_depth, prev_mask) = self
            .previous
            .as_ref()
            .map_or((&inputs.depth, &inputs.mask), |(d, m)| (d, m));
        let count = component
            .estimate(&EstimateData {
                motion: &motion,
                depth: &inputs.depth,
                previous_depth: prev_depth,
                masks: Some(Masks {
                    current: &inputs.mask,
                    previous: prev_mask,
                }),
                gamma: Some(&gamma),
            })?
            .to_vec();
        let sampled = twin::sss_sample(tw, inputs, &count);
        let control = component
            .control()
            .needs_control()
            .then_some(sampled.control.as_slice());
        component.update(&UpdateData {
            value: &sampled.value,
            control,
        })?;
        self.previous = Some((inputs.depth.clone(), inputs.mask.clone()));
        Ok((sampled.result, count))
    }

    /// The history written by the last frame (a copy of the component's texels; zero
    /// before the first frame, empty for a fixed count).
    #[must_use]
    pub fn history(&self) -> History {
        let zero = || vec![[f16::ZERO; 4]; self.pixels];
        match (self.component.as_deref(), self.model) {
            (_, Model::Fixed(_)) => History::default(),
            (Some((_, a)), _) => History {
                h: a.history().to_vec(),
                j: a.cv_history().map(<[_]>::to_vec).unwrap_or_default(),
            },
            (None, Model::Ocv) => History {
                h: zero(),
                j: zero(),
            },
            (None, _) => History {
                h: zero(),
                j: Vec::new(),
            },
        }
    }
}

/// A pass on either implementation.
#[derive(Debug)]
pub enum PassRunner {
    /// The wgpu pass.
    Gpu(Box<GpuPass>),
    /// The CPU twin.
    Cpu(CpuPass),
}

impl PassRunner {
    /// Runs one frame.
    ///
    /// # Errors
    ///
    /// As [`GpuPass::run_frame`] / [`CpuPass::run_frame`].
    pub fn run_frame(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
    ) -> Result<FrameOutput, PassError> {
        match self {
            Self::Gpu(g) => g.run_frame(params, inputs),
            Self::Cpu(c) => c.run_frame(params, inputs),
        }
    }

    /// The history written by the last frame.
    ///
    /// # Errors
    ///
    /// A failed GPU readback.
    pub fn history(&self) -> Result<History, PassError> {
        match self {
            Self::Gpu(g) => g.history(),
            Self::Cpu(c) => Ok(c.history()),
        }
    }
}

/// The resolved backend: a wgpu device, or the CPU twin.
#[derive(Clone, Debug)]
pub enum Backend {
    /// A wgpu device.
    Gpu(Box<GpuDevice>),
    /// The CPU twin.
    Cpu,
}

impl Backend {
    /// Resolves a [`BackendChoice`]: `auto` falls back to the CPU twin when no wgpu adapter
    /// can be created.
    ///
    /// # Errors
    ///
    /// With `gpu`, when no wgpu device can be created.
    pub fn resolve(choice: BackendChoice) -> Result<Self, PassError> {
        match choice {
            BackendChoice::Cpu => Ok(Self::Cpu),
            BackendChoice::Gpu => acquire_device().map(|d| Self::Gpu(Box::new(d))),
            BackendChoice::Auto => {
                Ok(acquire_device().map_or(Self::Cpu, |d| Self::Gpu(Box::new(d))))
            }
        }
    }

    /// One line saying which implementation runs.
    #[must_use]
    pub fn describe(&self) -> String {
        match self {
            Self::Gpu(d) => format!("wgpu: {}", d.describe()),
            Self::Cpu => format!(
                "CPU twin ({} threads), timing: CPU wall time",
                std::thread::available_parallelism().map_or(1, usize::from)
            ),
        }
    }

    /// Checks that a `width x height` frame fits the backend: the device's limits
    /// ([`check_frame_size`]) on a GPU; the CPU twin takes any size that fits in memory.
    ///
    /// # Errors
    ///
    /// [`PassError::FrameTooLarge`] naming the limit.
    pub fn check_frame(&self, width: u32, height: u32) -> Result<(), PassError> {
        match self {
            Self::Gpu(d) => d.check_frame(width, height),
            Self::Cpu => Ok(()),
        }
    }

    /// A pass for `model` on this backend, after [`Backend::check_frame`].
    ///
    /// # Errors
    ///
    /// [`PassError::FrameTooLarge`] when the frame does not fit the device.
    pub fn pass(&self, model: Model, width: u32, height: u32) -> Result<PassRunner, PassError> {
        self.check_frame(width, height)?;
        Ok(match self {
            Self::Gpu(d) => PassRunner::Gpu(Box::new(run_inner(d, model, width, height))),
            Self::Cpu => PassRunner::Cpu(CpuPass::new(model, width as usize * height as usize)),
        })
    }
}

/// Builds the wgpu pass on a device the caller owns (tests pass their own). wgpu panics on
/// a frame beyond the device's limits: check sizes you did not choose with
/// [`GpuDevice::check_frame`] first ([`Backend::pass`] does).
///
/// Pass times are timestamp queries on a hardware adapter that has them, else wall time:
/// a software rasterizer's (lavapipe's) timestamps did not bracket the work of the
/// adaptive models' four passes (measured: 0.5 ms for a frame whose single-pass fixed
/// baseline at the same count took 15 ms), while its wall time is the CPU time it spends.
#[must_use]
pub fn run_inner(device: &GpuDevice, model: Model, width: u32, height: u32) -> GpuPass {
    GpuPass::new(
        &device.device,
        &device.queue,
        width,
        height,
        model,
        device.timestamps && !device.is_software(),
    )
}

/// Runs `frames` through `model` on a caller-provided device and queue, returning every
/// frame's output and the final history. This is the entry point tests use with their own
/// device.
///
/// # Errors
///
/// [`PassError::FrameTooLarge`] for frames beyond the device's limits, else as
/// [`GpuPass::run_frame`].
pub fn run_frames_on(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    model: Model,
    params: &[PassParams],
    frames: &[FrameInputs],
) -> Result<(Vec<FrameOutput>, History), PassError> {
    let (w, h) = frames.first().map_or((0, 0), |f| (f.width, f.height));
    check_frame_size(device, w, h)?;
    let mut pass = GpuPass::new(device, queue, w, h, model, false);
    let mut out = Vec::with_capacity(frames.len());
    for (p, f) in params.iter().zip(frames) {
        out.push(pass.run_frame(p, f)?);
    }
    Ok((out, pass.history()?))
}

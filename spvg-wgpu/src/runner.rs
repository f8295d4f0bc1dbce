//! One interface over the two implementations of the pass: the wgpu pass and its CPU twin.

use half::f16;

use crate::device::{BackendChoice, GpuDevice, acquire_device, check_frame_size};
use crate::error::PassError;
use crate::frame::{FrameInputs, FrameOutput, History, Timer};
use crate::gpu::GpuPass;
use crate::params::{Model, PassParams};
use crate::twin;

/// The CPU twin with its own ping-pong history.
#[derive(Clone, Debug)]
pub struct CpuPass {
    model: Model,
    history: History,
}

impl CpuPass {
    /// A CPU pass for `model` with a cold (all-zero) history of `pixels` texels.
    #[must_use]
    pub fn new(model: Model, pixels: usize) -> Self {
        let zero = vec![[f16::ZERO; 4]; pixels];
        let history = match model {
            Model::Fixed(_) => History::default(),
            Model::As | Model::Ccv => History {
                h: zero,
                j: Vec::new(),
            },
            Model::Ocv => History {
                h: zero.clone(),
                j: zero,
            },
        };
        Self { model, history }
    }

    /// Runs one frame through the twin of the model's entry point.
    ///
    /// # Errors
    ///
    /// [`PassError::InputSize`] for inconsistent inputs.
    pub fn run_frame(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
    ) -> Result<FrameOutput, PassError> {
        if !inputs.is_consistent() {
            return Err(PassError::InputSize {
                expected: inputs.len(),
                got: inputs.lighting.len(),
            });
        }
        let mut p = *params;
        p.width = inputs.width;
        p.height = inputs.height;
        let tw = twin::Twin::new(&p)?;
        let start = std::time::Instant::now();
        let (result, count) = match self.model {
            Model::Fixed(_) => twin::sss_fixed(&tw, inputs),
            Model::As | Model::Ccv => {
                let (r, c, h) = twin::sss_adaptive(&tw, inputs, &self.history);
                self.history = h;
                (r, c)
            }
            Model::Ocv => {
                let (r, c, h) = twin::sss_ocv(&tw, inputs, &self.history);
                self.history = h;
                (r, c)
            }
        };
        Ok(FrameOutput {
            result,
            count,
            time_ms: start.elapsed().as_secs_f64() * 1e3,
            timer: Timer::WallClock,
        })
    }

    /// The history written by the last frame.
    #[must_use]
    pub fn history(&self) -> &History {
        &self.history
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
            Self::Cpu(c) => Ok(c.history().clone()),
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
#[must_use]
pub fn run_inner(device: &GpuDevice, model: Model, width: u32, height: u32) -> GpuPass {
    GpuPass::new(
        &device.device,
        &device.queue,
        width,
        height,
        model,
        device.timestamps,
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

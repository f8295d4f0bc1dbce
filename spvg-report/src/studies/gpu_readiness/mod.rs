//! GPU readiness: the adaptive component's two steps (AS, with the count dilation the
//! report runs) timed at 1080p and 2160p against a copy kernel that moves the same bytes
//! on the same device, and the ratio of the two. The ratio says how far each step is from
//! the bandwidth floor of its own memory traffic; on a software adapter both figures are
//! CPU time, so only the ratio means anything there.
//!
//! Byte count: each step moves, per pixel, the texels of the frame-size textures it
//! binds ([`estimate_bytes`], [`update_bytes`]); the 1x1 placeholders bound for the
//! inputs this run leaves out (masks, gamma, reprojected depth, control) are not counted.
//! Every texel is counted once, although the estimate reads the history and previous
//! depth at a reprojected texel: the floor is one pass over each texture. The copy kernel
//! reads that many bytes from `R32Uint` textures (texture loads) and writes that many into
//! `R32Uint` storage textures, over the frame in 8x8 workgroups like the steps.
//!
//! Files: [`bytes`] (the count), `inputs.rs` (the steps' inputs), `copy_kernel.rs`,
//! `timer.rs` (timestamps or wall time); here the run and its table.

use std::fmt::Write as _;
use std::path::Path;

use crate::wgpu_api::{AdaptivePass, AdaptiveSettings, EstimateInputs, UpdateInputs};
use spvg::SpvgConfig;

use crate::error::ReportError;
use crate::progress::Progress;
use crate::section::Section;
use crate::timing::ms;
use crate::wgpu_api::{GpuDevice, PassError};

pub mod bytes;
mod copy_kernel;
mod inputs;
mod one_pass;
mod timer;

pub use bytes::{
    LINK_FORMAT, MOTION_FORMAT, SCALAR_FORMAT, StepBytes, estimate_bytes, one_pass_bytes,
    update_bytes,
};
use copy_kernel::CopyKernel;
use inputs::Inputs;
use one_pass::ZeroSamples;
use timer::Timer;

/// Frames run before the measured ones by default (shader compilation, first touch).
pub const DEFAULT_WARMUP: u32 = 3;

/// The table's heading (with its blank line), also where the table is not run.
pub const HEADING: &str = "## GPU readiness: the component's steps against a copy kernel\n\n";

/// What the command runs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReadinessOptions {
    /// Frame sizes, `[width, height]`.
    pub sizes: Vec<[u32; 2]>,
    /// Measured frames per size (at least 1).
    pub frames: u32,
    /// Frames run first and not measured (shader compilation, first-touch allocation).
    pub warmup: u32,
    /// Count dilation radius of the component (the report's AS runs use 1).
    pub dilation: u32,
}

impl ReadinessOptions {
    /// The options for a command: the defaults, one `size` and the measured `frames` where
    /// given.
    #[must_use]
    pub fn for_command(size: Option<[u32; 2]>, frames: Option<u32>, warmup: u32) -> Self {
        let mut o = Self {
            warmup,
            ..Self::default()
        };
        if let Some(s) = size {
            o.sizes = vec![s];
        }
        if let Some(f) = frames {
            o.frames = f;
        }
        o
    }

    /// Frames the study renders (for a progress bar): per size the estimate, the update,
    /// the one-pass form and the three copies of every frame.
    #[must_use]
    pub fn frames_to_render(&self) -> u64 {
        self.sizes.len() as u64 * u64::from(self.warmup + self.frames)
    }
}

impl Default for ReadinessOptions {
    /// 1920x1080 and 3840x2160, 20 frames after 3 warm-up frames, dilation radius 1.
    fn default() -> Self {
        Self {
            sizes: vec![[1920, 1080], [3840, 2160]],
            frames: 20,
            warmup: DEFAULT_WARMUP,
            dilation: 1,
        }
    }
}

/// How the times were taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clock {
    /// GPU timestamp queries around each step's compute passes.
    Timestamps,
    /// Wall time from submit to the wait's return on a hardware adapter without
    /// timestamp queries.
    HardwareWallClock,
    /// Wall time from submit to the wait's return on a software adapter: CPU time.
    SoftwareCpuTime,
}

impl Clock {
    /// The clock of `device`: timestamps on a hardware adapter that has them; a software
    /// rasterizer's timestamps are not trusted (see `SssPass::for_device`).
    #[must_use]
    pub fn of(device: &GpuDevice) -> Self {
        if device.is_software() {
            Self::SoftwareCpuTime
        } else if device.timestamps {
            Self::Timestamps
        } else {
            Self::HardwareWallClock
        }
    }

    /// One sentence for the table.
    #[must_use]
    pub fn sentence(&self) -> &'static str {
        match self {
            Self::Timestamps => {
                "GPU timestamp queries bracketing each step's compute passes (GPU time)."
            }
            Self::HardwareWallClock => {
                "wall time from submit to completion, each step submitted alone (the adapter has no timestamp queries; submission overhead included)."
            }
            Self::SoftwareCpuTime => {
                "wall time from submit to completion on a software adapter: the figures are CPU time on this machine, and only the ratio means anything for a GPU."
            }
        }
    }
}

/// Which step a row times.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// The estimate (with the dilation pass when the radius is above 0).
    Estimate,
    /// The update.
    Update,
    /// The one-pass form in a renderer's dispatch that takes no sample.
    OnePass,
}

impl Step {
    /// Its name in the table.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Estimate => "estimate",
            Self::Update => "update",
            Self::OnePass => "one pass, zero samples",
        }
    }
}

/// One table row: a step at a size against its copy kernel (median times, ms).
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Frame size.
    pub size: [u32; 2],
    /// The step.
    pub step: Step,
    /// Its bytes per pixel, which the copy kernel moves too.
    pub bytes: StepBytes,
    /// Median step time (ms).
    pub step_ms: f64,
    /// Median copy-kernel time (ms).
    pub copy_ms: f64,
}

impl Row {
    /// Step time over copy time.
    #[must_use]
    pub fn ratio(&self) -> f64 {
        self.step_ms / self.copy_ms
    }
}

/// The command's result.
#[derive(Clone, Debug, PartialEq)]
pub struct Readiness {
    /// The adapter, in words.
    pub adapter: String,
    /// How the times were taken.
    pub clock: Clock,
    /// Timed samples where the timestamps came back unordered and the wall time stood in.
    pub wall_fallbacks: u32,
    /// What ran.
    pub options: ReadinessOptions,
    /// The rows, per size the estimate then the update.
    pub rows: Vec<Row>,
}

/// Runs the steps and their copy kernels on `device` at each size of `opts`.
///
/// # Errors
///
/// [`ReportError::Usage`] for no frames or a size the device cannot hold (naming it), a
/// component error, or a device failure.
pub fn run(device: &GpuDevice, opts: &ReadinessOptions) -> Result<Readiness, ReportError> {
    if opts.frames == 0 {
        return Err(ReportError::Usage(
            "frames: at least 1 measured frame".into(),
        ));
    }
    let clock = Clock::of(device);
    let mut timer = Timer::new(device, clock == Clock::Timestamps);
    let mut rows = Vec::new();
    for &size in &opts.sizes {
        crate::wgpu_api::check_frame_size(&device.device, size[0], size[1])?;
        rows.extend(run_size(device, &mut timer, size, opts)?);
    }
    Ok(Readiness {
        adapter: format!(
            "{} [{:?}, {:?}]",
            device.info.name, device.info.device_type, device.info.backend
        ),
        clock,
        wall_fallbacks: timer.fallbacks,
        options: opts.clone(),
        rows,
    })
}

fn run_size(
    d: &GpuDevice,
    timer: &mut Timer,
    size: [u32; 2],
    opts: &ReadinessOptions,
) -> Result<[Row; 3], ReportError> {
    let [w, h] = size;
    // The papers' update: with the spatial variance of young histories (the default) the
    // estimate also writes this frame's depth, 4 bytes a pixel the byte count leaves out.
    let config = SpvgConfig::builder()
        .target_variance(1e-4)
        .spatial_variance(0)
        .build()?;
    let settings = AdaptiveSettings {
        config,
        dilation: opts.dilation,
        ..AdaptiveSettings::default()
    };
    let mut pass = AdaptivePass::new(&d.device, settings, w, h).map_err(PassError::from)?;
    let inputs = Inputs::new(d, size);
    let est = estimate_bytes(opts.dilation > 0);
    let upd = update_bytes();
    let est_copy = CopyKernel::new(d, size, est)?;
    let upd_copy = CopyKernel::new(d, size, upd)?;
    // The one-pass form on its own component (the same settings), so that each form
    // continues its own histories.
    let mut one = AdaptivePass::new(&d.device, settings, w, h).map_err(PassError::from)?;
    let zero = ZeroSamples::new(d, &one);
    let one_bytes = one_pass_bytes();
    let one_copy = CopyKernel::new(d, size, one_bytes)?;
    let mut times: [Vec<f64>; 6] = Default::default();
    for f in 0..opts.warmup + opts.frames {
        let e = timer.measure(d, |enc, stamps| {
            let i = EstimateInputs::new(&inputs.motion, &inputs.depth, &inputs.depth);
            pass.record_estimate_timed(enc, &i, stamps)
                .map_err(|e| PassError::from(e).into())
        })?;
        let value = &inputs.value[(f % 2) as usize];
        let u = timer.measure(d, |enc, stamps| {
            let i = UpdateInputs::new(value);
            pass.record_update_timed(enc, &i, stamps)
                .map_err(|e| PassError::from(e).into())
        })?;
        let ce = timer.measure(d, |enc, stamps| {
            est_copy.record(enc, stamps);
            Ok(())
        })?;
        let cu = timer.measure(d, |enc, stamps| {
            upd_copy.record(enc, stamps);
            Ok(())
        })?;
        let o = timer.measure(d, |enc, stamps| {
            let i = EstimateInputs::new(&inputs.motion, &inputs.depth, &inputs.depth);
            zero.record(enc, &mut one, &i, stamps)
        })?;
        let co = timer.measure(d, |enc, stamps| {
            one_copy.record(enc, stamps);
            Ok(())
        })?;
        if f >= opts.warmup {
            for (v, t) in times.iter_mut().zip([e, u, ce, cu, o, co]) {
                v.push(t);
            }
        }
    }
    let [e, u, ce, cu, o, co] = times.map(median);
    Ok([
        Row {
            size,
            step: Step::Estimate,
            bytes: est,
            step_ms: e,
            copy_ms: ce,
        },
        Row {
            size,
            step: Step::Update,
            bytes: upd,
            step_ms: u,
            copy_ms: cu,
        },
        Row {
            size,
            step: Step::OnePass,
            bytes: one_bytes,
            step_ms: o,
            copy_ms: co,
        },
    ])
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// The table's markdown, headed [`HEADING`].
#[must_use]
pub fn markdown(r: &Readiness) -> String {
    let mut s = String::new();
    let o = &r.options;
    let e = estimate_bytes(o.dilation > 0);
    let u = update_bytes();
    s.push_str(HEADING);
    let _ = writeln!(
        s,
        "Adapter: {}. Times: {} The component runs AS with count dilation radius {} and \
         the papers' update (the spatial variance of young histories off: on, the estimate \
         also writes this frame's depth, 4 bytes a pixel); {} measured frames per size (after {} warm-up), each step submitted alone, the \
         median per step. \
         The copy kernel reads from `R32Uint` textures and writes `R32Uint` storage \
         textures, over the frame in 8x8 workgroups, the bytes of the frame-size textures \
         each step binds, per pixel: the estimate {} read + {} written (reads the history \
         `Rgba16Float` 8, motion `Rg32Float` 8, depth and previous depth `R32Float` 4 + 4{}; \
         writes {}), the update {} read + {} written (reads the history 8, the value \
         `R32Float` 4, the count and the link `R32Uint` 4 + 4; writes the other history 8), \
         the one-pass form {} read + {} written (what the component adds to a renderer's \
         dispatch that takes no sample: the history, motion and depths read, the other \
         history written; the counts not stored). \
         Ratio = step / copy: how far the step is from moving its bytes alone.\n",
        r.adapter,
        r.clock.sentence(),
        o.dilation,
        o.frames,
        o.warmup,
        e.read,
        e.written,
        if o.dilation > 0 {
            ", the count before dilation `R32Uint` 4"
        } else {
            ""
        },
        if o.dilation > 0 {
            "the count before dilation, the link and the dilated count `R32Uint` 4 + 4 + 4"
        } else {
            "the count and the link `R32Uint` 4 + 4"
        },
        u.read,
        u.written,
        one_pass_bytes().read,
        one_pass_bytes().written,
    );
    if r.wall_fallbacks > 0 {
        let _ = writeln!(
            s,
            "{} timed samples came back with unordered timestamps; their wall time stands \
             in.\n",
            r.wall_fallbacks
        );
    }
    let _ = writeln!(
        s,
        "| size | step | bytes/pixel | step (ms) | copy (ms) | ratio (step / copy) |"
    );
    let _ = writeln!(s, "| --- | --- | --- | --- | --- | --- |");
    for row in &r.rows {
        let [w, h] = row.size;
        let _ = writeln!(
            s,
            "| {w}x{h} | {} | {} | {} | {} | {:.2} |",
            row.step.name(),
            row.bytes.total(),
            ms(row.step_ms),
            ms(row.copy_ms),
            row.ratio()
        );
    }
    s
}

/// Runs the table on `device` at `opts`, writes `gpu_readiness.md` into `dir` and returns
/// the section (no acceptance lines: a timing study). Without a device the section says
/// so: the CPU twin has no passes to time.
///
/// # Errors
///
/// As [`run`], or a file that cannot be written (naming it).
pub fn write(
    dir: &Path,
    device: Option<&GpuDevice>,
    opts: &ReadinessOptions,
    progress: &Progress,
) -> Result<Section, ReportError> {
    let md = match device {
        Some(d) => {
            progress.stage("gpu-readiness: the component's steps against a copy kernel");
            let md = markdown(&run(d, opts)?);
            progress.inc(opts.frames_to_render());
            md
        }
        None => format!("{HEADING}Not run: no wgpu device (the CPU twin has no passes to time).\n"),
    };
    std::fs::create_dir_all(dir).map_err(|e| ReportError::io(dir, e))?;
    let path = dir.join("gpu_readiness.md");
    std::fs::write(&path, &md).map_err(|e| ReportError::io(&path, e))?;
    Ok(Section {
        name: "gpu-readiness",
        markdown: md,
        groups: Vec::new(),
    })
}

//! What the report's pass times mean on the backend that measured them.

use crate::wgpu_api::Backend;

/// How pass times were measured.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Timing {
    /// GPU timestamp queries on a hardware adapter: GPU time of the frame's passes.
    HardwareTimestamps,
    /// A hardware adapter without timestamp queries: wall time from submit to completion.
    HardwareWallClock,
    /// A software rasterizer (e.g. lavapipe): its "GPU" is the CPU.
    SoftwareRasterizer,
    /// The CPU twin.
    CpuTwin,
}

impl Timing {
    /// The timing of `backend`.
    #[must_use]
    pub fn of(backend: &Backend) -> Self {
        match backend {
            Backend::Cpu => Self::CpuTwin,
            Backend::Gpu(d) if d.is_software() => Self::SoftwareRasterizer,
            Backend::Gpu(d) if d.timestamps => Self::HardwareTimestamps,
            Backend::Gpu(_) => Self::HardwareWallClock,
        }
    }

    /// Whether the times are CPU time (software rasterizer or CPU twin).
    #[must_use]
    pub fn is_cpu_time(&self) -> bool {
        matches!(self, Self::SoftwareRasterizer | Self::CpuTwin)
    }

    /// Short name for chart axes.
    #[must_use]
    pub fn short(&self) -> &'static str {
        match self {
            Self::HardwareTimestamps => "GPU timestamps",
            Self::HardwareWallClock => "GPU, wall clock",
            Self::SoftwareRasterizer => "CPU time: software rasterizer",
            Self::CpuTwin => "CPU time: CPU twin",
        }
    }

    /// One sentence for the report.
    #[must_use]
    pub fn sentence(&self) -> &'static str {
        match self {
            Self::HardwareTimestamps => {
                "pass times are GPU timestamp queries on a hardware adapter (GPU time from the start of the frame's first pass to the end of its last: for the adaptive models the distant ratio, the component's estimate, the sampling and the component's update)."
            }
            Self::HardwareWallClock => {
                "pass times are wall time from submit to completion on a hardware adapter without timestamp queries (they include submission overhead)."
            }
            Self::SoftwareRasterizer => {
                "pass times are wall time from submit to completion on a software rasterizer (its timestamp queries do not bracket the work of the adaptive models' four passes), so they are CPU time on this machine: only ratios between runs mean anything, not the milliseconds."
            }
            Self::CpuTwin => {
                "pass times are CPU wall time of the CPU twin: only ratios between runs mean anything, not the milliseconds."
            }
        }
    }
}

/// A time in ms for tables: three decimals, or `n/a` when not measured (NaN).
#[must_use]
pub fn ms(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.3}")
    } else {
        "n/a".to_owned()
    }
}

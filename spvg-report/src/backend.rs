//! Which implementation runs the passes: the `--backend` choice resolved once for every
//! section, with the reason for the CPU twin when it is the one that runs. A device that
//! exists but fails is an error that names its cause; the twin never stands in for it.

use crate::error::ReportError;
use crate::wgpu_api::{Backend, GpuDevice, PassError, acquire_device, block_on};

/// `--backend`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Choice {
    /// A wgpu adapter (hardware first, then software Vulkan); the CPU twin only when no
    /// adapter exists.
    Auto,
    /// A wgpu adapter; an error without one.
    Gpu,
    /// The multi-threaded CPU twin.
    Cpu,
}

/// The backend every section of a command runs on.
#[derive(Debug)]
pub struct Resolved {
    /// The backend.
    pub backend: Backend,
    /// One line naming it, and for the CPU twin why it runs.
    pub description: String,
}

impl Resolved {
    /// The wgpu device (`None` on the CPU twin).
    #[must_use]
    pub fn device(&self) -> Option<&GpuDevice> {
        match &self.backend {
            Backend::Gpu(d) => Some(d),
            Backend::Cpu => None,
        }
    }
}

/// Resolves `choice` with `acquire` (the device acquisition; [`resolve`] passes
/// `spvg-wgpu`'s): `auto` takes the CPU twin only when `acquire` finds no adapter at all,
/// and says so; an adapter that refuses its device is an error naming the cause with either
/// choice.
///
/// # Errors
///
/// [`ReportError::Device`] naming `--backend` and the cause.
pub fn resolve_with(
    choice: Choice,
    acquire: impl FnOnce() -> Result<GpuDevice, PassError>,
) -> Result<Resolved, ReportError> {
    let gpu = |d: GpuDevice| Resolved {
        description: Backend::Gpu(Box::new(d.clone())).describe(),
        backend: Backend::Gpu(Box::new(d)),
    };
    let cpu = |why: String| Resolved {
        description: format!("{} ({why})", Backend::Cpu.describe()),
        backend: Backend::Cpu,
    };
    match choice {
        Choice::Cpu => Ok(cpu("--backend cpu".into())),
        Choice::Gpu => acquire()
            .map(gpu)
            .map_err(|e| ReportError::Device(format!("--backend gpu: {e}"))),
        Choice::Auto => match acquire() {
            Ok(d) => Ok(gpu(d)),
            Err(PassError::NoAdapter(why)) => Ok(cpu(format!("--backend auto: {why}"))),
            Err(e) => Err(ReportError::Device(format!(
                "--backend auto: {e} (a wgpu adapter exists but its device failed; \
                 --backend cpu runs the CPU twin instead)"
            ))),
        },
    }
}

/// [`resolve_with`] with `spvg-wgpu`'s device acquisition.
///
/// # Errors
///
/// As [`resolve_with`].
pub fn resolve(choice: Choice) -> Result<Resolved, ReportError> {
    resolve_with(choice, acquire)
}

/// `spvg-wgpu`'s device acquisition, with "no adapter" told apart from "the adapter
/// refused its device": the component reports both as one device error, and only the
/// first lets `auto` run the twin.
fn acquire() -> Result<GpuDevice, PassError> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    if block_on(instance.enumerate_adapters(wgpu::Backends::all())).is_empty() {
        return Err(PassError::NoAdapter(
            "no wgpu adapter found (install a GPU driver, or Mesa's software Vulkan: \
             mesa-vulkan-drivers)"
                .into(),
        ));
    }
    acquire_device().map_err(|e| PassError::RequestDevice(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_takes_the_twin_only_without_an_adapter_and_says_why() {
        let none = || Err(PassError::NoAdapter("no wgpu adapter found".into()));
        let r = resolve_with(Choice::Auto, none).expect("no adapter: the twin");
        assert!(matches!(r.backend, Backend::Cpu), "{}", r.description);
        assert!(
            r.description.contains("no wgpu adapter found"),
            "{}",
            r.description
        );
        let refused = || Err(PassError::RequestDevice("out of memory".into()));
        let e = resolve_with(Choice::Auto, refused).expect_err("a failed device is an error");
        let msg = e.to_string();
        assert!(
            msg.contains("--backend auto") && msg.contains("out of memory"),
            "{msg}"
        );
        let e = resolve_with(Choice::Gpu, none).expect_err("gpu needs an adapter");
        assert!(e.to_string().contains("--backend gpu"), "{e}");
        let r = resolve_with(Choice::Cpu, || panic!("cpu must not acquire"))
            .expect("cpu needs nothing");
        assert!(r.description.contains("--backend cpu"), "{}", r.description);
    }
}

//! # spvg-gpu-test: how every GPU test of the workspace gets its device
//!
//! A GPU test declares what it needs ([`GpuTest`]: its name, the device features) and asks
//! for a device. Where no adapter exists it is skipped with the reason printed, and
//! with `SPVG_REQUIRE_GPU=1` (CI sets it after installing Mesa's software Vulkan) the
//! missing adapter fails the test instead, so a machine without Vulkan cannot go green
//! without running the GPU tests. Where the adapter lacks a feature the test needs, the
//! test is skipped with that reason, whatever the environment says: the test cannot run
//! there, and saying so is the honest outcome.
//!
//! ```no_run
//! use spvg_gpu_test::GpuTest;
//!
//! let Some(dev) = GpuTest::new("my_pass_matches_its_twin").device() else {
//!     return;
//! };
//! // ... record passes on dev.device, submit on dev.queue ...
//! # let _ = dev;
//! ```

pub use spvg_wgpu::util::GpuDevice;

/// The environment variable that turns a missing adapter into a failure.
pub const REQUIRE_GPU: &str = "SPVG_REQUIRE_GPU";

/// What a GPU test needs of its device.
#[derive(Clone, Debug)]
pub struct GpuTest {
    name: String,
    features: wgpu::Features,
    /// The limits to request instead of the adapter's own.
    limits: Option<wgpu::Limits>,
}

/// Why a test gets no device.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Skip {
    /// No wgpu adapter, or it refused the device (the message says which).
    NoAdapter(String),
    /// The adapter lacks features the test needs.
    MissingFeatures(wgpu::Features),
}

impl GpuTest {
    /// A test named `name` (printed with the adapter it runs on, or why it was skipped)
    /// that needs a device of any adapter.
    #[must_use]
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            features: wgpu::Features::empty(),
            limits: None,
        }
    }

    /// Runs on a device requested with `limits` instead of the adapter's own
    /// (`wgpu::Limits::default()`: WebGPU's defaults, what a browser grants), so that the
    /// test fails where its passes need more than that.
    #[must_use]
    pub fn limits(mut self, limits: wgpu::Limits) -> Self {
        self.limits = Some(limits);
        self
    }

    /// Also needs `features` (timestamp queries, say).
    #[must_use]
    pub fn features(mut self, features: wgpu::Features) -> Self {
        self.features |= features;
        self
    }

    /// The device, or why there is none ([`device`](Self::device) decides what to do with
    /// the reason).
    ///
    /// # Errors
    ///
    /// The [`Skip`] reason.
    pub fn try_device(&self) -> Result<GpuDevice, Skip> {
        let dev = match &self.limits {
            Some(l) => spvg_wgpu::util::acquire_device_with_limits(l.clone()),
            None => spvg_wgpu::util::acquire_device(),
        }
        .map_err(|e| Skip::NoAdapter(e.to_string()))?;
        let missing = self.features - dev.device.features();
        if missing.is_empty() {
            Ok(dev)
        } else {
            Err(Skip::MissingFeatures(missing))
        }
    }

    /// The device for this test, printing the adapter; `None` after printing why the test
    /// is skipped.
    ///
    /// # Panics
    ///
    /// With `SPVG_REQUIRE_GPU=1` and no adapter, naming the test and the reason.
    #[must_use]
    pub fn device(&self) -> Option<GpuDevice> {
        let found = self.try_device();
        self.outcome(found.as_ref())?;
        found.ok()
    }

    /// What [`device`](Self::device) does with an acquisition's result, for a test suite
    /// that acquires one device and shares it ([`try_device`](Self::try_device) once,
    /// this in every test): prints the adapter and returns it, or prints why the test is
    /// skipped and returns `None`.
    ///
    /// # Panics
    ///
    /// With `SPVG_REQUIRE_GPU=1` and no adapter, naming the test and the reason.
    #[must_use]
    pub fn outcome<'a>(&self, found: Result<&'a GpuDevice, &Skip>) -> Option<&'a GpuDevice> {
        let name = &self.name;
        match found {
            Ok(d) => {
                eprintln!("{name}: running on {}", d.describe());
                Some(d)
            }
            Err(Skip::NoAdapter(e)) if gpu_required() => {
                panic!("{name}: {REQUIRE_GPU}=1 but there is no wgpu device: {e}")
            }
            Err(Skip::NoAdapter(e)) => {
                eprintln!(
                    "{name}: SKIPPED, no wgpu device ({e}); set {REQUIRE_GPU}=1 to make this a \
                     failure"
                );
                None
            }
            Err(Skip::MissingFeatures(f)) => {
                eprintln!("{name}: SKIPPED, the adapter lacks {f:?}");
                None
            }
        }
    }
}

/// Whether `SPVG_REQUIRE_GPU=1` is set.
#[must_use]
pub fn gpu_required() -> bool {
    std::env::var(REQUIRE_GPU).is_ok_and(|v| v == "1")
}

//! The page's renderer on a wgpu device, driven asynchronously: per frame the G-buffer,
//! the adaptive component's estimate (or a fixed count), the AO samples, the component's
//! update, a TAA resolve and the three panels the page shows, recorded into one encoder;
//! then the readbacks the caller asks for, awaited ([`spvg_wgpu::util::read_texture_async`])
//! rather than blocked on, so the same code runs in a browser and in native tests.

use half::f16;
use spvg_effects::ao::{AoParams, ao_source};
use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveSettings, EstimateInputs, UpdateInputs,
};
use spvg_wgpu::util::{
    bind_group, compute_pipeline, dispatch_8x8, read_buffer_async, read_texture_async,
    shader_module, texture_2d, view,
};
use wgpu::{TextureFormat as Tf, TextureUsages as Tu};

use crate::clock::now_ms;

/// The page's passes (`src/web.wgsl`), joined after the AO effect's module.
pub const WEB_WGSL: &str = include_str!("web.wgsl");

/// The whole module the renderer compiles: the AO effect's ([`ao_source`]) and the page's.
#[must_use]
pub fn shader_source() -> String {
    let mut s = ao_source();
    s.push_str("// ---- spvg-web src/web.wgsl\n");
    s.push_str(WEB_WGSL);
    s
}

/// The uniform block of `src/web.wgsl`.
///
/// WGSL twin: `struct WebParams` in `src/web.wgsl`; same field order and types.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct WebParams {
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// 1 where the TAA has a history to blend.
    pub taa_history: u32,
    /// Reference passes accumulated so far.
    pub reference_passes: u32,
    /// Rays per pixel of one reference pass.
    pub reference_rays: u32,
    /// 1 where the reference is of the view on screen.
    pub has_reference: u32,
    /// The weight of this frame in the TAA blend.
    pub taa_alpha: f32,
    /// The count the heat map shows as its hottest colour.
    pub count_scale: f32,
    /// The error panel's gain.
    pub error_gain: f32,
    /// Padding (0).
    pub pad: [u32; 3],
}

const _: () = assert!(
    size_of::<WebParams>() == 48,
    "WebParams must match the 48-byte WGSL struct"
);

/// The weight of a new frame in the TAA blend (the history keeps the rest).
pub const TAA_ALPHA: f32 = 0.1;

/// The error panel shows an absolute error of `1 / ERROR_GAIN` (in AO, 0..1) as its
/// hottest colour.
pub const ERROR_GAIN: f32 = 8.0;

/// Rays per pixel of one reference pass ([`Renderer::converge_reference`]).
pub const REFERENCE_RAYS: u32 = 64;

/// Frame seeds of the reference passes start here, far from any frame index a run
/// reaches, so the reference's samples are not those of a frame it is compared with.
const REFERENCE_SEED: u32 = 1 << 24;

/// The page's default target variance `sigma0^2`. AO is in 0..1 and its rays are
/// binary: a pixel whose rays split evenly has a variance of 0.25 per ray and asks for the
/// budget's maximum, open ground (every ray escapes) for its minimum. Measured on the
/// page's home view at 320x200 (24 frames from a reset, after TAA, against fixed 8..64 on
/// lavapipe), 5e-4 with the budget [1, 64] reached the PSNR of fixed 27 spp at 17.5 spp,
/// the best of the eight settings tried (BENCHMARKS.md lists them).
pub const TARGET_VARIANCE: f32 = 5e-4;

/// The page's default budget `[beta_min, beta_max]`.
pub const BUDGET: [u32; 2] = [1, 64];

/// The page's largest budget maximum, below the core's [`spvg::controller::MAX_BUDGET`]:
/// at 1024 a frame took about 12 s on a software adapter (SwiftShader), and a frame the
/// page waits for that long is a frozen page. 256 keeps a SwiftShader frame near 3 s.
pub const PAGE_MAX_BUDGET: u32 = 256;

/// The component's settings the page runs: AS with `target_variance` and `budget`, count
/// dilation radius 1 (occlusion is a rare event at an occluder's rim; docs/algorithms.md
/// §2.5), the rest the component's defaults.
///
/// # Errors
///
/// [`spvg::Error`] naming the bad parameter (a target variance that is not positive and
/// finite, a budget with `min > max` or a zero, a maximum above [`PAGE_MAX_BUDGET`]).
pub fn page_settings(
    target_variance: f32,
    [min, max]: [u32; 2],
) -> Result<AdaptiveSettings, spvg::Error> {
    if max > PAGE_MAX_BUDGET {
        return Err(spvg::Error::InvalidParameter {
            name: "max_samples",
            value: f64::from(max),
            expected: "must be at most the page's maximum, 256",
        });
    }
    Ok(AdaptiveSettings {
        config: spvg::SpvgConfig::builder()
            .target_variance(target_variance)
            .budget(min, max)
            .build()?,
        dilation: 1,
        ..AdaptiveSettings::default()
    })
}

/// How the renderer chooses its counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// The same count everywhere.
    Fixed(u32),
    /// The adaptive component (AS) with reprojection along the G-buffer's motion vectors.
    Adaptive,
}

/// Which results of a frame [`Renderer::render`] reads back (the counts always).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Reads {
    /// The three panels as RGBA8 (`3 width x height`).
    pub image: bool,
    /// The resolved AO after TAA.
    pub taa: bool,
    /// What the twin check compares: the G-buffer, the AO values and the history.
    pub twin: bool,
}

/// What the twin check compares of one GPU frame ([`crate::check::TwinCheck`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TwinReadback {
    /// Linear depth per pixel.
    pub depth: Vec<f32>,
    /// Motion vectors (pixels, current minus previous).
    pub motion: Vec<[f32; 2]>,
    /// The reprojected depth.
    pub reprojected_depth: Vec<f32>,
    /// The AO estimate per pixel (the component's monitored value).
    pub value: Vec<f32>,
    /// The component's history after the update (`spvg::texel::SpvgTexel16`).
    pub history: Vec<[f16; 4]>,
}

/// One rendered frame, read back.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frame {
    /// Samples per pixel.
    pub count: Vec<u32>,
    /// The three panels ([`Reads::image`]), empty otherwise.
    pub image: Vec<u8>,
    /// The AO after TAA ([`Reads::taa`]), empty otherwise.
    pub taa: Vec<f32>,
    /// What the twin check compares ([`Reads::twin`]).
    pub twin: Option<TwinReadback>,
    /// CPU wall time in milliseconds from the frame's recording to the completion of its
    /// first readback (the counts' copy, a few bytes per pixel, included).
    pub wall_ms: f64,
    /// The time between the frame's first pass's start and its last pass's end, in
    /// milliseconds, from timestamp queries where the device has them. On a software
    /// adapter (SwiftShader, lavapipe) this is CPU time too.
    pub gpu_ms: Option<f64>,
}

impl Frame {
    /// Mean samples per pixel.
    #[must_use]
    pub fn mean_spp(&self) -> f64 {
        crate::metrics::mean(self.count.iter().map(|&n| f64::from(n)))
    }
}

/// The page's compute pipelines, each with the layout its entry point's bindings give.
#[derive(Debug)]
struct Pipelines {
    gbuffer: wgpu::ComputePipeline,
    sample: wgpu::ComputePipeline,
    taa: wgpu::ComputePipeline,
    reference: wgpu::ComputePipeline,
    compose: wgpu::ComputePipeline,
}

/// Timestamp queries around a frame's passes.
#[derive(Debug)]
struct Timer {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    read: wgpu::Buffer,
    period_ns: f64,
}

/// The reference the renderer holds: the view it was converged for.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ReferenceView {
    camera: [f32; 4],
    lens: [f32; 4],
    mover: [f32; 4],
}

impl ReferenceView {
    fn of(p: &AoParams) -> Self {
        Self {
            camera: p.camera,
            lens: p.lens,
            mover: p.mover,
        }
    }
}

/// The page's renderer: the AO effect's scene through the adaptive component (or a
/// fixed count), a TAA resolve, a converged reference and the panels the page shows.
#[derive(Debug)]
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    size: [u32; 2],
    mode: Mode,
    adaptive: AdaptivePass,
    /// The count texture of [`Mode::Fixed`].
    fixed: wgpu::Texture,
    pipelines: Pipelines,
    ao_uniform: wgpu::Buffer,
    web_uniform: wgpu::Buffer,
    /// Ping-pong: this frame's and the previous frame's depth.
    depth: [wgpu::Texture; 2],
    motion: wgpu::Texture,
    reprojected_depth: wgpu::Texture,
    value: wgpu::Texture,
    /// Ping-pong TAA histories.
    taa: [wgpu::Texture; 2],
    /// Ping-pong running means of the reference passes.
    reference: [wgpu::Texture; 2],
    image: wgpu::Texture,
    /// Index of this frame's depth (and of the TAA history this frame writes).
    cur: usize,
    taa_history: bool,
    /// The view the reference was converged for, and its texture's index.
    reference_view: Option<(ReferenceView, usize)>,
    timer: Option<Timer>,
}

impl Renderer {
    /// Builds the renderer for a `width x height` frame on `device` (any limits from
    /// WebGPU's defaults up; timestamp queries are used where the device has
    /// `TIMESTAMP_QUERY`), starting in `mode`, the component running `settings`.
    ///
    /// # Errors
    ///
    /// As [`AdaptivePass::new`] (a bad setting or frame size).
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        [width, height]: [u32; 2],
        mode: Mode,
        settings: AdaptiveSettings,
    ) -> Result<Self, AdaptiveError> {
        let size = [width, height];
        let adaptive = AdaptivePass::new(device, settings, width, height)?;
        let module = shader_module(device, "spvg-web", shader_source());
        let pipeline = |entry: &str| compute_pipeline(device, &module, entry, None);
        let pipelines = Pipelines {
            gbuffer: pipeline("web_gbuffer"),
            sample: pipeline("web_sample"),
            taa: pipeline("web_taa"),
            reference: pipeline("web_reference"),
            compose: pipeline("web_compose"),
        };
        let rw = Tu::STORAGE_BINDING | Tu::TEXTURE_BINDING | Tu::COPY_SRC;
        let tex = |label, format| texture_2d(device, label, format, size, rw);
        let uniform = |label, bytes: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let timer = device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| Timer {
                set: device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("spvg-web frame"),
                    ty: wgpu::QueryType::Timestamp,
                    count: 2,
                }),
                resolve: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("spvg-web timestamps"),
                    size: 16,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
                read: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("spvg-web timestamps read"),
                    size: 16,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                period_ns: f64::from(queue.get_timestamp_period()),
            });
        let mut r = Self {
            device: device.clone(),
            queue: queue.clone(),
            size,
            mode,
            adaptive,
            fixed: texture_2d(
                device,
                "spvg-web fixed count",
                AdaptivePass::COUNT_FORMAT,
                size,
                Tu::TEXTURE_BINDING | Tu::COPY_DST | Tu::COPY_SRC,
            ),
            pipelines,
            ao_uniform: uniform("AoParams", size_of::<AoParams>() as u64),
            web_uniform: uniform("WebParams", size_of::<WebParams>() as u64),
            depth: [tex("depth a", Tf::R32Float), tex("depth b", Tf::R32Float)],
            motion: tex("motion", Tf::Rg32Float),
            reprojected_depth: tex("reprojected depth", Tf::R32Float),
            value: tex("ao value", Tf::R32Float),
            taa: [tex("taa a", Tf::R32Float), tex("taa b", Tf::R32Float)],
            // COPY_DST: a reference converged elsewhere is written in (`set_reference`).
            reference: ["reference a", "reference b"]
                .map(|l| texture_2d(device, l, Tf::R32Float, size, rw | Tu::COPY_DST)),
            image: texture_2d(
                device,
                "spvg-web panels",
                Tf::Rgba8Unorm,
                [3 * width, height],
                rw,
            ),
            cur: 0,
            taa_history: false,
            reference_view: None,
            timer,
        };
        r.set_mode(mode);
        Ok(r)
    }

    /// Frame size `[width, height]`.
    #[must_use]
    pub fn size(&self) -> [u32; 2] {
        self.size
    }

    /// The counts' rule.
    #[must_use]
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The component's settings.
    #[must_use]
    pub fn settings(&self) -> &AdaptiveSettings {
        self.adaptive.settings()
    }

    /// Whether frame times come from timestamp queries.
    #[must_use]
    pub fn has_timestamps(&self) -> bool {
        self.timer.is_some()
    }

    /// Switches the counts' rule. Entering [`Mode::Adaptive`] from a fixed count starts
    /// the component's histories over (the frames in between did not update them).
    pub fn set_mode(&mut self, mode: Mode) {
        if let Mode::Fixed(n) = mode {
            let pixels = (self.size[0] * self.size[1]) as usize;
            write_u32(&self.queue, &self.fixed, &vec![n; pixels], self.size);
        } else if self.mode != Mode::Adaptive {
            self.adaptive.reset_history();
        }
        self.mode = mode;
    }

    /// Hands the component new settings between frames ([`AdaptivePass::set_settings`]).
    ///
    /// # Errors
    ///
    /// As [`AdaptivePass::set_settings`]; the settings stay as they were.
    pub fn set_settings(&mut self, settings: AdaptiveSettings) -> Result<(), AdaptiveError> {
        self.adaptive.set_settings(settings)
    }

    /// Starts the component's histories and the TAA over (a camera cut).
    pub fn reset(&mut self) {
        self.adaptive.reset_history();
        self.taa_history = false;
    }

    /// The uniform block of the page's passes for a frame of `params`.
    fn web_params(&self, params: &AoParams, reference_passes: u32) -> WebParams {
        let config = &self.adaptive.settings().config;
        let count_scale = match self.mode {
            Mode::Fixed(n) => n.max(config.max_samples()),
            Mode::Adaptive => config.max_samples(),
        };
        let has_reference = self
            .reference_view
            .is_some_and(|(v, _)| v == ReferenceView::of(params));
        WebParams {
            width: self.size[0],
            height: self.size[1],
            taa_history: u32::from(self.taa_history),
            reference_passes,
            reference_rays: REFERENCE_RAYS,
            has_reference: u32::from(has_reference),
            taa_alpha: TAA_ALPHA,
            count_scale: count_scale as f32,
            error_gain: ERROR_GAIN,
            pad: [0; 3],
        }
    }

    /// The bind group of `pipeline`: the uniform blocks its entry point reads (`AO`: the
    /// effect's at binding 0, `WEB`: the page's at 11) and `textures` at their bindings.
    fn bind(
        &self,
        pipeline: &wgpu::ComputePipeline,
        uniforms: Uniforms,
        textures: &[(u32, &wgpu::Texture)],
    ) -> wgpu::BindGroup {
        let views: Vec<(u32, wgpu::TextureView)> =
            textures.iter().map(|&(b, t)| (b, view(t))).collect();
        let mut buffers = Vec::new();
        if uniforms.ao {
            buffers.push((0, &self.ao_uniform));
        }
        if uniforms.web {
            buffers.push((11, &self.web_uniform));
        }
        let layout = pipeline.get_bind_group_layout(0);
        bind_group(&self.device, None, &layout, &buffers, &views)
    }

    /// Renders one frame of `params` (the frame size is the renderer's) and reads back the
    /// counts and what `reads` asks for.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::Device`] when a readback fails.
    pub async fn render(
        &mut self,
        params: &AoParams,
        reads: Reads,
    ) -> Result<Frame, AdaptiveError> {
        let start = now_ms();
        let mut p = *params;
        [p.width, p.height] = self.size;
        self.queue
            .write_buffer(&self.ao_uniform, 0, bytemuck::bytes_of(&p));
        let web = self.web_params(&p, 0);
        self.queue
            .write_buffer(&self.web_uniform, 0, bytemuck::bytes_of(&web));
        let (cur, prev) = (self.cur, 1 - self.cur);
        let reference = self.reference_view.map_or(0, |(_, k)| k);
        let mut encoder = self.device.create_command_encoder(&Default::default());
        let gbuffer = self.bind(
            &self.pipelines.gbuffer,
            AO,
            &[
                (1, &self.depth[cur]),
                (2, &self.motion),
                (9, &self.reprojected_depth),
            ],
        );
        let stamp = |index| {
            self.timer
                .as_ref()
                .map(|t| wgpu::ComputePassTimestampWrites {
                    query_set: &t.set,
                    beginning_of_pass_write_index: (index == 0).then_some(0),
                    end_of_pass_write_index: (index == 1).then_some(1),
                })
        };
        dispatch_8x8(
            &mut encoder,
            "web_gbuffer",
            &self.pipelines.gbuffer,
            &gbuffer,
            stamp(0),
            self.size,
        );
        let adaptive = self.mode == Mode::Adaptive;
        if adaptive {
            self.adaptive.record_estimate(
                &mut encoder,
                &EstimateInputs::new(&self.motion, &self.depth[cur], &self.depth[prev])
                    .with_reprojected_depth(Some(&self.reprojected_depth)),
            )?;
        }
        let count = if adaptive {
            self.adaptive.count_texture().clone()
        } else {
            self.fixed.clone()
        };
        let sample = self.bind(&self.pipelines.sample, AO, &[(5, &count), (8, &self.value)]);
        dispatch_8x8(
            &mut encoder,
            "web_sample",
            &self.pipelines.sample,
            &sample,
            None,
            self.size,
        );
        if adaptive {
            self.adaptive
                .record_update(&mut encoder, &UpdateInputs::new(&self.value))?;
        }
        let taa = self.bind(
            &self.pipelines.taa,
            WEB,
            &[
                (12, &self.value),
                (13, &self.motion),
                (14, &self.taa[prev]),
                (15, &self.taa[cur]),
            ],
        );
        dispatch_8x8(
            &mut encoder,
            "web_taa",
            &self.pipelines.taa,
            &taa,
            None,
            self.size,
        );
        let compose = self.bind(
            &self.pipelines.compose,
            BOTH,
            &[
                (5, &count),
                (14, &self.taa[cur]),
                (16, &self.reference[reference]),
                (18, &self.image),
            ],
        );
        dispatch_8x8(
            &mut encoder,
            "web_compose",
            &self.pipelines.compose,
            &compose,
            stamp(1),
            [3 * self.size[0], self.size[1]],
        );
        if let Some(t) = &self.timer {
            encoder.resolve_query_set(&t.set, 0..2, &t.resolve, 0);
            encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.read, 0, 16);
        }
        self.queue.submit([encoder.finish()]);
        // The next frame reads this one's depth and TAA output as its previous ones.
        self.cur = prev;
        self.taa_history = true;

        let (device, queue) = (&self.device, &self.queue);
        let count: Vec<u32> = read_texture_async(device, queue, &count).await?;
        let wall_ms = now_ms() - start;
        let gpu_ms = match &self.timer {
            Some(t) => {
                let ticks: Vec<u64> = read_buffer_async(device, &t.read, 16).await?;
                match ticks[..] {
                    [begin, end] => Some(end.saturating_sub(begin) as f64 * t.period_ns * 1e-6),
                    _ => None,
                }
            }
            None => None,
        };
        let image = if reads.image {
            read_texture_async::<[u8; 4]>(device, queue, &self.image)
                .await?
                .into_flattened()
        } else {
            Vec::new()
        };
        let taa = if reads.taa {
            read_texture_async(device, queue, &self.taa[cur]).await?
        } else {
            Vec::new()
        };
        let twin = if reads.twin {
            Some(TwinReadback {
                depth: read_texture_async(device, queue, &self.depth[cur]).await?,
                motion: read_texture_async(device, queue, &self.motion).await?,
                reprojected_depth: read_texture_async(device, queue, &self.reprojected_depth)
                    .await?,
                value: read_texture_async(device, queue, &self.value).await?,
                history: read_texture_async(device, queue, self.adaptive.history_texture()).await?,
            })
        } else {
            None
        };
        Ok(Frame {
            count,
            image,
            taa,
            twin,
            wall_ms,
            gpu_ms,
        })
    }

    /// Converges a reference for the view of `params`: `passes` passes (at least one) of
    /// [`REFERENCE_RAYS`] rays per pixel, each with a frame seed of its own, averaged;
    /// returns it per pixel. The error panel shows the TAA output against it while the
    /// view (camera, lens, floating sphere) is the one it was made for.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::Device`] when the readback fails.
    pub async fn converge_reference(
        &mut self,
        params: &AoParams,
        passes: u32,
    ) -> Result<Vec<f32>, AdaptiveError> {
        let mut p = *params;
        [p.width, p.height] = self.size;
        let passes = passes.max(1);
        for k in 0..passes {
            p.frame = REFERENCE_SEED + k;
            self.queue
                .write_buffer(&self.ao_uniform, 0, bytemuck::bytes_of(&p));
            let web = self.web_params(&p, k);
            self.queue
                .write_buffer(&self.web_uniform, 0, bytemuck::bytes_of(&web));
            let (read, write) = ((k % 2) as usize, ((k + 1) % 2) as usize);
            let group = self.bind(
                &self.pipelines.reference,
                BOTH,
                &[(16, &self.reference[read]), (17, &self.reference[write])],
            );
            let mut encoder = self.device.create_command_encoder(&Default::default());
            dispatch_8x8(
                &mut encoder,
                "web_reference",
                &self.pipelines.reference,
                &group,
                None,
                self.size,
            );
            self.queue.submit([encoder.finish()]);
        }
        let last = (passes % 2) as usize;
        self.reference_view = Some((ReferenceView::of(&p), last));
        read_texture_async(&self.device, &self.queue, &self.reference[last]).await
    }

    /// Hands the renderer a reference that another renderer of the same size converged
    /// for the view of `params` ([`Renderer::converge_reference`]'s result), so that a
    /// second renderer of the same view (the page's fixed side) shows its error panel
    /// without converging the reference again. A reference of another size is ignored
    /// (the error panel then stays dark, as without a reference).
    pub fn set_reference(&mut self, params: &AoParams, reference: &[f32]) {
        let pixels = (self.size[0] * self.size[1]) as usize;
        if reference.len() != pixels {
            return;
        }
        let bits: Vec<u32> = reference.iter().map(|v| v.to_bits()).collect();
        write_u32(&self.queue, &self.reference[0], &bits, self.size);
        let mut p = *params;
        [p.width, p.height] = self.size;
        self.reference_view = Some((ReferenceView::of(&p), 0));
    }
}

/// Which uniform blocks an entry point of `src/web.wgsl` reads.
#[derive(Clone, Copy, Debug)]
struct Uniforms {
    /// The effect's `AoParams` (binding 0).
    ao: bool,
    /// The page's `WebParams` (binding 11).
    web: bool,
}

const AO: Uniforms = Uniforms {
    ao: true,
    web: false,
};
const WEB: Uniforms = Uniforms {
    ao: false,
    web: true,
};
const BOTH: Uniforms = Uniforms {
    ao: true,
    web: true,
};

/// Writes `data`, one `u32` per texel, to the whole of `texture`.
fn write_u32(queue: &wgpu::Queue, texture: &wgpu::Texture, data: &[u32], [w, h]: [u32; 2]) {
    queue.write_texture(
        texture.as_image_copy(),
        bytemuck::cast_slice(data),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * w),
            rows_per_image: Some(h),
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
}

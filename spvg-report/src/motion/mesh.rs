//! The mesh scene ([`crate::mesh`]) in the motion section: the scanned mesh under an
//! orbiting, jittered camera, run as the other scenes are (`run::run_frames`:
//! the ladder, `as` and `as-resolved`, scored single-frame and after the report's TAA)
//! against its own references ([`crate::mesh::ao::reference`]).
//!
//! Its renderer: the component decides each pixel's count from the mesh's G-buffer (on
//! the GPU, [`AdaptivePass`] fed uploaded textures, or its CPU twin), the CPU traces the
//! AO rays through the mesh's hierarchy ([`crate::mesh::ao::sample`]), and the
//! component updates with them. A GPU run is held against the twin on every frame and
//! every pixel as the motion section's are: a shadow [`AdaptiveTwin`] fed the same inputs
//! must give the GPU's counts and history texels bit for bit
//! (`render::record_frame`). The rays themselves are traced on the CPU in
//! both (there is no mesh on the GPU), so no AO value is compared.

use half::f16;

use super::data::TwinCheck;
use super::frames::{POSE_STRIDE, first_scored};
use super::options::MotionOptions;
use super::render::{Setup, adaptive, differing, record_frame, show_history_where_skipped};
use super::run::{Frames, Geometry, RunResult, SECOND_SEED, run_frames};
use super::scenes::core_variants;
use crate::error::ReportError;
use crate::mesh::ao::{reference, sample};
pub use crate::mesh::scene::NAME;
use crate::mesh::scene::{MeshPixel, MeshScene};
use crate::progress::Progress;
use crate::wgpu_api::{
    AdaptiveError, AdaptivePass, AdaptiveTwin, AoFrame, AoGuide, AoMode, EstimateData,
    EstimateInputs, GpuDevice, UpdateData, UpdateInputs, read_texture,
};

/// The component on the GPU, its input textures, and its check against the twin.
struct Gpu {
    pass: AdaptivePass,
    device: GpuDevice,
    /// Motion, depth, previous depth, reprojected depth, AO value, resolve weight.
    inputs: [wgpu::Texture; 6],
    shadow: AdaptiveTwin,
    record: TwinCheck,
}

enum Component {
    Fixed(u32),
    Cpu(Box<AdaptiveTwin>),
    Gpu(Box<Gpu>),
}

/// The mesh scene's renderer of one run.
pub(crate) struct MeshRenderer {
    component: Component,
    prefixes: [u32; 4],
    fractional: bool,
    previous_depth: Option<Vec<f32>>,
    /// Added to the frame index that seeds the rays (`SECOND_SEED` on a run's second
    /// seed).
    pub(crate) seed: u32,
}

impl MeshRenderer {
    /// The renderer of `setup` at `size` on `dev` (the CPU twin without one); a GPU run's
    /// check is named `scene` / `run`. Fixed counts and AS only (the identity history is
    /// not run on the mesh).
    pub(crate) fn new(
        dev: Option<&GpuDevice>,
        setup: &Setup,
        size: [u32; 2],
        scene: &str,
        run: &str,
    ) -> Result<Self, ReportError> {
        let [w, h] = size;
        let component = match (setup.mode, dev) {
            (AoMode::Fixed(n), _) => Component::Fixed(n),
            (AoMode::Identity, _) => {
                return Err(ReportError::Usage(format!(
                    "{scene} {run}: the mesh scene runs fixed counts and AS"
                )));
            }
            (AoMode::Adaptive, None) => Component::Cpu(Box::new(
                AdaptiveTwin::new(setup.settings(), w, h).map_err(adaptive)?,
            )),
            (AoMode::Adaptive, Some(d)) => {
                use wgpu::{TextureFormat as Tf, TextureUsages as Tu};
                let usage = Tu::TEXTURE_BINDING | Tu::COPY_DST;
                let tex = |label, f| spvg_wgpu::util::texture_2d(&d.device, label, f, size, usage);
                Component::Gpu(Box::new(Gpu {
                    pass: AdaptivePass::new(&d.device, setup.settings(), w, h).map_err(adaptive)?,
                    device: d.clone(),
                    inputs: [
                        tex("mesh motion", Tf::Rg32Float),
                        tex("mesh depth", Tf::R32Float),
                        tex("mesh previous depth", Tf::R32Float),
                        tex("mesh reprojected depth", Tf::R32Float),
                        tex("mesh ao value", Tf::R32Float),
                        tex("mesh resolve weight", Tf::R32Float),
                    ],
                    shadow: AdaptiveTwin::new(setup.settings(), w, h).map_err(adaptive)?,
                    record: TwinCheck {
                        scene: scene.to_owned(),
                        run: run.to_owned(),
                        adaptive: true,
                        ..TwinCheck::default()
                    },
                }))
            }
        };
        Ok(Self {
            component,
            prefixes: setup.prefixes,
            fractional: setup.mode == AoMode::Adaptive && setup.config.fractional_floor().is_some(),
            previous_depth: None,
            seed: 0,
        })
    }

    /// Renders frame `t` of `scene` (its G-buffer `g`) and, on the GPU, checks it; the
    /// estimate takes `resolve_weight` (the resolved-image rule's per-pixel weight, one
    /// per pixel, or `None`).
    pub(crate) fn frame(
        &mut self,
        scene: &MeshScene,
        t: u32,
        g: &[MeshPixel],
        resolve_weight: Option<&[f32]>,
    ) -> Result<AoFrame, ReportError> {
        let depth: Vec<f32> = g.iter().map(|p| p.depth).collect();
        let motion: Vec<[f32; 2]> = g.iter().map(|p| p.motion).collect();
        let reprojected: Vec<f32> = g.iter().map(|p| p.reprojected_depth).collect();
        // Frame 0 reads a zeroed previous depth, as the AO effect's does.
        let previous = self
            .previous_depth
            .take()
            .unwrap_or_else(|| vec![0.0; g.len()]);
        let data = EstimateData::new(&motion, &depth, &previous)
            .with_reprojected_depth(Some(&reprojected))
            .with_resolve_weight(resolve_weight);
        let count: Vec<u32> = match &mut self.component {
            Component::Fixed(n) => vec![*n; g.len()],
            Component::Cpu(a) => a.estimate(&data).map_err(adaptive)?.to_vec(),
            Component::Gpu(gpu) => {
                let q = &gpu.device.queue;
                let [m, d, p, r, _, rw] = &gpu.inputs;
                upload(q, m, &bytes(motion.iter().flatten()), 8);
                upload(q, d, &bytes(depth.iter()), 4);
                upload(q, p, &bytes(previous.iter()), 4);
                upload(q, r, &bytes(reprojected.iter()), 4);
                if let Some(w) = resolve_weight {
                    if w.len() != g.len() {
                        return Err(adaptive(AdaptiveError::SliceLength {
                            input: "resolve_weight",
                            expected: g.len(),
                            got: w.len(),
                        }));
                    }
                    upload(q, rw, &bytes(w.iter()), 4);
                }
                let mut enc = gpu
                    .device
                    .device
                    .create_command_encoder(&Default::default());
                gpu.pass
                    .record_estimate(
                        &mut enc,
                        &EstimateInputs::new(m, d, p)
                            .with_reprojected_depth(Some(r))
                            .with_resolve_weight(resolve_weight.map(|_| rw)),
                    )
                    .map_err(adaptive)?;
                q.submit([enc.finish()]);
                read_texture(&gpu.device.device, q, gpu.pass.count_texture()).map_err(adaptive)?
            }
        };
        let (mut value, prefixes) =
            sample(scene, t.wrapping_add(self.seed), g, &count, self.prefixes);
        let history: Option<(Vec<[f16; 4]>, spvg::texel::TexelEncoding)> = match &mut self.component
        {
            Component::Fixed(_) => None,
            Component::Cpu(a) => {
                a.update(&UpdateData::new(&value)).map_err(adaptive)?;
                Some((a.history().to_vec(), a.encoding()))
            }
            Component::Gpu(gpu) => {
                let q = &gpu.device.queue;
                upload(q, &gpu.inputs[4], &bytes(value.iter()), 4);
                let mut enc = gpu
                    .device
                    .device
                    .create_command_encoder(&Default::default());
                gpu.pass
                    .record_update(&mut enc, &UpdateInputs::new(&gpu.inputs[4]))
                    .map_err(adaptive)?;
                q.submit([enc.finish()]);
                let h: Vec<[f16; 4]> =
                    read_texture(&gpu.device.device, q, gpu.pass.history_texture())
                        .map_err(adaptive)?;
                // The shadow twin, fed the same inputs, must agree on every pixel.
                let want = gpu.shadow.estimate(&data).map_err(adaptive)?.to_vec();
                gpu.shadow
                    .update(&UpdateData::new(&value))
                    .map_err(adaptive)?;
                let bits = |h: &[[f16; 4]]| -> Vec<[u16; 4]> {
                    h.iter().map(|x| x.map(f16::to_bits)).collect()
                };
                let diffs = vec![
                    ("count", differing(&want, &count)),
                    ("history", differing(&bits(gpu.shadow.history()), &bits(&h))),
                ];
                record_frame(&mut gpu.record, t, scene.size[0], diffs);
                Some((h, gpu.pass.encoding()))
            }
        };
        self.previous_depth = Some(depth);
        let mut f = AoFrame {
            count,
            value: Vec::new(),
            prefixes,
        };
        if let (true, Some((h, enc))) = (self.fractional, &history) {
            f.value = std::mem::take(&mut value);
            show_history_where_skipped(&mut f, h, enc);
        } else {
            f.value = value;
        }
        Ok(f)
    }

    /// The run's check against the twin (`None` on the CPU twin and for fixed counts,
    /// which the GPU does not run on the mesh).
    pub(crate) fn twin_check(&self) -> Option<TwinCheck> {
        match &self.component {
            Component::Gpu(gpu) => Some(gpu.record.clone()),
            _ => None,
        }
    }
}

/// The bytes of `v` (the texture's native order).
fn bytes<'a>(v: impl Iterator<Item = &'a f32>) -> Vec<u8> {
    v.flat_map(|x| x.to_ne_bytes()).collect()
}

/// Writes `bytes` (`texel` bytes per texel, rows of the texture's width) to `texture`.
fn upload(queue: &wgpu::Queue, texture: &wgpu::Texture, bytes: &[u8], texel: u32) {
    let size = texture.size();
    queue.write_texture(
        texture.as_image_copy(),
        bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(size.width * texel),
            rows_per_image: Some(size.height),
        },
        size,
    );
}

/// Rays per sub-pixel position of the mesh scene's references (16 positions per pixel).
pub const REFERENCE_SAMPLES: u32 = 256;

/// The frames of the mesh scene whose references the report computes: every 4th frame
/// after the warm-up ([`POSE_STRIDE`], as the rotation's: the orbit's frames never
/// repeat), every frame with [`MotionOptions::full`].
#[must_use]
pub fn scored_frames(opts: &MotionOptions) -> Vec<u32> {
    let first = first_scored(opts);
    let stride = if opts.full { 1 } else { POSE_STRIDE };
    (first..opts.frames).step_by(stride as usize).collect()
}

/// The mesh scene's references, one per frame (empty on the frames not scored).
#[must_use]
pub fn references(opts: &MotionOptions, scene: &MeshScene) -> Vec<Vec<f32>> {
    let scored = scored_frames(opts);
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    (0..opts.frames)
        .map(|t| {
            if scored.contains(&t) {
                reference(scene, t, REFERENCE_SAMPLES, threads)
            } else {
                Vec::new()
            }
        })
        .collect()
}

/// The mesh scene through one run's renderer.
struct MeshFrames<'a> {
    scene: &'a MeshScene,
    renderer: MeshRenderer,
    /// The frame whose geometry was asked last and its G-buffer.
    frame: Option<(u32, Vec<MeshPixel>)>,
}

impl Frames for MeshFrames<'_> {
    fn geometry(&mut self, t: u32) -> Geometry {
        let g = self.scene.gbuffer(t);
        let geometry = Geometry {
            motion: g.iter().map(|p| p.motion).collect(),
            depth: g.iter().map(|p| p.depth).collect(),
            moving: vec![false; g.len()],
        };
        self.frame = Some((t, g));
        geometry
    }

    fn render(
        &mut self,
        t: u32,
        guide: Option<&mut AoGuide<'_>>,
        resolve_weight: Option<&[f32]>,
    ) -> Result<AoFrame, ReportError> {
        if guide.is_some() {
            return Err(ReportError::Usage(format!(
                "{NAME}: the TAA-guided update is not run on the mesh"
            )));
        }
        let g = match self.frame.take() {
            Some((k, g)) if k == t => g,
            _ => self.scene.gbuffer(t),
        };
        self.renderer.frame(self.scene, t, &g, resolve_weight)
    }

    fn twin_check(&self) -> Option<TwinCheck> {
        self.renderer.twin_check()
    }
}

/// Runs the mesh scene through the ladder, `as` and `as-resolved` ([`core_variants`])
/// against `refs` ([`references`]); `progress` counts each frame.
///
/// # Errors
///
/// A device failure or a rejected configuration.
pub fn runs(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    scene: &MeshScene,
    refs: &[Vec<f32>],
    progress: &Progress,
) -> Result<Vec<RunResult>, ReportError> {
    core_variants(opts)
        .into_iter()
        .map(|v| {
            let name = v.name(opts);
            progress.stage(&format!("motion: {NAME} {name}"));
            let setup = Setup::of(opts, &v)?;
            let mut frames = MeshFrames {
                scene,
                renderer: MeshRenderer::new(dev, &setup, scene.size, NAME, &name)?,
                frame: None,
            };
            let mut second = match opts.split {
                true => {
                    let mut r = MeshRenderer::new(dev, &setup, scene.size, NAME, &name)?;
                    r.seed = SECOND_SEED;
                    Some(MeshFrames {
                        scene,
                        renderer: r,
                        frame: None,
                    })
                }
                false => None,
            };
            run_frames(
                &mut frames,
                second.as_mut().map(|s| s as &mut dyn Frames),
                opts,
                scene.size,
                NAME,
                v,
                refs,
                false,
                progress,
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::scene::{Mesh, ORBIT};

    /// The GPU's component on the mesh scene equals its twin on every frame (the shadow
    /// twin's check records no difference), and the GPU runs give the CPU twin's runs'
    /// counts and images, for `as` and `as-resolved` (fractional counts).
    #[test]
    fn the_gpu_component_on_the_mesh_equals_the_twin() {
        let Some(dev) = spvg_gpu_test::GpuTest::new("mesh gpu_component_equals_twin").device()
        else {
            return;
        };
        let opts = MotionOptions {
            frames: 6,
            ..MotionOptions::new().expect("defaults")
        };
        let scene = MeshScene::new(Mesh::bunny().expect("bunny"), [24, 16], ORBIT);
        for v in core_variants(&opts).into_iter().skip(1) {
            let setup = Setup::of(&opts, &v).expect("valid variant");
            let name = v.name(&opts);
            let mut gpu = MeshRenderer::new(Some(&dev), &setup, scene.size, NAME, &name)
                .expect("gpu renderer");
            let mut cpu =
                MeshRenderer::new(None, &setup, scene.size, NAME, &name).expect("twin renderer");
            let mut skipped = 0;
            for t in 0..opts.frames {
                let g = scene.gbuffer(t);
                // The resolved-image rule's per-pixel weight, of mixed values (a weight
                // of 1, the blend weight, none as NaN and 0, above 1), from frame 1 on.
                let mixed = [1.0, crate::taa::WEIGHT, f32::NAN, 0.0, 2.0];
                let weight: Vec<f32> = (0..g.len())
                    .map(|i| mixed[(i + t as usize) % mixed.len()])
                    .collect();
                let w = (v.resolved && t > 0).then_some(weight.as_slice());
                let (a, b) = (
                    gpu.frame(&scene, t, &g, w).expect("gpu frame"),
                    cpu.frame(&scene, t, &g, w).expect("twin frame"),
                );
                assert_eq!(a.count, b.count, "{name} frame {t}");
                assert_eq!(a.value, b.value, "{name} frame {t}");
                skipped += a.count.iter().filter(|&&n| n == 0).count();
            }
            let check = gpu.twin_check().expect("a GPU run is checked");
            assert_eq!(check.frames, opts.frames, "{name}");
            assert_eq!(check.corrupt, None, "{name}");
            if v.resolved {
                assert!(
                    skipped > 0,
                    "{name}: the fractional floor skips some pixels"
                );
            }
        }
    }
}

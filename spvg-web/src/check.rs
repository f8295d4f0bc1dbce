//! The browser check: the GPU frames of the page held equal to the component's CPU twin
//! compiled into the same program, frame by frame.
//!
//! The subject is the component: per frame its twin is fed what the GPU's component was
//! fed (the G-buffer the GPU wrote: depth, motion vectors, reprojected depth; and the
//! GPU's AO values), and must give the GPU's counts on every pixel and its history texels
//! bit for bit. The scene around it is held to its own twin (`spvg_effects::ao::twin`)
//! within a tolerance instead, because WGSL lets a driver fuse a multiply-add, which
//! moves a rotated camera's world position by an ulp (lavapipe does): the G-buffer within
//! a few ulps ([`gbuffer_close`]), and the AO values on a lattice (every row, the columns
//! `x = t mod 8` of frame `t`) within one ray of the pixel's count (a fused ray test can
//! flip a grazing ray; the native test `spvg-effects/tests/ao.rs` allows the same). How
//! many of those were bit-equal too is counted and reported.

use half::f16;
use spvg_effects::ao::{AoParams, twin};
use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptiveSettings, AdaptiveTwin, EstimateData, UpdateData,
};

use crate::metrics::{EqualQuality, mean, psnr, taa_weighted};
use crate::renderer::{Frame, Mode, Reads, Renderer, TAA_ALPHA, TwinReadback};
use crate::scene::{View, check_view, params};

/// The component's twin fed what the page's GPU frames see.
#[derive(Debug)]
pub struct TwinCheck {
    twin: AdaptiveTwin,
    previous_depth: Option<Vec<f32>>,
    width: usize,
}

/// How one GPU frame compares with the twin.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Comparison {
    /// The first difference, if any (what, where, both values); `None` when the frame
    /// equals the twin.
    pub difference: Option<String>,
    /// Whether the GPU's G-buffer equalled the scene twin's bit for bit.
    pub gbuffer_equal: bool,
    /// AO values on the lattice equal to the twin's bit for bit.
    pub ao_equal: usize,
    /// AO values checked on the lattice.
    pub ao_checked: usize,
}

/// The first index where `gpu` and `cpu` differ under `same`, described.
fn first_difference<T: core::fmt::Debug>(
    what: &str,
    gpu: &[T],
    cpu: &[T],
    width: usize,
    same: impl Fn(&T, &T) -> bool,
) -> Option<String> {
    if gpu.len() != cpu.len() {
        return Some(format!(
            "{what}: {} values, the twin {}",
            gpu.len(),
            cpu.len()
        ));
    }
    let differ = gpu.iter().zip(cpu).filter(|(a, b)| !same(a, b)).count();
    let i = gpu.iter().zip(cpu).position(|(a, b)| !same(a, b))?;
    Some(format!(
        "{what}: {differ} pixels differ, first ({}, {}): gpu {:?}, twin {:?}",
        i % width,
        i / width,
        gpu[i],
        cpu[i]
    ))
}

fn same_f32(a: &f32, b: &f32) -> bool {
    a.to_bits() == b.to_bits()
}

impl TwinCheck {
    /// A twin of the component with `settings` for a `width x height` frame, before its
    /// first frame (as a new [`Renderer`] is).
    ///
    /// # Errors
    ///
    /// As [`AdaptiveTwin::new`].
    pub fn new(
        settings: AdaptiveSettings,
        [width, height]: [u32; 2],
    ) -> Result<Self, AdaptiveError> {
        Ok(Self {
            twin: AdaptiveTwin::new(settings, width, height)?,
            previous_depth: None,
            width: width as usize,
        })
    }

    /// Runs the twin on the frame of `params` and compares it with the GPU's `gpu_count`
    /// and `gpu` readback (module docs).
    ///
    /// # Errors
    ///
    /// As [`AdaptiveTwin::estimate`] and [`AdaptiveTwin::update`] (readbacks of the
    /// wrong length).
    pub fn frame(
        &mut self,
        params: &AoParams,
        gpu_count: &[u32],
        gpu: &TwinReadback,
    ) -> Result<Comparison, AdaptiveError> {
        let w = self.width;
        // The component: fed the GPU's G-buffer and AO values, bit for bit.
        // The GPU's first frame reads a zeroed previous depth.
        let zero = vec![0.0; gpu.depth.len()];
        let count = self
            .twin
            .estimate(
                &EstimateData::new(
                    &gpu.motion,
                    &gpu.depth,
                    self.previous_depth.as_ref().unwrap_or(&zero),
                )
                .with_reprojected_depth(Some(&gpu.reprojected_depth)),
            )?
            .to_vec();
        let mut difference = first_difference("counts", gpu_count, &count, w, u32::eq);
        self.twin.update(&UpdateData::new(&gpu.value))?;
        let bits =
            |v: &[[f16; 4]]| -> Vec<[u16; 4]> { v.iter().map(|t| t.map(f16::to_bits)).collect() };
        difference = difference.or_else(|| {
            first_difference(
                "history texels",
                &bits(&gpu.history),
                &bits(self.twin.history()),
                w,
                <[u16; 4]>::eq,
            )
        });
        self.previous_depth = Some(gpu.depth.clone());
        let scene = scene_comparison(params, &count, gpu, w);
        Ok(Comparison {
            difference: difference.or(scene.difference),
            ..scene
        })
    }
}

/// The scene held to its own twin (module docs) on a GPU frame whose counts were
/// `count`: its twin's G-buffer within a few ulps, its AO values on the lattice within
/// one ray. The fixed side of the side by side is held to this alone (a fixed frame has
/// no component to compare).
fn scene_comparison(params: &AoParams, count: &[u32], gpu: &TwinReadback, w: usize) -> Comparison {
    // The scene: its twin's G-buffer within a few ulps, its AO within one ray.
    let g = twin::gbuffer(params);
    let depth: Vec<f32> = g.iter().map(|x| x.depth).collect();
    let motion: Vec<[f32; 2]> = g.iter().map(|x| x.motion).collect();
    let reprojected: Vec<f32> = g.iter().map(|x| x.reprojected_depth).collect();
    let mut difference =
        first_difference("depth", &gpu.depth, &depth, w, |a, b| gbuffer_close(*a, *b))
            .or_else(|| {
                first_difference("motion", &gpu.motion, &motion, w, |a, b| {
                    gbuffer_close(a[0], b[0]) && gbuffer_close(a[1], b[1])
                })
            })
            .or_else(|| {
                first_difference(
                    "reprojected depth",
                    &gpu.reprojected_depth,
                    &reprojected,
                    w,
                    |a, b| gbuffer_close(*a, *b),
                )
            });
    let gbuffer_equal = gpu.depth.iter().zip(&depth).all(|(a, b)| same_f32(a, b))
        && gpu
            .motion
            .iter()
            .zip(&motion)
            .all(|(a, b)| same_f32(&a[0], &b[0]) && same_f32(&a[1], &b[1]))
        && gpu
            .reprojected_depth
            .iter()
            .zip(&reprojected)
            .all(|(a, b)| same_f32(a, b));
    let (mut ao_equal, mut ao_checked) = (0, 0);
    let column = (params.frame % 8) as usize;
    for (i, gp) in g.iter().enumerate().filter(|(i, _)| i % w % 8 == column) {
        let n = count[i];
        let want = twin::estimate(params, [(i % w) as u32, (i / w) as u32], &gp.surface, n);
        let got = gpu.value.get(i).copied().unwrap_or(f32::NAN);
        ao_checked += 1;
        ao_equal += usize::from(same_f32(&got, &want));
        // A NaN on either side is more than one ray apart too.
        let within = (got - want).abs() <= 1.0 / n.max(1) as f32 + 1e-6;
        if difference.is_none() && !within {
            difference = Some(format!(
                "AO value at ({}, {}): gpu {got}, twin {want} at {n} rays (more than one ray apart)",
                i % w,
                i / w
            ));
        }
    }
    Comparison {
        difference,
        gbuffer_equal,
        ao_equal,
        ao_checked,
    }
}

/// Whether two G-buffer values agree to within a few ulps: `1e-5` relative, or `1e-4`
/// absolute near zero (a fused multiply-add changes the last bits of a product of
/// magnitudes up to a few hundred pixels).
#[must_use]
pub fn gbuffer_close(gpu: f32, twin: f32) -> bool {
    same_f32(&gpu, &twin) || (gpu - twin).abs() <= 1e-4_f32.max(1e-5 * twin.abs())
}

/// Passes of [`crate::renderer::REFERENCE_RAYS`] rays in the check's reference.
pub const REFERENCE_PASSES: u32 = 16;

/// The fixed counts the equal-quality figure is measured against.
pub const EQUAL_QUALITY_COUNTS: [u32; 4] = [8, 16, 32, 64];

/// What the check found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CheckReport {
    /// Frames rendered.
    pub frames: u32,
    /// Frames equal to the twin: the component's counts and history bit for bit, the
    /// scene's G-buffer within a few ulps and its AO values within one ray.
    pub equal: u32,
    /// The first differing frame and what differed.
    pub first_failure: Option<(u32, String)>,
    /// Mean samples per pixel over the frames.
    pub spp: f64,
    /// PSNR of the last frame after TAA against the converged reference of its view.
    pub psnr_taa: f64,
    /// AO values on the lattice equal to the twin's bit for bit, and checked.
    pub ao_equal: (usize, usize),
    /// Frames whose G-buffer equalled the scene twin's bit for bit.
    pub gbuffer_equal: u32,
    /// Mean CPU wall time per frame (ms), the first frame (pipeline compilation) left out.
    pub wall_ms: f64,
    /// Mean timestamp-query span per frame (ms) where the device has them.
    pub gpu_ms: Option<f64>,
    /// Wall time (ms) spent converging the reference before the first frame (the page's
    /// first-frame time in the check includes it).
    pub reference_ms: f64,
    /// The equal-quality figure on the last view, where it was measured.
    pub equal_quality: Option<EqualQualityRun>,
    /// The side by side, where it ran: per frame a second renderer at the fixed count
    /// nearest the adaptive frame's mean, same view.
    pub side: Option<SideBySide>,
}

/// The fixed side of the check's side by side.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SideBySide {
    /// Fixed frames whose counts were all the adaptive frame's mean rounded, whose
    /// G-buffer equalled the adaptive frame's bit for bit (same view, two renderers), and
    /// whose scene matched its twin as the adaptive side's must.
    pub equal: u32,
    /// The first differing fixed frame and what differed.
    pub first_failure: Option<(u32, String)>,
    /// Mean samples per pixel of the fixed side (the adaptive side's is
    /// [`CheckReport::spp`]).
    pub spp: f64,
    /// PSNR of the fixed side's last frame after TAA, against the same reference.
    pub psnr_taa: f64,
}

impl CheckReport {
    /// Whether every frame equalled the twin.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.frames > 0
            && self.equal == self.frames
            && self.first_failure.is_none()
            && self
                .side
                .as_ref()
                .is_none_or(|s| s.equal == self.frames && s.first_failure.is_none())
    }

    /// The one line the page logs: `SPVG-WEB PASS frames=N twin_equal=N/N spp=...
    /// psnr_taa=...` and the times, or `SPVG-WEB FAIL ...` with the first differing frame.
    #[must_use]
    pub fn line(&self) -> String {
        let mut s = format!(
            "SPVG-WEB {} frames={} twin_equal={}/{} spp={:.2} psnr_taa={:.2} gbuffer_bit_equal={}/{} ao_bit_equal={}/{} frame_ms={:.1}",
            if self.passed() { "PASS" } else { "FAIL" },
            self.frames,
            self.equal,
            self.frames,
            self.spp,
            self.psnr_taa,
            self.gbuffer_equal,
            self.frames,
            self.ao_equal.0,
            self.ao_equal.1,
            self.wall_ms,
        );
        if let Some(g) = self.gpu_ms {
            s.push_str(&format!(" timestamp_ms={g:.1}"));
        }
        if let Some(side) = &self.side {
            s.push_str(&format!(
                " side_by_side=fixed,adaptive fixed_equal={}/{} fixed_spp={:.2} fixed_psnr_taa={:.2}",
                side.equal, self.frames, side.spp, side.psnr_taa
            ));
            if let Some((t, why)) = &side.first_failure {
                s.push_str(&format!(" fixed_first_difference=\"frame {t}: {why}\""));
            }
        }
        if let Some(q) = &self.equal_quality {
            s.push_str(&format!(
                " equal_quality=\"AS {:.2} spp {:.2} dB = {}\"",
                q.spp,
                q.psnr,
                q.equal.describe(q.spp)
            ));
        }
        if let Some((t, why)) = &self.first_failure {
            s.push_str(&format!(" first_difference=\"frame {t}: {why}\""));
        }
        s
    }
}

/// The equal-quality figure on one view: the adaptive run and the fixed ones, each from
/// a reset over the same frames.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EqualQualityRun {
    /// The adaptive run's samples per pixel behind its last resolved frame (each frame's
    /// mean count weighted by its weight in the TAA blend).
    pub spp: f64,
    /// The adaptive run's PSNR after TAA on its last frame.
    pub psnr: f64,
    /// Each fixed run's count and PSNR after TAA on its last frame.
    pub fixed: Vec<(u32, f64)>,
    /// Where the adaptive run sits among them.
    pub equal: EqualQuality,
}

/// Renders `frames` frames of the static view `view` in `mode` from a reset; returns
/// the samples per pixel behind the last resolved frame ([`taa_weighted`]: a run from a
/// reset starts at `beta_min`, which the resolve has mostly forgotten by its last frame)
/// and its PSNR after TAA against `reference`.
async fn static_run(
    renderer: &mut Renderer,
    mode: Mode,
    view: &View,
    frames: u32,
    reference: &[f32],
    show: &mut impl FnMut(&Frame) -> bool,
) -> Result<Option<(f64, f64)>, AdaptiveError> {
    let [w, h] = renderer.size();
    renderer.set_mode(mode);
    renderer.reset();
    let mut spp = Vec::new();
    let mut last = Frame::default();
    for t in 0..frames {
        let reads = Reads {
            image: true,
            taa: t + 1 == frames,
            twin: false,
        };
        last = renderer.render(&params(w, h, t, view, view), reads).await?;
        spp.push(last.mean_spp());
        if !show(&last) {
            return Ok(None);
        }
    }
    Ok(Some((
        taa_weighted(&spp, f64::from(TAA_ALPHA)),
        psnr(&last.taa, reference),
    )))
}

/// Renders `frames` frames of the static view `view` from a reset in each of
/// [`EQUAL_QUALITY_COUNTS`]'s fixed counts and adaptively, and places the adaptive run's
/// PSNR after TAA (last frame, against `reference`) among the fixed ones. Leaves the
/// renderer adaptive. `show` sees every frame (`5 frames` in all, in that order) and
/// cancels the measurement by returning `false`: the result is then `None`.
///
/// # Errors
///
/// As [`Renderer::render`].
pub async fn equal_quality(
    renderer: &mut Renderer,
    view: &View,
    frames: u32,
    reference: &[f32],
    mut show: impl FnMut(&Frame) -> bool,
) -> Result<Option<EqualQualityRun>, AdaptiveError> {
    let mut fixed = Vec::new();
    for n in EQUAL_QUALITY_COUNTS {
        let run = static_run(renderer, Mode::Fixed(n), view, frames, reference, &mut show);
        let Some((_, p)) = run.await? else {
            return Ok(None);
        };
        fixed.push((n, p));
    }
    let run = static_run(renderer, Mode::Adaptive, view, frames, reference, &mut show);
    let Some((spp, psnr)) = run.await? else {
        return Ok(None);
    };
    Ok(Some(EqualQualityRun {
        spp,
        psnr,
        equal: EqualQuality::of(psnr, &fixed),
        fixed,
    }))
}

/// The browser check on `renderer` (new, adaptive): converges the reference of the
/// scripted path's last view, renders the path's `frames` frames
/// ([`check_view`]) comparing each with the twin, measures PSNR after TAA on the last
/// frame and, with `equal_quality_frames > 0`, the equal-quality figure on the last view
/// over that many frames. With `side`, a second renderer of the same size renders each
/// frame's view at the fixed count nearest the adaptive frame's mean ([`SideBySide`]).
/// `show` sees every frame with its row (0 the adaptive, 1 the fixed side; the page draws
/// them).
///
/// # Errors
///
/// As [`Renderer::render`] and [`TwinCheck::new`]; a frame that differs from the twin is
/// not an error but a failed report.
pub async fn run_check(
    renderer: &mut Renderer,
    mut side: Option<&mut Renderer>,
    frames: u32,
    equal_quality_frames: u32,
    mut show: impl FnMut(u32, &Frame),
) -> Result<CheckReport, AdaptiveError> {
    let [w, h] = renderer.size();
    let frames = frames.max(1);
    let last = check_view(frames - 1, frames);
    let started = crate::clock::now_ms();
    let reference = renderer
        .converge_reference(&params(w, h, 0, &last, &last), REFERENCE_PASSES)
        .await?;
    let reference_ms = crate::clock::now_ms() - started;
    renderer.set_mode(Mode::Adaptive);
    renderer.reset();
    let mut twin = TwinCheck::new(*renderer.settings(), [w, h])?;
    let mut report = CheckReport {
        frames,
        reference_ms,
        side: side.as_ref().map(|_| SideBySide::default()),
        ..CheckReport::default()
    };
    if let Some(s) = side.as_deref_mut() {
        s.set_reference(&params(w, h, 0, &last, &last), &reference);
        s.reset();
    }
    let mut side_spp = Vec::new();
    let (mut spp, mut wall, mut stamps) = (Vec::new(), Vec::new(), Vec::new());
    for t in 0..frames {
        let p = params(
            w,
            h,
            t,
            &check_view(t, frames),
            &check_view(t.saturating_sub(1), frames),
        );
        let reads = Reads {
            image: true,
            taa: t + 1 == frames,
            twin: true,
        };
        let f = renderer.render(&p, reads).await?;
        let gpu = f
            .twin
            .as_ref()
            .ok_or(AdaptiveError::Device("no twin readback".into()))?;
        let c = twin.frame(&p, &f.count, gpu)?;
        report.ao_equal.0 += c.ao_equal;
        report.ao_equal.1 += c.ao_checked;
        report.gbuffer_equal += u32::from(c.gbuffer_equal);
        match c.difference {
            None => report.equal += 1,
            Some(why) => {
                report.first_failure.get_or_insert((t, why));
            }
        }
        spp.push(f.mean_spp());
        if t > 0 {
            wall.push(f.wall_ms);
            stamps.extend(f.gpu_ms);
        }
        if t + 1 == frames {
            report.psnr_taa = psnr(&f.taa, &reference);
        }
        show(0, &f);
        if let (Some(s), Some(r)) = (side.as_deref_mut(), report.side.as_mut()) {
            let n = (f.mean_spp().round() as u32).clamp(1, crate::renderer::PAGE_MAX_BUDGET);
            s.set_mode(Mode::Fixed(n));
            let g = s.render(&p, reads).await?;
            let fixed = g
                .twin
                .as_ref()
                .ok_or(AdaptiveError::Device("no twin readback".into()))?;
            let scene = scene_comparison(&p, &g.count, fixed, w as usize);
            let difference = first_difference(
                "fixed counts",
                &g.count,
                &vec![n; g.count.len()],
                w as usize,
                u32::eq,
            )
            .or_else(|| {
                first_difference(
                    "fixed side's depth against the adaptive side's",
                    &fixed.depth,
                    &gpu.depth,
                    w as usize,
                    same_f32,
                )
            })
            .or(scene.difference);
            match difference {
                None => r.equal += 1,
                Some(why) => {
                    r.first_failure.get_or_insert((t, why));
                }
            }
            side_spp.push(g.mean_spp());
            if t + 1 == frames {
                r.psnr_taa = psnr(&g.taa, &reference);
            }
            show(1, &g);
        }
    }
    if let Some(r) = report.side.as_mut() {
        r.spp = mean(side_spp);
    }
    report.spp = mean(spp);
    report.wall_ms = mean(wall);
    report.gpu_ms = (!stamps.is_empty()).then(|| mean(stamps));
    if equal_quality_frames > 0 {
        let keep_going = |f: &Frame| {
            show(0, f);
            true
        };
        report.equal_quality = equal_quality(
            renderer,
            &last,
            equal_quality_frames,
            &reference,
            keep_going,
        )
        .await?;
    }
    Ok(report)
}

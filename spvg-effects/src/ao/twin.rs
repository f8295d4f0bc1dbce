//! The AO renderer on the CPU: [`AoTwin`], the twin of [`AoPass`](super::AoPass) frame by
//! frame, and one function per entry point of `ao/ao.wgsl` (and per WGSL helper), same f32
//! operation order; the sample sequence and `unit_dir` come from the core crate and
//! the crate's `common/direction.wgsl` twin, as on the GPU.

use spvg::sequence::{pcg3d16, r2_offset_from_seed, r2_point, to_unit_f32};

use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptiveSettings, AdaptiveTwin, EstimateData, UpdateData,
};

use super::AoParams;
use super::pass::{AoFrame, AoGuide, AoMode, check_control};
use crate::common::unit_dir;

const CELL: f32 = 64.0;
/// Length of the occlusion rays, in pixels (`AO_RANGE`).
pub const RANGE: f32 = 16.0;
const OFFSET: f32 = 0.001;
/// Beyond any ray parameter (`AO_BIG`).
const BIG: f32 = 1.0e30;
/// The candidate spheres (`AO_SPHERES`): the 3x3 cells, the mover, the two extra movers.
pub const SPHERES: i32 = 12;

/// WGSL twin: `ao_cell_sphere`: centre xyz and radius of the sphere of cell `(ix, iy)`.
#[must_use]
pub fn cell_sphere(ix: i32, iy: i32) -> [f32; 4] {
    let h = pcg3d16([
        (ix as u32).wrapping_add(4096),
        (iy as u32).wrapping_add(4096),
        7,
    ]);
    let fx = (h[0] >> 8) as f32 * (1.0 / 256.0);
    let fz = (h[0] & 255) as f32 * (1.0 / 256.0);
    let fy = h[1] as f32 * (1.0 / 65536.0);
    let r = 4.0 + 8.0 * (h[2] as f32 * (1.0 / 65536.0));
    let cx = (ix as f32 + (0.25 + 0.5 * fx)) * CELL;
    let cy = (iy as f32 + (0.25 + 0.5 * fy)) * CELL;
    [cx, cy, r * (1.5 * fz - 0.5), r]
}

/// WGSL twin: `ao_sphere`: candidate sphere `k` near cell `(ix, iy)`: 0..8 the 3x3 cells
/// around it, 9 the mover, 10 and 11 the extra movers.
fn sphere(p: &AoParams, k: i32, ix: i32, iy: i32) -> [f32; 4] {
    match k {
        9 => p.mover,
        10 | 11 => p.extra_movers[(k - 10) as usize],
        _ => cell_sphere(ix + k % 3 - 1, iy + k / 3 - 1),
    }
}

/// WGSL twin: `ao_sphere_velocity`: the motion per frame of candidate sphere `k`.
fn sphere_velocity(p: &AoParams, k: i32) -> [f32; 3] {
    let v = match k {
        9 => p.mover_velocity,
        10 | 11 => p.extra_velocities[(k - 10) as usize],
        _ => [0.0; 4],
    };
    [v[0], v[1], v[2]]
}

/// The candidate spheres near world `(x, y)`: the 3x3 cells around it, then the movers.
fn spheres(p: &AoParams, x: f32, y: f32) -> impl Iterator<Item = (i32, [f32; 4])> + '_ {
    let ix = (x / CELL).floor() as i32;
    let iy = (y / CELL).floor() as i32;
    (0..SPHERES).map(move |k| (k, sphere(p, k, ix, iy)))
}

/// WGSL twin: `AoSurface`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// World position.
    pub position: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
    /// On a moving object (a moving sphere or the bar).
    pub moving: bool,
    /// That object's motion per frame (0 when static).
    pub velocity: [f32; 3],
}

/// WGSL twin: `ao_surface`: the top surface at world `(x, y)`: the highest sphere cap or
/// bar top over the plane.
#[must_use]
pub fn surface(p: &AoParams, x: f32, y: f32) -> Surface {
    let mut s = Surface {
        position: [x, y, 0.0],
        normal: [0.0, 0.0, 1.0],
        moving: false,
        velocity: [0.0; 3],
    };
    for (k, c) in spheres(p, x, y) {
        let dx = x - c[0];
        let dy = y - c[1];
        let d2 = dx * dx + dy * dy;
        let r2 = c[3] * c[3];
        if d2 < r2 {
            let z = c[2] + (r2 - d2).sqrt();
            if z > s.position[2] {
                s.position[2] = z;
                let inv = 1.0 / c[3];
                s.normal = [dx * inv, dy * inv, (z - c[2]) * inv];
                s.moving = k >= 9;
                s.velocity = sphere_velocity(p, k);
            }
        }
    }
    let (lo, hi) = (p.bar_min, p.bar_max);
    if x >= lo[0] && x < hi[0] && y >= lo[1] && y < hi[1] && hi[2] > lo[2] && hi[2] > s.position[2]
    {
        s.position[2] = hi[2];
        s.normal = [0.0, 0.0, 1.0];
        s.moving = true;
        s.velocity = [p.bar_velocity[0], p.bar_velocity[1], p.bar_velocity[2]];
    }
    s
}

fn half(p: &AoParams) -> [f32; 2] {
    [0.5 * p.width as f32, 0.5 * p.height as f32]
}

/// WGSL twin: `ao_world`: world xy of pixel position `q` under `camera` with `lens`
/// ([`AoParams::lens`]).
#[must_use]
pub fn world(p: &AoParams, q: [f32; 2], camera: [f32; 4], lens: [f32; 4]) -> [f32; 2] {
    let h = half(p);
    let q = [(q[0] - h[0]) * lens[1], (q[1] - h[1]) * lens[1]];
    [
        camera[0] + (camera[2] * q[0] - camera[3] * q[1]),
        camera[1] + (camera[3] * q[0] + camera[2] * q[1]),
    ]
}

/// WGSL twin: `ao_pixel`: pixel position of world xy under `camera` with `lens`.
#[must_use]
pub fn pixel(p: &AoParams, w: [f32; 2], camera: [f32; 4], lens: [f32; 4]) -> [f32; 2] {
    let d = [w[0] - camera[0], w[1] - camera[1]];
    let q = [
        (camera[2] * d[0] + camera[3] * d[1]) * lens[2],
        (camera[2] * d[1] - camera[3] * d[0]) * lens[2],
    ];
    let h = half(p);
    [q[0] + h[0], q[1] + h[1]]
}

/// One pixel of the G-buffer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GPixel {
    /// Linear depth (camera height minus surface height).
    pub depth: f32,
    /// The surface point's depth as the previous camera saw it (the previous camera's
    /// height minus the point's height in the previous frame).
    pub reprojected_depth: f32,
    /// Motion vector in the convention of `spvg::reproject`.
    pub motion: [f32; 2],
    /// The visible surface.
    pub surface: Surface,
}

/// CPU twin of the entry point `ao_gbuffer` at pixel `(x, y)`.
#[must_use]
pub fn gbuffer_pixel(p: &AoParams, x: u32, y: u32) -> GPixel {
    let q = [x as f32 + 0.5, y as f32 + 0.5];
    let w = world(p, q, p.camera, p.lens);
    let s = surface(p, w[0], w[1]);
    let previous: [f32; 3] = core::array::from_fn(|i| s.position[i] - s.velocity[i]);
    let pp = pixel(
        p,
        [previous[0], previous[1]],
        p.previous_camera,
        p.previous_lens,
    );
    GPixel {
        depth: p.lens[0] - s.position[2],
        reprojected_depth: p.previous_lens[0] - previous[2],
        motion: [
            (q[0] - pp[0]) + p.motion_bias[0],
            (q[1] - pp[1]) + p.motion_bias[1],
        ],
        surface: s,
    }
}

/// The whole G-buffer, row-major.
#[must_use]
pub fn gbuffer(p: &AoParams) -> Vec<GPixel> {
    (0..p.height)
        .flat_map(|y| (0..p.width).map(move |x| gbuffer_pixel(p, x, y)))
        .collect()
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// WGSL twin: `ao_slab`: the parameter interval `(near, far)` of the ray `o + t d` inside
/// the slab `lo <= x < hi` of one axis; empty (`near > far`) when it misses.
fn slab(o: f32, d: f32, lo: f32, hi: f32) -> [f32; 2] {
    if d == 0.0 {
        return if o >= lo && o < hi {
            [-BIG, BIG]
        } else {
            [BIG, -BIG]
        };
    }
    let a = (lo - o) / d;
    let b = (hi - o) / d;
    [a.min(b), a.max(b)]
}

/// WGSL twin: `ao_hits_bar`: whether the ray `o + t d`, `0 < t < RANGE`, enters the bar.
#[must_use]
pub fn hits_bar(p: &AoParams, o: [f32; 3], d: [f32; 3]) -> bool {
    let (lo, hi) = (p.bar_min, p.bar_max);
    if !(hi[0] > lo[0] && hi[1] > lo[1] && hi[2] > lo[2]) {
        return false;
    }
    let s: [[f32; 2]; 3] = core::array::from_fn(|i| slab(o[i], d[i], lo[i], hi[i]));
    let near = s[0][0].max(s[1][0]).max(s[2][0]);
    let far = s[0][1].min(s[1][1]).min(s[2][1]);
    near <= far && far > 0.0 && near < RANGE
}

/// The candidate spheres of the rays from `o`, in `ao_occluded`'s order. They depend on
/// the origin alone, so a pixel computes them once for all its rays (the WGSL recomputes
/// them per ray; the values, and so every ray test, are the same).
#[must_use]
pub fn candidates(p: &AoParams, o: [f32; 3]) -> [[f32; 4]; SPHERES as usize] {
    let mut c = [[0.0; 4]; SPHERES as usize];
    for (k, s) in spheres(p, o[0], o[1]) {
        c[k as usize] = s;
    }
    c
}

/// WGSL twin: `ao_occluded`: whether the ray `o + t d`, `0 < t < RANGE`, hits the plane,
/// the bar or a sphere.
#[must_use]
pub fn occluded(p: &AoParams, o: [f32; 3], d: [f32; 3]) -> bool {
    occluded_among(p, o, d, &candidates(p, o))
}

/// [`occluded`] with the origin's [`candidates`] computed once by the caller.
#[must_use]
pub fn occluded_among(
    p: &AoParams,
    o: [f32; 3],
    d: [f32; 3],
    spheres: &[[f32; 4]; SPHERES as usize],
) -> bool {
    if d[2] < 0.0 && -o[2] / d[2] < RANGE {
        return true;
    }
    if hits_bar(p, o, d) {
        return true;
    }
    for c in spheres {
        let oc = [o[0] - c[0], o[1] - c[1], o[2] - c[2]];
        let b = dot(oc, d);
        let disc = b * b - (dot(oc, oc) - c[3] * c[3]);
        if disc >= 0.0 {
            let t = -b - disc.sqrt();
            if t > 0.0 && t < RANGE {
                return true;
            }
        }
    }
    false
}

/// WGSL twin: `ao_estimate`'s value: the fraction of `n` cosine-weighted directions (R2
/// points seeded by pcg3d16 of the pixel and frame) that escape.
#[must_use]
pub fn estimate(p: &AoParams, px: [u32; 2], s: &Surface, n: u32) -> f32 {
    estimate_with_prefixes(p, px, s, n).0
}

/// WGSL twin: `ao_estimate`: [`estimate`], and the estimates of the first
/// `p.prefixes[j]` samples (0 where `p.prefixes[j]` is 0 or above `n`).
#[must_use]
pub fn estimate_with_prefixes(p: &AoParams, px: [u32; 2], s: &Surface, n: u32) -> (f32, [f32; 4]) {
    let mut prefix = [0.0_f32; 4];
    if n == 0 {
        return (0.0, prefix);
    }
    let offset = r2_offset_from_seed(pcg3d16([px[0], px[1], p.frame]));
    let nrm = s.normal;
    let sgn = if nrm[2] >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sgn + nrm[2]);
    let b = nrm[0] * nrm[1] * a;
    let t = [1.0 + sgn * nrm[0] * nrm[0] * a, sgn * b, -sgn * nrm[0]];
    let bt = [b, sgn + nrm[1] * nrm[1] * a, -nrm[1]];
    let o: [f32; 3] = core::array::from_fn(|i| s.position[i] + nrm[i] * OFFSET);
    let spheres = candidates(p, o);
    let mut open = 0_u32;
    for m in 0..n {
        let u = r2_point(offset, m);
        let u1 = to_unit_f32(u[0]);
        let dir = unit_dir(u[1]);
        let r = u1.sqrt();
        let disk = [r * dir[0], r * dir[1]];
        let z = (1.0 - u1).sqrt();
        let d: [f32; 3] = core::array::from_fn(|i| t[i] * disk[0] + bt[i] * disk[1] + nrm[i] * z);
        if !occluded_among(p, o, d, &spheres) {
            open += 1;
        }
        for (j, &c) in p.prefixes.iter().enumerate() {
            if c == m + 1 {
                prefix[j] = open as f32 / c as f32;
            }
        }
    }
    (open as f32 / n as f32, prefix)
}

/// CPU twin of the entry point `ao_sample` over the frame: the AO estimate per pixel with
/// `count[i]` samples.
#[must_use]
pub fn sample(p: &AoParams, g: &[GPixel], count: &[u32]) -> Vec<f32> {
    sample_with_prefixes(p, g, count).0
}

/// CPU twin of the entry point `ao_sample` over the frame: [`sample`], and per pixel the
/// prefix estimates of [`estimate_with_prefixes`] (empty when `p.prefixes` is all 0).
#[must_use]
pub fn sample_with_prefixes(
    p: &AoParams,
    g: &[GPixel],
    count: &[u32],
) -> (Vec<f32>, Vec<[f32; 4]>) {
    let w = p.width as usize;
    let mut estimates = vec![(0.0_f32, [0.0_f32; 4]); g.len().min(count.len())];
    // Every pixel's estimate depends on that pixel alone, so the frame splits into chunks
    // on all cores with the same result as one thread.
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let chunk = estimates.len().div_ceil(threads).max(1);
    std::thread::scope(|scope| {
        for (k, out) in estimates.chunks_mut(chunk).enumerate() {
            scope.spawn(move || {
                for (j, o) in out.iter_mut().enumerate() {
                    let i = k * chunk + j;
                    let px = [(i % w) as u32, (i / w) as u32];
                    *o = estimate_with_prefixes(p, px, &g[i].surface, count[i]);
                }
            });
        }
    });
    let (value, prefixes): (Vec<f32>, Vec<[f32; 4]>) = estimates.into_iter().unzip();
    let prefixes = if p.prefixes == [0; 4] {
        Vec::new()
    } else {
        prefixes
    };
    (value, prefixes)
}

/// The CPU twin of [`AoPass`](super::AoPass): [`gbuffer`], the component's
/// [`AdaptiveTwin`] (or a fixed count), [`sample`].
#[derive(Clone, Debug)]
pub struct AoTwin {
    mode: AoMode,
    adaptive: Option<AdaptiveTwin>,
    previous_depth: Option<Vec<f32>>,
    use_reprojected_depth: bool,
    prefixes: [u32; 4],
    use_second_moment: bool,
    /// [`AoTwin::set_resolve_weight`]'s weights.
    resolve_weight: Option<Vec<f32>>,
    /// The frame size of [`AoTwin::new`].
    size: [u32; 2],
}

impl AoTwin {
    /// The twin of [`AoPass::new`](super::AoPass::new).
    ///
    /// # Errors
    ///
    /// As [`AdaptiveTwin::new`].
    pub fn new(
        width: u32,
        height: u32,
        mode: AoMode,
        settings: AdaptiveSettings,
    ) -> Result<Self, AdaptiveError> {
        let adaptive = match mode {
            AoMode::Fixed(_) => None,
            AoMode::Adaptive | AoMode::Identity => {
                check_control(&settings)?;
                Some(AdaptiveTwin::new(settings, width, height)?)
            }
        };
        Ok(Self {
            mode,
            adaptive,
            previous_depth: None,
            use_reprojected_depth: true,
            prefixes: [0; 4],
            use_second_moment: false,
            resolve_weight: None,
            size: [width, height],
        })
    }

    /// The twin of
    /// [`AoPass::set_reprojected_depth`](super::AoPass::set_reprojected_depth).
    pub fn set_reprojected_depth(&mut self, on: bool) {
        self.use_reprojected_depth = on;
    }

    /// The twin of [`AoPass::set_second_moment`](super::AoPass::set_second_moment).
    pub fn set_second_moment(&mut self, on: bool) {
        self.use_second_moment = on;
    }

    /// The twin of [`AoPass::set_resolve_weight`](super::AoPass::set_resolve_weight).
    ///
    /// # Errors
    ///
    /// As [`AoPass::set_resolve_weight`](super::AoPass::set_resolve_weight): a slice that
    /// is not one value per pixel (`width x height` of [`new`](Self::new)).
    pub fn set_resolve_weight(&mut self, weight: Option<&[f32]>) -> Result<(), AdaptiveError> {
        let n = self.size[0] as usize * self.size[1] as usize;
        match weight {
            Some(w) if w.len() != n => Err(AdaptiveError::SliceLength {
                input: "resolve_weight",
                expected: n,
                got: w.len(),
            }),
            w => {
                self.resolve_weight = w.map(<[f32]>::to_vec);
                Ok(())
            }
        }
    }

    /// The twin of [`AoPass::set_prefix_counts`](super::AoPass::set_prefix_counts).
    pub fn set_prefix_counts(&mut self, prefixes: [u32; 4]) {
        self.prefixes = prefixes;
    }

    /// The component's twin (`None` for a fixed count): its counts and histories after a
    /// frame, the twin of [`AoPass::adaptive`](super::AoPass::adaptive).
    #[must_use]
    pub fn adaptive(&self) -> Option<&AdaptiveTwin> {
        self.adaptive.as_ref()
    }

    /// The twin of [`AoPass::adaptive_mut`](super::AoPass::adaptive_mut).
    #[must_use]
    pub fn adaptive_mut(&mut self) -> Option<&mut AdaptiveTwin> {
        self.adaptive.as_mut()
    }

    /// The twin of [`AoPass::run_frame`](super::AoPass::run_frame).
    ///
    /// # Errors
    ///
    /// As [`AdaptiveTwin::estimate`] (frame size of `params` not the renderer's).
    pub fn run_frame(&mut self, params: &AoParams) -> Result<AoFrame, AdaptiveError> {
        self.run_frame_guided(params, None)
    }

    /// The twin of [`AoPass::run_frame_guided`](super::AoPass::run_frame_guided).
    ///
    /// # Errors
    ///
    /// As [`run_frame`](Self::run_frame); [`AdaptiveError::SliceLength`] naming `guide`
    /// for a guide that is not one value per pixel.
    pub fn run_frame_guided(
        &mut self,
        params: &AoParams,
        guide: Option<&mut AoGuide<'_>>,
    ) -> Result<AoFrame, AdaptiveError> {
        let params = &AoParams {
            prefixes: self.prefixes,
            ..*params
        };
        let g = gbuffer(params);
        let depth: Vec<f32> = g.iter().map(|x| x.depth).collect();
        let reprojected: Vec<f32> = g.iter().map(|x| x.reprojected_depth).collect();
        let count = match (&mut self.adaptive, self.mode) {
            (Some(a), mode) => {
                let identity = mode == AoMode::Identity;
                let motion: Vec<[f32; 2]> = if identity {
                    vec![[0.0; 2]; g.len()]
                } else {
                    g.iter().map(|x| x.motion).collect()
                };
                // Frame 0 on the GPU reads a zeroed previous depth.
                let zero = vec![0.0; g.len()];
                let previous = if identity {
                    &depth
                } else {
                    self.previous_depth.as_ref().unwrap_or(&zero)
                };
                a.estimate(
                    &EstimateData::new(&motion, &depth, previous)
                        .with_reprojected_depth(
                            (self.use_reprojected_depth && !identity).then_some(&reprojected),
                        )
                        .with_resolve_weight(self.resolve_weight.as_deref()),
                )?
                .to_vec()
            }
            (None, AoMode::Fixed(n)) => vec![n; g.len()],
            (None, _) => vec![0; g.len()],
        };
        let (value, prefixes) = sample_with_prefixes(params, &g, &count);
        if let Some(a) = &mut self.adaptive {
            let guide = guide.map(|f| f(&value));
            let update = UpdateData::new(&value).with_guide(guide.as_deref());
            if self.use_second_moment {
                // Binary rays: the mean of the squares is the mean.
                a.update_with_moment(&update, &value)?;
            } else {
                a.update(&update)?;
            }
        }
        self.previous_depth = Some(depth);
        Ok(AoFrame {
            count,
            value,
            prefixes,
        })
    }
}

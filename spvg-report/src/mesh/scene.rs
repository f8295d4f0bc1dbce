//! The mesh scene: the scanned mesh on a ground plane, loaded from the repository's
//! `assets/bunny.obj` with `tobj`, seen by a perspective camera that orbits it with
//! sub-pixel Halton jitter, and its G-buffer cast through the mesh's [`Bvh`].

use super::bvh::{Bvh, V3, along, cross, dot, normalize, sub};
use crate::error::ReportError;

/// The scanned mesh the repository keeps (the Stanford bunny, npm package `bunny` 1.0.1;
/// `spvg-report/assets/README.md` gives its source and terms).
pub const BUNNY_OBJ: &str = include_str!("../../assets/bunny.obj");

/// The scene's name in the report's tables.
pub const NAME: &str = "bunny";

/// A triangle mesh: vertex positions and triangles of vertex indices.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Vertex positions (world units; `y` up, the ground at `y = 0`).
    pub positions: Vec<V3>,
    /// Triangles (indices into `positions`).
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// Parses a Wavefront OBJ text (every model of it, triangulated; materials ignored).
    ///
    /// # Errors
    ///
    /// [`ReportError::Asset`] naming the mesh when `tobj` rejects the text, a face names
    /// a vertex that does not exist, or it holds no triangle.
    pub fn from_obj(name: &str, text: &str) -> Result<Self, ReportError> {
        let bad = |why: String| ReportError::Asset(format!("mesh {name}: {why}"));
        let opts = tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ..tobj::LoadOptions::default()
        };
        let (models, _) = tobj::load_obj_buf(&mut text.as_bytes(), &opts, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .map_err(|e| bad(e.to_string()))?;
        let mut m = Self::default();
        for model in models {
            let base = m.positions.len() as u32;
            let p = &model.mesh.positions;
            m.positions
                .extend(p.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
            for t in model.mesh.indices.chunks_exact(3) {
                let t = [t[0] + base, t[1] + base, t[2] + base];
                if t.iter().any(|&i| i as usize >= m.positions.len()) {
                    return Err(bad(format!(
                        "a face names vertex {t:?} of {}",
                        m.positions.len()
                    )));
                }
                m.triangles.push(t);
            }
        }
        if m.triangles.is_empty() {
            return Err(bad("no triangle".into()));
        }
        if m.positions.iter().flatten().any(|x| !x.is_finite()) {
            return Err(bad("a vertex is not finite".into()));
        }
        Ok(m)
    }

    /// The repository's bunny ([`BUNNY_OBJ`]).
    ///
    /// # Errors
    ///
    /// As [`from_obj`](Self::from_obj) (not for the kept file: a test loads it).
    pub fn bunny() -> Result<Self, ReportError> {
        Self::from_obj("assets/bunny.obj", BUNNY_OBJ)
    }
}

/// Where the camera looks: about the bunny's centre (it spans `x` in [-5, 5], `y` in
/// [0, 9.7], `z` in [-3.7, 3.8]).
const TARGET: V3 = [0.0, 4.5, 0.0];
/// The camera's distance to [`TARGET`].
const DISTANCE: f32 = 24.0;
/// The camera's elevation above the ground plane, degrees (the top of the frame still
/// looks down at the ground, so every pixel has a surface).
const ELEVATION: f64 = 25.0;
/// The vertical field of view, degrees (the bunny fills about three quarters of the
/// frame's height).
const FOV: f64 = 30.0;
/// The azimuth at frame 0, degrees.
const AZIMUTH: f64 = 30.0;
/// The orbit of the report's mesh scene, degrees per frame (its ground moves up to about
/// 1.5 px per frame at 64x48, the bunny less).
pub const ORBIT: f64 = 1.5;
/// Frames in one cycle of the Halton (2, 3) jitter.
pub const JITTER_CYCLE: u32 = 16;

/// The radical inverse of `i` in `base` (the Halton sequence's coordinate).
#[must_use]
pub fn radical_inverse(mut i: u32, base: u32) -> f64 {
    let (mut f, mut r) = (1.0, 0.0);
    while i > 0 {
        f /= f64::from(base);
        r += f * f64::from(i % base);
        i /= base;
    }
    r
}

/// The sub-pixel jitter of frame `t`: the Halton (2, 3) point `t mod 16 + 1`, centred
/// (each coordinate in `(-0.5, 0.5)`).
#[must_use]
pub fn jitter(t: u32) -> [f32; 2] {
    let i = t % JITTER_CYCLE + 1;
    [radical_inverse(i, 2), radical_inverse(i, 3)].map(|x| (x - 0.5) as f32)
}

/// A camera: its position, its orthonormal frame (right, up, forward), and the tangents
/// of its half field of view (horizontal, vertical).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Position.
    pub eye: V3,
    /// Right, up, forward.
    pub axes: [V3; 3],
    /// `tan` of the half field of view, horizontally and vertically.
    pub half: [f32; 2],
}

impl Camera {
    /// The orbiting camera of a `size` frame at azimuth `degrees`.
    #[must_use]
    pub fn orbit(degrees: f64, size: [u32; 2]) -> Self {
        let (az, el) = (degrees.to_radians(), ELEVATION.to_radians());
        let d = f64::from(DISTANCE);
        let eye = [
            TARGET[0] + (d * el.cos() * az.sin()) as f32,
            TARGET[1] + (d * el.sin()) as f32,
            TARGET[2] + (d * el.cos() * az.cos()) as f32,
        ];
        let forward = normalize(sub(TARGET, eye));
        let right = normalize(cross(forward, [0.0, 1.0, 0.0]));
        let up = cross(right, forward);
        let v = (FOV.to_radians() * 0.5).tan();
        let aspect = f64::from(size[0]) / f64::from(size[1].max(1));
        Self {
            eye,
            axes: [right, up, forward],
            half: [(v * aspect) as f32, v as f32],
        }
    }

    /// The ray direction (unit) through the continuous pixel position `s` of a `size`
    /// frame (pixel centres at half-integers, `y` down).
    #[must_use]
    pub fn ray(&self, s: [f32; 2], size: [u32; 2]) -> V3 {
        let x = (2.0 * s[0] / size[0] as f32 - 1.0) * self.half[0];
        let y = (1.0 - 2.0 * s[1] / size[1] as f32) * self.half[1];
        let [r, u, f] = self.axes;
        normalize(core::array::from_fn(|k| f[k] + x * r[k] + y * u[k]))
    }

    /// The linear depth of `p` (along the forward axis).
    #[must_use]
    pub fn depth(&self, p: V3) -> f32 {
        dot(sub(p, self.eye), self.axes[2])
    }

    /// The continuous pixel position of `p` in a `size` frame (the inverse of
    /// [`ray`](Self::ray)).
    #[must_use]
    pub fn project(&self, p: V3, size: [u32; 2]) -> [f32; 2] {
        let v = sub(p, self.eye);
        let z = dot(v, self.axes[2]);
        let x = dot(v, self.axes[0]) / z / self.half[0];
        let y = dot(v, self.axes[1]) / z / self.half[1];
        [
            (x + 1.0) * 0.5 * size[0] as f32,
            (1.0 - y) * 0.5 * size[1] as f32,
        ]
    }
}

/// One pixel of the G-buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshPixel {
    /// Linear depth.
    pub depth: f32,
    /// The surface point's linear depth under the previous frame's camera.
    pub reprojected_depth: f32,
    /// Motion vector: this frame's pixel position of the surface point minus the
    /// previous frame's, in pixels, without the jitter (`spvg::reproject`'s convention).
    pub motion: [f32; 2],
    /// The surface point.
    pub position: V3,
    /// The unit geometric normal, facing the camera.
    pub normal: V3,
    /// Whether the point is on the mesh (else on the ground plane).
    pub on_mesh: bool,
}

/// The mesh on the ground plane `y = 0`, its hierarchy and the orbit.
#[derive(Clone, Debug)]
pub struct MeshScene {
    /// The mesh.
    pub mesh: Mesh,
    /// Its hierarchy.
    pub bvh: Bvh,
    /// Frame size.
    pub size: [u32; 2],
    /// Degrees of orbit per frame.
    pub orbit: f64,
}

impl MeshScene {
    /// The scene of `mesh` at `size`, orbiting by `orbit` degrees per frame.
    #[must_use]
    pub fn new(mesh: Mesh, size: [u32; 2], orbit: f64) -> Self {
        Self {
            bvh: Bvh::new(&mesh.positions, &mesh.triangles),
            mesh,
            size,
            orbit,
        }
    }

    /// The camera of frame `t` (frame 0's previous camera is itself).
    #[must_use]
    pub fn camera(&self, t: u32) -> Camera {
        Camera::orbit(AZIMUTH + self.orbit * f64::from(t), self.size)
    }

    /// The closest surface along `o + t d`: the mesh or the ground plane; its point, its
    /// geometric normal facing `-d`, and whether it is the mesh (`None`: the ray leaves
    /// the scene).
    #[must_use]
    pub fn cast(&self, o: V3, d: V3) -> Option<(V3, V3, bool)> {
        let plane = (d[1] < 0.0).then(|| -o[1] / d[1]).filter(|&t| t > 0.0);
        let hit = self.bvh.closest(o, d, plane.unwrap_or(f32::INFINITY));
        let (t, n, on_mesh) = match (hit, plane) {
            (Some(h), _) => {
                let [a, b, c] = self.mesh.triangles[h.triangle as usize]
                    .map(|i| self.mesh.positions[i as usize]);
                (h.t, normalize(cross(sub(b, a), sub(c, a))), true)
            }
            (None, Some(t)) => (t, [0.0, 1.0, 0.0], false),
            (None, None) => return None,
        };
        let n = if dot(n, d) > 0.0 { n.map(|x| -x) } else { n };
        Some((along(o, d, t), n, on_mesh))
    }

    /// The surface seen through the continuous pixel position `s` by `camera` (`None`:
    /// none; not at the report's poses, which look down at the ground everywhere).
    #[must_use]
    pub fn surface(&self, camera: &Camera, s: [f32; 2]) -> Option<(V3, V3, bool)> {
        self.cast(camera.eye, camera.ray(s, self.size))
    }

    /// The G-buffer of frame `t`: each pixel's surface through its centre moved by the
    /// frame's [`jitter`]. A pixel without a surface (none at the report's poses) reads
    /// depth 1e30, no motion and an upward normal at the origin.
    #[must_use]
    pub fn gbuffer(&self, t: u32) -> Vec<MeshPixel> {
        let (cam, prev) = (self.camera(t), self.camera(t.saturating_sub(1)));
        let j = jitter(t);
        let [w, h] = self.size;
        let mut out = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            for x in 0..w {
                let s = [x as f32 + 0.5 + j[0], y as f32 + 0.5 + j[1]];
                let px = match self.surface(&cam, s) {
                    Some((position, normal, on_mesh)) => {
                        // The unjittered positions: the history is read at the pixel the
                        // point was at, and the jitter accumulates inside each pixel.
                        let now = cam.project(position, self.size);
                        let before = prev.project(position, self.size);
                        MeshPixel {
                            depth: cam.depth(position),
                            reprojected_depth: prev.depth(position),
                            motion: [now[0] - before[0], now[1] - before[1]],
                            position,
                            normal,
                            on_mesh,
                        }
                    }
                    None => MeshPixel {
                        depth: 1e30,
                        reprojected_depth: 1e30,
                        normal: [0.0, 1.0, 0.0],
                        ..MeshPixel::default()
                    },
                };
                out.push(px);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kept_bunny_loads_whole() {
        let m = Mesh::bunny().expect("the kept file parses");
        // The npm package's counts (positions and cells).
        assert_eq!((m.positions.len(), m.triangles.len()), (1839, 3674));
        let top = m.positions.iter().map(|p| p[1]).fold(f32::MIN, f32::max);
        assert!((top - 9.6547).abs() < 1e-3, "{top}");
        for bad in [
            "",
            "v 0 0 0\nf 1 2 3\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n",
        ] {
            assert!(Mesh::from_obj("bad", bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn the_jitter_is_halton_2_3() {
        assert_eq!(jitter(0), [0.0, (1.0 / 3.0 - 0.5) as f32]);
        assert_eq!(jitter(1), [-0.25, (2.0 / 3.0 - 0.5) as f32]);
        assert_eq!(jitter(2), [0.25, (1.0 / 9.0 - 0.5) as f32]);
        assert_eq!(jitter(JITTER_CYCLE), jitter(0));
        // The cycle's mean is near the pixel centre.
        let m: f32 = (0..JITTER_CYCLE).map(|t| jitter(t)[0]).sum::<f32>() / 16.0;
        assert!(m.abs() < 0.04, "{m}");
    }

    /// The G-buffer agrees with its own definitions: every pixel sees a surface, the
    /// camera projects each point back to the jittered pixel position its ray went
    /// through, the motion vector carries the point to where the previous camera put it,
    /// and a static camera has no motion and the same depth twice.
    #[test]
    fn the_gbuffer_projects_back_and_its_motion_finds_the_previous_pixel() {
        let size = [48, 32];
        let scene = MeshScene::new(Mesh::bunny().expect("bunny"), size, 1.5);
        let t = 5;
        let g = scene.gbuffer(t);
        let (cam, prev) = (scene.camera(t), scene.camera(t - 1));
        let j = jitter(t);
        let on_mesh = g.iter().filter(|p| p.on_mesh).count();
        assert!(
            on_mesh > g.len() / 5 && on_mesh < g.len() * 3 / 4,
            "{on_mesh}"
        );
        for (i, p) in g.iter().enumerate() {
            assert!(p.depth > 0.0 && p.depth < 200.0, "pixel {i}: {p:?}");
            let s = [(i % 48) as f32 + 0.5 + j[0], (i / 48) as f32 + 0.5 + j[1]];
            let back = cam.project(p.position, size);
            assert!((back[0] - s[0]).abs() < 2e-3 && (back[1] - s[1]).abs() < 2e-3);
            let before = prev.project(p.position, size);
            assert!((s[0] - p.motion[0] - before[0]).abs() < 2e-3, "pixel {i}");
            assert!(
                dot(p.normal, cam.ray(s, size)) <= 0.0,
                "pixel {i} faces the camera"
            );
        }
        // Some pixels move by a pixel or more; none by more than 4.
        let most = g
            .iter()
            .map(|p| p.motion[0].hypot(p.motion[1]))
            .fold(0.0, f32::max);
        assert!(most > 0.3 && most < 4.0, "{most}");
        let still = MeshScene::new(scene.mesh.clone(), size, 0.0);
        for p in still.gbuffer(3) {
            assert_eq!(p.motion, [0.0, 0.0]);
            assert_eq!(p.depth, p.reprojected_depth);
        }
    }
}

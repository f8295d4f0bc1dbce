//! Ambient occlusion on the mesh scene, traced on the CPU through its hierarchy: the
//! per-frame sampler (the motion section's estimator: `n` cosine-weighted rays of length
//! [`RANGE`] from the R2 points of the pixel's seed, the fraction that escapes, with the
//! estimates of the first `prefixes` samples) and the converged reference of each frame.

use spvg::sequence::{pcg3d16, r2_offset_from_seed, r2_point, to_unit_f32};

use super::bvh::V3;
use super::scene::{MeshPixel, MeshScene};

/// Length of the occlusion rays (world units; the bunny is 9.7 tall).
pub const RANGE: f32 = 3.0;
/// How far a ray's origin is lifted off its surface along the normal.
const OFFSET: f32 = 1e-3;

/// Whether the ray `o + t d`, `0 < t < RANGE`, hits the mesh or the ground plane.
fn occluded(scene: &MeshScene, o: V3, d: V3) -> bool {
    (d[1] < 0.0 && -o[1] / d[1] < RANGE) || scene.bvh.occluded(o, d, RANGE)
}

/// The fraction of `n` cosine-weighted directions around `normal` at `position` that
/// escape, with directions from the R2 points of `seed` (`pcg3d16` of it offsets them),
/// and the estimates of the first `prefixes[j]` samples (0 where `prefixes[j]` is 0 or
/// above `n`: the value a fixed count of `prefixes[j]` gives, the sequence not depending
/// on the count).
#[must_use]
pub fn estimate(
    scene: &MeshScene,
    seed: [u32; 3],
    position: V3,
    normal: V3,
    n: u32,
    prefixes: [u32; 4],
) -> (f32, [f32; 4]) {
    let mut prefix = [0.0_f32; 4];
    if n == 0 {
        return (0.0, prefix);
    }
    let offset = r2_offset_from_seed(pcg3d16(seed));
    // Orthonormal basis around the normal (Duff et al. 2017), as the AO effect builds it.
    let nrm = normal;
    let sgn = if nrm[2] >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sgn + nrm[2]);
    let b = nrm[0] * nrm[1] * a;
    let t = [1.0 + sgn * nrm[0] * nrm[0] * a, sgn * b, -sgn * nrm[0]];
    let bt = [b, sgn + nrm[1] * nrm[1] * a, -nrm[1]];
    let o: V3 = core::array::from_fn(|i| position[i] + nrm[i] * OFFSET);
    let mut open = 0_u32;
    for m in 0..n {
        let u = r2_point(offset, m);
        let u1 = to_unit_f32(u[0]);
        let (s, c) = (to_unit_f32(u[1]) * core::f32::consts::TAU).sin_cos();
        let r = u1.sqrt();
        let z = (1.0 - u1).sqrt();
        let d: V3 = core::array::from_fn(|i| t[i] * r * c + bt[i] * r * s + nrm[i] * z);
        if !occluded(scene, o, d) {
            open += 1;
        }
        for (j, &k) in prefixes.iter().enumerate() {
            if k == m + 1 {
                prefix[j] = open as f32 / k as f32;
            }
        }
    }
    (open as f32 / n as f32, prefix)
}

/// Frame `t`'s AO per pixel of `g` with `count[i]` samples, and the prefix estimates
/// ([`estimate`]; the seed is the pixel and the frame, as on the AO effect).
#[must_use]
pub fn sample(
    scene: &MeshScene,
    t: u32,
    g: &[MeshPixel],
    count: &[u32],
    prefixes: [u32; 4],
) -> (Vec<f32>, Vec<[f32; 4]>) {
    let w = scene.size[0];
    g.iter()
        .zip(count)
        .enumerate()
        .map(|(i, (p, &n))| {
            let (x, y) = (i as u32 % w, i as u32 / w);
            estimate(scene, [x, y, t], p.position, p.normal, n, prefixes)
        })
        .unzip()
}

/// The sub-pixel positions of the reference per axis (`REFERENCE_GRID^2` per pixel).
pub const REFERENCE_GRID: u32 = 4;

/// Frame `t`'s reference: per pixel, the AO averaged over the pixel's footprint (a
/// `REFERENCE_GRID^2` grid of sub-pixel positions, each with `samples` rays from seeds
/// no run uses), what the jittered frames converge to after a resolve; `threads` share
/// the rows.
#[must_use]
pub fn reference(scene: &MeshScene, t: u32, samples: u32, threads: usize) -> Vec<f32> {
    let [w, h] = scene.size;
    let cam = scene.camera(t);
    let k = REFERENCE_GRID;
    let row = |y: u32| -> Vec<f32> {
        (0..w)
            .map(|x| {
                let mut sum = 0.0_f64;
                for j in 0..k * k {
                    let s = [
                        x as f32 + (j % k) as f32 / k as f32 + 0.5 / k as f32,
                        y as f32 + (j / k) as f32 / k as f32 + 0.5 / k as f32,
                    ];
                    // A surface-less position counts as open (none at the report's poses).
                    sum += scene.surface(&cam, s).map_or(1.0, |(p, n, _)| {
                        // Seeds with the top bit set: the runs' frames never reach it.
                        let seed = [x, y, 0x8000_0000 | (t * k * k + j)];
                        f64::from(estimate(scene, seed, p, n, samples, [0; 4]).0)
                    });
                }
                (sum / f64::from(k * k)) as f32
            })
            .collect()
    };
    let threads = threads.clamp(1, h.max(1) as usize);
    let rows: Vec<Vec<f32>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|i| {
                s.spawn(move || {
                    (0..h)
                        .filter(|y| *y as usize % threads == i)
                        .map(|y| (y, row(y)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        let mut all: Vec<(u32, Vec<f32>)> = handles
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_default())
            .collect();
        all.sort_by_key(|r| r.0);
        all.into_iter().map(|r| r.1).collect()
    });
    rows.concat()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::scene::Mesh;

    /// On the bare ground plane far from the mesh every ray escapes (AO 1 exactly); a
    /// point beside the bunny loses rays; a point facing the plane loses nearly all; the prefixes are the first samples' estimates.
    #[test]
    fn the_sampler_sees_the_ground_and_the_mesh() {
        let scene = MeshScene::new(Mesh::bunny().expect("bunny"), [32, 24], 1.0);
        let up = [0.0, 1.0, 0.0];
        let (far, _) = estimate(&scene, [1, 2, 3], [40.0, 0.0, 40.0], up, 64, [0; 4]);
        assert_eq!(far, 1.0);
        let (down, _) = estimate(
            &scene,
            [1, 2, 3],
            [40.0, 0.5, 40.0],
            [0.0, -1.0, 0.0],
            64,
            [0; 4],
        );
        // Facing the plane from 0.5 above it, a ray escapes only within cos 0.5/RANGE of
        // grazing: 2.8% of a cosine-weighted hemisphere.
        assert!(down < 0.1, "{down}");
        // Beside the bunny's base, the bunny occludes part of the hemisphere.
        let (near, pre) = estimate(&scene, [1, 2, 3], [0.0, 0.0, 4.3], up, 64, [4, 16, 64, 65]);
        assert!(near > 0.3 && near < 0.95, "{near}");
        assert_eq!(pre[2], near);
        assert_eq!(pre[3], 0.0, "a prefix above n is not written");
        let (first16, _) = estimate(&scene, [1, 2, 3], [0.0, 0.0, 4.3], up, 16, [0; 4]);
        assert_eq!(pre[1], first16);
    }

    /// The reference of 256 samples per position barely moves from the first 64 of them
    /// (far below the 1e-4 the runs aim at), and threads do not change it.
    #[test]
    fn the_reference_converges() {
        let scene = MeshScene::new(Mesh::bunny().expect("bunny"), [24, 16], 1.5);
        let a = reference(&scene, 3, 256, 2);
        assert_eq!(a, reference(&scene, 3, 256, 1));
        // The first 64 samples of each position: the reference moves little past them.
        let b = reference(&scene, 3, 64, 2);
        let msd: f64 = a
            .iter()
            .zip(&b)
            .map(|(x, y)| f64::from(x - y).powi(2))
            .sum::<f64>()
            / a.len() as f64;
        assert!(msd < 2e-5, "{msd}");
        assert!(a.iter().all(|x| (0.0..=1.0).contains(x)));
        assert!(a.iter().any(|&x| x < 0.9), "the bunny occludes");
    }
}

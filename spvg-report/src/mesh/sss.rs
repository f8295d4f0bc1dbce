//! The mesh scene as the subsurface section's input (`crate::scene::SceneKind::Mesh`):
//! the bunny under a still camera (frame 0's pose of the orbit, pixel centres, no
//! jitter: the section's scenes are static per lighting state), its depth in mm and its
//! mask (profile 1 on the bunny, 0 on the ground), and the irradiance of a key light
//! (`N . L`, shadowed by the mesh through its hierarchy) and of an ambient term: the
//! basis images the section's quadrature reference integrates.

use std::sync::OnceLock;

use super::bvh::{V3, dot, normalize};
use super::scene::{Mesh, MeshScene};

/// Millimetres per world unit: the camera's distance (24 units) at 1 m, the depth of the
/// section's procedural surface.
pub const MM_PER_UNIT: f32 = 1000.0 / 24.0;

/// The key light's direction (towards the light): from the upper left, in front.
const KEY: V3 = [-0.5, 0.8, 0.6];

/// The bunny and its hierarchy, parsed once (`None` if the kept file did not parse: a
/// test loads it).
fn bunny() -> Option<&'static MeshScene> {
    static BUNNY: OnceLock<Option<MeshScene>> = OnceLock::new();
    BUNNY
        .get_or_init(|| Mesh::bunny().ok().map(|m| MeshScene::new(m, [1, 1], 0.0)))
        .as_ref()
}

/// Per pixel of a `size` frame: the surface's point and normal where it is the bunny.
fn surfaces(size: [u32; 2]) -> Vec<Option<(V3, V3)>> {
    let Some(b) = bunny() else {
        return vec![None; (size[0] * size[1]) as usize];
    };
    let scene = MeshScene { size, ..b.clone() };
    let cam = scene.camera(0);
    (0..size[1])
        .flat_map(|y| (0..size[0]).map(move |x| [x as f32 + 0.5, y as f32 + 0.5]))
        .map(|s| {
            scene
                .surface(&cam, s)
                .filter(|&(_, _, on_mesh)| on_mesh)
                .map(|(p, n, _)| (p, n))
        })
        .collect()
}

/// The depth (mm) and mask of a `size` frame: profile 1 on the bunny, 0 elsewhere (the
/// ground is not subsurface; its depth is its own).
#[must_use]
pub fn geometry(size: [u32; 2]) -> (Vec<f32>, Vec<u8>) {
    let Some(b) = bunny() else {
        let n = (size[0] * size[1]) as usize;
        return (vec![1000.0; n], vec![0; n]);
    };
    let scene = MeshScene { size, ..b.clone() };
    let cam = scene.camera(0);
    (0..size[1])
        .flat_map(|y| (0..size[0]).map(move |x| [x as f32 + 0.5, y as f32 + 0.5]))
        .map(|s| match scene.surface(&cam, s) {
            Some((p, _, on_mesh)) => (cam.depth(p) * MM_PER_UNIT, u8::from(on_mesh)),
            None => (1e6, 0),
        })
        .unzip()
}

/// The basis lighting images of a `size` frame, linear RGB: the key light (`N . L`, 0
/// where the mesh shadows the point) and a constant ambient term; 0 off the bunny.
#[must_use]
pub fn bases(size: [u32; 2]) -> Vec<Vec<[f32; 3]>> {
    let l = normalize(KEY);
    let scene = bunny();
    let (mut key, mut ambient) = (Vec::new(), Vec::new());
    for s in surfaces(size) {
        let (k, a) = match (s, scene) {
            (Some((p, n)), Some(b)) => {
                let o: V3 = core::array::from_fn(|i| p[i] + n[i] * 1e-3);
                let lit = dot(n, l) > 0.0 && !b.bvh.occluded(o, l, f32::INFINITY);
                (if lit { dot(n, l) } else { 0.0 }, 0.05)
            }
            _ => (0.0, 0.0),
        };
        key.push([k, 0.85 * k, 0.75 * k]);
        ambient.push([a, 1.1 * a, 1.3 * a]);
    }
    vec![key, ambient]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bunny covers part of the frame, its depths are about 1 m, the key light leaves
    /// some of it in the mesh's own shadow or facing away, and the ground is masked out.
    #[test]
    fn the_subsurface_inputs_see_the_bunny_lit_and_shadowed() {
        let size = [64, 48];
        let (depth, mask) = geometry(size);
        let on = mask.iter().filter(|&&m| m == 1).count();
        assert!(on > mask.len() / 5 && on < mask.len() * 3 / 4, "{on}");
        for (z, m) in depth.iter().zip(&mask) {
            if *m == 1 {
                assert!(*z > 700.0 && *z < 1300.0, "{z}");
            }
        }
        let b = bases(size);
        assert_eq!(b.len(), 2);
        let key = &b[0];
        let dark = key
            .iter()
            .zip(&mask)
            .filter(|(k, m)| **m == 1 && k[0] == 0.0)
            .count();
        let lit = key
            .iter()
            .zip(&mask)
            .filter(|(k, m)| **m == 1 && k[0] > 0.3)
            .count();
        assert!(dark > 0 && lit > on / 3, "dark {dark}, lit {lit} of {on}");
        assert!(key.iter().zip(&mask).all(|(k, m)| *m == 1 || k[0] == 0.0));
    }
}

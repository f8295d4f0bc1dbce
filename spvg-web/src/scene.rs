//! What the page renders: the ambient-occlusion effect's scene (`spvg_effects::ao`, a plane
//! with spheres seen from above) under a camera a person pans and orbits about the view
//! axis, with a floating sphere they move; and the scripted path of the browser check.

use spvg_effects::ao::{AoParams, AoScene, Motion};

/// The camera and the floating sphere of one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// World xy of the frame centre (1 world unit is 1 pixel).
    pub centre: [f32; 2],
    /// The camera's rotation about the view axis, in degrees.
    pub angle: f32,
    /// World xy of the floating sphere's centre.
    pub object: [f32; 2],
}

impl Default for View {
    /// The effect's static camera (`spvg_effects::ao::ORIGIN`), the sphere beside it.
    fn default() -> Self {
        let [x, y] = spvg_effects::ao::ORIGIN;
        Self {
            centre: [x, y],
            angle: 0.0,
            object: [x - 60.0, y + 10.0],
        }
    }
}

impl View {
    /// The camera block of `AoParams`: centre, cos and sin of the rotation.
    fn camera(&self) -> [f32; 4] {
        let a = f64::from(self.angle).to_radians();
        [
            self.centre[0],
            self.centre[1],
            a.cos() as f32,
            a.sin() as f32,
        ]
    }

    /// World xy under pixel position `p` of a `width x height` frame (the inverse of the
    /// effect's `ao_pixel` at rest height).
    #[must_use]
    pub fn world(&self, [width, height]: [u32; 2], p: [f32; 2]) -> [f32; 2] {
        let [cx, cy, c, s] = self.camera();
        let q = [p[0] - 0.5 * width as f32, p[1] - 0.5 * height as f32];
        [cx + (c * q[0] - s * q[1]), cy + (s * q[0] + c * q[1])]
    }

    /// Pans by `d` pixels of the screen (the camera moves, the scene follows the pointer:
    /// a drag to the right moves the view's centre left in world units).
    pub fn pan(&mut self, d: [f32; 2]) {
        let [_, _, c, s] = self.camera();
        self.centre[0] -= c * d[0] - s * d[1];
        self.centre[1] -= s * d[0] + c * d[1];
    }
}

/// The floating sphere's height and radius: those of the effect's
/// [`Motion::MovingSphere`] (its cap stands more than the depth test's 2% above every
/// static surface, so the surface it uncovers is a disocclusion).
fn floating_sphere() -> [f32; 2] {
    let m = AoScene {
        width: 1,
        height: 1,
        motion: Motion::MovingSphere { speed: 0.0 },
    }
    .params(0)
    .mover;
    [m[2], m[3]]
}

/// The uniform block of frame `t` of a `width x height` frame seen from `view`, whose
/// previous frame was seen from `previous` (motion vectors and reprojected depths follow
/// from both).
#[must_use]
pub fn params(width: u32, height: u32, t: u32, view: &View, previous: &View) -> AoParams {
    let base = AoScene {
        width,
        height,
        motion: Motion::Static,
    }
    .params(t);
    let [z, r] = floating_sphere();
    let [x, y] = view.object;
    let [px, py] = previous.object;
    AoParams {
        camera: view.camera(),
        previous_camera: previous.camera(),
        mover: [x, y, z, r],
        mover_velocity: [x - px, y - py, 0.0, 0.0],
        ..base
    }
}

/// The scripted path of the browser check (`?check=N`) over `frames` frames: for the
/// first two thirds the camera pans 2 px and orbits 0.75 degrees per frame while the
/// sphere crosses at 3 px per frame (reprojection, disocclusion, pixels entering the
/// frame); for the last third everything holds still, so the TAA converges towards the
/// reference of the last view ([`check_view`]`(frames - 1, frames)`).
#[must_use]
pub fn check_view(t: u32, frames: u32) -> View {
    let moving = (2 * frames).div_ceil(3);
    let s = t.min(moving.saturating_sub(1)) as f32;
    let home = View::default();
    View {
        centre: [home.centre[0] + 2.0 * s, home.centre[1]],
        angle: 0.75 * s,
        object: [home.object[0] + 3.0 * s, home.object[1] + 0.5 * s],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn world_inverts_the_effects_pixel_mapping() {
        let size = [96, 64];
        let view = View {
            angle: 30.0,
            ..View::default()
        };
        let p = params(size[0], size[1], 0, &view, &view);
        for q in [[0.5, 0.5], [40.25, 17.5], [95.5, 63.5]] {
            let w = view.world(size, q);
            let back = spvg_effects::ao::twin::pixel(&p, w, p.camera, p.lens);
            assert!(
                (back[0] - q[0]).abs() < 1e-3 && (back[1] - q[1]).abs() < 1e-3,
                "{q:?} -> {w:?} -> {back:?}"
            );
        }
    }

    #[test]
    fn a_pan_moves_the_world_under_the_pointer_with_it() {
        let size = [96, 64];
        let mut view = View {
            angle: 60.0,
            ..View::default()
        };
        let grabbed = view.world(size, [30.5, 20.5]);
        view.pan([7.0, -3.0]);
        let now = view.world(size, [37.5, 17.5]);
        assert!(
            (now[0] - grabbed[0]).abs() < 1e-3 && (now[1] - grabbed[1]).abs() < 1e-3,
            "{grabbed:?} is now under the pointer at {now:?}"
        );
    }

    #[test]
    fn the_check_path_moves_then_holds() {
        let n = 30;
        assert_ne!(check_view(0, n), check_view(1, n), "frame 1 moves");
        assert_ne!(check_view(18, n), check_view(19, n), "frame 19 moves");
        for t in 20..n {
            assert_eq!(check_view(t, n), check_view(n - 1, n), "frame {t} holds");
        }
        let p = params(64, 48, 5, &check_view(5, n), &check_view(4, n));
        assert_eq!(
            p.mover_velocity,
            [3.0, 0.5, 0.0, 0.0],
            "the sphere's motion"
        );
    }
}

//! # The second consumer: stochastic ambient occlusion on a procedural height field
//!
//! A renderer that is not subsurface scattering, built on the adaptive component
//! ([`spvg_wgpu::adaptive`]): per frame, a G-buffer pass (`ao_gbuffer`: depth, motion vectors,
//! position, normal), the component's estimate, the AO sampling pass (`ao_sample`: `count`
//! cosine-weighted occlusion rays of length 16 px per pixel, the fraction that escapes),
//! and the component's update with the AO estimate as the monitored value (AS: no control
//! variate). [`AoPass`] runs it on a device (WGSL: `ao/ao.wgsl`), [`AoTwin`] on the CPU
//! ([`twin`] mirrors each entry point in Rust).
//!
//! The scene ([`AoScene`]): the plane `z = 0` with one sphere per 64-pixel cell (centre
//! jittered by a hash of the cell, radius 4..12 px, from half buried to resting on the
//! plane), and up to three extra spheres and a thin bar that can move across it (each
//! object's surface carries its own motion); seen from above by an orthographic
//! camera (1 world unit = 1 pixel at height 100) that can pan, rotate, and dolly towards
//! the plane with a zoom that follows the height ([`Motion`]). Besides the depth and motion
//! vectors, the G-buffer writes the reprojected depth (each pixel's surface point as the
//! previous camera saw it), which the component's depth test compares
//! ([`AoPass::set_reprojected_depth`]).

mod pass;
pub mod twin;

pub use pass::{AoFrame, AoGuide, AoMode, AoPass};
pub use twin::AoTwin;

/// The uniform block of `ao/ao.wgsl`.
///
/// WGSL twin: `struct AoParams` in `ao/ao.wgsl`; same field order and types.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct AoParams {
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// Frame index (seeds the sample sequence).
    pub frame: u32,
    /// Padding (0).
    pub pad: u32,
    /// World xy of the frame centre, cos and sin of the camera rotation.
    pub camera: [f32; 4],
    /// The same for the previous frame.
    pub previous_camera: [f32; 4],
    /// The moving sphere: centre xyz and radius (radius 0: no sphere).
    pub mover: [f32; 4],
    /// The moving sphere's motion since the previous frame (xyz, 0).
    pub mover_velocity: [f32; 4],
    /// The camera's lens: its height above the plane (the depth of the plane), world units
    /// per pixel and pixels per world unit (1 and 1 at height 100), 0.
    pub lens: [f32; 4],
    /// The same for the previous frame.
    pub previous_lens: [f32; 4],
    /// Added to every motion vector the G-buffer writes (xy, pixels; 0, 0): 0 for a
    /// correct motion buffer; a test or the report sets it to model a broken one.
    pub motion_bias: [f32; 4],
    /// Sample counts whose partial estimates the sampling pass also writes (0: none):
    /// the estimate of a pixel's first `prefixes[j]` samples is what a fixed count of
    /// `prefixes[j]` gives, bit for bit, because the sample sequence does not depend on
    /// the count; so one fixed-count run yields the runs of smaller counts too. Set by
    /// [`AoPass::set_prefix_counts`] (the scene leaves it 0).
    pub prefixes: [u32; 4],
    /// Two more moving spheres (centre xyz and radius each; radius 0: none), tested
    /// after [`mover`](Self::mover).
    pub extra_movers: [[f32; 4]; 2],
    /// Their motion since the previous frame (xyz, 0 each).
    pub extra_velocities: [[f32; 4]; 2],
    /// The moving bar: an axis-aligned box, its low corner (xyz, 0); no bar where the
    /// high corner is not above it on every axis.
    pub bar_min: [f32; 4],
    /// The moving bar's high corner (xyz, 0).
    pub bar_max: [f32; 4],
    /// The moving bar's motion since the previous frame (xyz, 0).
    pub bar_velocity: [f32; 4],
}

const _: () = assert!(
    size_of::<AoParams>() == 256,
    "AoParams must match the 256-byte WGSL struct"
);

/// How the camera and the moving sphere move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// Nothing moves.
    Static,
    /// The camera pans along `+x` at `speed` pixels per frame (the scene moves left on
    /// screen; integer speeds keep every pixel centre on the world's half-integer grid).
    Pan {
        /// Pixels per frame.
        speed: f32,
    },
    /// The camera rotates about the frame centre by `degrees` per frame.
    Rotate {
        /// Degrees per frame.
        degrees: f32,
    },
    /// A sphere of radius 10 px floats across the frame (centre 26 px above the plane, so
    /// its visible cap is more than 2% of the depth above every static surface) at `speed`
    /// pixels per frame; the camera is static. The surface behind it is uncovered by motion
    /// (disocclusion).
    MovingSphere {
        /// Pixels per frame.
        speed: f32,
    },
    /// The camera moves towards the plane by `rate` world units per frame, from height
    /// [`CAMERA_HEIGHT`] down to [`DOLLY_NEAREST`] and back (a triangle wave), and zooms
    /// with it (pixels per world unit `100 / height`, as the image of the plane grows in a
    /// perspective camera that moves closer): every depth changes by `rate` per frame (3%
    /// of the plane's depth and more at `rate` 3), and the motion vectors point away from
    /// the centre (towards it on the way back).
    Dolly {
        /// World units per frame.
        rate: f32,
    },
    /// Several objects cross the frame at `speed` pixels per frame in different directions,
    /// the camera static: three floating spheres (radius 9 along `+x`, radius 7 along `-x`,
    /// radius 8 along `+y`) and a thin bar (3 px wide, 40 px long, its top 14 px above the
    /// plane, within reach of the rays from the ground under it) moving across its width
    /// along `+x`. Faster and with more, and thinner, disoccluded regions than
    /// [`MovingSphere`](Self::MovingSphere): the bar uncovers a strip as wide as its motion
    /// every frame, and a 3 px strip of young pixels has few neighbours with history.
    MovingObjects {
        /// Pixels per frame.
        speed: f32,
    },
}

/// The moving bar of [`Motion::MovingObjects`]: its width (along its motion, `x`), length
/// (`y`), and the heights of its bottom and top.
pub const BAR: [f32; 4] = [3.0, 40.0, 11.0, 14.0];

/// The camera's height above the plane at rest (the plane's depth).
pub const CAMERA_HEIGHT: f32 = 100.0;

/// The height the dolly ([`Motion::Dolly`]) turns back at (at most; a whole number of
/// steps of its rate from [`CAMERA_HEIGHT`]).
pub const DOLLY_NEAREST: f32 = 60.0;

/// The lens block at camera height `h` (`AoParams::lens`).
fn lens(h: f32) -> [f32; 4] {
    [h, h / CAMERA_HEIGHT, CAMERA_HEIGHT / h, 0.0]
}

impl Motion {
    /// Short name for tables and files (`static`, `pan4`, `rotate1`, `object3`, `dolly3`,
    /// `objects5`).
    #[must_use]
    pub fn name(&self) -> String {
        match self {
            Self::Static => "static".into(),
            Self::Pan { speed } => format!("pan{speed}"),
            Self::Rotate { degrees } => format!("rotate{degrees}"),
            Self::MovingSphere { speed } => format!("object{speed}"),
            Self::Dolly { rate } => format!("dolly{rate}"),
            Self::MovingObjects { speed } => format!("objects{speed}"),
        }
    }
}

/// The AO scene: frame size and motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AoScene {
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// What moves.
    pub motion: Motion,
}

/// Where the static camera looks (world xy of the frame centre).
pub const ORIGIN: [f32; 2] = [40.0, 24.0];

impl AoScene {
    fn camera(&self, t: u32) -> [f32; 4] {
        let t = t as f32;
        match self.motion {
            Motion::Pan { speed } => [ORIGIN[0] + speed * t, ORIGIN[1], 1.0, 0.0],
            Motion::Rotate { degrees } => {
                let a = (f64::from(degrees) * f64::from(t)).to_radians();
                [ORIGIN[0], ORIGIN[1], a.cos() as f32, a.sin() as f32]
            }
            _ => [ORIGIN[0], ORIGIN[1], 1.0, 0.0],
        }
    }

    /// The camera's height at frame `t`.
    fn height(&self, t: u32) -> f32 {
        match self.motion {
            Motion::Dolly { rate } if rate > 0.0 => {
                // Steps of `rate` down to DOLLY_NEAREST at most, then back up, and again.
                let steps = ((CAMERA_HEIGHT - DOLLY_NEAREST) / rate).floor().max(1.0) as u32;
                let k = t % (2 * steps);
                let k = if k > steps { 2 * steps - k } else { k };
                CAMERA_HEIGHT - rate * k as f32
            }
            _ => CAMERA_HEIGHT,
        }
    }

    fn mover(&self, t: u32) -> [f32; 4] {
        match self.motion {
            Motion::MovingSphere { speed } => {
                let w = self.width as f32;
                // Enters at the left edge, leaves at the right, then again.
                let span = w + 24.0;
                let x = (speed * t as f32) % span - 12.0;
                [ORIGIN[0] - 0.5 * w + x, ORIGIN[1] + 2.0, 26.0, 10.0]
            }
            Motion::MovingObjects { speed } => self.crossing(OBJECT_SPHERES[0], speed, t),
            _ => [0.0; 4],
        }
    }

    /// The two further spheres of [`Motion::MovingObjects`] (radius 0 otherwise).
    fn extra_movers(&self, t: u32) -> [[f32; 4]; 2] {
        match self.motion {
            Motion::MovingObjects { speed } => {
                [1, 2].map(|k| self.crossing(OBJECT_SPHERES[k], speed, t))
            }
            _ => [[0.0; 4]; 2],
        }
    }

    /// The bar of [`Motion::MovingObjects`] as its low and high corners (all 0 otherwise:
    /// no bar).
    fn bar(&self, t: u32) -> [[f32; 4]; 2] {
        match self.motion {
            Motion::MovingObjects { speed } => {
                let [width, length, bottom, top] = BAR;
                // Its centre line crosses like a sphere of radius width / 2 along +x.
                let c = self.crossing(
                    ObjectPath {
                        axis: Axis::PlusX,
                        across: 0.0,
                        phase: 20.0,
                        sphere: [0.0, 0.5 * width],
                    },
                    speed,
                    t,
                );
                [
                    [c[0] - 0.5 * width, c[1] - 0.5 * length, bottom, 0.0],
                    [c[0] + 0.5 * width, c[1] + 0.5 * length, top, 0.0],
                ]
            }
            _ => [[0.0; 4]; 2],
        }
    }

    /// Where `path` is at frame `t` at `speed` px per frame: centre xyz and radius. It
    /// enters at one edge of the frame, leaves at the other, then again.
    fn crossing(&self, path: ObjectPath, speed: f32, t: u32) -> [f32; 4] {
        let (w, h) = (self.width as f32, self.height as f32);
        let [z, r] = path.sphere;
        let margin = r + 2.0;
        let extent = match path.axis {
            Axis::PlusX | Axis::MinusX => w,
            Axis::PlusY => h,
        };
        let along = (speed * t as f32 + path.phase) % (extent + 2.0 * margin) - margin;
        // Across the path, a fraction of the half frame.
        let across = path.across
            * 0.5
            * match path.axis {
                Axis::PlusX | Axis::MinusX => h,
                Axis::PlusY => w,
            };
        // Frame coordinates (pixels from the top-left corner) to world xy.
        let (left, top) = (ORIGIN[0] - 0.5 * w, ORIGIN[1] - 0.5 * h);
        match path.axis {
            Axis::PlusX => [left + along, ORIGIN[1] + across, z, r],
            Axis::MinusX => [left + (w - along), ORIGIN[1] + across, z, r],
            Axis::PlusY => [ORIGIN[0] + across, top + along, z, r],
        }
    }

    /// The uniform block of frame `t` (frame 0's previous frame is itself).
    #[must_use]
    pub fn params(&self, t: u32) -> AoParams {
        let prev = t.saturating_sub(1);
        let reach = 2.0 * self.width.max(self.height) as f32 / 3.0;
        let (m, mp) = (self.mover(t), self.mover(prev));
        let (extra, extra_before) = (self.extra_movers(t), self.extra_movers(prev));
        let (bar, bar_before) = (self.bar(t), self.bar(prev));
        AoParams {
            width: self.width,
            height: self.height,
            frame: t,
            pad: 0,
            camera: self.camera(t),
            previous_camera: self.camera(prev),
            mover: m,
            mover_velocity: velocity(m, mp, reach),
            lens: lens(self.height(t)),
            previous_lens: lens(self.height(prev)),
            motion_bias: [0.0; 4],
            prefixes: [0; 4],
            extra_movers: extra,
            extra_velocities: [0, 1].map(|k| velocity(extra[k], extra_before[k], reach)),
            bar_min: bar[0],
            bar_max: bar[1],
            bar_velocity: velocity(bar[0], bar_before[0], reach),
        }
    }
}

/// The motion of an object from `before` to `now` (xyz, 0); where it jumped further than
/// `reach` (it left the frame and re-entered at the other edge) it was not on screen
/// before, and a motion that points far outside the previous frame says so.
fn velocity(now: [f32; 4], before: [f32; 4], reach: f32) -> [f32; 4] {
    let d = [now[0] - before[0], now[1] - before[1], now[2] - before[2]];
    if d[0].abs().max(d[1].abs()) > reach {
        [1.0e9, 0.0, 0.0, 0.0]
    } else {
        [d[0], d[1], d[2], 0.0]
    }
}

/// The direction an object of [`Motion::MovingObjects`] crosses the frame in.
#[derive(Clone, Copy)]
enum Axis {
    PlusX,
    MinusX,
    PlusY,
}

/// The path of one object of [`Motion::MovingObjects`]: its direction, its offset across
/// it from the frame centre (a fraction of the half frame across it), how far along it is at frame 0 (px), its centre height
/// and radius.
#[derive(Clone, Copy)]
struct ObjectPath {
    axis: Axis,
    across: f32,
    phase: f32,
    sphere: [f32; 2],
}

/// The spheres of [`Motion::MovingObjects`]: each floats clear of the plane (its bottom
/// 13 px above it and more) and crosses its own part of the frame.
const OBJECT_SPHERES: [ObjectPath; 3] = [
    ObjectPath {
        axis: Axis::PlusX,
        across: -0.5,
        phase: 0.0,
        sphere: [24.0, 9.0],
    },
    ObjectPath {
        axis: Axis::MinusX,
        across: 0.55,
        phase: 50.0,
        sphere: [20.0, 7.0],
    },
    ObjectPath {
        axis: Axis::PlusY,
        across: 0.5,
        phase: 10.0,
        sphere: [22.0, 8.0],
    },
];

/// The WGSL of the AO consumer (`ao/ao.wgsl`), to be joined after the library functions
/// it calls ([`ao_source`] does).
pub const AO_WGSL: &str = include_str!("ao.wgsl");

/// `ao_sample_classified` (`ao/ao_classified.wgsl`), joined after [`AO_WGSL`] and the
/// component's decoder of a classified dispatch.
const AO_CLASSIFIED_WGSL: &str = include_str!("ao_classified.wgsl");

/// `ao_sample_one_pass` (`ao/ao_one_pass.wgsl`), joined after [`AO_WGSL`] and the
/// component's one-pass module.
const AO_ONE_PASS_WGSL: &str = include_str!("ao_one_pass.wgsl");

/// The whole AO module: the functions it calls ([`spvg_shaders::WGSL`] for the sample
/// sequence, the crate's `common/direction.wgsl` for `unit_dir`, the component's decoder
/// of a classified dispatch), then `ao/ao.wgsl` and `ao/ao_classified.wgsl`.
#[must_use]
pub fn ao_source() -> String {
    crate::gpu::assemble(&[
        ("spvg_shaders::WGSL", spvg_shaders::WGSL),
        ("common/direction.wgsl", crate::common::DIRECTION_WGSL),
        (
            "spvg_wgpu AdaptivePass::CLASSIFIED_WGSL",
            spvg_wgpu::adaptive::AdaptivePass::CLASSIFIED_WGSL,
        ),
        ("ao/ao.wgsl", AO_WGSL),
        ("ao/ao_classified.wgsl", AO_CLASSIFIED_WGSL),
    ])
}

/// The AO module of the one-pass form: as [`ao_source`] without the classified entry, with
/// the component's one-pass module (`one_pass`, its bindings at group
/// [`ONE_PASS_GROUP`]) and `ao/ao_one_pass.wgsl`.
#[must_use]
pub fn ao_one_pass_source(one_pass: &str) -> String {
    crate::gpu::assemble(&[
        ("spvg_shaders::WGSL", spvg_shaders::WGSL),
        ("common/direction.wgsl", crate::common::DIRECTION_WGSL),
        ("ao/ao.wgsl", AO_WGSL),
        ("spvg_wgpu AdaptivePass::one_pass_wgsl", one_pass),
        ("ao/ao_one_pass.wgsl", AO_ONE_PASS_WGSL),
    ])
}

/// The group of the component's bindings in the one-pass AO module (the effect's own are
/// group 0).
pub const ONE_PASS_GROUP: u32 = 1;

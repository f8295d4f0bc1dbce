//! Procedural, deterministic evaluation scenes (docs/algorithms.md §7) on a Burley surface.
//!
//! Every scene's lighting is a sum of basis images scaled by per-frame intensities,
//! `B(t) = sum_k I_k(t) B_k(s(t))`, where `s(t)` is a geometry/shadow state index. The
//! pass is linear in the lighting for a fixed geometry, so the converged reference is
//! `sum_k I_k(t) Ref_k(s(t))` with one quadrature per (state, basis) (see
//! [`crate::reference`]).
//!
//! Units: depth in mm; the texel is `w_px = 1e-3` of the depth, so 1 mm at the surface's
//! 1 m: skin1's red profile (`d` = 1.07 mm) spans a few pixels, marble's more.

use half::f16;

use crate::wgpu_api::FrameInputs;
use spvg::sequence::pcg3d16;

/// Frames per second of every scene.
pub const FPS: f32 = 60.0;

/// The four dynamic-lighting scenes of docs/algorithms.md §7.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SceneKind {
    /// Constant lighting with a shadow edge and a depth discontinuity.
    Static,
    /// The key light flashes: `I(t) = sin(2 pi 5 t) + 1` at 60 fps.
    Flash,
    /// The key light switches off and on every 3 s (first switch at t = 1 s so that short
    /// runs see one), plus a small light flickering every frame.
    Switch,
    /// A shadow bar sweeps across the surface and an opaque disc moves in front of it,
    /// uncovering surface (disocclusion).
    Occluders,
    /// The scanned bunny under a still camera and a shadowing key light
    /// ([`crate::mesh::sss`]).
    Mesh,
}

impl SceneKind {
    /// All scenes in report order.
    pub const ALL: [Self; 4] = [Self::Static, Self::Flash, Self::Switch, Self::Occluders];

    /// What the scene shows, in one sentence (for the report).
    #[must_use]
    pub fn description(&self) -> &'static str {
        match self {
            Self::Static => {
                "Constant lighting on a skin surface with a shadow edge and a depth step: the steady state, where adaptive sampling should match fixed64 with far fewer samples."
            }
            Self::Flash => {
                "The key light flashes at 5 Hz (I(t) = sin(2 pi 5 t) + 1 at 60 fps): temporal change that plain adaptive sampling mistakes for noise."
            }
            Self::Switch => {
                "The key light switches off and on every 3 s (first at 1 s) while a small light flickers every frame: a sudden jump in the monitored variance."
            }
            Self::Occluders => {
                "A shadow bar sweeps across the surface and an opaque disc moves in front of it, uncovering surface without history (disocclusion)."
            }
            Self::Mesh => {
                "The Stanford bunny (a scanned mesh, spvg-report/assets) under a key light that it shadows itself, on a ground that is not subsurface: content nobody here modelled."
            }
        }
    }

    /// Lower-case name.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Static => "static",
            Self::Flash => "flash",
            Self::Switch => "switch",
            Self::Occluders => "occluders",
            Self::Mesh => crate::mesh::scene::NAME,
        }
    }
}

/// Per-pixel geometry of one state: view depth (mm) and subsurface mask.
#[derive(Clone, Debug, PartialEq)]
pub struct Geometry {
    /// View depth in mm.
    pub depth: Vec<f32>,
    /// 1 on the subsurface material, 0 elsewhere.
    pub mask: Vec<u8>,
}

/// The lighting of one frame: its state and the intensity of each basis image.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameLights {
    /// Geometry/shadow state (index into the scene's distinct states).
    pub state: u32,
    /// Intensity of each basis light.
    pub intensities: Vec<f32>,
}

/// A scene at a resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scene {
    /// Which scene.
    pub kind: SceneKind,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Spatial variation of the lights.
    pub lighting: Lighting,
}

/// Depth of the main surface and of the part behind the depth discontinuity, mm.
const Z_NEAR: f32 = 1000.0;
const Z_FAR: f32 = 1080.0;
/// Depth of the occluding disc, mm.
const Z_DISC: f32 = 800.0;

/// The spatial variation of the lights away from shadow edges.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Lighting {
    /// Constant irradiance except at shadow edges (docs/algorithms.md §7's "constant lighting with a shadow
    /// edge"): flat regions have zero Monte Carlo variance, so the variance sits at edges.
    #[default]
    Constant,
    /// A gentle variation (wavelengths of ~90 and ~125 pixels, +-15%, and a 25% falloff
    /// down the image): every pixel has some Monte Carlo variance.
    Gradient,
}

fn smooth_texture(lighting: Lighting, x: f32, y: f32) -> f32 {
    // Irradiance from a light is smooth except at shadow edges. A pore-scale texture
    // (periods of a few pixels) was tried first: it spreads similar Monte Carlo variance
    // over every pixel, where a per-pixel variance target cannot beat a fixed count in MSE.
    match lighting {
        Lighting::Constant => 1.0,
        Lighting::Gradient => 0.85 + 0.15 * (x * 0.07).sin() * (y * 0.05).sin(),
    }
}

impl Scene {
    /// A scene of `kind` at `width x height` with [`Lighting::Constant`].
    #[must_use]
    pub fn new(kind: SceneKind, width: u32, height: u32) -> Self {
        Self {
            kind,
            width,
            height,
            lighting: Lighting::Constant,
        }
    }

    fn len(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Motion of the occluders: two pixels every 4 frames (a state), so a 96-frame run
    /// has 24 states, each with its own reference.
    fn occluder_offset(state: u32) -> f32 {
        2.0 * state as f32
    }

    /// Lights of frame `t`.
    #[must_use]
    pub fn lights(&self, t: u32) -> FrameLights {
        let time = t as f32 / FPS;
        match self.kind {
            SceneKind::Static | SceneKind::Mesh => FrameLights {
                state: 0,
                intensities: vec![1.0, 1.0],
            },
            SceneKind::Flash => FrameLights {
                state: 0,
                intensities: vec![(2.0 * core::f32::consts::PI * 5.0 * time).sin() + 1.0, 1.0],
            },
            SceneKind::Switch => {
                // On for t < 1 s, then toggles every 3 s.
                let on = if time < 1.0 {
                    true
                } else {
                    ((time - 1.0) / 3.0).floor() as i64 % 2 == 1
                };
                let flicker = 0.6 + 0.4 * (pcg3d16([t, 7, 11])[0] as f32 / 65535.0);
                FrameLights {
                    state: 0,
                    intensities: vec![if on { 1.0 } else { 0.0 }, 1.0, flicker],
                }
            }
            SceneKind::Occluders => FrameLights {
                state: t / 4,
                intensities: vec![1.0, 1.0],
            },
        }
    }

    /// Geometry of a state.
    #[must_use]
    pub fn geometry(&self, state: u32) -> Geometry {
        if self.kind == SceneKind::Mesh {
            let (depth, mask) = crate::mesh::sss::geometry([self.width, self.height]);
            return Geometry { depth, mask };
        }
        let (w, h) = (self.width as f32, self.height as f32);
        let mut depth = vec![Z_NEAR; self.len()];
        let mut mask = vec![1_u8; self.len()];
        for (i, (z, m)) in depth.iter_mut().zip(mask.iter_mut()).enumerate() {
            let x = (i % self.width as usize) as f32 + 0.5;
            let y = (i / self.width as usize) as f32 + 0.5;
            if x >= 0.62 * w {
                *z = Z_FAR;
            }
            if y >= 0.88 * h {
                *m = 0;
            }
            if self.kind == SceneKind::Occluders {
                let cx = 0.2 * w + Self::occluder_offset(state);
                let cy = 0.45 * h;
                let r = 0.14 * h;
                if (x - cx).powi(2) + (y - cy).powi(2) < r * r {
                    *z = Z_DISC;
                    *m = 0;
                }
            }
        }
        Geometry { depth, mask }
    }

    /// Basis lighting images of a state, linear RGB (f32), in the order of
    /// [`FrameLights::intensities`].
    #[must_use]
    pub fn bases(&self, state: u32) -> Vec<Vec<[f32; 3]>> {
        if self.kind == SceneKind::Mesh {
            return crate::mesh::sss::bases([self.width, self.height]);
        }
        let (w, h) = (self.width as f32, self.height as f32);
        let px = |i: usize| {
            (
                (i % self.width as usize) as f32 + 0.5,
                (i / self.width as usize) as f32 + 0.5,
            )
        };
        let key: Vec<[f32; 3]> = (0..self.len())
            .map(|i| {
                let (x, y) = px(i);
                let tex = smooth_texture(self.lighting, x, y);
                // Hard shadow edge along a diagonal, soft falloff across the surface.
                let lit = if x + 0.5 * y < 0.5 * w { 1.0 } else { 0.08 };
                let falloff = match self.lighting {
                    Lighting::Constant => 1.0,
                    Lighting::Gradient => 0.75 + 0.25 * (1.0 - y / h),
                };
                let mut shade = lit * falloff;
                if self.kind == SceneKind::Occluders {
                    let bar = 0.8 * w - Self::occluder_offset(state);
                    if (x - bar).abs() < 0.07 * w {
                        shade *= 0.1;
                    }
                }
                [shade * tex, 0.85 * shade * tex, 0.75 * shade * tex]
            })
            .collect();
        let ambient: Vec<[f32; 3]> = (0..self.len())
            .map(|i| {
                let (x, y) = px(i);
                let t = 0.05 * smooth_texture(self.lighting, x, y);
                [t, 1.1 * t, 1.3 * t]
            })
            .collect();
        let mut out = vec![key, ambient];
        if self.kind == SceneKind::Switch {
            let (cx, cy, r) = (0.3 * w, 0.3 * h, 0.08 * w);
            out.push(
                (0..self.len())
                    .map(|i| {
                        let (x, y) = px(i);
                        let g = (-((x - cx).powi(2) + (y - cy).powi(2)) / (r * r)).exp();
                        let t = 0.6 * g * smooth_texture(self.lighting, x, y);
                        [t, 0.7 * t, 0.4 * t]
                    })
                    .collect(),
            );
        }
        out
    }

    /// The pass inputs of frame `t`, quantised to the texture formats.
    #[must_use]
    pub fn inputs(&self, t: u32) -> FrameInputs {
        let lights = self.lights(t);
        let g = self.geometry(lights.state);
        let bases = self.bases(lights.state);
        let lighting = (0..self.len())
            .map(|i| {
                let mut c = [0.0_f32; 3];
                for (b, k) in bases.iter().zip(&lights.intensities) {
                    if let Some(v) = b.get(i) {
                        for ch in 0..3 {
                            c[ch] += k * v[ch];
                        }
                    }
                }
                [
                    f16::from_f32(c[0]),
                    f16::from_f32(c[1]),
                    f16::from_f32(c[2]),
                    f16::ONE,
                ]
            })
            .collect();
        FrameInputs {
            width: self.width,
            height: self.height,
            lighting,
            depth: g.depth,
            mask: g.mask,
        }
    }
}

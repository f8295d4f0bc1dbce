//! What the floor study sweeps, and what its two effects' sweeps share.

/// The resolve's blend weight of the current frame (the report's, `crate::taa::WEIGHT`).
pub const TAA_WEIGHT: f32 = crate::taa::WEIGHT;

/// `log2(spp)` of `curve` (sorted by spp, PSNR rising; `key` gives a point's spp, PSNR and
/// flicker) interpolated linearly in PSNR at `psnr`, and the flicker interpolated the same
/// way; `None` outside the curve.
pub(super) fn at_psnr<F>(
    curve: &[F],
    psnr: f64,
    key: impl Fn(&F) -> [f64; 3],
) -> Option<(f64, f64)> {
    curve.windows(2).find_map(|w| {
        let ([sa, pa, fa], [sb, pb, fb]) = (key(&w[0]), key(&w[1]));
        let (lo, hi) = (pa.min(pb), pa.max(pb));
        (psnr >= lo && psnr <= hi && hi > lo).then(|| {
            let s = (psnr - pa) / (pb - pa);
            let l = sa.log2() + s * (sb.log2() - sa.log2());
            (l.exp2(), fa + s * (fb - fa))
        })
    })
}

/// The label a sweep adds for the resolved-image rule's weight (nothing for 0, the
/// per-frame target).
pub(super) fn rule_label(resolve: f32) -> String {
    if resolve > 0.0 {
        format!(" resolved {resolve}")
    } else {
        String::new()
    }
}

/// Which effects the study sweeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FloorEffects {
    /// Ambient occlusion only.
    Ao,
    /// The subsurface effect only.
    Sss,
    /// Both (subsurface first: it is the shorter).
    Both,
}

/// What the study sweeps. `None` lists take each effect's default.
#[derive(Clone, Debug, PartialEq)]
pub struct FloorOptions {
    /// The effects.
    pub effects: FloorEffects,
    /// AO: one scene (`static`, `pan4`, `object3`), or all three.
    pub scene: Option<String>,
    /// The fractional floors (AO: 0.25; subsurface: 0.25, 0.125, 0).
    pub floors: Option<Vec<f32>>,
    /// The targets `sigma0^2` of the floor's sweep (AO: ten from 3.2e-2 to 6.25e-5, or three
    /// with `quick`; subsurface: nine from 1e-3 to 1.6e-8).
    pub targets: Option<Vec<f32>>,
    /// AO: the count dilation radii.
    pub dilations: Vec<u32>,
    /// The resolved-image rule's steady weights, 0 for the per-frame target.
    pub resolves: Vec<f32>,
    /// AO: `beta_max` of the fractional runs.
    pub max_samples: u32,
    /// AO: what stands in the clamp box for a neighbour that skipped.
    pub sparse: SparseBox,
    /// AO: three targets instead of ten.
    pub quick: bool,
}

impl Default for FloorOptions {
    fn default() -> Self {
        Self {
            effects: FloorEffects::Both,
            scene: None,
            floors: None,
            targets: None,
            dilations: vec![1],
            resolves: vec![0.0, TAA_WEIGHT],
            max_samples: 64,
            sparse: SparseBox::History,
            quick: false,
        }
    }
}

/// What stands in a 3x3 clamp box for a neighbour that took no sample this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SparseBox {
    /// Its reprojected history: what the resolve shows there this frame (the default).
    History,
    /// Nothing: the box spans the neighbours that sampled (degenerate where one or two
    /// did, as with one-sample binary values at low counts).
    Sampled,
}

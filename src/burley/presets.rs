//! Measured material presets (docs/algorithms.md §5): per-channel mean free path and albedo.
//!
//! The values are those of docs/algorithms.md §5, from measured scattering data with an isotropic phase
//! function (the data set Christensen & Burley 2015 fit their profiles to). Mean free
//! paths are in millimetres; a renderer working in other units scales them (or the radii)
//! before building the profiles.
//!
//! # Examples
//!
//! ```
//! use spvg::burley::{ShapeFit, presets};
//! let [r, g, b] = presets::SKIN1.profiles::<f32>(ShapeFit::default()).unwrap();
//! assert_eq!(r.albedo(), 0.44);
//! assert!(r.shape() > g.shape() && g.shape() > b.shape());
//! assert!(presets::ALL.iter().all(|m| m.profiles::<f64>(ShapeFit::default()).is_ok()));
//! ```

use num_traits::Float;

use super::{BurleyProfile, ShapeFit, lit};
use crate::Error;

/// One measured material: mean free path and albedo per RGB channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialPreset {
    /// Lower-case material name, for example `"skin1"`.
    pub name: &'static str,
    /// Mean free path `l` in millimetres for R, G, B.
    pub mean_free_path_mm: [f64; 3],
    /// Albedo `A` for R, G, B.
    pub albedo: [f64; 3],
}

impl MaterialPreset {
    /// The three per-channel profiles `BurleyProfile::new(albedo[i], mean_free_path_mm[i],
    /// fit)`, radii in millimetres.
    ///
    /// # Errors
    ///
    /// The first failing channel's [`BurleyProfile::new`] error (a value that does not
    /// convert to `T` becomes NaN and is rejected there). Never for the presets of this
    /// module with `f32` or `f64`.
    pub fn profiles<T: Float>(&self, fit: ShapeFit) -> Result<[BurleyProfile<T>; 3], Error> {
        let channel = |a: f64, l: f64| BurleyProfile::new(lit::<T>(a), lit::<T>(l), fit);
        let [a0, a1, a2] = self.albedo;
        let [l0, l1, l2] = self.mean_free_path_mm;
        Ok([channel(a0, l0)?, channel(a1, l1)?, channel(a2, l2)?])
    }

    /// The largest mean free path of the three channels, in millimetres (`lmax` of the
    /// filtered-sampling mip level, [`filtered_mip_level`](super::filtered_mip_level)).
    #[inline]
    #[must_use]
    pub fn max_mean_free_path_mm(&self) -> f64 {
        let [r, g, b] = self.mean_free_path_mm;
        r.max(g).max(b)
    }
}

/// Skin (type 1).
pub const SKIN1: MaterialPreset = MaterialPreset {
    name: "skin1",
    mean_free_path_mm: [3.75, 1.47, 0.79],
    albedo: [0.44, 0.22, 0.13],
};

/// Skin (type 2).
pub const SKIN2: MaterialPreset = MaterialPreset {
    name: "skin2",
    mean_free_path_mm: [4.85, 1.11, 0.62],
    albedo: [0.63, 0.44, 0.34],
};

/// Marble.
pub const MARBLE: MaterialPreset = MaterialPreset {
    name: "marble",
    mean_free_path_mm: [8.51, 5.57, 3.96],
    albedo: [0.83, 0.79, 0.75],
};

/// Apple.
pub const APPLE: MaterialPreset = MaterialPreset {
    name: "apple",
    mean_free_path_mm: [6.97, 6.40, 1.92],
    albedo: [0.85, 0.84, 0.53],
};

/// Potato.
pub const POTATO: MaterialPreset = MaterialPreset {
    name: "potato",
    mean_free_path_mm: [14.29, 7.27, 2.31],
    albedo: [0.77, 0.62, 0.21],
};

/// Whole milk.
pub const WHOLEMILK: MaterialPreset = MaterialPreset {
    name: "wholemilk",
    mean_free_path_mm: [10.90, 6.58, 2.54],
    albedo: [0.91, 0.88, 0.76],
};

/// Ketchup. Its blue albedo is 0: a valid profile whose `R` is identically zero.
pub const KETCHUP: MaterialPreset = MaterialPreset {
    name: "ketchup",
    mean_free_path_mm: [5.33, 0.80, 0.56],
    albedo: [0.16, 0.01, 0.00],
};

/// Every preset, in the order of docs/algorithms.md §5.
pub const ALL: [MaterialPreset; 7] = [SKIN1, SKIN2, MARBLE, APPLE, POTATO, WHOLEMILK, KETCHUP];

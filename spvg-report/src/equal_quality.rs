//! Equal-quality figures (the SPVG paper's headline measure): the fixed sample count that
//! reaches an adaptive run's PSNR, and the fixed runs' PSNR at the adaptive run's mean
//! count, both interpolated linearly in `log2(spp)` between the two fixed runs that
//! bracket the value. Outside the fixed runs nothing is extrapolated: the figure says
//! which end it lies beyond.

use std::fmt;

/// A fixed-count run as the interpolation sees it: mean spp and PSNR (dB).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedPoint {
    /// Mean samples per pixel.
    pub spp: f64,
    /// PSNR, dB.
    pub psnr: f64,
}

/// An interpolated figure, or the end of the fixed runs it lies beyond.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Interpolated {
    /// Inside the fixed runs' range.
    At(f64),
    /// Above the largest fixed run (the spp of that run).
    Beyond(f64),
    /// Below the smallest fixed run (the spp of that run).
    Below(f64),
    /// Fewer than two usable fixed runs.
    None,
}

impl Interpolated {
    /// The value where it was interpolated.
    #[must_use]
    pub fn value(self) -> Option<f64> {
        match self {
            Self::At(v) => Some(v),
            _ => None,
        }
    }
}

/// The usable fixed points (finite spp > 0 and PSNR), sorted by spp.
fn sorted(fixed: &[FixedPoint]) -> Vec<FixedPoint> {
    let mut v: Vec<FixedPoint> = fixed
        .iter()
        .copied()
        .filter(|p| p.spp.is_finite() && p.spp > 0.0 && p.psnr.is_finite())
        .collect();
    v.sort_by(|a, b| a.spp.total_cmp(&b.spp));
    v
}

/// The fixed count whose PSNR equals `psnr`: between consecutive fixed runs (by spp)
/// whose PSNRs bracket it, `log2(spp)` linear in the PSNR. [`Interpolated::Beyond`] the
/// largest run when `psnr` exceeds every fixed run's, [`Interpolated::Below`] the
/// smallest when it is under every one.
///
/// # Examples
///
/// ```
/// use spvg_report::equal_quality::{FixedPoint, Interpolated, equal_spp};
/// let fixed = [FixedPoint { spp: 16.0, psnr: 40.0 }, FixedPoint { spp: 64.0, psnr: 46.0 }];
/// // Halfway in PSNR is halfway in log2(spp): 32 spp.
/// assert_eq!(equal_spp(&fixed, 43.0), Interpolated::At(32.0));
/// assert_eq!(equal_spp(&fixed, 47.0), Interpolated::Beyond(64.0));
/// ```
#[must_use]
pub fn equal_spp(fixed: &[FixedPoint], psnr: f64) -> Interpolated {
    let v = sorted(fixed);
    if v.len() < 2 || !psnr.is_finite() {
        return Interpolated::None;
    }
    for pair in v.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let (lo, hi) = (a.psnr.min(b.psnr), a.psnr.max(b.psnr));
        if psnr >= lo && psnr <= hi {
            let t = if hi > lo {
                (psnr - a.psnr) / (b.psnr - a.psnr)
            } else {
                0.0
            };
            let l = a.spp.log2() + t * (b.spp.log2() - a.spp.log2());
            return Interpolated::At(l.exp2());
        }
    }
    let best = v.iter().fold(f64::NEG_INFINITY, |m, p| m.max(p.psnr));
    if psnr > best {
        Interpolated::Beyond(v[v.len() - 1].spp)
    } else {
        Interpolated::Below(v[0].spp)
    }
}

/// The fixed runs' PSNR at `spp` samples: linear in `log2(spp)` between the two fixed
/// runs that bracket `spp`; [`Interpolated::Beyond`] / [`Interpolated::Below`] outside.
///
/// # Examples
///
/// ```
/// use spvg_report::equal_quality::{FixedPoint, Interpolated, psnr_at};
/// let fixed = [FixedPoint { spp: 16.0, psnr: 40.0 }, FixedPoint { spp: 64.0, psnr: 46.0 }];
/// assert_eq!(psnr_at(&fixed, 32.0), Interpolated::At(43.0));
/// assert_eq!(psnr_at(&fixed, 8.0), Interpolated::Below(16.0));
/// ```
#[must_use]
pub fn psnr_at(fixed: &[FixedPoint], spp: f64) -> Interpolated {
    let v = sorted(fixed);
    if v.len() < 2 || !(spp.is_finite() && spp > 0.0) {
        return Interpolated::None;
    }
    if spp < v[0].spp {
        return Interpolated::Below(v[0].spp);
    }
    if spp > v[v.len() - 1].spp {
        return Interpolated::Beyond(v[v.len() - 1].spp);
    }
    for pair in v.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        if spp >= a.spp && spp <= b.spp {
            let span = b.spp.log2() - a.spp.log2();
            let t = if span > 0.0 {
                (spp.log2() - a.spp.log2()) / span
            } else {
                0.0
            };
            return Interpolated::At(a.psnr + t * (b.psnr - a.psnr));
        }
    }
    Interpolated::None
}

/// [`psnr_at`], extrapolated linearly in `log2(spp)` from the two nearest fixed runs where
/// `spp` lies outside them: the PSNR and whether it was extrapolated (`None` with fewer
/// than two usable runs). For an acceptance check that must compare at the run's own spp;
/// its line says when the figure is extrapolated.
///
/// # Examples
///
/// ```
/// use spvg_report::equal_quality::{FixedPoint, psnr_at_or_extrapolated};
/// let fixed = [FixedPoint { spp: 16.0, psnr: 40.0 }, FixedPoint { spp: 64.0, psnr: 46.0 }];
/// assert_eq!(psnr_at_or_extrapolated(&fixed, 32.0), Some((43.0, false)));
/// // One octave below 16 spp: 3 dB below fixed16 on the line through both runs.
/// assert_eq!(psnr_at_or_extrapolated(&fixed, 8.0), Some((37.0, true)));
/// ```
#[must_use]
pub fn psnr_at_or_extrapolated(fixed: &[FixedPoint], spp: f64) -> Option<(f64, bool)> {
    match psnr_at(fixed, spp) {
        Interpolated::At(v) => Some((v, false)),
        Interpolated::None => None,
        Interpolated::Below(_) | Interpolated::Beyond(_) => {
            let v = sorted(fixed);
            let (a, b) = if spp < v[0].spp {
                (v[0], v[1])
            } else {
                (v[v.len() - 2], v[v.len() - 1])
            };
            let span = b.spp.log2() - a.spp.log2();
            if span <= 0.0 {
                return None;
            }
            let t = (spp.log2() - a.spp.log2()) / span;
            Some((a.psnr + t * (b.psnr - a.psnr), true))
        }
    }
}

/// An adaptive run's equal-quality figure: the fixed count reaching its PSNR and that
/// count over the run's mean spp.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EqualQuality {
    /// The adaptive run's mean spp.
    pub spp: f64,
    /// The fixed count at the run's PSNR.
    pub fixed: Interpolated,
}

impl EqualQuality {
    /// The adaptive run at `spp` and `psnr` against `fixed`.
    #[must_use]
    pub fn new(fixed: &[FixedPoint], spp: f64, psnr: f64) -> Self {
        Self {
            spp,
            fixed: equal_spp(fixed, psnr),
        }
    }

    /// The equal-quality fixed count over the run's mean spp, where interpolated.
    #[must_use]
    pub fn ratio(&self) -> Option<f64> {
        self.fixed.value().map(|n| n / self.spp)
    }
}

impl fmt::Display for EqualQuality {
    /// `fixed 40.3 (2.01x)`, `beyond fixed64 (> 3.20x)`, `below fixed16 (< 0.80x)` or
    /// `n/a`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.fixed {
            Interpolated::At(n) => write!(f, "fixed {n:.1} ({:.2}x)", n / self.spp),
            Interpolated::Beyond(n) => {
                write!(f, "beyond fixed{n:.0} (> {:.2}x)", n / self.spp)
            }
            Interpolated::Below(n) => write!(f, "below fixed{n:.0} (< {:.2}x)", n / self.spp),
            Interpolated::None => write!(f, "n/a"),
        }
    }
}

/// A fixed run's instability after TAA at its PSNR after TAA: a point of the line
/// [`flicker_at_psnr`] reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlickerPoint {
    /// PSNR after TAA, dB.
    pub psnr: f64,
    /// Instability after TAA ([`crate::metrics::Flicker`]).
    pub flicker: f64,
}

/// The fixed runs' instability after TAA at `psnr` after TAA: `log(flicker)` interpolated
/// linearly in PSNR between the two runs around it (an amplitude falls by a factor 10 per
/// 20 dB, so the line is straight there), or extrapolated from the nearest two outside
/// them (the flag says so). `None` with fewer than two finite points of distinct PSNR.
///
/// ```
/// use spvg_report::equal_quality::{FlickerPoint, flicker_at_psnr};
/// let fixed = [
///     FlickerPoint { psnr: 40.0, flicker: 1e-2 },
///     FlickerPoint { psnr: 60.0, flicker: 1e-3 },
/// ];
/// let (f, out) = flicker_at_psnr(&fixed, 50.0).unwrap();
/// assert!((f - 10f64.powf(-2.5)).abs() < 1e-12 && !out);
/// let (f, out) = flicker_at_psnr(&fixed, 80.0).unwrap();
/// assert!((f - 1e-4).abs() < 1e-12 && out);
/// ```
#[must_use]
pub fn flicker_at_psnr(fixed: &[FlickerPoint], psnr: f64) -> Option<(f64, bool)> {
    let mut v: Vec<FlickerPoint> = fixed
        .iter()
        .copied()
        .filter(|p| p.psnr.is_finite() && p.flicker.is_finite() && p.flicker > 0.0)
        .collect();
    v.sort_by(|a, b| a.psnr.total_cmp(&b.psnr));
    v.dedup_by(|a, b| a.psnr == b.psnr);
    if v.len() < 2 || !psnr.is_finite() {
        return None;
    }
    let inside = psnr >= v[0].psnr && psnr <= v[v.len() - 1].psnr;
    let k = v
        .windows(2)
        .position(|w| psnr <= w[1].psnr)
        .unwrap_or(v.len() - 2);
    let (a, b) = (v[k], v[k + 1]);
    let t = (psnr - a.psnr) / (b.psnr - a.psnr);
    let log = a.flicker.ln() + t * (b.flicker.ln() - a.flicker.ln());
    Some((log.exp(), !inside))
}

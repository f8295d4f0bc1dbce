//! How runs appear in the plots: a colour per model (lighter for swept settings) and the
//! legend entries of the per-frame and Pareto plots.

use super::canvas::Rgb;
use super::chart::{Entry, Marker};
use crate::evaluate::{FrameRecord, RunSummary};

/// Legend name of the swept settings.
pub(super) const SWEEP: &str = "sweep";

/// Whether a run label names a swept setting (defaults are a bare model name).
#[inline]
#[must_use]
pub(super) fn is_sweep(label: &str) -> bool {
    label.contains(' ')
}

/// Colour of a run: its model's colour, lighter for a swept setting.
pub(super) fn colour(label: &str) -> Rgb {
    let base = match label.split(' ').next().unwrap_or("") {
        "fixed8" => [200, 200, 200],
        "fixed16" => [150, 150, 150],
        "fixed32" => [100, 100, 100],
        "fixed64" => [40, 40, 40],
        "as" => [220, 30, 30],
        "ccv" => [20, 160, 40],
        "ocv" => [30, 60, 220],
        _ => [0, 0, 0],
    };
    if is_sweep(label) {
        base.map(|c| ((u16::from(c) + 255) / 2) as u8)
    } else {
        base
    }
}

/// Legend of a per-frame plot: every run, in order.
pub(super) fn series_legend(runs: &[(String, Vec<FrameRecord>)]) -> Vec<Entry> {
    runs.iter()
        .map(|(label, _)| Entry {
            name: label.clone(),
            colour: colour(label),
            marker: Marker::Line,
        })
        .collect()
}

/// Legend of a Pareto plot: each model once in order of appearance, then "sweep" when
/// any swept setting is plotted.
pub(super) fn pareto_legend(all: &[RunSummary]) -> Vec<Entry> {
    let mut entries: Vec<Entry> = Vec::new();
    for s in all.iter().filter(|s| !is_sweep(&s.label)) {
        if !entries.iter().any(|e| e.name == s.label) {
            entries.push(Entry {
                name: s.label.clone(),
                colour: colour(&s.label),
                marker: Marker::Dot,
            });
        }
    }
    if all.iter().any(|s| is_sweep(&s.label)) {
        entries.push(Entry {
            name: SWEEP.into(),
            colour: colour("fixed32 sweep"),
            marker: Marker::Ring,
        });
    }
    entries
}

/// Fixtures shared by the plot tests.
#[cfg(test)]
pub(super) mod fixtures {
    use crate::evaluate::RunSummary;
    use spvg_wgpu::{Model, Timer};

    /// Model names as the report labels its default runs.
    pub(in crate::plot) fn model_names() -> Vec<String> {
        [8, 16, 32, 64]
            .map(Model::Fixed)
            .into_iter()
            .chain([Model::As, Model::Ccv, Model::Ocv])
            .map(|m| m.name())
            .collect()
    }

    /// A run summary with the given scene, label, mean spp and mean PSNR.
    pub(in crate::plot) fn summary(
        scene: &'static str,
        label: &str,
        spp: f64,
        psnr: f64,
    ) -> RunSummary {
        RunSummary {
            scene,
            label: label.into(),
            model: Model::As,
            mean_spp: spp,
            worst_spp: spp,
            p50_ms: spp / 4.0,
            p95_ms: spp / 3.0,
            max_ms: spp / 2.0,
            mean_psnr: psnr,
            worst_psnr: psnr,
            mean_psnr_acc: psnr,
            worst_psnr_acc: psnr,
            history_bytes: 0,
            timer: Timer::WallClock,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::fixtures::{model_names, summary};
    use super::*;

    #[test]
    fn model_colours_are_distinct_and_sweeps_lighter() {
        let names = model_names();
        let colours: Vec<Rgb> = names.iter().map(|n| colour(n)).collect();
        for (i, a) in colours.iter().enumerate() {
            for (j, b) in colours.iter().enumerate().skip(i + 1) {
                assert_ne!(a, b, "{} and {} share a colour", names[i], names[j]);
            }
            let light = colour(&format!("{} kappa=1", names[i]));
            assert!(
                light.iter().zip(a).all(|(l, d)| l >= d) && light != *a,
                "sweep of {} not lighter: {light:?} vs {a:?}",
                names[i]
            );
        }
        // Fixed counts darken as the count grows.
        let greys: Vec<u8> = colours.iter().take(4).map(|c| c[0]).collect();
        assert!(
            greys.windows(2).all(|w| w[0] > w[1]),
            "fixed greys {greys:?}"
        );
    }

    #[test]
    fn legends_list_every_series() {
        let runs: Vec<(String, Vec<FrameRecord>)> =
            model_names().into_iter().map(|n| (n, Vec::new())).collect();
        let names: Vec<String> = series_legend(&runs).into_iter().map(|e| e.name).collect();
        assert_eq!(names, model_names(), "per-frame legend");

        let mut all = Vec::new();
        for scene in ["static", "flash"] {
            for (i, n) in model_names().iter().enumerate() {
                all.push(summary(scene, n, 8.0 * (i + 1) as f64, 30.0 + i as f64));
            }
        }
        let plain = pareto_legend(&all);
        let names: Vec<String> = plain.iter().map(|e| e.name.clone()).collect();
        assert_eq!(
            names,
            model_names(),
            "each model once, in order, no sweep entry"
        );
        assert!(
            plain.iter().all(|e| e.marker == Marker::Dot),
            "default runs are dots"
        );

        all.push(summary("flash", "ccv kappa=0", 20.0, 40.0));
        all.push(summary("switch", "as s0^2=1e-5", 30.0, 41.0));
        let swept = pareto_legend(&all);
        let names: Vec<&str> = swept.iter().map(|e| e.name.as_str()).collect();
        let mut want: Vec<String> = model_names();
        want.push(SWEEP.into());
        assert_eq!(names, want, "models then one sweep entry");
        assert_eq!(
            swept.last().map(|e| e.marker),
            Some(Marker::Ring),
            "sweeps are rings"
        );
    }
}

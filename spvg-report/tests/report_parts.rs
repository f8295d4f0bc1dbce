//! The report's parts against independent expectations: chart labels and clipping, image
//! captions and de-duplication, relMSE, and untimed runs.

use std::path::PathBuf;

use spvg::burley::presets::SKIN1;
use spvg_report::images::{ImageWriter, compose, zoom};
use spvg_report::metrics::{RELMSE_EPS, relmse};
use spvg_report::scene::{Scene, SceneKind};
use spvg_report::subsurface::figures::{self as charts, ParetoX, Series, group_label};
use spvg_report::subsurface::run::{FrameRecord, RunSpec, RunSummary, run_scene};
use spvg_report::timing::ms;
use spvg_report::wgpu_api::{Backend, Model, PassConfig, Timer};

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("spvg-report-parts-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display()));
    d
}

fn record(frame: u32, psnr: f64) -> FrameRecord {
    FrameRecord {
        frame,
        spp: 10.0,
        time_ms: 1.0,
        psnr,
        relmse: 10f64.powf(-psnr / 10.0),
        psnr_taa: psnr,
        relmse_taa: 10f64.powf(-psnr / 10.0),
        flicker_taa: 1e-3,
        zero_pixels: 0,
        count_step: 0.5,
        at_bounds: [0.5, 0.1],
        target: 1e-4,
        planned_spp: f64::NAN,
    }
}

fn summary(scene: &'static str, label: &str, spp: f64, psnr: f64) -> RunSummary {
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
        mean_relmse: 1e-3,
        mean_psnr_taa: psnr,
        worst_psnr_taa: psnr,
        mean_relmse_taa: 1e-3,
        flicker_taa: 1e-3,
        history_bytes: 8,
        timer: Timer::WallClock,
        budget_spp: None,
        in_band: f64::NAN,
        count_step: 0.5,
        longest_skip: None,
    }
}

#[test]
fn coincident_points_share_one_label() {
    assert_eq!(group_label(&["fixed64"]), "fixed64", "a single run");
    assert_eq!(
        group_label(&["ccv kappa=1", "ocv kappa=1"]),
        "ccv/ocv kappa=1",
        "one setting"
    );
    assert_eq!(
        group_label(&["as", "as kappa=0", "ccv"]),
        "as/ccv (report, kappa=0)",
        "settings differ"
    );
}

#[test]
fn psnr_chart_clips_spikes_and_says_so() {
    let dir = scratch("psnr");
    // 100 frames near 45 dB with two dark-frame spikes at 90 dB.
    let recs: Vec<FrameRecord> = (0..100)
        .map(|t| {
            record(
                t,
                if t == 30 || t == 60 {
                    90.0
                } else {
                    45.0 + f64::from(t % 3)
                },
            )
        })
        .collect();
    let runs = vec![("as".to_owned(), recs)];
    let (file, outside) = charts::write_series(&dir, "flash", Series::Psnr, &runs)
        .unwrap_or_else(|e| panic!("psnr chart: {e}"));
    assert_eq!(outside, 2, "the two spikes lie outside the clipped axis");
    let svg = std::fs::read_to_string(dir.join(&file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    assert!(
        svg.contains("2 points off the axis"),
        "the caption says what is off the axis"
    );
    assert!(svg.contains("\nas\n</text>"), "the legend names the run");
    let (_, none) = charts::write_series(&dir, "flash", Series::Spp, &runs)
        .unwrap_or_else(|e| panic!("spp chart: {e}"));
    assert_eq!(none, 0, "the spp chart is not clipped");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn pareto_labels_every_setting() {
    let dir = scratch("pareto");
    let all = vec![
        summary("static", "fixed64", 64.0, 50.0),
        summary("static", "as", 20.0, 49.0),
        summary("static", "as s0^2=1e-3", 8.0, 40.0),
        summary("static", "as kappa=0", 30.0, 45.0),
        summary("flash", "ccv", 25.0, 47.0),
    ];
    let file = charts::write_pareto(&dir, ParetoX::Spp, &["static", "flash"], &all, "CPU time")
        .unwrap_or_else(|e| panic!("pareto: {e}"));
    let svg = std::fs::read_to_string(dir.join(&file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    for label in [
        "fixed64",
        "as s0^2=1e-3",
        "as kappa=0",
        "ccv",
        "static",
        "flash",
    ] {
        assert!(svg.contains(label), "{file} does not show {label:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn images_are_enlarged_captioned_and_written_once() {
    let (w, h) = (32, 24);
    let px: Vec<u8> = (0..w * h).flat_map(|i| [(i % 251) as u8, 7, 200]).collect();
    let k = zoom(w);
    assert_eq!(k, 8, "32 px wide frames are enlarged 8x to reach 256 px");
    let img = compose(w, h, &px, None, &["static / as", "frame 3 / result"]);
    assert_eq!(img.width(), w * k, "width");
    assert!(img.height() > h * k, "a caption strip below the frame");
    // Every enlarged pixel keeps its source colour.
    for (x, y) in [(0, 0), (5, 7), (31, 23)] {
        let i = 3 * (y * w + x) as usize;
        let want = [px[i], px[i + 1], px[i + 2]];
        assert_eq!(
            img.get(x * k + k - 1, y * k + k - 1),
            Some(want),
            "pixel ({x}, {y})"
        );
    }
    // The caption strip holds both the background and text ink.
    let img = &img;
    let strip: Vec<[u8; 3]> = (h * k..img.height())
        .flat_map(|y| (0..img.width()).filter_map(move |x| img.get(x, y)))
        .collect();
    assert!(strip.contains(&[40, 40, 40]), "caption background");
    assert!(strip.contains(&[255, 255, 255]), "caption text");

    let dir = scratch("images");
    let mut writer = ImageWriter::new(&dir);
    let first = writer
        .write("a.png", "result", (w, h), &px, None, &["a"])
        .unwrap_or_else(|e| panic!("a.png: {e}"));
    let again = writer
        .write("b.png", "result", (w, h), &px, None, &["b"])
        .unwrap_or_else(|e| panic!("b.png: {e}"));
    let other_kind = writer
        .write("c.png", "count", (w, h), &px, None, &["c"])
        .unwrap_or_else(|e| panic!("c.png: {e}"));
    assert!(
        !first.duplicate && first.file == "a.png",
        "first written: {first:?}"
    );
    assert!(
        again.duplicate && again.file == "a.png",
        "same pixels link the first: {again:?}"
    );
    assert!(
        !other_kind.duplicate,
        "another kind is another image: {other_kind:?}"
    );
    assert!(
        dir.join("a.png").exists() && !dir.join("b.png").exists(),
        "b.png not written"
    );
    assert_eq!(writer.skipped, 1, "one duplicate skipped");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn relmse_follows_its_formula_over_scored_pixels() {
    let reference = [[0.2_f32; 3], [0.8; 3], [0.5; 3]];
    let image = [[0.3_f32; 3], [0.6; 3], [100.0; 3]];
    // Luminance of a grey is the grey value; the third pixel is masked out.
    let want =
        (0.1_f64.powi(2) / (0.04 + RELMSE_EPS) + 0.2_f64.powi(2) / (0.64 + RELMSE_EPS)) / 2.0;
    let got = relmse(&image, &reference, &[1, 1, 0]);
    assert!((got - want).abs() < 1e-6 * want, "{got} != {want}");
}

#[test]
fn untimed_runs_print_na_not_zero() {
    let scene = Scene::new(SceneKind::Static, 8, 6);
    let spec = RunSpec {
        model: Model::Fixed(8),
        cfg: PassConfig::default(),
        label: "fixed8".into(),
        budget_spp: None,
        budget_gain: 0.25,
        guided: false,
    };
    let (records, s) = run_scene(
        &Backend::Cpu,
        scene,
        &SKIN1,
        &spec,
        1,
        None,
        |_, _, _, _| {},
    )
    .unwrap_or_else(|e| panic!("one-frame run: {e}"));
    assert_eq!(records.len(), 1, "one frame");
    assert!(
        s.p50_ms.is_nan() && s.p95_ms.is_nan(),
        "frame 0 is not timed: {s:?}"
    );
    assert_eq!(ms(s.p50_ms), "n/a", "printed as n/a");
    assert_eq!(ms(0.25), "0.250", "three decimals otherwise");
}

/// The budget acceptance counts the frames from the warm-up on whose mean spp lies within
/// 10% of the budget, the band's edges included, whatever the warm-up's length.
#[test]
fn budget_band_counts_frames_after_the_warm_up() {
    use spvg_report::subsurface::run::{BUDGET_WARMUP, in_band};
    // The warm-up's frames far off the budget (ignored), then 16, 17.5, 14.5, 20, 12, 16,
    // 16, 16: 6 of the 8 judged frames lie in [14.4, 17.6].
    let judged = [16.0, 17.5, 14.5, 20.0, 12.0, 16.0, 16.0, 16.0];
    let spp: Vec<f64> = (0..BUDGET_WARMUP)
        .map(|t| if t % 2 == 0 { 40.0 } else { 1.0 })
        .chain(judged)
        .collect();
    let recs: Vec<FrameRecord> = spp
        .iter()
        .enumerate()
        .map(|(t, &s)| FrameRecord {
            spp: s,
            ..record(t as u32, 40.0)
        })
        .collect();
    assert_eq!(in_band(&recs, 16.0), 6.0 / 8.0, "fraction in band");
    assert!(
        in_band(&recs[..BUDGET_WARMUP as usize], 16.0).is_nan(),
        "no frame after the warm-up"
    );
}

/// A budget run on the CPU twin: the feed-forward's model of each frame's total (the
/// previous frame's demand curve at the target the frame ran with) against the counts
/// the frame really took, and the totals against the budget.
#[test]
fn budget_run_predicts_and_holds_its_totals() {
    let scene = Scene::new(SceneKind::Flash, 40, 30);
    let cfg = PassConfig {
        spvg: spvg::SpvgConfig::builder()
            .target_variance(5e-7)
            .build()
            .expect("valid target"),
        ..PassConfig::default()
    };
    let spec = RunSpec::budget(cfg, 16.0, 0.25);
    let (records, s) = run_scene(
        &Backend::Cpu,
        scene,
        &SKIN1,
        &spec,
        40,
        None,
        |_, _, _, _| {},
    )
    .unwrap_or_else(|e| panic!("budget run: {e}"));
    assert!(records[0].planned_spp.is_nan(), "no plan before frame 0");
    for r in &records[1..] {
        let err = (r.planned_spp / r.spp - 1.0).abs();
        assert!(
            err <= 0.05,
            "frame {}: planned {} spp, took {} (tol 5%)",
            r.frame,
            r.planned_spp,
            r.spp
        );
    }
    assert!(
        s.in_band >= 0.95,
        "frames within 10% of the budget: {}",
        s.in_band
    );
}

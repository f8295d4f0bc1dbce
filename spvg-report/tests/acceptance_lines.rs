//! Every acceptance line, in report.md and in the motion section, has the one format
//! `- PASS: ...` / `- FAIL: ...`, and the motion, separable and budget lines judge their bounds.

use std::path::PathBuf;
use std::process::Command;

use spvg_report::acceptance::is_line;
use spvg_report::budget_table::{BudgetRow, checks as budget_checks};
use spvg_report::motion::{
    AgeErrors, MotionBound, MotionOptions, MotionReport, MotionRun, NO_REPROJECTED_DEPTH,
    acceptance::acceptance, markdown, poses::StillBaseline, tighter_name,
};
use spvg_report::separable::{FocusResult, FocusRun, FocusTiming, checks};

/// The lines of `text` that carry a verdict word, other than the report's verdict line.
fn verdict_lines(text: &str) -> Vec<&str> {
    text.lines()
        .filter(|l| (l.contains("PASS") || l.contains("FAIL")) && !l.starts_with("**Verdict"))
        .collect()
}

/// A moving-object run whose every frame has `n` pixels per class (steady, uncovered at
/// ages 1, 2, 3), each with the squared errors `mse` (steady first).
fn with_uncovered(mut r: MotionRun, mse: [f64; 4]) -> MotionRun {
    let n = 100;
    let frame = AgeErrors {
        sse: mse.map(|e| e * n as f64),
        n: [n; 4],
    };
    r.uncovered_errors = vec![frame; r.spp.len()];
    r
}

/// A run of `frames` frames at `spp` samples and `psnr` dB on every frame.
fn run(scene: &str, mode: &str, spp: f64, psnr: f64) -> MotionRun {
    let frames = 40;
    MotionRun {
        scene: scene.into(),
        mode: mode.into(),
        spp: vec![spp; frames],
        psnr: vec![psnr; frames],
        psnr_steady: vec![psnr; frames],
        ..MotionRun::default()
    }
}

#[test]
fn motion_lines_judge_their_bounds_in_one_format() {
    let mut rep = MotionReport {
        runs: vec![
            run("static-pan", "fixed64", 64.0, 40.0),
            run("static-pan", "as", 20.0, 39.5),
            // 1.2x the static camera's samples, 0.5 dB below: passes.
            run("pan1", "as", 24.0, 39.0),
            // 1.3x: fails the 1.25x bound.
            run("pan2", "as", 26.0, 39.4),
            // 1.1x but 1.5 dB below: fails the 1 dB bound.
            run("pan4", "as", 22.0, 38.0),
            // The dolly against the static cameras at its heights: 1.1x, 0.5 dB below: passes;
            // without the reprojected depth it is quoted, not judged.
            run("static-dolly3", "as", 20.0, 39.5),
            run("dolly3", "as", 22.0, 39.0),
            run("dolly3", NO_REPROJECTED_DEPTH, 8.0, 35.0),
            // 1.15x, 0.3 dB below: passes the pan criterion and the 0.5 dB young-history
            // bound; the young-history row is quoted, not judged.
            run("pan8", "as", 23.0, 39.2),
            run("pan8", "as-young", 22.0, 39.4),
            // Below the identity history's PSNR: fails (the run is below, with its
            // uncovered pixels' errors).
            run("object3", "as-identity", 32.0, 41.0),
            run("object3", "as-spatial", 31.0, 41.2),
            // AS at a tighter target above the identity history's PSNR, but at more than its
            // spp: dominates nothing, the line still fails.
            run("object3", &tighter_name(0.9), 33.0, 41.5),
            // On objects5, AS at the report's target is below the identity history's PSNR
            // (39.0 vs 39.2 dB) but AS at 0.9 sigma0^2 reaches 39.3 dB at 30.8 spp, under
            // its 31 spp: passes.
            run("objects5", "as-identity", 31.0, 39.2),
            run("objects5", &tighter_name(0.9), 30.8, 39.3),
            run("objects5", &tighter_name(0.8), 31.5, 39.4),
            // Uncovered pixels at their third frame: 10 log10(1e-4 / 1.6e-4) = 2.04 dB below
            // the steady ones on object3 (fails), 10 log10(1e-4 / 1.2e-4) = 0.79 dB below on
            // objects5 (passes).
            with_uncovered(run("object3", "as", 30.0, 40.0), [1e-4, 1e-3, 4e-4, 1.6e-4]),
            with_uncovered(
                run("objects5", "as", 30.0, 39.0),
                [1e-4, 1e-3, 4e-4, 1.2e-4],
            ),
        ],
        agreement: vec![("pan4".into(), 0.995, 16), ("rotate2".into(), 0.98, 16)],
        // The frame after the broken one 5% above the frame before: passes.
        motion_bound: Some(MotionBound {
            frame: 20,
            before: 20.0,
            broken: 8.0,
            after: 21.0,
        }),
        motion_bound_young: vec![(
            "as-spatial".into(),
            MotionBound {
                frame: 20,
                before: 20.0,
                broken: 8.0,
                after: 19.5,
            },
        )],
        still: Vec::new(),
        lines: Vec::new(),
    };
    rep.lines = acceptance(&rep);
    let verdicts: Vec<(bool, &str)> = rep.lines.iter().map(|c| (c.pass, c.name())).collect();
    assert_eq!(
        verdicts,
        [
            (true, "Second consumer (AO), static-pan camera"),
            (true, "Pan criterion, pan1"),
            (false, "Pan criterion, pan2"),
            (false, "Pan criterion, pan4"),
            (true, "Pan criterion, pan8"),
            (true, "Pan criterion, dolly3"),
            (true, "Young history, pan8"),
            (true, "Disocclusion by motion, object3"),
            (true, "Disocclusion by motion, objects5"),
            (false, "Reprojection against the identity history, object3"),
            (true, "Reprojection against the identity history, objects5"),
            (false, "Uncovered pixels, object3"),
            (true, "Uncovered pixels, objects5"),
            (true, "Motion bound, static"),
            (true, "GPU vs twin, pan4"),
            (false, "GPU vs twin, rotate2"),
        ],
        "{:#?}",
        rep.lines
    );
    let dolly = &rep.lines[5].text;
    assert!(
        dolly.contains("without the reprojected depth") && dolly.contains("fails the criterion"),
        "{dolly}"
    );
    rep.motion_bound = Some(MotionBound {
        after: 17.0,
        ..rep.motion_bound.expect("set above")
    });
    let young = &rep.lines[6].text;
    assert!(young.contains("as-young: 22.0 spp = 1.10x"), "{young}");
    let identity = &rep.lines[10].text;
    assert!(
        identity.contains("as s0^2 x0.9: 39.30 dB at 30.8 spp, dominates")
            && identity.contains("as s0^2 x0.8: 39.40 dB at 31.5 spp (after TAA"),
        "{identity}"
    );
    let uncovered = &rep.lines[11].text;
    assert!(
        uncovered.contains("37.96 dB vs steady 40.00 dB (-2.04 dB; within 1 dB)")
            && uncovered.contains("first frame 30.00 dB, second 33.98 dB")
            && uncovered.contains("pooled over frames 16..39 (2400 pixel-frames at age 3"),
        "{uncovered}"
    );
    assert!(
        rep.lines[13]
            .text
            .contains("as-spatial: next frame 19.50 spp")
    );
    let bound = acceptance(&rep);
    assert!(
        !bound[13].pass,
        "15% below the frame before fails: {:?}",
        bound[13]
    );
    let opts = MotionOptions::new().expect("valid options");
    let (md, _) = markdown(&rep, &opts, "test");
    let lines = verdict_lines(&md);
    assert_eq!(lines.len(), rep.lines.len(), "one line per check: {md}");
    for l in lines {
        assert!(is_line(l), "not `- PASS: ` / `- FAIL: `: {l:?}");
    }
}

/// The young-history line judges the static camera held at the moving camera's poses,
/// on the frames whose poses it held, where the report ran it; the first pose's static
/// camera is then quoted, not judged.
#[test]
fn young_history_judges_the_static_camera_at_the_same_poses() {
    // pan8 is 1.02 dB below static-pan (the first pose) over frames 16..39: fails the 0.5 dB
    // bound alone.
    let mut pan8 = run("pan8", "as", 23.0, 39.0);
    // Frames 16 and 20 at 38.8 dB (the pan's other frames at 39.0 do not count).
    (pan8.psnr[16], pan8.psnr[20]) = (38.8, 38.8);
    let mut rep = MotionReport {
        runs: vec![run("static-pan", "as", 20.0, 40.0), pan8],
        ..MotionReport::default()
    };
    let judged = |rep: &MotionReport| {
        acceptance(rep)
            .into_iter()
            .find(|c| c.name() == "Young history, pan8")
            .expect("the line")
    };
    let first = judged(&rep);
    assert!(
        !first.pass && first.text.contains("+1.02 dB below it"),
        "{first:?}"
    );
    // Held at frames 16 and 20: 22 spp and 39.1 dB, so AS is 1.05x and 0.30 dB below.
    rep.still = vec![StillBaseline {
        scene: "pan8".into(),
        frames: vec![16, 20],
        spp: vec![22.0, 22.0],
        psnr: vec![39.0, 39.2],
    }];
    let held = judged(&rep);
    assert!(
        held.pass
            && held
                .text
                .contains("1.05x the spp of the static camera held at its poses")
            && held.text.contains("+0.30 dB below it")
            && held
                .text
                .contains("against static-pan (the first pose): 1.15x, +1.02 dB below"),
        "{held:?}"
    );
    // 0.6 dB below the held camera fails.
    rep.still[0].psnr = vec![39.5, 39.3];
    assert!(!judged(&rep).pass);
}

#[test]
fn report_md_acceptance_lines_have_one_format() {
    let dir = std::env::temp_dir().join(format!("spvg-report-lines-{}", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_spvg-report"))
        .args([
            "--width=16",
            "--height=12",
            "--frames=12",
            "--backend=cpu",
            "--scenes=static,flash,switch",
            "--models=fixed16,fixed64,as,ccv,ocv",
            "--no-motion",
            "--no-separable",
        ])
        .arg(format!("--out={}", dir.display()))
        .output()
        .unwrap_or_else(|e| panic!("cannot run spvg-report: {e}"));
    assert!(
        out.status.success(),
        "spvg-report failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let path: PathBuf = dir.join("report.md");
    let md = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let lines = verdict_lines(&md);
    // flash ccv/ocv, switch ccv/ocv, static as; static as after TAA against the fixed
    // runs and its equal-quality ratio; the budget on flash and switch (band and PSNR
    // against fixed16); the TAA-guided AS on flash and switch; the damped policy's two;
    // the firefly clamp's one.
    assert_eq!(lines.len(), 16, "{lines:#?}");
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("- PASS: firefly clamp k=4: ")),
        "{lines:#?}"
    );
    for l in &lines {
        assert!(is_line(l), "not `- PASS: ` / `- FAIL: `: {l:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The final-image lines compare AS after TAA with the fixed runs after TAA at AS's mean
/// spp (interpolated in log2(spp)) and state the equal-quality counts.
#[test]
fn final_image_lines_compare_at_equal_spp() {
    let with_taa = |scene: &str, mode: &str, spp: f64, psnr: f64, taa: f64| MotionRun {
        psnr_taa: vec![taa; 40],
        ..run(scene, mode, spp, psnr)
    };
    // fixed8/16/32 at 30/33/36 dB, 33/36/39 dB after TAA (3 dB per octave); AS at
    // 16 sqrt(2) spp, halfway in log2 between fixed16 and fixed32: the fixed runs after
    // TAA give 37.5 dB there.
    let as_spp = 16.0 * 2_f64.sqrt();
    let mut runs = Vec::new();
    for scene in ["pan1", "pan2"] {
        for (n, p) in [(8.0, 30.0), (16.0, 33.0), (32.0, 36.0)] {
            runs.push(with_taa(scene, &format!("fixed{n}"), n, p, p + 3.0));
        }
    }
    runs.push(with_taa("pan1", "as", as_spp, 35.0, 38.0));
    runs.push(with_taa("pan2", "as", as_spp, 35.0, 37.0));
    let rep = MotionReport {
        runs,
        ..MotionReport::default()
    };
    let lines = acceptance(&rep);
    let verdicts: Vec<(bool, &str)> = lines.iter().map(|c| (c.pass, c.name())).collect();
    assert_eq!(
        verdicts,
        [
            (true, "Final image (AO), pan1"),
            (false, "Final image (AO), pan2")
        ],
        "{lines:#?}"
    );
    // Single-frame 35 dB: two thirds of the way from fixed16 to fixed32, 2^(4 + 2/3) spp.
    let eq = 2_f64.powf(4.0 + 2.0 / 3.0);
    let want = format!("fixed {eq:.1} ({:.2}x)", eq / as_spp);
    assert!(lines[0].text.contains("37.50 dB"), "{}", lines[0].text);
    assert!(
        lines[0].text.contains("margin +0.50 dB"),
        "{}",
        lines[0].text
    );
    assert!(lines[0].text.contains(&want), "{want} in {}", lines[0].text);
}

/// A focus run of the separable section with the fields its checks read.
fn focus_run(
    name: &str,
    time_ms: f64,
    psnr_focus: f64,
    band: f64,
    inside: f64,
    outside: f64,
) -> FocusRun {
    FocusRun {
        name: name.into(),
        time_ms,
        psnr_focus,
        rmse_band: band,
        rmse_inside: inside,
        rmse_outside: outside,
        ..FocusRun::default()
    }
}

#[test]
fn separable_lines_judge_their_bounds_in_one_format() {
    let result = |hybrid: FocusRun| FocusResult {
        runs: vec![
            focus_run("separable", 10.0, 30.0, 0.02, 0.01, 0.02),
            focus_run("as", 60.0, 40.0, 0.01, 0.01, 0.01),
            focus_run("ccv", 50.0, 40.0, 0.01, 0.01, 0.01),
            hybrid,
        ],
        focus_fraction: 0.1,
        cpu_time: true,
        timing: None,
    };
    // Bound on time: 10 + 1.3 x 0.1 x 40 = 15.2 ms; seam bound 1.5 x max(0.02, 0.01) = 0.03.
    let good = checks(&result(focus_run(
        "hybrid-ccv",
        15.0,
        39.9,
        0.029,
        0.01,
        0.02,
    )));
    assert_eq!(good.len(), 3, "three separable lines");
    assert!(good.iter().all(|c| c.pass), "{good:?}");
    let bad = checks(&result(focus_run(
        "hybrid-ccv",
        15.3,
        39.7,
        0.031,
        0.01,
        0.02,
    )));
    assert!(bad.iter().all(|c| !c.pass), "{bad:?}");
    for c in good.iter().chain(&bad) {
        assert!(is_line(&c.line()), "{}", c.line());
    }
    // With timing rows the time line judges the median per-frame slack, not the runs'
    // medians (whose bound, 100 + 1.3 x 0.05 x 100 = 106.5 ms, says the opposite in both
    // cases below), and names their size and frame count, whatever the quality runs took.
    let timed = |hybrid_ms: f64, slack_ms: f64| {
        let mut r = result(focus_run("hybrid-ccv", 99.0, 39.9, 0.029, 0.01, 0.02));
        r.timing = Some(FocusTiming {
            size: [640, 480],
            frames: 24,
            focus_fraction: 0.05,
            separable_ms: 100.0,
            ccv_ms: 200.0,
            hybrid_ms,
            slack_ms,
            ..FocusTiming::default()
        });
        checks(&r)[1].clone()
    };
    let (pass, fail) = (timed(106.6, 0.4), timed(106.4, -0.1));
    assert!(pass.pass && !fail.pass, "{pass:?} {fail:?}");
    assert!(
        pass.line().contains("at 640x480, 24 frames") && pass.line().contains("0.400 ms >= 0"),
        "{}",
        pass.line()
    );
    assert!(fail.line().contains("-0.100 ms >= 0"), "{}", fail.line());
    assert!(is_line(&pass.line()) && is_line(&fail.line()));
}

#[test]
fn budget_line_judges_its_bound_in_one_format() {
    let row = |adaptive: bool, psnr: f64, samples: f64| BudgetRow {
        budget: 512,
        adaptive,
        picked: adaptive,
        beta_min: if adaptive { 64 } else { 0 },
        psnr,
        samples,
        ..BudgetRow::default()
    };
    // 40% of the samples, 0.5 dB below: passes; 60%, or 1.5 dB below: fails.
    let pass = budget_checks(&[row(true, 49.5, 400.0), row(false, 50.0, 1000.0)]);
    let more = budget_checks(&[row(true, 49.5, 600.0), row(false, 50.0, 1000.0)]);
    let worse = budget_checks(&[row(true, 48.5, 400.0), row(false, 50.0, 1000.0)]);
    assert_eq!(pass.len(), 1, "one budget line");
    assert!(
        pass[0].pass && !more[0].pass && !worse[0].pass,
        "{pass:?} {more:?} {worse:?}"
    );
    for c in pass.iter().chain(&more).chain(&worse) {
        assert!(is_line(&c.line()), "{}", c.line());
    }
}

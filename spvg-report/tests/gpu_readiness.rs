//! The GPU-readiness study: its byte count against a hand count of the textures each
//! step binds, and its function on a tiny frame returning finite positive times.

mod common;

use spvg_report::studies::gpu_readiness::{
    ReadinessOptions, Step, StepBytes, estimate_bytes, markdown, one_pass_bytes, run, update_bytes,
};

#[test]
fn byte_count_matches_a_hand_count() {
    // Estimate: history Rgba16Float 8, motion Rg32Float 8, depth 4, previous depth 4 read;
    // count 4 and link 4 written.
    assert_eq!(
        estimate_bytes(false),
        StepBytes {
            read: 8 + 8 + 4 + 4,
            written: 4 + 4
        },
        "estimate without dilation"
    );
    // With dilation the estimate writes the raw count instead, and the dilation pass reads
    // it (4) and writes the dilated count (4).
    assert_eq!(
        estimate_bytes(true),
        StepBytes {
            read: 28,
            written: 12
        },
        "estimate with dilation"
    );
    // Update (AS): history 8, value 4, count 4, link 4 read; the other history 8 written.
    assert_eq!(
        update_bytes(),
        StepBytes {
            read: 20,
            written: 8
        },
        "update"
    );
    assert_eq!(update_bytes().total(), 28, "update total");
    // One pass (AS, counts not stored): the estimate's reads, the other history written.
    assert_eq!(
        one_pass_bytes(),
        StepBytes {
            read: 24,
            written: 8
        },
        "one pass"
    );
}

#[test]
fn tiny_run_gives_finite_positive_times_and_ratios() {
    let Some(dev) = common::device("tiny_run_gives_finite_positive_times_and_ratios") else {
        return;
    };
    let opts = ReadinessOptions {
        sizes: vec![[64, 32]],
        frames: 2,
        warmup: 1,
        dilation: 1,
    };
    let r = run(&dev, &opts).expect("the command runs on a tiny frame");
    assert_eq!(r.rows.len(), 3, "one row per step");
    assert_eq!(r.rows[0].step, Step::Estimate, "estimate first");
    assert_eq!(r.rows[1].step, Step::Update, "update second");
    assert_eq!(r.rows[2].step, Step::OnePass, "the one-pass form third");
    for row in &r.rows {
        for (what, v) in [
            ("step", row.step_ms),
            ("copy", row.copy_ms),
            ("ratio", row.ratio()),
        ] {
            assert!(v.is_finite() && v > 0.0, "{:?} {what}: {v}", row.step);
        }
    }
    let md = markdown(&r);
    assert!(md.contains("| 64x32 | estimate | 40 |"), "{md}");
    assert!(md.contains("| 64x32 | update | 28 |"), "{md}");
    assert!(
        md.contains("| 64x32 | one pass, zero samples | 32 |"),
        "{md}"
    );
    if dev.is_software() {
        assert!(
            md.contains("CPU time"),
            "a software adapter says CPU time: {md}"
        );
    }
}

#[test]
fn zero_frames_is_refused() {
    let Some(dev) = common::device("zero_frames_is_refused") else {
        return;
    };
    let opts = ReadinessOptions {
        sizes: vec![[8, 8]],
        frames: 0,
        ..ReadinessOptions::default()
    };
    let e = run(&dev, &opts).expect_err("no measured frame");
    assert!(e.to_string().contains("frames"), "{e}");
}

fn command(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_spvg-report"))
        .arg("gpu-readiness")
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run spvg-report gpu-readiness {args:?}: {e}"))
}

#[test]
fn command_help_names_its_flags_and_bad_frames_are_refused() {
    let out = command(&["--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "--help failed: {text}");
    for flag in ["--frames", "--warmup", "--out", "copy kernel", "CPU time"] {
        assert!(
            text.contains(flag),
            "--help does not mention {flag:?}: {text}"
        );
    }
    for bad in [["--frames", "0"], ["--frames", "x"], ["--warmup", "-1"]] {
        let out = command(&bad);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{bad:?} succeeded");
        assert_ne!(out.status.code(), Some(101), "{bad:?} panicked: {err}");
        assert!(
            err.contains(bad[0]),
            "{bad:?}: stderr does not name the flag: {err}"
        );
    }
}

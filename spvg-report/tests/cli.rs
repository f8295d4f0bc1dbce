//! The binary's command line, run as a user would: `--help` and the subcommands',
//! `--flag=value`, and every bad input (non-zero exit, the flag named on stderr, no
//! panic).

use std::path::PathBuf;
use std::process::{Command, Output};

fn report(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spvg-report"))
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run spvg-report {args:?}: {e}"))
}

fn scratch(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("spvg-report-cli-{}-{tag}", std::process::id()))
}

/// Runs `args`, expects failure with every word of `named` on stderr and no panic.
fn rejects(args: &[&str], named: &[&str]) {
    let out = report(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} succeeded; stderr: {err}");
    assert_eq!(
        out.status.code(),
        Some(1),
        "{args:?}: an error exits with 1 (2 is a failed line, 101 a panic): {err}"
    );
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    for word in named {
        assert!(
            err.contains(word),
            "{args:?}: stderr does not name {word:?}: {err}"
        );
    }
}

#[test]
fn help_exits_zero_and_describes_every_flag_and_subcommand() {
    let out = report(&["--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "--help failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    for flag in [
        "--width",
        "--height",
        "--frames",
        "--backend",
        "--out",
        "--material",
        "--image-frame",
        "--sigma0-sq",
        "--ao-sigma0-sq",
        "--scenes",
        "--models",
        "--full",
        "--no-sweep",
        "--skip",
        "--no-reference",
        "--gradient",
        "--afis",
        "--firefly-clamp",
        "Exit status",
    ] {
        assert!(text.contains(flag), "--help does not list {flag}: {text}");
    }
    for command in [
        "all",
        "subsurface",
        "motion",
        "separable",
        "budget",
        "governor",
        "floor",
        "gpu-readiness",
        "pass-breakdown",
    ] {
        assert!(
            text.contains(&format!("\n  {command} ")),
            "--help does not list the subcommand {command}: {text}"
        );
        // Each subcommand takes the global flags, with the same meaning.
        let sub = report(&[command, "--help"]);
        let sub_text = String::from_utf8_lossy(&sub.stdout);
        assert!(sub.status.success(), "{command} --help failed");
        for global in [
            "--backend",
            "--out",
            "--width",
            "--height",
            "--frames",
            "--full",
        ] {
            assert!(
                sub_text.contains(global),
                "{command} --help does not list {global}: {sub_text}"
            );
        }
    }
    assert!(
        text.contains("[1, 1024]"),
        "--help does not give the fixedN range: {text}"
    );
}

#[test]
fn bad_inputs_name_their_flag() {
    let out = scratch("bad");
    let out = out.to_str().unwrap_or("target/spvg-report-cli");
    rejects(&["--bogus"], &["--bogus"]);
    rejects(
        &["--models", "fixed2000"],
        &["--models", "fixed2000", "1024"],
    );
    rejects(&["--models=fixed0"], &["--models", "1024"]);
    rejects(&["--models", "fixedx"], &["--models"]);
    rejects(&["--sigma0-sq", "-1"], &["--sigma0-sq", "> 0"]);
    rejects(&["--sigma0-sq=nan"], &["--sigma0-sq", "> 0"]);
    rejects(&["--sigma0-sq", "abc"], &["--sigma0-sq"]);
    rejects(&["--firefly-clamp", "0"], &["--firefly-clamp", "> 0"]);
    rejects(&["--firefly-clamp=nan"], &["--firefly-clamp", "> 0"]);
    rejects(&["--firefly-clamp", "-4"], &["--firefly-clamp", "> 0"]);
    rejects(&["--budget-spp", "4"], &["--budget-spp", "[8, 64]"]);
    rejects(&["--budget-spp=65"], &["--budget-spp", "[8, 64]"]);
    rejects(&["--budget-spp", "inf"], &["--budget-spp"]);
    rejects(&["--budget-gain", "0"], &["--budget-gain", "(0, 1]"]);
    rejects(&["--budget-gain=1.5"], &["--budget-gain", "(0, 1]"]);
    rejects(&["--frames", "1"], &["--frames", "2"]);
    rejects(&["--frames=0"], &["--frames"]);
    rejects(&["--width", "0"], &["--width", "1"]);
    rejects(&["--height", "-3"], &["--height"]);
    rejects(&["--width", "40000"], &["--width", "32768"]);
    rejects(
        &["--backend", "vulkan"],
        &["--backend", "auto", "gpu", "cpu"],
    );
    rejects(&["--material", "jade"], &["--material", "skin1", "marble"]);
    rejects(&["--scenes", "static,moon"], &["--scenes", "moon"]);
    rejects(&["--skip", "motion,moon"], &["--skip", "moon"]);
    rejects(&["--ao-sigma0-sq", "-1"], &["--ao-sigma0-sq", "> 0"]);
    rejects(&["motion", "--ao-sigma0-sq=inf"], &["--ao-sigma0-sq"]);
    rejects(&["teleport"], &["teleport"]);
    // The pans' strip grows with the frames: past the device's (or the twin's) limit it is
    // an error naming --frames, before anything renders.
    rejects(
        &["motion", "--frames", "100000", "--out", out],
        &["--frames", "strip"],
    );
    // A section's flags belong to its subcommand (or to `all`).
    rejects(&["motion", "--scenes", "static"], &["--scenes"]);
    rejects(&["budget", "--frames", "1"], &["--frames", "2"]);
    // The timing studies need a device: on the CPU twin an error that says so.
    rejects(
        &["gpu-readiness", "--backend", "cpu", "--out", out],
        &["gpu-readiness", "wgpu device"],
    );
    rejects(
        &["pass-breakdown", "--backend", "cpu", "--out", out],
        &["pass-breakdown", "wgpu device"],
    );
    rejects(
        &["--frames", "8", "--image-frame", "8", "--out", out],
        &["--image-frame", "[0, 7]"],
    );
    rejects(
        &["subsurface", "--image-frame", "96", "--out", out],
        &["--image-frame", "[0, 95]"],
    );
    rejects(&["--out", "/proc/x"], &["--out", "/proc/x"]);
    // Beyond the adapter's limits on a GPU, beyond the twin's on the CPU: a clear error
    // naming the size flags, never a panic inside wgpu.
    rejects(
        &[
            "--width",
            "20000",
            "--height",
            "20000",
            "--no-reference",
            "--out",
            out,
        ],
        &["--width 20000 --height 20000"],
    );
    rejects(
        &[
            "--width",
            "20000",
            "--height",
            "20000",
            "--no-reference",
            "--backend",
            "cpu",
            "--out",
            out,
        ],
        &["--width 20000 --height 20000"],
    );
    let _ = std::fs::remove_dir_all(out);
}

#[test]
fn equals_form_and_two_frames_run() {
    let dir = scratch("ok");
    let out = report(&[
        "subsurface",
        "--width=16",
        "--height=12",
        "--frames=2",
        "--image-frame=1",
        "--scenes=flash",
        "--models=fixed8,ccv",
        "--no-sweep",
        "--backend=cpu",
        &format!("--out={}", dir.display()),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    // Two frames are too few for the lines: some fail (exit status 2), none is an error.
    assert!(
        matches!(out.status.code(), Some(0 | 2)),
        "a 2-frame run failed: {err}"
    );
    assert!(
        err.contains("CPU twin") && err.contains("--backend cpu"),
        "the backend and why: {err}"
    );
    let md =
        std::fs::read_to_string(dir.join("report.md")).unwrap_or_else(|e| panic!("report.md: {e}"));
    assert!(
        md.starts_with("# spvg report\n\n**Verdict"),
        "no verdict line first: {md}"
    );
    let csv =
        std::fs::read_to_string(dir.join("runs.csv")).unwrap_or_else(|e| panic!("runs.csv: {e}"));
    // One row per pass run (fixed8, ccv and the budget run, which the default suite runs
    // on flash) and the three circle policies of the kappa sweep (core crate).
    let rows = |prefix: &str| csv.lines().filter(|l| l.starts_with(prefix)).count();
    assert_eq!(csv.lines().count(), 7, "header + one row per run: {csv}");
    assert_eq!(rows("flash,"), 3, "pass runs: {csv}");
    assert_eq!(rows("flash,ccv,budget,"), 1, "the budget run: {csv}");
    assert_eq!(rows("circle,core,"), 3, "kappa=0, kappa=1, damped: {csv}");
    let _ = std::fs::remove_dir_all(&dir);
}

//! Two runs, one report: two runs of `spvg-report` with the same flags write the same
//! `runs.csv`, `frames.csv`, `motion.csv` and `motion_runs.csv`, byte for byte apart from
//! the columns that are times (named `*_ms`). The run is small (the subsurface and motion
//! sections at 24x16, 6 frames) and on the backend `auto` finds: in CI the software
//! rasterizer, whose frames the motion section also holds against the CPU twin.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The CSV files two runs must agree on.
const FILES: [&str; 4] = ["runs.csv", "frames.csv", "motion.csv", "motion_runs.csv"];

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("spvg-report-two-runs-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs the report into `dir` and returns its exit status code.
fn report(dir: &Path) -> Option<i32> {
    let out = Command::new(env!("CARGO_BIN_EXE_spvg-report"))
        .args([
            "--width=24",
            "--height=16",
            "--frames=6",
            // The governor's device run follows the device's clock (its counts too): its
            // twin runs are held equal twice by the governor's own unit test.
            "--skip=separable,budget,governor",
        ])
        .arg(format!("--out={}", dir.display()))
        .output()
        .unwrap_or_else(|e| panic!("cannot run spvg-report: {e}"));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "spvg-report panicked: {err}");
    out.status.code()
}

/// `csv` without its time columns (headers ending in `_ms`).
fn without_times(csv: &str) -> String {
    let mut lines = csv.lines();
    let Some(header) = lines.next() else {
        return String::new();
    };
    let keep: Vec<bool> = header.split(',').map(|h| !h.ends_with("_ms")).collect();
    let strip = |line: &str| -> String {
        line.split(',')
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(v, _)| v)
            .collect::<Vec<_>>()
            .join(",")
    };
    std::iter::once(header)
        .chain(lines)
        .map(|l| strip(l) + "\n")
        .collect()
}

#[test]
fn time_columns_are_the_only_ones_dropped() {
    let csv = "scene,p50_ms,psnr,time_ms\nstatic,1.5,40.0,2.0\n";
    assert_eq!(without_times(csv), "scene,psnr\nstatic,40.0\n");
}

#[test]
fn two_runs_write_the_same_csv_files() {
    let (a, b) = (scratch("a"), scratch("b"));
    let codes = [report(&a), report(&b)];
    for (dir, code) in [(&a, codes[0]), (&b, codes[1])] {
        // Some lines fail at this size (exit status 2); an error (1) is a failure here.
        assert!(
            matches!(code, Some(0 | 2)),
            "{}: exit status {code:?}",
            dir.display()
        );
    }
    for file in FILES {
        let read = |d: &Path| {
            let p = d.join(file);
            std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
        };
        let (x, y) = (without_times(&read(&a)), without_times(&read(&b)));
        assert!(x.lines().count() > 1, "{file} has no rows");
        if x != y {
            let first = x
                .lines()
                .zip(y.lines())
                .enumerate()
                .find(|(_, (p, q))| p != q)
                .map_or_else(
                    || "the files differ in length".to_owned(),
                    |(i, (p, q))| format!("line {}: {p} / {q}", i + 1),
                );
            panic!("{file} differs between two runs: {first}");
        }
    }
    let _ = std::fs::remove_dir_all(&a);
    let _ = std::fs::remove_dir_all(&b);
}

//! The second moment's line (`spvg_report::budget::moment`, docs/algorithms.md §8.8) at
//! the report's size: with the moment, the controller's mean count on the wide budget is
//! within 1.1x of what the closed-form per-sample variance requires, and on the
//! published budget no more pixels sit at 64 than that variance puts there.

use spvg_report::budget::moment::{GRID, PUBLISHED, SIZE, WIDE, check, jittered_ao, required, run};

#[test]
fn the_count_follows_the_per_sample_variance_under_jitter() {
    let q = jittered_ao(SIZE, GRID);
    // The jitter moves the occlusion at edges: some pixels see different q per offset.
    let moved = (0..q[0].len())
        .filter(|&i| q.iter().any(|img| (img[i] - q[0][i]).abs() > 0.1))
        .count();
    assert!(moved > 20, "only {moved} pixels move under the jitter");
    let (need, got) = (required(&q, WIDE), run(&q, WIDE, true).expect("run"));
    let ratio = got.spp / need.spp;
    eprintln!(
        "wide: {:.1} spp against {:.1} required ({ratio:.3}x)",
        got.spp, need.spp
    );
    assert!((1.0 / 1.1..=1.1).contains(&ratio), "{ratio}");
    let (need, got) = (
        required(&q, PUBLISHED),
        run(&q, PUBLISHED, true).expect("run"),
    );
    eprintln!(
        "published: {} at 64 against {} required",
        got.at_ceiling, need.at_ceiling
    );
    assert!(got.at_ceiling <= need.at_ceiling);
}

/// The whole line, the runs without the moment included (slow unoptimised: run with
/// `--release -- --ignored`).
#[test]
#[ignore = "the runs without the moment take 4096 rays at edges"]
fn the_line() {
    let line = check(&jittered_ao(SIZE, GRID)).expect("check");
    println!("{}", line.line());
    assert!(line.pass);
}

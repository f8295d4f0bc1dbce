//! The docs/algorithms.md §7 *circle* scenario: one pixel whose integrand is `4/pi` inside the disk of
//! radius 0.5 centred in the unit square and 0 outside (mean 1, per-sample variance
//! `4/pi - 1 ~ 0.2732`), sampled uniformly, under the SPVG controller with `eta = 0.2`,
//! `sigma0^2 = 0.08^2`, budget `[8, 64]`, for `kappa = 0` and `kappa = 1`, each from the
//! zero history and from the disocclusion seed (`history_valid = false` on frame 0).
//!
//! The count that reaches the target is `(4/pi - 1) / 0.08^2 ~ 42.7`.
//!
//! Run with `cargo run --example circle`.

// The scenario (integrand, estimate, controller parameters, one frame's step) and its
// generator are shared with tests/controller.rs, which checks the settled count.
use spvg_fixtures::circle;

use spvg::SpvgHistory;
use spvg_fixtures::splitmix::SplitMix64;

struct Run {
    label: String,
    counts: Vec<u32>,
    variances: Vec<f64>,
    errors: Vec<f64>,
}

fn run(kappa: f64, seeded: bool, frames: usize, seed: u64) -> Result<Run, spvg::Error> {
    let config = circle::config(kappa)?;
    let mut rng = SplitMix64(seed);
    let mut history = SpvgHistory::default();
    let mut run = Run {
        label: format!(
            "kappa={kappa} {}",
            if seeded { "seeded" } else { "zero-history" }
        ),
        counts: Vec::new(),
        variances: Vec::new(),
        errors: Vec::new(),
    };
    for t in 0..frames {
        // With `seeded`, frame 0 is a disocclusion: its history is declared invalid.
        let frame = circle::frame(&config, &mut history, &mut rng, t, seeded);
        run.counts.push(frame.count);
        run.variances.push(history.variance);
        run.errors.push(frame.sample - 1.0);
    }
    Ok(run)
}

fn main() -> Result<(), spvg::Error> {
    let frames = 30;
    let per_sample = circle::per_sample_variance();
    let target = circle::TARGET;
    println!(
        "circle: per-sample variance {per_sample:.4}, target {target}, ideal count {:.1}",
        per_sample / target
    );
    let runs = [
        run(0.0, false, frames, 1)?,
        run(1.0, false, frames, 1)?,
        run(0.0, true, frames, 1)?,
        run(1.0, true, frames, 1)?,
    ];
    print!("frame");
    for r in &runs {
        print!(" | {:>26}", r.label);
    }
    println!();
    print!("     ");
    for _ in &runs {
        print!(" | {:>4} {:>10} {:>10}", "n", "var", "S-1");
    }
    println!();
    for t in 0..frames {
        print!("{t:>5}");
        for r in &runs {
            print!(
                " | {:>4} {:>10.6} {:>10.6}",
                r.counts[t], r.variances[t], r.errors[t]
            );
        }
        println!();
    }
    for r in &runs {
        let at_max = r.counts.iter().filter(|&&n| n == 64).count();
        let mean_count = r.counts.iter().map(|&n| f64::from(n)).sum::<f64>() / frames as f64;
        let mse = r.errors.iter().map(|e| e * e).sum::<f64>() / frames as f64;
        let first_below_max = r.counts[1..]
            .iter()
            .position(|&n| n < 64)
            .map_or_else(|| "never".to_owned(), |t| (t + 1).to_string());
        println!(
            "{:<20} mean count {mean_count:5.2} over {frames} frames, {at_max:2} frames at the \
             budget max, first frame below it after frame 0: {first_below_max}, mean squared \
             error {:.2} x target",
            r.label,
            mse / target
        );
    }
    policy_table()
}

/// The table of docs/algorithms.md §8.1: kappa = 0, kappa = 1 and the damped correction
/// from the zero history, over 2000 pixels and 400 frames (steady window from frame 100),
/// then the damped correction's cap swept around its setting.
fn policy_table() -> Result<(), spvg::Error> {
    let (pixels, frames, steady_from) = (2000, 400, 100);
    println!(
        "\npolicies from the zero history ({pixels} pixels, {frames} frames, steady window \
         from frame {steady_from}):"
    );
    println!(
        "{:<22} | {:>24} | {:>16} | {:>20} | {:>17} | {:>19}",
        "policy",
        "frames to within 10%",
        "steady mean |dn|",
        "lag-1 autocorrelation",
        "steady mean count",
        "samples, frames 0-29"
    );
    let damped = circle::damped_config()?;
    let mut rows = vec![
        ("kappa=0".to_owned(), circle::config(0.0)?),
        ("kappa=1".to_owned(), circle::config(1.0)?),
        (format!("damped c={}", circle::DAMPED_MAX_CHANGE), damped),
    ];
    for c in [0.25, 0.3, 0.33, 0.37, 0.4, 0.5] {
        rows.push((
            format!("  sweep: damped c={c}"),
            damped.to_builder().max_change(Some(c)).build()?,
        ));
    }
    for (label, config) in &rows {
        let f = circle::figures(config, pixels, frames, steady_from);
        println!(
            "{label:<22} | {:>24} | {:>16.2} | {:>21.2} | {:>17.2} | {:>19.1}",
            f.frames_to_band, f.mean_abs_step, f.lag1, f.steady_mean, f.cold_start_samples
        );
    }
    Ok(())
}

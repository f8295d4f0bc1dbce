//! The SPEC 7 *circle* scenario: one pixel whose integrand is `4/pi` inside the disk of
//! radius 0.5 centred in the unit square and 0 outside (mean 1, per-sample variance
//! `4/pi - 1 ~ 0.2732`), sampled uniformly, under the SPVG controller with `eta = 0.2`,
//! `sigma0^2 = 0.08^2`, budget `[8, 64]`, for `kappa = 0` and `kappa = 1`, each from the
//! zero history and from the disocclusion seed (`history_valid = false` on frame 0).
//!
//! The count that reaches the target is `(4/pi - 1) / 0.08^2 ~ 42.7`.
//!
//! Run with `cargo run --example circle`.

use spvg::{SpvgConfig, SpvgHistory};

/// splitmix64 (Steele, Lea & Flood 2014): a tiny deterministic generator.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) with 53 random bits.
    fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// The circle integrand at a point of the unit square.
fn integrand(x: f64, y: f64) -> f64 {
    let (dx, dy) = (x - 0.5, y - 0.5);
    if dx * dx + dy * dy <= 0.25 {
        4.0 / std::f64::consts::PI
    } else {
        0.0
    }
}

/// One frame's Monte Carlo estimate with `n` uniform samples.
fn estimate(rng: &mut SplitMix64, n: u32) -> f64 {
    let sum: f64 = (0..n)
        .map(|_| {
            let x = rng.next_f64();
            let y = rng.next_f64();
            integrand(x, y)
        })
        .sum();
    sum / f64::from(n)
}

struct Run {
    label: String,
    counts: Vec<u32>,
    variances: Vec<f64>,
    errors: Vec<f64>,
}

fn run(kappa: f64, seeded: bool, frames: usize, seed: u64) -> Result<Run, spvg::Error> {
    let config = SpvgConfig::<f64>::builder()
        .eta(0.2)
        .target_variance(0.08 * 0.08)
        .kappa(kappa)
        .budget(8, 64)
        .build()?;
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
    for frame in 0..frames {
        // The disocclusion seed: the first frame's history is declared invalid.
        let valid = !(seeded && frame == 0);
        let n = config.estimate_with_validity(&history, 1.0, valid);
        let s = estimate(&mut rng, n);
        config.update(&mut history, s, n, valid);
        run.counts.push(n);
        run.variances.push(history.variance);
        run.errors.push(s - 1.0);
    }
    Ok(run)
}

fn main() -> Result<(), spvg::Error> {
    let frames = 30;
    let per_sample = 4.0 / std::f64::consts::PI - 1.0;
    let target = 0.08_f64 * 0.08;
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
    Ok(())
}

//! Function-level equality: every exported WGSL function against the core crate function
//! it mirrors, bit for bit, on the hard cases of `spvg::arbitrary` (NaN, +-inf, +-0,
//! subnormals, +-MAX, f16 extremes, values next to 1) and on budget edges, under a set
//! of parameter blocks that spans the validated ranges (weights down to subnormals,
//! targets from 3e-39 to 3e38, budgets [1, 1] to [u32::MAX, u32::MAX], every count
//! policy with and without the damped correction, the firefly clamp off and on (`k` from
//! 1e-30 to 3e38), AS/CCV/OCV, f16 and f32 texels, nearest and stochastic rounding).
//!
//! Runs on the first wgpu adapter (lavapipe on CI) and skips, passing, where there is
//! none. Permitted differences, each applied only where stated:
//! - NaN: any NaN equals any NaN (IEEE leaves a produced NaN's payload and sign open).
//! - Burley functions (`spvg_burley_*`, `spvg_filtered_mip_level`): they call the
//!   device's exp/log/asinh/sinh/cosh, which Vulkan does not require to be correctly
//!   rounded (exp: 3 + 2|x| ulp); results agree within the relative bound stated at each
//!   call, and exactly on every special case (NaN, 0, 1, infinities).
//! - `spvg_filtered_mip_index`: compared with the floor of the core's
//!   `filtered_mip_level`, whose libm `log2` rounds `q` a few ulps above a power of 4 to
//!   the integer: there the exact comparison of the shader is one level finer (the
//!   oracle skips those `q`, counted).
//!
//! `cargo test -p spvg-shaders --test equality -- --nocapture` prints the case count and
//! the identical count of every function.

mod harness;

use half::f16;
use harness::{Batch, Run as _, Word, compare, compare_or, gpu};
use spvg::arbitrary::{finite_f32_from_bits, hard_f32_from_bits, weight_f32_from_bits};
use spvg::budget::{FrameDemand, count_at};
use spvg::burley::{BurleyProfile, RatioEstimator, filtered_mip_level, footprint_radius};
use spvg::controller::CountPolicy;
use spvg::controller::fractional::{
    fractional_raw_count, realise_count, recorded_count, skips, span_weight,
};
use spvg::controller::rules::{firefly_clamp, per_sample_variance};
use spvg::controller::young::{SpatialMoments, age_weight, next_age, read_age, spatial_window};
use spvg::cv::{As, Ccv, ControlModel, Ocv, PixelController, PixelFrame};
use spvg::dilation::{KEEP, dilated_count, dilated_count_with_prior, tile_region};
use spvg::reproject::{
    BorderCount, HistorySource, PreviousSample, Reprojection, border_texel, footprint_texel,
    previous_texel,
};
use spvg::sequence::{dither_threshold, pcg3d16, r2_offset_from_seed, r2_point, to_unit_f32};
use spvg::texel::{
    CvTexel16, CvTexel32, Layout, Rounding, SpvgTexel16, SpvgTexel32, Texel, TexelEncoding,
    channel_bits, to_f16,
};
use spvg::{CvHistory, SpvgConfig, SpvgHistory};
use spvg_shaders::{Control, Params, ReprojectionRule, Storage, StoreRounding};

/// Cases per parameter block.
const N: usize = 2048;

/// splitmix64: a reproducible stream of 64-bit words.
struct Gen(u64);

impl Gen {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn u32(&mut self) -> u32 {
        (self.next() >> 32) as u32
    }
    /// A hard f32 (`spvg::arbitrary`): NaN, +-inf, +-0, subnormals, +-MAX, near 1, ...
    fn hard(&mut self) -> f32 {
        hard_f32_from_bits(self.next())
    }
    /// Uniform in [0, 1) on a 2^-24 grid.
    fn unit(&mut self) -> f32 {
        (self.u32() >> 8) as f32 / 16_777_216.0
    }
    /// A weight-like value in (0, 1] (`spvg::arbitrary`), 0 now and then.
    fn ratio(&mut self) -> f32 {
        if self.u32().is_multiple_of(16) {
            0.0
        } else {
            weight_f32_from_bits(self.next())
        }
    }
    /// A count: 0, budget edges, f32 rounding edges or a random word.
    fn count(&mut self, c: &SpvgConfig<f32>) -> u32 {
        let edges = [
            0,
            1,
            c.min_samples(),
            c.max_samples(),
            c.min_samples().saturating_sub(1),
            c.max_samples().saturating_add(1),
            8,
            64,
            16_777_217,
            u32::MAX,
        ];
        let r = self.u32();
        if r.is_multiple_of(3) {
            r >> (r % 32)
        } else {
            edges[(r as usize / 3) % edges.len()]
        }
    }
    fn flag(&mut self) -> u32 {
        self.u32() & 1
    }
    /// An f16 value widened to f32, from raw f16 bits half the time (inf and NaN
    /// included) and from a hard f32 the other half.
    fn f16_value(&mut self) -> f32 {
        if self.u32() & 1 == 0 {
            f16::from_bits((self.u32() >> 16) as u16).to_f32()
        } else {
            f16::from_f32(self.hard()).to_f32()
        }
    }
}

fn bits(x: f32) -> u32 {
    x.to_bits()
}

/// One parameter block and the core objects it was built from.
struct Setup {
    config: SpvgConfig<f32>,
    control: Control,
    enc: TexelEncoding,
    layout: Layout,
    rounding: StoreRounding,
    params: Params,
}

/// Parameter blocks spanning the validated ranges; configurations the core rejects are
/// skipped (e.g. a weight whose 2/eta overflows).
fn setups() -> Vec<Setup> {
    let targets = [1e-4, 5e-7, 1.0, 0.25, 3.0e38, 2.94e-39, 1e-30, 1e30, 1e-3];
    let budgets = [
        (8, 64),
        (1, 1),
        (1, 1024),
        (64, 64),
        // The budget's ceiling (`MAX_BUDGET`, 4096): the builder refuses a larger
        // maximum, so the extremes a shader meets are at the ceiling, not at u32::MAX.
        (1, 4096),
        (4096, 4096),
        (3, 4095),
    ];
    let kappas = [0.2, 0.0, 1.0, 0.7];
    let eps_us = [0.01, 0.0, 1.0];
    let eps_as = [1e-6, 0.0, 1.0, 3.0e38];
    let a0s = [1.0, 0.0, 1e30, 2.5];
    let mut g = Gen(7);
    let mut out = Vec::new();
    for k in 0..24_usize {
        let eta = if k == 0 {
            0.2
        } else {
            weight_f32_from_bits(g.next())
        };
        let (lo, hi) = budgets[k % budgets.len()];
        let policy = match k % 6 {
            1 => CountPolicy::TwoPhase,
            3 => CountPolicy::UnrealClamp,
            5 => CountPolicy::Fixed(lo),
            _ => CountPolicy::Spvg,
        };
        let Ok(config) = SpvgConfig::<f32>::builder()
            .eta(eta)
            .target_variance(targets[k % targets.len()])
            .kappa(kappas[k % kappas.len()])
            .budget(lo, hi)
            .eps_u(eps_us[k % eps_us.len()])
            .policy(policy)
            .max_change([None, Some(0.5), Some(1e-7), Some(3.0e38)][k % 4])
            .firefly_clamp([None, Some(8.0), Some(0.5), Some(1e-30), Some(3.0e38)][k % 5])
            .age_weight(k % 3 != 1)
            .spatial_variance([2, 0, 1, 255, 4][k % 5])
            .build()
        else {
            continue;
        };
        let eta_cv = if k % 5 == 0 {
            0.2
        } else {
            weight_f32_from_bits(g.next())
        };
        let control = match k % 4 {
            1 => Control::As,
            2 => Control::Ccv,
            _ => match Ocv::new(eta_cv, eps_as[(k / 2) % 4], a0s[(k / 3) % 4]) {
                Ok(o) => Control::Ocv(o.with_f16_inputs(k % 8 < 4)),
                Err(_) => Control::Ccv,
            },
        };
        let mut enc = TexelEncoding::for_config(&config)
            .unwrap_or_else(|_| TexelEncoding::new(1e-4).expect("valid"));
        if let Control::Ocv(o) = control {
            enc = enc.for_ocv(&o).unwrap_or(enc);
        }
        let layout = if (k / 2) % 2 == 0 {
            Layout::F16
        } else {
            Layout::F32
        };
        let rounding = if (k / 3) % 2 == 0 {
            StoreRounding::Nearest
        } else {
            StoreRounding::Stochastic
        };
        let params = Params::new(
            &config,
            control,
            &Storage {
                encoding: enc,
                layout,
                rounding,
            },
        );
        out.push(Setup {
            config,
            control,
            enc,
            layout,
            rounding,
            params,
        });
    }
    out
}

/// `N` cases per setup, each from `case(setup, gen)`.
fn batches(all: &[Setup], seed: u64, case: impl Fn(&Setup, &mut Gen) -> Vec<u32>) -> Vec<Batch> {
    let mut g = Gen(seed);
    all.iter()
        .map(|s| Batch {
            params: s.params,
            input: (0..N).flat_map(|_| case(s, &mut g)).collect(),
        })
        .collect()
}

fn f(w: u32) -> f32 {
    f32::from_bits(w)
}

fn history(w: &[u32]) -> SpvgHistory<f32> {
    SpvgHistory {
        mean: f(w[0]),
        variance: f(w[1]),
        mean_count: f(w[2]),
    }
}

fn cv_history(w: &[u32]) -> CvHistory<f32> {
    CvHistory {
        cov_fg: f(w[0]),
        var_g: f(w[1]),
        mean_f: f(w[2]),
        mean_g: f(w[3]),
    }
}

/// A history: fully hard, or realistic (variance around the target, counts in the
/// budget) so that the estimate's interior is covered too.
fn gen_history(s: &Setup, g: &mut Gen) -> [u32; 3] {
    if g.u32().is_multiple_of(2) {
        [bits(g.hard()), bits(g.hard()), bits(g.hard())]
    } else {
        let t = s.config.target_variance();
        let var = match g.u32() % 4 {
            0 => t,
            1 => t * (g.unit() * 20.0),
            2 => t * (1.0 + (g.u32() % 5) as f32 * f32::EPSILON),
            _ => g.hard(),
        };
        let mc = match g.u32() % 3 {
            0 => (g.u32() % 80) as f32,
            1 => g.unit() * 80.0,
            _ => g.hard(),
        };
        [bits(g.hard()), bits(var), bits(mc)]
    }
}

/// A monitored value for a history `h` (three words): a unit value, a hard value, or
/// within +-20 of the history's sigma of its mean, where the firefly clamp's bounds lie
/// (`k` = 8 and 0.5 in the setups), the bounds themselves included.
fn gen_sample(s: &Setup, g: &mut Gen, h: &[u32]) -> f32 {
    let (mean, var) = (f(h[0]), f(h[1]));
    let sigma = var.max(s.config.target_variance()).sqrt();
    let k = s.config.firefly_clamp().unwrap_or(8.0);
    match g.u32() % 5 {
        0 => g.unit(),
        1 => g.hard(),
        2 => mean + k * sigma,
        3 => mean - k * sigma,
        _ => mean + (g.unit() * 40.0 - 20.0) * sigma,
    }
}

fn f32_words(n: usize) -> Vec<Word> {
    vec![Word::F32; n]
}

#[test]
fn controller_functions_match_the_core() {
    let Some(gpu) = gpu("controller_functions_match_the_core") else {
        return;
    };
    let all = setups();

    let b = batches(&all, 1, |s, g| {
        let mut v = gen_history(s, g).to_vec();
        v.push(bits(if g.u32() % 2 == 0 {
            g.ratio()
        } else {
            g.hard()
        }));
        v.push(g.flag());
        v
    });
    compare(
        gpu,
        "spvg_estimate_count",
        "ou(r, spvg_estimate_count(P, spvg_History(f(b), f(b + 1u), f(b + 2u)), f(b + 3u), w(b + 4u) != 0u));",
        5,
        &[Word::U32],
        &b,
        |bi, c| {
            vec![
                all[bi]
                    .config
                    .estimate_with_validity(&history(c), f(c[3]), c[4] != 0),
            ]
        },
    );
    compare(
        gpu,
        "spvg_raw_estimate",
        "o(r, spvg_raw_estimate(P, spvg_History(f(b), f(b + 1u), f(b + 2u))));",
        5,
        &[Word::F32],
        &b,
        |bi, c| vec![bits(all[bi].config.raw_estimate(&history(c)))],
    );
    compare(
        gpu,
        "spvg_frame_demand",
        "let d = spvg_frame_demand(P, spvg_History(f(b), f(b + 1u), f(b + 2u)), f(b + 3u), w(b + 4u) != 0u);
    o(r, d.scaled); o(r + 1u, d.offset); o(r + 2u, d.fixed);",
        5,
        &[Word::F32, Word::F32, Word::F32],
        &b,
        |bi, c| {
            let d = FrameDemand::pixel(&all[bi].config, &history(c), f(c[3]), c[4] != 0);
            vec![bits(d.scaled), bits(d.offset), bits(d.fixed)]
        },
    );

    // One point of the clamped demand curve: a candidate target near the block's (the
    // governor's candidates are sqrt 2 apart), or a hard one.
    let b = batches(&all, 11, |s, g| {
        let mut v = gen_history(s, g).to_vec();
        v.push(bits(if g.u32() % 2 == 0 {
            g.ratio()
        } else {
            g.hard()
        }));
        v.push(g.flag());
        let t = s.config.target_variance();
        v.push(bits(match g.u32() % 3 {
            0 => t * 2.0_f32.powf((g.u32() % 16) as f32 * 0.5 - 4.0),
            1 => t * (0.01 + g.unit() * 100.0),
            _ => g.hard(),
        }));
        v
    });
    compare(
        gpu,
        "spvg_count_at",
        "ou(r, spvg_count_at(P, f(b + 5u), spvg_History(f(b), f(b + 1u), f(b + 2u)), f(b + 3u), w(b + 4u) != 0u));",
        6,
        &[Word::U32],
        &b,
        |bi, c| {
            vec![count_at(
                &all[bi].config,
                f(c[5]),
                &history(c),
                f(c[3]),
                c[4] != 0,
            )]
        },
    );

    let b = batches(&all, 2, |s, g| {
        let x = match g.u32() % 4 {
            0 => s.config.min_samples_f() + (g.unit() - 0.5) * 4.0,
            1 => s.config.max_samples_f() * (1.0 + (g.unit() - 0.5) * 1e-6),
            2 => g.unit() * 100.0,
            _ => g.hard(),
        };
        vec![bits(x)]
    });
    compare(
        gpu,
        "spvg_round_count",
        "ou(r, spvg_round_count(P, f(b)));",
        1,
        &[Word::U32],
        &b,
        |bi, c| vec![all[bi].config.round_count(f(c[0]))],
    );
    compare(
        gpu,
        "spvg_samples_distant",
        "ob(r, spvg_samples_distant(P, f(b)));",
        1,
        &[Word::U32],
        &b,
        |bi, c| vec![u32::from(all[bi].config.samples_distant(f(c[0])))],
    );

    let b = batches(&all, 3, |_, g| {
        let r = g.u32();
        vec![if r % 2 == 0 { r } else { r >> (r % 32) }]
    });
    compare(
        gpu,
        "spvg_u32_to_f32",
        "o(r, spvg_u32_to_f32(w(b)));",
        1,
        &[Word::F32],
        &b,
        |_, c| vec![bits(c[0] as f32)],
    );

    // The clamp on the domain it is called on: a read history (finite mean, variance
    // >= 0), a finite sample (the update refuses the others first); k = 0 where off.
    let b = batches(&all, 11, |s, g| {
        let mut v = vec![
            bits(finite_f32_from_bits(g.next())),
            bits(finite_f32_from_bits(g.next()).abs()),
            0,
        ];
        if g.u32().is_multiple_of(2) {
            v[0] = bits(g.unit());
            v[1] = bits(s.config.target_variance() * g.unit() * 20.0);
        }
        let x = gen_sample(s, g, &v);
        v[2] = bits(if x.is_finite() { x } else { 0.0 });
        v
    });
    compare(
        gpu,
        "spvg_firefly_clamp",
        "o(r, spvg_firefly_clamp(P, f(b), f(b + 1u), f(b + 2u)));",
        3,
        &[Word::F32],
        &b,
        |bi, c| {
            let cfg = &all[bi].config;
            let k = cfg.firefly_clamp().unwrap_or(0.0);
            let t = cfg.target_variance();
            vec![bits(firefly_clamp(k, t, f(c[0]), f(c[1]), f(c[2])))]
        },
    );
    let b = batches(&all, 4, |s, g| {
        let mut v = gen_history(s, g).to_vec();
        v.push(bits(gen_sample(s, g, &v)));
        v.push(g.count(&s.config));
        v.push(g.flag());
        v
    });
    // The cases must reach the clamp: count those whose result it changes.
    let clamped: usize = b
        .iter()
        .zip(&all)
        .filter(|(_, s)| s.config.firefly_clamp().is_some())
        .map(|(batch, s)| {
            let off = s.config.to_builder().firefly_clamp(None).build();
            let off = off.expect("valid");
            batch
                .input
                .chunks(6)
                .filter(|c| {
                    let (mut on_h, mut off_h) = (history(c), history(c));
                    s.config.update(&mut on_h, f(c[3]), c[4], c[5] != 0);
                    off.update(&mut off_h, f(c[3]), c[4], c[5] != 0);
                    on_h != off_h
                })
                .count()
        })
        .sum();
    eprintln!("spvg_update_history: the firefly clamp changes {clamped} cases");
    assert!(
        clamped > 2000,
        "only {clamped} cases reach the firefly clamp"
    );
    compare(
        gpu,
        "spvg_update_history",
        "let u = spvg_update_history(P, spvg_History(f(b), f(b + 1u), f(b + 2u)), f(b + 3u), w(b + 4u), w(b + 5u) != 0u);
    o(r, u.history.mean); o(r + 1u, u.history.variance); o(r + 2u, u.history.mean_count); ob(r + 3u, u.accepted);",
        6,
        &[Word::F32, Word::F32, Word::F32, Word::U32],
        &b,
        |bi, c| {
            let mut h = history(c);
            let ok = all[bi].config.update(&mut h, f(c[3]), c[4], c[5] != 0);
            vec![bits(h.mean), bits(h.variance), bits(h.mean_count), u32::from(ok)]
        },
    );
    // The guided update: the same cases with a guide that is the history's mean (the
    // identity with the unguided rule), near the sample (a TAA history), hard (NaN and
    // the infinities fall back to the mean) or random.
    let b = batches(&all, 5, |s, g| {
        let mut v = gen_history(s, g).to_vec();
        let x = gen_sample(s, g, &v);
        v.push(bits(x));
        v.push(g.count(&s.config));
        v.push(g.flag());
        let guide = match g.u32() % 4 {
            0 => f(v[0]),
            1 => x + (g.unit() - 0.5) * 0.1,
            2 => g.hard(),
            _ => g.unit(),
        };
        v.push(bits(guide));
        v
    });
    compare(
        gpu,
        "spvg_update_history_guided",
        "let u = spvg_update_history_guided(P, spvg_History(f(b), f(b + 1u), f(b + 2u)), f(b + 3u), f(b + 6u), w(b + 4u), w(b + 5u) != 0u);
    o(r, u.history.mean); o(r + 1u, u.history.variance); o(r + 2u, u.history.mean_count); ob(r + 3u, u.accepted);",
        7,
        &[Word::F32, Word::F32, Word::F32, Word::U32],
        &b,
        |bi, c| {
            let mut h = history(c);
            let ok = all[bi]
                .config
                .update_guided(&mut h, f(c[3]), f(c[6]), c[4], c[5] != 0);
            vec![bits(h.mean), bits(h.variance), bits(h.mean_count), u32::from(ok)]
        },
    );
}

/// The OCV model of a setup (the coefficient functions with AS/CCV blocks use eps_a = 0,
/// a0 = 0, eta_cv = 1, which is what `Params` holds for them).
fn ocv_of(s: &Setup) -> Ocv<f32> {
    match s.control {
        Control::Ocv(o) => o,
        Control::As | Control::Ccv => Ocv::new(1.0, 0.0, 0.0).expect("valid"),
    }
}

fn gen_cv(g: &mut Gen) -> [u32; 4] {
    if g.u32().is_multiple_of(2) {
        [
            bits(g.hard()),
            bits(g.hard()),
            bits(g.hard()),
            bits(g.hard()),
        ]
    } else {
        let m = g.unit() * 2.0;
        [
            bits((g.unit() - 0.3) * 1e-3),
            bits(g.unit() * 1e-3),
            bits(m),
            bits(m * (0.5 + g.unit())),
        ]
    }
}

fn gen_luminance(g: &mut Gen) -> f32 {
    match g.u32() % 3 {
        0 => g.unit() * 2.0,
        1 => g.hard(),
        _ => 0.0,
    }
}

#[test]
fn cv_functions_match_the_core() {
    let Some(gpu) = gpu("cv_functions_match_the_core") else {
        return;
    };
    let all = setups();
    // The issue's reproducer: eps_a = 0 makes the raw ratio 1e-9 / 0 = +inf, which
    // saturates and takes the upper bound a0 + fbar / G = 2.619.
    let repro = {
        let config = SpvgConfig::<f32>::published();
        let ocv = Ocv::new(0.5_f32, 0.0, 1.0).expect("valid");
        let enc = TexelEncoding::for_config(&config).expect("valid");
        let storage = Storage {
            encoding: enc,
            layout: Layout::F32,
            rounding: StoreRounding::Nearest,
        };
        Batch {
            params: Params::new(&config, Control::Ocv(ocv), &storage),
            input: [1e-9_f32, 0.0, 0.3, 0.2, 0.34, 0.21].map(bits).to_vec(),
        }
    };
    let got = gpu.run(
        "o(r, spvg_cv_coefficient(P, spvg_CvHistory(f(b), f(b + 1u), f(b + 2u), f(b + 3u)), f(b + 4u), f(b + 5u)));",
        6,
        1,
        &[repro],
    );
    let want = Ocv::new(0.5_f32, 0.0, 1.0).expect("valid").coefficient(
        &CvHistory {
            cov_fg: 1e-9,
            var_g: 0.0,
            mean_f: 0.3,
            mean_g: 0.2,
        },
        0.34,
        0.21,
    );
    assert_eq!(f(got[0][0]), want, "the infinite-ratio ocv_alpha case");
    assert!(
        (want - 2.619).abs() < 1e-3,
        "core gives the upper bound {want}"
    );

    let b = batches(&all, 11, |_, g| {
        let mut v = gen_cv(g).to_vec();
        v.push(bits(gen_luminance(g)));
        v.push(bits(gen_luminance(g)));
        v
    });
    compare(
        gpu,
        "spvg_cv_coefficient",
        "o(r, spvg_cv_coefficient(P, spvg_CvHistory(f(b), f(b + 1u), f(b + 2u), f(b + 3u)), f(b + 4u), f(b + 5u)));",
        6,
        &[Word::F32],
        &b,
        |bi, c| {
            let j = cv_history(c);
            let a = match all[bi].control {
                Control::As => As.coefficient(&(), f(c[4]), f(c[5])),
                Control::Ccv => Ccv.coefficient(&(), f(c[4]), f(c[5])),
                Control::Ocv(o) => o.coefficient(&j, f(c[4]), f(c[5])),
            };
            vec![bits(a)]
        },
    );
    compare(
        gpu,
        "spvg_raw_coefficient",
        "o(r, spvg_raw_coefficient(P, spvg_CvHistory(f(b), f(b + 1u), f(b + 2u), f(b + 3u))));",
        6,
        &[Word::F32],
        &b,
        |bi, c| vec![bits(ocv_of(&all[bi]).raw_coefficient(&cv_history(c)))],
    );
    let b3 = batches(&all, 12, |_, g| {
        vec![
            bits(g.hard()),
            bits(gen_luminance(g)),
            bits(gen_luminance(g)),
        ]
    });
    compare(
        gpu,
        "spvg_clamp_to_bound",
        "o(r, spvg_clamp_to_bound(P, f(b), f(b + 1u), f(b + 2u)));",
        3,
        &[Word::F32],
        &b3,
        |bi, c| {
            vec![bits(ocv_of(&all[bi]).clamp_to_bound(
                f(c[0]),
                f(c[1]),
                f(c[2]),
            ))]
        },
    );
    // Ocv::update_inputs is defined for finite input (the update refuses the rest).
    let b = batches(&all, 16, |_, g| {
        vec![
            bits(finite_f32_from_bits(g.next())),
            bits(finite_f32_from_bits(g.next())),
        ]
    });
    compare(
        gpu,
        "spvg_update_inputs",
        "let z = spvg_update_inputs(P, f(b), f(b + 1u)); o(r, z.x); o(r + 1u, z.y);",
        2,
        &f32_words(2),
        &b,
        |bi, c| {
            let (a, b) = ocv_of(&all[bi]).update_inputs(f(c[0]), f(c[1]));
            vec![bits(a), bits(b)]
        },
    );

    let b = batches(&all, 13, |_, g| {
        let mut v = gen_cv(g).to_vec();
        v.push(bits(gen_luminance(g)));
        v.push(bits(gen_luminance(g)));
        v.push(g.flag());
        v
    });
    compare(
        gpu,
        "spvg_update_cv",
        "let u = spvg_update_cv(P, spvg_CvHistory(f(b), f(b + 1u), f(b + 2u), f(b + 3u)), f(b + 4u), f(b + 5u), w(b + 6u) != 0u);
    o(r, u.cv.cov_fg); o(r + 1u, u.cv.var_g); o(r + 2u, u.cv.mean_f); o(r + 3u, u.cv.mean_g); ob(r + 4u, u.accepted);",
        7,
        &[Word::F32, Word::F32, Word::F32, Word::F32, Word::U32],
        &b,
        |bi, c| {
            let mut j = cv_history(c);
            let ok = match all[bi].control {
                Control::As => As.update_state(&mut (), f(c[4]), f(c[5]), c[6] != 0),
                Control::Ccv => Ccv.update_state(&mut (), f(c[4]), f(c[5]), c[6] != 0),
                Control::Ocv(o) => o.update_state(&mut j, f(c[4]), f(c[5]), c[6] != 0),
            };
            vec![
                bits(j.cov_fg),
                bits(j.var_g),
                bits(j.mean_f),
                bits(j.mean_g),
                u32::from(ok),
            ]
        },
    );

    let b = batches(&all, 14, |s, g| {
        let mut v = gen_history(s, g).to_vec();
        v.extend(gen_cv(g));
        v.push(bits(gen_luminance(g)));
        v.push(bits(gen_luminance(g)));
        v.push(bits(if g.u32() % 2 == 0 {
            g.ratio()
        } else {
            g.hard()
        }));
        v.push(g.count(&s.config));
        v.push(g.flag());
        v
    });
    compare(
        gpu,
        "spvg_update_pixel",
        "let s = spvg_update_pixel(P, spvg_History(f(b), f(b + 1u), f(b + 2u)),
        spvg_CvHistory(f(b + 3u), f(b + 4u), f(b + 5u), f(b + 6u)), f(b + 7u), f(b + 8u), f(b + 9u),
        w(b + 10u), w(b + 11u) != 0u);
    o(r, s.history.mean); o(r + 1u, s.history.variance); o(r + 2u, s.history.mean_count);
    o(r + 3u, s.cv.cov_fg); o(r + 4u, s.cv.var_g); o(r + 5u, s.cv.mean_f); o(r + 6u, s.cv.mean_g);
    o(r + 7u, s.alpha); o(r + 8u, s.monitored); ob(r + 9u, s.accepted);",
        12,
        &[
            Word::F32,
            Word::F32,
            Word::F32,
            Word::F32,
            Word::F32,
            Word::F32,
            Word::F32,
            Word::F32,
            Word::F32,
            Word::U32,
        ],
        &b,
        |bi, c| {
            let s = &all[bi];
            let mut h = history(c);
            let mut j = cv_history(&c[3..]);
            let frame = PixelFrame {
                radiance: f(c[7]),
                preintegrated: f(c[8]),
                gamma: f(c[9]),
            };
            let (n, valid) = (c[10], c[11] != 0);
            let u = match s.control {
                Control::As => {
                    PixelController::new(s.config, As).update(&mut h, &mut (), frame, n, valid)
                }
                Control::Ccv => {
                    PixelController::new(s.config, Ccv).update(&mut h, &mut (), frame, n, valid)
                }
                Control::Ocv(o) => {
                    PixelController::new(s.config, o).update(&mut h, &mut j, frame, n, valid)
                }
            };
            vec![
                bits(h.mean),
                bits(h.variance),
                bits(h.mean_count),
                bits(j.cov_fg),
                bits(j.var_g),
                bits(j.mean_f),
                bits(j.mean_g),
                bits(u.alpha),
                bits(u.monitored),
                u32::from(u.accepted),
            ]
        },
    );
    let b = batches(&all, 15, |_, g| {
        vec![
            bits(gen_luminance(g)),
            bits(gen_luminance(g)),
            bits(g.ratio()),
        ]
    });
    compare(
        gpu,
        "spvg_split",
        "let z = spvg_split(f(b), f(b + 1u), f(b + 2u)); o(r, z.x); o(r + 1u, z.y);",
        3,
        &f32_words(2),
        &b,
        |_, c| {
            let (x, y) = PixelController::<f32, As>::split(&PixelFrame {
                radiance: f(c[0]),
                preintegrated: f(c[1]),
                gamma: f(c[2]),
            });
            vec![bits(x), bits(y)]
        },
    );
}

fn rounding_of(s: &Setup, random: u32) -> Rounding {
    match s.rounding {
        StoreRounding::Nearest => Rounding::Nearest,
        StoreRounding::Stochastic => Rounding::Stochastic(random),
    }
}

/// A stored channel value as the layout holds it.
fn stored(s: &Setup, g: &mut Gen) -> u32 {
    match s.layout {
        Layout::F16 => bits(g.f16_value()),
        Layout::F32 => bits(g.hard()),
    }
}

#[test]
fn texel_functions_match_the_core() {
    let Some(gpu) = gpu("texel_functions_match_the_core") else {
        return;
    };
    let all = setups();
    let b = batches(&all, 21, |s, g| (0..4).map(|_| stored(s, g)).collect());
    compare(
        gpu,
        "spvg_decode_history",
        "let h = spvg_decode_history(P, vec4<f32>(f(b), f(b + 1u), f(b + 2u), f(b + 3u)));
    o(r, h.mean); o(r + 1u, h.variance); o(r + 2u, h.mean_count);",
        4,
        &f32_words(3),
        &b,
        |bi, c| {
            let s = &all[bi];
            let h = match s.layout {
                Layout::F16 => SpvgTexel16(
                    c.iter()
                        .map(|w| f16::from_f32(f(*w)))
                        .collect::<Vec<_>>()
                        .try_into()
                        .expect("4"),
                )
                .decode(&s.enc),
                Layout::F32 => SpvgTexel32([f(c[0]), f(c[1]), f(c[2]), f(c[3])]).decode(&s.enc),
            };
            vec![bits(h.mean), bits(h.variance), bits(h.mean_count)]
        },
    );
    compare(
        gpu,
        "spvg_decode_cv",
        "let j = spvg_decode_cv(P, vec4<f32>(f(b), f(b + 1u), f(b + 2u), f(b + 3u)));
    o(r, j.cov_fg); o(r + 1u, j.var_g); o(r + 2u, j.mean_f); o(r + 3u, j.mean_g);",
        4,
        &f32_words(4),
        &b,
        |bi, c| {
            let s = &all[bi];
            let j = match s.layout {
                Layout::F16 => CvTexel16(
                    c.iter()
                        .map(|w| f16::from_f32(f(*w)))
                        .collect::<Vec<_>>()
                        .try_into()
                        .expect("4"),
                )
                .decode(&s.enc),
                Layout::F32 => CvTexel32([f(c[0]), f(c[1]), f(c[2]), f(c[3])]).decode(&s.enc),
            };
            vec![
                bits(j.cov_fg),
                bits(j.var_g),
                bits(j.mean_f),
                bits(j.mean_g),
            ]
        },
    );

    let b = batches(&all, 22, |_, g| {
        let mut v: Vec<u32> = (0..4)
            .map(|_| {
                bits(if g.u32() % 2 == 0 {
                    g.hard()
                } else {
                    g.unit() * 3.0
                })
            })
            .collect();
        v.push(g.u32());
        v
    });
    let texel_words = |t: [f16; 4]| t.map(|x| bits(x.to_f32())).to_vec();
    compare(
        gpu,
        "spvg_encode_history",
        "let t = spvg_encode_history(P, spvg_History(f(b), f(b + 1u), f(b + 2u)), w(b + 4u));
    o(r, t.x); o(r + 1u, t.y); o(r + 2u, t.z); o(r + 3u, t.w);",
        5,
        &f32_words(4),
        &b,
        |bi, c| {
            let s = &all[bi];
            let h = history(c);
            let rounding = rounding_of(s, c[4]);
            match s.layout {
                Layout::F16 => texel_words(SpvgTexel16::encode(&s.enc, &h, rounding).0),
                Layout::F32 => SpvgTexel32::encode(&s.enc, &h, rounding)
                    .0
                    .map(bits)
                    .to_vec(),
            }
        },
    );
    compare(
        gpu,
        "spvg_encode_cv",
        "let t = spvg_encode_cv(P, spvg_CvHistory(f(b), f(b + 1u), f(b + 2u), f(b + 3u)), w(b + 4u));
    o(r, t.x); o(r + 1u, t.y); o(r + 2u, t.z); o(r + 3u, t.w);",
        5,
        &f32_words(4),
        &b,
        |bi, c| {
            let s = &all[bi];
            let j = cv_history(c);
            let rounding = rounding_of(s, c[4]);
            match s.layout {
                Layout::F16 => texel_words(CvTexel16::encode(&s.enc, &j, rounding).0),
                Layout::F32 => CvTexel32::encode(&s.enc, &j, rounding).0.map(bits).to_vec(),
            }
        },
    );

    // Every f16 neighbourhood: each f16 value, the midpoints (ties) and the f32 values
    // next to them, both signs, plus hard f32 values, with random words.
    let mut xs: Vec<f32> = Vec::new();
    for h in 0..0x7c00_u16 {
        let v = f16::from_bits(h).to_f32();
        let next = f16::from_bits(h + 1).to_f32();
        let mid = ((f64::from(v) + f64::from(next)) / 2.0) as f32;
        for x in [v, mid] {
            for d in [-1_i32, 0, 1] {
                let y = f32::from_bits(x.to_bits().wrapping_add_signed(d));
                xs.extend([y, -y]);
            }
        }
    }
    let mut g = Gen(23);
    xs.extend((0..N).map(|_| g.hard()));
    for rounding in [StoreRounding::Nearest, StoreRounding::Stochastic] {
        let s = &all[0];
        let mut params = s.params;
        params.rounding = match rounding {
            StoreRounding::Nearest => 0,
            StoreRounding::Stochastic => 1,
        };
        let input: Vec<u32> = xs.iter().flat_map(|x| [bits(*x), g.u32()]).collect();
        compare(
            gpu,
            &format!("spvg_to_f16 ({rounding:?})"),
            "o(r, spvg_to_f16(f(b), P.rounding, w(b + 1u)));",
            2,
            &[Word::F32],
            &[Batch { params, input }],
            |_, c| {
                let r = match rounding {
                    StoreRounding::Nearest => Rounding::Nearest,
                    StoreRounding::Stochastic => Rounding::Stochastic(c[1]),
                };
                vec![bits(to_f16(f(c[0]), r).to_f32())]
            },
        );
    }
}

#[test]
fn sequence_functions_match_the_core() {
    let Some(gpu) = gpu("sequence_functions_match_the_core") else {
        return;
    };
    let all = setups();
    let b = batches(&all[..4], 31, |_, g| {
        let r = g.u32();
        vec![r, g.u32() >> (r % 32), g.u32() % 4096]
    });
    compare(
        gpu,
        "spvg_pcg3d16, spvg_r2_offset_from_seed, spvg_r2_point, spvg_to_unit_f32",
        "let s = spvg_pcg3d16(vec3<u32>(w(b), w(b + 1u), w(b + 2u)));
    let q = spvg_r2_point(spvg_r2_offset_from_seed(s), w(b + 2u));
    ou(r, s.x); ou(r + 1u, s.y); ou(r + 2u, s.z); ou(r + 3u, q.x); ou(r + 4u, q.y);
    o(r + 5u, spvg_to_unit_f32(q.x));",
        3,
        &[
            Word::U32,
            Word::U32,
            Word::U32,
            Word::U32,
            Word::U32,
            Word::F32,
        ],
        &b,
        |_, c| {
            let s = pcg3d16([c[0], c[1], c[2]]);
            let q = r2_point(r2_offset_from_seed(s), c[2]);
            vec![s[0], s[1], s[2], q[0], q[1], bits(to_unit_f32(q[0]))]
        },
    );
    compare(
        gpu,
        "spvg_channel_bits",
        "ou(r, spvg_channel_bits(w(b), w(b + 1u) % 4u));",
        3,
        &[Word::U32],
        &b,
        |_, c| vec![channel_bits(c[0], c[1] % 4)],
    );
}

/// A motion component: hard values (NaN, infinities, subnormals, huge) a quarter of the
/// time, else a pixel offset within +-3 frame widths on a 2^-8 grid or an arbitrary
/// fraction, so that positions land inside, on and past every edge.
fn gen_motion(g: &mut Gen, size: u32) -> f32 {
    let span = 6.0 * size.max(1) as f32;
    match g.u32() % 4 {
        0 => g.hard(),
        1 => ((g.unit() - 0.5) * span * 256.0).round() / 256.0,
        _ => (g.unit() - 0.5) * span,
    }
}

#[test]
fn reprojection_functions_match_the_core() {
    let Some(gpu) = gpu("reprojection_functions_match_the_core") else {
        return;
    };
    let all = setups();
    let b = batches(&all[..4], 37, |_, g| {
        // Frame sides: empty, one texel, small, up to the 2^16 of the component, and any
        // u32 (where `width - 1` rounds in f32), u32::MAX itself.
        let side = |g: &mut Gen| match g.u32() % 8 {
            0 => 0,
            1 => 1,
            2 => 1 + g.u32() % 16,
            3 => u32::MAX - g.u32() % 4,
            4 | 5 => g.u32(),
            _ => 1 + g.u32() % 65_536,
        };
        let (w, h) = (side(g), side(g));
        let (x, y) = (g.u32() % w.max(1), g.u32() % h.max(1));
        let (vx, vy) = (gen_motion(g, w), gen_motion(g, h));
        let depth = if g.flag() == 0 {
            g.hard()
        } else {
            0.1 + 10.0 * g.unit()
        };
        let previous = if g.flag() == 0 {
            g.hard()
        } else {
            depth * (0.9 + 0.2 * g.unit())
        };
        let tolerance = [0.0, 0.02, 0.05, 1.0, 1e-30, 1e30, f32::MAX][(g.u32() % 7) as usize];
        vec![
            x,
            y,
            vx.to_bits(),
            vy.to_bits(),
            w,
            h,
            previous.to_bits(),
            depth.to_bits(),
            f32::to_bits(tolerance),
        ]
    });
    let texel = |q: Option<[u32; 2]>| q.map_or([0, 0, 0], |q| [q[0], q[1], 1]);
    compare(
        gpu,
        "spvg_reproject_texel, spvg_reproject_border_texel, spvg_reproject_footprint_texel, \
         spvg_reproject_depth_agrees",
        "let p = vec2<u32>(w(b), w(b + 1u));
    let v = vec2<f32>(f(b + 2u), f(b + 3u));
    let size = vec2<u32>(w(b + 4u), w(b + 5u));
    let q = spvg_reproject_texel(p, v, size);
    let e = spvg_reproject_border_texel(p, v, size);
    ou(r, q.x); ou(r + 1u, q.y); ou(r + 2u, q.z);
    ou(r + 3u, e.x); ou(r + 4u, e.y); ou(r + 5u, e.z);
    ob(r + 6u, spvg_reproject_depth_agrees(f(b + 6u), f(b + 7u), f(b + 8u)));
    for (var k = 1u; k <= 3u; k++) {
        let t = spvg_reproject_footprint_texel(p, v, size, k);
        ou(r + 4u + 3u * k, t.x); ou(r + 5u + 3u * k, t.y); ou(r + 6u + 3u * k, t.z);
    }",
        9,
        &[Word::U32; 16],
        &b,
        |_, c| {
            let (p, v, size) = ([c[0], c[1]], [f(c[2]), f(c[3])], [c[4], c[5]]);
            let q = texel(previous_texel(p, v, size));
            let e = texel(border_texel(p, v, size));
            let agrees = Reprojection::new(f(c[8]))
                .expect("valid tolerance")
                .depth_agrees(f(c[6]), f(c[7]));
            let mut out = vec![q[0], q[1], q[2], e[0], e[1], e[2], u32::from(agrees)];
            for k in 1..=3 {
                out.extend(texel(footprint_texel(p, v, size, k)));
            }
            out
        },
    );
}

/// Profiles: (albedo, d) of the presets' range and the extremes of a normal `d`.
fn profiles() -> Vec<BurleyProfile<f32>> {
    [
        (1.0, 1.0),
        (0.44, 0.62),
        (0.83, 2.4),
        (1.0, 1e-3),
        (0.5, 100.0),
        (0.0, 3.7),
    ]
    .iter()
    .map(|&(a, d)| BurleyProfile::from_shape(a, d).expect("valid profile"))
    .collect()
}

/// Relative bound of the Burley functions on lavapipe (see the module docs).
const BURLEY: Word = Word::Approx {
    rel: 2e-5,
    abs: 1e-30,
};

/// The ratio estimator's mean: a weighted mean of lightings of either sign, so the
/// device's weight error enters relative to the lightings, not to the (possibly
/// cancelled) mean: 2e-5 relative plus 1e-6 absolute (lightings of order 1).
const RATIO_MEAN: Word = Word::Approx {
    rel: 2e-5,
    abs: 1e-6,
};

#[test]
fn burley_functions_match_the_core() {
    let Some(gpu) = gpu("burley_functions_match_the_core") else {
        return;
    };
    let params = setups()[0].params;
    let profs = profiles();
    let mut g = Gen(41);
    let batches_of = |g: &mut Gen, case: &dyn Fn(&BurleyProfile<f32>, &mut Gen) -> Vec<u32>| {
        profs
            .iter()
            .map(|p| Batch {
                params,
                input: (0..N)
                    .flat_map(|_| {
                        let mut v = vec![bits(p.albedo()), bits(p.shape()), bits(p.inv_shape())];
                        v.extend(case(p, g));
                        v
                    })
                    .collect(),
            })
            .collect::<Vec<_>>()
    };
    let radius_or_xi = |p: &BurleyProfile<f32>, g: &mut Gen| -> f32 {
        match g.u32() % 4 {
            0 => g.unit(),
            1 => p.shape() * g.unit() * 12.0,
            2 => 1.0 - g.unit() * 1e-3,
            _ => g.hard(),
        }
    };
    let b = batches_of(&mut g, &|p, g| {
        vec![bits(radius_or_xi(p, g)), bits(radius_or_xi(p, g))]
    });
    let prof = "let pr = spvg_BurleyProfile(f(b), f(b + 1u), f(b + 2u)); let x = f(b + 3u); let y = f(b + 4u);";
    let p_of = |bi: usize| profs[bi];
    compare(
        gpu,
        "spvg_burley_pdf, _cdf, _distant_ratio",
        &format!(
            "{prof} o(r, spvg_burley_pdf(pr, x)); o(r + 1u, spvg_burley_cdf(pr, x)); o(r + 2u, spvg_burley_distant_ratio(pr, x));"
        ),
        5,
        &[BURLEY; 3],
        &b,
        |bi, c| {
            let p = p_of(bi);
            let x = f(c[3]);
            vec![bits(p.pdf(x)), bits(p.cdf(x)), bits(p.distant_ratio(x))]
        },
    );
    compare(
        gpu,
        "spvg_burley_inverse_cdf, _approx_inverse_cdf",
        &format!(
            "{prof} o(r, spvg_burley_inverse_cdf(pr, x)); o(r + 1u, spvg_burley_approx_inverse_cdf(pr, x, 2.5715));"
        ),
        5,
        &[BURLEY; 2],
        &b,
        |bi, c| {
            let p = p_of(bi);
            let x = f(c[3]);
            vec![
                bits(p.inverse_cdf(x)),
                bits(p.approx_inverse_cdf(x, 2.5715)),
            ]
        },
    );
    compare_or(
        gpu,
        "spvg_burley_sample_distant",
        &format!(
            "{prof} let s = spvg_burley_sample_distant(pr, x, y); o(r, s.radius); o(r + 1u, s.pdf);"
        ),
        5,
        &[BURLEY; 2],
        &b,
        |bi, c| {
            let p = p_of(bi);
            let s = p.sample_distant(f(c[3]), f(c[4]));
            // A device exp that returns 0 below 2^-126 (lavapipe) makes a subnormal
            // distant ratio 0: then the sample is (r0, 0), as for gamma = 0. Below 2^-100
            // the device's exp has lost relative precision (and the pdf's exp flushes):
            // excluded, as no pixel samples a distant energy fraction under 1e-30.
            let r0 = f(c[4]).max(0.0);
            let gamma = p.distant_ratio(r0);
            let alt = if gamma.is_subnormal() {
                Some(vec![bits(r0), 0])
            } else if gamma > 0.0 && gamma < 2f32.powi(-100) {
                Some(Vec::new())
            } else {
                None
            };
            (vec![bits(s.radius), bits(s.pdf)], alt)
        },
    );

    // Two samples into a fresh ratio estimator: r, dz, pdf, lighting each.
    let b = batches_of(&mut g, &|p, g| {
        (0..2)
            .flat_map(|_| {
                let r = radius_or_xi(p, g);
                let dz = if g.u32() % 2 == 0 {
                    (g.unit() - 0.5) * p.shape()
                } else {
                    g.hard()
                };
                let pdf = if g.u32() % 2 == 0 {
                    p.pdf(r.abs())
                } else {
                    g.hard()
                };
                [bits(r), bits(dz), bits(pdf), bits(gen_luminance(g))]
            })
            .collect()
    });
    compare_or(
        gpu,
        "spvg_burley_ratio_weight, _ratio_add",
        &format!("{prof}
    var e = spvg_RatioEstimator(0.0, 0.0);
    e = spvg_burley_ratio_add(pr, e, f(b + 3u), f(b + 4u), f(b + 5u), f(b + 6u));
    e = spvg_burley_ratio_add(pr, e, f(b + 7u), f(b + 8u), f(b + 9u), f(b + 10u));
    let wr = f(b + 3u); let wdz = f(b + 4u); let wpdf = f(b + 5u);
    let in_domain = spvg_is_finite(wr) && spvg_is_finite(wdz) && spvg_is_finite(wpdf) && wr >= 0.0 && wpdf > 0.0;
    o(r, select(0.0, spvg_burley_ratio_weight(pr, wr, wdz, wpdf), in_domain));
    o(r + 1u, e.sum_weights); o(r + 2u, e.mean);"),
        11,
        &[BURLEY, BURLEY, RATIO_MEAN],
        &b,
        |bi, c| {
            let p = p_of(bi);
            let mut e = RatioEstimator::new(&p);
            let _ = e.add(f(c[3]), f(c[4]), true, f(c[5]), f(c[6]));
            let _ = e.add(f(c[7]), f(c[8]), true, f(c[9]), f(c[10]));
            // The weight on the domain `add` passes it (finite, r >= 0, pdf > 0).
            let (r, dz, pdf) = (f(c[3]), f(c[4]), f(c[5]));
            let in_domain = r.is_finite() && dz.is_finite() && pdf.is_finite() && r >= 0.0 && pdf > 0.0;
            let w = if in_domain { e.weight(r, dz, true, pdf) } else { 0.0 };
            // A kernel exp(-x/3) below 2^-80 (x > 166: 1e-24 of the profile's peak)
            // comes out 0 or imprecise from a device exp near the bottom of the range
            // (lavapipe flushes below 2^-126), where the core divides two tiny numbers:
            // excluded.
            let far = [(c[3], c[4]), (c[7], c[8])]
                .iter()
                .any(|&(r, dz)| f(r).hypot(f(dz)) * p.inv_shape() > 166.0);
            (
                vec![bits(w), bits(e.sum_weights()), bits(e.mean_lighting().unwrap_or(0.0))],
                far.then(Vec::new),
            )
        },
    );

    // footprint_radius with hypot(w, h) from the host: exact.
    let b = batches_of(&mut g, &|_, g| {
        let (w, h) = (g.unit() * 1e-2, g.unit() * 1e-2);
        vec![bits(g.hard()), bits(w), bits(h), bits(w.hypot(h))]
    });
    // Exact, except that a subnormal radius (below 2^-126, from a subnormal depth) may be
    // one unit (2^-149) off: lavapipe's multiplications into the subnormal range are not
    // always the IEEE products.
    compare(
        gpu,
        "spvg_footprint_radius",
        "o(r, spvg_footprint_radius(f(b + 3u), f(b + 6u)));",
        7,
        &[Word::Approx {
            rel: 0.0,
            abs: 1.5e-45,
        }],
        &b,
        |_, c| vec![bits(footprint_radius(f(c[3]), f(c[4]), f(c[5])))],
    );

    // AFIS: the level (device log2) and the exact index.
    let b = batches_of(&mut g, &|_, g| {
        let pdf = if g.u32() % 4 == 0 {
            g.hard()
        } else {
            g.unit() * 2.0
        };
        let n = 1 + g.u32() % 64;
        let lmax = 1.0 + g.unit() * 10.0;
        let area = if g.u32() % 4 == 0 {
            g.hard()
        } else {
            g.unit() * 1e-3
        };
        vec![bits(pdf), n, bits(lmax), bits(area)]
    });
    compare_or(
        gpu,
        "spvg_filtered_mip_level",
        "o(r, spvg_filtered_mip_level(f(b + 3u), w(b + 4u), f(b + 5u), f(b + 6u)));",
        7,
        &[BURLEY],
        &b,
        |_, c| {
            let (pdf, n, lmax, area) = (f(c[3]), c[4], f(c[5]), f(c[6]));
            // A subnormal q (level above 63, far past any mip chain): the device's log2
            // does not read subnormals (lavapipe), excluded.
            let q = pdf * n as f32 / (16.0 * lmax * lmax * area);
            (
                vec![bits(filtered_mip_level(pdf, n, lmax, area))],
                q.is_subnormal().then(Vec::new),
            )
        },
    );
    let max_mip = 12_u32;
    let near_power_of_4 = std::cell::Cell::new(0_usize);
    compare(
        gpu,
        "spvg_filtered_mip_index",
        &format!(
            "ou(r, spvg_filtered_mip_index(f(b + 3u), w(b + 4u), f(b + 5u), f(b + 6u), {max_mip}u));"
        ),
        7,
        &[Word::U32],
        &b,
        |_, c| {
            let (pdf, n, lmax, area) = (f(c[3]), c[4], f(c[5]), f(c[6]));
            let level = filtered_mip_level(pdf, n, lmax, area);
            let want = if level.is_nan() {
                0
            } else {
                (level.floor().min(max_mip as f32)) as u32
            };
            // Where q lies a few ulps above a power of 4 the core's log2 rounds to the
            // integer; the exact comparison is then one level finer.
            let q = pdf * n as f32 / (16.0 * lmax * lmax * area);
            if q > 0.0 && q.is_finite() && want > 0 && want < max_mip {
                let p4 = f32::from_bits((127 - 2 * want) << 23);
                if q > p4 && q.to_bits() - p4.to_bits() <= 8 {
                    near_power_of_4.set(near_power_of_4.get() + 1);
                    return vec![want - 1];
                }
            }
            vec![want]
        },
    );
    eprintln!(
        "spvg_filtered_mip_index: {} cases a few ulps above a power of 4",
        near_power_of_4.get()
    );
}

/// A texel as `spvg_decode_history` reads it, decoded by the core for the setup's layout.
fn decode_texel(s: &Setup, t: &[u32]) -> SpvgHistory<f32> {
    match s.layout {
        Layout::F16 => SpvgTexel16([0, 1, 2, 3].map(|k| f16::from_f32(f(t[k])))).decode(&s.enc),
        Layout::F32 => SpvgTexel32([0, 1, 2, 3].map(|k| f(t[k]))).decode(&s.enc),
    }
}

/// The core's encoding of `h` as texel words, with the written mark (spare channel 1).
fn encode_written(s: &Setup, h: &SpvgHistory<f32>, random: u32) -> Vec<u32> {
    let rounding = rounding_of(s, random);
    let mut t = match s.layout {
        Layout::F16 => SpvgTexel16::encode(&s.enc, h, rounding)
            .0
            .map(|x| bits(x.to_f32())),
        Layout::F32 => SpvgTexel32::encode(&s.enc, h, rounding).0.map(bits),
    };
    t[3] = bits(1.0);
    t.to_vec()
}

/// The texel forms of the estimate and the update (the written mark in the spare channel)
/// against the core's decode, `estimate_with_validity`, `update` and encode, with the
/// mark's rule written out here: valid where the spare channel is >= 0.5; a refused frame
/// keeps a valid texel and clears an invalid one; an accepted one is encoded with spare 1.
#[test]
fn history_texel_functions_match_the_core() {
    let Some(gpu) = gpu("history_texel_functions_match_the_core") else {
        return;
    };
    let all = setups();
    let b = batches(&all, 41, |s, g| {
        let mut v: Vec<u32> = (0..3).map(|_| stored(s, g)).collect();
        // The spare channel: unwritten, written, the threshold and next to it, anything.
        v.push(match g.u32() % 6 {
            0 => 0,
            1 => bits(1.0),
            2 => bits(0.5),
            3 => bits(0.499_999_97),
            _ => stored(s, g),
        });
        let [h0, h1, h2] = gen_history(s, g);
        if g.flag() == 0 {
            // A realistic history, as the layout's texture returns it.
            (v[0], v[1], v[2]) = (h0, h1, h2);
            if s.layout == Layout::F16 {
                for x in &mut v[..3] {
                    *x = bits(f16::from_f32(f(*x)).to_f32());
                }
            }
        }
        v.push(bits(if g.flag() == 0 { g.ratio() } else { g.hard() }));
        v.push(bits(if g.flag() == 0 { g.unit() } else { g.hard() }));
        v.push(g.count(&s.config));
        v.push(g.u32());
        v
    });
    compare(
        gpu,
        "spvg_history_written, spvg_estimate_texel, spvg_update_history_texel, \
         spvg_encode_written_history",
        "let t = vec4<f32>(f(b), f(b + 1u), f(b + 2u), f(b + 3u));
    ob(r, spvg_history_written(t));
    ou(r + 1u, spvg_estimate_texel(P, t, f(b + 4u)));
    let u = spvg_update_history_texel(P, t, f(b + 5u), w(b + 6u), w(b + 7u));
    o(r + 2u, u.x); o(r + 3u, u.y); o(r + 4u, u.z); o(r + 5u, u.w);
    let e = spvg_encode_written_history(P, spvg_History(f(b), f(b + 1u), f(b + 2u)), w(b + 7u));
    o(r + 6u, e.x); o(r + 7u, e.y); o(r + 8u, e.z); o(r + 9u, e.w);",
        8,
        &[
            Word::U32,
            Word::U32,
            Word::F32,
            Word::F32,
            Word::F32,
            Word::F32,
            Word::F32,
            Word::F32,
            Word::F32,
            Word::F32,
        ],
        &b,
        |bi, c| {
            let s = &all[bi];
            let valid = f(c[3]) >= 0.5;
            let decoded = decode_texel(s, c);
            let count = s.config.estimate_with_validity(&decoded, f(c[4]), valid);
            let mut h = if valid {
                decoded
            } else {
                SpvgHistory::default()
            };
            let updated = if s.config.update(&mut h, f(c[5]), c[6], valid) {
                encode_written(s, &h, c[7])
            } else if valid {
                c[..4].to_vec()
            } else {
                vec![0; 4]
            };
            let mut out = vec![u32::from(valid), count];
            out.extend(updated);
            out.extend(encode_written(s, &history(c), c[7]));
            out
        },
    );
    // The guided texel update on the same cases, the guide the (finite) word 4 reused
    // half the time and a value near the sample the other half.
    let b: Vec<Batch> = b
        .into_iter()
        .map(|mut batch| {
            for (k, c) in batch.input.chunks_mut(8).enumerate() {
                if k % 2 == 1 {
                    c[4] = bits(f(c[5]) + 0.01 * (k % 7) as f32);
                }
            }
            batch
        })
        .collect();
    compare(
        gpu,
        "spvg_update_history_texel_guided",
        "let t = vec4<f32>(f(b), f(b + 1u), f(b + 2u), f(b + 3u));
    let u = spvg_update_history_texel_guided(P, t, f(b + 5u), f(b + 4u), w(b + 6u), w(b + 7u));
    o(r, u.x); o(r + 1u, u.y); o(r + 2u, u.z); o(r + 3u, u.w);",
        8,
        &f32_words(4),
        &b,
        |bi, c| {
            let s = &all[bi];
            let valid = f(c[3]) >= 0.5;
            let mut h = if valid {
                decode_texel(s, c)
            } else {
                SpvgHistory::default()
            };
            if s.config
                .update_guided(&mut h, f(c[5]), f(c[4]), c[6], valid)
            {
                encode_written(s, &h, c[7])
            } else if valid {
                c[..4].to_vec()
            } else {
                vec![0; 4]
            }
        },
    );
}

/// The synthetic previous frame of the locate and dilation cases: a hash of the case's
/// seed and the texel (the same integer arithmetic in the kernels below).
fn texel_hash(seed: u32, q: [u32; 2]) -> u32 {
    let h = seed ^ q[0].wrapping_mul(0x9e37_79b1) ^ q[1].wrapping_mul(0x85eb_ca77);
    let h = (h ^ (h >> 15)).wrapping_mul(0x2c1b_3c6d);
    h ^ (h >> 12)
}

/// `texel_hash` in WGSL, on `seed` and the texel `q`, into `hh`.
const TEXEL_HASH: &str = "var hh = seed ^ (q.x * 0x9e3779b1u) ^ (q.y * 0x85ebca77u);
        hh = (hh ^ (hh >> 15u)) * 0x2c1b3c6du;
        hh = hh ^ (hh >> 12u);";

/// The core's rule with depth tolerance `tolerance` and the switches of `switches`: bit 0
/// the border prior, bit 1 the footprint search, bit 2 `BorderCount::Maximum`.
fn rule_of(switches: u32, tolerance: f32) -> Reprojection<f32> {
    Reprojection::new(tolerance)
        .expect("valid tolerance")
        .with_border_prior(switches & 1 != 0)
        .with_footprint_search(switches & 2 != 0)
        .with_border_count(if switches & 4 != 0 {
            BorderCount::Maximum
        } else {
            BorderCount::Texel
        })
}

/// The whole reprojection decision, `spvg_reproject_locate_start` then
/// `spvg_reproject_locate` until decided, against `Reprojection::locate` (with the
/// border prior, the footprint search and the border count switched per case) followed
/// by the written check: on hard motion (NaN, infinities, subnormals, huge), positions
/// inside, on and past every frame edge, resized frames, empty and one-texel frames, hard
/// and near-tolerance depths, and a previous frame whose mask, depth and written mark
/// vary texel by texel. Also compared: how many texels the search read (the core's
/// callback calls; a read outside the previous frame would add 100) and
/// `spvg_reproject_entering_count`. The shader's rule is `ReprojectionRule::new` of the
/// core's, so the case also holds the crate's flags helper to the core's switches.
#[test]
fn locate_matches_the_core() {
    let Some(gpu) = gpu("locate_matches_the_core") else {
        return;
    };
    let all = setups();
    let b = batches(&all[..4], 43, |_, g| {
        let side = |g: &mut Gen| match g.u32() % 6 {
            0 => 0,
            1 => 1,
            2 | 3 => 1 + g.u32() % 16,
            _ => 1 + g.u32() % 65_536,
        };
        let (w, h) = (side(g), side(g));
        let (pw, ph) = match g.u32() % 8 {
            0 => (w + 1, h),
            1 => (w, h.saturating_sub(1)),
            _ => (w, h),
        };
        let (x, y) = (g.u32() % w.max(1), g.u32() % h.max(1));
        let (vx, vy) = match g.u32() % 4 {
            // Sub-pixel motion: the footprint search's case.
            0 => ((g.unit() - 0.5) * 3.0, (g.unit() - 0.5) * 3.0),
            _ => (gen_motion(g, w), gen_motion(g, h)),
        };
        let depth = if g.u32() % 8 == 0 {
            g.hard()
        } else {
            0.1 + 10.0 * g.unit()
        };
        let tolerance = [0.0_f32, 0.02, 0.05, 1.0, 1e-30][(g.u32() % 5) as usize];
        let near = |g: &mut Gen| depth * (1.0 + tolerance * (2.0 * g.unit() - 1.0) * 1.02);
        let depths = [depth, near(g), g.hard(), depth * 0.5];
        let mut v = vec![g.u32(), x, y, bits(vx), bits(vy), w, h, pw, ph];
        v.extend([bits(depth), g.u32() % 8, bits(tolerance)]);
        v.extend(depths.map(bits));
        v.extend([g.u32() >> (g.u32() % 32), g.u32() % 2048]);
        // The rule the shader runs, built by the crate's helper from the core's rule.
        let rule = ReprojectionRule::new(&rule_of(v[10], f(v[11])));
        v.extend([bits(rule.depth_tolerance), rule.flags]);
        v
    });
    let body = format!(
        "let seed = w(b);
    let pixel = vec2<u32>(w(b + 1u), w(b + 2u));
    let v = vec2<f32>(f(b + 3u), f(b + 4u));
    let size = vec2<u32>(w(b + 5u), w(b + 6u));
    let psize = vec2<u32>(w(b + 7u), w(b + 8u));
    let depth = f(b + 9u);
    let rule = spvg_Reprojection(f(b + 18u), w(b + 19u));
    var l = spvg_reproject_locate_start(rule, pixel, v, size, psize);
    var reads = 0u;
    while (l.source == spvg_SOURCE_PENDING && reads < 8u) {{
        let q = l.texel;
        {TEXEL_HASH}
        if (q.x >= psize.x || q.y >= psize.y) {{ reads += 100u; }}
        let s = spvg_PreviousTexel((hh & 7u) != 0u, f(b + 12u + ((hh >> 6u) & 3u)), ((hh >> 3u) & 7u) != 0u);
        l = spvg_reproject_locate(rule, pixel, v, psize, depth, l, s);
        reads += 1u;
    }}
    ou(r, l.source); ou(r + 1u, l.texel.x); ou(r + 2u, l.texel.y); ou(r + 3u, reads);
    ou(r + 4u, spvg_reproject_entering_count(rule, w(b + 16u), w(b + 17u)));"
    );
    // How often each path of the rule was taken: continued at the nearest texel, at a
    // footprint texel, the border prior, located but not written, no texel passing.
    let paths = [0, 1, 2, 3, 4].map(|_| core::cell::Cell::new(0_usize));
    let outcome = compare(
        gpu,
        "spvg_reproject_locate",
        &body,
        20,
        &[Word::U32; 5],
        &b,
        |_, c| {
            let (seed, pixel, v) = (c[0], [c[1], c[2]], [f(c[3]), f(c[4])]);
            let (size, previous_size, depth, switches) =
                ([c[5], c[6]], [c[7], c[8]], f(c[9]), c[10]);
            let rule = rule_of(switches, f(c[11]));
            let reads = core::cell::Cell::new(0);
            let previous = |q: [u32; 2]| {
                reads.set(reads.get() + 1);
                let h = texel_hash(seed, q);
                PreviousSample {
                    mask: h & 7 != 0,
                    depth: f(c[12 + ((h >> 6) & 3) as usize]),
                }
            };
            let written = |q: [u32; 2]| (texel_hash(seed, q) >> 3) & 7 != 0;
            let located = rule.locate(pixel, v, depth, size, previous_size, previous);
            let (source, q) = match located {
                HistorySource::History(q) if written(q) => (1, q),
                HistorySource::BorderPrior(q) if written(q) => (2, q),
                _ => (0, [0, 0]),
            };
            let path = match (located, source) {
                (HistorySource::History(q), 1) if Some(q) == previous_texel(pixel, v, size) => 0,
                (HistorySource::History(_), 1) => 1,
                (_, 2) => 2,
                (HistorySource::Disoccluded, _) => 4,
                _ => 3,
            };
            paths[path].set(paths[path].get() + 1);
            vec![
                source,
                q[0],
                q[1],
                reads.get(),
                rule.entering_count(c[16], c[17]),
            ]
        },
    );
    assert_eq!(
        outcome.identical, outcome.cases,
        "bit-identical, no exception"
    );
    let paths = paths.map(core::cell::Cell::into_inner);
    eprintln!(
        "spvg_reproject_locate paths: {} nearest texel, {} footprint texel, {} border prior, \
         {} not written, {} disoccluded",
        paths[0], paths[1], paths[2], paths[3], paths[4]
    );
    assert!(
        paths.iter().all(|&n| n >= 50),
        "every path taken often: {paths:?}"
    );
}

/// Count dilation, `spvg_dilation_window` folded with `spvg_dilation_take` over the
/// window, against `spvg::dilation::dilated_count` on a frame of counts with zeros and
/// `KEEP` marks: own counts 0, marked, budget edges and any word; radii 0 to 8 and up to
/// `u32::MAX` on small frames; pixels on every edge and outside the frame; one-row frames
/// up to 70,000 wide. Also compared: the window's size (the reads).
#[test]
fn dilation_matches_the_core() {
    let Some(gpu) = gpu("dilation_matches_the_core") else {
        return;
    };
    let all = setups();
    let b = batches(&all[..4], 47, |_, g| {
        let (w, h, radius) = if g.u32() % 8 == 0 {
            (1 + g.u32() % 70_000, 1, g.u32() % 9)
        } else {
            let r = match g.u32() % 4 {
                0 => g.u32() >> (g.u32() % 32),
                _ => g.u32() % 9,
            };
            (g.u32() % 25, g.u32() % 25, r)
        };
        let edge = |g: &mut Gen, n: u32| match g.u32() % 4 {
            0 => 0,
            1 => n.saturating_sub(1),
            2 => n + g.u32() % 3,
            _ => g.u32() % n.max(1),
        };
        let (x, y) = (edge(g, w), edge(g, h));
        let own = match g.u32() % 8 {
            0 => 0,
            1 => KEEP,
            2 => KEEP | (g.u32() % 1025),
            3 => 1,
            4 => u32::MAX,
            _ => g.u32() % 1025,
        };
        vec![g.u32(), x, y, w, h, radius, own]
    });
    let body = format!(
        "let seed = w(b);
    let pixel = vec2<u32>(w(b + 1u), w(b + 2u));
    let size = vec2<u32>(w(b + 3u), w(b + 4u));
    var d = spvg_dilation_window(w(b + 6u), pixel, size, w(b + 5u));
    var reads = 0u;
    for (var y = d.lo.y; y <= d.hi.y; y++) {{
        for (var x = d.lo.x; x <= d.hi.x; x++) {{
            let q = vec2<u32>(x, y);
            {TEXEL_HASH}
            var c = (hh >> 8u) % 1025u;
            if ((hh & 7u) == 0u) {{ c = 0u; }}
            if ((hh & 7u) == 1u) {{ c = c | spvg_DILATION_KEEP; }}
            if (all(q == pixel)) {{ c = w(b + 6u); }}
            d.count = spvg_dilation_take(d.count, c);
            reads += 1u;
        }}
    }}
    ou(r, d.count); ou(r + 1u, reads);"
    );
    // Cases where the window raised the pixel's own count, and where the pixel kept it
    // (0 or marked KEEP).
    let (raised, kept) = (core::cell::Cell::new(0), core::cell::Cell::new(0));
    let outcome = compare(
        gpu,
        "spvg_dilation_window, spvg_dilation_take",
        &body,
        7,
        &[Word::U32; 2],
        &b,
        |_, c| {
            let (seed, pixel, size, radius, own) = (c[0], [c[1], c[2]], [c[3], c[4]], c[5], c[6]);
            let counts: Vec<u32> = (0..size[1])
                .flat_map(|y| (0..size[0]).map(move |x| [x, y]))
                .map(|q| {
                    let h = texel_hash(seed, q);
                    match h & 7 {
                        _ if q == pixel => own,
                        0 => 0,
                        1 => KEEP | ((h >> 8) % 1025),
                        _ => (h >> 8) % 1025,
                    }
                })
                .collect();
            // The window's size, written out independently of both.
            let inside = pixel[0] < size[0] && pixel[1] < size[1];
            let span = |p: u32, n: u32| {
                let lo = u64::from(p).saturating_sub(u64::from(radius));
                let hi = (u64::from(p) + u64::from(radius)).min(u64::from(n) - 1);
                hi - lo + 1
            };
            let reads = if inside && own != 0 && own & KEEP == 0 {
                (span(pixel[0], size[0]) * span(pixel[1], size[1])) as u32
            } else {
                0
            };
            let dilated = dilated_count(&counts, size, pixel, radius);
            if inside && dilated > own {
                raised.set(raised.get() + 1);
            }
            if inside && (own == 0 || own & KEEP != 0) {
                kept.set(kept.get() + 1);
            }
            vec![dilated, reads]
        },
    );
    assert_eq!(
        outcome.identical, outcome.cases,
        "bit-identical, no exception"
    );
    eprintln!(
        "spvg_dilation_window: {} raised by a neighbour, {} kept (0 or KEEP)",
        raised.get(),
        kept.get()
    );
    assert!(
        raised.get() >= 500 && kept.get() >= 500,
        "both paths taken often"
    );
}

/// The depth-aware neighbour prior, `spvg_dilation_prior_window` folded with
/// `spvg_dilation_prior_take` and finished by `spvg_dilation_prior_count`, against `spvg::dilation::dilated_count_with_prior` on the
/// frames of `dilation_matches_the_core`, with a same-surface flag per texel from the
/// hash (the same integer arithmetic on both sides).
#[test]
fn dilation_prior_matches_the_core() {
    let Some(gpu) = gpu("dilation_prior_matches_the_core") else {
        return;
    };
    let all = setups();
    let b = batches(&all[..4], 48, |_, g| {
        let (w, h) = if g.u32() % 8 == 0 {
            (1 + g.u32() % 3000, 1)
        } else {
            (g.u32() % 25, g.u32() % 25)
        };
        let radius = g.u32() % 9;
        let edge = |g: &mut Gen, n: u32| match g.u32() % 4 {
            0 => 0,
            1 => n.saturating_sub(1),
            2 => n + g.u32() % 3,
            _ => g.u32() % n.max(1),
        };
        let (x, y) = (edge(g, w), edge(g, h));
        let own = match g.u32() % 6 {
            0 => 0,
            1 => KEEP,
            2 | 3 => KEEP | (g.u32() % 1025),
            _ => g.u32() % 1025,
        };
        vec![g.u32(), x, y, w, h, radius, own]
    });
    let body = format!(
        "let seed = w(b);
    let pixel = vec2<u32>(w(b + 1u), w(b + 2u));
    let size = vec2<u32>(w(b + 3u), w(b + 4u));
    let own = w(b + 6u);
    var d = spvg_dilation_prior_window(own, pixel, size, w(b + 5u));
    for (var y = d.lo.y; y <= d.hi.y; y++) {{
        for (var x = d.lo.x; x <= d.hi.x; x++) {{
            let q = vec2<u32>(x, y);
            {TEXEL_HASH}
            var c = (hh >> 8u) % 1025u;
            if ((hh & 7u) == 0u) {{ c = 0u; }}
            if ((hh & 7u) == 1u) {{ c = c | spvg_DILATION_KEEP; }}
            if (all(q == pixel)) {{ c = own; }}
            d = spvg_dilation_prior_take(d, own, c, ((hh >> 4u) & 1u) == 0u);
        }}
    }}
    ou(r, spvg_dilation_prior_count(d, own));"
    );
    let raised = core::cell::Cell::new(0);
    let outcome = compare(
        gpu,
        "spvg_dilation_prior_window, spvg_dilation_prior_take, spvg_dilation_prior_count",
        &body,
        7,
        &[Word::U32],
        &b,
        |_, c| {
            let (seed, pixel, size, radius, own) = (c[0], [c[1], c[2]], [c[3], c[4]], c[5], c[6]);
            let counts: Vec<u32> = (0..size[1])
                .flat_map(|y| (0..size[0]).map(move |x| [x, y]))
                .map(|q| {
                    let h = texel_hash(seed, q);
                    match h & 7 {
                        _ if q == pixel => own,
                        0 => 0,
                        1 => KEEP | ((h >> 8) % 1025),
                        _ => (h >> 8) % 1025,
                    }
                })
                .collect();
            let same = |q: [u32; 2]| (texel_hash(seed, q) >> 4) & 1 == 0;
            let prior = dilated_count_with_prior(&counts, size, pixel, radius, same);
            if own & KEEP != 0 && prior > own & !KEEP {
                raised.set(raised.get() + 1);
            }
            vec![prior]
        },
    );
    assert_eq!(outcome.identical, outcome.cases, "bit-identical");
    eprintln!(
        "spvg_dilation_prior: {} pixels without history raised",
        raised.get()
    );
    assert!(raised.get() >= 500, "the prior acts often");
}

/// The one-pass tile's regions, `spvg_tile_region` and `spvg_spatial_window`, against
/// `spvg::dilation::tile_region` and `spvg::controller::young::spatial_window`: pixels on
/// tile edges and frame edges, frames of 1 to 40 texels and near `u32::MAX`, halos 0 to
/// 8 and any word (the saturating ends).
#[test]
fn tile_regions_match_the_core() {
    let Some(gpu) = gpu("tile_regions_match_the_core") else {
        return;
    };
    let all = setups();
    let b = batches(&all[..2], 53, |_, g| {
        let side = |g: &mut Gen| match g.u32() % 6 {
            0 => u32::MAX - g.u32() % 20,
            _ => 1 + g.u32() % 40,
        };
        let (w, h) = (side(g), side(g));
        let at = |g: &mut Gen, n: u32| match g.u32() % 5 {
            0 => n - 1,
            1 => (g.u32() % n) / 8 * 8,
            2 => ((g.u32() % n) / 8 * 8 + 7).min(n - 1),
            _ => g.u32() % n,
        };
        let (x, y) = (at(g, w), at(g, h));
        let halo = match g.u32() % 4 {
            0 => g.u32(),
            _ => g.u32() % 9,
        };
        vec![x, y, w, h, halo]
    });
    let body = "let pixel = vec2<u32>(w(b), w(b + 1u));
    let size = vec2<u32>(w(b + 2u), w(b + 3u));
    let t = spvg_tile_region(pixel, size, w(b + 4u));
    let s = spvg_spatial_window(pixel, size);
    ou(r, t.lo.x); ou(r + 1u, t.lo.y); ou(r + 2u, t.hi.x); ou(r + 3u, t.hi.y);
    ou(r + 4u, s.lo.x); ou(r + 5u, s.lo.y); ou(r + 6u, s.hi.x); ou(r + 7u, s.hi.y);";
    let outcome = compare(
        gpu,
        "spvg_tile_region, spvg_spatial_window",
        body,
        5,
        &[Word::U32; 8],
        &b,
        |_, c| {
            let (pixel, size, halo) = ([c[0], c[1]], [c[2], c[3]], c[4]);
            let [lo, hi] = tile_region(pixel, size, halo);
            let [slo, shi] = spatial_window(pixel, size);
            vec![lo[0], lo[1], hi[0], hi[1], slo[0], slo[1], shi[0], shi[1]]
        },
    );
    assert_eq!(outcome.identical, outcome.cases, "bit-identical");
}

/// An age as the spare channel may hold it: written ages, the thresholds, anything.
fn gen_age_word(s: &Setup, g: &mut Gen) -> u32 {
    match g.u32() % 8 {
        0 => 0,
        1 => bits(1.0),
        2 => bits(0.5),
        3 => bits(0.499_999_97),
        4 => bits(255.0),
        5 => bits((g.u32() % 8) as f32),
        6 => bits(g.unit() * 300.0),
        _ => stored(s, g),
    }
}

/// Nine neighbour values around a sample: near it (same surface, noise), far, or hard.
fn gen_neighbours(g: &mut Gen, centre: f32) -> Vec<u32> {
    (0..9)
        .map(|_| {
            bits(match g.u32() % 4 {
                0 | 1 => centre + (g.unit() - 0.5) * 0.1,
                2 => g.unit(),
                _ => g.hard(),
            })
        })
        .collect()
}

/// The young-history rules (`spvg::controller::young`, `rules::update_young`) and their
/// texel form against the core: the age read and its advance, the age-aware weight, the
/// spatial moments and variance, and the whole update under every setup (age weight on
/// and off, spatial limits 0 to 255); the texel form with the age written out here
/// (spare channel = the new age, refused frames keep a valid texel and clear an invalid
/// one).
#[test]
fn young_history_functions_match_the_core() {
    let Some(gpu) = gpu("young_history_functions_match_the_core") else {
        return;
    };
    let all = setups();
    let b = batches(&all, 51, |s, g| {
        vec![gen_age_word(s, g), g.u32() % 300, g.flag(), g.flag()]
    });
    compare(
        gpu,
        "spvg_read_age, spvg_next_age, spvg_age_weight",
        "ou(r, spvg_read_age(f(b)));
    ou(r + 1u, spvg_next_age(w(b + 1u), w(b + 2u) != 0u, w(b + 3u) != 0u));
    let a = spvg_age_weight(P, w(b + 1u));
    o(r + 2u, a.x); o(r + 3u, a.y); o(r + 4u, a.z);",
        4,
        &[Word::U32, Word::U32, Word::F32, Word::F32, Word::F32],
        &b,
        |bi, c| {
            let w = age_weight(&all[bi].config.weight(), c[1]);
            vec![
                read_age(f(c[0])),
                next_age(c[1], c[2] != 0, c[3] != 0),
                bits(w.eta()),
                bits(w.retain()),
                bits(w.eta_retain()),
            ]
        },
    );
    let moments = |c: &[u32]| {
        c[1..10]
            .iter()
            .fold(SpatialMoments::default(), |m, &v| m.push(f(c[0]), f(v)))
    };
    let b = batches(&all, 52, |_, g| {
        let centre = if g.flag() == 0 { g.unit() } else { g.hard() };
        let mut v = vec![bits(centre)];
        v.extend(gen_neighbours(g, centre));
        v
    });
    compare(
        gpu,
        "spvg_spatial_push, spvg_spatial_variance",
        "var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    for (var k = 1u; k < 10u; k++) { m = spvg_spatial_push(m, f(b), f(b + k)); }
    ou(r, m.count); o(r + 1u, m.sum); o(r + 2u, m.sum_sq);
    var v = -1.0;
    if (m.count >= 2u) { v = spvg_spatial_variance(m); }
    o(r + 3u, v);",
        10,
        &[Word::U32, Word::F32, Word::F32, Word::F32],
        &b,
        |_, c| {
            let m = moments(c);
            vec![
                m.count,
                bits(m.sum),
                bits(m.sum_sq),
                bits(m.variance().unwrap_or(-1.0)),
            ]
        },
    );
    // A TAA guide for the guided forms (the history's mean, near the sample, hard or
    // random: as for spvg_update_history_guided).
    let guide = |g: &mut Gen, x: f32, mean: f32| match g.u32() % 4 {
        0 => mean,
        1 => x + (g.unit() - 0.5) * 0.1,
        2 => g.hard(),
        _ => g.unit(),
    };
    // The whole update: history (3), sample, count, valid, age, nine neighbours, and the
    // guide that the guided form reads (word 16).
    let b = batches(&all, 53, |s, g| {
        let mut v = gen_history(s, g).to_vec();
        let x = gen_sample(s, g, &v);
        v.push(bits(x));
        v.push(g.count(&s.config));
        v.push(g.flag());
        v.push(if g.flag() == 0 {
            g.u32() % 6
        } else {
            g.u32() % 300
        });
        v.extend(gen_neighbours(g, x));
        let c = guide(g, x, f(v[0]));
        v.push(bits(c));
        v
    });
    // Cases whose history the young-history rules change (against the published update).
    let changed = core::cell::Cell::new(0);
    compare(
        gpu,
        "spvg_update_young",
        "var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    for (var k = 7u; k < 16u; k++) { m = spvg_spatial_push(m, f(b + 3u), f(b + k)); }
    let u = spvg_update_young(P, spvg_History(f(b), f(b + 1u), f(b + 2u)), f(b + 3u), w(b + 4u), w(b + 5u) != 0u, w(b + 6u), m);
    o(r, u.history.mean); o(r + 1u, u.history.variance); o(r + 2u, u.history.mean_count);
    ou(r + 3u, u.age); ob(r + 4u, u.accepted);",
        17,
        &[Word::F32, Word::F32, Word::F32, Word::U32, Word::U32],
        &b,
        |bi, c| {
            let cfg = &all[bi].config;
            let m = c[7..16]
                .iter()
                .fold(SpatialMoments::default(), |m, &v| m.push(f(c[3]), f(v)));
            // The library reads the stored history as `SpvgConfig::update` does.
            let (mut h, mut age) = (history(c), c[6]);
            let ok = cfg.update_young(&mut h, &mut age, f(c[3]), c[4], c[5] != 0, m.variance());
            let mut plain = history(c);
            cfg.update(&mut plain, f(c[3]), c[4], c[5] != 0);
            if plain != h {
                changed.set(changed.get() + 1);
            }
            vec![
                bits(h.mean),
                bits(h.variance),
                bits(h.mean_count),
                age,
                u32::from(ok),
            ]
        },
    );
    // The guided form on the same cases.
    compare(
        gpu,
        "spvg_update_young_guided",
        "var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    for (var k = 7u; k < 16u; k++) { m = spvg_spatial_push(m, f(b + 3u), f(b + k)); }
    let u = spvg_update_young_guided(P, spvg_History(f(b), f(b + 1u), f(b + 2u)), f(b + 3u), f(b + 16u), w(b + 4u), w(b + 5u) != 0u, w(b + 6u), m);
    o(r, u.history.mean); o(r + 1u, u.history.variance); o(r + 2u, u.history.mean_count);
    ou(r + 3u, u.age); ob(r + 4u, u.accepted);",
        17,
        &[Word::F32, Word::F32, Word::F32, Word::U32, Word::U32],
        &b,
        |bi, c| {
            let cfg = &all[bi].config;
            let m = c[7..16]
                .iter()
                .fold(SpatialMoments::default(), |m, &v| m.push(f(c[3]), f(v)));
            let (mut h, mut age) = (history(c), c[6]);
            let ok = cfg.update_young_guided(
                &mut h,
                &mut age,
                f(c[3]),
                f(c[16]),
                c[4],
                c[5] != 0,
                m.variance(),
            );
            vec![
                bits(h.mean),
                bits(h.variance),
                bits(h.mean_count),
                age,
                u32::from(ok),
            ]
        },
    );
    eprintln!(
        "spvg_update_young: the rules change {} cases",
        changed.get()
    );
    assert!(
        changed.get() > 2000,
        "only {} cases reach the rules",
        changed.get()
    );
    // The texel form: texel (4), sample, count, random, nine neighbours.
    let b = batches(&all, 54, |s, g| {
        let mut v: Vec<u32> = (0..3).map(|_| stored(s, g)).collect();
        v.push(gen_age_word(s, g));
        let [h0, h1, h2] = gen_history(s, g);
        if g.flag() == 0 {
            (v[0], v[1], v[2]) = (h0, h1, h2);
            if s.layout == Layout::F16 {
                for x in &mut v[..3] {
                    *x = bits(f16::from_f32(f(*x)).to_f32());
                }
            }
        }
        let x = if g.flag() == 0 { g.unit() } else { g.hard() };
        v.push(bits(x));
        v.push(g.count(&s.config));
        v.push(g.u32());
        v.extend(gen_neighbours(g, x));
        let c = guide(g, x, f(v[0]));
        v.push(bits(c));
        v
    });
    compare(
        gpu,
        "spvg_update_young_texel",
        "var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    for (var k = 7u; k < 16u; k++) { m = spvg_spatial_push(m, f(b + 4u), f(b + k)); }
    let t = vec4<f32>(f(b), f(b + 1u), f(b + 2u), f(b + 3u));
    let u = spvg_update_young_texel(P, t, f(b + 4u), w(b + 5u), m, w(b + 6u));
    o(r, u.x); o(r + 1u, u.y); o(r + 2u, u.z); o(r + 3u, u.w);",
        17,
        &[Word::F32, Word::F32, Word::F32, Word::F32],
        &b,
        |bi, c| {
            let s = &all[bi];
            let valid = f(c[3]) >= 0.5;
            let m = c[7..16]
                .iter()
                .fold(SpatialMoments::default(), |m, &v| m.push(f(c[4]), f(v)));
            let mut h = if valid {
                decode_texel(s, c)
            } else {
                SpvgHistory::default()
            };
            let mut age = read_age(f(c[3]));
            if s.config
                .update_young(&mut h, &mut age, f(c[4]), c[5], valid, m.variance())
            {
                let mut t = encode_written(s, &h, c[6]);
                t[3] = bits(age as f32);
                t
            } else if valid {
                c[..4].to_vec()
            } else {
                vec![0; 4]
            }
        },
    );
    // The guided texel form on the same cases.
    compare(
        gpu,
        "spvg_update_young_texel_guided",
        "var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    for (var k = 7u; k < 16u; k++) { m = spvg_spatial_push(m, f(b + 4u), f(b + k)); }
    let t = vec4<f32>(f(b), f(b + 1u), f(b + 2u), f(b + 3u));
    let u = spvg_update_young_texel_guided(P, t, f(b + 4u), f(b + 16u), w(b + 5u), m, w(b + 6u));
    o(r, u.x); o(r + 1u, u.y); o(r + 2u, u.z); o(r + 3u, u.w);",
        17,
        &[Word::F32, Word::F32, Word::F32, Word::F32],
        &b,
        |bi, c| {
            let s = &all[bi];
            let valid = f(c[3]) >= 0.5;
            let m = c[7..16]
                .iter()
                .fold(SpatialMoments::default(), |m, &v| m.push(f(c[4]), f(v)));
            let mut h = if valid {
                decode_texel(s, c)
            } else {
                SpvgHistory::default()
            };
            let mut age = read_age(f(c[3]));
            if s.config.update_young_guided(
                &mut h,
                &mut age,
                f(c[4]),
                f(c[16]),
                c[5],
                valid,
                m.variance(),
            ) {
                let mut t = encode_written(s, &h, c[6]);
                t[3] = bits(age as f32);
                t
            } else if valid {
                c[..4].to_vec()
            } else {
                vec![0; 4]
            }
        },
    );
}

/// The setups with fractional counts on: each setup's configuration without the damped
/// correction (refused with fractional counts) and with a floor from 0 to 8 (skipped
/// where the budget's maximum is below it), same control model and storage.
fn fractional_setups() -> Vec<Setup> {
    let floors = [0.25, 0.0, 1.0, 8.0, 0.3, 2.5];
    setups()
        .into_iter()
        .enumerate()
        .filter_map(|(k, s)| {
            let config = s
                .config
                .to_builder()
                .max_change(None)
                .fractional_floor(Some(floors[k % floors.len()]))
                // The resolved-image rule on in two setups of three.
                .resolve_weight([Some(0.1), None, Some(0.37)][k % 3])
                .build()
                .ok()?;
            let params = Params::new(
                &config,
                s.control,
                &Storage {
                    encoding: s.enc,
                    layout: s.layout,
                    rounding: s.rounding,
                },
            );
            Some(Setup {
                config,
                params,
                ..s
            })
        })
        .collect()
}

/// A renderer's resolve weight word: none (-1, NaN, 0), hard values, weights in
/// `(0, 1]`, and above 1.
fn gen_resolve_input(g: &mut Gen) -> u32 {
    bits(match g.u32() % 6 {
        0 => -1.0,
        1 => f32::NAN,
        2 => g.hard(),
        3 => g.unit(),
        4 => 1.0 + g.unit(),
        _ => 0.0,
    })
}

/// A real count word: -1 (the integer rule), NaN, infinities, hard values, counts near
/// the budget and real counts below one.
fn gen_real(s: &Setup, g: &mut Gen) -> u32 {
    bits(match g.u32() % 6 {
        0 => -1.0,
        1 => g.hard(),
        2 => g.unit(),
        3 => g.unit() * 80.0,
        4 => (g.u32() % 70) as f32,
        _ => s.config.floor_f(),
    })
}

/// Fractional counts (`spvg::controller::fractional`, docs/algorithms.md §8.6) against
/// the core: the dither threshold, the raw and clamped real counts, the realised count,
/// the whole fractional estimate (history and texel forms), the recorded count, the span
/// weight, and the fractional update (history and texel forms, skipped frames
/// included), under every setup with fractional counts on and, for the estimate and
/// the update, also off (where they must be the integer rules).
#[test]
fn fractional_functions_match_the_core() {
    let Some(gpu) = gpu("fractional_functions_match_the_core") else {
        return;
    };
    let on = fractional_setups();
    assert!(
        on.len() >= 16,
        "only {} setups with fractional counts",
        on.len()
    );
    let b = batches(&on[..4], 61, |_, g| {
        let r = g.u32();
        vec![r >> (r % 32), g.u32() % 70_000, g.u32()]
    });
    compare(
        gpu,
        "spvg_dither_threshold",
        "ou(r, spvg_dither_threshold(w(b), w(b + 1u), w(b + 2u)));",
        3,
        &[Word::U32],
        &b,
        |_, c| vec![dither_threshold(c[0], c[1], c[2])],
    );
    // Real counts: hard, below one, near the integers, huge.
    let b = batches(&on[..4], 62, |_, g| {
        let c = match g.u32() % 5 {
            0 => g.hard(),
            1 => g.unit(),
            2 => (g.u32() % 80) as f32 + f32::EPSILON * (g.u32() % 4) as f32,
            3 => (g.u32() % 80) as f32 - 1e-4,
            _ => g.unit() * 80.0,
        };
        vec![bits(c), g.u32()]
    });
    compare(
        gpu,
        "spvg_realise_count",
        "ou(r, spvg_realise_count(f(b), w(b + 1u)));",
        2,
        &[Word::U32],
        &b,
        |_, c| vec![realise_count(f(c[0]), c[1])],
    );
    let mut all = on;
    all.extend(setups());
    // History (3), gamma, valid, threshold, age, the renderer's resolve weight.
    let b = batches(&all, 63, |s, g| {
        let mut v = gen_history(s, g).to_vec();
        v.push(bits(match g.u32() % 3 {
            0 => 1.0,
            1 => g.unit(),
            _ => g.hard(),
        }));
        v.push(g.flag());
        v.push(g.u32());
        v.push(match g.u32() % 4 {
            0 => g.u32() % 8,
            1 => g.u32() % 300,
            2 => 255,
            _ => g.u32(),
        });
        v.push(gen_resolve_input(g));
        v
    });
    compare(
        gpu,
        "spvg_resolve_weight, spvg_fractional_raw_count, spvg_real_count, spvg_estimate_resolved, spvg_estimate_fractional",
        "let h = spvg_History(f(b), f(b + 1u), f(b + 2u));
    let a = spvg_resolve_weight(P, w(b + 6u), f(b + 7u));
    o(r, a);
    o(r + 1u, spvg_fractional_raw_count(P, h, a));
    o(r + 2u, spvg_real_count(P, h, a));
    let e = spvg_estimate_resolved(P, h, w(b + 6u), f(b + 3u), w(b + 4u) != 0u, w(b + 5u), f(b + 7u));
    ou(r + 3u, e.count); o(r + 4u, e.real);
    let d = spvg_estimate_fractional(P, h, f(b + 3u), w(b + 4u) != 0u, w(b + 5u));
    ou(r + 5u, d.count); o(r + 6u, d.real);",
        8,
        &[
            Word::F32,
            Word::F32,
            Word::F32,
            Word::U32,
            Word::F32,
            Word::U32,
            Word::F32,
        ],
        &b,
        |bi, c| {
            let cfg = &all[bi].config;
            let h = history(c);
            let read = spvg::controller::rules::read_history(&h);
            let a = cfg.resolve_weight_at(c[6], f(c[7]));
            let raw = fractional_raw_count(
                &spvg::controller::rules::EstimateUniforms::new(cfg),
                read.variance,
                read.mean_count,
                a,
            );
            let e = cfg.estimate_resolved(&h, c[6], f(c[3]), c[4] != 0, c[5], f(c[7]));
            let d = cfg.estimate_fractional(&h, f(c[3]), c[4] != 0, c[5]);
            vec![
                bits(a),
                bits(raw),
                bits(cfg.real_count_at(&h, c[6], f(c[7]))),
                e.count,
                bits(e.real.unwrap_or(-1.0)),
                d.count,
                bits(d.real.unwrap_or(-1.0)),
            ]
        },
    );
    // The texel forms: texel (4), gamma, threshold, the renderer's resolve weight.
    let b = batches(&all, 64, |s, g| {
        let mut v: Vec<u32> = (0..3).map(|_| stored(s, g)).collect();
        v.push(gen_age_word(s, g));
        v.push(bits(if g.flag() == 0 { 1.0 } else { g.hard() }));
        v.push(g.u32());
        v.push(gen_resolve_input(g));
        v
    });
    compare(
        gpu,
        "spvg_estimate_texel_fractional, spvg_estimate_texel_resolved",
        "let t = vec4<f32>(f(b), f(b + 1u), f(b + 2u), f(b + 3u));
    let e = spvg_estimate_texel_fractional(P, t, f(b + 4u), w(b + 5u));
    ou(r, e.count); o(r + 1u, e.real);
    let d = spvg_estimate_texel_resolved(P, t, f(b + 4u), w(b + 5u), f(b + 6u));
    ou(r + 2u, d.count); o(r + 3u, d.real);",
        7,
        &[Word::U32, Word::F32, Word::U32, Word::F32],
        &b,
        |bi, c| {
            let s = &all[bi];
            let valid = f(c[3]) >= 0.5;
            let age = read_age(f(c[3]));
            let h = decode_texel(s, c);
            let e = s
                .config
                .estimate_resolved(&h, age, f(c[4]), valid, c[5], f32::NAN);
            let d = s
                .config
                .estimate_resolved(&h, age, f(c[4]), valid, c[5], f(c[6]));
            vec![
                e.count,
                bits(e.real.unwrap_or(-1.0)),
                d.count,
                bits(d.real.unwrap_or(-1.0)),
            ]
        },
    );
    // Recorded count and span weight: real, count, and the weight of the setup.
    let b = batches(&all, 65, |s, g| {
        let r = gen_real(s, g);
        let n = match g.u32() % 3 {
            0 => g.u32() % 10,
            1 => {
                // Next to the real count: the dither's outcomes and just above them.
                let c = if f(r) > 0.0 { f(r).min(1e6) } else { 0.0 };
                (c as u32).saturating_add(g.u32() % 3)
            }
            _ => g.count(&s.config),
        };
        vec![r, n]
    });
    compare(
        gpu,
        "spvg_recorded_count, spvg_span_weight",
        "o(r, spvg_recorded_count(f(b), w(b + 1u)));
    let s = spvg_span_weight(vec3<f32>(P.eta, P.retain, P.eta_retain), w(b + 1u));
    o(r + 1u, s.x); o(r + 2u, s.y); o(r + 3u, s.z);",
        2,
        &[Word::F32, Word::F32, Word::F32, Word::F32],
        &b,
        |bi, c| {
            let w = span_weight(&all[bi].config.weight(), c[1]);
            vec![
                bits(recorded_count(f(c[0]), c[1])),
                bits(w.eta()),
                bits(w.retain()),
                bits(w.eta_retain()),
            ]
        },
    );
    // The whole update: history (3), sample, count, valid, age, nine neighbours, guide,
    // real count.
    let skipped = core::cell::Cell::new(0);
    let b = batches(&all, 66, |s, g| {
        let mut v = gen_history(s, g).to_vec();
        let x = gen_sample(s, g, &v);
        v.push(bits(x));
        v.push(if g.u32().is_multiple_of(3) {
            0
        } else {
            g.count(&s.config)
        });
        v.push(g.flag());
        v.push(g.u32() % 300);
        v.extend(gen_neighbours(g, x));
        v.push(bits(match g.u32() % 3 {
            0 => f32::NAN,
            1 => x + (g.unit() - 0.5) * 0.1,
            _ => g.hard(),
        }));
        v.push(gen_real(s, g));
        v
    });
    let real_of = |w: u32| {
        let r = f(w);
        spvg::controller::fractional::is_real(r).then_some(r)
    };
    compare(
        gpu,
        "spvg_update_fractional",
        "var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    for (var k = 7u; k < 16u; k++) { m = spvg_spatial_push(m, f(b + 3u), f(b + k)); }
    let u = spvg_update_fractional(P, spvg_History(f(b), f(b + 1u), f(b + 2u)), f(b + 3u), f(b + 16u), w(b + 4u), f(b + 17u), w(b + 5u) != 0u, w(b + 6u), m);
    o(r, u.history.mean); o(r + 1u, u.history.variance); o(r + 2u, u.history.mean_count);
    ou(r + 3u, u.age); ob(r + 4u, u.accepted);",
        18,
        &[Word::F32, Word::F32, Word::F32, Word::U32, Word::U32],
        &b,
        |bi, c| {
            let cfg = &all[bi].config;
            let m = c[7..16]
                .iter()
                .fold(SpatialMoments::default(), |m, &v| m.push(f(c[3]), f(v)));
            let (mut h, mut age) = (history(c), c[6]);
            let real = real_of(c[17]);
            if skips(c[4], f(c[17]), c[5] != 0) {
                skipped.set(skipped.get() + 1);
            }
            let ok = cfg.update_fractional(
                &mut h,
                &mut age,
                f(c[3]),
                f(c[16]),
                c[4],
                real,
                c[5] != 0,
                m.variance(),
            );
            vec![
                bits(h.mean),
                bits(h.variance),
                bits(h.mean_count),
                age,
                u32::from(ok),
            ]
        },
    );
    eprintln!("spvg_update_fractional: {} skipped frames", skipped.get());
    assert!(
        skipped.get() > 2000,
        "only {} skipped frames",
        skipped.get()
    );
    // The texel form: texel (4), sample, count, random, nine neighbours, guide, real.
    let b = batches(&all, 67, |s, g| {
        let mut v: Vec<u32> = (0..3).map(|_| stored(s, g)).collect();
        v.push(gen_age_word(s, g));
        let [h0, h1, h2] = gen_history(s, g);
        if g.flag() == 0 {
            (v[0], v[1], v[2]) = (h0, h1, h2);
            if s.layout == Layout::F16 {
                for x in &mut v[..3] {
                    *x = bits(f16::from_f32(f(*x)).to_f32());
                }
            }
        }
        let x = if g.flag() == 0 { g.unit() } else { g.hard() };
        v.push(bits(x));
        v.push(if g.u32().is_multiple_of(3) {
            0
        } else {
            g.count(&s.config)
        });
        v.push(g.u32());
        v.extend(gen_neighbours(g, x));
        v.push(bits(if g.flag() == 0 { f32::NAN } else { g.unit() }));
        v.push(gen_real(s, g));
        v
    });
    compare(
        gpu,
        "spvg_update_fractional_texel",
        "var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    for (var k = 7u; k < 16u; k++) { m = spvg_spatial_push(m, f(b + 4u), f(b + k)); }
    let t = vec4<f32>(f(b), f(b + 1u), f(b + 2u), f(b + 3u));
    let u = spvg_update_fractional_texel(P, t, f(b + 4u), f(b + 16u), w(b + 5u), f(b + 17u), m, w(b + 6u));
    o(r, u.x); o(r + 1u, u.y); o(r + 2u, u.z); o(r + 3u, u.w);",
        18,
        &[Word::F32, Word::F32, Word::F32, Word::F32],
        &b,
        |bi, c| {
            let s = &all[bi];
            let valid = f(c[3]) >= 0.5;
            let m = c[7..16]
                .iter()
                .fold(SpatialMoments::default(), |m, &v| m.push(f(c[4]), f(v)));
            let mut h = if valid {
                decode_texel(s, c)
            } else {
                SpvgHistory::default()
            };
            let mut age = read_age(f(c[3]));
            let real = real_of(c[17]);
            let ok = s.config.update_fractional(
                &mut h,
                &mut age,
                f(c[4]),
                f(c[16]),
                c[5],
                real,
                valid,
                m.variance(),
            );
            if ok || skips(c[5], f(c[17]), valid) {
                let mut t = encode_written(s, &h, c[6]);
                t[3] = bits(age as f32);
                t
            } else if valid {
                c[..4].to_vec()
            } else {
                vec![0; 4]
            }
        },
    );
}

/// A frame's second moment word (docs/algorithms.md §8.8) for a frame whose mean is `x`:
/// none (NaN), binary rays (the mean itself), a spread above `x^2`, rounding just below
/// it, and hard values.
fn gen_moment(g: &mut Gen, x: f32) -> u32 {
    bits(match g.u32() % 6 {
        0 => f32::NAN,
        1 => x,
        2 => x * x + g.unit() * 0.3,
        3 => x * x * (1.0 - f32::EPSILON),
        4 => x * x,
        _ => g.hard(),
    })
}

/// The second-moment update (`spvg::controller::rules::update_moment`,
/// docs/algorithms.md §8.8) against the core: the per-sample variance, the whole update in
/// its history and texel forms, with and without a moment, under every setup (the firefly
/// clamp off and on) and the fractional ones.
#[test]
fn second_moment_functions_match_the_core() {
    let Some(gpu) = gpu("second_moment_functions_match_the_core") else {
        return;
    };
    let mut all = fractional_setups();
    all.extend(setups());
    let b = batches(&all[..4], 71, |s, g| {
        let h = gen_history(s, g);
        let x = gen_sample(s, g, &h);
        let count = match g.u32() % 4 {
            0 => g.u32() % 3,
            1 => g.u32(),
            _ => g.count(&s.config),
        };
        vec![bits(x), gen_moment(g, x), count]
    });
    compare(
        gpu,
        "spvg_per_sample_variance",
        "o(r, spvg_per_sample_variance(f(b), f(b + 1u), w(b + 2u)));",
        3,
        &[Word::F32],
        &b,
        |_, c| vec![bits(per_sample_variance(f(c[0]), f(c[1]), c[2]))],
    );
    // The whole update: history (3), sample, count, valid, age, nine neighbours, guide,
    // real count, second moment.
    let b = batches(&all, 72, |s, g| {
        let mut v = gen_history(s, g).to_vec();
        let x = gen_sample(s, g, &v);
        v.push(bits(x));
        v.push(if g.u32().is_multiple_of(5) {
            g.u32() % 2
        } else {
            g.count(&s.config)
        });
        v.push(g.flag());
        v.push(g.u32() % 300);
        v.extend(gen_neighbours(g, x));
        v.push(bits(match g.u32() % 3 {
            0 => f32::NAN,
            1 => x + (g.unit() - 0.5) * 0.1,
            _ => g.hard(),
        }));
        v.push(gen_real(s, g));
        v.push(gen_moment(g, x));
        v
    });
    let real_of = |w: u32| {
        let r = f(w);
        spvg::controller::fractional::is_real(r).then_some(r)
    };
    let moments = core::cell::Cell::new(0);
    compare(
        gpu,
        "spvg_update_moment",
        "var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    for (var k = 7u; k < 16u; k++) { m = spvg_spatial_push(m, f(b + 3u), f(b + k)); }
    let u = spvg_update_moment(P, spvg_History(f(b), f(b + 1u), f(b + 2u)), f(b + 3u), f(b + 16u), f(b + 18u), w(b + 4u), f(b + 17u), w(b + 5u) != 0u, w(b + 6u), m);
    o(r, u.history.mean); o(r + 1u, u.history.variance); o(r + 2u, u.history.mean_count);
    ou(r + 3u, u.age); ob(r + 4u, u.accepted);",
        19,
        &[Word::F32, Word::F32, Word::F32, Word::U32, Word::U32],
        &b,
        |bi, c| {
            let cfg = &all[bi].config;
            let m = c[7..16]
                .iter()
                .fold(SpatialMoments::default(), |m, &v| m.push(f(c[3]), f(v)));
            let (mut h, mut age) = (history(c), c[6]);
            let valid = c[5] != 0;
            if valid && per_sample_variance(f(c[3]), f(c[18]), c[4]) >= 0.0 {
                moments.set(moments.get() + 1);
            }
            let ok = cfg.update_moment(
                &mut h,
                &mut age,
                f(c[3]),
                f(c[16]),
                f(c[18]),
                c[4],
                real_of(c[17]),
                valid,
                m.variance(),
            );
            vec![
                bits(h.mean),
                bits(h.variance),
                bits(h.mean_count),
                age,
                u32::from(ok),
            ]
        },
    );
    eprintln!(
        "spvg_update_moment: {} frames with a per-sample variance",
        moments.get()
    );
    assert!(
        moments.get() > 2000,
        "only {} frames with a moment",
        moments.get()
    );
    // The texel form: texel (4), sample, count, random, nine neighbours, guide, real,
    // second moment.
    let b = batches(&all, 73, |s, g| {
        let mut v: Vec<u32> = (0..3).map(|_| stored(s, g)).collect();
        v.push(gen_age_word(s, g));
        let [h0, h1, h2] = gen_history(s, g);
        if g.flag() == 0 {
            (v[0], v[1], v[2]) = (h0, h1, h2);
            if s.layout == Layout::F16 {
                for x in &mut v[..3] {
                    *x = bits(f16::from_f32(f(*x)).to_f32());
                }
            }
        }
        let x = if g.flag() == 0 { g.unit() } else { g.hard() };
        v.push(bits(x));
        v.push(if g.u32().is_multiple_of(5) {
            g.u32() % 2
        } else {
            g.count(&s.config)
        });
        v.push(g.u32());
        v.extend(gen_neighbours(g, x));
        v.push(bits(if g.flag() == 0 { f32::NAN } else { g.unit() }));
        v.push(gen_real(s, g));
        v.push(gen_moment(g, x));
        v
    });
    compare(
        gpu,
        "spvg_update_moment_texel",
        "var m = spvg_SpatialMoments(0u, 0.0, 0.0);
    for (var k = 7u; k < 16u; k++) { m = spvg_spatial_push(m, f(b + 4u), f(b + k)); }
    let t = vec4<f32>(f(b), f(b + 1u), f(b + 2u), f(b + 3u));
    let u = spvg_update_moment_texel(P, t, f(b + 4u), f(b + 16u), f(b + 18u), w(b + 5u), f(b + 17u), m, w(b + 6u));
    o(r, u.x); o(r + 1u, u.y); o(r + 2u, u.z); o(r + 3u, u.w);",
        19,
        &[Word::F32, Word::F32, Word::F32, Word::F32],
        &b,
        |bi, c| {
            let s = &all[bi];
            let valid = f(c[3]) >= 0.5;
            let m = c[7..16]
                .iter()
                .fold(SpatialMoments::default(), |m, &v| m.push(f(c[4]), f(v)));
            let mut h = if valid {
                decode_texel(s, c)
            } else {
                SpvgHistory::default()
            };
            let mut age = read_age(f(c[3]));
            let real = real_of(c[17]);
            let ok = s.config.update_moment(
                &mut h,
                &mut age,
                f(c[4]),
                f(c[16]),
                f(c[18]),
                c[5],
                real,
                valid,
                m.variance(),
            );
            if ok || skips(c[5], f(c[17]), valid) {
                let mut t = encode_written(s, &h, c[6]);
                t[3] = bits(age as f32);
                t
            } else if valid {
                c[..4].to_vec()
            } else {
                vec![0; 4]
            }
        },
    );
}

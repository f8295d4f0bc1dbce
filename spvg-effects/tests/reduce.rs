//! The budget reduction (`src/sss/shaders/reduce.wgsl`) against its CPU twin, and a moving target
//! with a fixed texel encoding: the GPU pass and the twin stay bit-identical while
//! `sigma0^2` crosses powers of two, and the stored variances keep their meaning.

mod common;

use half::f16;
use spvg::SpvgConfig;
use spvg::budget::{BudgetConfig, CURVE_POINTS, Governor};
use spvg::burley::presets::SKIN1;
use spvg::texel::{SpvgTexel16, TexelEncoding};
use spvg_effects::sss::twin::{BlockTwin, pixel_gamma_s, reduce_demand};
use spvg_effects::sss::{FrameInputs, FrameSums, Model, PassConfig, ReducePass, SssPass, SssTwin};

const W: u32 = 37;
const H: u32 = 29;

/// A frame with structure: a lit gradient whose level changes with `t`, depths from
/// 0.3 m to 3 m (some pixels below the zero-sample threshold: large distant ratio at
/// small footprint only near the camera), and a mask with holes.
fn inputs(t: u32) -> FrameInputs {
    let n = (W * H) as usize;
    let mut lighting = Vec::with_capacity(n);
    let mut depth = Vec::with_capacity(n);
    let mut mask = Vec::with_capacity(n);
    for y in 0..H {
        for x in 0..W {
            let l = 0.05 + 0.9 * ((x * 7 + y * 3 + t * 11) % 23) as f32 / 23.0;
            let l = if t % 4 == 2 { l * 4.0 } else { l };
            let v = f16::from_f32(l);
            lighting.push([v, f16::from_f32(0.7 * l), f16::from_f32(0.5 * l), f16::ONE]);
            depth.push(300.0 + 2700.0 * ((x + 2 * y) % 31) as f32 / 31.0);
            mask.push(u8::from(!(x * 5 + y * 11 + t).is_multiple_of(13)));
        }
    }
    FrameInputs {
        width: W,
        height: H,
        lighting,
        depth,
        mask,
    }
}

/// A target that crosses several powers of two, around the fixed encoding target 1e-4.
fn target(t: u32) -> f32 {
    [1e-4, 3e-4, 5e-5, 1e-3, 2e-5, 1e-4, 7e-4][t as usize % 7]
}

/// Frame `t`'s settings: its target (the first frame's, 1e-4, fixes the encoding).
fn config(t: u32) -> PassConfig {
    PassConfig {
        spvg: SpvgConfig::builder()
            .target_variance(target(t))
            .build()
            .expect("valid target"),
        ..PassConfig::default()
    }
}

/// The encoding the first frame's target fixes.
fn fixed_encoding() -> TexelEncoding {
    TexelEncoding::new(1e-4).expect("valid target")
}

/// An H texel decoded with `enc`, and its written mark.
fn decode(enc: &TexelEncoding, h: [f16; 4]) -> (spvg::SpvgHistory<f32>, bool) {
    (enc.decode(SpvgTexel16(h)), h[3].to_f32() >= 0.5)
}

/// The candidate targets of frame `t`: a governor's, around a base that moves with `t`.
fn candidates(t: u32) -> [f32; CURVE_POINTS] {
    let budget = BudgetConfig::builder(1e4).build().expect("valid budget");
    let g = Governor::new(budget, f64::from(target(t + 3))).expect("valid target");
    g.curve_targets().map(|c| c as f32)
}

/// The clamped demand curve of one frame from the core crate alone: per pixel, the
/// estimate of a configuration rebuilt at each candidate target, summed in u64.
fn curve_u64(
    tw: &BlockTwin,
    targets: &[f32; CURVE_POINTS],
    inputs: &FrameInputs,
    hist: &[[f16; 4]],
) -> [u64; CURVE_POINTS] {
    let controller = tw.spvg;
    let at: Vec<_> = targets
        .iter()
        .map(|&s| {
            controller
                .to_builder()
                .target_variance(s)
                .build()
                .expect("valid target")
        })
        .collect();
    let mut s = [0_u64; CURVE_POINTS];
    for y in 0..H {
        for x in 0..W {
            let i = (y * W + x) as usize;
            if inputs.mask[i] == 0 {
                continue;
            }
            let (h, valid) = decode(&tw.enc, hist[i]);
            let gamma = pixel_gamma_s(tw, inputs, x, y);
            for (sum, c) in s.iter_mut().zip(&at) {
                *sum += u64::from(c.estimate_with_validity(&h, gamma, valid));
            }
        }
    }
    s
}

#[test]
fn moving_target_with_fixed_encoding_matches_the_twin() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("moving_target_with_fixed_encoding_matches_the_twin").device()
    else {
        return;
    };
    let mut gpu = SssPass::new(&dev.device, &dev.queue, W, H, Model::Ccv, false);
    let mut cpu = SssTwin::new(Model::Ccv, W, H);
    let reduce = ReducePass::new(&dev.device, &dev.queue, W, H);
    let mut saw_valid = false;
    for t in 0..14 {
        let frame = inputs(t);
        let cfg = config(t);
        let params = gpu.frame_params(&cfg, &SKIN1, t).expect("valid params");
        assert_eq!(
            cpu.frame_params(&cfg, &SKIN1, t).expect("valid params"),
            params,
            "frame {t}: the twin's block is the pass's"
        );
        let g = gpu.run_frame(&params, &frame).expect("gpu frame");
        let c = cpu.run_frame(&params, &frame).expect("cpu frame");
        // Counts equal; texels equal but for the pass's Burley sampling, within 2e-5 of
        // the core's, not bit-identical (spvg-shaders README; `common::SAMPLING_ULPS`);
        // the texel scales themselves are the block's.
        let gh = gpu.history().expect("history").h;
        let same = |a: usize| a as f64 / (W * H) as f64;
        let counts = same(g.count.iter().zip(&c.count).filter(|(a, b)| a == b).count());
        let texels = same(
            gh.iter()
                .zip(&cpu.history().h)
                .filter(|(a, b)| a == b)
                .count(),
        );
        let ulps = common::max_f16_ulps(&gh, &cpu.history().h);
        eprintln!(
            "frame {t} sigma0^2 {}: counts equal {counts:.4}, H texels equal {texels:.4}, \
             largest texel difference {ulps} f16 ulp",
            target(t)
        );
        assert_eq!(g.count, c.count, "frame {t}: counts");
        // The one exception, as in tests/sss_consumer.rs: a stored channel may differ by
        // the Burley sampling's tolerance.
        assert!(
            ulps <= common::SAMPLING_ULPS,
            "frame {t}: texels {ulps} f16 ulp apart"
        );
        assert_eq!(
            params.spvg.var_scale,
            2.0_f32.powi(-13),
            "frame {t}: fixed scale"
        );

        // The reduction over the history the next frame reads: GPU against the twin, bit
        // for bit.
        let targets = candidates(t);
        let gp = reduce
            .run(
                &params,
                &targets,
                gpu.reduce_inputs().expect("CCV keeps history"),
            )
            .expect("reduce");
        let tw = BlockTwin::new(&params, &cfg.spvg, fixed_encoding()).expect("valid block");
        let cp = reduce_demand(&tw, &targets, &frame, &gh, &g.count);
        assert_eq!(
            gp.len(),
            (W.div_ceil(8) * H.div_ceil(8)) as usize,
            "one partial per workgroup"
        );
        assert_eq!(gp, cp, "frame {t}: partials");

        // Independent sums: the counts, and the core's per-pixel estimate at each
        // candidate target, exact.
        let sums = FrameSums::from_partials(&gp, &targets);
        let total: u64 = g.count.iter().map(|&n| u64::from(n)).sum();
        assert_eq!(sums.total, total, "frame {t}: total count");
        let want = curve_u64(&tw, &targets, &frame, &gh);
        assert_eq!(
            sums.curve.totals,
            want.map(|n| n as f64),
            "frame {t}: demand curve"
        );
        assert_eq!(
            sums.curve.targets,
            targets.map(f64::from),
            "frame {t}: candidates"
        );
        assert!(
            want.windows(2).all(|w| w[0] >= w[1]),
            "frame {t}: the curve falls with the target: {want:?}"
        );
        // Some frame's pixels respond to the target within the candidates.
        saw_valid |= want[0] > want[CURVE_POINTS - 1];
    }
    assert!(saw_valid, "the frames built valid histories with variance");
}

/// The stored variance keeps its meaning when the target moves: the twin keeps the first
/// frame's encoding at every later target, and the variance it stored decodes with that
/// encoding; rebuilt from a later frame's target it would read 8 times larger.
#[test]
fn stored_variance_reads_the_same_under_a_moving_target() {
    let mut cpu = SssTwin::new(Model::Ccv, W, H);
    for (t, sigma0_sq) in [1e-4, 1e-3, 2e-5].into_iter().enumerate() {
        let cfg = PassConfig {
            spvg: SpvgConfig::builder()
                .target_variance(sigma0_sq)
                .build()
                .expect("valid target"),
            ..PassConfig::default()
        };
        let p = cpu.frame_params(&cfg, &SKIN1, t as u32).expect("valid");
        assert_eq!(
            p.spvg.var_scale,
            2.0_f32.powi(-13),
            "fixed encoding at {sigma0_sq}"
        );
        cpu.run_frame(&p, &inputs(t as u32)).expect("frame");
    }
    let hist = cpu.history().h;
    let read = |enc: TexelEncoding| -> Vec<f32> {
        hist.iter().map(|h| decode(&enc, *h).0.variance).collect()
    };
    let written = read(fixed_encoding());
    assert!(written.iter().any(|&v| v > 0.0), "some variance was stored");
    // Rebuilding the encoding from the last frame's target (2^-10 instead of 2^-13)
    // reads every stored variance 8 times larger: the defect the fixed encoding removes.
    let moved = read(TexelEncoding::new(1e-3).expect("valid target"));
    for (m, w) in moved.iter().zip(&written) {
        assert_eq!(
            *m,
            8.0 * w,
            "per-frame encoding rescales the stored variance"
        );
    }
}

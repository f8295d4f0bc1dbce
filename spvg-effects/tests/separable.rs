//! The separable filter and its hybrid frame: the WGSL validates; the twin has the
//! properties of a normalised gather (constant in, constant out; an impulse keeps its
//! energy and spreads by the kernel; nothing bleeds across the silhouette; tagged pixels
//! pass the AFIS result through); the GPU equals the twin. GPU tests skip cleanly without
//! an adapter (`SPVG_REQUIRE_GPU=1` makes that a failure).

mod common;

use half::f16;
use spvg::burley::presets::{MARBLE, SKIN1};
use spvg_effects::sss::twin::{HybridSources, SeparableTwin, sep_horizontal, sep_vertical};
use spvg_effects::sss::{
    FrameInputs, MAX_SEPARABLE_SAMPLES, SeparableConfig, SeparableParams, SeparablePass,
    separable_source,
};

#[test]
fn separable_wgsl_validates_without_a_gpu() {
    let module = naga::front::wgsl::parse_str(&separable_source()).expect("separable.wgsl parses");
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .expect("separable.wgsl validates");
    for entry in ["sep_horizontal", "sep_vertical"] {
        assert!(
            module.entry_points.iter().any(|e| e.name == entry),
            "entry point {entry} missing"
        );
    }
    // The block's array length is the Rust constant.
    assert!(
        separable_source().contains(&format!("array<vec4<f32>, {MAX_SEPARABLE_SAMPLES}>")),
        "kernel array length"
    );
}

fn flat(w: u32, h: u32, level: f32, depth: f32) -> FrameInputs {
    let n = (w * h) as usize;
    let v = f16::from_f32(level);
    FrameInputs {
        width: w,
        height: h,
        lighting: vec![[v, v, v, f16::ONE]; n],
        depth: vec![depth; n],
        mask: vec![1; n],
    }
}

#[test]
fn constant_lighting_stays_constant() {
    let (w, h) = (19, 13);
    let mut inputs = flat(w, h, 0.75, 700.0);
    // Holes in the mask and varied depth: still a normalised gather of equal values.
    for (i, m) in inputs.mask.iter_mut().enumerate() {
        if i % 7 == 3 {
            *m = 0;
        }
    }
    for (i, z) in inputs.depth.iter_mut().enumerate() {
        *z = 300.0 + (i % 11) as f32 * 150.0;
    }
    let p = SeparableConfig::default()
        .params(&SKIN1, w, h, false)
        .unwrap();
    let out = SeparableTwin.run_frame(&p, &inputs, None).unwrap();
    for (i, t) in out.result.iter().enumerate() {
        let want = if inputs.mask[i] == 0 { 0.0 } else { 0.75 };
        for (c, v) in t[..3].iter().enumerate() {
            let got = v.to_f32();
            assert!(
                (got - want).abs() <= 1e-3,
                "pixel {i} channel {c}: {got} != {want}"
            );
        }
    }
}

#[test]
fn an_impulse_keeps_its_energy_and_spreads_by_the_kernel() {
    // One lit pixel in the middle of a large surface, 1 mm texels (depth 1000 mm, w_px
    // 1e-3): the first pass spreads it along its row by the kernel, each tap's weight split
    // between the two texels around the tap by linear interpolation. Every pixel gathers
    // with the same kernel, so the row's total is the impulse (weights sum to 1).
    let (w, h) = (41, 5);
    let mut inputs = flat(w, h, 0.0, 1000.0);
    let (cx, cy) = (20_usize, 2_usize);
    inputs.lighting[cy * w as usize + cx] = [f16::ONE; 4];
    let cfg = SeparableConfig::default();
    let p = cfg.params(&SKIN1, w, h, false).unwrap();
    let blurred = sep_horizontal(&p, &inputs, None);
    let kernel = cfg.kernel(&SKIN1).unwrap();
    for c in 0..3 {
        let row: f32 = (0..w as usize)
            .map(|x| blurred[cy * w as usize + x][c])
            .sum();
        assert!((row - 1.0).abs() < 1e-5, "channel {c}: row total {row}");
        // Brute force: pixel x gathers tap k at u = x + o_k, so the impulse at cx reaches x
        // with weight w_k (1 - t) when floor(u) = cx and w_k t when floor(u) + 1 = cx.
        for x in 0..w as usize {
            let mut want = 0.0_f32;
            for k in &kernel {
                let u = x as f32 + k[0];
                let (u0, t) = (u.floor(), u - u.floor());
                if u0 as i64 == cx as i64 {
                    want += k[c + 1] * (1.0 - t);
                }
                if u0 as i64 + 1 == cx as i64 {
                    want += k[c + 1] * t;
                }
            }
            let got = blurred[cy * w as usize + x][c];
            assert!(
                (got - want).abs() < 1e-6,
                "x {x} channel {c}: {got} != {want}"
            );
        }
        // Other rows are untouched by the first pass.
        assert_eq!(blurred[0][c], 0.0, "row 0");
    }
}

#[test]
fn nothing_bleeds_across_the_silhouette() {
    // A bright region off the material next to a dark subsurface one: the dark pixels
    // read their own value where a tap lands off the material.
    let (w, h) = (24, 8);
    let mut inputs = flat(w, h, 0.1, 1000.0);
    for y in 0..h as usize {
        for x in 12..w as usize {
            inputs.mask[y * w as usize + x] = 0;
            inputs.lighting[y * w as usize + x] = [f16::from_f32(100.0); 4];
        }
    }
    let p = SeparableConfig::default()
        .params(&MARBLE, w, h, false)
        .unwrap();
    let out = SeparableTwin.run_frame(&p, &inputs, None).unwrap();
    for y in 0..h as usize {
        for x in 0..12 {
            let got = out.result[y * w as usize + x][0].to_f32();
            assert!((got - 0.1).abs() < 1e-3, "({x}, {y}): {got}");
        }
    }
}

/// A frame with structure for the GPU comparison: a shadow edge, a bright spot, depths
/// from 0.4 m to 2 m, mask holes, and (hybrid) a tagged disc with its own result.
fn structured(w: u32, h: u32) -> (FrameInputs, Vec<u8>, Vec<[f16; 4]>) {
    let mut f = flat(w, h, 0.0, 1000.0);
    let mut technique = vec![0_u8; f.len()];
    let mut afis = vec![[f16::ZERO; 4]; f.len()];
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let lit = if x < w / 2 { 1.0 } else { 0.05 };
            let spot = if (x as i32 - 30).abs() < 2 && (y as i32 - 9).abs() < 2 {
                4.0
            } else {
                0.0
            };
            let l = lit + spot + 0.01 * ((x * 13 + y * 7) % 17) as f32;
            f.lighting[i] = [
                f16::from_f32(l),
                f16::from_f32(0.8 * l),
                f16::from_f32(0.6 * l),
                f16::ONE,
            ];
            f.depth[i] = 400.0 + 1600.0 * ((x + 3 * y) % 29) as f32 / 29.0;
            f.mask[i] = u8::from(!(x * 5 + y * 11).is_multiple_of(13));
            let (dx, dy) = (x as f32 - 20.0, y as f32 - 12.0);
            if dx * dx + dy * dy < 64.0 {
                technique[i] = 1;
                afis[i] = [f16::from_f32(0.9 * l + 0.1); 4];
            }
        }
    }
    (f, technique, afis)
}

#[test]
fn hybrid_twin_passes_the_afis_result_through_where_tagged() {
    let (w, h) = (48, 24);
    let (inputs, technique, afis) = structured(w, h);
    let p = SeparableConfig::default()
        .params(&SKIN1, w, h, true)
        .unwrap();
    let sources = HybridSources {
        technique: &technique,
        afis: &afis,
    };
    let out = SeparableTwin.run_frame(&p, &inputs, Some(sources)).unwrap();
    for i in 0..inputs.len() {
        if technique[i] == 1 && inputs.mask[i] != 0 {
            assert_eq!(out.result[i][..3], afis[i][..3], "pixel {i}");
        }
    }
    // A separable pixel next to the region reads the AFIS result there: a brighter AFIS
    // result brightens it.
    let brighter: Vec<[f16; 4]> = afis
        .iter()
        .map(|t| t.map(|v| v * f16::from_f32(2.0)))
        .collect();
    let again = SeparableTwin
        .run_frame(
            &p,
            &inputs,
            Some(HybridSources {
                technique: &technique,
                afis: &brighter,
            }),
        )
        .unwrap();
    let edge = (12 * w + 29) as usize; // (29, 12): one pixel outside the disc of radius 8.
    assert_eq!(technique[edge], 0, "the probe is a separable pixel");
    assert!(
        again.result[edge][1].to_f32() > out.result[edge][1].to_f32(),
        "{} <= {}",
        again.result[edge][1],
        out.result[edge][1]
    );
}

#[test]
fn bad_configurations_are_rejected_by_name() {
    for (cfg, name) in [
        (
            SeparableConfig {
                samples: 16,
                ..SeparableConfig::default()
            },
            "samples",
        ),
        (
            SeparableConfig {
                samples: 35,
                ..SeparableConfig::default()
            },
            "samples",
        ),
        (
            SeparableConfig {
                strength: f32::NAN,
                ..SeparableConfig::default()
            },
            "strength",
        ),
        (
            SeparableConfig {
                w_px: 0.0,
                ..SeparableConfig::default()
            },
            "w_px",
        ),
    ] {
        let e = cfg.params(&SKIN1, 8, 8, false).unwrap_err();
        assert!(e.to_string().contains(name), "{e}");
    }
    let p = SeparableConfig::default()
        .params(&SKIN1, 8, 8, false)
        .unwrap();
    assert!(
        SeparableTwin
            .run_frame(&p, &flat(8, 7, 1.0, 1000.0), None)
            .is_err(),
        "size"
    );
}

#[test]
fn separable_params_layout() {
    // Each field lands where the WGSL struct puts it: the kernel at byte 32.
    let mut p: SeparableParams = bytemuck::Zeroable::zeroed();
    p.kernel[0][0] = 1.5;
    p.samples = 7;
    let bytes = bytemuck::bytes_of(&p);
    assert_eq!(bytes.len(), 560, "block size");
    assert_eq!(&bytes[8..12], &7_u32.to_ne_bytes(), "samples at 8");
    assert_eq!(&bytes[32..36], &1.5_f32.to_ne_bytes(), "kernel at 32");
}

/// The largest distance in f16 ulps between the pass's result and the CPU twin's for one
/// frame; asserts the pass took no samples. The gathers are sums of products in the same
/// order; a device may fuse them (FMA), which moves a result by at most a rounding step of
/// the f16 store, so callers allow 1.
fn gpu_vs_twin_ulps(
    pass: &mut SeparablePass,
    p: &SeparableParams,
    inputs: &FrameInputs,
    sources: Option<HybridSources<'_>>,
) -> u32 {
    let gpu = pass.run_frame(p, inputs, sources).unwrap();
    assert!(gpu.count.iter().all(|&n| n == 0), "no samples");
    let blurred = sep_horizontal(p, inputs, sources);
    let cpu = sep_vertical(p, inputs, sources, &blurred);
    common::max_f16_ulps(&gpu.result, &cpu)
}

#[test]
fn gpu_equals_twin_for_the_separable_and_hybrid_passes() {
    let Some(d) =
        spvg_gpu_test::GpuTest::new("gpu_equals_twin_for_the_separable_and_hybrid_passes").device()
    else {
        return;
    };
    let (w, h) = (48, 24);
    let (inputs, technique, afis) = structured(w, h);
    let mut pass = SeparablePass::new(&d.device, &d.queue, w, h);
    for (hybrid, strength, samples) in [(false, 1.0, 17), (true, 1.0, 17), (false, 0.7, 25)] {
        let cfg = SeparableConfig {
            strength,
            samples,
            ..SeparableConfig::default()
        };
        let p = cfg.params(&SKIN1, w, h, hybrid).unwrap();
        let sources = hybrid.then_some(HybridSources {
            technique: &technique,
            afis: &afis,
        });
        let ulps = gpu_vs_twin_ulps(&mut pass, &p, &inputs, sources);
        assert!(
            ulps <= 1,
            "hybrid {hybrid}, strength {strength}: {ulps} f16 ulps apart"
        );
    }
}

#[test]
fn host_kernels_have_ascending_offsets() {
    // The passes' texel walk (separable.wgsl) is what runs when a pixel's taps come in
    // ascending order; every kernel the host builds must give it that.
    for material in spvg::burley::presets::ALL {
        for samples in (3..=MAX_SEPARABLE_SAMPLES as u32).step_by(2) {
            let cfg = SeparableConfig {
                samples,
                ..SeparableConfig::default()
            };
            let k = cfg.kernel(&material).unwrap();
            assert!(
                k.windows(2).all(|w| w[0][0] < w[1][0]),
                "{} with {samples} samples: offsets {:?}",
                material.name,
                k.iter().map(|t| t[0]).collect::<Vec<_>>()
            );
        }
    }
}

#[test]
fn gpu_equals_twin_for_kernels_in_any_order_and_span() {
    // The passes walk the texels where a pixel's taps ascend over a short span and load two
    // texels per tap elsewhere; the twin loads per tap always. Kernels out of order (all
    // reversed; two middle taps swapped, so a walk stops part way) and texels much smaller
    // than the kernel (a span longer than the walk takes, at some depths of the frame but
    // not others) must give the twin's sums as well as the host's kernel does.
    let Some(d) =
        spvg_gpu_test::GpuTest::new("gpu_equals_twin_for_kernels_in_any_order_and_span").device()
    else {
        return;
    };
    let (w, h) = (48, 24);
    let (inputs, technique, afis) = structured(w, h);
    let mut pass = SeparablePass::new(&d.device, &d.queue, w, h);
    for (case, w_px, hybrid) in [
        ("ascending", 1e-3, false),
        ("ascending, small texels", 0.2e-3, false),
        ("reversed", 1e-3, false),
        ("two swapped", 1e-3, true),
        ("two swapped, small texels", 0.2e-3, false),
    ] {
        let cfg = SeparableConfig {
            samples: 17,
            w_px,
            h_px: w_px,
            ..SeparableConfig::default()
        };
        let mut p = cfg.params(&SKIN1, w, h, hybrid).unwrap();
        if case.starts_with("reversed") {
            p.kernel[..17].reverse();
        } else if case.starts_with("two swapped") {
            p.kernel.swap(10, 12);
        }
        let sources = hybrid.then_some(HybridSources {
            technique: &technique,
            afis: &afis,
        });
        let ulps = gpu_vs_twin_ulps(&mut pass, &p, &inputs, sources);
        assert!(ulps <= 1, "{case}: {ulps} f16 ulps apart");
    }
}

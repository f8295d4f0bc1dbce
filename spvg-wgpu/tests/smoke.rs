//! Quick smoke test: the WGSL builds and runs.
use half::f16;
use spvg_wgpu::material::SKIN1;
use spvg_wgpu::*;

#[test]
fn smoke() {
    let Ok(dev) = acquire_device() else {
        eprintln!("skip: no adapter");
        return;
    };
    eprintln!("{}", dev.describe());
    let (w, h) = (32u32, 32u32);
    let n = (w * h) as usize;
    let lighting: Vec<[f16; 4]> = (0..n)
        .map(|i| {
            let x = (i % w as usize) as f32;
            let v = if x < 16.0 { 1.0 } else { 0.2 };
            [
                f16::from_f32(v),
                f16::from_f32(v * 0.8),
                f16::from_f32(v * 0.6),
                f16::ONE,
            ]
        })
        .collect();
    let inputs = FrameInputs {
        width: w,
        height: h,
        lighting,
        depth: vec![500.0; n],
        mask: vec![1; n],
    };
    let cfg = PassConfig::default();
    for model in [Model::Fixed(16), Model::As, Model::Ccv, Model::Ocv] {
        let mut gpu = run_inner(&dev, model, w, h);
        let mut cpu = CpuPass::new(model, n);
        for f in 0..3 {
            let p = cfg.params(model, &SKIN1, w, h, f).unwrap();
            let a = gpu.run_frame(&p, &inputs).unwrap();
            let b = cpu.run_frame(&p, &inputs).unwrap();
            let same = a.count.iter().zip(&b.count).filter(|(x, y)| x == y).count();
            let maxd = a
                .result
                .iter()
                .zip(&b.result)
                .map(|(x, y)| (x[0].to_f32() - y[0].to_f32()).abs())
                .fold(0.0, f32::max);
            eprintln!(
                "{model:?} f{f}: counts same {same}/{n} mean {} maxdiff {maxd} t={:.3}ms {:?}",
                a.count.iter().sum::<u32>() as f32 / n as f32,
                a.time_ms,
                a.timer
            );
        }
    }
}

#[test]
fn diag() {
    let Ok(dev) = acquire_device() else {
        return;
    };
    let (w, h) = (32u32, 32u32);
    let n = (w * h) as usize;
    let lighting: Vec<[f16; 4]> = (0..n)
        .map(|i| {
            let x = (i % w as usize) as f32;
            let v = if x < 16.0 { 1.0 } else { 0.2 };
            [
                f16::from_f32(v),
                f16::from_f32(v * 0.8),
                f16::from_f32(v * 0.6),
                f16::ONE,
            ]
        })
        .collect();
    let inputs = FrameInputs {
        width: w,
        height: h,
        lighting,
        depth: vec![500.0; n],
        mask: vec![1; n],
    };
    let cfg = PassConfig::default();
    let model = Model::As;
    let mut gpu = run_inner(&dev, model, w, h);
    let mut cpu = CpuPass::new(model, n);
    for f in 0..3 {
        let p = cfg.params(model, &SKIN1, w, h, f).unwrap();
        let a = gpu.run_frame(&p, &inputs).unwrap();
        let b = cpu.run_frame(&p, &inputs).unwrap();
        let ha = gpu.history().unwrap();
        let hb = cpu.history();
        let mut hd = [0usize; 4];
        let mut worst = [0f32; 4];
        for (x, y) in ha.h.iter().zip(&hb.h) {
            for c in 0..4 {
                if x[c] != y[c] {
                    hd[c] += 1;
                    worst[c] = worst[c]
                        .max((x[c].to_f32() - y[c].to_f32()).abs() / y[c].to_f32().abs().max(1e-6));
                }
            }
        }
        let rd = a
            .result
            .iter()
            .zip(&b.result)
            .filter(|(x, y)| x != y)
            .count();
        eprintln!(
            "f{f}: hist texel channel diffs {hd:?} worst rel {worst:?}; result texels differing {rd}"
        );
        for (i, (x, y)) in a.count.iter().zip(&b.count).enumerate() {
            if x != y && f == 2 {
                eprintln!("  px {} {}: gpu {x} cpu {y}", i % 32, i / 32);
            }
        }
    }
}

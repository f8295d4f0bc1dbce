//! Same inputs, same frame. The AO consumer around the adaptive component renders the
//! report's moving scenes at the report's sizes for the report's 48 frames: twice on the
//! GPU, the second time with a busy-loop thread on every core, and once on the CPU twin.
//! Every frame of the three must be equal bit for bit: the counts, the history texels, the
//! AO values and the prefix estimates (the fixed runs of smaller counts), for the adaptive
//! component and for a fixed count. A per-lane fault of the rasterizer, a race between
//! passes, a readback of work still in flight or state kept between runs shows up here
//! as a frame that differs, with its pixel and its SIMD lane (`x mod 8`).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use half::f16;
use spvg::SpvgConfig;
use spvg_effects::ao::{AoMode, AoPass, AoScene, AoTwin, Motion};
use spvg_gpu_test::{GpuDevice, GpuTest};
use spvg_wgpu::adaptive::AdaptiveSettings;
use spvg_wgpu::util::read_texture;

/// The report's frames per run.
const FRAMES: u32 = 48;

/// The prefix counts of the report's fixed run (its equal-quality ladder).
const PREFIXES: [u32; 4] = [16, 32, 0, 0];

/// One frame as the test compares it: counts, history texels (empty for a fixed count),
/// AO values and prefix estimates, all as bits.
#[derive(Debug, PartialEq)]
struct Frame {
    count: Vec<u32>,
    history: Vec<[u16; 4]>,
    value: Vec<u32>,
    prefixes: Vec<[u32; 4]>,
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn frame(f: spvg_effects::ao::AoFrame, history: Vec<[f16; 4]>) -> Frame {
    Frame {
        count: f.count,
        history: history.iter().map(|t| t.map(f16::to_bits)).collect(),
        value: bits(&f.value),
        prefixes: f.prefixes.iter().map(|p| p.map(f32::to_bits)).collect(),
    }
}

/// The report's settings: its controller, count dilation 1, the neighbour prior and the
/// reprojected depth on.
fn settings() -> AdaptiveSettings {
    AdaptiveSettings {
        config: SpvgConfig::builder()
            .target_variance(1e-4)
            .build()
            .expect("the report's controller"),
        dilation: 1,
        ..AdaptiveSettings::default()
    }
}

/// The GPU run of `scene` in `mode` with the report's settings and prefix ladder.
fn gpu_run(dev: &GpuDevice, scene: AoScene, mode: AoMode) -> Vec<Frame> {
    let mut pass = AoPass::new(
        &dev.device,
        &dev.queue,
        scene.width,
        scene.height,
        mode,
        settings(),
    )
    .expect("renderer");
    pass.set_prefix_counts(PREFIXES);
    (0..FRAMES)
        .map(|t| {
            let f = pass.run_frame(&scene.params(t)).expect("gpu frame");
            let history = match pass.adaptive() {
                Some(a) => read_texture(&dev.device, &dev.queue, a.history_texture())
                    .expect("history readback"),
                None => Vec::new(),
            };
            frame(f, history)
        })
        .collect()
}

fn twin_run(scene: AoScene, mode: AoMode) -> Vec<Frame> {
    let mut twin = AoTwin::new(scene.width, scene.height, mode, settings()).expect("twin");
    twin.set_prefix_counts(PREFIXES);
    (0..FRAMES)
        .map(|t| {
            let f = twin.run_frame(&scene.params(t)).expect("twin frame");
            let history = twin
                .adaptive()
                .map_or_else(Vec::new, |a| a.history().to_vec());
            frame(f, history)
        })
        .collect()
}

/// Busy-loop threads, one per core, until dropped.
struct Load {
    stop: Arc<AtomicBool>,
    threads: Vec<std::thread::JoinHandle<u64>>,
}

impl Load {
    fn start() -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let cores = std::thread::available_parallelism().map_or(1, usize::from);
        let threads = (0..cores)
            .map(|k| {
                let stop = Arc::clone(&stop);
                std::thread::spawn(move || {
                    let mut x = k as u64;
                    while !stop.load(Ordering::Relaxed) {
                        for _ in 0..1000 {
                            x = std::hint::black_box(x.wrapping_mul(6_364_136_223_846_793_005) + 1);
                        }
                    }
                    x
                })
            })
            .collect();
        Self { stop, threads }
    }
}

impl Drop for Load {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

/// The first difference between two runs of one scene, naming the frame, the quantity,
/// the pixel and its SIMD lane, and how many pixels of that frame differ.
fn first_difference(a: &[Frame], b: &[Frame], width: u32) -> Option<String> {
    for (t, (x, y)) in a.iter().zip(b).enumerate() {
        if x == y {
            continue;
        }
        let parts: [(&str, Vec<bool>); 4] = [
            (
                "count",
                x.count.iter().zip(&y.count).map(|(p, q)| p != q).collect(),
            ),
            (
                "history",
                x.history
                    .iter()
                    .zip(&y.history)
                    .map(|(p, q)| p != q)
                    .collect(),
            ),
            (
                "value",
                x.value.iter().zip(&y.value).map(|(p, q)| p != q).collect(),
            ),
            (
                "prefix",
                x.prefixes
                    .iter()
                    .zip(&y.prefixes)
                    .map(|(p, q)| p != q)
                    .collect(),
            ),
        ];
        for (what, differs) in parts {
            let bad: Vec<usize> = differs
                .iter()
                .enumerate()
                .filter_map(|(i, &d)| d.then_some(i))
                .collect();
            if let Some(&i) = bad.first() {
                let (px, py) = (i as u32 % width, i as u32 / width);
                let mut lanes = [0_usize; 8];
                for &j in &bad {
                    lanes[j % width as usize % 8] += 1;
                }
                return Some(format!(
                    "frame {t}: {what} differs at {} pixels, first ({px}, {py}); by x mod 8: \
                     {lanes:?}",
                    bad.len()
                ));
            }
        }
        return Some(format!("frame {t}: the frames differ in length"));
    }
    (a.len() != b.len()).then(|| format!("{} against {} frames", a.len(), b.len()))
}

#[test]
fn moving_scenes_render_the_same_frames_on_every_run_and_equal_the_twin() {
    let Some(dev) = GpuTest::new("moving_scenes_render_the_same_frames_on_every_run").device()
    else {
        return;
    };
    let scenes = [
        // Half the report's pan8 frame each way (still 24x12 tiles of 8x8, the pan
        // crossing the frame): CI runs this test on lavapipe and again on SwiftShader,
        // where the full 384x192 frame took a quarter of an hour of the CI budget.
        (Motion::Pan { speed: 4.0 }, [192, 96]),
        (Motion::MovingSphere { speed: 3.0 }, [128, 96]),
        (Motion::Dolly { rate: 3.0 }, [128, 96]),
    ];
    let mut failures = Vec::new();
    for (motion, [width, height]) in scenes {
        let scene = AoScene {
            width,
            height,
            motion,
        };
        for mode in [AoMode::Fixed(64), AoMode::Adaptive] {
            let name = format!("{} {}", motion.name(), mode.name());
            let idle = gpu_run(&dev, scene, mode);
            let loaded = {
                let _load = Load::start();
                gpu_run(&dev, scene, mode)
            };
            let twin = twin_run(scene, mode);
            for (what, other) in [("the loaded GPU run", &loaded), ("the twin", &twin)] {
                match first_difference(&idle, other, width) {
                    Some(d) => failures.push(format!("{name}: GPU against {what}: {d}")),
                    None => eprintln!("{name}: GPU equals {what} on all {FRAMES} frames"),
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

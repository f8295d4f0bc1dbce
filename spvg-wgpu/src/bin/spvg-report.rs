//! `spvg-report`: runs every scene with every model and a sweep of target variance and
//! kappa, and writes a table (stdout and `report.md`), per-frame CSV, images and plots.
//!
//! Usage: `spvg-report [--width 128] [--height 96] [--frames 96]
//! [--backend auto|gpu|cpu] [--out out] [--material skin1|marble] [--image-frame 60]
//! [--no-sweep] [--gradient] [--afis]`
//!
//! `--gradient` gives the lights a smooth spatial variation ([`Lighting::Gradient`]);
//! the default is SPEC 7's constant lighting with shadow edges. `--afis` reads the
//! lighting through the mip chain (filtered sampling); references stay unfiltered.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;

use spvg::burley::MaterialPreset;
use spvg::burley::presets::{MARBLE, SKIN1};
use spvg_wgpu::evaluate::{FrameRecord, ReferenceCache, RunSpec, RunSummary, run_scene};
use spvg_wgpu::plot;
use spvg_wgpu::reference::Quadrature;
use spvg_wgpu::scene::{Lighting, Scene, SceneKind};
use spvg_wgpu::{Backend, BackendChoice, Model, PassConfig};

struct Args {
    width: u32,
    height: u32,
    frames: u32,
    backend: BackendChoice,
    out: PathBuf,
    material: MaterialPreset,
    image_frame: u32,
    sweep: bool,
    lighting: Lighting,
    afis: bool,
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        width: 128,
        height: 96,
        frames: 96,
        backend: BackendChoice::Auto,
        out: PathBuf::from("out"),
        material: SKIN1,
        image_frame: 63,
        sweep: true,
        lighting: Lighting::Constant,
        afis: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        if flag == "--no-sweep" {
            a.sweep = false;
            continue;
        }
        if flag == "--afis" {
            a.afis = true;
            continue;
        }
        if flag == "--gradient" {
            a.lighting = Lighting::Gradient;
            continue;
        }
        if flag == "--help" || flag == "-h" {
            return Err("usage: spvg-report [--width N] [--height N] [--frames N] [--backend auto|gpu|cpu] [--out DIR] [--material skin1|marble] [--image-frame N] [--no-sweep] [--gradient] [--afis]".into());
        }
        let value = it.next().ok_or(format!("{flag} needs a value"))?;
        let num = |v: &str| v.parse::<u32>().map_err(|e| format!("{flag} {v}: {e}"));
        match flag.as_str() {
            "--width" => a.width = num(&value)?,
            "--height" => a.height = num(&value)?,
            "--frames" => a.frames = num(&value)?,
            "--image-frame" => a.image_frame = num(&value)?,
            "--backend" => a.backend = value.parse()?,
            "--out" => a.out = PathBuf::from(value),
            "--material" => {
                a.material = match value.as_str() {
                    "skin1" => SKIN1,
                    "marble" => MARBLE,
                    _ => return Err(format!("unknown material {value}")),
                }
            }
            _ => return Err(format!("unknown flag {flag}")),
        }
    }
    if a.width == 0 || a.height == 0 || a.frames == 0 {
        return Err("width, height and frames must be positive".into());
    }
    Ok(a)
}

fn specs(sweep: bool, afis: bool) -> Vec<RunSpec> {
    let base = PassConfig {
        afis,
        ..PassConfig::default()
    };
    let mut v: Vec<RunSpec> = [8, 16, 32, 64]
        .into_iter()
        .map(|n| RunSpec {
            model: Model::Fixed(n),
            cfg: base,
            label: format!("fixed{n}"),
        })
        .collect();
    for model in [Model::As, Model::Ccv, Model::Ocv] {
        v.push(RunSpec {
            model,
            cfg: base,
            label: model.name(),
        });
    }
    if sweep {
        for model in [Model::As, Model::Ccv, Model::Ocv] {
            for sigma0_sq in [1e-3_f32, 1e-5, 1e-6] {
                v.push(RunSpec {
                    model,
                    cfg: PassConfig { sigma0_sq, ..base },
                    label: format!("{} s0^2={sigma0_sq:e}", model.name()),
                });
            }
            for kappa in [0.0_f32, 1.0] {
                v.push(RunSpec {
                    model,
                    cfg: PassConfig { kappa, ..base },
                    label: format!("{} kappa={kappa}", model.name()),
                });
            }
        }
    }
    v
}

fn row(s: &RunSummary) -> String {
    format!(
        "| {} | {} | {:.1} | {:.1} | {:.3} | {:.3} | {:.3} | {:.2} | {:.2} | {:.2} | {:.2} | {} |",
        s.scene,
        s.label,
        s.mean_spp,
        s.worst_spp,
        s.p50_ms,
        s.p95_ms,
        s.max_ms,
        s.mean_psnr,
        s.worst_psnr,
        s.mean_psnr_acc,
        s.worst_psnr_acc,
        s.history_bytes
    )
}

const HEADER: &str = "| scene | config | mean spp | worst-frame spp | p50 ms | p95 ms | max ms | mean PSNR | worst PSNR | mean PSNR acc | worst PSNR acc | history B/px |\n|---|---|---|---|---|---|---|---|---|---|---|---|";

fn find<'a>(all: &'a [RunSummary], scene: &str, label: &str) -> Option<&'a RunSummary> {
    all.iter().find(|s| s.scene == scene && s.label == label)
}

/// Why the acceptance criteria come out as they do (written into report.md).
const NOTES: &str = "## Notes on the criteria\n\n\
- A per-pixel variance target makes each pixel's error about `sigma0^2` (or less where the \
budget floor of 8 samples already reaches it); a fixed count of 64 gives `sigma1^2 / 64`. At \
the default `sigma0^2 = 1e-4` the target is looser than the fixed-64 noise of these scenes \
(MSE about 1.2e-5, 49 dB), so adaptive runs sit 5 dB below fixed64 at a quarter of its \
samples: the static criterion (within 1 dB at half the samples) needs a target near the \
fixed-64 noise level; see the `s0^2=1e-6` lines above.\n\
- Under flashing light AS is pinned at the 64-sample budget (its monitored variance is \
mostly temporal), so its PSNR is fixed64's; CCV/OCV allocate by the residual and sit at \
their static-scene quality, which again depends on `sigma0^2`: the flash criterion holds at \
`1e-5` and `1e-6`, not at `1e-4` or `1e-3`.\n\
- Switch: AS spikes to the 64 budget when the light goes off; CCV/OCV do not. At \
`sigma0^2 = 1e-6` their steady state alone is above 32 spp, so the worst frame is no longer \
under half of the (clamped) AS spike.\n\
- The accumulated PSNR (EMA 0.2 of the result) lags lighting that changes every frame, so it \
is low on flash and switch for every model; it measures the resolve, not the sampler.\n\
- The zero-sample rule (`eps_u`) is never triggered in these scenes (the distant ratio at \
500 mm is about 0.85); `tests/zero_sample.rs` exercises it.\n\
- With `--gradient` (smooth light variation everywhere) the same picture holds; a pore-scale \
lighting texture spreads variance over every pixel, where a variance target cannot beat a \
fixed count in MSE at all.\n";

/// The swept settings as label suffixes ("" = defaults).
const SETTINGS: [&str; 6] = [
    "",
    " s0^2=1e-3",
    " s0^2=1e-5",
    " s0^2=1e-6",
    " kappa=0",
    " kappa=1",
];

fn verdict(ok: bool) -> &'static str {
    if ok { "PASS" } else { "FAIL" }
}

/// The three acceptance criteria, at the defaults and at every swept setting (each model
/// compared with AS or fixed64 at the same setting).
fn acceptance(all: &[RunSummary]) -> String {
    let mut o = String::new();
    let get = |sc: &str, l: String| find(all, sc, &l);
    for set in SETTINGS {
        let name = if set.is_empty() {
            "defaults"
        } else {
            set.trim()
        };
        let mut lines = String::new();
        if let Some(a) = get("flash", format!("as{set}")) {
            for m in ["ccv", "ocv"] {
                if let Some(c) = get("flash", format!("{m}{set}")) {
                    let ratio = a.mean_spp / c.mean_spp.max(1e-9);
                    let loss = a.mean_psnr - c.mean_psnr;
                    let _ = writeln!(
                        lines,
                        "  - flash {m}: {ratio:.2}x fewer mean spp than AS ({:.1} vs {:.1}, need >= 2x), PSNR loss {loss:.2} dB ({:.2} vs {:.2}, need <= 2): {}",
                        c.mean_spp,
                        a.mean_spp,
                        c.mean_psnr,
                        a.mean_psnr,
                        verdict(ratio >= 2.0 && loss <= 2.0)
                    );
                }
            }
        }
        if let Some(a) = get("switch", format!("as{set}")) {
            for m in ["ccv", "ocv"] {
                if let Some(c) = get("switch", format!("{m}{set}")) {
                    let _ = writeln!(
                        lines,
                        "  - switch {m}: worst-frame spp {:.1} vs AS {:.1} (need <= half): {}",
                        c.worst_spp,
                        a.worst_spp,
                        verdict(c.worst_spp <= 0.5 * a.worst_spp)
                    );
                }
            }
        }
        if let (Some(a), Some(f)) = (
            get("static", format!("as{set}")),
            get("static", "fixed64".into()),
        ) {
            let d = f.mean_psnr - a.mean_psnr;
            let _ = writeln!(
                lines,
                "  - static as: {:.2} dB vs fixed64 {:.2} dB (gap {d:.2}, need <= 1) with {:.1} vs {:.1} spp (need <= half): {}",
                a.mean_psnr,
                f.mean_psnr,
                a.mean_spp,
                f.mean_spp,
                verdict(d <= 1.0 && a.mean_spp <= 0.5 * f.mean_spp)
            );
        }
        if !lines.is_empty() {
            let _ = writeln!(o, "- {name}:\n{lines}");
        }
    }
    o
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args = parse_args()?;
    std::fs::create_dir_all(&args.out)?;
    let backend = Backend::resolve(args.backend)?;
    let started = std::time::Instant::now();
    eprintln!("backend: {}", backend.describe());
    let specs = specs(args.sweep, args.afis);
    let total = specs.len() * SceneKind::ALL.len();
    let mut done = 0;
    let mut summaries = Vec::new();
    let mut csv = String::from("scene,config,frame,spp,time_ms,psnr,psnr_acc\n");
    let image_frame = args.image_frame.min(args.frames - 1);
    for kind in SceneKind::ALL {
        let scene = Scene {
            lighting: args.lighting,
            ..Scene::new(kind, args.width, args.height)
        };
        let mut refs = ReferenceCache::new(
            scene,
            args.material,
            PassConfig::default(),
            Quadrature::default(),
        );
        let mut per_frame: Vec<(String, Vec<FrameRecord>)> = Vec::new();
        for spec in &specs {
            eprint!(
                "\r[{done:>3}/{total}] {:>9} {:<22} {:>5.0}s ",
                kind.name(),
                spec.label,
                started.elapsed().as_secs_f64()
            );
            let _ = std::io::stderr().flush();
            let default_run = !spec.label.contains(' ');
            let out_dir = args.out.clone();
            let label = spec.label.clone();
            let (records, summary) = run_scene(
                &backend,
                scene,
                &args.material,
                spec,
                args.frames,
                &mut refs,
                |t, out, reference, mask| {
                    if t == image_frame && default_run {
                        let stem = format!("{}_{}_f{t}", kind.name(), label);
                        if let Err(e) = plot::write_frame_images(
                            &out_dir,
                            &stem,
                            scene.width,
                            scene.height,
                            out,
                            reference,
                            mask,
                        ) {
                            eprintln!("\nwarning: images for {stem}: {e}");
                        }
                    }
                },
            )?;
            for r in &records {
                let _ = writeln!(
                    csv,
                    "{},{},{},{:.4},{:.4},{:.3},{:.3}",
                    kind.name(),
                    spec.label,
                    r.frame,
                    r.spp,
                    r.time_ms,
                    r.psnr,
                    r.psnr_acc
                );
            }
            if default_run {
                per_frame.push((spec.label.clone(), records));
            }
            summaries.push(summary);
            done += 1;
        }
        plot::write_series_plots(&args.out, kind.name(), &per_frame)?;
    }
    eprintln!(
        "\r[{done}/{total}] done in {:.1}s{:30}",
        started.elapsed().as_secs_f64(),
        ""
    );
    plot::write_pareto(&args.out, &summaries)?;

    let mut md = String::new();
    let _ = writeln!(md, "# spvg-wgpu report\n");
    let _ = writeln!(
        md,
        "- backend: {}\n- resolution {}x{}, {} frames per run at 60 fps, material {}, lighting {:?}, AFIS {}\n- metrics over subsurface pixels; PSNR of luminance, peak 1, against a 64x64-node quadrature reference (good to ~5e-4 rmse, see reference.rs); accumulated = EMA weight 0.2 of the result, reset where history is invalid (it lags changing lighting, hence low values on flash/switch); pass time excludes frame 0 (shader JIT)\n- defaults: eta 0.2, sigma0^2 1e-4, kappa 0.2, budget [8, 64], eps_u 0.01\n- total wall time {:.1} s\n",
        backend.describe(),
        args.width,
        args.height,
        args.frames,
        args.material.name,
        args.lighting,
        if args.afis {
            "on (mip chain)"
        } else {
            "off (mip 0)"
        },
        started.elapsed().as_secs_f64()
    );
    let _ = writeln!(md, "## Acceptance\n\n{}", acceptance(&summaries));
    let _ = writeln!(md, "## Results\n\n{HEADER}");
    for s in &summaries {
        let _ = writeln!(md, "{}", row(s));
    }
    let _ = writeln!(md, "\n{NOTES}\n{}", plot::PLOT_NOTES);
    std::fs::write(args.out.join("report.md"), &md)?;
    std::fs::write(args.out.join("frames.csv"), &csv)?;
    println!("{HEADER}");
    for s in &summaries {
        println!("{}", row(s));
    }
    println!("\n{}", acceptance(&summaries));
    println!("wrote {}", args.out.join("report.md").display());
    Ok(())
}

fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("spvg-report: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

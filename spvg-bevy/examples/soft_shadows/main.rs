//! Soft shadows from an area light with spvg's adaptive sample counts, in Bevy.
//!
//! A ground plane and four spheres, a camera orbiting them with Bevy's TAA, and a
//! user-written stochastic effect (`effect.rs` and `assets/shaders/soft_shadows.wesl`): per
//! pixel, spvg's count of shadow rays to a rectangular light.
//!
//! Headless (the default; what CI builds), it renders on a fixed time step and, after the
//! last frame, writes into the directory given as the first argument (default
//! `target/spvg-bevy-example`):
//!
//! - `scene.png`: the same view without the effect (a camera without it);
//! - `counts.png`: spvg's per-pixel counts of the last frame (black: 0, outside the mask;
//!   blue to red: `min_samples` to `max_samples`, log scale);
//! - `shadows.png`: the effect after Bevy's TAA.
//!
//! ```text
//! cargo run --example soft_shadows -- [out-dir] [frames]
//! ```
//!
//! With the `window` feature it opens a window instead (`window.rs`: an orbit camera,
//! toggles for adaptive or fixed counts and for the counts view, the mean count on screen):
//!
//! ```text
//! cargo run --example soft_shadows --features window
//! cargo run --example soft_shadows --features window -- --headless [out-dir] [frames]
//! ```

// Shared with the headless tests, which use the parts this example does not.
#[allow(dead_code, reason = "shared with the tests")]
mod effect;
#[allow(dead_code, reason = "shared with the tests")]
mod scene;
#[cfg(feature = "window")]
mod window;

use std::path::{Path, PathBuf};

use bevy::prelude::*;
use scene::{Compilation, add_capture, app, camera_pose, set_targets, shadows, spawn_camera};
use spvg_bevy::spvg::{self, SpvgConfig};
use spvg_bevy::{AdaptiveSampling, AdaptiveSettings, SpvgStatus};

const SIZE: [u32; 2] = [320, 200];

/// The example's controller: target variance, 2 to 64 samples.
fn config() -> Result<SpvgConfig<f32>, spvg::Error> {
    SpvgConfig::<f32>::builder()
        .target_variance(2e-3)
        .min_samples(2)
        .max_samples(64)
        .build()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let headless = args.iter().position(|a| a == "--headless");
    #[cfg(feature = "window")]
    if headless.is_none() {
        return window::run(config()?);
    }
    if let Some(k) = headless {
        args.remove(k);
    }
    let mut args = args.into_iter();
    let out = PathBuf::from(
        args.next()
            .unwrap_or_else(|| "target/spvg-bevy-example".into()),
    );
    let frames: usize = args.next().map_or(Ok(32), |s| s.parse())?;
    headless_run(&out, frames)
}

fn headless_run(out: &Path, frames: usize) -> Result<(), Box<dyn std::error::Error>> {
    let config = config()?;
    // Synchronous compilation and a warm-up: the figures below are the same on every run.
    let mut app = app(Compilation::Synchronous, true);
    let captures = add_capture(&mut app);
    app.finish();
    app.cleanup();
    scene::spawn_scene(app.world_mut(), true);
    scene::warm_up(&mut app, &captures, SIZE)?;
    let world = app.world_mut();
    let adaptive = AdaptiveSampling::with_settings(AdaptiveSettings {
        config,
        dilation: 1,
        ..AdaptiveSettings::default()
    });
    let (effect, h_effect) = spawn_camera(world, SIZE, Some(shadows(0)), Some(adaptive));
    let (plain, h_plain) = spawn_camera(world, SIZE, None, None);
    set_targets(&mut app, vec![h_effect, h_plain]);
    for t in 0..frames {
        for e in [effect, plain] {
            if let Some(mut pose) = app.world_mut().get_mut::<Transform>(e) {
                *pose = camera_pose(t as f32);
            }
        }
        app.update();
    }
    let status = app.world().get::<SpvgStatus>(effect).cloned();
    if status != Some(SpvgStatus::Running) {
        return Err(format!("spvg is not running on the camera: {status:?}").into());
    }
    let last = captures
        .last()
        .ok_or("no frame was captured (no GPU adapter?)")?;
    let view = last.view(effect).ok_or("no spvg data for the camera")?;
    std::fs::create_dir_all(out)?;
    let rgb = |img: &[[f32; 4]]| -> Vec<u8> {
        img.iter()
            .flat_map(|p| [p[0], p[1], p[2]].map(srgb8))
            .collect()
    };
    write_png(&out.join("shadows.png"), SIZE, &rgb(&last.images[0]))?;
    write_png(&out.join("scene.png"), SIZE, &rgb(&last.images[1]))?;
    let (lo, hi) = (config.min_samples() as f32, config.max_samples() as f32);
    let counts: Vec<u8> = view
        .count
        .iter()
        .flat_map(|&c| {
            if c == 0 {
                return [0, 0, 0];
            }
            // log scale, blue (min) to red (max), as the effect's counts view
            let t = ((c as f32).ln() - lo.ln()) / (hi.ln() - lo.ln()).max(1e-6);
            let t = t.clamp(0.0, 1.0);
            [
                (255.0 * t) as u8,
                (77.0 * (1.0 - (2.0 * t - 1.0).abs())) as u8,
                (255.0 * (1.0 - t)) as u8,
            ]
        })
        .collect();
    write_png(&out.join("counts.png"), SIZE, &counts)?;
    let covered = view.mask.iter().filter(|m| **m != 0).count().max(1);
    let mean = view.count.iter().map(|c| u64::from(*c)).sum::<u64>() as f64 / covered as f64;
    println!(
        "{frames} frames at {}x{}: mean {mean:.2} spp over the covered pixels of the last frame; \
         wrote scene.png, counts.png, shadows.png to {}",
        SIZE[0],
        SIZE[1],
        out.display()
    );
    Ok(())
}

/// Linear to 8-bit sRGB.
fn srgb8(x: f32) -> u8 {
    let x = x.clamp(0.0, 1.0);
    let s = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

fn write_png(path: &Path, size: [u32; 2], rgb: &[u8]) -> Result<(), Box<dyn std::error::Error>> {
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut encoder = png::Encoder::new(file, size[0], size[1]);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.write_header()?.write_image_data(rgb)?;
    Ok(())
}

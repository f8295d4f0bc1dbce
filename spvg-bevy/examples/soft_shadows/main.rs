//! Soft shadows from an area light with spvg's adaptive sample counts, in Bevy, headless.
//!
//! A ground plane and four spheres, a camera orbiting them with Bevy's TAA, and a
//! user-written stochastic effect (`effect.rs`, `effect.wgsl`): per pixel, `n` shadow rays
//! to a rectangular light, `n` read from spvg's count texture. After the last frame it
//! writes, into the directory given as the first argument (default
//! `target/spvg-bevy-example`):
//!
//! - `scene.png`: the same view without the effect (a camera without it);
//! - `counts.png`: spvg's per-pixel counts of the last frame (black: 0, outside the mask;
//!   blue to red: `min_samples` to `max_samples`);
//! - `shadows.png`: the effect after Bevy's TAA.
//!
//! ```text
//! cargo run --example soft_shadows -- [out-dir] [frames]
//! ```

// Shared with the headless test, which uses the parts this example does not.
#[allow(dead_code)]
mod effect;
#[allow(dead_code)]
mod scene;

use std::path::{Path, PathBuf};

use bevy::prelude::*;
use effect::SoftShadows;
use scene::{Targets, add_capture, app, camera_pose, spawn_camera, spawn_scene};
use spvg::SpvgConfig;
use spvg_bevy::{AdaptiveSampling, SpvgStatus};

const SIZE: [u32; 2] = [320, 200];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(
        args.next()
            .unwrap_or_else(|| "target/spvg-bevy-example".into()),
    );
    let frames: usize = args.next().map_or(Ok(32), |s| s.parse())?;
    let config = SpvgConfig::<f32>::builder()
        .target_variance(2e-3)
        .min_samples(2)
        .max_samples(64)
        .build()?;

    let mut app = app();
    let captures = add_capture(&mut app);
    app.finish();
    app.cleanup();
    let world = app.world_mut();
    spawn_scene(world, true);
    let adaptive = AdaptiveSampling {
        dilation: 1,
        ..AdaptiveSampling::new(config)
    };
    let (shadows, h_shadows) =
        spawn_camera(world, SIZE, Some(SoftShadows::Adaptive), Some(adaptive));
    let (plain, h_plain) = spawn_camera(world, SIZE, None, None);
    let targets = Targets(vec![h_shadows, h_plain]);
    app.insert_resource(targets.clone());
    app.sub_app_mut(bevy::render::RenderApp)
        .insert_resource(targets);
    for t in 0..frames {
        for e in [shadows, plain] {
            if let Some(mut pose) = app.world_mut().get_mut::<Transform>(e) {
                *pose = camera_pose(t as f32);
            }
        }
        app.update();
    }
    let status = app.world().get::<SpvgStatus>(shadows).cloned();
    if status != Some(SpvgStatus::Running) {
        return Err(format!("spvg is not running on the camera: {status:?}").into());
    }
    let last = captures
        .0
        .lock()
        .map_err(|_| "capture lock poisoned")?
        .last()
        .cloned()
        .ok_or("no frame was captured (no GPU adapter?)")?;
    std::fs::create_dir_all(&out)?;
    let rgb = |img: &[[f32; 4]]| -> Vec<u8> {
        img.iter()
            .flat_map(|p| [p[0], p[1], p[2]].map(srgb8))
            .collect()
    };
    write_png(&out.join("shadows.png"), SIZE, &rgb(&last.images[0]))?;
    write_png(&out.join("scene.png"), SIZE, &rgb(&last.images[1]))?;
    let (lo, hi) = (config.min_samples() as f32, config.max_samples() as f32);
    let counts: Vec<u8> = last
        .count
        .iter()
        .flat_map(|&c| {
            if c == 0 {
                return [0, 0, 0];
            }
            // log scale, blue (min) to red (max)
            let t = ((c as f32).ln() - lo.ln()) / (hi.ln() - lo.ln()).max(1e-6);
            let t = t.clamp(0.0, 1.0);
            [
                (255.0 * t) as u8,
                (80.0 * (1.0 - (2.0 * t - 1.0).abs())) as u8,
                (255.0 * (1.0 - t)) as u8,
            ]
        })
        .collect();
    write_png(&out.join("counts.png"), SIZE, &counts)?;
    let covered = last.mask.iter().filter(|m| **m != 0).count().max(1);
    let mean = last.count.iter().map(|c| u64::from(*c)).sum::<u64>() as f64 / covered as f64;
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

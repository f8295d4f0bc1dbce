//! Route 2 of docs/integrating.md: a renderer's own adaptive pass, written with plain wgpu,
//! that runs spvg's rules from the spvg-shaders library (`spvg_shaders::WGSL`) instead of
//! recording `AdaptivePass`, with the component's default rules and a count dilation of
//! radius 1. The pass (`pass.rs`, `pass.wgsl`) records four dispatches per frame:
//! estimate, dilation with the neighbour prior, the renderer's sampling, and the update
//! with the spatial moments of young histories. This prints how the counts follow a
//! panning camera and a moving disc; `tests/route2.rs` checks that its counts, links and
//! histories equal the component's.
//!
//! ```text
//! cargo run -p spvg-wgpu --example route2
//! ```

mod pass;
mod scene;

use pass::{Inputs, Route2Pass};
use scene::Scene;
use spvg::SpvgConfig;
use spvg::reproject::Reprojection;
use spvg_wgpu::util::{acquire_device, read_texture};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let gpu = acquire_device()?;
    let (device, queue) = (&gpu.device, &gpu.queue);
    let info = &gpu.info;
    println!(
        "route 2 on {} [{:?}, {:?}]",
        info.name, info.device_type, info.backend
    );
    // The published controller with the core's defaults (the spatial variance of young
    // histories on), the default reprojection rule, count dilation 1 (and with it the
    // neighbour prior): AdaptiveSettings { dilation: 1, ..AdaptiveSettings::default() }.
    let config = SpvgConfig::published();
    let scene = Scene {
        width: 96,
        height: 48,
    };
    let mut pass = Route2Pass::new(device, &config, scene.width, scene.height)?;
    pass.set_reprojection(&Reprojection::default());
    pass.set_count_dilation(1);
    let mut previous = None;
    for t in 0..12 {
        let frame = scene.frame(t);
        let textures = scene.upload(device, queue, &frame);
        let [motion, depth, radiance] = &textures;
        let previous_depth = previous
            .as_ref()
            .map_or(depth, |p: &[wgpu::Texture; 3]| &p[1]);
        let mut encoder = device.create_command_encoder(&Default::default());
        pass.record(
            device,
            queue,
            &mut encoder,
            &Inputs {
                motion,
                depth,
                previous_depth,
                radiance,
            },
        );
        queue.submit([encoder.finish()]);
        let counts: Vec<u32> = read_texture(device, queue, pass.count_texture())?;
        let total: u64 = counts.iter().map(|&n| u64::from(n)).sum();
        let at = |n: u32| counts.iter().filter(|&&c| c == n).count();
        println!(
            "frame {t:2}: {:5.1} spp, {:4} pixels at beta_min, {:4} at beta_max",
            total as f64 / counts.len() as f64,
            at(config.min_samples()),
            at(config.max_samples()),
        );
        previous = Some(textures);
    }
    Ok(())
}

//! Route 2 of docs/integrating.md: a renderer's own single compute pass, written with plain
//! wgpu, that runs spvg's rules from the spvg-shaders library (`spvg_shaders::WGSL`)
//! instead of recording `AdaptivePass`. The pass (`route2_pass/route2.wgsl`) locates each
//! pixel's history, estimates and dilates its count, takes that many samples and updates
//! the history; this prints how the counts follow a panning camera and a moving disc.
//! `tests/route2.rs` checks that its counts equal the component's.
//!
//! ```text
//! cargo run -p spvg-wgpu --example route2
//! ```

#[path = "route2_pass/mod.rs"]
mod route2_pass;

use route2_pass::{Inputs, Route2Pass, Scene};
use spvg::SpvgConfig;
use spvg_wgpu::util::read_texture;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (device, queue, name) = route2_pass::device()?;
    println!("route 2 on {name}");
    // One fused dispatch has no neighbourhood of this frame to give the spatial variance
    // of young histories (docs/integrating.md, route 2, step 5): off.
    let config = SpvgConfig::builder()
        .target_variance(1e-3)
        .kappa(0.5)
        .spatial_variance(0)
        .build()?;
    let scene = Scene {
        width: 96,
        height: 48,
    };
    let mut pass = Route2Pass::new(&device, &config, scene.width, scene.height)?;
    pass.set_count_dilation(1);
    let mut previous = None;
    for t in 0..12 {
        let frame = scene.frame(t);
        let textures = scene.upload(&device, &queue, &frame);
        let [motion, depth, radiance] = &textures;
        let previous_depth = previous
            .as_ref()
            .map_or(depth, |p: &[wgpu::Texture; 3]| &p[1]);
        let mut encoder = device.create_command_encoder(&Default::default());
        pass.record(
            &device,
            &queue,
            &mut encoder,
            &Inputs {
                motion,
                depth,
                previous_depth,
                radiance,
            },
        );
        queue.submit([encoder.finish()]);
        let counts: Vec<u32> = read_texture(&device, &queue, pass.count_texture())?;
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

//! Frame updates of 65,536 f16 pixels (the benches' inputs), for instruction counts under
//! callgrind and for comparing builds bit for bit.
//!
//! ```sh
//! cargo build --release --example frame_profile
//! valgrind --tool=callgrind --toggle-collect='*frame_profile::run*' \
//!     target/release/examples/frame_profile ocv
//! ```
//!
//! The instructions callgrind collects, over 65,536, are the instructions per pixel of
//! one frame update (the variant `texel::selected_loop_variant` names, printed first: AVX2
//! on a CPU with AVX2, FMA and F16C; `SPVG_MAX_LOOP_VARIANT=as-compiled` or `avx2` caps
//! it, to compare the variants' bits on one machine). Modes: `ocv`
//! (`update_frame_ocv`, f16 inputs), `as` (`update_frame` with AS), `ocv-sr` and `as-sr`
//! (stochastic rounding), `ocv-scalar` (the benches' per-pixel loop); an optional second
//! argument runs that many frames. The last line is a hash of every stored bit.

use spvg::cv::{As, Ocv, PixelController};
use spvg::texel::{
    CvTexel16, FrameInputs, Rounding, SpvgTexel16, TexelEncoding, update_frame, update_frame_ocv,
};
use spvg::{CvHistory, SpvgConfig, SpvgHistory};

const PIXELS: usize = 65_536;

fn main() -> Result<(), spvg::Error> {
    let mode = std::env::args().nth(1).unwrap_or_else(|| "ocv".into());
    let frames: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    // The benches' frame: about 2% disoccluded pixels.
    let mut frame = spvg::texel::FrameInputsBuf::with_capacity(PIXELS);
    for (pixel, count, valid) in spvg_fixtures::workload::frame(PIXELS) {
        frame.push(pixel, count, valid);
    }
    let config = SpvgConfig::<f32>::published();
    let enc = TexelEncoding::new(config.target_variance())?;
    let h0 = SpvgHistory {
        mean: 0.4,
        variance: 2e-4,
        mean_count: 24.0,
    };
    let j0 = CvHistory {
        cov_fg: 1e-3,
        var_g: 8e-4,
        mean_f: 0.5,
        mean_g: 0.4,
    };
    let mut h = vec![enc.encode::<SpvgTexel16>(&h0, Rounding::Nearest); PIXELS];
    let mut j = vec![enc.encode::<CvTexel16>(&j0, Rounding::Nearest); PIXELS];
    for _ in 0..frames {
        run(&mode, &config, &enc, &frame.inputs(), &mut h, &mut j)?;
    }
    // FNV-1a over every stored bit.
    let bits = h.iter().map(|t| t.0).chain(j.iter().map(|t| t.0)).flatten();
    let hash = bits.fold(0xcbf2_9ce4_8422_2325_u64, |a, v| {
        (a ^ u64::from(v.to_bits())).wrapping_mul(0x100_0000_01b3)
    });
    println!("loop variant: {}", spvg::texel::selected_loop_variant());
    println!("{mode}: bits {hash:016x}");
    Ok(())
}

/// One frame update in `mode`: the function callgrind collects in.
#[inline(never)]
fn run(
    mode: &str,
    config: &SpvgConfig<f32>,
    enc: &TexelEncoding,
    inputs: &FrameInputs<'_>,
    h: &mut [SpvgTexel16],
    j: &mut [CvTexel16],
) -> Result<(), spvg::Error> {
    let rounding = if mode.ends_with("-sr") {
        Rounding::Stochastic(7)
    } else {
        Rounding::Nearest
    };
    // f16 CV texels take the model with f16 inputs, as in the benches.
    let ocv = PixelController::new(*config, Ocv::with_weight(0.05)?.with_f16_inputs(true));
    match mode {
        "ocv" | "ocv-sr" => update_frame_ocv(&ocv, enc, rounding, inputs, h, j),
        "as" | "as-sr" => {
            update_frame(&PixelController::new(*config, As), enc, rounding, inputs, h)
        }
        "ocv-scalar" => {
            // The benches' scalar loop: decode, the per-pixel controller, encode.
            spvg_fixtures::workload::scalar_frame_ocv(&ocv, enc, inputs, h, j);
            Ok(())
        }
        _ => Err(spvg::Error::InconsistentParameters {
            names: "mode",
            expected: "ocv, ocv-sr, as, as-sr or ocv-scalar",
        }),
    }
}

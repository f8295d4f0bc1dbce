//! The page natively: its WGSL validated by naga (no GPU needed), and on a device with
//! WebGPU's default limits (`wgpu::Limits::default()`, what a browser grants) its passes
//! run and its browser check passes: every frame of the scripted path equal to the
//! component's twin (G-buffer, counts and history texels bit for bit), the same async
//! code the page runs, polled here on the native device.

use spvg_gpu_test::GpuTest;
use spvg_web::check::{EQUAL_QUALITY_COUNTS, TwinCheck, run_check};
use spvg_web::metrics::EqualQuality;
use spvg_web::renderer::{BUDGET, Mode, Reads, Renderer, TARGET_VARIANCE, page_settings};
use spvg_web::scene::{View, check_view, params};
use spvg_wgpu::util::block_on;

#[test]
fn wgsl_validates_without_a_gpu() {
    let source = spvg_web::renderer::shader_source();
    let module = naga::front::wgsl::parse_str(&source).expect("the page's WGSL parses");
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .expect("the page's WGSL validates");
    for entry in [
        "web_gbuffer",
        "web_sample",
        "web_taa",
        "web_reference",
        "web_compose",
    ] {
        assert!(
            module.entry_points.iter().any(|e| e.name == entry),
            "entry point {entry}"
        );
    }
}

fn device(name: &str) -> Option<spvg_gpu_test::GpuDevice> {
    GpuTest::new(name).limits(wgpu::Limits::default()).device()
}

#[test]
fn browser_check_passes_under_webgpu_default_limits() {
    let Some(dev) = device("browser_check_passes_under_webgpu_default_limits") else {
        return;
    };
    let settings = page_settings(TARGET_VARIANCE, BUDGET).expect("the page's settings");
    // Not multiples of the 8x8 workgroup.
    let mut r = Renderer::new(&dev.device, &dev.queue, [84, 60], Mode::Adaptive, settings)
        .expect("renderer");
    let mut shown = 0;
    let report = block_on(run_check(&mut r, None, 15, 4, |_, f| {
        assert_eq!(f.image.len(), 3 * 84 * 60 * 4, "the panels are read back");
        shown += 1;
    }))
    .expect("check");
    eprintln!("{}", report.line());
    assert!(report.passed(), "{}", report.line());
    assert_eq!(report.equal, 15, "{}", report.line());
    assert_eq!(
        shown,
        15 + 4 * (EQUAL_QUALITY_COUNTS.len() + 1),
        "every frame shown"
    );
    // The check did compare something: adaptive counts above the minimum, AO values
    // on the lattice, a resolved image close to the reference.
    assert!(
        report.spp > f64::from(BUDGET[0]) + 0.5 && report.spp < f64::from(BUDGET[1]),
        "mean spp {} inside the budget and above its minimum",
        report.spp
    );
    assert!(
        report.ao_equal.1 >= 15 * 60 * 10,
        "lattice {:?}",
        report.ao_equal
    );
    assert!(report.psnr_taa > 20.0, "psnr after TAA {}", report.psnr_taa);
    let q = report.equal_quality.as_ref().expect("measured");
    assert_eq!(q.fixed.len(), EQUAL_QUALITY_COUNTS.len(), "{q:?}");
    assert!(
        q.fixed.windows(2).all(|w| w[1].1 > w[0].1),
        "more samples, higher PSNR: {q:?}"
    );
    assert_ne!(q.equal, EqualQuality::Unknown, "{q:?}");
    assert!(line_parses(&report.line()), "{}", report.line());
}

/// The check can fail: a twin of another component (a target variance twice the GPU's)
/// is caught on the counts or the history texels, and the failure names the frame.
#[test]
fn a_twin_of_another_component_fails_the_check() {
    let Some(dev) = device("a_twin_of_another_component_fails_the_check") else {
        return;
    };
    let size = [48, 32];
    let settings = page_settings(TARGET_VARIANCE, BUDGET).expect("the page's settings");
    let other = page_settings(2.0 * TARGET_VARIANCE, BUDGET).expect("valid settings");
    let mut r =
        Renderer::new(&dev.device, &dev.queue, size, Mode::Adaptive, settings).expect("renderer");
    let mut twin = TwinCheck::new(other, size).expect("twin");
    let reads = Reads {
        image: false,
        taa: false,
        twin: true,
    };
    let mut differences = Vec::new();
    for t in 0..6 {
        let p = params(
            size[0],
            size[1],
            t,
            &check_view(t, 6),
            &check_view(t.saturating_sub(1), 6),
        );
        let f = block_on(r.render(&p, reads)).expect("frame");
        let c = twin
            .frame(&p, &f.count, f.twin.as_ref().expect("twin readback"))
            .expect("compared");
        differences.extend(c.difference);
    }
    assert!(
        differences
            .iter()
            .any(|d| d.starts_with("counts") || d.starts_with("history texels")),
        "{differences:?}"
    );
}

/// The line the script looks for.
fn line_parses(line: &str) -> bool {
    line.starts_with("SPVG-WEB PASS frames=15 twin_equal=15/15 spp=") && line.contains(" psnr_taa=")
}

/// A fixed count is that count on every pixel, the converged reference agrees with a
/// frame of many rays, and the error panel appears only for the reference's view.
#[test]
fn fixed_counts_and_the_reference() {
    let Some(dev) = device("fixed_counts_and_the_reference") else {
        return;
    };
    let settings = page_settings(TARGET_VARIANCE, BUDGET).expect("the page's settings");
    let size = [40, 24];
    let mut r =
        Renderer::new(&dev.device, &dev.queue, size, Mode::Fixed(5), settings).expect("renderer");
    let view = View::default();
    let p = params(size[0], size[1], 0, &view, &view);
    let reads = Reads {
        image: true,
        taa: true,
        twin: false,
    };
    let f = block_on(r.render(&p, reads)).expect("frame");
    assert!(f.count.iter().all(|&n| n == 5), "fixed 5 everywhere");
    let reference = block_on(r.converge_reference(&p, 4)).expect("reference");
    r.set_mode(Mode::Fixed(256));
    r.reset();
    let f = block_on(r.render(&p, reads)).expect("frame");
    let psnr = spvg_web::metrics::psnr(&f.taa, &reference);
    assert!(psnr > 30.0, "256 rays against 4 x 64: {psnr} dB");
    // The error panel (the third) is a heat colour for this view, and the dim checker
    // for another.
    let panel = |img: &[u8]| -> Vec<u8> {
        (0..size[1] as usize)
            .flat_map(|y| {
                let row = y * 3 * size[0] as usize * 4;
                img[row + 2 * size[0] as usize * 4..row + 3 * size[0] as usize * 4].to_vec()
            })
            .collect()
    };
    let is_checker = |px: &[u8]| px.chunks(4).all(|c| c[0] == c[1] && c[1] == c[2]);
    assert!(
        !is_checker(&panel(&f.image)),
        "an error heat map for the reference's view"
    );
    let moved = View {
        centre: [view.centre[0] + 3.0, view.centre[1]],
        ..view
    };
    let f = block_on(r.render(&params(size[0], size[1], 1, &moved, &view), reads)).expect("frame");
    assert!(
        is_checker(&panel(&f.image)),
        "no reference for another view"
    );
}

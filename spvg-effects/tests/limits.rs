//! Frame sizes beyond the device's limits are a typed error before any resource exists,
//! never a wgpu panic.

mod common;

use spvg_effects::sss::Model;
use spvg_effects::{Backend, PassError, check_frame_size};

#[test]
fn oversized_frames_are_typed_errors() {
    let Some(dev) = spvg_gpu_test::GpuTest::new("oversized_frames_are_typed_errors").device()
    else {
        return;
    };
    let side = dev.device.limits().max_texture_dimension_2d;
    assert!(
        check_frame_size(&dev.device, 64, 48).is_ok(),
        "a small frame fits"
    );
    assert!(
        check_frame_size(&dev.device, side, 1).is_ok(),
        "the largest side fits"
    );
    for (w, h) in [(side + 1, 8), (8, side + 1), (20_000, 20_000)] {
        match check_frame_size(&dev.device, w, h) {
            Err(PassError::FrameTooLarge {
                width,
                height,
                limit,
                needed,
                allowed,
            }) => {
                assert_eq!((width, height), (w, h), "the error names the frame");
                assert_eq!(limit, "max_texture_dimension_2d", "the texture side limit");
                assert!(needed > allowed, "{needed} vs {allowed}");
            }
            other => panic!("{w}x{h}: expected FrameTooLarge, got {other:?}"),
        }
    }
    // The backend refuses to build the pass instead of panicking inside wgpu.
    let backend = Backend::Gpu(Box::new(dev));
    assert!(
        matches!(
            backend.pass(Model::As, side + 1, 4),
            Err(PassError::FrameTooLarge { .. })
        ),
        "Backend::pass checks the frame first"
    );
}

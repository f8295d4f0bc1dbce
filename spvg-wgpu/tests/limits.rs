//! Frame sizes beyond the device's limits are a typed error before any resource exists,
//! never a wgpu panic.

mod common;

use spvg_wgpu::sss::Model;
use spvg_wgpu::{Backend, PassError};

#[test]
fn oversized_frames_are_typed_errors() {
    let Some(dev) = common::device("oversized_frames_are_typed_errors") else {
        return;
    };
    let side = dev.device.limits().max_texture_dimension_2d;
    assert!(dev.check_frame(64, 48).is_ok(), "a small frame fits");
    assert!(dev.check_frame(side, 1).is_ok(), "the largest side fits");
    for (w, h) in [(side + 1, 8), (8, side + 1), (20_000, 20_000)] {
        match dev.check_frame(w, h) {
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

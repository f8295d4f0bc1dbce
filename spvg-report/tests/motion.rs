//! The motion section's references: the shortcuts (one world strip for every pan and
//! their static camera, local recomputation around the moving sphere) against the direct
//! per-frame quadrature, and the quadrature against facts of the geometry.

use spvg_report::motion::{MotionOptions, reference, references};
use spvg_report::wgpu_api::{AoScene, Motion, ao_twin as twin};

fn small() -> MotionOptions {
    let mut o = MotionOptions::new().expect("valid options");
    o.frames = 4;
    o.grid = 6;
    o
}

#[test]
fn shortcuts_equal_the_direct_references() {
    let size = [40, 24];
    // At the pans' size the static camera is a window of their strip too.
    let opts = MotionOptions {
        pan_size: size,
        size,
        ..small()
    };
    for motion in [
        Motion::Static,
        Motion::Pan { speed: 1.0 },
        Motion::Pan { speed: 8.0 },
        Motion::MovingSphere { speed: 3.0 },
        Motion::MovingObjects { speed: 5.0 },
    ] {
        let fast = references(&opts, size, motion);
        let scene = AoScene {
            width: size[0],
            height: size[1],
            motion,
        };
        for (t, got) in fast.iter().enumerate() {
            let want = reference(&scene.params(t as u32), opts.grid);
            assert_eq!(got, &want, "{} frame {t}", motion.name());
        }
    }
}

#[test]
fn quadrature_is_one_on_open_ground() {
    let scene = AoScene {
        width: 96,
        height: 64,
        motion: Motion::Static,
    };
    let p = scene.params(0);
    let r = reference(&p, 16);
    let g = twin::gbuffer(&p);
    assert!(r.iter().all(|v| (0.0..=1.0).contains(v)), "AO in [0, 1]");
    let open = r.iter().filter(|&&v| v == 1.0).count();
    let occluded = r.iter().filter(|&&v| v < 0.9).count();
    assert!(
        open > 500 && occluded > 50,
        "open {open}, occluded {occluded}"
    );
    // Flat ground is open exactly where no sphere rises within reach of its rays: a point
    // of the plane more than 16 px + radius from every nearby centre.
    for (gp, v) in g.iter().zip(&r) {
        let s = gp.surface.position;
        if s[2] != 0.0 {
            continue;
        }
        let far = (-2..=3)
            .flat_map(|i| (-2..=3).map(move |j| twin::cell_sphere(i, j)))
            .all(|c| (c[0] - s[0]).hypot(c[1] - s[1]) > c[3] + 16.5);
        if far {
            assert_eq!(*v, 1.0, "open ground at {s:?}");
        }
    }
}

#[test]
fn default_suite_scores_after_the_warm_up_and_full_scores_every_frame() {
    use spvg_report::motion::WARM_UP;
    let size = [24, 16];
    let default = MotionOptions {
        frames: 40,
        ..small()
    };
    let full = MotionOptions {
        full: true,
        ..default
    };
    let motion = Motion::Rotate { degrees: 2.0 };
    let empty = |refs: &[Vec<f32>]| refs.iter().filter(|r| r.is_empty()).count();
    let d = references(&default, size, motion);
    assert_eq!(d.len(), 40, "one reference slot per frame");
    assert_eq!(empty(&d), WARM_UP, "the warm-up is not scored by default");
    assert!(d[WARM_UP..].iter().all(|r| r.len() == 24 * 16));
    assert_eq!(
        empty(&references(&full, size, motion)),
        0,
        "--full scores every frame"
    );
}

//! The motion section's references: the shortcuts (one world strip for every pan and
//! their static camera, local recomputation around the moving objects, one reference per
//! view shared by the frames and runs that see it) against the direct per-frame
//! quadrature, and the quadrature against facts of the geometry.

use spvg_report::motion::reference::{ReferenceKey, shared_reference};
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
        Motion::Rotate { degrees: 2.0 },
    ] {
        let fast = references(&opts, size, motion);
        let scene = AoScene {
            width: size[0],
            height: size[1],
            motion,
        };
        assert!(!fast[0].is_empty(), "{} frame 0 is scored", motion.name());
        // (The rotation scores every 4th frame: its others are empty.)
        for (t, got) in fast.iter().enumerate().filter(|(_, r)| !r.is_empty()) {
            let want = reference(&scene.params(t as u32), opts.grid);
            assert_eq!(got, &want, "{} frame {t}", motion.name());
        }
    }
}

/// The dolly's heights come back every 26 frames: its later frames take the reference of
/// the earlier frame with the same view, and that equals their own direct quadrature.
#[test]
fn a_repeated_view_shares_its_reference() {
    let size = [40, 24];
    let opts = MotionOptions {
        size,
        frames: 30,
        full: true,
        ..small()
    };
    let dolly = Motion::Dolly { rate: 3.0 };
    let scene = AoScene {
        width: size[0],
        height: size[1],
        motion: dolly,
    };
    let fast = references(&opts, size, dolly);
    assert_eq!(fast.len(), 30, "every frame scored with --full");
    // Frames 0 and 26, 1 and 25 see the same view: one key, one reference.
    for (a, b) in [(0, 26), (1, 25), (4, 22)] {
        let (pa, pb) = (scene.params(a), scene.params(b));
        assert_eq!(
            ReferenceKey::of(&pa, opts.grid),
            ReferenceKey::of(&pb, opts.grid),
            "frames {a} and {b}"
        );
        assert_eq!(fast[a as usize], fast[b as usize], "frames {a} and {b}");
        assert_eq!(fast[b as usize], reference(&pb, opts.grid), "frame {b}");
    }
    // A static camera held at a frame's height and zoom (the dolly's baseline) sees what
    // the frame sees: the same key, and the shared reference is the frame's.
    let still = AoScene {
        motion: Motion::Static,
        ..scene
    };
    let mut held = still.params(7);
    let p = scene.params(12);
    (held.lens, held.previous_lens) = (p.lens, p.lens);
    assert_eq!(
        ReferenceKey::of(&held, opts.grid),
        ReferenceKey::of(&p, opts.grid)
    );
    assert_eq!(
        *shared_reference(&held, opts.grid),
        reference(&p, opts.grid)
    );
    // What the key leaves out does not move the reference; what it holds does.
    let mut moved = p;
    moved.frame += 5;
    moved.previous_camera[0] += 3.0;
    moved.mover_velocity = [1.0, 2.0, 0.0, 0.0];
    assert_eq!(reference(&moved, opts.grid), reference(&p, opts.grid));
    let mut other = p;
    other.lens[1] *= 1.25;
    assert_ne!(
        ReferenceKey::of(&other, opts.grid),
        ReferenceKey::of(&p, opts.grid)
    );
    assert_ne!(
        ReferenceKey::of(&p, opts.grid + 1),
        ReferenceKey::of(&p, opts.grid)
    );
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
    let empty = |refs: &[Vec<f32>]| refs.iter().filter(|r| r.is_empty()).count();
    let object = Motion::MovingSphere { speed: 3.0 };
    let d = references(&default, size, object);
    assert_eq!(d.len(), 40, "one reference slot per frame");
    assert_eq!(empty(&d), WARM_UP, "the warm-up is not scored by default");
    assert!(d[WARM_UP..].iter().all(|r| r.len() == 24 * 16));
    // The rotation's frames each need a reference of their own: the default scores the
    // frames whose poses its still baseline holds, every 4th after the warm-up.
    let rotate = Motion::Rotate { degrees: 2.0 };
    let r = references(&default, size, rotate);
    let scored: Vec<usize> = (0..40).filter(|&t| !r[t].is_empty()).collect();
    assert_eq!(scored, [16, 20, 24, 28, 32, 36]);
    for m in [object, rotate] {
        assert_eq!(
            empty(&references(&full, size, m)),
            0,
            "--full scores every frame of {}",
            m.name()
        );
    }
}

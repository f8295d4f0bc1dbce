//! The motion section: scenes with motion, run through the second consumer (ambient
//! occlusion) and the adaptive component: camera pans at up to 8 px per frame, a camera
//! rotation, a sphere moving across the surface, several objects (three spheres and a thin
//! bar) moving faster in different directions (disocclusion by motion), a dolly, and a
//! scanned mesh under an orbiting camera with sub-pixel jitter ([`mesh`]). Each
//! scene runs AS with reprojection and `fixed64` (whose ladder gives the fixed counts 16
//! and 32: the equal-quality figures), against a converged quadrature reference of its
//! own ([`reference()`]), each run measured also after a TAA resolve ([`crate::taa`]);
//! every GPU frame is held against the CPU twin ([`render`]).
//!
//! One concept per module, each importing only those listed before it: the options
//! ([`options`]), the results ([`data`], [`uncovered`]), the scenes and the ways of
//! running them ([`scenes`]), the references ([`mod@reference`]), the renderer and its
//! check against the twin ([`render`]), one scene's run ([`run`]), the baselines
//! ([`frames`]: which frames are scored and which poses held; [`poses`]: cameras held at a
//! moving camera's poses), the motion bound ([`bound`]), the acceptance lines ([`acceptance`]), the charts
//! ([`figures`]) and the markdown and CSV ([`mod@markdown`]). This file runs them in order.

pub mod acceptance;
pub mod bound;
pub mod data;
pub mod figures;
pub mod frames;
pub mod markdown;
pub mod mesh;
pub mod options;
pub mod poses;
pub mod reference;
pub mod render;
pub mod run;
pub mod scenes;
pub mod uncovered;

use std::fmt::Write as _;
use std::path::Path;

use crate::error::ReportError;
use crate::mesh::scene::{Mesh, MeshScene, ORBIT};
use crate::progress::Progress;
use crate::section::Section;
use crate::wgpu_api::{GpuDevice, Motion};

pub use data::{MotionBound, MotionReport, MotionRun, StillBaseline, TwinCheck, WARM_UP};
pub use options::MotionOptions;
pub use reference::{reference, references};
pub use scenes::{OBJECTS, Variant, others, pans, variants};
pub use uncovered::{AgeErrors, since_uncovered};

/// The scene groups: the pans with their static camera at `pan_size` (its runs named
/// `static-pan`), the other motions with theirs at `size`.
fn groups(opts: &MotionOptions) -> [(&'static str, [u32; 2], Vec<Motion>); 2] {
    [
        ("pan", opts.pan_size, pans(opts.full)),
        ("", opts.size, others()),
    ]
}

/// Frames the motion section renders (for a progress bar): every run's, the baselines',
/// the motion bound's and the mesh scene's.
#[must_use]
pub fn frames_to_render(opts: &MotionOptions) -> u64 {
    let n = scenes::core_variants(opts).len() as u64 * u64::from(opts.frames);
    if opts.only_mesh {
        return n;
    }
    let mut n = n;
    for (_, size, moving) in groups(opts) {
        for motion in std::iter::once(Motion::Static).chain(moving.iter().copied()) {
            n += variants(motion, opts).len() as u64 * u64::from(opts.frames);
            n += poses::still_frames(opts, size, motion);
        }
    }
    n + bound::bound_frames(opts)
}

/// The name a run of `motion` in `group` is reported under (`static-pan` for the pans'
/// static camera).
fn scene_name(group: &str, motion: Motion) -> String {
    if motion == Motion::Static && !group.is_empty() {
        format!("static-{group}")
    } else {
        motion.name()
    }
}

/// Whether `checks` hold every frame (a corrupt run is not scored); says on the progress
/// output which run is corrupt, and where.
fn clean<'a>(checks: impl IntoIterator<Item = &'a TwinCheck>, progress: &Progress) -> bool {
    let mut ok = true;
    for c in checks {
        if let Some(d) = &c.corrupt {
            ok = false;
            progress.println(&format!(
                "error: corrupt GPU run, not scored: {} {} frame {}: {} differs from the twin at \
                 {} pixels (first ({}, {}); by x mod 8 {:?})",
                c.scene, c.run, d.frame, d.what, d.pixels, d.first[0], d.first[1], d.lanes
            ));
        }
    }
    ok
}

/// Runs the motion section on `dev` (the CPU twin without one); `progress` counts frames
/// and names each stage.
///
/// # Errors
///
/// A device failure or a rejected configuration (a corrupt GPU run is not an error: its
/// check says so and the run is left out).
pub fn report(
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    progress: &Progress,
) -> Result<MotionReport, ReportError> {
    let mut rep = MotionReport::default();
    let scene = MeshScene::new(Mesh::bunny()?, opts.mesh_size, ORBIT);
    progress.stage(&format!(
        "motion: reference {} {}x{}",
        mesh::NAME,
        scene.size[0],
        scene.size[1]
    ));
    let refs = mesh::references(opts, &scene);
    for r in mesh::runs(dev, opts, &scene, &refs, progress)? {
        if clean(&r.twin_check, progress) {
            rep.runs.extend(r.runs);
        }
        rep.twin_checks.extend(r.twin_check);
    }
    if opts.only_mesh {
        return Ok(rep);
    }
    for (group, size, moving) in groups(opts) {
        for motion in std::iter::once(Motion::Static).chain(moving) {
            let name = scene_name(group, motion);
            progress.stage(&format!("motion: reference {name} {}x{}", size[0], size[1]));
            let refs = references(opts, size, motion);
            for v in variants(motion, opts) {
                progress.stage(&format!("motion: {name} {}", v.name(opts)));
                let r = run::run(dev, opts, size, motion, &name, v, &refs, progress)?;
                if clean(&r.twin_check, progress) {
                    rep.runs.extend(r.runs);
                }
                rep.twin_checks.extend(r.twin_check);
            }
            if let Some(s) = poses::still_at_poses(dev, opts, size, motion, &refs, progress)? {
                if clean(&s.twin_checks, progress) {
                    rep.still.push(s.baseline);
                }
                rep.twin_checks.extend(s.twin_checks);
            }
        }
    }
    progress.stage("motion: the motion bound (one frame of 1e30 motion, static)");
    for (k, v) in bound::bound_variants(opts).into_iter().enumerate() {
        let Some((b, check)) = bound::motion_bound_of(dev, opts, v, progress)? else {
            continue;
        };
        if clean(&check, progress) {
            if k == 0 {
                rep.motion_bound = Some(b);
            } else {
                rep.motion_bound_young.push((v.name(opts), b));
            }
        }
        rep.twin_checks.extend(check);
    }
    Ok(rep)
}

/// Runs the motion section and writes `motion.md`, `motion.csv`, `motion_runs.csv` and
/// the charts into `dir`; returns the section (its markdown with the charts linked, and
/// its acceptance lines).
///
/// # Errors
///
/// A device failure, or a file that cannot be written (naming it).
pub fn write(
    dir: &Path,
    dev: Option<&GpuDevice>,
    opts: &MotionOptions,
    backend: &str,
    progress: &Progress,
) -> Result<Section, ReportError> {
    let rep = report(dev, opts, progress)?;
    let lines = acceptance::acceptance(&rep, opts.full);
    let mut md = markdown::markdown(&rep, opts, backend, &lines);
    std::fs::create_dir_all(dir).map_err(|e| ReportError::io(dir, e))?;
    let _ = writeln!(
        md,
        "\nPer-frame values: [motion.csv](motion.csv); per run, with the equal-quality figures: [motion_runs.csv](motion_runs.csv).\n"
    );
    let mut charts: Vec<String> = vec![mesh::NAME.into()];
    for (group, _, moving) in groups(opts).into_iter().filter(|_| !opts.only_mesh) {
        for motion in std::iter::once(Motion::Static).chain(moving) {
            charts.push(scene_name(group, motion));
        }
    }
    for scene in charts {
        let file = figures::write_spp_chart(dir, &rep, &scene)?;
        let _ = writeln!(md, "![{scene}]({file})\n");
    }
    for scene in OBJECTS.map(|m| m.name()) {
        if let Some(file) = figures::write_uncovered_chart(dir, &rep, &scene)? {
            let _ = writeln!(
                md,
                "{scene}: PSNR per frame of the steady pixels and of the newly uncovered ones at \
                 their first, second and third frame on screen (`as` solid, `{}` dashed where it \
                 ran):\n\n![{scene} uncovered]({file})\n",
                scenes::YOUNG
            );
        }
    }
    for (file, text) in [
        ("motion_runs.csv", markdown::runs_csv(&rep)),
        ("motion.csv", markdown::frames_csv(&rep)),
        ("motion.md", md.clone()),
    ] {
        let path = dir.join(file);
        std::fs::write(&path, text).map_err(|e| ReportError::io(&path, e))?;
    }
    Ok(Section {
        name: "motion",
        markdown: md,
        groups: lines,
    })
}

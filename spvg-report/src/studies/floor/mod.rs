//! Fractional counts below the floor (docs/algorithms.md §8.6) and the resolved-image rule
//! (§8.7), swept after a temporal resolve: the fractional floor over a range of targets
//! against fixed counts from 1 to 64 and against AS [8, 64], on ambient occlusion
//! ([`ao`]: the static camera, the 4 px/frame pan, the floating sphere) and on the
//! subsurface effect's static scene ([`sss`]). Each runs on the effects' CPU twins (equal
//! to the GPU: `spvg-effects/tests/ao.rs`, `sss_consumer.rs`), so the figures are the same
//! on every machine. A study: it judges nothing (the report's `as-resolved` runs judge the
//! rule).

use std::path::Path;

use crate::error::ReportError;
use crate::progress::Progress;
use crate::section::Section;

pub use options::{FloorEffects, FloorOptions, SparseBox, TAA_WEIGHT};

/// Appends one formatted line (or an empty one) to a markdown string.
macro_rules! say {
    ($md:ident) => {
        $md.push('\n')
    };
    ($md:ident, $($t:tt)*) => {{
        let _ = writeln!($md, $($t)*);
    }};
}

pub mod ao;
mod options;
pub mod sss;

/// Runs the study and writes `floor.md` into `dir`.
///
/// # Errors
///
/// A configuration the core refuses (a floor or target out of range, named), a twin
/// failure, a file that cannot be written.
pub fn write(dir: &Path, opts: &FloorOptions, progress: &Progress) -> Result<Section, ReportError> {
    let mut md = String::from(
        "## Fractional counts and the resolved-image rule after TAA (study, not judged)\n",
    );
    if matches!(opts.effects, FloorEffects::Sss | FloorEffects::Both) {
        md.push_str(&sss::markdown(opts, progress)?);
    }
    if matches!(opts.effects, FloorEffects::Ao | FloorEffects::Both) {
        md.push_str(&ao::markdown(opts, progress)?);
    }
    std::fs::create_dir_all(dir).map_err(|e| ReportError::io(dir, e))?;
    let path = dir.join("floor.md");
    std::fs::write(&path, &md).map_err(|e| ReportError::io(&path, e))?;
    Ok(Section {
        name: "floor",
        markdown: md,
        groups: Vec::new(),
    })
}

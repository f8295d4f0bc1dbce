//! The runs of one scene, as the report keeps them: per-frame records, summaries and the
//! frame images of the report-setting runs.

use super::run::{FrameRecord, RunSpec, RunSummary};
use crate::error::ReportError;
use crate::images::{ERROR_FULL, ImageWriter, Ramp, UNSCORED, Written, count_grey, srgb8};
use crate::metrics::rgb;
use crate::scene::{Scene, SceneKind};
use crate::wgpu_api::{FrameOutput, luminance};

/// The frame images of one run.
#[derive(Clone, Debug)]
pub struct ImageRow {
    /// Run label.
    pub label: String,
    /// Result image.
    pub result: Written,
    /// Count image.
    pub count: Written,
    /// Error image (with a reference only).
    pub error: Option<Written>,
}

/// Everything measured on one scene.
#[derive(Debug)]
pub struct SceneRuns {
    /// The scene.
    pub kind: SceneKind,
    /// Per-frame records of the default-setting runs (for the per-frame charts).
    pub per_frame: Vec<(String, Vec<FrameRecord>)>,
    /// Per-frame records of every run, for `frames.csv`.
    pub(crate) all_frames: Vec<(String, Vec<FrameRecord>)>,
    /// Summary of every run.
    pub summaries: Vec<RunSummary>,
    /// Frame images of the default-setting runs.
    pub images: Vec<ImageRow>,
    /// The scene's thumbnail (its reference image, else its first result image).
    pub thumbnail: Option<String>,
}

impl SceneRuns {
    /// No runs yet.
    #[must_use]
    pub fn new(kind: SceneKind) -> Self {
        Self {
            kind,
            per_frame: Vec::new(),
            all_frames: Vec::new(),
            summaries: Vec::new(),
            images: Vec::new(),
            thumbnail: None,
        }
    }

    /// Adds a finished run.
    pub fn push(&mut self, spec: &RunSpec, records: Vec<FrameRecord>, summary: RunSummary) {
        if !spec.is_sweep() {
            self.per_frame.push((spec.label.clone(), records.clone()));
        }
        self.all_frames.push((spec.label.clone(), records));
        self.summaries.push(summary);
    }

    /// Writes the images of frame `t` of run `label`: result, count and (with a reference)
    /// error, plus the scene's reference image once.
    ///
    /// # Errors
    ///
    /// [`ReportError::Io`] naming the file.
    #[allow(
        clippy::too_many_arguments,
        reason = "one call site; the frame's parts"
    )]
    pub fn frame_images(
        &mut self,
        writer: &mut ImageWriter,
        label: &str,
        t: u32,
        scene: Scene,
        out: &FrameOutput,
        reference: &[[f32; 3]],
        mask: &[u8],
    ) -> Result<(), ReportError> {
        let name = self.kind.name();
        let size = (scene.width, scene.height);
        let frame = format!("frame {t}");
        if self.thumbnail.is_none() && !reference.is_empty() {
            let px: Vec<u8> = reference.iter().flat_map(|v| v.map(srgb8)).collect();
            let w = writer.write(
                &format!("{name}_reference_f{t}.png"),
                "reference",
                size,
                &px,
                None,
                &[&format!("{name}: reference"), &frame],
            )?;
            self.thumbnail = Some(w.file);
        }
        let result: Vec<u8> = out.result.iter().flat_map(|v| rgb(*v).map(srgb8)).collect();
        let caption = |what: &str| [format!("{name} / {label}"), format!("{frame} / {what}")];
        let [a, b] = caption("result");
        let result = writer.write(
            &format!("{name}_{label}_f{t}_result.png"),
            "result",
            size,
            &result,
            None,
            &[&a, &b],
        )?;
        if self.thumbnail.is_none() {
            self.thumbnail = Some(result.file.clone());
        }
        let count: Vec<u8> = out.count.iter().flat_map(|&c| [count_grey(c); 3]).collect();
        let ramp = Ramp {
            colour: &|f| [count_grey((f * 64.0).round() as u32); 3],
            ends: ["0 spp", "64 spp"],
            key: None,
        };
        let [a, b] = caption("samples per pixel");
        let count = writer.write(
            &format!("{name}_{label}_f{t}_count.png"),
            "count",
            size,
            &count,
            Some(&ramp),
            &[&a, &b],
        )?;
        let error = if reference.is_empty() {
            None
        } else {
            let px = error_pixels(out, reference, mask);
            let ramp = Ramp {
                colour: &|f| [srgb8(f as f32); 3],
                ends: ["0", "|lum err| 0.05"],
                key: Some((UNSCORED, "not scored")),
            };
            let [a, b] = caption("luminance error");
            Some(writer.write(
                &format!("{name}_{label}_f{t}_error.png"),
                "error",
                size,
                &px,
                Some(&ramp),
                &[&a, &b],
            )?)
        };
        self.images.push(ImageRow {
            label: label.to_owned(),
            result,
            count,
            error,
        });
        Ok(())
    }
}

/// The luminance error image: `|result - reference|` on the sRGB ramp up to
/// [`ERROR_FULL`], [`UNSCORED`] outside the mask.
fn error_pixels(out: &FrameOutput, reference: &[[f32; 3]], mask: &[u8]) -> Vec<u8> {
    out.result
        .iter()
        .zip(reference)
        .zip(mask)
        .flat_map(|((v, r), m)| {
            if *m == 0 {
                UNSCORED
            } else {
                [srgb8((luminance(rgb(*v)) - luminance(*r)).abs() / ERROR_FULL); 3]
            }
        })
        .collect()
}

//! Progress of a long run on stderr: an indicatif bar of frames rendered when stderr is a
//! terminal, else one line per stage with the elapsed time (logs stay readable).

use std::io::IsTerminal as _;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar counting frames, with the current stage as its message.
#[derive(Debug)]
pub struct Progress {
    bar: ProgressBar,
    /// Print each stage as a line (stderr is not a terminal).
    lines: bool,
    /// Prefix of the printed lines (the binary's name).
    prefix: &'static str,
    started: Instant,
}

impl Progress {
    /// A bar of `frames` frames on stderr (drawn only on a terminal), printing stage lines
    /// prefixed with `prefix` otherwise.
    #[must_use]
    pub fn new(prefix: &'static str, frames: u64) -> Self {
        let terminal = std::io::stderr().is_terminal();
        let target = if terminal {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some(frames), target);
        bar.set_style(
            ProgressStyle::with_template(
                "{elapsed_precise} [{wide_bar}] {pos}/{len} frames, ETA {eta} {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        Self {
            bar,
            lines: !terminal,
            prefix,
            started: Instant::now(),
        }
    }

    /// A progress that shows and prints nothing (tests, library callers).
    #[must_use]
    pub fn hidden() -> Self {
        Self {
            bar: ProgressBar::hidden(),
            lines: false,
            prefix: "",
            started: Instant::now(),
        }
    }

    /// Adds `frames` to the bar's length (a later part of the run).
    pub fn add_frames(&self, frames: u64) {
        self.bar.inc_length(frames);
    }

    /// Counts `frames` frames done.
    pub fn inc(&self, frames: u64) {
        self.bar.inc(frames);
    }

    /// Names the current stage (the bar's message, or a printed line off a terminal).
    pub fn stage(&self, what: &str) {
        if self.lines {
            eprintln!(
                "{}: {what} ({:.0} s)",
                self.prefix,
                self.started.elapsed().as_secs_f64()
            );
        }
        self.bar.set_message(what.to_owned());
    }

    /// Prints a line above the bar (or on its own off a terminal; nothing when hidden).
    pub fn println(&self, line: &str) {
        if self.lines {
            eprintln!("{}: {line}", self.prefix);
        } else if !self.bar.is_hidden() {
            self.bar.suspend(|| eprintln!("{}: {line}", self.prefix));
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }

    /// Seconds since the progress was created.
    #[must_use]
    pub fn elapsed_s(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }
}

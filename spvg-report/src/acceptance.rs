//! One acceptance check and its line, the single format of every acceptance line the
//! crate writes (report.md's sections, motion.md, stdout): `- PASS: <what was measured>`
//! or `- FAIL: <what was measured>`, so that `^- (PASS|FAIL): ` finds every one.

use std::fmt;

/// One acceptance check: what was measured against what bound, and whether it held.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Check {
    /// Whether the check holds.
    pub pass: bool,
    /// What was measured, against which bound (no verdict word: [`Check::line`] adds it).
    pub text: String,
}

impl Check {
    /// A check that holds when `pass`.
    #[must_use]
    pub fn new(pass: bool, text: impl Into<String>) -> Self {
        Self {
            pass,
            text: text.into(),
        }
    }

    /// `PASS` or `FAIL`.
    #[must_use]
    pub fn verdict(&self) -> &'static str {
        if self.pass { "PASS" } else { "FAIL" }
    }

    /// The markdown line: `- PASS: text` or `- FAIL: text`.
    #[must_use]
    pub fn line(&self) -> String {
        self.to_string()
    }

    /// The part of the text before its first colon (the check's name, for a verdict that
    /// lists what failed).
    #[must_use]
    pub fn name(&self) -> &str {
        self.text.split(':').next().unwrap_or("")
    }
}

impl fmt::Display for Check {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "- {}: {}", self.verdict(), self.text)
    }
}

/// Whether `line` is an acceptance line in the one format (`- PASS: ` or `- FAIL: `
/// followed by text).
#[must_use]
pub fn is_line(line: &str) -> bool {
    ["- PASS: ", "- FAIL: "]
        .iter()
        .any(|p| line.strip_prefix(p).is_some_and(|rest| !rest.is_empty()))
}

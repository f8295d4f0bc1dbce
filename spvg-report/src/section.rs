//! What every section of the report hands back: its markdown, its acceptance lines in
//! titled groups, and the one verdict over every section a command ran.

use std::fmt::Write as _;

use crate::acceptance::Check;

/// A titled group of acceptance lines; `judged` groups make the verdict, the others (the
/// subsurface sweep) only inform.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Group {
    /// The group's heading.
    pub title: String,
    /// Whether its lines count in the verdict.
    pub judged: bool,
    /// Its lines.
    pub checks: Vec<Check>,
}

impl Group {
    /// A judged group.
    #[must_use]
    pub fn judged(title: impl Into<String>, checks: Vec<Check>) -> Self {
        Self {
            title: title.into(),
            judged: true,
            checks,
        }
    }

    /// The group as markdown: its heading and one line per check (empty without checks).
    #[must_use]
    pub fn markdown(&self) -> String {
        if self.checks.is_empty() {
            return String::new();
        }
        let mut md = format!("### {}\n\n", self.title);
        for c in &self.checks {
            let _ = writeln!(md, "{}", c.line());
        }
        md.push('\n');
        md
    }
}

/// One section of the report as a command ran it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Section {
    /// Its name (`subsurface`, `motion`, `separable`, `budget`, `gpu-readiness`,
    /// `pass-breakdown`).
    pub name: &'static str,
    /// Its markdown, appended to `report.md`.
    pub markdown: String,
    /// Its acceptance lines (none for a timing study).
    pub groups: Vec<Group>,
}

impl Section {
    /// The judged lines of the section.
    pub fn judged(&self) -> impl Iterator<Item = &Check> {
        self.groups
            .iter()
            .filter(|g| g.judged)
            .flat_map(|g| &g.checks)
    }
}

/// The verdict over the judged lines of `sections`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Verdict {
    /// The one line that opens `report.md` and ends the command's output.
    pub line: String,
    /// Judged lines.
    pub judged: usize,
    /// Judged lines that fail.
    pub failed: usize,
}

impl Verdict {
    /// Judges `sections`: PASS when every judged line holds, FAIL naming the failing
    /// lines by section, *not judged* when no section judged anything (a timing study, or
    /// a run without references).
    #[must_use]
    pub fn of(sections: &[Section]) -> Self {
        let judged: usize = sections.iter().map(|s| s.judged().count()).sum();
        let mut failing: Vec<String> = Vec::new();
        for s in sections {
            for c in s.judged().filter(|c| !c.pass) {
                let name = format!("{}: {}", s.name, c.name());
                if !failing.contains(&name) {
                    failing.push(name);
                }
            }
        }
        let failed = sections
            .iter()
            .map(|s| s.judged().filter(|c| !c.pass).count())
            .sum();
        let per_section: Vec<String> = sections
            .iter()
            .map(|s| (s.name, s.judged().count()))
            .filter(|(_, n)| *n > 0)
            .map(|(name, n)| format!("{name} {n}"))
            .collect();
        let (mut sweep, mut sweep_pass) = (0, 0);
        for c in sections
            .iter()
            .flat_map(|s| &s.groups)
            .filter(|g| !g.judged)
            .flat_map(|g| &g.checks)
        {
            sweep += 1;
            sweep_pass += usize::from(c.pass);
        }
        let sweep = if sweep > 0 {
            format!(
                " Across the sweep, {sweep_pass} of {sweep} lines hold (the sweep shows what each setting buys; it is not judged)."
            )
        } else {
            String::new()
        };
        let line = if judged == 0 {
            "**Verdict: not judged**: no section ran a judged line (a timing study, or a run without references).".to_owned()
        } else if failed == 0 {
            format!(
                "**Verdict: PASS**: all {judged} judged acceptance lines hold ({}).{sweep}",
                per_section.join(", ")
            )
        } else {
            format!(
                "**Verdict: FAIL**: {failed} of {judged} judged acceptance lines fail ({}).{sweep}",
                failing.join("; ")
            )
        };
        Self {
            line,
            judged,
            failed,
        }
    }

    /// Whether every judged line holds and at least one was judged.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.judged > 0 && self.failed == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn section(name: &'static str, judged: &[bool], sweep: &[bool]) -> Section {
        let checks = |v: &[bool]| {
            v.iter()
                .enumerate()
                .map(|(i, &p)| Check::new(p, format!("line {i}: x")))
                .collect()
        };
        Section {
            name,
            markdown: String::new(),
            groups: vec![
                Group::judged("a", checks(judged)),
                Group {
                    title: "sweep".into(),
                    judged: false,
                    checks: checks(sweep),
                },
            ],
        }
    }

    #[test]
    fn the_verdict_counts_judged_lines_only_and_names_failures_by_section() {
        let pass = Verdict::of(&[section("a", &[true, true], &[false])]);
        assert!(pass.passed(), "{}", pass.line);
        assert!(
            pass.line.starts_with("**Verdict: PASS**: all 2 judged"),
            "{}",
            pass.line
        );
        assert!(pass.line.contains("0 of 1 lines hold"), "{}", pass.line);
        let fail = Verdict::of(&[
            section("a", &[true], &[]),
            section("motion", &[true, false], &[]),
        ]);
        assert!(!fail.passed(), "{}", fail.line);
        assert_eq!((fail.judged, fail.failed), (3, 1), "{}", fail.line);
        assert!(fail.line.contains("motion: line 1"), "{}", fail.line);
        let none = Verdict::of(&[section("a", &[], &[true])]);
        assert!(!none.passed(), "{}", none.line);
        assert!(none.line.contains("not judged"), "{}", none.line);
    }
}

//! Replays the seed corpus of every fuzz target through the same checks on stable Rust, so
//! `cargo test --workspace` exercises the fuzz invariants without nightly or libFuzzer.
//!
//! Every directory under `corpus/` must name an entry of `spvg_fuzz::TARGETS`, and every
//! target (each `fuzz_targets/*.rs`) must have a corpus of a few seeds: a corpus nobody
//! replays, or a target nobody seeds, fails here.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn entries(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{} unreadable: {e}", dir.display()))
        .filter_map(Result::ok)
        .map(|e| e.path())
        .collect();
    v.sort();
    v
}

fn stem(p: &Path) -> String {
    p.file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or_else(|| panic!("odd name {}", p.display()))
        .to_owned()
}

#[test]
fn every_corpus_passes_its_check() {
    let dirs: Vec<_> = entries(&root().join("corpus"))
        .into_iter()
        .filter(|p| p.is_dir())
        .collect();
    assert!(!dirs.is_empty(), "no corpus directories");
    for dir in &dirs {
        let name = stem(dir);
        let check = spvg_fuzz::TARGETS
            .iter()
            .find(|(t, _)| *t == name)
            .map(|&(_, c)| c)
            .unwrap_or_else(|| panic!("corpus/{name} has no check in spvg_fuzz::TARGETS"));
        let files: Vec<_> = entries(dir).into_iter().filter(|p| p.is_file()).collect();
        assert!(files.len() >= 5, "corpus/{name} too small: {files:?}");
        for f in &files {
            let data = std::fs::read(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            // A panic names the check; say which seed it was.
            println!("replaying {}", f.display());
            check(&data);
        }
    }
}

#[test]
fn every_target_has_a_check_and_a_corpus() {
    let targets: BTreeSet<String> = entries(&root().join("fuzz_targets"))
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .map(|p| stem(p))
        .collect();
    let checks: BTreeSet<String> = spvg_fuzz::TARGETS
        .iter()
        .map(|(t, _)| (*t).to_owned())
        .collect();
    assert_eq!(
        targets, checks,
        "fuzz_targets/*.rs and spvg_fuzz::TARGETS differ"
    );
    for t in &targets {
        let dir = root().join("corpus").join(t);
        assert!(dir.is_dir(), "target {t} has no corpus/{t}/");
    }
}

//! Replays the seed corpus of each fuzz target through the same checks on stable Rust, so
//! `cargo test --workspace` exercises the fuzz invariants without nightly or libFuzzer.

use std::path::Path;

#[test]
fn estimators_corpus_passes_the_checks() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus/estimators");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("corpus {} unreadable: {e}", dir.display()))
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    assert!(files.len() >= 5, "seed corpus too small: {files:?}");
    for f in &files {
        let data = std::fs::read(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        spvg_fuzz::check_estimators(&data);
    }
}

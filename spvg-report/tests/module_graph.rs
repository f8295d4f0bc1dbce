//! No import cycles between the library's files: a file may import the files before it in
//! its section (and what every section shares), never one that imports it back, directly
//! or through others. A `mod.rs` declaring its children is not an import; a child
//! importing from its own `mod.rs` while that file imports the child is a cycle.

use std::collections::BTreeMap;
use std::path::Path;

/// A file's module path (`motion/run.rs` -> `motion::run`, `motion/mod.rs` -> `motion`).
fn module_of(file: &str) -> Vec<String> {
    let stem = file.trim_end_matches(".rs");
    let mut parts: Vec<String> = stem.split('/').map(str::to_owned).collect();
    if parts.last().is_some_and(|p| p == "mod" || p == "lib") {
        parts.pop();
    }
    parts
}

/// The paths the `use` declarations of `src` name, outside comments and the test module.
fn use_paths(src: &str) -> Vec<String> {
    let code = src.split("#[cfg(test)]").next().unwrap_or("");
    let mut out = Vec::new();
    let mut open: Option<String> = None;
    for line in code.lines() {
        let line = line.split("//").next().unwrap_or("").trim();
        let text = match open.take() {
            Some(mut t) => {
                t.push(' ');
                t.push_str(line);
                t
            }
            None => {
                let Some(body) = ["use ", "pub use ", "pub(crate) use ", "pub(super) use "]
                    .iter()
                    .find_map(|p| line.strip_prefix(p))
                else {
                    continue;
                };
                body.to_owned()
            }
        };
        match text.split_once(';') {
            Some((tree, _)) => expand(tree, &mut out),
            None => open = Some(text),
        }
    }
    out
}

/// The paths a `use` tree names (`a::{b, c::{d}}` -> `a::b`, `a::c::d`).
fn expand(tree: &str, out: &mut Vec<String>) {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        out.push(tree.split(" as ").next().unwrap_or("").trim().to_owned());
        return;
    };
    let prefix = tree[..open].trim_end_matches("::");
    let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
    let (mut depth, mut start) = (0, 0);
    let mut items = Vec::new();
    for (i, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    items.push(&inner[start..]);
    for item in items.into_iter().map(str::trim).filter(|i| !i.is_empty()) {
        if item == "self" {
            out.push(prefix.to_owned());
        } else {
            expand(&format!("{prefix}::{item}"), out);
        }
    }
}

/// The import edges between `files` (path relative to `src`, text): each file to the
/// files whose items it imports.
fn edges(files: &BTreeMap<String, String>) -> BTreeMap<String, Vec<String>> {
    let modules: BTreeMap<Vec<String>, &String> = files.keys().map(|f| (module_of(f), f)).collect();
    // The file defining the longest known prefix of `path`.
    let resolve = |path: &[String]| {
        (0..=path.len())
            .rev()
            .find_map(|k| modules.get(&path[..k]).copied())
    };
    let mut out = BTreeMap::new();
    for (file, src) in files {
        let me = module_of(file);
        let declares = file.ends_with("mod.rs") || file == "lib.rs";
        let mut to = Vec::new();
        for path in use_paths(src) {
            let segs: Vec<String> = path.split("::").map(str::to_owned).collect();
            let target = match segs.first().map(String::as_str) {
                Some("crate") => segs[1..].to_vec(),
                Some("super") => {
                    let mut base = me.clone();
                    let mut rest = &segs[..];
                    while rest.first().is_some_and(|s| s == "super") {
                        base.pop();
                        rest = &rest[1..];
                    }
                    base.extend(rest.iter().cloned());
                    base
                }
                Some("self") => me.iter().chain(&segs[1..]).cloned().collect(),
                // A module file's own children (`use child::Item`).
                Some(first)
                    if declares
                        && modules.contains_key(&[me.clone(), vec![first.to_owned()]].concat()) =>
                {
                    me.iter().chain(&segs).cloned().collect()
                }
                _ => continue,
            };
            if let Some(t) = resolve(&target).filter(|t| *t != file && !to.contains(*t)) {
                to.push(t.clone());
            }
        }
        out.insert(file.clone(), to);
    }
    out
}

/// One cycle of `edges`, if any, as the files along it.
fn a_cycle(edges: &BTreeMap<String, Vec<String>>) -> Option<Vec<String>> {
    fn visit(
        u: &str,
        edges: &BTreeMap<String, Vec<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(u.to_owned(), 1);
        stack.push(u.to_owned());
        for v in edges.get(u).into_iter().flatten() {
            match state.get(v).copied().unwrap_or(0) {
                0 => {
                    if let Some(c) = visit(v, edges, state, stack) {
                        return Some(c);
                    }
                }
                1 => {
                    let from = stack.iter().position(|s| s == v).unwrap_or(0);
                    let mut c = stack[from..].to_vec();
                    c.push(v.clone());
                    return Some(c);
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(u.to_owned(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for u in edges.keys() {
        if state.get(u).copied().unwrap_or(0) == 0
            && let Some(c) = visit(u, edges, &mut state, &mut Vec::new())
        {
            return Some(c);
        }
    }
    None
}

/// The library's files under `dir` (relative paths), the binary left out.
fn read(dir: &Path, root: &Path, files: &mut BTreeMap<String, String>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        let rel = p
            .strip_prefix(root)
            .map(|r| r.to_string_lossy().replace('\\', "/"))
            .unwrap_or_default();
        if p.is_dir() && rel != "bin" {
            read(&p, root, files);
        } else if rel.ends_with(".rs") {
            let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{rel}: {e}"));
            files.insert(rel, text);
        }
    }
}

#[test]
fn the_check_finds_a_cycle_through_a_parent() {
    let files: BTreeMap<String, String> = [
        ("lib.rs", "pub mod a;\npub mod b;\n"),
        ("a/mod.rs", "pub mod x;\nuse x::Thing;\npub struct Top;\n"),
        ("a/x.rs", "use super::Top;\npub struct Thing;\n"),
        ("b.rs", "use crate::a::{x::{self, Thing}, Top as T};\n"),
    ]
    .iter()
    .map(|(f, s)| ((*f).to_owned(), (*s).to_owned()))
    .collect();
    let e = edges(&files);
    assert_eq!(e["b.rs"], ["a/x.rs", "a/mod.rs"], "{e:?}");
    let c = a_cycle(&e).expect("a/mod.rs and a/x.rs import each other");
    assert!(
        c.contains(&"a/x.rs".to_owned()) && c.contains(&"a/mod.rs".to_owned()),
        "{c:?}"
    );
    // Without the child's import of its parent, no cycle.
    let mut fixed = files;
    fixed.insert("a/x.rs".into(), "pub struct Thing;\n".into());
    assert_eq!(a_cycle(&edges(&fixed)), None);
}

#[test]
fn the_library_has_no_import_cycle() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = BTreeMap::new();
    read(&root, &root, &mut files);
    assert!(files.len() > 40, "{} files read", files.len());
    let e = edges(&files);
    // The check sees the sections' imports (a real edge, as a sanity check of the parse).
    assert!(
        e["motion/run.rs"].contains(&"motion/render.rs".to_owned()),
        "{:?}",
        e["motion/run.rs"]
    );
    if let Some(c) = a_cycle(&e) {
        panic!("an import cycle: {}", c.join(" -> "));
    }
}

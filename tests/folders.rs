//! Inside every folder of `src/`, the modules (its files and sub-folders) import each other
//! without a circle, as the top-level modules do (`tests/layers.rs`). The graph is built from
//! every `crate::`, `super::` and `self::` path in the code (comments and `#[cfg(test)]`
//! modules left out), resolved to the module it names: a file of folder `F` under child `a`
//! that names `F::b::...` gives the edge a -> b. Items the folder's `mod.rs` re-exports are
//! the folder's own and give no edge.

mod common;

use common::source::{code, sources};

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The module path of a file under `src` (`integrate/implicit/mod.rs` is
/// `["integrate", "implicit"]`; `lib.rs` and `main.rs` are the crate root).
fn module_of(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|c| c.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The paths that start at `i` of `code` (`crate::a::{b, c::d}` gives `[a, b]` and
/// `[a, c, d]`, cut after the first segment past a brace: enough to name the module).
fn paths_at(code: &str, mut i: usize) -> Vec<Vec<String>> {
    let bytes = code.as_bytes();
    let mut prefix = Vec::new();
    loop {
        let start = i;
        while i < bytes.len() && is_ident(bytes[i] as char) {
            i += 1;
        }
        if i > start {
            prefix.push(code[start..i].to_string());
        }
        if code[i..].starts_with("::{") {
            // a group: each member's first two segments
            let close = code[i..].find('}').map_or(code.len(), |c| i + c);
            return code[i + 3..close]
                .split(',')
                .map(|m| {
                    let mut p = prefix.clone();
                    p.extend(
                        m.trim()
                            .split("::")
                            .take(2)
                            .map(|s| s.trim().trim_start_matches('{').to_string())
                            .filter(|s| !s.is_empty()),
                    );
                    p
                })
                .collect();
        }
        if code[i..].starts_with("::") {
            i += 2;
        } else {
            return vec![prefix];
        }
    }
}

/// Every module-relative path in `code`, resolved against the file's module `here`.
fn resolved(code: &str, here: &[String]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for (i, _) in code.match_indices("::") {
        let before = &code[..i];
        let word_start = before.rfind(|c: char| !is_ident(c)).map_or(0, |p| p + 1);
        let word = &before[word_start..];
        if word_start > 0 && before[..word_start].ends_with("::") {
            continue; // inside a longer path: taken from its first segment
        }
        // `self` is the file's module (a folder's `mod.rs` is the folder), `super` its parent
        let mut base: Vec<String> = match word {
            "crate" => Vec::new(),
            "self" => here.to_vec(),
            "super" => here.to_vec(),
            _ => continue,
        };
        let mut path = paths_at(code, word_start);
        if word == "super" {
            // each leading `super` climbs one module
            for p in &mut path {
                let supers = p.iter().take_while(|s| *s == "super").count();
                for _ in 0..supers {
                    base.pop();
                }
                p.drain(..supers);
            }
        } else {
            for p in &mut path {
                p.remove(0);
            }
        }
        out.extend(path.into_iter().map(|p| {
            let mut full = base.clone();
            full.extend(p);
            full
        }));
    }
    out
}

/// The edges between the children of every folder: folder -> (from child, to child).
fn folder_edges(src: &Path) -> BTreeMap<String, BTreeSet<(String, String)>> {
    let mut files = Vec::new();
    sources(src, &mut files);
    let mut edges: BTreeMap<String, BTreeSet<(String, String)>> = BTreeMap::new();
    for file in files {
        let rel = file.strip_prefix(src).expect("under src");
        let here = module_of(rel);
        let text = std::fs::read_to_string(&file).expect("readable source");
        for target in resolved(&code(&text), &here) {
            // every folder that holds both the file and the target under different children
            for depth in 0..here.len() {
                let folder = &here[..depth];
                if !src.join(folder.join("/")).is_dir() || target.len() <= depth {
                    continue;
                }
                if target[..depth] != *folder {
                    continue;
                }
                let (from, to) = (&here[depth], &target[depth]);
                let dir = src.join(folder.join("/"));
                let child = dir.join(format!("{to}.rs")).exists() || dir.join(to).is_dir();
                if from != to && child {
                    edges
                        .entry(folder.join("/"))
                        .or_default()
                        .insert((from.clone(), to.clone()));
                }
            }
        }
    }
    edges
}

/// A circle in a graph, if there is one.
fn circle(edges: &BTreeSet<(String, String)>) -> Option<Vec<String>> {
    let mut next: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for (a, b) in edges {
        next.entry(a).or_default().push(b);
    }
    // depth-first search with the path on a stack
    fn visit<'a>(
        n: &'a str,
        next: &BTreeMap<&'a str, Vec<&'a str>>,
        state: &mut BTreeMap<&'a str, u8>,
        path: &mut Vec<&'a str>,
    ) -> Option<Vec<String>> {
        state.insert(n, 1);
        path.push(n);
        for &m in next.get(n).into_iter().flatten() {
            match state.get(m) {
                Some(1) => {
                    let at = path.iter().position(|p| *p == m).expect("on the path");
                    let mut c: Vec<String> = path[at..].iter().map(|s| s.to_string()).collect();
                    c.push(m.to_string());
                    return Some(c);
                }
                Some(_) => {}
                None => {
                    if let Some(c) = visit(m, next, state, path) {
                        return Some(c);
                    }
                }
            }
        }
        path.pop();
        state.insert(n, 2);
        None
    }
    let mut state = BTreeMap::new();
    for &n in next.keys() {
        if !state.contains_key(n) {
            if let Some(c) = visit(n, &next, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

#[test]
fn no_folder_imports_in_a_circle() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let circles: Vec<String> = folder_edges(&src)
        .iter()
        .filter_map(|(folder, e)| circle(e).map(|c| format!("  src/{folder}: {}", c.join(" -> "))))
        .collect();
    assert!(
        circles.is_empty(),
        "modules of one folder that import each other in a circle (move the shared item to a lower module):\n{}",
        circles.join("\n")
    );
}

/// The check resolves `crate::`, `super::` and grouped paths, and finds a circle.
#[test]
fn the_folder_check_resolves_paths_and_finds_a_circle() {
    let here: Vec<String> = ["integrate", "explicit", "contact"]
        .map(String::from)
        .to_vec();
    let code = "use super::super::implicit::StepReport;\nuse crate::integrate::{state::Energies, resident};\nfn f() { self::g(); }";
    let found = resolved(code, &here);
    let want: Vec<Vec<String>> = vec![
        vec!["integrate", "implicit", "StepReport"],
        vec!["integrate", "state", "Energies"],
        vec!["integrate", "resident"],
        vec!["integrate", "explicit", "contact", "g"],
    ]
    .into_iter()
    .map(|p| p.into_iter().map(String::from).collect())
    .collect();
    assert_eq!(found, want);
    let edges: BTreeSet<(String, String)> = [("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")]
        .map(|(x, y)| (x.to_string(), y.to_string()))
        .into();
    assert_eq!(
        circle(&edges),
        Some(["a", "b", "c", "a"].map(String::from).to_vec())
    );
    let acyclic: BTreeSet<(String, String)> = [("a", "b"), ("b", "c"), ("a", "c")]
        .map(|(x, y)| (x.to_string(), y.to_string()))
        .into();
    assert_eq!(circle(&acyclic), None);
}

//! The library's modules form one-way layers: a module uses only modules below it
//! (`docs/architecture.md`). The graph is built from every `crate::<module>` path in the
//! code of `src/` (comments and `#[cfg(test)]` modules left out), so a new upward import
//! fails here on any machine.

mod common;

use common::source::{code, sources};

use std::collections::BTreeSet;
use std::path::Path;

/// The top-level modules of `src/`, lowest first.
const LAYERS: &[&str] = &[
    "error",
    "limits",
    "parallel",
    "material",
    "geometry",
    "element",
    "mesh",
    "scene",
    "contact",
    "kernels",
    "model",
    "search",
    "backend",
    "gpu",
    "linalg",
    "integrate",
    "domain",
    "check",
    "output",
    "checkpoint",
    "setup",
    "report",
    "run",
    "study",
];

/// The modules named by `crate::<name>` paths in `code`.
fn uses(code: &str) -> BTreeSet<String> {
    code.match_indices("crate::")
        .map(|(i, m)| {
            code[i + m.len()..]
                .chars()
                .take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '_')
                .collect::<String>()
        })
        .filter(|name| !name.is_empty())
        .collect()
}

/// The (module, file, used module) of every use of a module at or above the user's layer.
fn upward_uses(src: &Path) -> Vec<(String, String, String)> {
    let mut files = Vec::new();
    sources(src, &mut files);
    let mut found = Vec::new();
    for file in files {
        let rel = file.strip_prefix(src).expect("under src");
        let first = rel.iter().next().expect("a first component");
        let top = first.to_string_lossy().trim_end_matches(".rs").to_string();
        if top == "lib" || top == "main" {
            continue;
        }
        let layer = |m: &str| {
            LAYERS
                .iter()
                .position(|l| *l == m)
                .unwrap_or_else(|| panic!("module `{m}` is not in LAYERS: give it its layer"))
        };
        let own = layer(&top);
        let text = std::fs::read_to_string(&file).expect("readable source");
        for used in uses(&code(&text)) {
            if used != top && layer(&used) > own {
                found.push((top.clone(), rel.display().to_string(), used));
            }
        }
    }
    found
}

#[test]
fn no_module_uses_one_above_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let upward = upward_uses(&src);
    assert!(
        upward.is_empty(),
        "modules that use a module above them (move the code, or the module's layer):\n{}",
        upward
            .iter()
            .map(|(m, f, u)| format!("  {m} ({f}) uses {u}"))
            .collect::<Vec<_>>()
            .join("\n")
    );
}

/// The check itself finds an upward use, ignores comments and test modules, and knows every
/// module of `src/`.
#[test]
fn the_layer_check_finds_an_upward_use_and_only_in_code() {
    let text = "//! see crate::run\nuse crate::model::Model;\nfn f() { crate::gpu::x(); } // crate::study\n#[cfg(test)]\nmod tests { use crate::setup; }";
    let found = uses(&code(text));
    assert_eq!(
        found,
        ["gpu", "model"].iter().map(|s| s.to_string()).collect()
    );
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let lib = std::fs::read_to_string(src.join("lib.rs")).expect("lib.rs");
    for line in lib.lines() {
        if let Some(m) = line.strip_prefix("pub mod ") {
            let m = m.trim_end_matches(';');
            assert!(LAYERS.contains(&m), "module `{m}` has no layer");
        }
    }
}

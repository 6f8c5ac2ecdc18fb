//! The crate's layering (`src/lib.rs`, "Layers"): every `crate::X` reference in a top-level
//! module's files points to the same or a lower layer, and no study refers to another study.
//! Run with `--nocapture` to print the module graph (`module -> dependencies`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The layers of `src/lib.rs`, lowest first.
const LAYERS: &[&[&str]] = &[
    &["error", "stats", "progress", "provenance", "dd"],
    &["system", "linalg", "conditioning"],
    &["model", "strategy", "metrics", "scene", "plot"],
    &[
        "sweep",
        "perf",
        "stability",
        "cond_cost",
        "engine_scale",
        "forming",
        "study",
    ],
];
const STUDIES: usize = 3;

fn layer(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

fn rust_files(path: &Path, out: &mut Vec<PathBuf>) {
    if path.is_dir() {
        for e in std::fs::read_dir(path).unwrap() {
            rust_files(&e.unwrap().path(), out);
        }
    } else if path.extension().is_some_and(|e| e == "rs") {
        out.push(path.to_path_buf());
    }
}

/// Top-level module → the top-level modules its files name as `crate::X` (code and docs).
fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut g = BTreeMap::new();
    for e in std::fs::read_dir(&src).unwrap() {
        let path = e.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        if name == "lib" || name == "bin" {
            continue;
        }
        let mut files = Vec::new();
        rust_files(&path, &mut files);
        let mut deps = BTreeSet::new();
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            for (i, _) in text.match_indices("crate::") {
                let rest = &text[i + "crate::".len()..];
                let dep: String = rest
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                // `crate::Error`/`crate::Result` are the root re-exports of `error`.
                let dep = if dep.starts_with(char::is_uppercase) {
                    "error".to_string()
                } else {
                    dep
                };
                if !dep.is_empty() && dep != name {
                    deps.insert(dep);
                }
            }
        }
        g.insert(name, deps);
    }
    g
}

/// What breaks the layering in `g`, one line per problem.
fn problems(g: &BTreeMap<String, BTreeSet<String>>) -> Vec<String> {
    let mut problems = Vec::new();
    for (module, deps) in g {
        let Some(l) = layer(module) else {
            problems.push(format!("module `{module}` is in no layer of src/lib.rs"));
            continue;
        };
        for d in deps {
            match layer(d) {
                None => problems.push(format!(
                    "`{module}` names `crate::{d}`, which is in no layer"
                )),
                Some(ld) if ld > l => problems.push(format!(
                    "`{module}` (layer {}) depends on `{d}` (layer {})",
                    l + 1,
                    ld + 1
                )),
                Some(ld) if ld == STUDIES && l == STUDIES => {
                    problems.push(format!("study `{module}` imports study `{d}`"))
                }
                _ => {}
            }
        }
    }
    problems
}

#[test]
fn every_module_is_in_a_layer_and_dependencies_point_down() {
    let g = graph();
    for (module, deps) in &g {
        println!(
            "{module} -> {}",
            deps.iter().cloned().collect::<Vec<_>>().join(", ")
        );
    }
    let p = problems(&g);
    assert!(p.is_empty(), "{}", p.join("\n"));
}

#[test]
fn the_check_finds_edges_and_flags_violations() {
    // The scanner must see real edges, and the rule must reject a study → study edge and an
    // upward edge, or the test above could never fail.
    let g = graph();
    assert!(g["sweep"].contains("strategy"), "{:?}", g["sweep"]);
    assert!(g["metrics"].contains("conditioning"), "{:?}", g["metrics"]);
    let edge =
        |a: &str, b: &str| BTreeMap::from([(a.to_string(), BTreeSet::from([b.to_string()]))]);
    assert_eq!(problems(&edge("stability", "sweep")).len(), 1);
    assert_eq!(problems(&edge("system", "strategy")).len(), 1);
    assert_eq!(problems(&edge("nowhere", "system")).len(), 1);
    assert!(problems(&edge("sweep", "strategy")).is_empty());
}

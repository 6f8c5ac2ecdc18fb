//! The crate's layering (`src/lib.rs`, "Layers"): every `crate::X` reference in a module's
//! files points to the same or a lower layer, the module graph has no circle, no study refers to
//! another study (only to the studies' support modules), and every experiment binary has its
//! study at `src/study/<binary>`. The nodes are the top-level modules of `src/` and, for
//! `src/study/`, each of its children (`study::sweep`, …). Run with `--nocapture` to print the
//! module graph (`module -> dependencies`). Also the repository's size limits (files,
//! functions) and that the run times the docs state are those `scripts/budgets.sh` measures.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The layers of `src/lib.rs`, lowest first; `study` stands for every `study::X`.
const LAYERS: &[&[&str]] = &[
    &["error", "stats", "progress", "provenance", "dd"],
    &["route"],
    &["system"],
    &["linalg"],
    &["conditioning"],
    &["model", "scene"],
    &["strategy"],
    &["metrics", "plot", "vtk", "forming", "friction", "generate"],
    &["study"],
];
/// Children of `src/study/` that are no binary's study but shared by studies.
const STUDY_SUPPORT: &[&str] = &[
    "study::text",
    "study::forming_runs",
    "study::shape",
    "study::out_guard",
    "study::checkpoint",
    "study::grid",
    "study::hertz",
    "study::outcomes",
];

fn layer(module: &str) -> Option<usize> {
    let key = if module.starts_with("study::") {
        "study"
    } else {
        module
    };
    LAYERS.iter().position(|l| l.contains(&key))
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

/// Every `.rs` file under `src/`.
fn src_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    rust_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut files,
    );
    files
}

fn ident(s: &str) -> String {
    s.chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
        .collect()
}

/// The nodes: `(name, files)` for every top-level module and every child of `src/study/`.
fn nodes() -> Vec<(String, Vec<PathBuf>)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut out = Vec::new();
    for e in std::fs::read_dir(&src).unwrap() {
        let path = e.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        if name == "lib" || name == "bin" || name == "study" {
            continue;
        }
        let mut files = Vec::new();
        rust_files(&path, &mut files);
        out.push((name, files));
    }
    for e in std::fs::read_dir(src.join("study")).unwrap() {
        let path = e.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        if name == "mod" {
            continue;
        }
        let mut files = Vec::new();
        rust_files(&path, &mut files);
        out.push((format!("study::{name}"), files));
    }
    out
}

/// Node → the nodes its files name (`crate::X`, `crate::study::Y`, and a study child's
/// `super::Y`), in code and docs.
fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let mut g = BTreeMap::new();
    for (name, files) in nodes() {
        let mut deps = BTreeSet::new();
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            for (i, _) in text.match_indices("crate::") {
                let rest = &text[i + "crate::".len()..];
                let dep = ident(rest);
                // `crate::Error`/`crate::Result` are the root re-exports of `error`.
                let dep = if dep.starts_with(char::is_uppercase) {
                    "error".to_string()
                } else if dep == "study" {
                    match rest.strip_prefix("study::").map(ident) {
                        Some(child) if !child.is_empty() => format!("study::{child}"),
                        _ => continue,
                    }
                } else {
                    dep
                };
                if !dep.is_empty() && dep != name {
                    deps.insert(dep);
                }
            }
            // A study child's direct `super::X` (not `super::super`) names a sibling, from its
            // top file; deeper files' `super::` stay inside the child.
            let top = f
                .file_stem()
                .is_some_and(|s| s == "mod" || f.parent().is_some_and(|p| p.ends_with("study")));
            if name.starts_with("study::") && top {
                for (i, _) in text.match_indices("super::") {
                    let dep = ident(&text[i + "super::".len()..]);
                    let sibling = format!("study::{dep}");
                    if !dep.is_empty() && dep != "super" && sibling != name {
                        deps.insert(sibling);
                    }
                }
            }
        }
        g.insert(name, deps);
    }
    g
}

/// A circle through `start`, if there is one (depth-first search over the graph).
fn circle(g: &BTreeMap<String, BTreeSet<String>>, start: &str) -> Option<Vec<String>> {
    fn walk(
        g: &BTreeMap<String, BTreeSet<String>>,
        node: &str,
        start: &str,
        path: &mut Vec<String>,
        seen: &mut BTreeSet<String>,
    ) -> bool {
        for d in g.get(node).into_iter().flatten() {
            if d == start {
                return true;
            }
            if seen.insert(d.clone()) {
                path.push(d.clone());
                if walk(g, d, start, path, seen) {
                    return true;
                }
                path.pop();
            }
        }
        false
    }
    let mut path = vec![start.to_string()];
    walk(g, start, start, &mut path, &mut BTreeSet::new()).then(|| {
        path.push(start.to_string());
        path
    })
}

/// What breaks the layering in `g`, one line per problem.
fn problems(g: &BTreeMap<String, BTreeSet<String>>) -> Vec<String> {
    let mut problems = Vec::new();
    for (module, deps) in g {
        let Some(l) = layer(module) else {
            problems.push(format!("module `{module}` is in no layer"));
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
                _ if module.starts_with("study::")
                    && d.starts_with("study::")
                    && !STUDY_SUPPORT.contains(&d.as_str()) =>
                {
                    problems.push(format!("study `{module}` imports study `{d}`"))
                }
                _ => {}
            }
        }
    }
    let mut reported = BTreeSet::new();
    for module in g.keys() {
        if reported.contains(module) {
            continue;
        }
        if let Some(c) = circle(g, module) {
            reported.extend(c.iter().cloned());
            problems.push(format!("import circle: {}", c.join(" -> ")));
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
    // The scanner must see real edges, and the rule must reject a study → study edge, an
    // upward edge and a circle, or the test above could never fail.
    let g = graph();
    assert!(
        g["study::sweep"].contains("strategy"),
        "{:?}",
        g["study::sweep"]
    );
    assert!(g["metrics"].contains("conditioning"), "{:?}", g["metrics"]);
    assert!(g["study::deep_drawing"].contains("study::forming_runs"));
    let edges = |e: &[(&str, &str)]| {
        let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (a, b) in e {
            g.entry(a.to_string()).or_default().insert(b.to_string());
            g.entry(b.to_string()).or_default();
        }
        g
    };
    assert_eq!(
        problems(&edges(&[("study::stress", "study::sweep")])).len(),
        1
    );
    assert!(problems(&edges(&[("study::sweep", "study::text")])).is_empty());
    assert_eq!(problems(&edges(&[("system", "strategy")])).len(), 1);
    assert_eq!(problems(&edges(&[("nowhere", "system")])).len(), 1);
    assert!(problems(&edges(&[("study::sweep", "strategy")])).is_empty());
    let c = problems(&edges(&[
        ("model", "dd"),
        ("dd", "scene"),
        ("scene", "model"),
    ]));
    assert!(
        c.contains(&"import circle: dd -> scene -> model -> dd".to_string()),
        "{c:?}"
    );
}

/// Every binary in `experiments/` has its study at `src/study/<binary>/`.
#[test]
fn every_binary_has_its_study() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for e in std::fs::read_dir(root.join("experiments")).unwrap() {
        let path = e.unwrap().path();
        // `experiments/alias/`: former names of binaries, each compiling its binary's file.
        if !path.is_file() {
            continue;
        }
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let study = root.join("src/study");
        assert!(
            study.join(&name).join("mod.rs").is_file(),
            "experiments/{name}.rs has no study at src/study/{name}/"
        );
        // Every binary is a few lines through the shared entry.
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.lines().count() <= 60 && text.contains("study::main::<"),
            "experiments/{name}.rs: over 60 lines or not through study::main"
        );
        // Every study has mod.rs, figures.rs and report.rs: `solve` and `cond` draw nothing; the forming
        // experiments' files are `forming_runs`'s.
        let dir = match name.as_str() {
            "deep_drawing" | "stretch_test" => study.join("forming_runs"),
            _ => study.join(&name),
        };
        for file in ["figures.rs", "report.rs"] {
            if matches!(name.as_str(), "solve" | "cond") && file == "figures.rs" {
                continue;
            }
            assert!(dir.join(file).is_file(), "{} lacks {file}", dir.display());
        }
    }
}

/// No file under `src/` is over 800 lines (a module that grows past it is split by concern).
#[test]
fn no_source_file_over_800_lines() {
    let long: Vec<String> = src_files()
        .iter()
        .filter_map(|f| {
            let n = std::fs::read_to_string(f).unwrap().lines().count();
            (n > 800).then(|| format!("{} ({n} lines)", f.display()))
        })
        .collect();
    assert!(long.is_empty(), "{}", long.join("\n"));
}

/// The module path of every file under `src/` (`conditioning::sparse` for
/// `src/conditioning/sparse/mod.rs`), with the file's code: comment lines and the
/// `#[cfg(test)]` tail removed.
fn file_modules() -> BTreeMap<String, String> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut out = BTreeMap::new();
    for f in src_files() {
        let rel = f.strip_prefix(&src).unwrap().with_extension("");
        let mut parts: Vec<String> = rel
            .components()
            .map(|c| c.as_os_str().to_string_lossy().to_string())
            .collect();
        if matches!(
            parts.last().map(String::as_str),
            Some("mod" | "lib" | "main")
        ) {
            parts.pop();
        }
        let text = std::fs::read_to_string(&f).unwrap();
        let code = text.split("#[cfg(test)]").next().unwrap_or("");
        let code: String = code
            .lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n");
        out.insert(parts.join("::"), code);
    }
    out
}

/// File → the files it imports from: every `crate::a::b`, `super::a`, `self::a` path and
/// `{…}` group in its code, resolved to the longest module with a file. An edge to the file's
/// own ancestor module (a child naming its parent's items) is not counted: the parent
/// declares the child, as every Rust module tree does.
fn file_graph() -> BTreeMap<String, BTreeSet<String>> {
    let files = file_modules();
    let resolve = |segs: &[String]| -> Option<String> {
        (1..=segs.len())
            .rev()
            .map(|k| segs[..k].join("::"))
            .find(|m| files.contains_key(m))
    };
    let mut g = BTreeMap::new();
    for (module, code) in &files {
        let here: Vec<String> = if module.is_empty() {
            Vec::new()
        } else {
            module.split("::").map(String::from).collect()
        };
        let mut deps = BTreeSet::new();
        for base in ["crate::", "super::", "self::"] {
            for (i, _) in code.match_indices(base) {
                if i > 0 && code[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
                    continue;
                }
                let root: Vec<String> = match base {
                    "crate::" => Vec::new(),
                    "super::" => here[..here.len().saturating_sub(1)].to_vec(),
                    _ => here.clone(),
                };
                let rest = &code[i + base.len()..];
                // The path's segments, then a `{…}` group's first segments.
                let mut segs = root.clone();
                let mut r = rest;
                loop {
                    let id = ident(r);
                    if id.is_empty() || id == "super" {
                        break;
                    }
                    segs.push(id.clone());
                    r = &r[id.len()..];
                    match r.strip_prefix("::") {
                        Some(t) => r = t,
                        None => break,
                    }
                }
                let mut targets = vec![segs.clone()];
                if let Some(group) = r.strip_prefix('{') {
                    let group = group.split('}').next().unwrap_or("");
                    for item in group.split(',') {
                        let id = ident(item.trim());
                        if !id.is_empty() && id != "self" {
                            let mut s = segs.clone();
                            s.push(id);
                            targets.push(s);
                        }
                    }
                }
                for t in targets {
                    if let Some(dep) = resolve(&t) {
                        let ancestor = module.starts_with(&format!("{dep}::")) || dep.is_empty();
                        if dep != *module && !ancestor {
                            deps.insert(dep);
                        }
                    }
                }
            }
        }
        g.insert(module.clone(), deps);
    }
    g
}

/// No two files import from each other, directly or around a circle.
#[test]
fn no_import_circle_between_files() {
    let g = file_graph();
    assert!(
        g["conditioning::sparse"].contains("conditioning::bracket"),
        "the scanner sees no edges: {:?}",
        g["conditioning::sparse"]
    );
    let circles: Vec<String> = g
        .keys()
        .filter_map(|f| circle(&g, f))
        .map(|c| c.join(" -> "))
        .collect();
    assert!(circles.is_empty(), "{}", circles.join("\n"));
}

/// The functions of `text` longer than `limit` lines, from the `fn` line to its closing brace
/// (braces in strings, chars and comments skipped): `(name, first line, lines)`.
fn long_functions(text: &str, limit: usize) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let code = |l: &str| -> String {
        // Drop string and char literals and a trailing comment (enough for brace counting).
        let mut out = String::new();
        let mut chars = l.chars().peekable();
        while let Some(c) = chars.next() {
            match c {
                '"' => {
                    while let Some(d) = chars.next() {
                        if d == '\\' {
                            chars.next();
                        } else if d == '"' {
                            break;
                        }
                    }
                }
                '\'' if matches!(chars.clone().nth(1), Some('\'')) => {
                    chars.next();
                    chars.next();
                }
                '/' if chars.peek() == Some(&'/') => break,
                _ => out.push(c),
            }
        }
        out
    };
    let mut found = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        let t = l.trim_start();
        if t.starts_with("//") {
            continue;
        }
        let Some(at) = t.find("fn ") else { continue };
        let head = &t[..at];
        let is_item = head.split_whitespace().all(|w| {
            matches!(w, "pub" | "const" | "unsafe" | "async" | "extern") || w.starts_with("pub(")
        });
        if !is_item {
            continue;
        }
        let name = ident(&t[at + 3..]);
        let (mut depth, mut started) = (0i64, false);
        for (j, l2) in lines.iter().enumerate().skip(i) {
            let c = code(l2);
            if !started && c.contains(';') && !c.contains('{') {
                break;
            }
            for ch in c.chars() {
                match ch {
                    '{' => {
                        depth += 1;
                        started = true;
                    }
                    '}' => depth -= 1,
                    _ => {}
                }
            }
            if started && depth == 0 {
                let n = j - i + 1;
                if n > limit {
                    found.push((name.clone(), i + 1, n));
                }
                break;
            }
        }
    }
    found
}

/// No function under `src/` is over 120 lines (one that grows past it is split into named
/// steps).
#[test]
fn no_function_over_120_lines() {
    let sample = "fn short() {\n    let s = \"{\";\n}\n\npub fn long() {\n".to_string()
        + &"    x();\n".repeat(130)
        + "}\n";
    assert_eq!(long_functions(&sample, 120), vec![("long".into(), 5, 132)]);
    let long: Vec<String> = src_files()
        .iter()
        .flat_map(|f| {
            let text = std::fs::read_to_string(f).unwrap();
            long_functions(&text, 120)
                .into_iter()
                .map(move |(name, line, n)| format!("{}:{line} {name} ({n} lines)", f.display()))
        })
        .collect();
    assert!(long.is_empty(), "{}", long.join("\n"));
}

/// Every run time of `scripts/budgets.tsv` (which `scripts/budgets.sh` measures) is what the
/// documents it names state: each states it on a line that names the command's binary, and
/// the binary exists.
#[test]
fn stated_run_times_are_the_budgets() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read =
        |f: &str| std::fs::read_to_string(root.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
    let table = read("scripts/budgets.tsv");
    let mut rows = 0;
    let mut wrong = Vec::new();
    for line in table
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let cols: Vec<&str> = line.split('\t').collect();
        assert_eq!(
            cols.len(),
            5,
            "budgets.tsv, five tab-separated columns: {line}"
        );
        let (name, seconds, stated, files, command) = (cols[0], cols[1], cols[2], cols[3], cols[4]);
        assert!(
            seconds
                .parse::<f64>()
                .is_ok_and(|s| s > 0.0 && s.is_finite()),
            "{name}: seconds {seconds}"
        );
        let bin = command.split_whitespace().next().unwrap_or("");
        assert!(
            root.join(format!("experiments/{bin}.rs")).exists(),
            "{name}: no binary {bin}"
        );
        for f in files.split(',') {
            if !read(f)
                .lines()
                .any(|l| l.contains(stated) && l.contains(bin))
            {
                wrong.push(format!(
                    "{f} does not state \"{stated}\" for {name} ({bin})"
                ));
            }
        }
        rows += 1;
    }
    assert!(rows >= 10, "budgets.tsv has {rows} rows");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

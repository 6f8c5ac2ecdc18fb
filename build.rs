//! Embeds, for provenance records, the versions of the main dependencies (from Cargo.lock)
//! and the git commit the binary was built from, with `-dirty` when tracked files differed
//! from it (so a binary run from any directory records its own source, not the caller's).
fn git(args: &[&str]) -> Option<String> {
    let o = std::process::Command::new("git").args(args).output().ok()?;
    o.status
        .success()
        .then(|| String::from_utf8_lossy(&o.stdout).trim().to_string())
}

fn main() {
    println!("cargo:rerun-if-changed=Cargo.lock");
    // Re-run when the sources or the checkout's HEAD/index change (commit, checkout, edit).
    for p in [
        "src",
        "experiments",
        "benches",
        "examples",
        "Cargo.toml",
        "build.rs",
        ".git/HEAD",
        ".git/index",
    ] {
        println!("cargo:rerun-if-changed={p}");
    }
    // A commit on a branch moves the branch's ref, not .git/HEAD: watch the ref too.
    if let Some(r) = std::fs::read_to_string(".git/HEAD")
        .ok()
        .and_then(|h| h.strip_prefix("ref: ").map(|r| r.trim().to_string()))
    {
        // (A watched path that does not exist would re-run this script on every build.)
        for p in [format!(".git/{r}"), ".git/packed-refs".to_string()] {
            if std::path::Path::new(&p).exists() {
                println!("cargo:rerun-if-changed={p}");
            }
        }
    }
    let commit = match git(&["rev-parse", "HEAD"]) {
        Some(sha) => {
            let dirty = git(&["status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty());
            if dirty {
                format!("{sha}-dirty")
            } else {
                sha
            }
        }
        None => "unknown".to_string(),
    };
    println!("cargo:rustc-env=PENALTY_LAB_GIT_COMMIT={commit}");
    let lock = std::fs::read_to_string("Cargo.lock").unwrap_or_default();
    let wanted = [
        "faer",
        "nalgebra",
        "rayon",
        "plotters",
        "rand_chacha",
        "serde_json",
    ];
    let mut out = Vec::new();
    let mut name: Option<String> = None;
    for line in lock.lines() {
        if let Some(n) = line.strip_prefix("name = ") {
            name = Some(n.trim_matches('"').to_string());
        } else if let Some(v) = line.strip_prefix("version = ") {
            if let Some(n) = name.take() {
                if wanted.contains(&n.as_str()) {
                    out.push(format!("{n}={}", v.trim_matches('"')));
                }
            }
        }
    }
    println!("cargo:rustc-env=PENALTY_LAB_DEP_VERSIONS={}", out.join(";"));
}

//! Provenance: the recorded git commit is the one the binary was built from, whatever the
//! directory it runs in (issue: a binary run from elsewhere recorded the caller's commit).

use penalty_lab::provenance::git_commit;

#[test]
fn commit_is_captured_at_build_time() {
    let here = git_commit();
    let checkout = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(".git");
    if !checkout.exists() {
        assert_eq!(here, "unknown");
        return;
    }
    // Built from a git checkout (CI clones it): a full SHA, maybe `-dirty`.
    let sha = here.strip_suffix("-dirty").unwrap_or(&here);
    assert_eq!(sha.len(), 40, "{here}");
    assert!(sha.chars().all(|c| c.is_ascii_hexdigit()), "{here}");
    // Running elsewhere does not change it (this test binary is its own process).
    std::env::set_current_dir(std::env::temp_dir()).unwrap();
    assert_eq!(git_commit(), here);
}

#[test]
fn atomic_writes_leave_only_the_file() {
    use penalty_lab::provenance::{write_atomic, write_json, Provenance};
    let tmp = tempfile::tempdir().expect("create a temporary folder");
    let dir = tmp.path();
    let path = dir.join("a.txt");
    write_atomic(&path, b"first").unwrap();
    write_atomic(&path, b"second").unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "second");
    let rec = Provenance::new("test").record(serde_json::json!({"seed": 7}));
    write_json(&dir.join("r.json"), &rec).unwrap();
    let names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "temporary files left behind: {names:?}");
    let back: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("r.json")).unwrap()).unwrap();
    assert_eq!(back["experiment"], "test");
    assert_eq!(back["seed"], 7);
    assert_eq!(back["git_commit"], git_commit().as_str());
    // A folder that does not exist: an error naming it, nothing written.
    let missing = dir.join("missing").join("b.txt");
    let err = write_atomic(&missing, b"x").unwrap_err().to_string();
    assert!(err.contains("missing"), "{err}");
}

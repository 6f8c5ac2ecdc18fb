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

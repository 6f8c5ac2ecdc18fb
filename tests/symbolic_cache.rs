//! The process-wide symbolic-analysis cache of `SparseLlt::analyze` (its own test binary:
//! tests running in parallel threads of one process would share and evict entries).

#[path = "common/mod.rs"]
mod common;

use common::matrices::{laplacian_2d, sparse_of};

/// One symbolic analysis per pattern: a second analysis of an identical pattern (other
/// values) is the cached one; another pattern gets its own.
#[test]
fn symbolic_analysis_is_shared_by_identical_patterns() {
    use penalty_lab::linalg::SparseLlt;
    use std::sync::Arc;
    let a = laplacian_2d(23, 1.0);
    let b = laplacian_2d(23, 7.0);
    let c = laplacian_2d(24, 1.0);
    let sa = SparseLlt::analyze(sparse_of(&a)).unwrap();
    let sb = SparseLlt::analyze(sparse_of(&b)).unwrap();
    let sc = SparseLlt::analyze(sparse_of(&c)).unwrap();
    assert!(Arc::ptr_eq(&sa, &sb));
    assert!(!Arc::ptr_eq(&sa, &sc));
    // The shared analysis factors the other matrix correctly: log det of the 7× matrix.
    let fb = SparseLlt::factorize(sb, sparse_of(&b)).unwrap();
    let fa = SparseLlt::factorize(sa, sparse_of(&a)).unwrap();
    let ld = |f: &SparseLlt| f.l_diagonal().iter().map(|d| 2.0 * d.log10()).sum::<f64>();
    let n = a.n() as f64;
    let expect = ld(&fa) + n * 7f64.log10();
    assert!((ld(&fb) - expect).abs() <= 64.0 * n * f64::EPSILON * expect.abs());
}

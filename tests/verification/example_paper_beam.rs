//! The `paper_beam` example (examples/paper_beam.rs) runs and reproduces the paper's printed
//! cond₂(K) (Eq. 31), ε of Eq. 28 and cond₂(K + ε) (Eq. 35) at their printed precision.

#[allow(dead_code)] // the example's `main` is not called here
#[path = "../../examples/paper_beam.rs"]
mod example;

use penalty_lab::study::paper_beam::printed::{agrees, EQ31_COND_K, EQ35_COND, EQ35_EPS};

#[test]
fn example_reproduces_the_printed_numbers() {
    let (cond_k, rows) = example::run().expect("the example runs");
    assert!(agrees(cond_k, EQ31_COND_K), "cond2(K) = {cond_k}");
    let (name, eps, cond) = &rows[1];
    assert_eq!(name, "paper");
    for (e, printed) in eps.iter().zip(EQ35_EPS) {
        assert!(agrees(*e, printed), "eps {e} vs {printed}");
    }
    assert!(agrees(*cond, EQ35_COND), "cond2(K + eps) = {cond}");
    // The classical ε = 1e4 system is worse conditioned than the paper's (its point).
    assert!(rows[0].2 > *cond, "{rows:?}");
}

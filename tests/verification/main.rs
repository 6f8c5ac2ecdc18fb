//! Verification against what does not come from this code: the paper's printed numbers, high-precision and rational references, closed forms, independent implementations of the kernels, and physics self-checks of the forming solver.
//!
//! One test binary per tier (`cargo test --release --test verification`); tests that need a
//! process of their own (process-wide caches, the working directory) stay in single files.

#[path = "../common/mod.rs"]
mod common;

mod amg;
mod cond_adversarial;
mod cond_reference;
mod contact_bench;
mod coupled;
mod dd_vs_faer_fx128;
mod elasticity;
mod example_paper_beam;
mod forming_convergence;
mod forming_element;
mod forming_sim;
mod kernels;
mod optimal;
mod paper_beam;
mod saddle_cond;
mod saddle_rows;
mod solver_cost;
mod sparse_cond;
mod stress;
mod two_body;
mod verdict;

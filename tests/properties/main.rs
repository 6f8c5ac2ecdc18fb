//! Property tests (proptest, seeded, regressions committed beside each file): the accuracy contract of cond₂ on random SPD matrices, the readers under fuzzing, randomized contact scenes, the sweep's generators.
//!
//! One test binary per tier (`cargo test --release --test properties`); tests that need a
//! process of their own (process-wide caches, the working directory) stay in single files.

#[path = "../common/mod.rs"]
mod common;

mod cond_properties;
mod fuzz_readers;
mod properties;
mod sweep_props;

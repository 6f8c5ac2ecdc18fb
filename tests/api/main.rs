//! The library's behaviour through its public API, one module per area of `src/`: each strategy's defining property, the solve engine, the elimination route, `condensed`'s δ guarantee, the structure-aware routes, scene files.
//!
//! One test binary per tier (`cargo test --release --test api`); tests that need a
//! process of their own (process-wide caches, the working directory) stay in single files.

#[path = "../common/mod.rs"]
mod common;

mod checkpoints;
mod cond_scaling;
mod cond_starts;
mod condensed_delta;
mod constraint_rows;
mod eliminated;
mod engine;
mod krylov_to_err;
mod near_null_scenes;
mod scene_fuzz;
mod scene_reading;
mod scene_round_trips;
mod scene_support;
mod scene_validation;
mod strategy_consistency;
mod strategy_errors;
mod strategy_exact_delta;
mod strategy_formulas;
mod strategy_lagrange;
mod strategy_support;
mod structure_routes;

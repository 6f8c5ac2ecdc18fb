//! CLI smoke and contract tests of the binaries (`experiments/`): outputs, exit statuses, `--render-only`, determinism; and the figure helpers they draw with.
//!
//! One test binary per tier (`cargo test --release --test cli`); tests that need a
//! process of their own (process-wide caches, the working directory) stay in single files.

#[path = "../common/mod.rs"]
mod common;

mod cond_accuracy_cli;
mod cond_cli;
mod cond_cost_cli;
mod contact_bench_cli;
mod forming_cli;
mod friction_bench_cli;
mod out_guard;
mod paper_beam_cli;
mod penalty_scaling_cli;
mod plot_smoke;
mod runtime_vs_error_cli;
mod solve_cli;
mod solver_cost_cli;
mod study_entry;
mod sweep_config_errors;
mod sweep_figures;
mod sweep_resume;
mod sweep_run_outputs;
mod sweep_scene_files;
mod sweep_shards;
mod sweep_solve_agreement;
mod sweep_support;

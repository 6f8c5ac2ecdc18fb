//! Studies: one experiment of the paper reproduced end to end as library code. A study
//! computes and returns its record; its drawings and its report are functions of the record;
//! it never prints. Every binary in `experiments/` is `study::main::<TheStudy>()`: the shared
//! entry ([`main`]) parses the flags, runs the study, saves and reloads its record, renders
//! its drawings and prints.
//!
//! One module per binary in `experiments/`, named like it (`tests/architecture.rs` checks
//! it): [`sweep`], [`solve`], [`cond`], [`paper_beam`], [`deep_drawing`], [`stretch_test`],
//! [`runtime_vs_error`], [`stress`], [`cond_cost`], [`cond_accuracy`], [`engine_scale`],
//! [`contact_bench`], [`solver_cost`], [`penalty_scaling`], [`friction_bench`]. Each has `mod.rs` (configuration, record and run), `figures.rs` and
//! `report.rs` (`solve` and `cond` draw nothing and have no `figures.rs`; [`deep_drawing`] and
//! [`stretch_test`] declare an experiment whose files are [`forming_runs`]'s; `stretch_test`
//! adds its own `--json` summary in `report.rs`). No study
//! imports another; what several share is a support module: [`text`] (number formats,
//! aligned tables and wrapped notes of the printed reports), [`shape`] (the one shape of a
//! study, [`Study`], and the entry every study binary goes through, [`main`]), [`grid`]
//! (knob grids), [`outcomes`] (rows solved, failed and skipped per method: the summary at the end of a run and its exit status 4), [`hertz`] (the contact benchmarks' cases, meshes and analytic solutions,
//! shared by `contact_bench` and `solver_cost`) and [`forming_runs`] (the forming
//! experiments' runs, records and figures).

pub mod checkpoint;
pub mod cond;
pub mod cond_accuracy;
pub mod cond_cost;
pub mod contact_bench;
pub mod deep_drawing;
pub mod engine_scale;
pub mod forming_runs;
pub mod friction_bench;
pub mod grid;
pub mod hertz;
pub mod out_guard;
pub mod outcomes;
pub mod paper_beam;
pub mod penalty_scaling;
pub mod runtime_vs_error;
pub mod shape;
pub mod solve;
pub mod solver_cost;
pub mod stress;
pub mod stretch_test;
pub mod sweep;
pub mod text;

pub use shape::{main, Drawing, RunContext, Study};

//! Studies: one experiment of the paper reproduced end to end as library code. A study
//! computes, returns its record (and the data behind its figures) and renders figures from the
//! saved files; it never prints. The binaries in `experiments/` only parse flags, call the
//! study, write its record and print.
//!
//! One module per binary in `experiments/`, named like it (`tests/architecture.rs` checks
//! it): [`sweep`], [`solve`], [`paper_beam`], [`deep_drawing`], [`stretch_test`],
//! [`runtime_vs_error`], [`stress`], [`cond_cost`], [`cond_accuracy`], [`engine_scale`]. No
//! study imports another; what several share is a support module: [`text`] (number formats,
//! aligned tables and wrapped notes of the printed reports), [`shape`] (the one shape of a
//! study, [`Study`], and the entry every study binary goes through, [`main`]) and
//! [`forming_runs`] (the forming
//! experiments' runs, records and figures).

pub mod cond_accuracy;
pub mod cond_cost;
pub mod contact_bench;
pub mod deep_drawing;
pub mod engine_scale;
pub mod forming_runs;
pub mod paper_beam;
pub mod runtime_vs_error;
pub mod shape;
pub mod solve;
pub mod stress;
pub mod stretch_test;
pub mod sweep;
pub mod text;

pub use shape::{main, Drawing, RunContext, Study};

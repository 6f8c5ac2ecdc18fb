//! Axisymmetric rigid-viscoplastic "flow approach" sheet-forming solver (paper sections 2
//! and 5), MFP2D-like.
//!
//! `∫ σ_ij δε̇_ij dΩ = ∫ t_i δv_i d(∂Ω)` (Eq. 1), `ε̇_ij = ½(v_i,j + v_j,i)` (Eq. 2),
//! `s_ij = 2μ* ε̇_ij` (Eq. 3), `μ* = σ̄/(3ε̄̇)` (Eq. 4), discretized to `K[μ*(v)] v = q` (Eq. 6)
//! and solved with penalty contact `(K + D E Dᵀ) v = q + D E û` (Eq. 9) whose penalties come
//! from the classical constant ε, the paper's Eq. 28–29 or the exact `condensed` rule.
//!
//! * [`material`] — Eq. 4 with the hardening of Eq. 38 (as printed and continuous), cut-off.
//! * [`element`] — the 2-node linear bending shell element (velocities + rotation rate).
//! * [`tools`] — punch (hemispherical or flat with profile radius), die.
//! * [`config`] — every parameter, TOML, the Woo-like and Ghosh–Hecker presets.
//! * [`solver`] — steps, Picard on μ*, contact in local nodal axes, friction, telemetry.
//! * [`report`] — JSON/CSV of runs and the figures (Fig. 7 and friends).
//!
//! Units: inch, ton-force, second.
//!
//! ## Fig. 7: what we reproduce and what we do not
//! See `figures/deep_drawing/README.md` for the measured comparison with the paper's statement
//! ("in all but one increment the condition number is improved with the modified approach";
//! first example 2.705e5 classical vs 3.721e2 modified).

// Index loops mirror the element/assembly formulas (i, j are matrix indices).
#![allow(clippy::needless_range_loop)]

pub mod assembly;
pub mod config;
pub mod element;
pub mod experiment;
pub mod material;
pub mod report;
pub mod solver;
pub mod tools;

pub use config::{ContactRule, FormingConfig, ThicknessUpdate};
pub use material::{Hardening, Material};
pub use solver::{RunResult, Simulation, Snapshot, StepRecord};

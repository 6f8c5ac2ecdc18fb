//! Axisymmetric rigid-viscoplastic "flow approach" sheet-forming solver (paper sections 2
//! and 5), MFP2D-like.
//!
//! `∫ σ_ij δε̇_ij dΩ = ∫ t_i δv_i d(∂Ω)` (Eq. 1), `ε̇_ij = ½(v_i,j + v_j,i)` (Eq. 2),
//! `s_ij = 2μ* ε̇_ij` (Eq. 3), `μ* = σ̄/(3ε̄̇)` (Eq. 4), discretized to `K[μ*(v)] v = q` (Eq. 6)
//! and solved with penalty contact `(K + D E Dᵀ) v = q + D E û` (Eq. 9) whose penalties come
//! from the classical constant ε, the paper's Eq. 28–29 (two readings) or the exact `condensed`
//! rule.
//!
//! * [`material`] — Eq. 4 with the hardening of Eq. 38 (as printed and continuous), cut-off.
//! * [`element`] — the 2-node linear bending shell element (velocities + rotation rate).
//! * [`tools`] — punch (hemispherical or flat with profile radius), die.
//! * [`config`] — every parameter, TOML, the Woo-like and Ghosh–Hecker presets.
//! * [`solver`] — steps, Picard on μ*, contact in local nodal axes, friction, telemetry.
//! * [`report`] — JSON/CSV of runs and the figures (Fig. 7 and friends).
//! * [`validity`] — the guards that reject a run outside the model's domain (exit status 3).
//! * [`acceleration`] — Anderson acceleration of the Picard iteration.
//!
//! Units: inch, ton-force, second.
//!
//! ## Fig. 7: what we reproduce and what we do not
//! The paper: with the modified penalty the condition number of the main system is better "in
//! all but one increment" (Fig. 7), and in its first example 3.721e2 against 2.705e5 (×727).
//! Ours (default runs, `figures/deep_drawing/README.md`, `figures/test_example/README.md`):
//! Eq. 28 is better at **every** step (100/100, no exception step), by ×32 to ×1.7e3 (median
//! ×386) on the deep draw and ×214 at the last step of the stretching test; the exact
//! `condensed` rule gains another factor ≈ 3–10. Our absolute condition numbers are ~4 orders
//! higher than the paper's (classical ~1e9 against 2.7e5): K itself is ill-conditioned by the
//! cut-off (μ* spread up to 1e3), the thin sheet's bending/membrane stiffness ratio and the
//! rigid-mode drag; MFP2D's scaling is not published. The literal Eq. 28 does **not** keep the
//! penetration below δ (up to ≈ 660 δ on the draw, where stationary die nodes get ε ≤ 0, are
//! clipped and released) and its Picard loop converges in about a third of the steps;
//! `condensed` keeps every penetration ≤ δ.
//!
//! ## Modelling choices (defaults in [`config::FormingConfig`])
//! * μ* through the thickness from the RMS rate ([`config::MuThroughThickness`]); per-layer
//!   μ* makes Picard drift in plastic-hinge modes, mid-surface μ* over-stiffens pure bending.
//! * Picard with Anderson acceleration (depth 3, [`acceleration`]), converged on the nodal
//!   velocities (`v_r`, `v_z`) at 1e-3 relative with an unchanged contact set, capped at 40
//!   iterations; a capped step is recorded with its final change and counted in the summary.
//! * Contact constraints are offered to the strategies as `bilateral` on the Picard-level
//!   contact set (D holds only the active contact DOFs, as in the paper's Eq. 7); the set is
//!   updated every iteration (tensile contacts released, penetrating candidates added).
//! * The blank holder is a prescribed force (nodal loads) — not a kinematic stop.
//! * Rigid-mode drag 1e-10 · max K_zz on every v_z (K must be invertible for `condensed`).

// Index loops mirror the element/assembly formulas (i, j are matrix indices).
#![allow(clippy::needless_range_loop)]

pub mod acceleration;
pub mod assembly;
pub mod config;
pub mod element;
pub mod experiment;
pub mod material;
pub mod report;
pub mod solver;
pub mod tools;
pub mod validity;

pub use config::{ContactRule, FormingConfig, ThicknessUpdate};
pub use material::{Hardening, Material};
pub use solver::{RunResult, Simulation, Snapshot, StepRecord};

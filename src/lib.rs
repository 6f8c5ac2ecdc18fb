//! # penalty-lab
//!
//! A research harness for contact penalty methods and the conditioning of finite-element
//! systems, built around T. Bednarek, P. Kowalczyk, A. Marczewski, W. Sosnowski, *Improvement
//! of stability conditions and uniqueness of penalty approach in contact modelling in sheet
//! metal forming*, Computer Methods in Materials Science (2011) — "the paper".
//!
//! The paper replaces the user-chosen penalty factor ε by an allowed penetration δ and computes
//! ε per contact DOF (Eq. 17, 28–29). This crate implements that, the classical alternatives and
//! an exact δ-targeting penalty side by side, with exact condition numbers for every solve.
//!
//! ## Tour
//! * [`system`] — K (dense or sparse), q, constraints (`bilateral`/`upper`/`lower`), gaps.
//! * [`strategy`] — the eight built-in strategies, their registry ([`strategy::registry`],
//!   where a rule from outside the crate joins) and [`strategy::solve`].
//! * [`metrics`] / [`conditioning`] — cond₂ with its accuracy contract and bounds (route
//!   recorded; what the bounds prove: [`conditioning::certify`]), log10|det|, ratios.
//! * [`linalg`] — factorize once, solve many; log-det from the factor.
//! * [`model`] — the 1-DOF spring (Eq. 10–17), Euler–Bernoulli beams (Eq. 30–34), the 5-point
//!   membrane, Q4 elasticity with rows that couple DOFs (inclined planes, two bodies with
//!   node-to-segment and mortar rows: [`model::two_body`], [`model::cylinder`]); seeded random
//!   scenes of those families ([`generate`]) and scenes that scale to 10⁶ DOFs
//!   ([`model::scalable`]).
//! * [`scene`] — scene files (JSON, Matrix Market) in and out.
//! * [`forming`] — the axisymmetric flow-approach sheet-forming solver (paper sections 2, 5;
//!   Fig. 7).
//! * [`route`] — the one route policy: storage, solve and cond₂ routes from a matrix's
//!   structure.
//! * [`study`] — one study per binary, as library code (the binaries only parse flags and
//!   print): [`study::sweep`] — the ε/δ sweep over generated or stored scenes (rows,
//!   manifest, figures); [`study::paper_beam`] — Sec. 4.2, Eq. 30–37, number by number;
//!   [`study::solve`] — one scene, one strategy; [`study::deep_drawing`] and
//!   [`study::stretch_test`] — the forming examples (Fig. 7); [`study::stress`] — forward
//!   error against an extended-precision reference, refinement, strategies at extreme knobs;
//!   [`study::runtime_vs_error`] — time to solution against error, 1e2–1e6 DOFs;
//!   [`study::cond_cost`] — what an exact cond₂ costs by route; [`study::cond_accuracy`] —
//!   cond₂ by route, time against error; [`study::engine_scale`] — the contact engine from
//!   10⁴ to 10⁶ DOFs.
//! * [`provenance`] — git commit, crate versions and command for every data file.
//! * [`progress`] — one progress bar (with ETA) for every long run; `--quiet` silences it.
//! * [`plot`] — one figure style, PNG + SVG.
//! * [`stats`] — the one median / quantile / log–log slope.
//! * [`dd`] — double-double arithmetic (extended-precision references and certificates).
//!
//! In the repository, `docs/methods.md` gives the equations and algorithms in depth (the
//! solve engine, the cond₂ certificate, the optimal penalty, the forming solver) and
//! `docs/performance.md` the current measurements with their machine and commit (every earlier
//! one: `docs/history/performance-log.md`).
//!
//! ## Using the library: one scene, one strategy, its cond₂
//! The `solve` binary in a few lines — a scene (K, q, constraints), a strategy, the system it
//! ends with and that system's cond₂ with its bounds:
//! ```
//! use penalty_lab::conditioning::cond2;
//! use penalty_lab::metrics::system_matrix;
//! use penalty_lab::model::beam::{Frame, Section};
//! use penalty_lab::strategy::{solve, Method};
//! use penalty_lab::system::{Constraint, ConstraintKind, Problem};
//!
//! // The paper's beam (Eq. 30–34): three frame elements, three bilateral ties.
//! let k = Frame::cantilever(3, 30.0, Section::rectangle(2100.0, 1.0, 1.0))?.assemble(false)?;
//! let q = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -50.0, 1.0, 0.0];
//! let kind = ConstraintKind::Bilateral;
//! let constraints = [(4, 3.0), (6, -1.0), (7, 30.0)]
//!     .map(|(dof, limit)| Constraint::on_dof(dof, limit, kind))
//!     .to_vec();
//! let beam = Problem::new(k, q, constraints)?;
//!
//! // Eq. 28 at δ = 0.1: ε = (501.9, 1390, 557) and cond₂ = 513.871, as the paper prints.
//! let sol = solve(&beam, Method::paper(0.1))?;
//! let c = cond2(&system_matrix(&beam, &sol))?;
//! assert!((c.cond2 - 513.871).abs() < 5e-4);
//! assert!(c.bounds_proven && c.cond2_lo <= c.cond2 && c.cond2 <= c.cond2_hi);
//!
//! // Our exact δ-targeting rule: every gap exactly δ, a better-conditioned system.
//! let exact = solve(&beam, Method::condensed(0.1))?;
//! assert!(exact.gaps.iter().all(|g| (g.abs() - 0.1).abs() < 1e-9));
//! assert!(cond2(&system_matrix(&beam, &exact))?.cond2 < c.cond2);
//! # Ok::<(), penalty_lab::Error>(())
//! ```
//! Scene files: [`scene::read_scene`]; every metric at once: [`metrics::compute`].
//!
//! ## The certified cond₂ of your own matrix
//! A matrix assembled elsewhere, written as Matrix Market (`K.mtx`): its cond₂ = σ_max/σ_min,
//! the bracket proven for the stored matrix, and whether the value is proven within the
//! contract `max(1e-12, 4·ε_mach·cond₂)` — what the `cond` binary prints
//! (`cond K.mtx --json`, [`study::cond`]):
//! ```
//! # let dir = tempfile::tempdir()?;
//! # let path = dir.path().join("K.mtx");
//! # std::fs::write(&path, "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 2\n2 1 -1\n2 2 2\n")?;
//! use penalty_lab::{conditioning::cond2, scene::read_matrix_market};
//! let k = read_matrix_market(&path)?; // e.g. Path::new("K.mtx")
//! let c = cond2(&k)?;
//! println!("cond2 = {:e} in [{:e}, {:e}], route {}", c.cond2, c.cond2_lo, c.cond2_hi, c.route.name());
//! assert!(c.bounds_proven && c.within_contract()); // [[2, -1], [-1, 2]]: cond₂ = 3
//! # assert!((c.cond2 - 3.0).abs() <= 1e-12 * 3.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! **Same bits for any thread count.** The studies parallelise over their own jobs (rayon);
//! faer's dense kernels would otherwise split their work over faer's global pool, whose
//! rounding depends on its size. Every binary therefore runs with
//! `faer::set_global_parallelism(faer::Par::Seq)`; a program that calls the library and wants
//! reproducible bits does the same.
//!
//! ## Features
//! `cli` (on by default) holds what the binaries need beside the numerics: [`study`],
//! [`plot`], [`vtk`] and [`progress`], with clap, plotters, vtkio, indicatif and ctrlc. A crate that only
//! computes depends on `penalty-lab = { version = "0.1", default-features = false }`: systems,
//! strategies, certified cond₂, metrics, models, friction, forming, scenes and provenance
//! (`.ci/run` checks that build with clippy). `lapack` adds the independent LAPACK reference.
//! From Python: the `penalty_lab` module in `python/` (`pip install ./python`).
//!
//! ## Layers
//! Dependencies point down only, the module graph has no circle, no study imports another
//! study, and every binary has its study at `src/study/<binary>` (checked by
//! `tests/architecture.rs`, which also prints the module graph):
//! 1. foundation — `error`, `stats`, `progress` (feature `cli`), `provenance`, `dd`;
//! 2. numerics, bottom up — `route` (the one storage / solve / cond₂ route policy), `system`,
//!    `linalg`, `conditioning`;
//! 3. core — `model`, `scene`; then `strategy`; then `metrics`, `plot`, `vtk` (ParaView
//!    output), `forming`, `friction`, `generate` (the seeded scene families, some calibrated
//!    by a Lagrange solve);
//! 4. studies — `study::<binary>` for every binary, and the support modules `study::text`,
//!    `study::forming_runs` that several studies share;
//! 5. binaries (`experiments/`) — arguments → study → record → figures.
//!
//! ## Glossary (paper symbol → code → units)
//! | paper | code | meaning | units |
//! |---|---|---|---|
//! | **K** | [`system::Problem::k`] | stiffness (flow: viscosity) matrix after essential BCs | force/length |
//! | **q** | [`system::Problem::q`] | load vector | force |
//! | **u** | [`strategy::Solution::u`] | displacements (flow: velocities) | length |
//! | **D** | [`system::Constraint::terms`] | N×m matrix; column c is the row `d_c` of constraint c, its terms (DOF, coefficient); Boolean (column c selects DOF `d_c`) for single-DOF constraints | — |
//! | **û** | [`system::Constraint::limit`] | contact limits | length |
//! | ε, **ε** = D ε̄ Dᵀ | [`strategy::Solution::penalties`] | penalty factor per constraint | force/length |
//! | δ | `delta` in [`strategy::Method`] | allowed penetration | length |
//! | g = Dᵀu − û | [`strategy::Solution::gaps`] | signed gap | length |
//! | K̄ = DᵀKD, q̄ = Dᵀq | [`strategy::paper::eq28`] | reduced system of Eq. 26–27 | — |
//! | S = DᵀK⁻¹D | [`strategy::condensed`] | condensed flexibility (ours) | length/force |
//! | D_ij = ∫N_iN_j, M_ik = ∫N_iN̂_k, ω_i = ∫N_i | [`model::two_body`] | mortar row of slave node i, `(Σ_j D_ij v_j − Σ_k M_ik v_k)/ω_i` (a normalized gap) | length |
//! | E* = E/(1 − ν²); 1/E* = 1/E₁* + 1/E₂* | [`model::elasticity::Material::contact_modulus`], [`model::cylinder::CylinderOnBlock::e_star`] | contact modulus (one body; a pair) | force/length² |
//! | uw(·) | [`conditioning::cond2`] | 2-norm condition number σ_max/σ_min | — |
//! | \|·\| (det) | [`conditioning::log10_abs_det`] | log10 of \|det\| | — |
//! | μ* | [`forming::Material::mu_star`] | viscosity function of Eq. 4, μ* = σ̄/(3ε̄̇) | ton-force·s/in² |
//! | μ | [`friction::FrictionProblem::mu`] | Coulomb's friction coefficient (`|λ_T| ≤ μλ_N`) | — |
//! | λ_N, λ_T | [`friction::Increment::lam_n`], [`friction::Increment::lam_t`] | normal (compressive, ≥ 0) and friction force on the body per contact, along d_N and d_T | force |
//! | ε_T, δ_T | [`friction::TangentRule`] | tangential ("stick") penalty; allowed elastic slip of the δ_T rule, ε_T = μλ_N/δ_T | force/length; length |
//! | σ̄ = σ_y(ε̄) + (ε̄̇/γ)^(1/n) | [`forming::Material::sigma_bar`] | effective stress, Eq. 4 and 38 | ton-force/in² |
//! | v (forming) | `u` of the step's system | nodal velocities and rotation rates | in/s, rad/s |
//! | δ (forming) | [`forming::ContactRule`] | allowed penetration per step; δ/Δt on the normal velocity | in |
//!
//! Sign convention: `K u = q − D r` where r are the contact forces (`r_c = ε_c g_c` for a
//! penalty); an `upper` obstacle (`u ≤ û`) pushes with `r ≥ 0`, a `lower` one with `r ≤ 0`.
#![warn(missing_docs)]

pub mod conditioning;
pub mod dd;
pub mod error;
pub mod forming;
pub mod friction;
pub mod generate;
pub mod linalg;
pub mod metrics;
pub mod model;
#[cfg(feature = "cli")]
pub mod plot;
#[cfg(feature = "cli")]
pub mod progress;
pub mod provenance;
pub mod route;
pub mod scene;
pub mod stats;
pub mod strategy;
#[cfg(feature = "cli")]
pub mod study;
pub mod system;
#[cfg(feature = "cli")]
pub mod vtk;

pub use error::{Error, Result};

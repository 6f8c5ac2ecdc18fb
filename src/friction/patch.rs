//! `patch-two-body-friction`: the two-body contact patch test in full slip — uniform pressure p
//! and shear μp across a non-matching interface.
//!
//! **Bodies** ([`crate::model::two_body::TwoBlocks`]: steel under aluminium, plane strain,
//! uniform Q4 meshes, non-matching at y = H₁). **Exact state:** in both blocks the uniform
//! stress `σ_yy = −p`, `σ_xy = τ = μp`, `σ_xx = 0`, with the upper block slid by S along +x
//! over the lower one. Plane strain: `ε_xx = ν(1 + ν)p/E`, `ε_yy = −p/E*`, `γ = τ/G` in each
//! block, so
//!
//! ```text
//!   lower (0 ≤ y ≤ H₁):     u = ε₁ₓₓ x + γ₁ y,              v = ε₁ᵧᵧ y
//!   upper (y' = y − H₁):    u = ε₂ₓₓ x + γ₁ H₁ + γ₂ y' + S,  v = ε₁ᵧᵧ H₁ + ε₂ᵧᵧ y'
//! ```
//!
//! with p from the squeeze w as in the frictionless patch test (`v = −w` at the top). The
//! lower block's base and the upper block's top are held at these values; the four side
//! faces carry the exact tractions (`t = (0, ∓τ)` on the left/right faces: consistent nodal
//! forces, exact for a uniform traction); the interface is free. The relative slip at the
//! interface, `(ε₂ₓₓ − ε₁ₓₓ) x + S`, is positive everywhere for S = [`SLIDE`]·w, so one load
//! increment from the unloaded state is in full slip: friction on the upper body is −μp per
//! unit length, on the lower one +μp. Bilinear elements hold the exact field, so a
//! discretization that transmits both tractions consistently (mortar) reproduces it to
//! rounding; one-pass node-to-segment hands the master nodes the wrong shares and fails.
//!
//! **Rows**, per slave node i (upper block's bottom face): the interface rows of
//! [`crate::model::two_body`] on v (normal, `lower`, limit 0) and the same rows on u
//! (tangential: `s = Σ_j D_ij u_j/ω_i − Σ_k M_ik u_k/ω_i`, the relative slip). Read back:
//! `p_i = λ_N,i/ω_i`, `τ_i = −λ_T,i/ω_i` ([`PatchProblem::tractions`]).

use super::FrictionProblem;
use crate::error::{Error, Result};
use crate::model::elasticity::{self, Geometry, Grid};
use crate::model::two_body::{self, Discretization, TwoBlocks};

/// The slide S over the squeeze w.
pub const SLIDE: f64 = 10.0;

/// The case: the blocks, their squeeze, μ and the interface rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchFriction {
    /// The two blocks.
    pub blocks: TwoBlocks,
    /// The squeeze w (length).
    pub squeeze: f64,
    /// Coulomb's μ.
    pub mu: f64,
    /// Mortar or one-pass node-to-segment.
    pub disc: Discretization,
}

/// The built problem with what reads its tractions back.
#[derive(Clone, Debug)]
pub struct PatchProblem {
    /// The frictional problem (one load increment).
    pub problem: FrictionProblem,
    /// The tributary length ω_i of each row's slave node.
    pub weights: Vec<f64>,
    /// The exact pressure p.
    pub pressure: f64,
    /// The exact shear τ = μp.
    pub shear: f64,
}

impl PatchFriction {
    /// The default case: 1 × (0.5 + 0.5) blocks meshed 4 × 2 below and 7 × 2 above,
    /// w = 1e-3, μ = 0.2, mortar rows.
    pub fn standard(disc: Discretization) -> PatchFriction {
        PatchFriction {
            blocks: TwoBlocks::steel_under_aluminium(1.0, (0.5, 0.5), (4, 2), (7, 2)),
            squeeze: 1e-3,
            mu: 0.2,
            disc,
        }
    }

    /// The exact displacement (u, v) at (x, y) of the lower (`upper = false`) or upper block,
    /// y in the block's own coordinates (module doc).
    pub fn exact(&self, upper: bool, x: f64, y: f64) -> (f64, f64) {
        let b = &self.blocks;
        let p = b.exact_pressure(self.squeeze);
        let tau = self.mu * p;
        let strains = |m: &elasticity::Material| {
            let g = m.young / (2.0 * (1.0 + m.poisson));
            (
                m.poisson * (1.0 + m.poisson) * p / m.young,
                -p / m.contact_modulus(),
                tau / g,
            )
        };
        let (e1x, e1y, g1) = strains(&b.lower);
        if !upper {
            return (e1x * x + g1 * y, e1y * y);
        }
        let (e2x, e2y, g2) = strains(&b.upper);
        let slide = SLIDE * self.squeeze;
        (
            e2x * x + g1 * b.h_lower + g2 * y + slide,
            e1y * b.h_lower + e2y * y,
        )
    }

    /// The problem (module doc).
    pub fn problem(&self) -> Result<PatchProblem> {
        let b = &self.blocks;
        Error::positive("patch squeeze w", self.squeeze)?;
        if self.disc == Discretization::Nts2 {
            return Err(Error::unsupported(
                "two-pass node-to-segment rows with friction",
                "mortar or nts-1 (nts-2's rows are dependent)",
            ));
        }
        let lower = Grid::uniform(b.width, b.h_lower, b.mesh_lower.0, b.mesh_lower.1);
        let upper = Grid::uniform(b.width, b.h_upper, b.mesh_upper.0, b.mesh_upper.1);
        let off = 2 * lower.nodes();
        let geometry = Geometry::PlaneStrain;
        let mut t = elasticity::assemble(&lower, geometry, &b.lower)?;
        let tu = elasticity::assemble(&upper, geometry, &b.upper)?;
        t.extend(tu.into_iter().map(|(i, j, v)| (i + off, j + off, v)));
        // Held: the lower base and the upper top, at the exact field.
        let mut fixed = vec![None; off + 2 * upper.nodes()];
        for (i, &x) in lower.xs.iter().enumerate() {
            let (u, v) = self.exact(false, x, 0.0);
            let n = lower.node(i, 0);
            (fixed[2 * n], fixed[2 * n + 1]) = (Some(u), Some(v));
        }
        for (i, &x) in upper.xs.iter().enumerate() {
            let (u, v) = self.exact(true, x, b.h_upper);
            let n = off + 2 * upper.node(i, upper.ny() - 1);
            (fixed[n], fixed[n + 1]) = (Some(u), Some(v));
        }
        let (k, mut q, map) = elasticity::eliminate(&t, &fixed)?;
        // The side faces' tractions (0, ∓τ), consistent nodal forces of each edge.
        let p = b.exact_pressure(self.squeeze);
        let tau = self.mu * p;
        for (grid, base) in [(&lower, 0), (&upper, off)] {
            for (i, sign) in [(0, -1.0), (grid.xs.len() - 1, 1.0)] {
                for j in 0..grid.ny() - 1 {
                    let l = grid.ys[j + 1] - grid.ys[j];
                    for node in [grid.node(i, j), grid.node(i, j + 1)] {
                        let d = map[base + 2 * node + 1];
                        if d != usize::MAX {
                            q[d] += sign * tau * l / 2.0;
                        }
                    }
                }
            }
        }
        let dofs = |grid: &Grid, base: usize, j: usize, c: usize| -> Vec<usize> {
            (0..grid.xs.len())
                .map(|i| map[base + 2 * grid.node(i, j) + c])
                .collect()
        };
        let top = lower.ny() - 1;
        let rows = |c: usize| -> Vec<two_body::Terms> {
            let (sd, md) = (dofs(&upper, off, 0, c), dofs(&lower, 0, top, c));
            match self.disc {
                Discretization::Mortar => {
                    two_body::mortar_rows(&upper.xs, &sd, &lower.xs, &md, geometry)
                }
                _ => upper
                    .xs
                    .iter()
                    .enumerate()
                    .map(|(i, &x)| two_body::nts_terms(x, sd[i], &lower.xs, &md))
                    .collect(),
            }
        };
        let weights = two_body::tributary(&upper.xs, geometry);
        let normal = rows(1).into_iter().map(|r| (r, 0.0)).collect();
        let m = weights.len();
        let g_upper = b.upper.young / (2.0 * (1.0 + b.upper.poisson));
        let layer = b.h_upper / b.mesh_upper.1 as f64;
        let problem = FrictionProblem::new(
            k.in_preferred_storage(),
            vec![q],
            normal,
            rows(0),
            self.mu,
            (weights.clone(), vec![layer; m], g_upper),
        )?;
        Ok(PatchProblem {
            problem,
            weights,
            pressure: p,
            shear: tau,
        })
    }
}

impl PatchProblem {
    /// `(p_i, τ_i)` per row of the last increment of `sol`: `λ_N,i/ω_i`, `−λ_T,i/ω_i`.
    pub fn tractions(&self, sol: &super::FrictionSolution) -> Vec<(f64, f64)> {
        let last = sol.increments.last().expect("one increment");
        self.weights
            .iter()
            .enumerate()
            .map(|(i, w)| (last.lam_n[i] / w, -last.lam_t[i] / w))
            .collect()
    }

    /// The patch test's measure: the largest relative deviation of the rows' pressures from
    /// their mean and of their shears from theirs, `max_i |p_i − p̄|/p̄`, `max_i |τ_i − τ̄|/τ̄`
    /// (Lagrange's means are p and μp; a penalty's uniform state sits at a slightly smaller
    /// p, its penetration taken off the squeeze: not a failure of the patch test).
    pub fn traction_errors(&self, sol: &super::FrictionSolution) -> (f64, f64) {
        let t = self.tractions(sol);
        let n = t.len() as f64;
        let (pm, tm) = t
            .iter()
            .fold((0.0, 0.0), |(a, b), (p, s)| (a + p / n, b + s / n));
        t.iter().fold((0.0f64, 0.0f64), |(ep, et), (p, s)| {
            (ep.max((p - pm).abs() / pm), et.max((s - tm).abs() / tm))
        })
    }
}

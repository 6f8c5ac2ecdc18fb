//! `sliding-block`: an elastic block pressed on a rigid plane and pushed along it.
//!
//! **Geometry** (plane strain, consistent units, E = 1, ν = 0.3): the block `0 ≤ x ≤ W`,
//! `0 ≤ y ≤ H` (W = 2, H = 1) on the rigid plane y = 0, `nx × ny` Q4 elements. Its top face is
//! held by a rigid platen: increment 0 presses it down by `press·H` (travel 0); increments
//! 1..=steps move it along x by `travel·k/steps` at the same depth (displacement control, so
//! the run goes on past the onset of sliding). Every bottom node is a contact: normal row
//! `u_y ≥ 0` (û = 0, the block touches the plane everywhere at the start), tangential row
//! `u_x`, area w = its tributary length, layer h = H/ny.
//!
//! **What it checks.** Pressing alone already sticks the edges (Poisson's expansion meets
//! friction); pushing spreads slip inwards from the trailing and leading edges until every
//! node slides. In full slip every contact carries λ_T = −μλ_N, so `|T|/N = μ` — exactly, for
//! any method whose increment converged: `onset_ratio` tests the law, and the travel at which
//! full slip starts (`onset_travel`) shows a penalty's elastic slip: a soft ε_T lets the
//! platen travel further before the block slides. DOF numbering: node (i, j), i = 0..=nx, j
//! = 0..ny (the top row j = ny is prescribed) has free DOFs `2(i·ny + j) + c`, c = 0 (x),
//! 1 (y), as [`crate::model::incline_block::free_dof`].

use super::FrictionProblem;
use crate::error::{Error, Result};
use crate::model::elasticity::{assemble_mapped, eliminate, Geometry, Material};

/// Width W.
pub const WIDTH: f64 = 2.0;
/// Height H.
pub const HEIGHT: f64 = 1.0;
/// The block's material.
pub const MATERIAL: Material = Material {
    young: 1.0,
    poisson: 0.3,
};

/// The case's knobs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlidingBlock {
    /// Elements along x.
    pub nx: usize,
    /// Elements along y.
    pub ny: usize,
    /// Coulomb's μ.
    pub mu: f64,
    /// The platen's depth over H (increment 0).
    pub press: f64,
    /// The platen's final travel along x (length).
    pub travel: f64,
    /// Push increments after the press.
    pub steps: usize,
}

impl Default for SlidingBlock {
    fn default() -> Self {
        SlidingBlock {
            nx: 16,
            ny: 8,
            mu: 0.2,
            press: 0.01,
            travel: 0.02,
            steps: 20,
        }
    }
}

impl SlidingBlock {
    /// The platen's travel at increment k.
    pub fn travel_at(&self, k: usize) -> f64 {
        self.travel * k as f64 / self.steps as f64
    }

    /// The frictional problem (module doc).
    pub fn problem(&self) -> Result<FrictionProblem> {
        let (nx, ny) = (self.nx, self.ny);
        if nx < 2 || ny < 1 {
            return Err(Error::out_of_range(
                "sliding block elements",
                format!("{nx} × {ny}"),
                "at least 2 × 1",
            ));
        }
        Error::positive("platen depth over H", self.press)?;
        Error::positive("platen travel", self.travel)?;
        if self.steps == 0 {
            return Err(Error::out_of_range("push increments", 0, "≥ 1"));
        }
        let (nnx, nny) = (nx + 1, ny + 1);
        let coords: Vec<(f64, f64)> = (0..nnx)
            .flat_map(|i| {
                (0..nny).map(move |j| {
                    let x = WIDTH * i as f64 / nx as f64;
                    (x, HEIGHT * j as f64 / ny as f64)
                })
            })
            .collect();
        let t = assemble_mapped(&coords, (nnx, nny), Geometry::PlaneStrain, &MATERIAL)?;
        let platen = |ux: f64, uy: f64| {
            let mut fixed = vec![None; 2 * nnx * nny];
            for i in 0..nnx {
                let top = i * nny + ny;
                fixed[2 * top] = Some(ux);
                fixed[2 * top + 1] = Some(uy);
            }
            fixed
        };
        let (k, q_press, map) = eliminate(&t, &platen(0.0, -self.press * HEIGHT))?;
        let (_, q_push, _) = eliminate(&t, &platen(1.0, 0.0))?;
        let loads = (0..=self.steps)
            .map(|s| {
                let tr = self.travel_at(s);
                q_press
                    .iter()
                    .zip(&q_push)
                    .map(|(a, b)| a + tr * b)
                    .collect()
            })
            .collect();
        let dx = WIDTH / nx as f64;
        let (mut normal, mut tangents, mut areas) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..nnx {
            let node = i * nny;
            normal.push((vec![(map[2 * node + 1], 1.0)], 0.0));
            tangents.push(vec![(map[2 * node], 1.0)]);
            areas.push(if i == 0 || i == nx { dx / 2.0 } else { dx });
        }
        let layers = vec![HEIGHT / ny as f64; nnx];
        let g = MATERIAL.young / (2.0 * (1.0 + MATERIAL.poisson));
        FrictionProblem::new(
            k.in_preferred_storage(),
            loads,
            normal,
            tangents,
            self.mu,
            (areas, layers, g),
        )
    }
}

//! `inclined-friction`: the crowned block of [`crate::model::incline_block`] pressed onto the
//! plane inclined at θ, with Coulomb friction on its contact rows.
//!
//! The block, its mesh, the rigid clamp on its top face and the normal rows are those of the
//! frictionless case (`sinθ·u_x + cosθ·u_y ≥ −g₀`, rows that couple a node's two DOFs); the
//! clamp goes down to [`crate::model::incline_block::PRESS`]·H in `steps` equal increments
//! (the load is linear in its depth). Each bottom node adds the tangential row along the plane,
//! down-slope: `s = cosθ·u_x − sinθ·u_y`; its contact length w is its share of the bottom
//! face's width over cosθ (the length along the plane), its layer h the element height H/ny.
//!
//! **What it shows.** Without friction the block's bottom slides down-slope against the plane
//! as the clamp pushes (the clamp carries the tangential load); with friction the contact zone
//! grows a stick core, wider as μ grows, and a penalty's ε_T adds to rows that already couple
//! DOFs: the case of the solver-cost study where a penalty truly costs, now with friction.

use super::FrictionProblem;
use crate::error::{Error, Result};
use crate::model::incline_block::{self, HEIGHT, MATERIAL, WIDTH};

/// The case's knobs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InclinedFriction {
    /// θ in degrees, in (0, 60).
    pub theta_deg: f64,
    /// Elements along x.
    pub nx: usize,
    /// Elements along y.
    pub ny: usize,
    /// Coulomb's μ.
    pub mu: f64,
    /// Press increments.
    pub steps: usize,
}

impl InclinedFriction {
    /// The frictional problem (module doc).
    pub fn problem(&self) -> Result<FrictionProblem> {
        if self.steps == 0 {
            return Err(Error::out_of_range("press increments", 0, "≥ 1"));
        }
        let base = incline_block::problem(self.theta_deg, self.nx, self.ny)?;
        let (s, c) = self.theta_deg.to_radians().sin_cos();
        let loads = (1..=self.steps)
            .map(|k| {
                let t = k as f64 / self.steps as f64;
                base.q.iter().map(|v| t * v).collect()
            })
            .collect();
        let dx = WIDTH / self.nx as f64;
        let (mut normal, mut tangents, mut areas) = (Vec::new(), Vec::new(), Vec::new());
        for (i, con) in base.constraints.iter().enumerate() {
            // The row's terms are (x, sinθ), (y, cosθ) of one node (incline_block's rows).
            let (dx_dof, dy_dof) = (con.terms[0].0, con.terms[1].0);
            normal.push((con.terms.clone(), con.limit));
            tangents.push(vec![(dx_dof, c), (dy_dof, -s)]);
            let share = if i == 0 || i == self.nx { 0.5 } else { 1.0 };
            areas.push(share * dx / c);
        }
        let m = normal.len();
        let g = MATERIAL.young / (2.0 * (1.0 + MATERIAL.poisson));
        FrictionProblem::new(
            base.k,
            loads,
            normal,
            tangents,
            self.mu,
            (areas, vec![HEIGHT / self.ny as f64; m], g),
        )
    }
}

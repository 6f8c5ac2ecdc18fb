//! A block pressed onto a rigid plane inclined by θ: contact rows with two terms (issue 45).
//!
//! Take the flat-punch scene of [`elasticity::indentation`] (a block on a frictionless base,
//! lifted by w against a flat rigid punch on its top) and turn the whole of it by θ
//! counter-clockwise. The unknowns of every node with two free DOFs are then the global
//! displacements `(u_x, u_y) = R(θ)(u_ξ, u_η)` (ξ, η the block's own axes), so with
//! `T = diag(R(θ), …)` over those nodes (identity on the nodes that keep one DOF: the base's
//! rollers and the symmetry line, whose remaining DOF stays in the block's frame — a skew
//! support, as production codes write one)
//!
//! `K' = T K Tᵀ`, `q' = T q`, and the punch row `u_η ≤ û` becomes `n·u ≤ û` with the plane's
//! normal `n = (−sin θ, cos θ)`: two terms per contact node.
//!
//! The physics is the flat punch's, so the exact contact pressure is uniform; what changes is
//! D, which is no longer Boolean: the coupled rows take the general-D routes (`K + D E Dᵀ`
//! with the rows' fill, `S = DᵀK⁻¹D`, the generic saddle route). The rows are unit and share no
//! DOF, so a node's contact force is still `f_c = −d_cᵀ(K'u − q')` and
//! [`Indentation::pressures`] reads it unchanged. `K'` is assembled from `K`'s entries with
//! each product `v·(T_ik·T_jl)` formed once for the pair (i, j) and (j, i), so `K'` is
//! symmetric bit for bit.

use super::elasticity::{self, Indentation};
use crate::error::{Error, Result};
use crate::system::{Constraint, Problem, Stiffness};
use std::collections::BTreeMap;

/// The normal `n = (−sin θ, cos θ)` of the plane inclined by `theta` (radians).
pub fn normal(theta: f64) -> (f64, f64) {
    (-theta.sin(), theta.cos())
}

/// The flat-punch scene `flat` turned by `theta` (radians, |θ| ≤ π/2; module doc). `free` is
/// the global DOF (`2·node + component`) of each of `flat`'s unknowns, in order
/// ([`elasticity::free_dofs`]).
pub fn rotated(flat: &Indentation, free: &[usize], theta: f64) -> Result<Indentation> {
    if !(theta.is_finite() && theta.abs() <= std::f64::consts::FRAC_PI_2) {
        return Err(Error::input(format!(
            "inclination θ must be finite and |θ| ≤ π/2 (got {theta})"
        )));
    }
    let p = &flat.problem;
    if free.len() != p.n() {
        return Err(Error::input(format!(
            "{} DOF numbers for a problem of N = {}",
            free.len(),
            p.n()
        )));
    }
    let (s, c) = theta.sin_cos();
    // The unknown holding each node's other component, where both are free.
    let mut slot: BTreeMap<usize, usize> = BTreeMap::new();
    for (i, &g) in free.iter().enumerate() {
        slot.insert(g, i);
    }
    let partner = |i: usize| slot.get(&(free[i] ^ 1)).copied();
    // Column i of T: the global unknowns a block-frame unknown i contributes to.
    let column = |i: usize| -> Vec<(usize, f64)> {
        match partner(i) {
            None => vec![(i, 1.0)],
            Some(j) if free[i].is_multiple_of(2) => vec![(i, c), (j, s)], // ξ ↦ (c, s)
            Some(j) => vec![(j, -s), (i, c)],                             // η ↦ (−s, c)
        }
    };
    let cols: Vec<Vec<(usize, f64)>> = (0..p.n()).map(column).collect();
    let mut lower: BTreeMap<(usize, usize), f64> = BTreeMap::new();
    let mut err = None;
    p.k.for_each_entry(|i, j, v| {
        for &(a, ta) in &cols[i] {
            for &(b, tb) in &cols[j] {
                if a >= b {
                    *lower.entry((a, b)).or_insert(0.0) += v * (ta * tb);
                }
            }
        }
        if !v.is_finite() {
            err = Some(Error::input("stiffness entry is not finite"));
        }
    });
    if let Some(e) = err {
        return Err(e);
    }
    let mut t = Vec::with_capacity(2 * lower.len());
    for (&(a, b), &v) in &lower {
        t.push((a, b, v));
        if a != b {
            t.push((b, a, v));
        }
    }
    let k = Stiffness::from_triplets(p.n(), &t)?;
    let mut q = vec![0.0; p.n()];
    for (i, &qi) in p.q.iter().enumerate() {
        for &(a, ta) in &cols[i] {
            q[a] += ta * qi;
        }
    }
    let constraints = p
        .constraints
        .iter()
        .map(|con| {
            let d = con
                .single_dof()
                .ok_or_else(|| Error::input("the flat scene's constraints must be single-DOF"))?;
            Ok(Constraint::row(cols[d].clone(), con.limit, con.kind))
        })
        .collect::<Result<Vec<_>>>()?;
    let mut problem = Problem::new(k, q, constraints)?.in_preferred_storage();
    if let Some(surface) = &p.surface {
        problem = problem.with_surface(surface.clone())?;
    }
    Ok(Indentation {
        problem,
        ..flat.clone()
    })
}

/// The flat punch of [`elasticity::indentation`] on `grid` turned by `theta` (radians).
pub fn inclined_punch(
    grid: &elasticity::Grid,
    material: &elasticity::Material,
    lift: f64,
    theta: f64,
) -> Result<Indentation> {
    let flat = elasticity::indentation(
        grid,
        elasticity::Geometry::PlaneStrain,
        material,
        elasticity::Base::Sliding,
        lift,
        |_| 0.0,
    )?
    .with_surface(grid)?;
    let free = elasticity::free_dofs(grid, elasticity::Base::Sliding);
    rotated(&flat, &free, theta)
}

/// The indentation `scene` (one `upper` row `v_i ≤ f(x_i)` per top node, as
/// [`elasticity::indentation`] builds it) with each row taken along the rigid obstacle's
/// normal at the node instead of along y: a curved obstacle with nodal normals (issue 45).
///
/// The obstacle's surface above the node at x is `y = H + f(x)`; its unit normal into the
/// obstacle is `m = (−f'(x), 1)/s`, `s = √(1 + f'(x)²)`, and the distance from the node to the
/// surface's tangent line along m is `f(x)/s`, so the row becomes `m·u ≤ f(x)/s` — two terms
/// where the node's x-DOF is free (one, `v ≤ f`, on the symmetry line, where f' = 0).
/// `free` is the global DOF (`2·node + component`) of each of `scene`'s unknowns, in order
/// ([`elasticity::free_dofs`]); `slope` is f'. Small deformation: the normal is the
/// undeformed one. The rows share no DOF and are unit, so [`Indentation::pressures`] reads
/// the normal pressure.
pub fn with_nodal_normals(
    scene: Indentation,
    free: &[usize],
    slope: impl Fn(f64) -> f64,
) -> Result<Indentation> {
    if free.len() != scene.problem.n() {
        return Err(Error::input(format!(
            "nodal normals: {} free DOFs listed for {} unknowns",
            free.len(),
            scene.problem.n()
        )));
    }
    let mut rows = Vec::with_capacity(scene.problem.m());
    for (con, node) in scene.problem.constraints.iter().zip(&scene.contact) {
        let Some(d) = con.single_dof() else {
            return Err(Error::input(
                "nodal normals: the scene's rows must be single-DOF (v ≤ f)",
            ));
        };
        let fp = slope(node.x);
        if !fp.is_finite() {
            return Err(Error::input(format!(
                "nodal normals: the obstacle's slope is not finite at x = {}",
                node.x
            )));
        }
        let s = fp.hypot(1.0);
        // The node's x-DOF: the global DOF one below its y-DOF, if it is free.
        let ux = free.binary_search(&(free[d] - 1)).ok();
        rows.push(match ux {
            Some(x) if fp != 0.0 => {
                Constraint::row(vec![(x, -fp / s), (d, 1.0 / s)], con.limit / s, con.kind)
            }
            _ => con.clone(),
        });
    }
    let problem = Problem::new(scene.problem.k.clone(), scene.problem.q.clone(), rows)?;
    Ok(Indentation { problem, ..scene })
}

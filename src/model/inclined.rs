//! A block pressed onto a rigid plane inclined by θ: contact rows with two terms.
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
        return Err(Error::out_of_range(
            "inclination θ",
            theta,
            "finite with |θ| ≤ π/2",
        ));
    }
    let p = &flat.problem;
    if free.len() != p.n() {
        return Err(Error::length_mismatch(
            "DOF numbers (one per unknown of the problem)",
            free.len(),
            p.n(),
        ));
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
            err = Some(Error::not_finite("stiffness entry"));
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
            let d = con.single_dof().ok_or_else(|| {
                Error::unsupported("turning the flat scene", "single-DOF constraints")
            })?;
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
/// normal at the node instead of along y: a curved obstacle with nodal normals.
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
        return Err(Error::length_mismatch(
            "nodal normals: free DOFs (one per unknown)",
            free.len(),
            scene.problem.n(),
        ));
    }
    let mut rows = Vec::with_capacity(scene.problem.m());
    for (con, node) in scene.problem.constraints.iter().zip(&scene.contact) {
        let Some(d) = con.single_dof() else {
            return Err(Error::unsupported(
                "nodal normals",
                "the scene's rows single-DOF (v ≤ f)",
            ));
        };
        let fp = slope(node.x);
        if !fp.is_finite() {
            return Err(Error::not_finite(format!(
                "nodal normals: the obstacle's slope at x = {}",
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
    let mut problem = Problem::new(scene.problem.k.clone(), scene.problem.q.clone(), rows)?;
    if let Some(modes) = scene.problem.near_null.clone() {
        problem = problem.with_near_null(modes)?;
    }
    Ok(Indentation { problem, ..scene })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::elasticity::{Base, Geometry, Grid, Material};

    /// The rows of [`with_nodal_normals`] by hand, on a parabolic obstacle y = x²/(2R) with
    /// R = 2 over a 4 × 2 block of width 2: at x = 1 the slope is ½, the unit normal
    /// (−1, 2)/√5 and the limit the vertical one times 2/√5; at x = ½ the slope is ¼, the
    /// normal (−1, 4)/√17; on the symmetry line the row stays `v ≤ f`. The x-term sits on the
    /// node's own x-DOF (global 2·node, beside its y-DOF 2·node + 1).
    #[test]
    fn nodal_normal_rows_by_hand() {
        let grid = Grid::uniform(2.0, 1.0, 4, 2);
        let material = Material {
            young: 100.0,
            poisson: 0.25,
        };
        let r = 2.0;
        let scene = elasticity::indentation(
            &grid,
            Geometry::PlaneStrain,
            &material,
            Base::Clamped,
            0.01,
            |x| x * x / (2.0 * r),
        )
        .unwrap();
        let vertical: Vec<_> = scene.problem.constraints.clone();
        let xs: Vec<f64> = scene.contact.iter().map(|c| c.x).collect();
        let free = elasticity::free_dofs(&grid, Base::Clamped);
        let normals = with_nodal_normals(scene, &free, |x| x / r).unwrap();
        // (x, m_x, m_y, limit / vertical limit), by hand.
        let s17 = 17f64.sqrt();
        let (s5, s2) = (5f64.sqrt(), 2f64.sqrt());
        let table = [
            (0.5, -1.0 / s17, 4.0 / s17, 4.0 / s17),
            (1.0, -1.0 / s5, 2.0 / s5, 2.0 / s5),
            (1.5, -0.6, 0.8, 0.8),
            (2.0, -1.0 / s2, 1.0 / s2, 1.0 / s2),
        ];
        let by_hand = |x: f64| table.iter().find(|t| t.0 == x).map(|t| (t.1, t.2, t.3));
        assert_eq!(xs.len(), 5);
        for ((row, old), &x) in normals.problem.constraints.iter().zip(&vertical).zip(&xs) {
            let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * b.abs().max(1.0);
            match by_hand(x) {
                None => assert_eq!((x, row), (0.0, old), "x = 0: v ≤ f unchanged"),
                Some((mx, my, scale)) => {
                    assert_eq!(row.terms.len(), 2, "x = {x}");
                    let (gx, gy) = (free[row.terms[0].0], free[row.terms[1].0]);
                    assert_eq!(gy, free[old.single_dof().unwrap()], "x = {x}: y-DOF");
                    assert_eq!((gx % 2, gx + 1), (0, gy), "x = {x}: the node's own x-DOF");
                    assert!(close(row.terms[0].1, mx), "x = {x}: {:?}", row.terms);
                    assert!(close(row.terms[1].1, my), "x = {x}: {:?}", row.terms);
                    assert!(
                        close(row.limit, old.limit * scale),
                        "x = {x}: {}",
                        row.limit
                    );
                }
            }
        }
    }
}

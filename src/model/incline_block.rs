//! An elastic block pressed on a rigid plane inclined at θ: contact rows that couple the two
//! DOFs of a node, `sinθ·u_x + cosθ·u_y ≥ −g₀`.
//!
//! **Why.** A single-DOF row adds `ε·e_d e_dᵀ` to K, a diagonal entry that any diagonal
//! preconditioner absorbs. A row along an inclined normal `n = (sinθ, cosθ)` adds the 2×2
//! block `ε·n nᵀ` to a node's DOFs, which is not diagonal: Jacobi scaling leaves a
//! `O(ε)` coupling, and its cond₂ grows with ε. The DOFs and the supports stay axis-aligned
//! (nothing is rotated to the plane's frame), as in a code that meets an inclined obstacle.
//!
//! **Geometry** (plane strain; lengths and E in consistent units, the block's E = 1, ν = 0.3):
//! the plane through the origin descending to the right at θ, `y_p(x) = −x·tanθ`, outward
//! normal `n = (sinθ, cosθ)`. The block occupies `0 ≤ x ≤ W`, `y_b(x) ≤ y ≤ H` with W = 2,
//! H = 1, and its bottom face follows the plane with a parabolic crown,
//! `y_b(x) = y_p(x) + κ(x − W/2)²`, κ = [`CROWN`]: it touches the plane at x = W/2 and the
//! initial normal gap of a bottom node is `g₀(x) = κ(x − W/2)²·cosθ`. The mesh is the
//! `nx × ny`-element tensor grid mapped between `y_b` and H (Q4, [`assemble_mapped`], each
//! entry summed once for both triangles: K is symmetric bit for bit). The
//! top face is clamped and moved by `(0, −d)`, d = [`PRESS`]·H: the block is pressed down
//! onto the plane and contact spreads from the crown (a Hertz-like zone on the incline);
//! the clamp carries the tangential part of the load (the plane is frictionless).
//!
//! **Constraints:** one per bottom node, kind `lower`: `sinθ·u_x + cosθ·u_y ≥ −g₀(x)`
//! (`g = n·u + g₀ ≥ 0`). DOF numbering: node (i, j), i = 0..=nx along x, j = 0..ny up
//! (the top row j = ny is prescribed), has free DOFs `2(i·ny + j) + c`, c = 0 (x), 1 (y)
//! ([`free_dof`]). The problem carries the rigid-body modes of the free nodes
//! ([`NearNull::rigid_body_modes`], block size 2) for a nodal AMG.

use super::elasticity::{assemble_mapped, eliminate, Geometry, Material};
use crate::error::{Error, Result};
use crate::system::{Constraint, ConstraintKind, NearNull, Problem};

/// Width W of the block.
pub const WIDTH: f64 = 2.0;
/// Height H of the block (at its left side above the plane's origin).
pub const HEIGHT: f64 = 1.0;
/// κ of the crown `κ(x − W/2)²` of the bottom face.
pub const CROWN: f64 = 0.1;
/// The top face's prescribed downward displacement over H.
pub const PRESS: f64 = 0.01;
/// The block's material.
pub const MATERIAL: Material = Material {
    young: 1.0,
    poisson: 0.3,
};

/// The triplets with each entry's duplicates summed once, in triplet order, for the pair
/// (i, j) and (j, i) together: a stiffness symmetric bit for bit (summing (i, j) and (j, i)
/// separately may round differently where a mapped mesh's elements differ; CG and the
/// symmetric cond₂ routes need the exact symmetry).
fn symmetric_sums(triplets: &[(usize, usize, f64)]) -> Vec<(usize, usize, f64)> {
    let mut sums: std::collections::BTreeMap<(usize, usize), f64> = Default::default();
    for &(i, j, v) in triplets.iter().filter(|t| t.0 <= t.1) {
        *sums.entry((i, j)).or_insert(0.0) += v;
    }
    sums.into_iter()
        .flat_map(|((i, j), v)| {
            let mirror = (i != j).then_some((j, i, v));
            std::iter::once((i, j, v)).chain(mirror)
        })
        .collect()
}

/// The free DOF of component `c` (0: x, 1: y) of node (i, j), j < ny (module doc).
pub fn free_dof(ny: usize, i: usize, j: usize, c: usize) -> usize {
    2 * (i * ny + j) + c
}

/// The block on the plane inclined at `theta_deg` degrees with `nx × ny` elements (module doc).
pub fn problem(theta_deg: f64, nx: usize, ny: usize) -> Result<Problem> {
    if !(theta_deg > 0.0 && theta_deg < 60.0) {
        return Err(Error::out_of_range(
            "incline angle θ (degrees)",
            theta_deg,
            "in (0, 60)",
        ));
    }
    if nx < 2 || ny < 1 {
        return Err(Error::out_of_range(
            "inclined block elements",
            format!("{nx} × {ny}"),
            "at least 2 × 1",
        ));
    }
    let (s, c) = theta_deg.to_radians().sin_cos();
    let tan = s / c;
    let bottom = |x: f64| -x * tan + CROWN * (x - WIDTH / 2.0).powi(2);
    let (nnx, nny) = (nx + 1, ny + 1);
    let mut coords = Vec::with_capacity(nnx * nny);
    for i in 0..nnx {
        let x = WIDTH * i as f64 / nx as f64;
        let yb = bottom(x);
        for j in 0..nny {
            coords.push((x, yb + (HEIGHT - yb) * j as f64 / ny as f64));
        }
    }
    let triplets = symmetric_sums(&assemble_mapped(
        &coords,
        (nnx, nny),
        Geometry::PlaneStrain,
        &MATERIAL,
    )?);
    let mut fixed = vec![None; 2 * nnx * nny];
    for i in 0..nnx {
        let top = i * nny + ny;
        fixed[2 * top] = Some(0.0);
        fixed[2 * top + 1] = Some(-PRESS * HEIGHT);
    }
    let (k, q, map) = eliminate(&triplets, &fixed)?;
    let constraints = (0..nnx)
        .map(|i| {
            let x = WIDTH * i as f64 / nx as f64;
            let g0 = CROWN * (x - WIDTH / 2.0).powi(2) * c;
            let node = i * nny;
            debug_assert_eq!(map[2 * node], free_dof(ny, i, 0, 0));
            Constraint::row(
                vec![(map[2 * node], s), (map[2 * node + 1], c)],
                -g0,
                ConstraintKind::Lower,
            )
        })
        .collect();
    // The rigid-body modes of the free nodes (j < ny), in free-DOF order, for a nodal AMG.
    let free_coords: Vec<Vec<f64>> = (0..nnx)
        .flat_map(|i| (0..ny).map(move |j| i * nny + j))
        .map(|node| vec![coords[node].0, coords[node].1])
        .collect();
    Problem::new(k, q, constraints)?
        .with_near_null(NearNull::rigid_body_modes(&free_coords, 2)?)
        .map(Problem::in_preferred_storage)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_couple_two_dofs_along_the_normal() {
        let p = problem(30.0, 8, 4).unwrap();
        assert_eq!(p.n(), 2 * 9 * 4);
        assert_eq!(p.m(), 9);
        let (s, c) = 30f64.to_radians().sin_cos();
        for (i, con) in p.constraints.iter().enumerate() {
            assert_eq!(
                con.terms,
                vec![(free_dof(4, i, 0, 0), s), (free_dof(4, i, 0, 1), c)]
            );
            assert!(con.limit <= 0.0);
        }
        // The crown touches at x = W/2 (node 4 of 8 elements).
        assert_eq!(p.constraints[4].limit, 0.0);
        // K and K + D E Dᵀ symmetric bit for bit (CG and the symmetric routes need it).
        assert!(p.k.is_symmetric());
        assert!(p.penalized_k(&vec![1e6; p.m()]).is_symmetric());
    }

    #[test]
    fn rigid_body_modes_are_in_the_kernel_away_from_the_clamp() {
        let (nx, ny) = (6, 4);
        let p = problem(30.0, nx, ny).unwrap();
        let nn = p.near_null.as_ref().unwrap();
        assert_eq!((nn.block_size, nn.k, nn.n()), (2, 3, p.n()));
        let scale = (0..p.n()).map(|i| p.k.get(i, i)).fold(0.0, f64::max);
        for col in 0..3 {
            let b = &nn.b[col * p.n()..(col + 1) * p.n()];
            let kb = p.k.matvec(b);
            let bmax = b.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            // Rows of nodes not next to the clamped top (j ≤ ny − 2) see all their columns.
            for i in 0..=nx {
                for j in 0..ny - 1 {
                    for c in 0..2 {
                        let r = kb[free_dof(ny, i, j, c)];
                        let tol = 64.0 * f64::EPSILON * scale * bmax;
                        assert!(r.abs() <= tol, "mode {col}, node ({i}, {j}): {r:e}");
                    }
                }
            }
        }
    }

    #[test]
    fn bad_angles_and_meshes_are_refused() {
        assert!(problem(0.0, 8, 4).is_err());
        assert!(problem(f64::NAN, 8, 4).is_err());
        assert!(problem(75.0, 8, 4).is_err());
        assert!(problem(30.0, 1, 4).is_err());
    }
}

//! Linear elasticity in 3-D on a block of trilinear hexahedra (H8), pressed by a rigid sphere:
//! the 3-D family of `solver_cost` (a quarter of the block, two symmetry planes).
//!
//! **Element.** `K_e = ∫ Bᵀ C B dV` by 2×2×2 Gauss quadrature on each box
//! `[x0, x1] × [y0, y1] × [z0, z1]` (exact for a box's trilinear field), strains in Voigt
//! order `(ε_xx, ε_yy, ε_zz, γ_yz, γ_xz, γ_xy)` (engineering shears) and the isotropic
//! `C = E/((1+ν)(1−2ν)) [[1−ν, ν, ν], [ν, 1−ν, ν], [ν, ν, 1−ν]] ⊕ (E/(2(1+ν))) I₃`.
//!
//! **Mesh** ([`Grid3`]). A tensor grid `xs × ys × zs`, xs = ys graded like the plane block of
//! [`super::elasticity::Grid::graded`]: elements of size h on `[0, fine]` next to the symmetry
//! planes x = 0, y = 0 and below the top face z = H, growing geometrically beyond. Node
//! (i, j, k) is node `(i·ny + j)·nz + k`, its DOFs `3·node + c` (c = 0, 1, 2: x, y, z).
//!
//! **Contact scene** ([`sphere_indentation`]). The bottom face z = 0 is clamped and lifted by
//! w (u = (0, 0, w)), the planes x = 0 and y = 0 are symmetry planes (u_x = 0, resp. u_y = 0),
//! and every top node (x, y, H) meets a rigid sphere of radius R whose surface lies
//! `(x² + y²)/(2R)` above it (Hertz's paraboloid): the single-DOF row `u_z ≤ (x² + y²)/(2R)`
//! (`upper`; small deformation, frictionless, normal = z). Prescribed DOFs are eliminated
//! (`K_ff u_f = q_f = −K_fp u_p`, K_ff SPD). Units are the caller's.
//!
//! **Pressure.** A top node's contact force is `f_c = −(K u − q)_c` (compressive positive)
//! and its pressure `p_c = f_c / ω_c` with the tributary area `ω_c = ∫ N_c dA` over the top
//! face (products of the edge weights: a uniform pressure reads back uniform); the total force
//! of the whole block is 4 Σ f_c (the quarter model).
//!
//! **Near-null space.** The rigid-body modes of the free nodes (k ≥ 1), three slots per node
//! ([`NearNull::rigid_body_modes`] with [`NearNull::with_slots`]): a symmetry plane's
//! prescribed component is a slot without an unknown, which a nodal AMG fills with a
//! decoupled identity row (the practice of codes that keep Dirichlet rows), so every node
//! block is 3 × 3.
//!
//! When to use: 3-D conditioning and iterative-solver cost (`solver_cost`'s `hertz-3d`),
//! checked against Hertz's sphere (`a = (3PR/(4E*))^(1/3)`, `p0 = 3P/(2πa²)`).

use super::elasticity::{eliminate, Base, Material};
use crate::error::{Error, Result};
use crate::system::{Constraint, ConstraintKind, NearNull, Problem, Stiffness};
use std::collections::HashMap;

/// A tensor grid of nodes in 3-D, each axis increasing from 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid3 {
    /// Node x coordinates, xs\[0\] = 0 (the symmetry plane x = 0).
    pub xs: Vec<f64>,
    /// Node y coordinates, ys\[0\] = 0 (the symmetry plane y = 0).
    pub ys: Vec<f64>,
    /// Node z coordinates, zs\[0\] = 0 (bottom) to zs\[last\] = H (top, the contact face).
    pub zs: Vec<f64>,
}

impl Grid3 {
    /// A `width × width × height` block with elements of size `h` on `[0, fine]` in x and y
    /// and in the top `fine` of z, growing by `growth` (≥ 1) away from the contact corner.
    pub fn graded(width: f64, height: f64, h: f64, fine: f64, growth: f64) -> Result<Grid3> {
        let plane = super::elasticity::Grid::graded(width, height, h, fine, growth)?;
        let nodes = plane.xs.len() * plane.xs.len() * plane.ys.len();
        if nodes > 5_000_000 {
            return Err(Error::out_of_range(
                "3-D grid: h",
                h,
                format!("large enough for at most 5e6 nodes on a {width}² × {height} block"),
            ));
        }
        Ok(Grid3 {
            ys: plane.xs.clone(),
            xs: plane.xs,
            zs: plane.ys,
        })
    }

    /// A uniform grid of `nx × ny × nz` elements on `wx × wy × h` (positive, finite sizes; at
    /// least one element per axis; [`Grid3::validate`]).
    pub fn uniform(
        (wx, wy, h): (f64, f64, f64),
        (nx, ny, nz): (usize, usize, usize),
    ) -> Result<Grid3> {
        for (name, v) in [("width x", wx), ("width y", wy), ("height", h)] {
            Error::positive(format!("3-D grid: {name}"), v)?;
        }
        let axis = |len: f64, n: usize| (0..=n).map(|i| len * i as f64 / n as f64).collect();
        let grid = Grid3 {
            xs: axis(wx, nx),
            ys: axis(wy, ny),
            zs: axis(h, nz),
        };
        grid.validate()?;
        Ok(grid)
    }

    /// Checks every axis: at least 2 nodes (one element), finite coordinates from 0, strictly
    /// increasing (every element of positive size) — the fields are public, so [`assemble`]
    /// checks them again.
    pub fn validate(&self) -> Result<()> {
        for (name, axis) in [("x", &self.xs), ("y", &self.ys), ("z", &self.zs)] {
            if axis.len() < 2 {
                return Err(Error::out_of_range(
                    format!("3-D grid: nodes along {name}"),
                    axis.len(),
                    "at least 2 (one element)",
                ));
            }
            if axis[0] != 0.0 {
                return Err(Error::out_of_range(
                    format!("3-D grid: first {name} coordinate"),
                    axis[0],
                    "0",
                ));
            }
            if let Some(w) = axis.windows(2).find(|w| !(w[1].is_finite() && w[1] > w[0])) {
                return Err(Error::out_of_range(
                    format!("3-D grid: {name} coordinate after {}", w[0]),
                    w[1],
                    "finite and increasing",
                ));
            }
        }
        if self.nodes() > 5_000_000 {
            return Err(Error::out_of_range(
                "3-D grid: nodes",
                self.nodes(),
                "at most 5e6",
            ));
        }
        Ok(())
    }

    /// Nodes per axis.
    pub fn dims(&self) -> (usize, usize, usize) {
        (self.xs.len(), self.ys.len(), self.zs.len())
    }

    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.xs.len() * self.ys.len() * self.zs.len()
    }

    /// Node index of (i, j, k).
    pub fn node(&self, i: usize, j: usize, k: usize) -> usize {
        (i * self.ys.len() + j) * self.zs.len() + k
    }

    /// Height H (the top face's z).
    pub fn height(&self) -> f64 {
        *self.zs.last().unwrap_or(&0.0)
    }
}

/// The 6×6 isotropic constitutive matrix (Voigt order of the module doc).
pub fn c_matrix(m: &Material) -> [[f64; 6]; 6] {
    let (e, nu) = (m.young, m.poisson);
    let f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mut c = [[0.0; 6]; 6];
    for (r, row) in c.iter_mut().enumerate().take(3) {
        for (s, v) in row.iter_mut().enumerate().take(3) {
            *v = if r == s { f * (1.0 - nu) } else { f * nu };
        }
    }
    for (r, row) in c.iter_mut().enumerate().skip(3) {
        row[r] = e / (2.0 * (1.0 + nu));
    }
    c
}

/// The local node `a` of a hexahedron: its offsets (di, dj, dk) ∈ {0, 1}³, a = 4di + 2dj + dk.
fn corner(a: usize) -> (usize, usize, usize) {
    (a >> 2, (a >> 1) & 1, a & 1)
}

/// The 24×24 stiffness of the box `dx × dy × dz`, local node `a = 4di + 2dj + dk` at offsets
/// (di, dj, dk) ∈ {0, 1}³, DOFs (u_x, u_y, u_z) per node; symmetric bit for bit.
pub fn element_stiffness(c: &[[f64; 6]; 6], (dx, dy, dz): (f64, f64, f64)) -> Vec<[f64; 24]> {
    let g = 1.0 / 3f64.sqrt();
    let mut ke = vec![[0.0; 24]; 24];
    let w = dx * dy * dz / 8.0;
    for gp in 0..8 {
        let (gi, gj, gk) = corner(gp);
        let xi = [-g, g];
        let (s, t, u) = (xi[gi], xi[gj], xi[gk]);
        // B: 6 × 24.
        let mut b = [[0.0; 24]; 6];
        for a in 0..8 {
            let (di, dj, dk) = corner(a);
            let (sa, ta, ua) = (
                2.0 * di as f64 - 1.0,
                2.0 * dj as f64 - 1.0,
                2.0 * dk as f64 - 1.0,
            );
            let nx = sa * (1.0 + ta * t) * (1.0 + ua * u) / 8.0 * 2.0 / dx;
            let ny = ta * (1.0 + sa * s) * (1.0 + ua * u) / 8.0 * 2.0 / dy;
            let nz = ua * (1.0 + sa * s) * (1.0 + ta * t) / 8.0 * 2.0 / dz;
            let col = 3 * a;
            b[0][col] = nx;
            b[1][col + 1] = ny;
            b[2][col + 2] = nz;
            b[3][col + 1] = nz;
            b[3][col + 2] = ny;
            b[4][col] = nz;
            b[4][col + 2] = nx;
            b[5][col] = ny;
            b[5][col + 1] = nx;
        }
        // C B, then Bᵀ (C B) on the upper triangle.
        let mut cb = [[0.0; 24]; 6];
        for r in 0..6 {
            for q in 0..24 {
                cb[r][q] = (0..6).map(|s| c[r][s] * b[s][q]).sum();
            }
        }
        for p in 0..24 {
            for q in p..24 {
                ke[p][q] += w * (0..6).map(|r| b[r][p] * cb[r][q]).sum::<f64>();
            }
        }
    }
    for p in 1..24 {
        let (upper, lower) = ke.split_at_mut(p);
        for (q, row) in upper.iter().enumerate() {
            lower[0][q] = row[p];
        }
    }
    ke
}

/// The global stiffness of the grid as (row, column, value) triplets over all `3·nodes`
/// DOFs, each entry summed once and mirrored (element matrices cached per box size): a
/// stiffness symmetric bit for bit (CG and the symmetric cond₂ routes need it; summing
/// (i, j) and (j, i) separately may round differently).
pub fn assemble(grid: &Grid3, material: &Material) -> Result<Vec<(usize, usize, f64)>> {
    material.validate()?;
    grid.validate()?;
    let (nx, ny, nz) = grid.dims();
    let c = c_matrix(material);
    let mut cache: HashMap<(u64, u64, u64), Vec<[f64; 24]>> = HashMap::new();
    let mut t = Vec::with_capacity((nx - 1) * (ny - 1) * (nz - 1) * 576);
    for i in 0..nx - 1 {
        for j in 0..ny - 1 {
            for k in 0..nz - 1 {
                let size = (
                    grid.xs[i + 1] - grid.xs[i],
                    grid.ys[j + 1] - grid.ys[j],
                    grid.zs[k + 1] - grid.zs[k],
                );
                let key = (size.0.to_bits(), size.1.to_bits(), size.2.to_bits());
                let ke = cache
                    .entry(key)
                    .or_insert_with(|| element_stiffness(&c, size));
                let dof = |p: usize| {
                    let (di, dj, dk) = corner(p / 3);
                    3 * grid.node(i + di, j + dj, k + dk) + p % 3
                };
                for (p, row) in ke.iter().enumerate() {
                    for (q, &v) in row.iter().enumerate() {
                        let (r, c) = (dof(p), dof(q));
                        if r <= c {
                            t.push((r, c, v));
                        }
                    }
                }
            }
        }
    }
    let upper = Stiffness::from_triplets(3 * grid.nodes(), &t)?;
    drop(t);
    let mut out = Vec::with_capacity(2 * upper.nnz());
    upper.for_each_entry(|i, j, v| {
        out.push((i, j, v));
        if i != j {
            out.push((j, i, v));
        }
    });
    Ok(out)
}

/// Trapezoid weights `∫ N_i` of the linear hat functions on the nodes `xs`.
fn edge_weights(xs: &[f64]) -> Vec<f64> {
    let mut w = vec![0.0; xs.len()];
    for k in 0..xs.len().saturating_sub(1) {
        let l = xs[k + 1] - xs[k];
        w[k] += l / 2.0;
        w[k + 1] += l / 2.0;
    }
    w
}

/// One top node in contact with the sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TopNode {
    /// Its x.
    pub x: f64,
    /// Its y.
    pub y: f64,
    /// Tributary area ω = ∫ N dA over the top face (of the quarter).
    pub weight: f64,
}

impl TopNode {
    /// Distance from the axis, √(x² + y²).
    pub fn r(&self) -> f64 {
        self.x.hypot(self.y)
    }
}

/// The quarter block pressed onto a rigid sphere (module doc).
#[derive(Clone, Debug)]
pub struct SphereIndentation {
    /// `K_ff`, `q_f`, one `upper` row per top node (order of [`Self::contact`]) and the
    /// rigid-body modes of the free nodes.
    pub problem: Problem,
    /// The top nodes, (i, j) in grid order.
    pub contact: Vec<TopNode>,
    /// The lift w of the bottom face.
    pub lift: f64,
}

impl SphereIndentation {
    /// Contact pressures `p_c = −(K u − q)_c / ω_c` at the top nodes for the solution `u`
    /// (compressive positive).
    pub fn pressures(&self, u: &[f64]) -> Vec<f64> {
        let p = &self.problem;
        let r = p.k.matvec(u);
        p.constraints
            .iter()
            .zip(&self.contact)
            .map(|(con, node)| {
                let d = con.lead_dof();
                -(r[d] - p.q[d]) / node.weight
            })
            .collect()
    }

    /// The total contact force of the whole block, `4 Σ p_c ω_c`.
    pub fn total_force(&self, u: &[f64]) -> f64 {
        let p = self.pressures(u);
        4.0 * p
            .iter()
            .zip(&self.contact)
            .map(|(p, n)| p * n.weight)
            .sum::<f64>()
    }
}

/// The prescribed value of every DOF: the bottom lifted by `lift` (clamped in x and y where
/// `base` is [`Base::Clamped`]), the symmetry planes held normal to themselves.
fn prescribed(grid: &Grid3, base: Base, lift: f64) -> Vec<Option<f64>> {
    let (nx, ny, nz) = grid.dims();
    let mut fixed = vec![None; 3 * grid.nodes()];
    for i in 0..nx {
        for j in 0..ny {
            let n = grid.node(i, j, 0);
            fixed[3 * n + 2] = Some(lift);
            if base == Base::Clamped {
                fixed[3 * n] = Some(0.0);
                fixed[3 * n + 1] = Some(0.0);
            }
            for k in 0..nz {
                let n = grid.node(i, j, k);
                if i == 0 {
                    fixed[3 * n] = Some(0.0);
                }
                if j == 0 {
                    fixed[3 * n + 1] = Some(0.0);
                }
            }
        }
    }
    fixed
}

/// The quarter block of `grid` lifted by `lift` onto the rigid sphere of `radius` (module
/// doc), with the base `base` (the 3-D family: clamped; sliding: the uniform-compression
/// check with `radius` = ∞).
pub fn sphere_indentation(
    grid: &Grid3,
    material: &Material,
    base: Base,
    radius: f64,
    lift: f64,
) -> Result<SphereIndentation> {
    if !lift.is_finite() {
        return Err(Error::out_of_range("lift", lift, "finite"));
    }
    if radius.is_nan() || radius <= 0.0 {
        return Err(Error::out_of_range("sphere radius R", radius, "> 0"));
    }
    let triplets = assemble(grid, material)?;
    let (nx, ny, nz) = grid.dims();
    let fixed = prescribed(grid, base, lift);
    let (k, q, map) = eliminate(&triplets, &fixed)?;
    drop(triplets);
    let (wx, wy) = (edge_weights(&grid.xs), edge_weights(&grid.ys));
    let mut constraints = Vec::with_capacity(nx * ny);
    let mut contact = Vec::with_capacity(nx * ny);
    for i in 0..nx {
        for j in 0..ny {
            let (x, y) = (grid.xs[i], grid.ys[j]);
            let d = map[3 * grid.node(i, j, nz - 1) + 2];
            let limit = (x * x + y * y) / (2.0 * radius);
            constraints.push(Constraint::on_dof(d, limit, ConstraintKind::Upper));
            contact.push(TopNode {
                x,
                y,
                weight: wx[i] * wy[j],
            });
        }
    }
    // Three slots per node with any free DOF, in node order.
    let at = |node: usize| {
        let (k, rest) = (node % nz, node / nz);
        vec![grid.xs[rest / ny], grid.ys[rest % ny], grid.zs[k]]
    };
    let near_null = NearNull::rigid_body_modes_in_slots(3, at, &fixed)?;
    let problem = Problem::new(k, q, constraints)?
        .with_near_null(near_null)?
        .in_preferred_storage();
    Ok(SphereIndentation {
        problem,
        contact,
        lift,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steel() -> Material {
        Material {
            young: 200.0,
            poisson: 0.3,
        }
    }

    /// The six rigid-body modes have no energy in a distorted-size box.
    #[test]
    fn rigid_modes_have_no_energy() {
        let c = c_matrix(&steel());
        let size = (0.7, 1.3, 0.4);
        let ke = element_stiffness(&c, size);
        let coords: Vec<Vec<f64>> = (0..8)
            .map(|a| {
                let (i, j, k) = corner(a);
                vec![i as f64 * size.0, j as f64 * size.1, k as f64 * size.2]
            })
            .collect();
        let nn = NearNull::rigid_body_modes(&coords, 3).unwrap();
        let scale = ke
            .iter()
            .map(|r| r.iter().fold(0.0f64, |m, v| m.max(v.abs())))
            .fold(0.0, f64::max);
        for m in 0..6 {
            let v = &nn.b[24 * m..24 * (m + 1)];
            for (p, row) in ke.iter().enumerate() {
                let f: f64 = row.iter().zip(v).map(|(a, b)| a * b).sum();
                assert!(
                    f.abs() <= 64.0 * f64::EPSILON * scale * 2.0,
                    "mode {m}, dof {p}: {f:e}"
                );
            }
        }
    }

    /// A unit cube under uniaxial strain ε_xx = 1 (the others held 0) stores energy
    /// C₁₁/2 = E(1−ν)/(2(1+ν)(1−2ν)): the element integrates the constant strain exactly.
    #[test]
    fn constant_strain_energy_is_exact() {
        let m = steel();
        let c = c_matrix(&m);
        let ke = element_stiffness(&c, (1.0, 1.0, 1.0));
        let u: Vec<f64> = (0..24)
            .map(|p| {
                if p % 3 == 0 {
                    corner(p / 3).0 as f64
                } else {
                    0.0
                }
            })
            .collect();
        let e: f64 = (0..24)
            .map(|p| u[p] * (0..24).map(|q| ke[p][q] * u[q]).sum::<f64>())
            .sum::<f64>()
            / 2.0;
        let want = c[0][0] / 2.0;
        assert!((e - want).abs() <= 1e-13 * want, "{e} vs {want}");
    }

    /// Uniform compression of a block on a sliding base by a flat rigid face (R = ∞): lateral
    /// faces free, so uniaxial stress σ_zz = E w/H; every top node's pressure reads back
    /// E·w/H, and the linear field solves K u = q at every non-contact DOF.
    #[test]
    fn uniform_compression_reads_back_uniform_pressure() {
        let m = steel();
        let grid = Grid3::graded(2.0, 1.5, 0.25, 1.0, 1.3).unwrap();
        let w = 1e-3;
        let ind = sphere_indentation(&grid, &m, Base::Sliding, f64::INFINITY, w).unwrap();
        let p = &ind.problem;
        assert!(p.k.is_symmetric());
        let h = grid.height();
        let ez = -w / h;
        let ex = -m.poisson * ez;
        let fixed = prescribed(&grid, Base::Sliding, w);
        let mut u = Vec::with_capacity(p.n());
        for node in 0..grid.nodes() {
            let (k, rest) = (node % grid.zs.len(), node / grid.zs.len());
            let (i, j) = (rest / grid.ys.len(), rest % grid.ys.len());
            let field = [ex * grid.xs[i], ex * grid.ys[j], w + ez * grid.zs[k]];
            for c in 0..3 {
                if fixed[3 * node + c].is_none() {
                    u.push(field[c]);
                }
            }
        }
        assert_eq!(u.len(), p.n());
        let r = p.k.matvec(&u);
        let contact: Vec<usize> = p.constraints.iter().map(|c| c.lead_dof()).collect();
        let scale = p.k.max_abs() * w;
        for (d, (rd, qd)) in r.iter().zip(&p.q).enumerate() {
            if !contact.contains(&d) {
                assert!((rd - qd).abs() <= 1e-11 * scale, "dof {d}: {rd} vs {qd}");
            }
        }
        let want = m.young * w / h;
        for (c, pc) in ind.pressures(&u).iter().enumerate() {
            assert!((pc - want).abs() <= 1e-9 * want, "node {c}: {pc} vs {want}");
        }
        let area = 4.0 * 2.0 * 2.0;
        assert!((ind.total_force(&u) - want * area).abs() <= 1e-9 * want * area);
    }

    /// The near-null space has three slots per free node; the rigid translations and
    /// rotations are in the kernel of the padded K at nodes away from every support.
    #[test]
    fn near_null_slots_cover_the_free_dofs() {
        let grid = Grid3::uniform((1.0, 1.0, 1.0), (3, 3, 3)).unwrap();
        let ind = sphere_indentation(&grid, &steel(), Base::Clamped, 10.0, 0.0).unwrap();
        let nn = ind.problem.near_null.as_ref().unwrap();
        assert_eq!(nn.block_size, 3);
        assert_eq!(nn.k, 6);
        // 4·4·3 free nodes, 3 slots each; unknowns: minus the symmetry planes' components.
        assert_eq!(nn.padded_n(), 3 * 48);
        assert_eq!(nn.n(), ind.problem.n());
        assert_eq!(ind.problem.n(), 3 * 48 - 12 - 12);
        assert!(sphere_indentation(&grid, &steel(), Base::Clamped, 0.0, 0.0).is_err());
        assert!(sphere_indentation(&grid, &steel(), Base::Clamped, 1.0, f64::NAN).is_err());
    }

    /// Bad grids are errors naming the axis and the value, before any assembly (no panic, no
    /// NaN stiffness): one node on an axis, a shifted origin, a NaN or repeated coordinate,
    /// a non-positive size, zero elements.
    #[test]
    fn bad_grids_are_refused_with_the_axis_named() {
        let ok = Grid3::uniform((1.0, 1.0, 1.0), (2, 2, 2)).unwrap();
        let with = |f: &dyn Fn(&mut Grid3)| {
            let mut g = ok.clone();
            f(&mut g);
            g
        };
        let m = steel();
        for (grid, says) in [
            (with(&|g| g.xs.truncate(1)), "nodes along x"),
            (with(&|g| g.ys[0] = 0.1), "first y coordinate"),
            (with(&|g| g.zs[1] = f64::NAN), "z coordinate after 0"),
            (with(&|g| g.xs[2] = g.xs[1]), "x coordinate after 0.5"),
        ] {
            let e = assemble(&grid, &m).unwrap_err().to_string();
            assert!(e.contains(says), "{e}");
        }
        for (sizes, counts, says) in [
            ((0.0, 1.0, 1.0), (2, 2, 2), "width x"),
            ((1.0, 1.0, f64::INFINITY), (2, 2, 2), "height"),
            ((1.0, 1.0, 1.0), (2, 0, 2), "nodes along y"),
        ] {
            let e = Grid3::uniform(sizes, counts).unwrap_err().to_string();
            assert!(e.contains(says), "{e}");
        }
    }
}

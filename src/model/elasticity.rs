//! Linear elasticity on a block of bilinear quadrilaterals (Q4), plane strain or axisymmetric,
//! pressed against a rigid indenter: the contact problems of the Hertz and patch benchmarks.
//!
//! **Element.** `K_e = ∫ Bᵀ C B w dA` by 2×2 Gauss quadrature (exact for a rectangle's
//! bilinear field in plane strain), with
//! - plane strain: ε = (∂u/∂x, ∂v/∂y, ∂u/∂y + ∂v/∂x), w = 1 (per unit thickness),
//!   `C = E/((1+ν)(1−2ν)) [[1−ν, ν, 0], [ν, 1−ν, 0], [0, 0, (1−2ν)/2]]`;
//! - axisymmetric (x = r, y = z): ε = (∂u/∂r, ∂v/∂z, u/r, ∂u/∂z + ∂v/∂r), w = r (per radian:
//!   a total force is 2π times the sum of nodal forces), C the 4×4 isotropic matrix.
//!
//! **Mesh.** A tensor grid `xs × ys` ([`Grid`]) graded toward the contact zone: elements of
//! size h on `[0, fine]` next to the symmetry line x = 0 and below the top face, growing
//! geometrically beyond. Node (i, j) at (xs\[i\], ys\[j\]) is node `i·ny + j` with DOFs
//! `2·node` (x or r) and `2·node + 1` (y or z).
//!
//! **Contact scene** ([`indentation`]). The bottom face y = 0 is lifted by w (prescribed
//! v = w; its u is fixed where `base` is [`Base::Clamped`], free where [`Base::Sliding`]),
//! the symmetry line x = 0 has u = 0, and every top node (x_i, H) meets a rigid indenter whose
//! surface lies `profile(x_i)` above it: the constraint is `v_i ≤ profile(x_i)` (`upper`;
//! small deformation, frictionless, normal = y). Prescribed DOFs are eliminated, so the
//! problem is `K_ff u_f = q_f = −K_fp u_p` with `K_ff` SPD. Units are the caller's (E in
//! force/length², lengths in length).
//!
//! **Contact pressure.** A node's contact force is read from equilibrium, `f_c = −(K u − q)_c`
//! (compressive positive; the same formula for every rule: a penalty's ε_c·penetration, a
//! Lagrange multiplier), and its pressure is `p_c = f_c / ω_c` with the tributary weight
//! `ω_c = ∫ N_c ds` (plane strain) or `∫ N_c r dr` (axisymmetric) over the top face — the row
//! sums of the consistent boundary mass matrix: a uniform pressure reads back uniform. Plane
//! scenes carry their nodes' rigid-body modes in slots (`NearNull::rigid_body_modes_in_slots`).
//! When to use: the analytic contact benchmarks of `contact_bench`, `solver_cost` and the
//! sweep's `hertz` and `patch` families. K is checked against scikit-fem's (`tests/verification`).

use super::contact_forces;
use crate::error::{Error, Result};
use crate::system::{Constraint, ConstraintKind, NearNull, Problem, Stiffness, Surface};

/// Plane strain or axisymmetry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Geometry {
    /// Plane strain, per unit thickness; x ≥ 0 is half of a body symmetric about x = 0.
    PlaneStrain,
    /// Axisymmetric about x = r = 0, per radian.
    Axisymmetric,
}

impl Geometry {
    /// Hertz's contact half-width (plane strain, cylinder) or radius (axisymmetric, sphere) a
    /// of a rigid indenter of radius R pressed by the total load P onto an elastic half-space
    /// of contact modulus E* (frictionless; Johnson, *Contact Mechanics*, 1985, §4.2, §5.8):
    /// `a = √(4PR/(πE*))` (P per unit length) or `a = (3PR/(4E*))^(1/3)`.
    pub fn hertz_half_width(self, load: f64, radius: f64, e_star: f64) -> f64 {
        match self {
            Geometry::PlaneStrain => (4.0 * load * radius / (std::f64::consts::PI * e_star)).sqrt(),
            Geometry::Axisymmetric => (3.0 * load * radius / (4.0 * e_star)).cbrt(),
        }
    }

    /// The load of [`Self::hertz_half_width`] for the half-width a: `P = πa²E*/(4R)` (per unit
    /// length) or `P = 4E*a³/(3R)`.
    pub fn hertz_load(self, a: f64, radius: f64, e_star: f64) -> f64 {
        match self {
            Geometry::PlaneStrain => std::f64::consts::PI * a * a * e_star / (4.0 * radius),
            Geometry::Axisymmetric => 4.0 * e_star * a.powi(3) / (3.0 * radius),
        }
    }
}

/// Isotropic linear elastic material.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Material {
    /// Young's modulus E (> 0).
    pub young: f64,
    /// Poisson's ratio ν (−1 < ν < 0.5).
    pub poisson: f64,
}

impl Material {
    /// The plane-strain modulus `E* = E/(1 − ν²)` of Hertz theory (rigid indenter).
    pub fn contact_modulus(&self) -> f64 {
        self.young / (1.0 - self.poisson * self.poisson)
    }

    pub(crate) fn validate(&self) -> Result<()> {
        Error::positive("Young's modulus", self.young)?;
        if !(self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(Error::out_of_range(
                "Poisson's ratio ν",
                self.poisson,
                "in (−1, 0.5)",
            ));
        }
        Ok(())
    }

    /// The constitutive matrix for `geometry` (3×3 plane strain, 4×4 axisymmetric, stored 4×4
    /// with the hoop row/column unused in plane strain).
    pub fn c_matrix(&self, geometry: Geometry) -> [[f64; 4]; 4] {
        let (e, nu) = (self.young, self.poisson);
        let f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let (a, b, g) = (f * (1.0 - nu), f * nu, f * (1.0 - 2.0 * nu) / 2.0);
        // Order: εx, εy, γxy, εθ.
        let mut c = [[0.0; 4]; 4];
        c[0][0] = a;
        c[1][1] = a;
        c[0][1] = b;
        c[1][0] = b;
        c[2][2] = g;
        if geometry == Geometry::Axisymmetric {
            c[3][3] = a;
            c[0][3] = b;
            c[3][0] = b;
            c[1][3] = b;
            c[3][1] = b;
        }
        c
    }
}

/// A tensor-product grid of nodes: x (or r) coordinates `xs`, y (or z) coordinates `ys`, both
/// increasing from 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Node abscissae, xs\[0\] = 0.
    pub xs: Vec<f64>,
    /// Node ordinates, ys\[0\] = 0 (bottom) to ys\[last\] = H (top, the contact face).
    pub ys: Vec<f64>,
}

/// Coordinates from 0 to `length`: steps of `h` up to `fine`, then steps growing by `growth`
/// (the last one stretched or shrunk to end at `length`).
pub(crate) fn graded_axis(length: f64, h: f64, fine: f64, growth: f64) -> Vec<f64> {
    let mut v = vec![0.0];
    let mut step = h;
    let mut x = 0.0;
    while x + 1e-9 * h < length {
        if x + 1e-9 * h >= fine {
            step *= growth;
        }
        x = (x + step).min(length);
        if length - x < 0.5 * step {
            x = length;
        }
        v.push(x);
    }
    v
}

impl Grid {
    /// A `width × height` block with elements of size `h` on `[0, fine]` in x and in the top
    /// `fine` of y, growing by the factor `growth` (≥ 1) away from the contact corner.
    pub fn graded(width: f64, height: f64, h: f64, fine: f64, growth: f64) -> Result<Grid> {
        for (name, v) in [
            ("width", width),
            ("height", height),
            ("h", h),
            ("fine", fine),
        ] {
            Error::positive(format!("graded grid: {name}"), v)?;
        }
        if !(growth.is_finite() && growth >= 1.0) {
            return Err(Error::out_of_range(
                "graded grid: growth",
                growth,
                "a finite number ≥ 1",
            ));
        }
        // Elements per axis: the uniform zone, then a geometric growth (all uniform if 1).
        let count = |len: f64| {
            if growth > 1.0 {
                fine.min(len) / h + (len / fine).max(1.0).ln() / growth.ln()
            } else {
                len / h
            }
        };
        if count(width) > 1e5 || count(height) > 1e5 {
            return Err(Error::out_of_range(
                "graded grid: h",
                h,
                format!(
                    "large enough for a {width} × {height} block (at most 1e5 elements per axis)"
                ),
            ));
        }
        let xs = graded_axis(width, h, fine, growth);
        let ys: Vec<f64> = graded_axis(height, h, fine, growth)
            .into_iter()
            .rev()
            .map(|d| height - d)
            .collect();
        Ok(Grid { xs, ys })
    }

    /// A uniform grid of `nx × ny` elements on `width × height`.
    pub fn uniform(width: f64, height: f64, nx: usize, ny: usize) -> Grid {
        Grid {
            xs: (0..=nx).map(|i| width * i as f64 / nx as f64).collect(),
            ys: (0..=ny).map(|j| height * j as f64 / ny as f64).collect(),
        }
    }

    /// Node count in y.
    pub fn ny(&self) -> usize {
        self.ys.len()
    }

    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.xs.len() * self.ys.len()
    }

    /// Node index of (i, j).
    pub fn node(&self, i: usize, j: usize) -> usize {
        i * self.ny() + j
    }

    /// Height H (the top face's y).
    pub fn height(&self) -> f64 {
        *self.ys.last().unwrap_or(&0.0)
    }
}

/// The 8×8 stiffness of the rectangle `[x0, x1] × [y0, y1]`, nodes in the order (x0, y0),
/// (x1, y0), (x1, y1), (x0, y1), DOFs (u, v) per node.
pub fn element_stiffness(
    geometry: Geometry,
    c: &[[f64; 4]; 4],
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> [[f64; 8]; 8] {
    let (hx, hy) = (x1 - x0, y1 - y0);
    let g = 1.0 / 3f64.sqrt();
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let mut ke = [[0.0; 8]; 8];
    for &(xi, eta) in &[(-g, -g), (g, -g), (g, g), (-g, g)] {
        let x = x0 + 0.5 * (1.0 + xi) * hx;
        let det = 0.25 * hx * hy;
        let w = det
            * match geometry {
                Geometry::PlaneStrain => 1.0,
                Geometry::Axisymmetric => x,
            };
        // B: rows εx, εy, γxy, εθ; columns u0 v0 u1 v1 ...
        let mut b = [[0.0; 8]; 4];
        for (a, &(xa, ya)) in corners.iter().enumerate() {
            let n = 0.25 * (1.0 + xa * xi) * (1.0 + ya * eta);
            let dndx = 0.25 * xa * (1.0 + ya * eta) * 2.0 / hx;
            let dndy = 0.25 * ya * (1.0 + xa * xi) * 2.0 / hy;
            b[0][2 * a] = dndx;
            b[1][2 * a + 1] = dndy;
            b[2][2 * a] = dndy;
            b[2][2 * a + 1] = dndx;
            if geometry == Geometry::Axisymmetric {
                b[3][2 * a] = n / x;
            }
        }
        add_btcb(&mut ke, &b, c, w);
    }
    mirror(&mut ke);
    ke
}

/// `Kₑ += w·BᵀCB`, the lower triangle (q ≥ p) only: [`mirror`] makes the upper its mirror,
/// so that Kₑ — and K, summed in the same element order for (i, j) and (j, i) — is symmetric
/// bit for bit, as the certified cond₂ routes and Cholesky need (Bᵀ(CB) in the other order
/// would differ in the last bits).
fn add_btcb(ke: &mut [[f64; 8]; 8], b: &[[f64; 8]; 4], c: &[[f64; 4]; 4], w: f64) {
    for p in 0..8 {
        // (C B)[:, p]
        let mut cb = [0.0; 4];
        for (r, cbr) in cb.iter_mut().enumerate() {
            *cbr = (0..4).map(|s| c[r][s] * b[s][p]).sum();
        }
        for q in p..8 {
            ke[q][p] += w * (0..4).map(|r| b[r][q] * cb[r]).sum::<f64>();
        }
    }
}

/// Copies the lower triangle of `ke` onto the upper.
fn mirror(ke: &mut [[f64; 8]; 8]) {
    for (p, q) in (0..8).flat_map(|p| (p + 1..8).map(move |q| (p, q))) {
        ke[p][q] = ke[q][p];
    }
}

/// The 8×8 stiffness of the bilinear (isoparametric) quadrilateral with corners `xy` in
/// counter-clockwise order, DOFs (u, v) per corner, by 2×2 Gauss quadrature:
/// `Kₑ = Σ_g w_g det J_g B_gᵀ C B_g` (times r in axisymmetry), `[∂N/∂x; ∂N/∂y] = J⁻¹[∂N/∂ξ;
/// ∂N/∂η]`. For a rectangle it is [`element_stiffness`] (to rounding). Errors where det J ≤ 0
/// at a Gauss point (a folded or clockwise element).
pub fn quad_stiffness(
    geometry: Geometry,
    c: &[[f64; 4]; 4],
    xy: [(f64, f64); 4],
) -> Result<[[f64; 8]; 8]> {
    let g = 1.0 / 3f64.sqrt();
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let mut ke = [[0.0; 8]; 8];
    for &(xi, eta) in &[(-g, -g), (g, -g), (g, g), (-g, g)] {
        let mut n = [0.0; 4];
        let mut dxi = [0.0; 4];
        let mut deta = [0.0; 4];
        for (a, &(xa, ya)) in corners.iter().enumerate() {
            n[a] = 0.25 * (1.0 + xa * xi) * (1.0 + ya * eta);
            dxi[a] = 0.25 * xa * (1.0 + ya * eta);
            deta[a] = 0.25 * ya * (1.0 + xa * xi);
        }
        let sum = |w: &[f64; 4], f: fn((f64, f64)) -> f64| -> f64 {
            (0..4).map(|a| w[a] * f(xy[a])).sum()
        };
        let (j00, j01) = (sum(&dxi, |p| p.0), sum(&dxi, |p| p.1));
        let (j10, j11) = (sum(&deta, |p| p.0), sum(&deta, |p| p.1));
        let det = j00 * j11 - j01 * j10;
        if !(det > 0.0 && det.is_finite()) {
            return Err(Error::out_of_range(
                format!("det J of quadrilateral {xy:?}"),
                format!("{det:e}"),
                "> 0 (a quadrilateral that is not folded and is counter-clockwise)",
            ));
        }
        let x = sum(&n, |p| p.0);
        let w = det
            * match geometry {
                Geometry::PlaneStrain => 1.0,
                Geometry::Axisymmetric => x,
            };
        let mut b = [[0.0; 8]; 4];
        for a in 0..4 {
            let dndx = (j11 * dxi[a] - j01 * deta[a]) / det;
            let dndy = (-j10 * dxi[a] + j00 * deta[a]) / det;
            b[0][2 * a] = dndx;
            b[1][2 * a + 1] = dndy;
            b[2][2 * a] = dndy;
            b[2][2 * a + 1] = dndx;
            if geometry == Geometry::Axisymmetric {
                b[3][2 * a] = n[a] / x;
            }
        }
        add_btcb(&mut ke, &b, c, w);
    }
    mirror(&mut ke);
    Ok(ke)
}

/// The global stiffness of a structured mesh of `nx × ny` nodes whose node (i, j) (index
/// `i·ny + j`, as [`Grid::node`]) lies at `coords[i·ny + j]`, x growing with i and y with j,
/// as (row, column, value) triplets over all `2·nodes` DOFs ([`quad_stiffness`] per element).
pub fn assemble_mapped(
    coords: &[(f64, f64)],
    (nx, ny): (usize, usize),
    geometry: Geometry,
    material: &Material,
) -> Result<Vec<(usize, usize, f64)>> {
    material.validate()?;
    if nx < 2 || ny < 2 {
        return Err(Error::out_of_range(
            "mapped mesh nodes",
            format!("{nx} × {ny}"),
            "at least 2 × 2",
        ));
    }
    if coords.len() != nx * ny {
        return Err(Error::length_mismatch(
            format!("mapped mesh coordinates ({nx} × {ny} nodes)"),
            coords.len(),
            nx * ny,
        ));
    }
    let c = material.c_matrix(geometry);
    let mut t = Vec::with_capacity((nx - 1) * (ny - 1) * 64);
    for i in 0..nx - 1 {
        for j in 0..ny - 1 {
            let nodes = [
                i * ny + j,
                (i + 1) * ny + j,
                (i + 1) * ny + j + 1,
                i * ny + j + 1,
            ];
            let ke = quad_stiffness(geometry, &c, nodes.map(|k| coords[k]))?;
            let dof = |k: usize| 2 * nodes[k / 2] + k % 2;
            for (p, row) in ke.iter().enumerate() {
                for (q, &v) in row.iter().enumerate() {
                    t.push((dof(p), dof(q), v));
                }
            }
        }
    }
    Ok(t)
}

/// The global stiffness of the grid as (row, column, value) triplets over all `2·nodes` DOFs.
pub fn assemble(
    grid: &Grid,
    geometry: Geometry,
    material: &Material,
) -> Result<Vec<(usize, usize, f64)>> {
    material.validate()?;
    let c = material.c_matrix(geometry);
    let (nx, ny) = (grid.xs.len(), grid.ys.len());
    if nx < 2 || ny < 2 {
        return Err(Error::out_of_range(
            "elasticity grid nodes",
            format!("{nx} × {ny}"),
            "at least 2 × 2 (one element)",
        ));
    }
    let mut t = Vec::with_capacity((nx - 1) * (ny - 1) * 64);
    for i in 0..nx - 1 {
        for j in 0..ny - 1 {
            let ke = element_stiffness(
                geometry,
                &c,
                (grid.xs[i], grid.xs[i + 1]),
                (grid.ys[j], grid.ys[j + 1]),
            );
            let nodes = [
                grid.node(i, j),
                grid.node(i + 1, j),
                grid.node(i + 1, j + 1),
                grid.node(i, j + 1),
            ];
            let dof = |k: usize| 2 * nodes[k / 2] + k % 2;
            for (p, row) in ke.iter().enumerate() {
                for (q, &v) in row.iter().enumerate() {
                    t.push((dof(p), dof(q), v));
                }
            }
        }
    }
    Ok(t)
}

/// How the bottom face is supported (besides being lifted by w).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Base {
    /// Bonded to a rigid base: u = 0 on the bottom.
    Clamped,
    /// Frictionless base: u free on the bottom (uniform compression is then exact).
    Sliding,
}

/// The node of one contact row: a top node in contact with the indenter, or the node a
/// two-body row belongs to ([`super::two_body`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactNode {
    /// Its abscissa (x or r).
    pub x: f64,
    /// Tributary weight ω = ∫ N ds (plane strain) or ∫ N r dr (axisymmetric) over the top.
    pub weight: f64,
    /// A node-to-segment row's own node: the free DOF (normal) of the node whose gap the row
    /// measures, its term with coefficient ±1; None for nodal and mortar rows.
    pub own_dof: Option<usize>,
    /// A second-pass row of two-pass node-to-segment (a master node against the slave face):
    /// the other side of the slave nodes' load, left out of [`Indentation::total_force`].
    pub second_pass: bool,
}

impl ContactNode {
    /// A node at `x` with tributary weight `weight`: no own DOF, not of a second pass.
    pub fn new(x: f64, weight: f64) -> ContactNode {
        ContactNode {
            x,
            weight,
            own_dof: None,
            second_pass: false,
        }
    }
}

/// A block pushed onto a rigid indenter (see the module doc): the contact problem and what is
/// needed to read pressures from its solutions.
#[derive(Clone, Debug)]
pub struct Indentation {
    /// `K_ff`, `q_f` and one constraint per contact node or row (`upper` rows under a rigid
    /// indenter, `lower` rows between two bodies), in the order of [`Self::contact`].
    pub problem: Problem,
    /// The contact nodes, from the symmetry line outwards.
    pub contact: Vec<ContactNode>,
    /// Free DOFs: number of nodes' DOFs kept.
    pub n_free: usize,
    /// The lift w of the bottom face.
    pub lift: f64,
    /// Plane strain or axisymmetric.
    pub geometry: Geometry,
}

impl Indentation {
    /// The scene with its contact surface attached to the problem ([`Surface`]: the top
    /// nodes' tributary weights ω, and the diagonal of the whole block's bounding box — the
    /// half model mirrored: √((2W)² + H²) in plane strain, √(2·(2W)² + H²) for the cylinder of
    /// radius W), so that `constant`'s ε is per unit contact length (plane strain) or area
    /// per radian (axisymmetric) and the barrier's κ rule has its length scale.
    pub fn with_surface(self, grid: &Grid) -> Result<Indentation> {
        let width = *grid.xs.last().unwrap_or(&0.0);
        self.with_surface_of(width, grid.height())
    }

    /// [`Self::with_surface`] for a body (or bodies) of half-width `width` and height
    /// `height` (two stacked blocks: the sum of their heights).
    pub fn with_surface_of(self, width: f64, height: f64) -> Result<Indentation> {
        let across = 2.0 * width;
        let h = height;
        let bbox_diagonal = match self.geometry {
            Geometry::PlaneStrain => across.hypot(h),
            Geometry::Axisymmetric => (2.0 * across * across + h * h).sqrt(),
        };
        let surface = Surface {
            weights: self.contact.iter().map(|n| n.weight).collect(),
            bbox_diagonal,
        };
        Ok(Indentation {
            problem: self.problem.with_surface(surface)?,
            ..self
        })
    }

    /// Contact pressures p_c = −(K u − q)_c / ω_c at the contact nodes for the solution `u`
    /// for an `upper` row (compressive positive; a `lower` row's with the sign turned).
    ///
    /// The row forces f are read from equilibrium, `K u − q = −D f` (`model::contact_forces`):
    /// `f_c = −(K u − q)_d` for single-DOF rows, `DᵀD f = −Dᵀ(K u − q)` for rows that couple
    /// DOFs (D of full column rank: one-pass node-to-segment, mortar; NaN where DᵀD is
    /// singular or nearly so); `p_c = s_c f_c / ω_c`, `s_c` +1 for an `upper` row and −1 for
    /// a `lower` one. **Two-pass node-to-segment** (a row of the [`ContactNode::second_pass`],
    /// every row with its [`ContactNode::own_dof`] d): its rows are dependent and a row's share
    /// of a force is not defined, so f_c is the contact force on the row's own node,
    /// `−(K u − q)_d / a_cd` (a_cd = ±1), every row's force on it together: p_c is the nodal
    /// pressure of each interface node of both bodies (one-pass rows: the row force itself).
    pub fn pressures(&self, u: &[f64]) -> Vec<f64> {
        let p = &self.problem;
        let mut r = p.k.matvec(u);
        for (ri, qi) in r.iter_mut().zip(&p.q) {
            *ri -= qi;
        }
        let sign = |con: &crate::system::Constraint| {
            if con.kind == ConstraintKind::Lower {
                -1.0
            } else {
                1.0
            }
        };
        if p.is_selection() {
            // r = −D f with D Boolean: f_c = −r_d.
            return p
                .constraints
                .iter()
                .zip(&self.contact)
                .map(|(con, node)| sign(con) * -con.value(&r) / node.weight)
                .collect();
        }
        let forces = match self.two_pass_own_dofs() {
            Some(own) => contact_forces::nodal_forces(p, &own, &r),
            None => contact_forces::row_forces(p, &r),
        };
        p.constraints
            .iter()
            .zip(&self.contact)
            .zip(forces)
            .map(|((con, node), f)| sign(con) * f / node.weight)
            .collect()
    }

    /// Every row's own DOF where the rows are two-pass node-to-segment (some row of the
    /// second pass, every row with its own DOF); None otherwise.
    fn two_pass_own_dofs(&self) -> Option<Vec<usize>> {
        if !self.contact.iter().any(|n| n.second_pass) {
            return None;
        }
        self.contact.iter().map(|n| n.own_dof).collect()
    }

    /// The total contact force of the whole body for the solution `u`: twice the half model's
    /// (plane strain, per unit thickness) or 2π times the per-radian sum (axisymmetric). Of
    /// two-pass node-to-segment rows only the first pass's count: the slave (upper) body's
    /// interface nodes carry the whole load, and the second pass's nodes (the lower body's)
    /// the same load from the other side.
    pub fn total_force(&self, u: &[f64]) -> f64 {
        let p = self.pressures(u);
        let half: f64 = p
            .iter()
            .zip(&self.contact)
            .filter(|(_, n)| !n.second_pass)
            .map(|(p, n)| p * n.weight)
            .sum();
        match self.geometry {
            Geometry::PlaneStrain => 2.0 * half,
            Geometry::Axisymmetric => 2.0 * std::f64::consts::PI * half,
        }
    }
}

/// Tributary weights of the top nodes: ∫ N_i ds (plane strain) or ∫ N_i r dr (axisymmetric)
/// of the linear edge functions, exact.
pub(crate) fn top_weights(xs: &[f64], geometry: Geometry) -> Vec<f64> {
    let mut w = vec![0.0; xs.len()];
    for k in 0..xs.len().saturating_sub(1) {
        let (a, b) = (xs[k], xs[k + 1]);
        let l = b - a;
        match geometry {
            Geometry::PlaneStrain => {
                w[k] += l / 2.0;
                w[k + 1] += l / 2.0;
            }
            Geometry::Axisymmetric => {
                // ∫ (b − r)/l · r dr and ∫ (r − a)/l · r dr over [a, b].
                w[k] += l * (2.0 * a + b) / 6.0;
                w[k + 1] += l * (a + 2.0 * b) / 6.0;
            }
        }
    }
    w
}

/// Eliminates the prescribed DOFs (`fixed[d] = Some(value)`) from the system of `triplets`:
/// `K_ff`, `q_f = −K_fp u_p` and the free index of every DOF (`usize::MAX` where prescribed).
pub fn eliminate(
    triplets: &[(usize, usize, f64)],
    fixed: &[Option<f64>],
) -> Result<(Stiffness, Vec<f64>, Vec<usize>)> {
    let mut map = vec![usize::MAX; fixed.len()];
    let mut n_free = 0;
    for (d, f) in fixed.iter().enumerate() {
        if f.is_none() {
            map[d] = n_free;
            n_free += 1;
        }
    }
    let mut kff = Vec::with_capacity(triplets.len());
    let mut q = vec![0.0; n_free];
    for &(r, c, v) in triplets {
        match (map[r], fixed[c]) {
            (usize::MAX, _) => {}
            (fr, None) => kff.push((fr, map[c], v)),
            (fr, Some(uc)) => q[fr] -= v * uc,
        }
    }
    Ok((Stiffness::from_triplets(n_free, &kff)?, q, map))
}

/// The prescribed value of every DOF of `grid` (None: free): the bottom face lifted by
/// `lift` (and held in x where `base` is clamped), the symmetry line held in x.
pub(crate) fn prescribed(grid: &Grid, base: Base, lift: f64) -> Vec<Option<f64>> {
    let mut fixed: Vec<Option<f64>> = vec![None; 2 * grid.nodes()];
    for i in 0..grid.xs.len() {
        let n = grid.node(i, 0);
        fixed[2 * n + 1] = Some(lift);
        if base == Base::Clamped {
            fixed[2 * n] = Some(0.0);
        }
    }
    for j in 0..grid.ny() {
        fixed[2 * grid.node(0, j)] = Some(0.0);
    }
    fixed
}

/// The global DOF (`2·node + component`) of each unknown of [`indentation`]'s problem on
/// `grid` with `base`, in order.
pub fn free_dofs(grid: &Grid, base: Base) -> Vec<usize> {
    let fixed = prescribed(grid, base, 0.0);
    (0..fixed.len()).filter(|&d| fixed[d].is_none()).collect()
}

/// The block of `grid` lifted by `lift` onto the indenter whose surface lies `profile(x)`
/// above the top node at x (the module doc gives the boundary conditions).
pub fn indentation(
    grid: &Grid,
    geometry: Geometry,
    material: &Material,
    base: Base,
    lift: f64,
    profile: impl Fn(f64) -> f64,
) -> Result<Indentation> {
    if !lift.is_finite() {
        return Err(Error::out_of_range("lift", lift, "finite"));
    }
    let triplets = assemble(grid, geometry, material)?;
    let (nx, ny) = (grid.xs.len(), grid.ys.len());
    let fixed = prescribed(grid, base, lift);
    let (k, q, map) = eliminate(&triplets, &fixed)?;
    let n_free = q.len();
    let weights = top_weights(&grid.xs, geometry);
    let mut constraints = Vec::with_capacity(nx);
    let mut contact = Vec::with_capacity(nx);
    for (i, (&x, &w)) in grid.xs.iter().zip(&weights).enumerate() {
        let d = map[2 * grid.node(i, ny - 1) + 1];
        let limit = profile(x);
        if !limit.is_finite() {
            return Err(Error::out_of_range(
                format!("indenter profile at x = {x}"),
                limit,
                "finite",
            ));
        }
        constraints.push(Constraint::on_dof(d, limit, ConstraintKind::Upper));
        contact.push(ContactNode::new(x, w));
    }
    let mut problem = Problem::new(k, q, constraints)?;
    if geometry == Geometry::PlaneStrain {
        let at = |n: usize| vec![grid.xs[n / ny], grid.ys[n % ny]];
        problem = problem.with_near_null(NearNull::rigid_body_modes_in_slots(2, at, &fixed)?)?;
    }
    Ok(Indentation {
        problem: problem.in_preferred_storage(),
        contact,
        n_free,
        lift,
        geometry,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rigid translation has zero strain energy, in both geometries for u (plane strain)
    /// and v (both).
    #[test]
    fn rigid_modes_have_no_energy() {
        let m = Material {
            young: 100.0,
            poisson: 0.3,
        };
        for geo in [Geometry::PlaneStrain, Geometry::Axisymmetric] {
            let c = m.c_matrix(geo);
            let ke = element_stiffness(geo, &c, (0.5, 1.5), (0.0, 2.0));
            let v: Vec<f64> = (0..8).map(|k| if k % 2 == 1 { 1.0 } else { 0.0 }).collect();
            for row in &ke {
                let f: f64 = row.iter().zip(&v).map(|(a, b)| a * b).sum();
                assert!(f.abs() <= 1e-12 * 100.0, "{geo:?}: {f}");
            }
        }
    }

    /// Uniform pressure p on the top of a sliding block: u = linear field, exact; each top
    /// node's force is p·ω_c, so the pressures read back are p to rounding.
    #[test]
    fn uniform_compression_reads_back_uniform_pressure() {
        let m = Material {
            young: 1000.0,
            poisson: 0.25,
        };
        for geo in [Geometry::PlaneStrain, Geometry::Axisymmetric] {
            let grid = Grid::graded(2.0, 1.0, 0.1, 0.5, 1.3).unwrap();
            let ind = indentation(&grid, geo, &m, Base::Sliding, 1e-3, |_| 0.0).unwrap();
            // Free lateral faces: σx = σθ = 0, εy = −w/H. Plane strain: εx = −ν/(1−ν)·εy,
            // σy = E/(1−ν²)·εy; axisymmetric (uniaxial stress): εr = −ν·εy, σy = E·εy.
            let h = grid.height();
            let ey = -1e-3 / h;
            let (ex, sy) = match geo {
                Geometry::PlaneStrain => (
                    -m.poisson / (1.0 - m.poisson) * ey,
                    m.contact_modulus() * ey,
                ),
                Geometry::Axisymmetric => (-m.poisson * ey, m.young * ey),
            };
            let mut u = vec![0.0; ind.n_free];
            let mut k = 0;
            for (i, &x) in grid.xs.iter().enumerate() {
                for (j, &y) in grid.ys.iter().enumerate() {
                    if i > 0 {
                        u[k] = ex * x;
                        k += 1;
                    }
                    if j > 0 {
                        u[k] = 1e-3 + ey * y;
                        k += 1;
                    }
                }
            }
            assert_eq!(k, ind.n_free);
            // Equilibrium away from the top: K u = q at every free DOF but the contact ones.
            let r = ind.problem.k.matvec(&u);
            let contact: Vec<usize> = ind
                .problem
                .constraints
                .iter()
                .map(|c| c.lead_dof())
                .collect();
            let scale = ind.problem.k.max_abs() * 1e-3;
            for (d, (rd, qd)) in r.iter().zip(&ind.problem.q).enumerate() {
                if !contact.contains(&d) {
                    assert!(
                        (rd - qd).abs() <= 1e-12 * scale,
                        "{geo:?} dof {d}: {rd} vs {qd}"
                    );
                }
            }
            let p = ind.pressures(&u);
            let want = -sy;
            for (c, pc) in p.iter().enumerate() {
                assert!(
                    (pc - want).abs() <= 1e-9 * want,
                    "{geo:?} node {c}: {pc} vs {want}"
                );
            }
        }
    }
}

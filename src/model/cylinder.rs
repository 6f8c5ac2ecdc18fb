//! Hertz between two elastic bodies (`hertz-two-body`): an elastic cylinder of
//! radius R pressed onto an elastic block, plane strain, frictionless, half model (x ≥ 0),
//! meshed independently so that the interface does not match.
//!
//! **Hertz** (Johnson 1985, §4.2 and §5.8): two bodies of contact moduli E₁* and E₂*
//! (`E* = E/(1 − ν²)`) and radii ∞ (the block) and R act as a rigid cylinder of radius R on a
//! half-space of modulus `1/E* = 1/E₁* + 1/E₂*`: `a = √(4PR/(πE*))`, `p0 = 2P/(πa)`,
//! `p(x) = p0 √(1 − x²/a²)` (P per unit length).
//!
//! **Bodies.** The block is `grid` (its top, y = H₁, the contact face; base supported as
//! `base`, the symmetry line held in x), Q4 ([`elasticity::assemble`]). Of the cylinder the
//! cap near the contact is modelled: x ∈ [0, W₂], from its surface `y = H₁ + x²/(2R)` (Hertz's
//! parabola) up to a flat top at `y = H₁ + H₂`, pushed down by `squeeze` (v = −w; u free), its
//! symmetry line held in x. Its nodes lie on the graded abscissae `xs₂` (size `h` up to
//! `fine`, then growing by `growth`) and, on each vertical, at heights graded the same way up
//! from the surface, so its elements are general quadrilaterals
//! ([`elasticity::assemble_mapped`]). The cap must be much wider and taller than a (its
//! truncation is a bias of the same kind as the block's finite size).
//!
//! **Rows** (small deformation, normal y; the cylinder's surface the slave side): the initial
//! gap of a slave point at x is `g0(x) = x²/(2R)`, and every row of [`two_body`] gains it as
//! its limit: `nts-1`, `v_s − (1 − ξ) v_m₁ − ξ v_m₂ ≥ −g0(x_s)`; `nts-2`, those and the block's
//! top nodes under the cap against the slave segments (limit the slave surface's linear
//! interpolant at the master node); `mortar`, `(Σ_j D_ij v_j − Σ_k M_ik v_k)/ω_i ≥
//! −(∫ N_i g0 ds)/ω_i` (the weighted gap, exact by 2-point Gauss: N_i g0 is cubic). Pressures
//! are read as in [`two_body`] ([`Indentation::pressures`]; p_c = −f_c/ω_c at the slave nodes;
//! `nts-2`: the nodal pressure of each row's own node, both bodies').

use super::elasticity::{
    self, graded_axis, prescribed, Base, ContactNode, Geometry, Grid, Indentation, Material,
};
use super::two_body::{self, Discretization, Terms};
use crate::error::{Error, Result};
use crate::system::{Constraint, ConstraintKind, NearNull, Problem};

/// The cylinder on the block (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct CylinderOnBlock {
    /// The block's mesh (top y = H₁: the contact face).
    pub block: Grid,
    /// How the block's base is supported.
    pub base: Base,
    /// The block's material.
    pub lower: Material,
    /// The cylinder's radius R.
    pub radius: f64,
    /// The modelled cap's half-width W₂ (≤ the block's and < R).
    pub cap_width: f64,
    /// The cap's height H₂ above its lowest point.
    pub cap_height: f64,
    /// The cylinder's element size at the contact.
    pub h: f64,
    /// Extent of its uniform-size zone (from x = 0 and from the surface).
    pub fine: f64,
    /// Growth factor of its elements beyond (≥ 1).
    pub growth: f64,
    /// The cylinder's material.
    pub upper: Material,
}

impl CylinderOnBlock {
    /// The pair's contact modulus `E* = 1/(1/E₁* + 1/E₂*)`.
    pub fn e_star(&self) -> f64 {
        1.0 / (1.0 / self.lower.contact_modulus() + 1.0 / self.upper.contact_modulus())
    }

    /// The initial gap `g0(x) = x²/(2R)` of the cylinder's surface over the block at x.
    pub fn gap0(&self, x: f64) -> f64 {
        x * x / (2.0 * self.radius)
    }

    /// The cap's node abscissae and (relative) heights (module doc).
    fn cap_axes(&self) -> Result<(Vec<f64>, Vec<f64>)> {
        let w = *self.block.xs.last().unwrap_or(&0.0);
        for (name, v) in [
            ("R", self.radius),
            ("cap width", self.cap_width),
            ("cap height", self.cap_height),
            ("h", self.h),
            ("fine", self.fine),
        ] {
            Error::positive(format!("cylinder: {name}"), v)?;
        }
        if !(self.growth.is_finite() && self.growth >= 1.0) {
            return Err(Error::out_of_range(
                "cylinder: growth",
                self.growth,
                "a finite number ≥ 1",
            ));
        }
        if !(self.cap_width <= w && self.cap_width < self.radius) {
            return Err(Error::out_of_range(
                "cylinder: the cap's half-width",
                self.cap_width,
                format!("within the block's ({w}) and below R = {}", self.radius),
            ));
        }
        if self.gap0(self.cap_width) >= 0.5 * self.cap_height {
            return Err(Error::out_of_range(
                "cylinder: the cap's height",
                self.cap_height,
                format!(
                    "more than twice the rise of its curved face ({} at x = {})",
                    self.gap0(self.cap_width),
                    self.cap_width
                ),
            ));
        }
        let xs = graded_axis(self.cap_width, self.h, self.fine, self.growth);
        let ds = graded_axis(self.cap_height, self.h, self.fine, self.growth);
        if xs.len() * ds.len() > 4_000_000 {
            return Err(Error::out_of_range(
                "cylinder: h",
                self.h,
                "large enough for its cap (at most 4e6 cap nodes)",
            ));
        }
        Ok((xs, ds))
    }
}

/// `∫ N_i g0 dx` per node i of the 1-D mesh `xs` (2-point Gauss per segment: exact for the
/// cubic N_i·x²).
fn weighted_gap(xs: &[f64], g0: impl Fn(f64) -> f64) -> Vec<f64> {
    let mut w = vec![0.0; xs.len()];
    let r = 0.5 / 3f64.sqrt();
    for k in 0..xs.len() - 1 {
        let (a, b) = (xs[k], xs[k + 1]);
        for t in [0.5 - r, 0.5 + r] {
            let x = a + t * (b - a);
            let g = 0.5 * (b - a) * g0(x);
            w[k] += (1.0 - t) * g;
            w[k + 1] += t * g;
        }
    }
    w
}

/// The cylinder on the block pressed by `squeeze`, with rows of `disc`, as an
/// [`Indentation`] (one contact node per row: its node's abscissa and tributary length;
/// `lift` = the squeeze, so that force control finds the squeeze that carries a load), with its
/// surface box spanning both bodies.
pub fn hertz_two_body(
    c: &CylinderOnBlock,
    squeeze: f64,
    disc: Discretization,
) -> Result<Indentation> {
    if !squeeze.is_finite() {
        return Err(Error::not_finite("cylinder: the squeeze"));
    }
    let (xs, ds) = c.cap_axes()?;
    let block = &c.block;
    let h1 = block.height();
    let (nx, ny) = (xs.len(), ds.len());
    let top = *ds.last().unwrap_or(&0.0);
    let mut coords = Vec::with_capacity(nx * ny);
    for &x in &xs {
        let y0 = c.gap0(x);
        for &d in &ds {
            coords.push((x, h1 + y0 + d / top * (top - y0)));
        }
    }
    let off = 2 * block.nodes();
    let mut t = elasticity::assemble(block, Geometry::PlaneStrain, &c.lower)?;
    let tu = elasticity::assemble_mapped(&coords, (nx, ny), Geometry::PlaneStrain, &c.upper)?;
    t.extend(tu.into_iter().map(|(i, j, v)| (i + off, j + off, v)));
    let mut fixed = prescribed(block, c.base, 0.0);
    fixed.resize(off + 2 * nx * ny, None);
    for i in 0..nx {
        fixed[off + 2 * (i * ny + ny - 1) + 1] = Some(-squeeze);
    }
    for j in 0..ny {
        fixed[off + 2 * j] = Some(0.0);
    }
    let (k, q, map) = elasticity::eliminate(&t, &fixed)?;
    let n_free = q.len();
    let sd: Vec<usize> = (0..nx).map(|i| map[off + 2 * i * ny + 1]).collect();
    let md: Vec<usize> = (0..block.xs.len())
        .map(|i| map[2 * block.node(i, block.ny() - 1) + 1])
        .collect();
    let (sx, mx) = (&xs, &block.xs);
    let ws = two_body::tributary(sx, Geometry::PlaneStrain);
    let mut rows: Vec<(Terms, f64, ContactNode)> = Vec::new(); // (terms, limit, node)
    match disc {
        Discretization::Nts1 | Discretization::Nts2 => {
            for (i, &x) in sx.iter().enumerate() {
                let node = ContactNode {
                    own_dof: Some(sd[i]),
                    ..ContactNode::new(x, ws[i])
                };
                rows.push((two_body::nts_terms(x, sd[i], mx, &md), -c.gap0(x), node));
            }
            if disc == Discretization::Nts2 {
                let wm = two_body::tributary(mx, Geometry::PlaneStrain);
                let w2 = c.cap_width;
                for (k, &x) in mx.iter().enumerate().filter(|(_, &x)| x <= w2) {
                    let terms: Terms = two_body::nts_terms(x, md[k], sx, &sd)
                        .into_iter()
                        .map(|(d, a)| (d, -a))
                        .collect();
                    // The slave surface's height over the master node: its linear interpolant.
                    let seg = sx.windows(2).position(|w| x <= w[1]).unwrap_or(nx - 2);
                    let xi = ((x - sx[seg]) / (sx[seg + 1] - sx[seg])).clamp(0.0, 1.0);
                    let g = (1.0 - xi) * c.gap0(sx[seg]) + xi * c.gap0(sx[seg + 1]);
                    rows.push((terms, -g, two_body::second_pass(x, wm[k], md[k])));
                }
            }
        }
        Discretization::Mortar => {
            let wg = weighted_gap(sx, |x| c.gap0(x));
            let m_rows = two_body::mortar_rows(sx, &sd, mx, &md, Geometry::PlaneStrain);
            for (i, terms) in m_rows.into_iter().enumerate() {
                rows.push((terms, -wg[i] / ws[i], ContactNode::new(sx[i], ws[i])));
            }
        }
    }
    let mut constraints = Vec::with_capacity(rows.len());
    let mut contact = Vec::with_capacity(rows.len());
    for (terms, limit, node) in rows {
        constraints.push(Constraint::row(terms, limit, ConstraintKind::Lower));
        contact.push(node);
    }
    let width = *block.xs.last().unwrap_or(&0.0);
    // The block's nodes, then the cap's (mapped) ones.
    let (n1, ny1) = (block.nodes(), block.ny());
    let at = |n: usize| {
        if n < n1 {
            vec![block.xs[n / ny1], block.ys[n % ny1]]
        } else {
            let (x, y) = coords[n - n1];
            vec![x, y]
        }
    };
    let modes = NearNull::rigid_body_modes_in_slots(2, at, &fixed)?;
    Indentation {
        problem: Problem::new(k, q, constraints)?
            .with_near_null(modes)?
            .in_preferred_storage(),
        contact,
        n_free,
        lift: squeeze,
        geometry: Geometry::PlaneStrain,
    }
    .with_surface_of(width, h1 + c.cap_height)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `∫ N_i x² dx` summed over i is `∫ x² dx` (partition of unity), and on one segment
    /// [0, 1] the two hat moments are 1/12 and 1/4 (by hand).
    #[test]
    fn weighted_gap_is_exact_for_the_parabola() {
        let w = weighted_gap(&[0.0, 1.0], |x| x * x);
        assert!((w[0] - 1.0 / 12.0).abs() <= 1e-15 && (w[1] - 0.25).abs() <= 1e-15);
        let xs = [0.0, 0.3, 0.35, 1.0, 2.5];
        let total: f64 = weighted_gap(&xs, |x| x * x).iter().sum();
        assert!((total - 2.5f64.powi(3) / 3.0).abs() <= 1e-14 * total);
    }

    /// The two-pass rows on a small cylinder: the first pass is `nts-1` unchanged; the second
    /// adds one row per block top node under the cap, `(1 − ξ)v_a + ξ v_b − v_m ≥ −g`, with g
    /// the chord of the slave nodes' x²/2R over the master node (computed here from the slave
    /// abscissae, by hand); every row of every discretization has coefficients summing to 0
    /// (a rigid vertical motion of both bodies opens no gap) and a non-negative initial gap.
    #[test]
    fn two_pass_rows_add_the_master_pass() {
        let c = CylinderOnBlock {
            block: Grid::graded(4.0, 4.0, 0.25, 1.5, 1.2).unwrap(),
            base: Base::Clamped,
            lower: Material {
                young: 210e3,
                poisson: 0.3,
            },
            radius: 10.0,
            cap_width: 1.5,
            cap_height: 1.5,
            h: 0.25 * 4.0 / 7.0,
            fine: 1.0,
            growth: 1.2,
            upper: Material {
                young: 70e3,
                poisson: 0.33,
            },
        };
        let one = hertz_two_body(&c, 1e-3, Discretization::Nts1).unwrap();
        let two = hertz_two_body(&c, 1e-3, Discretization::Nts2).unwrap();
        let m1 = one.problem.m();
        let under: Vec<f64> = c.block.xs.iter().copied().filter(|&x| x <= 1.5).collect();
        assert_eq!(two.problem.m(), m1 + under.len());
        assert_eq!(two.problem.constraints[..m1], one.problem.constraints[..]);
        let sx: Vec<f64> = one.contact.iter().map(|n| n.x).collect();
        for (row, node) in two.problem.constraints[m1..].iter().zip(&two.contact[m1..]) {
            let x = node.x;
            let b = sx.iter().position(|&s| s >= x).unwrap().max(1);
            let xi = (x - sx[b - 1]) / (sx[b] - sx[b - 1]);
            let chord = (1.0 - xi) * sx[b - 1].powi(2) / 20.0 + xi * sx[b].powi(2) / 20.0;
            assert!(
                (row.limit + chord).abs() <= 1e-15 + 1e-14 * chord,
                "x = {x}: limit {} vs −{chord}",
                row.limit
            );
            assert!(
                chord >= x * x / 20.0 - 1e-15,
                "the chord lies above the parabola"
            );
        }
        let mortar = hertz_two_body(&c, 1e-3, Discretization::Mortar).unwrap();
        for scene in [&one, &two, &mortar] {
            for row in &scene.problem.constraints {
                let sum: f64 = row.terms.iter().map(|t| t.1).sum();
                let size: f64 = row.terms.iter().map(|t| t.1.abs()).sum();
                assert!(sum.abs() <= 8.0 * f64::EPSILON * size, "{:?}", row.terms);
                assert!(row.limit <= 0.0, "initial gap −limit = {}", -row.limit);
            }
        }
    }
}

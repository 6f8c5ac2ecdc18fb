//! Two elastic blocks stacked with non-matching interface meshes: the two-body contact patch
//! test (El-Abbasi & Bathe 2001; Crisfield 2000; Taylor & Papadopoulos 1991), with node-to-segment
//! and mortar constraint rows.
//!
//! **Bodies.** Plane strain, Q4 ([`elasticity::assemble`]): the lower block `W × H₁` on
//! `nx₁ × ny₁` elements, the upper block `W × H₂` on `nx₂ × ny₂` elements, stacked at y = H₁
//! (undeformed, touching). Boundary conditions: the lower block's base on rollers (v = 0),
//! the symmetry line x = 0 of both bodies held in x (u = 0), and the upper block's top
//! pressed down by `w` (v = −w): displacement control, so that each body's K is nonsingular
//! on its own (the methods that need K⁻¹ apply). Prescribed DOFs are eliminated
//! (`K_ff u_f = −K_fp u_p`). DOFs: the lower block's nodes first, then the upper block's,
//! node (i, j) of a block with DOFs `2·node` (x) and `2·node + 1` (y).
//!
//! **Interface, small deformation, frictionless.** The normal is y; the gap of an upper
//! (slave) point over the lower (master) surface is `g = v_upper − v_lower` (initially 0),
//! kept `g ≥ 0` (`lower` rows, limit 0). The slave side is the upper block's bottom face.
//! - `nts-1` (one-pass node-to-segment): one row per slave node s over the master segment
//!   [m₁, m₂] that contains it at ξ: `g_s = v_s − (1 − ξ) v_m₁ − ξ v_m₂` (≤ 3 terms);
//! - `nts-2` (two-pass): those rows and the same with the bodies' roles swapped (every
//!   master node against the slave segments); the rows are linearly dependent where nodes
//!   line up (always at the faces' ends), and the pass count doubles the stiffness of a
//!   penalty;
//! - `mortar` (segment-to-segment, the standard multiplier space on the slave side): one row
//!   per slave node i, `g̃_i = (Σ_j D_ij v_j − Σ_k M_ik v_k) / ω_i` with
//!   `D_ij = ∫ N_i N_j ds`, `M_ik = ∫ N_i N̂_k ds` over the slave face (N slave, N̂ master
//!   shape functions; products of linear functions on each overlap of a slave and a master
//!   segment, integrated exactly by 2-point Gauss) and `ω_i = ∫ N_i ds`: the weighted gap
//!   normalized to length units (Popp's normalized gap), so δ is a penetration and a
//!   multiplier `ω_i·p_i` is a nodal force.
//!
//! **Pressure.** Every row's force f_c (a penalty's `ε_c g_c`, a multiplier) acts on the
//! slave side as `f_c d_c`; the contact pressure read at row c is `p_c = −f_c / ω_c` (ω_c the
//! tributary length of the row's slave node; compressive positive), the forces read from
//! equilibrium ([`Indentation::pressures`]). For `mortar` this is
//! exact: with uniform p, `f_c = −ω_c p` makes both bodies' nodal forces the consistent ones
//! (`Σ_i D_ij p = p ∫N_j`, `Σ_i M_ik p = p ∫N̂_k` since `Σ_i N_i = 1`), which is why mortar
//! passes the patch test; one-pass node-to-segment hands the master nodes `(1 − ξ, ξ)` of
//! each slave force instead, which is not `p ∫N̂_k`, and fails it. For `nts-2` a row's own
//! share is not defined (its rows are dependent: the least-squares forces would be NaN), so
//! each row reads the contact force on its own node ([`ContactNode::own_dof`]: the slave
//! node of its pass, coefficient +1 for an upper node, −1 for a lower one), `r = K u − q`
//! there: `p_c = r_s/ω_c` at an upper node s, `−r_m/ω_c` at a lower node m — the nodal
//! pressure of every interface node of both bodies, whatever the rows' dependence (for
//! `nts-1` it is the row force itself, kept as it was). The load is the first pass's
//! `Σ p_c ω_c` (the upper body's interface; the second pass's nodes carry it back:
//! [`Indentation::total_force`] counts the first pass only).
//!
//! **Exact solution** of the patch test: uniform compression, `p = w / (H₁/E₁* + H₂/E₂*)`,
//! `E* = E/(1 − ν²)` (plane strain, free lateral expansion on frictionless faces), reproduced
//! exactly by bilinear elements.
//!
//! **Axisymmetric** ([`patch_in`]): the same blocks as two stacked discs of radius W about the
//! symmetry line; every integral of the rows and every tributary weight takes the weight r (per
//! radian), and the exact pressure is `w / (H₁/E₁ + H₂/E₂)` (no plane-strain constraint).

use super::elasticity::{self, ContactNode, Geometry, Grid, Indentation, Material};
use crate::error::{Error, Result};
use crate::system::{Constraint, ConstraintKind, NearNull, Problem};

/// A constraint row's terms `(DOF, coefficient)`.
pub(crate) type Terms = Vec<(usize, f64)>;

/// How the interface rows are formed (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Discretization {
    /// One-pass node-to-segment.
    #[serde(rename = "nts-1")]
    Nts1,
    /// Two-pass node-to-segment.
    #[serde(rename = "nts-2")]
    Nts2,
    /// Mortar (segment-to-segment, standard multipliers, normalized gap).
    #[serde(rename = "mortar")]
    Mortar,
}

impl Discretization {
    /// Every discretization, in table order.
    pub const ALL: [Discretization; 3] = [
        Discretization::Nts1,
        Discretization::Nts2,
        Discretization::Mortar,
    ];

    /// Its name in rows (`nts-1`, `nts-2`, `mortar`).
    pub fn name(self) -> &'static str {
        match self {
            Discretization::Nts1 => "nts-1",
            Discretization::Nts2 => "nts-2",
            Discretization::Mortar => "mortar",
        }
    }

    /// The discretization named `s` ([`Self::name`]).
    pub fn from_name(s: &str) -> Result<Discretization> {
        Discretization::ALL
            .into_iter()
            .find(|d| d.name() == s)
            .ok_or_else(|| {
                let valid = Discretization::ALL.map(Discretization::name);
                Error::unknown("discretization", s, &valid, "")
            })
    }
}

/// The two blocks (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoBlocks {
    /// Width W of both blocks.
    pub width: f64,
    /// Lower block height H₁.
    pub h_lower: f64,
    /// Upper block height H₂.
    pub h_upper: f64,
    /// Lower block elements (nx₁, ny₁).
    pub mesh_lower: (usize, usize),
    /// Upper block elements (nx₂, ny₂).
    pub mesh_upper: (usize, usize),
    /// Lower block material.
    pub lower: Material,
    /// Upper block material.
    pub upper: Material,
}

impl TwoBlocks {
    /// The patch test's pair of materials — E₁ = 210e3, ν₁ = 0.3 below, E₂ = E₁/3 = 70e3,
    /// ν₂ = 0.33 above (steel on aluminium) — on blocks `width` wide, `heights` (H₁, H₂)
    /// high, meshed (nx₁, ny₁) and (nx₂, ny₂).
    pub fn steel_under_aluminium(
        width: f64,
        heights: (f64, f64),
        mesh_lower: (usize, usize),
        mesh_upper: (usize, usize),
    ) -> TwoBlocks {
        TwoBlocks {
            width,
            h_lower: heights.0,
            h_upper: heights.1,
            mesh_lower,
            mesh_upper,
            lower: Material {
                young: 210e3,
                poisson: 0.3,
            },
            upper: Material {
                young: 70e3,
                poisson: 0.33,
            },
        }
    }

    /// The exact uniform pressure of the patch test at `squeeze`: `w / (H₁/E₁* + H₂/E₂*)`.
    pub fn exact_pressure(&self, squeeze: f64) -> f64 {
        squeeze
            / (self.h_lower / self.lower.contact_modulus()
                + self.h_upper / self.upper.contact_modulus())
    }

    /// [`Self::exact_pressure`] in `geometry`: axisymmetric (two stacked discs, free lateral
    /// surfaces) with the plain moduli, `w / (H₁/E₁ + H₂/E₂)`.
    pub fn exact_pressure_in(&self, geometry: Geometry, squeeze: f64) -> f64 {
        match geometry {
            Geometry::PlaneStrain => self.exact_pressure(squeeze),
            Geometry::Axisymmetric => {
                squeeze / (self.h_lower / self.lower.young + self.h_upper / self.upper.young)
            }
        }
    }
}

/// ∫ of the product of two linear functions on [a, b] given by their end values, exactly (2-point
/// Gauss): `(fa, fb)` and `(ga, gb)`; in axisymmetry with the weight r (a cubic: still exact).
pub(super) fn product_integral(
    a: f64,
    b: f64,
    f: (f64, f64),
    g: (f64, f64),
    geometry: Geometry,
) -> f64 {
    let half = 0.5 * (b - a);
    let r = 0.5 / 3f64.sqrt();
    [0.5 - r, 0.5 + r]
        .iter()
        .map(|&t| {
            let ft = f.0 + t * (f.1 - f.0);
            let gt = g.0 + t * (g.1 - g.0);
            let w = match geometry {
                Geometry::PlaneStrain => 1.0,
                Geometry::Axisymmetric => a + t * (b - a),
            };
            half * ft * gt * w
        })
        .sum()
}

/// The value at x of node k's hat function on the 1-D mesh `xs`.
pub(super) fn hat(xs: &[f64], k: usize, x: f64) -> f64 {
    let left = k.checked_sub(1).map(|l| xs[l]);
    let right = xs.get(k + 1).copied();
    match (left, right) {
        (Some(l), _) if x >= l && x <= xs[k] => (x - l) / (xs[k] - l),
        (_, Some(r)) if x >= xs[k] && x <= r => (r - x) / (r - xs[k]),
        _ => 0.0,
    }
}

/// Node-to-segment terms of the node at `x` (DOF `own`) over the face `xs` with DOFs `other`:
/// `v_own − (1 − ξ) v_a − ξ v_b`, zero coefficients dropped.
pub(crate) fn nts_terms(x: f64, own: usize, xs: &[f64], other: &[usize]) -> Terms {
    let seg = xs
        .windows(2)
        .position(|w| x <= w[1])
        .unwrap_or(xs.len() - 2);
    let xi = ((x - xs[seg]) / (xs[seg + 1] - xs[seg])).clamp(0.0, 1.0);
    let mut t = vec![(own, 1.0), (other[seg], -(1.0 - xi)), (other[seg + 1], -xi)];
    t.retain(|&(_, a)| a != 0.0);
    t
}

/// The contact node of a second-pass row (the master node at `x`, tributary weight `weight`,
/// normal DOF `dof`): its own DOF, marked as of the second pass.
pub(super) fn second_pass(x: f64, weight: f64, dof: usize) -> ContactNode {
    ContactNode {
        own_dof: Some(dof),
        second_pass: true,
        ..ContactNode::new(x, weight)
    }
}

/// Tributary lengths ∫ N_i ds on the 1-D mesh `xs` (axisymmetric: ∫ N_i r dr, per radian).
pub(crate) fn tributary(xs: &[f64], geometry: Geometry) -> Vec<f64> {
    elasticity::top_weights(xs, geometry)
}

/// Mortar rows of the slave face `sx` (DOFs `sd`) over the master face `mx` (DOFs `md`):
/// `(Σ_j D_ij v_j − Σ_k M_ik v_k)/ω_i` per slave node i (module doc).
pub(crate) fn mortar_rows(
    sx: &[f64],
    sd: &[usize],
    mx: &[f64],
    md: &[usize],
    geometry: Geometry,
) -> Vec<Terms> {
    let w = tributary(sx, geometry);
    let mut rows: Vec<std::collections::BTreeMap<usize, f64>> = vec![Default::default(); sx.len()];
    for s in 0..sx.len() - 1 {
        // Breakpoints of the slave segment: its ends and the master nodes inside it.
        let mut cuts: Vec<f64> = vec![sx[s], sx[s + 1]];
        cuts.extend(mx.iter().copied().filter(|&x| x > sx[s] && x < sx[s + 1]));
        cuts.sort_by(f64::total_cmp);
        for piece in cuts.windows(2) {
            let (a, b) = (piece[0], piece[1]);
            for i in [s, s + 1] {
                let ni = (hat(sx, i, a), hat(sx, i, b));
                for j in [s, s + 1] {
                    let nj = (hat(sx, j, a), hat(sx, j, b));
                    *rows[i].entry(sd[j]).or_insert(0.0) +=
                        product_integral(a, b, ni, nj, geometry);
                }
                let mid = 0.5 * (a + b);
                let k = mx
                    .windows(2)
                    .position(|m| mid <= m[1])
                    .unwrap_or(mx.len() - 2);
                for kk in [k, k + 1] {
                    let nk = (hat(mx, kk, a), hat(mx, kk, b));
                    *rows[i].entry(md[kk]).or_insert(0.0) -=
                        product_integral(a, b, ni, nk, geometry);
                }
            }
        }
    }
    rows.into_iter()
        .zip(w)
        .map(|(r, wi)| {
            r.into_iter()
                .filter(|&(_, v)| v != 0.0)
                .map(|(d, v)| (d, v / wi))
                .collect()
        })
        .collect()
}

/// The lower and the upper block's meshes (the upper one stacked at y = H₁ in the module
/// doc's description; its own coordinates start at 0).
fn grids(b: &TwoBlocks) -> (Grid, Grid) {
    let (n1, n2) = (b.mesh_lower, b.mesh_upper);
    (
        Grid::uniform(b.width, b.h_lower, n1.0, n1.1),
        Grid::uniform(b.width, b.h_upper, n2.0, n2.1),
    )
}

/// The prescribed value of every DOF of both blocks (None: free; module doc): the lower
/// base on rollers, the symmetry line held in x, the upper top pushed down by `squeeze`.
fn prescribed(lower: &Grid, upper: &Grid, squeeze: f64) -> Vec<Option<f64>> {
    let off = 2 * lower.nodes();
    let mut fixed: Vec<Option<f64>> = vec![None; off + 2 * upper.nodes()];
    for i in 0..lower.xs.len() {
        fixed[2 * lower.node(i, 0) + 1] = Some(0.0);
    }
    for i in 0..upper.xs.len() {
        fixed[off + 2 * upper.node(i, upper.ny() - 1) + 1] = Some(-squeeze);
    }
    for j in 0..lower.ny() {
        fixed[2 * lower.node(0, j)] = Some(0.0);
    }
    for j in 0..upper.ny() {
        fixed[off + 2 * upper.node(0, j)] = Some(0.0);
    }
    fixed
}

/// The exact displacements of the patch test at `squeeze` on the unknowns of [`patch`]'s
/// problem, in its order (any discretization: the same unknowns): uniform compression by
/// p = [`TwoBlocks::exact_pressure`], `σ_yy = −p`, `σ_xx = 0` (frictionless faces),
/// plane strain, so in each body `u = p ν(1 + ν)/E · x` and `v` falls linearly by `p/E*` per
/// unit height, `v = −p y/E₁*` in the lower block and `v = −p H₁/E₁* − p (y − H₁)/E₂*` in
/// the upper one (reaching −squeeze at its top). Bilinear elements hold this field exactly,
/// so a discretization that passes the patch test reproduces it to rounding.
pub fn exact_displacements(blocks: &TwoBlocks, squeeze: f64) -> Result<Vec<f64>> {
    exact_displacements_in(Geometry::PlaneStrain, blocks, squeeze)
}

/// [`exact_displacements`] in `geometry`; axisymmetric (σ_zz = −p, σ_rr = σ_θθ = 0):
/// `u_r = p ν r/E` and `v` falls by `p/E` per unit height, p = [`TwoBlocks::exact_pressure_in`].
pub fn exact_displacements_in(
    geometry: Geometry,
    blocks: &TwoBlocks,
    squeeze: f64,
) -> Result<Vec<f64>> {
    let b = blocks;
    validate(b, squeeze)?;
    let (lower, upper) = grids(b);
    let fixed = prescribed(&lower, &upper, squeeze);
    let p = b.exact_pressure_in(geometry, squeeze);
    let (lateral, vertical): (PerModulus, PerModulus) = match geometry {
        Geometry::PlaneStrain => (
            |m| m.poisson * (1.0 + m.poisson) / m.young,
            |m| 1.0 / m.contact_modulus(),
        ),
        Geometry::Axisymmetric => (|m| m.poisson / m.young, |m| 1.0 / m.young),
    };
    let lateral = |m: &Material| p * lateral(m);
    let dv1 = p * vertical(&b.lower);
    let dv2 = p * vertical(&b.upper);
    let mut full = vec![0.0; fixed.len()];
    for (j, &y) in lower.ys.iter().enumerate() {
        for (i, &x) in lower.xs.iter().enumerate() {
            let n = lower.node(i, j);
            full[2 * n] = lateral(&b.lower) * x;
            full[2 * n + 1] = -dv1 * y;
        }
    }
    let off = 2 * lower.nodes();
    for (j, &y) in upper.ys.iter().enumerate() {
        for (i, &x) in upper.xs.iter().enumerate() {
            let n = upper.node(i, j);
            full[off + 2 * n] = lateral(&b.upper) * x;
            full[off + 2 * n + 1] = -dv1 * b.h_lower - dv2 * y;
        }
    }
    Ok(full
        .into_iter()
        .zip(&fixed)
        .filter(|(_, f)| f.is_none())
        .map(|(u, _)| u)
        .collect())
}

/// A strain per unit stress of a material (1/E*, ν(1 + ν)/E, ...).
type PerModulus = fn(&Material) -> f64;

/// Checks the blocks and the squeeze (one-line errors).
fn validate(b: &TwoBlocks, squeeze: f64) -> Result<()> {
    Error::positive("two blocks: width", b.width)?;
    Error::positive("two blocks: lower height", b.h_lower)?;
    Error::positive("two blocks: upper height", b.h_upper)?;
    if !squeeze.is_finite() {
        return Err(Error::not_finite("two blocks: the squeeze"));
    }
    for (which, (nx, ny)) in [("lower", b.mesh_lower), ("upper", b.mesh_upper)] {
        if nx == 0 || ny == 0 {
            return Err(Error::out_of_range(
                format!("two blocks: the {which} mesh"),
                format!("{nx} × {ny} elements"),
                "at least one element each way",
            ));
        }
    }
    Ok(())
}

/// The patch test of `blocks` pressed by `squeeze` (module doc), with rows of `disc`, as an
/// [`Indentation`]: one contact node per row (its slave node's abscissa and tributary length
/// ω; node-to-segment rows with their own DOF, the second pass marked), `lift` = the squeeze,
/// so that [`Indentation::pressures`] reads `p_c = −f_c/ω_c` (module doc, **Pressure**) and
/// force control (`strategy::force_control`) finds the squeeze that carries a load.
pub fn patch(blocks: &TwoBlocks, squeeze: f64, disc: Discretization) -> Result<Indentation> {
    patch_in(Geometry::PlaneStrain, blocks, squeeze, disc)
}

/// [`patch`] in `geometry`: axisymmetric, two stacked discs of radius W (x = r, the symmetry
/// line the axis), the mortar integrals and the tributary weights ω taken with the weight r
/// (per radian), so that forces and [`Indentation::total_force`] are per radian and 2π times.
pub fn patch_in(
    geometry: Geometry,
    blocks: &TwoBlocks,
    squeeze: f64,
    disc: Discretization,
) -> Result<Indentation> {
    let b = blocks;
    validate(b, squeeze)?;
    let (lower, upper) = grids(b);
    let off = 2 * lower.nodes();
    let mut t = elasticity::assemble(&lower, geometry, &b.lower)?;
    let tu = elasticity::assemble(&upper, geometry, &b.upper)?;
    t.extend(tu.into_iter().map(|(i, j, v)| (i + off, j + off, v)));
    let fixed = prescribed(&lower, &upper, squeeze);
    let (k, q, map) = elasticity::eliminate(&t, &fixed)?;
    let n_free = q.len();
    // The interface faces: the upper block's bottom (slave), the lower block's top (master).
    let sd: Vec<usize> = (0..upper.xs.len())
        .map(|i| map[off + 2 * upper.node(i, 0) + 1])
        .collect();
    let md: Vec<usize> = (0..lower.xs.len())
        .map(|i| map[2 * lower.node(i, lower.ny() - 1) + 1])
        .collect();
    let (sx, mx) = (&upper.xs, &lower.xs);
    let (ws, wm) = (tributary(sx, geometry), tributary(mx, geometry));
    let mut rows: Vec<(Terms, ContactNode)> = Vec::new();
    match disc {
        Discretization::Nts1 | Discretization::Nts2 => {
            for (i, &x) in sx.iter().enumerate() {
                let node = ContactNode {
                    own_dof: Some(sd[i]),
                    ..ContactNode::new(x, ws[i])
                };
                rows.push((nts_terms(x, sd[i], mx, &md), node));
            }
            if disc == Discretization::Nts2 {
                for (k, &x) in mx.iter().enumerate() {
                    // The master node over the slave face: g = v_s(x) − v_m ≥ 0, i.e. the
                    // node-to-segment row of the lower body with the sign turned.
                    let terms = nts_terms(x, md[k], sx, &sd)
                        .into_iter()
                        .map(|(d, a)| (d, -a))
                        .collect();
                    rows.push((terms, second_pass(x, wm[k], md[k])));
                }
            }
        }
        Discretization::Mortar => {
            for ((terms, &w), &x) in mortar_rows(sx, &sd, mx, &md, geometry)
                .into_iter()
                .zip(&ws)
                .zip(sx)
            {
                rows.push((terms, ContactNode::new(x, w)));
            }
        }
    }
    let mut constraints = Vec::with_capacity(rows.len());
    let mut contact = Vec::with_capacity(rows.len());
    for (terms, node) in rows {
        constraints.push(Constraint::row(terms, 0.0, ConstraintKind::Lower));
        contact.push(node);
    }
    let mut problem = Problem::new(k, q, constraints)?;
    if geometry == Geometry::PlaneStrain {
        // Both blocks' nodes, the upper one stacked at y = H₁.
        let (n1, ny1, ny2) = (lower.nodes(), lower.ny(), upper.ny());
        let at = |n: usize| {
            if n < n1 {
                vec![lower.xs[n / ny1], lower.ys[n % ny1]]
            } else {
                let m = n - n1;
                vec![upper.xs[m / ny2], b.h_lower + upper.ys[m % ny2]]
            }
        };
        problem = problem.with_near_null(NearNull::rigid_body_modes_in_slots(2, at, &fixed)?)?;
    }
    Ok(Indentation {
        problem: problem.in_preferred_storage(),
        contact,
        n_free,
        lift: squeeze,
        geometry,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A normalized mortar row's slave coefficients sum to 1 and its master ones to −1
    /// (`Σ_j D_ij = Σ_k M_ik = ω_i`, both faces spanning the same interval), whatever the
    /// meshes; on matching meshes D = M, so a rigid common motion leaves every gap 0.
    #[test]
    fn mortar_rows_are_partitions_of_unity() {
        let sx: Vec<f64> = (0..=5).map(|i| 0.2 * i as f64).collect();
        let mx: Vec<f64> = [0.0, 0.15, 0.5, 0.55, 0.9, 1.0].to_vec();
        let sd: Vec<usize> = (0..sx.len()).collect();
        let md: Vec<usize> = (100..100 + mx.len()).collect();
        for (mx, md) in [(&mx, &md), (&sx, &md[..sx.len()].to_vec())] {
            for row in mortar_rows(&sx, &sd, mx, md, Geometry::PlaneStrain) {
                let slave: f64 = row.iter().filter(|t| t.0 < 100).map(|t| t.1).sum();
                let master: f64 = row.iter().filter(|t| t.0 >= 100).map(|t| t.1).sum();
                assert!((slave - 1.0).abs() <= 8.0 * f64::EPSILON, "{row:?}");
                assert!((master + 1.0).abs() <= 8.0 * f64::EPSILON, "{row:?}");
            }
        }
        // Matching meshes: the master coefficient of node k equals the slave one of node k.
        for row in mortar_rows(&sx, &sd, &sx, &md[..sx.len()], Geometry::PlaneStrain) {
            for &(d, a) in row.iter().filter(|t| t.0 < 100) {
                let b = row.iter().find(|t| t.0 == 100 + d).map_or(0.0, |t| t.1);
                assert!((a + b).abs() <= 8.0 * f64::EPSILON, "{row:?}");
            }
        }
    }

    /// u in equilibrium with a force on every row: `(K + D E Dᵀ) u = q`, every row active
    /// with the penalty `eps` (dense Cholesky: the blocks are small).
    fn all_active(s: &Indentation, eps: f64) -> Vec<f64> {
        let p = &s.problem;
        let k = p.penalized_k(&vec![eps; p.m()]).to_dense();
        let llt = k.llt(faer::Side::Lower).unwrap();
        let mut b = faer::Mat::<f64>::from_fn(p.n(), 1, |i, _| p.q[i]);
        faer::linalg::solvers::Solve::solve_in_place(&llt, b.as_mut());
        (0..p.n()).map(|i| b[(i, 0)]).collect()
    }

    /// One-pass rows (`nts-1`, `mortar`) keep the least-squares row forces of
    /// `contact_forces::row_forces` as their pressures, bit for bit (`p_c = −f_c/ω_c`, the
    /// reading before two-pass rows had theirs), in both geometries; for `nts-1` the nodal
    /// reading (the force on each row's own node) agrees with them to rounding, since no other
    /// row touches a slave node. Two-pass rows are dependent (their least-squares forces are
    /// NaN); they get the nodal reading, every row with its own DOF, the second pass marked.
    #[test]
    fn one_pass_pressures_are_the_row_forces_and_two_pass_the_nodal_ones() {
        use crate::model::contact_forces::{nodal_forces, row_forces};
        let b = TwoBlocks::steel_under_aluminium(1.0, (0.6, 0.4), (4, 3), (7, 2));
        for geometry in [Geometry::PlaneStrain, Geometry::Axisymmetric] {
            for disc in Discretization::ALL {
                let s = patch_in(geometry, &b, 1e-3, disc).unwrap();
                let u = all_active(&s, 1e6);
                let p = &s.problem;
                let mut r = p.k.matvec(&u);
                for (ri, qi) in r.iter_mut().zip(&p.q) {
                    *ri -= qi;
                }
                let rows = row_forces(p, &r);
                let got = s.pressures(&u);
                let what = format!("{geometry:?} {}", disc.name());
                let own: Option<Vec<usize>> = s.contact.iter().map(|n| n.own_dof).collect();
                if disc == Discretization::Nts2 {
                    assert!(rows.iter().all(|f| f.is_nan()), "{what}: dependent rows");
                    let own = own.unwrap();
                    let nodal = nodal_forces(p, &own, &r);
                    for (c, node) in s.contact.iter().enumerate() {
                        assert_eq!(got[c], -nodal[c] / node.weight, "{what} row {c}");
                    }
                    let second = s.contact.iter().filter(|n| n.second_pass).count();
                    assert_eq!(second, b.mesh_lower.0 + 1, "{what}");
                    assert!(got.iter().all(|v| v.is_finite() && *v > 0.0), "{what}");
                    continue;
                }
                assert!(s.contact.iter().all(|n| !n.second_pass), "{what}");
                for (c, node) in s.contact.iter().enumerate() {
                    let old = -rows[c] / node.weight;
                    assert_eq!(got[c].to_bits(), old.to_bits(), "{what} row {c}");
                }
                if disc == Discretization::Nts1 {
                    let nodal = nodal_forces(p, &own.unwrap(), &r);
                    let scale = rows.iter().fold(0.0_f64, |a, f| a.max(f.abs()));
                    for (f, g) in rows.iter().zip(&nodal) {
                        assert!((f - g).abs() <= 1e-9 * scale, "{what}: {f} vs {g}");
                    }
                } else {
                    assert!(own.is_none(), "{what}: mortar rows have no own node");
                }
            }
        }
    }

    /// One-pass node-to-segment on a node at ξ = 0.25 of its segment.
    #[test]
    fn nts_row_interpolates_the_master_segment() {
        let t = nts_terms(0.25, 7, &[0.0, 1.0, 2.0], &[10, 11, 12]);
        assert_eq!(t, vec![(7, 1.0), (10, -0.75), (11, -0.25)]);
        let t = nts_terms(1.0, 7, &[0.0, 1.0, 2.0], &[10, 11, 12]);
        assert_eq!(t, vec![(7, 1.0), (11, -1.0)]);
    }
}

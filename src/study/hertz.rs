//! The contact benchmarks' cases (Hertz plane and axisymmetric, the flat punch), their meshes
//! and scenes ([`Setup`]), their analytic references and the pressure measures compared with
//! them: shared by `contact_bench` and `solver_cost`.
//!
//! **Hertz** (rigid indenter of radius R on an elastic half-space, frictionless, load P;
//! E* = E/(1 − ν²); Johnson, *Contact Mechanics*, 1985, §4.2 and §5.8):
//! - plane strain (cylinder, P per unit length): `a = √(4PR/(πE*))`, `p0 = 2P/(πa)`;
//! - axisymmetric (sphere): `a = (3PR/(4E*))^(1/3)`, `p0 = 3P/(2πa²)`;
//! - both: `p(x) = p0 √(1 − x²/a²)` for |x| ≤ a, 0 beyond.
//!
//! The half-space is modelled by a block much larger than a (`block_over_a` times, 16 by
//! default), clamped at its base, whose bias the domain study measures
//! (`contact_bench`'s domain study); the indenter's surface is the parabola x²/(2R) of Hertz theory.
//!
//! **Flat punch** (`flat-punch`): a flat rigid punch covering the whole top of a block on a
//! frictionless base; the exact pressure is uniform, `p̄ = P / A` (A the contact length of the
//! half model times 2, or the disc area πW²), and it is reproduced exactly by bilinear
//! elements, so any deviation is the contact rule's. One body in uniform compression: this is
//! *not* the two-body, non-matching contact patch test of El-Abbasi & Bathe (2001), which needs
//! two bodies and segment rows. It was formerly called `patch`; that name still reads.
//!
//! **Inclined plane** (`inclined-15`, `inclined-30`, `inclined-45`): the flat punch turned by θ
//! ([`crate::model::inclined`]); the pressure is the flat punch's, but every contact row
//! `n·u ≤ û` has two terms, so D is not Boolean.
//!
//! **Measures** (nodal, over the top nodes with weights ω_c of [`crate::model::elasticity`]):
//! - `p_err_rel`: `√(Σ ω_c (p_c − p(x_c))²) / √(Σ ω_c p(x_c)²)` over every top node (p = 0
//!   beyond a, so pressure spilled past the exact radius counts) — a discrete L2 error on the
//!   tributary quadrature; `err_penalty` and `err_discretization` in the same measure;
//! - `a_num`: where p² extrapolated from the two outermost loaded nodes vanishes
//!   ([`contact_width`]; always between the outermost loaded node and the next, so within h);
//! - `p0_num`: the pressure at the node on the axis (x = 0).

use crate::error::Result;
use crate::model::cylinder::CylinderOnBlock;
use crate::model::elasticity::{self, Base, ContactNode, Geometry, Grid, Indentation, Material};
use crate::model::two_body::{Discretization, TwoBlocks};

/// Geometric growth of the elements away from the contact zone.
pub const GROWTH: f64 = 1.2;
/// Uniform-size zone of the mesh, over a: the contact zone and a margin.
pub const FINE_OVER_A: f64 = 1.5;

/// The material and geometry of the cases: an elastic block (E, ν) under a rigid indenter of
/// radius R, loaded so that the Hertz half-width is `a_target`; the Hertz block is
/// `block_over_a`·a square, clamped at its base; the flat punch's block is a × a on a
/// frictionless base.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Indenter radius R.
    pub radius: f64,
    /// Hertz contact half-width (radius) a the load is chosen for.
    pub a_target: f64,
    /// The second body's elements per first-body elements at the contact (upper, lower) in
    /// the two-body cases ([`MESH_RATIO`] by default).
    pub mesh_ratio: (usize, usize),
}

impl Setup {
    /// E* = E/(1 − ν²).
    pub fn e_star(&self) -> f64 {
        self.young / (1.0 - self.poisson * self.poisson)
    }

    /// The case's load P and analytic solution (the flat punch: uniform pressure 1e-3·E* on
    /// the top of an a × a block, half model).
    pub fn exact(&self, case: Case) -> (f64, Exact) {
        let (a, r, es) = (self.a_target, self.radius, self.e_star());
        match case {
            Case::HertzPlane | Case::HertzAxi | Case::HertzNormals => {
                let p = case.geometry().hertz_load(a, r, es);
                (p, Exact::hertz(case.geometry(), p, r, es))
            }
            Case::HertzTwoBody => {
                let es = 1.0 / (1.0 / es + 1.0 / self.cylinder_material().contact_modulus());
                let p = Geometry::PlaneStrain.hertz_load(a, r, es);
                (p, Exact::hertz(Geometry::PlaneStrain, p, r, es))
            }
            _ => {
                let half = self.a_target;
                let p0 = 1e-3 * es;
                (
                    2.0 * half * p0,
                    Exact {
                        a: half,
                        p0,
                        hertzian: false,
                    },
                )
            }
        }
    }

    /// The mesh of `case` at relative size `h_rel` (element size h_rel·a at the contact) on a
    /// Hertz block of `block`·a (graded by [`GROWTH`] outside [`FINE_OVER_A`]·a; the flat
    /// punch's block is a × a, uniform, whatever `block`).
    pub fn grid(&self, case: Case, h_rel: f64, block: f64) -> Result<Grid> {
        let a = self.a_target;
        match case {
            c if c.is_uniform() => Grid::graded(a, a, h_rel * a, a, 1.0),
            _ => Grid::graded(block * a, block * a, h_rel * a, FINE_OVER_A * a, GROWTH),
        }
    }

    /// The contact scene of `case` on `grid` with base lift `lift`, with its contact surface
    /// ([`Indentation::with_surface`]).
    pub fn scene(&self, case: Case, grid: &Grid, lift: f64) -> Result<Indentation> {
        let mat = Material {
            young: self.young,
            poisson: self.poisson,
        };
        let r = self.radius;
        let scene = match case {
            Case::HertzNormals => {
                let flat = elasticity::indentation(
                    grid,
                    Geometry::PlaneStrain,
                    &mat,
                    Base::Clamped,
                    lift,
                    |x| x * x / (2.0 * r),
                )?;
                let free = elasticity::free_dofs(grid, Base::Clamped);
                crate::model::inclined::with_nodal_normals(flat, &free, |x| x / r)
            }
            Case::HertzTwoBody => {
                return crate::model::cylinder::hertz_two_body(
                    &self.cylinder_on(grid),
                    lift,
                    Discretization::Mortar,
                )
            }
            Case::FlatPunch => {
                elasticity::indentation(grid, case.geometry(), &mat, Base::Sliding, lift, |_| 0.0)
            }
            c if c.two_body().is_some() => {
                // The surface's box spans both blocks.
                let disc = c.two_body().expect("a two-body case");
                let b = self.two_blocks(grid);
                return crate::model::two_body::patch(&b, lift, disc)?
                    .with_surface_of(b.width, b.h_lower + b.h_upper);
            }
            c if c.is_uniform() => {
                return crate::model::inclined::inclined_punch(
                    grid,
                    &mat,
                    lift,
                    c.theta_deg().to_radians(),
                )
            }
            _ => elasticity::indentation(grid, case.geometry(), &mat, Base::Clamped, lift, |x| {
                x * x / (2.0 * r)
            }),
        }?;
        scene.with_surface(grid)
    }

    /// The elastic cylinder of `hertz-two-body` on the block `grid` ([`CylinderOnBlock`]):
    /// radius R, the material of [`UPPER_BLOCK`] (E/3, ν = 0.33), a cap of 0.5R × 0.5R, its
    /// elements `mesh_ratio` (7:4 by default) finer than the block's at the contact, graded
    /// like it; the block clamped at its base.
    pub fn cylinder_on(&self, grid: &Grid) -> CylinderOnBlock {
        let (num, den) = self.mesh_ratio;
        let h = grid.xs.get(1).copied().unwrap_or(1.0);
        let a = self.a_target;
        CylinderOnBlock {
            block: grid.clone(),
            base: Base::Clamped,
            lower: Material {
                young: self.young,
                poisson: self.poisson,
            },
            radius: self.radius,
            cap_width: 0.5 * self.radius,
            cap_height: 0.5 * self.radius,
            h: h * den as f64 / num as f64,
            fine: FINE_OVER_A * a,
            growth: GROWTH,
            upper: self.cylinder_material(),
        }
    }

    /// The material of the second body of the two-body cases ([`UPPER_BLOCK`]: E/3, ν = 0.33).
    pub fn cylinder_material(&self) -> Material {
        Material {
            young: UPPER_BLOCK.1 * self.young,
            poisson: UPPER_BLOCK.2,
        }
    }

    /// The two blocks of the two-body cases on the lower block's `grid` ([`UPPER_BLOCK`],
    /// `mesh_ratio` upper elements across per `lower`).
    pub fn two_blocks(&self, grid: &Grid) -> TwoBlocks {
        let (h_rel, e_rel, nu) = UPPER_BLOCK;
        let (num, den) = self.mesh_ratio;
        let (nx, ny) = (grid.xs.len() - 1, grid.ys.len() - 1);
        let a = self.a_target;
        TwoBlocks {
            width: *grid.xs.last().unwrap_or(&a),
            h_lower: grid.height(),
            h_upper: h_rel * a,
            mesh_lower: (nx, ny),
            mesh_upper: (
                ((nx * num) as f64 / den as f64).round() as usize,
                (ny / 2).max(1),
            ),
            lower: Material {
                young: self.young,
                poisson: self.poisson,
            },
            upper: Material {
                young: e_rel * self.young,
                poisson: nu,
            },
        }
    }

    /// The first guess of the base lift that carries the load on `grid`: the half-space
    /// indentation a²/R (the flat punch: p̄H/E*).
    pub fn lift_guess(&self, case: Case, grid: &Grid) -> f64 {
        match case {
            c if c.two_body().is_some() => {
                let p0 = self.exact(c).1.p0;
                p0 * self.a_target / self.two_blocks(grid).exact_pressure(self.a_target)
            }
            c if c.is_uniform() => self.exact(c).1.p0 * grid.height() / self.e_star(),
            _ => self.a_target * self.a_target / self.radius,
        }
    }
}

/// Which benchmark.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Case {
    /// Rigid cylinder on a block, plane strain.
    HertzPlane,
    /// Rigid sphere on a cylindrical block, axisymmetric.
    HertzAxi,
    /// Flat rigid punch covering the top of a block, plane strain (one body, uniform
    /// compression: not the two-body contact patch test). Serialized `flat-punch`; `patch`
    /// (its former name) still reads.
    #[serde(alias = "patch")]
    FlatPunch,
    /// The flat punch turned by 15° onto an inclined rigid plane
    /// ([`crate::model::inclined`]): contact rows with two terms, the same uniform pressure.
    #[serde(rename = "inclined-15")]
    Inclined15,
    /// The flat punch turned by 30°.
    #[serde(rename = "inclined-30")]
    Inclined30,
    /// The flat punch turned by 45°.
    #[serde(rename = "inclined-45")]
    Inclined45,
    /// The two-body contact patch test ([`crate::model::two_body`]): an upper block on the
    /// a × a block, non-matching interface meshes, mortar rows.
    #[serde(rename = "patch-two-body-mortar")]
    PatchMortar,
    /// The two-body patch test with one-pass node-to-segment rows (which fail it).
    #[serde(rename = "patch-two-body-nts-1")]
    PatchNts1,
    /// Hertz between two elastic bodies ([`crate::model::cylinder`]): an elastic cylinder
    /// (E/3, ν = 0.33) on the Hertz block, plane strain, non-matching meshes, mortar rows;
    /// Hertz with the pair's E*.
    #[serde(rename = "hertz-two-body")]
    HertzTwoBody,
    /// The rigid cylinder of `hertz-plane` with every contact row along the obstacle's normal
    /// at its node ([`crate::model::inclined::with_nodal_normals`]): a curved rigid obstacle
    /// with nodal normals, two terms per row.
    #[serde(rename = "hertz-normals")]
    HertzNormals,
    /// The two-body patch test with two-pass node-to-segment rows: linearly dependent, so
    /// Lagrange (and `condensed`) refuse them and the case has no Lagrange reference; the
    /// pressures are the nodal ones of both bodies' interface nodes
    /// ([`crate::model::two_body`], **Pressure**).
    #[serde(rename = "patch-two-body-nts-2")]
    PatchNts2,
}

/// The upper block of the two-body cases: its height over a, its modulus over the lower
/// block's E and its ν.
pub const UPPER_BLOCK: (f64, f64, f64) = (0.5, 1.0 / 3.0, 0.33);

/// The default elements across the second body per element of the first (upper, lower):
/// `7:4`, so the interface meshes never match (5:9, 10:18, 20:35 on the default meshes).
pub const MESH_RATIO: (usize, usize) = (7, 4);

impl Case {
    /// The cases `contact_bench` runs by default: all but `hertz-two-body` (≈ 1 min of its
    /// own on 2 cores, beside the default run's ≈ 40 s: together too close to its 2-minute
    /// budget), `hertz-normals` and `patch-two-body-nts-2` (no Lagrange reference).
    pub const DEFAULT: &'static [Case] = Case::ALL.split_at(8).0;

    /// Every case, in table order.
    pub const ALL: [Case; 11] = [
        Case::HertzPlane,
        Case::HertzAxi,
        Case::FlatPunch,
        Case::Inclined15,
        Case::Inclined30,
        Case::Inclined45,
        Case::PatchMortar,
        Case::PatchNts1,
        Case::HertzTwoBody,
        Case::HertzNormals,
        Case::PatchNts2,
    ];

    /// Its name in rows and options (`hertz-plane`, `hertz-axi`, `flat-punch`,
    /// `inclined-15`, `inclined-30`, `inclined-45`, `patch-two-body-mortar`,
    /// `patch-two-body-nts-1`, `hertz-two-body`, `hertz-normals`, `patch-two-body-nts-2`).
    pub fn name(self) -> &'static str {
        match self {
            Case::HertzPlane => "hertz-plane",
            Case::HertzAxi => "hertz-axi",
            Case::FlatPunch => "flat-punch",
            Case::Inclined15 => "inclined-15",
            Case::Inclined30 => "inclined-30",
            Case::Inclined45 => "inclined-45",
            Case::PatchMortar => "patch-two-body-mortar",
            Case::PatchNts1 => "patch-two-body-nts-1",
            Case::HertzTwoBody => "hertz-two-body",
            Case::HertzNormals => "hertz-normals",
            Case::PatchNts2 => "patch-two-body-nts-2",
        }
    }

    /// The interface discretization of a two-body case.
    pub fn two_body(self) -> Option<Discretization> {
        match self {
            Case::PatchMortar => Some(Discretization::Mortar),
            Case::PatchNts1 => Some(Discretization::Nts1),
            Case::PatchNts2 => Some(Discretization::Nts2),
            _ => None,
        }
    }

    /// A case with a second elastic body (the two-body patch tests and `hertz-two-body`):
    /// the cases `mesh_ratio` shapes.
    pub fn two_bodies(self) -> bool {
        self.two_body().is_some() || self == Case::HertzTwoBody
    }

    /// The inclination θ of the rigid plane in degrees (0 for the flat punch and Hertz).
    pub fn theta_deg(self) -> f64 {
        match self {
            Case::Inclined15 => 15.0,
            Case::Inclined30 => 30.0,
            Case::Inclined45 => 45.0,
            _ => 0.0,
        }
    }

    /// A uniform-pressure case on an a × a block: the flat punch (level or inclined) and the
    /// two-body patch test.
    pub fn is_uniform(self) -> bool {
        !matches!(
            self,
            Case::HertzPlane | Case::HertzAxi | Case::HertzTwoBody | Case::HertzNormals
        )
    }

    /// The base of a single-body case on one grid, whose rows are one per top node in order
    /// (the cases `--vtk` writes: [`crate::vtk::indentation_fields`]); None for the others.
    pub fn vtk_base(self) -> Option<Base> {
        match self {
            Case::HertzPlane | Case::HertzAxi | Case::HertzNormals => Some(Base::Clamped),
            Case::FlatPunch => Some(Base::Sliding),
            _ => None,
        }
    }

    /// A Hertz case against a rigid indenter (the domain study's cases: its block is the
    /// model of the half-space whose bias `err_domain` measures).
    pub fn is_rigid_hertz(self) -> bool {
        matches!(self, Case::HertzPlane | Case::HertzAxi)
    }

    /// How the contact rows are discretized (`nodal`: one row per contact node; two bodies:
    /// `mortar`, `nts-1`, `nts-2`).
    pub fn discretization(self) -> &'static str {
        match self {
            Case::HertzTwoBody => Discretization::Mortar.name(),
            _ => self.two_body().map_or("nodal", Discretization::name),
        }
    }

    /// Whether the case's contact rows are linearly dependent (`patch-two-body-nts-2`):
    /// Lagrange refuses them (a singular saddle point), so the case has no Lagrange reference
    /// and its rows no `err_penalty` or `err_discretization`.
    pub fn dependent_rows(self) -> bool {
        self.two_body() == Some(Discretization::Nts2)
    }

    /// The case named `s` (`patch` is read as `flat-punch`, its former name).
    pub fn from_name(s: &str) -> Option<Case> {
        let s = if s == "patch" { "flat-punch" } else { s };
        Case::ALL.into_iter().find(|c| c.name() == s)
    }

    /// Plane strain or axisymmetric.
    pub fn geometry(self) -> Geometry {
        match self {
            Case::HertzAxi => Geometry::Axisymmetric,
            _ => Geometry::PlaneStrain,
        }
    }
}

/// The analytic solution of one case: contact half-width (radius) and peak pressure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exact {
    /// Contact half-width (plane) or radius (axisymmetric); the block half-width for the flat punch.
    pub a: f64,
    /// Peak (for the flat punch: uniform) pressure.
    pub p0: f64,
    /// Whether the pressure is Hertzian (`p0 √(1 − x²/a²)`) or uniform (the flat punch).
    pub hertzian: bool,
}

impl Exact {
    /// Hertz for load `load`, radius `radius` and contact modulus `e_star` in `geometry`.
    pub fn hertz(geometry: Geometry, load: f64, radius: f64, e_star: f64) -> Exact {
        let pi = std::f64::consts::PI;
        let a = geometry.hertz_half_width(load, radius, e_star);
        let p0 = match geometry {
            Geometry::PlaneStrain => 2.0 * load / (pi * a),
            Geometry::Axisymmetric => 3.0 * load / (2.0 * pi * a * a),
        };
        Exact {
            a,
            p0,
            hertzian: true,
        }
    }

    /// The exact pressure at x.
    pub fn pressure(&self, x: f64) -> f64 {
        if x > self.a * (1.0 + 1e-12) {
            0.0
        } else if self.hertzian {
            self.p0 * (1.0 - (x / self.a).powi(2)).max(0.0).sqrt()
        } else {
            self.p0
        }
    }
}

/// Weighted discrete L2 norm `√(Σ ω_c f_c²)` over every contact node: pressure spilled past
/// the exact radius a counts (the exact pressure is 0 there).
fn node_norm(nodes: &[ContactNode], f: impl Fn(usize) -> f64) -> f64 {
    nodes
        .iter()
        .enumerate()
        .map(|(c, n)| n.weight * f(c).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// `‖p − p_exact‖ / ‖p_exact‖` over every contact node (module doc).
pub fn pressure_error(nodes: &[ContactNode], p: &[f64], exact: &Exact) -> f64 {
    let e = node_norm(nodes, |c| p[c] - exact.pressure(nodes[c].x));
    e / node_norm(nodes, |c| exact.pressure(nodes[c].x))
}

/// `‖p − p_ref‖ / ‖p_exact‖` over every contact node: the distance of two numerical pressure
/// fields in the measure of [`pressure_error`].
pub fn pressure_distance(nodes: &[ContactNode], p: &[f64], p_ref: &[f64], exact: &Exact) -> f64 {
    let e = node_norm(nodes, |c| p[c] - p_ref[c]);
    e / node_norm(nodes, |c| exact.pressure(nodes[c].x))
}

/// The contact half-width read from nodal pressures: beyond the outermost node k whose
/// pressure exceeds `floor`, where p² extrapolated linearly through nodes k−1 and k reaches 0
/// (exact for the Hertzian edge p ∝ √(a − x)), kept within [x_k, x_{k+1}]; x_k where the
/// pressure does not fall towards node k (a flat punch) or every node is in contact; 0 where
/// none is.
pub fn contact_width(nodes: &[ContactNode], p: &[f64], floor: f64) -> f64 {
    let Some(k) = p.iter().rposition(|&v| v > floor) else {
        return 0.0;
    };
    if k + 1 == nodes.len() || k == 0 {
        return nodes[k].x;
    }
    let (q0, q1) = (p[k - 1].max(0.0).powi(2), p[k].powi(2));
    if q0 <= q1 {
        return nodes[k].x;
    }
    let a = nodes[k].x + q1 * (nodes[k].x - nodes[k - 1].x) / (q0 - q1);
    a.clamp(nodes[k].x, nodes[k + 1].x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every case reads back from its name (also through serde); the default run holds the
    /// first eight, without the on-request cases; `patch-two-body-nts-2` is the two-pass
    /// discretization, the only one with dependent rows.
    #[test]
    fn case_names_and_the_default_run() {
        for c in Case::ALL {
            assert_eq!(Case::from_name(c.name()), Some(c));
            let json = serde_json::to_string(&c).unwrap();
            assert_eq!(json, format!("\"{}\"", c.name()));
            assert_eq!(c.dependent_rows(), c == Case::PatchNts2);
        }
        assert_eq!(Case::DEFAULT.len(), 8);
        for c in [Case::HertzTwoBody, Case::HertzNormals, Case::PatchNts2] {
            assert!(!Case::DEFAULT.contains(&c), "{}", c.name());
        }
        assert_eq!(Case::PatchNts2.discretization(), "nts-2");
        assert!(Case::PatchNts2.is_uniform());
    }

    /// Hertz's load–width relations invert: the load that gives width a back from a.
    #[test]
    fn hertz_closed_forms_are_consistent() {
        let pi = std::f64::consts::PI;
        let (r, e) = (50.0, 2.0e5);
        for g in [Geometry::PlaneStrain, Geometry::Axisymmetric] {
            let a = g.hertz_half_width(100.0, r, e);
            assert!((g.hertz_load(a, r, e) - 100.0).abs() <= 4.0 * f64::EPSILON * 100.0);
        }
        let pl = Exact::hertz(Geometry::PlaneStrain, 100.0, r, e);
        // P = π a p0 / 2 (plane), P = 2π a² p0 / 3 (axisymmetric): the integrals of p.
        assert!((pi * pl.a * pl.p0 / 2.0 - 100.0).abs() <= 1e-12 * 100.0);
        let ax = Exact::hertz(Geometry::Axisymmetric, 100.0, r, e);
        assert!((2.0 * pi * ax.a * ax.a * ax.p0 / 3.0 - 100.0).abs() <= 1e-12 * 100.0);
        // p0 = E* a / (2R) (plane), p0 = 2 E* a / (π R) (axisymmetric).
        assert!((pl.p0 - e * pl.a / (2.0 * r)).abs() <= 1e-12 * pl.p0);
        assert!((ax.p0 - 2.0 * e * ax.a / (pi * r)).abs() <= 1e-12 * ax.p0);
    }
}

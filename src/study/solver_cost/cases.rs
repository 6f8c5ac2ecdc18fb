//! The families of `solver_cost` and their mesh levels (h halving from level to level), each
//! with its Lagrange reference and its discretization error.
//!
//! - `hertz-plane`, `hertz-axi`: the contact benchmarks' Hertz cases ([`crate::study::hertz`]:
//!   rigid cylinder / sphere of R = 10 on a 16a block, E = 210e3, ν = 0.3, loaded for a = 1),
//!   element size h/a at the contact = `hertz_h0`/2^l; every solve force-controlled
//!   ([`solve_at_load`]) so that rules are compared at equal load. Discretization error:
//!   Lagrange's pressure against Hertz's on this block ([`hertz::pressure_error`], which also
//!   holds the finite block's bias); a rule's penalty error: its pressure's distance from
//!   Lagrange's ([`hertz::pressure_distance`]). Length scale (δ): a; ε relative to E*/a.
//! - **Rows that couple DOFs, force-controlled the same way** (the contact benchmarks' cases):
//!   `hertz-normals` (`hertz-plane` with every row along the cylinder's normal at its node,
//!   `−f'·u_x + v ≤ …` normalized: two terms on one node), `patch-nts-1` (the two-body patch
//!   test, a block on the a × a block at 7:4 interface meshes, one-pass node-to-segment rows:
//!   three terms on nodes of both bodies; it fails the patch test, which is its discretization
//!   error) and `hertz-two-body` (an elastic cylinder, E/3, ν = 0.33, on the Hertz block,
//!   mortar rows: each row couples the slave node's neighbours and every master node under
//!   them; Hertz with the pair's E*). Not in the default run: `hertz-two-body`.
//! - `membrane`: the 5-point membrane (`−Δu = f`, f = −10, unit square, clamped edges,
//!   [`membrane::stiffness`]) with side = (side₀ + 1)·2^l − 1 interior nodes (h = 1/(side+1)),
//!   on the obstacle `u ≥ ψ = −0.35 − 0.7·((x−½)² + (y−½)²)` at every node. Length scale: 0.35
//!   (the obstacle's depth at the centre); ε relative to max K_dd.
//! - `beam`: the cantilever on a wavy bed ([`crate::model::beam::bed`], length 100,
//!   E = 2.1e5, 1×1 section) with `beam_el0`·2^l elements, a uniform load 2e-3 per unit length
//!   (nodal −0.2/n_el), the bed `w ≥ −0.5·(1 + sin(3πx/L))·x/L` at every node. Length scale:
//!   0.5; ε relative to max K_dd.
//!
//! - `incline-15`, `incline-30`, `incline-45`: the block of [`incline_block`] (W × H = 2 × 1,
//!   E = 1, ν = 0.3, crowned bottom along the plane, top clamped and pressed by 0.01·H) on the
//!   plane inclined at θ = 15°, 30°, 45°, with `6·2^l × 3·2^l` Q4 elements: one two-term row
//!   `sinθ·u_x + cosθ·u_y ≥ −g₀` per bottom node, the DOFs and supports axis-aligned — the
//!   coupled rows a diagonal preconditioner cannot absorb. Length scale: 0.01 (the press);
//!   ε relative to max `d_cᵀ K d_c`.
//!
//! - `hertz-3d`: the quarter of an `8a × 8a × 8a` block of trilinear hexahedra
//!   ([`crate::model::solid`]: E = 210e3, ν = 0.3, clamped base, symmetry planes x = 0 and
//!   y = 0) under the rigid sphere of R = 10, element size h/a at the contact =
//!   `sphere_h0`/2^l on `[0, 1.25a]` growing by 2 beyond: one row `u_z ≤ r²/(2R)` per top
//!   node. Displacement-controlled: the base lift is set by Lagrange so that it carries
//!   Hertz's load for a = 1 (a secant step from the half-space's a²/R), and every rule
//!   solves at that lift. Discretization error: Lagrange's pressure against Hertz's for the
//!   load it carries ([`hertz::pressure_error`], r = √(x² + y²), ω the top areas), the
//!   finite block's bias included. Length scale: a; ε relative to max K_dd. A rule's penalty
//!   error: its pressure's distance from Lagrange's on the same mesh at the same lift, in the
//!   same measure ([`hertz::pressure_distance`]), as for the 2-D Hertz families.
//!
//! For `membrane`, `beam` and the incline families the errors are on u: a rule's
//! penalty error is `‖u − u_L‖∞/‖u_L‖∞` against Lagrange on the same mesh; the
//! discretization error of level l is estimated by the next level,
//! `‖u_l − R u_{l+1}‖∞/‖R u_{l+1}‖∞` at the coarse nodes (R: restriction to them); the finest
//! level's is extrapolated at the last observed ratio (`err_discretization_extrapolated`).

use crate::error::{Error, Result};
use crate::model::beam::bed::{self, Bed};
use crate::model::elasticity::{Base, ContactNode, Geometry, Grid, Material};
use crate::model::incline_block;
use crate::model::membrane;
use crate::model::solid::{self, Grid3, SphereIndentation};
use crate::strategy::force_control::{solve_at_load, FORCE_TOL};
use crate::strategy::{self, Method, Solution};
use crate::study::hertz::{self, Case, Exact, Setup};
use crate::system::{Constraint, ConstraintKind, Problem};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// A family of `solver_cost`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
#[value(rename_all = "kebab-case")]
pub enum Family {
    /// Hertz, plane strain.
    HertzPlane,
    /// Hertz, axisymmetric.
    HertzAxi,
    /// The 5-point membrane on a paraboloid obstacle.
    Membrane,
    /// The cantilever on a wavy bed.
    Beam,
    /// The block pressed on a plane inclined at 15° (two-term rows).
    #[serde(rename = "incline-15")]
    #[value(name = "incline-15")]
    Incline15,
    /// The same at 30°.
    #[serde(rename = "incline-30")]
    #[value(name = "incline-30")]
    Incline30,
    /// The same at 45°.
    #[serde(rename = "incline-45")]
    #[value(name = "incline-45")]
    Incline45,
    /// A 3-D hexahedral block under a rigid sphere (one-DOF rows).
    #[serde(rename = "hertz-3d")]
    #[value(name = "hertz-3d")]
    Hertz3d,
    /// Hertz plane with every row along the cylinder's normal at its node (two terms).
    HertzNormals,
    /// An elastic cylinder on the Hertz block, mortar rows (coupling nodes of both bodies).
    HertzTwoBody,
    /// The two-body patch test with one-pass node-to-segment rows (three terms).
    #[serde(rename = "patch-nts-1")]
    #[value(name = "patch-nts-1")]
    PatchNts1,
}

impl Family {
    /// Every family, in table order.
    pub const ALL: [Family; 11] = [
        Family::HertzPlane,
        Family::HertzAxi,
        Family::Membrane,
        Family::Beam,
        Family::Incline15,
        Family::Incline30,
        Family::Incline45,
        Family::HertzNormals,
        Family::PatchNts1,
        Family::HertzTwoBody,
        Family::Hertz3d,
    ];

    /// The families of the default run, within 6 minutes on 2 cores: all but
    /// `hertz-two-body` (mortar rows; minutes of its own) and `hertz-axi` (one-DOF rows like
    /// `hertz-plane`'s, whose costs it repeats within a few per cent); `--families` adds them.
    pub fn defaults() -> Vec<Family> {
        Family::ALL
            .into_iter()
            .filter(|f| !matches!(f, Family::HertzTwoBody | Family::HertzAxi))
            .collect()
    }

    /// Its name in rows.
    pub fn name(self) -> &'static str {
        match self {
            Family::HertzPlane => "hertz-plane",
            Family::HertzAxi => "hertz-axi",
            Family::Membrane => "membrane",
            Family::Beam => "beam",
            Family::Incline15 => "incline-15",
            Family::Incline30 => "incline-30",
            Family::Incline45 => "incline-45",
            Family::Hertz3d => "hertz-3d",
            Family::HertzNormals => "hertz-normals",
            Family::HertzTwoBody => "hertz-two-body",
            Family::PatchNts1 => "patch-nts-1",
        }
    }

    /// The contact benchmark case of a family solved under force control (the Hertz cases,
    /// the two-body ones; [`crate::study::hertz`]).
    pub fn hertz_case(self) -> Option<Case> {
        match self {
            Family::HertzPlane => Some(Case::HertzPlane),
            Family::HertzAxi => Some(Case::HertzAxi),
            Family::HertzNormals => Some(Case::HertzNormals),
            Family::HertzTwoBody => Some(Case::HertzTwoBody),
            Family::PatchNts1 => Some(Case::PatchNts1),
            _ => None,
        }
    }

    /// The plane's inclination θ in degrees (incline families).
    pub fn incline_deg(self) -> Option<f64> {
        match self {
            Family::Incline15 => Some(15.0),
            Family::Incline30 => Some(30.0),
            Family::Incline45 => Some(45.0),
            _ => None,
        }
    }

    /// Whether its contact rows couple DOFs (two or more terms).
    pub fn coupled(self) -> bool {
        self.incline_deg().is_some()
            || matches!(
                self,
                Family::HertzNormals | Family::HertzTwoBody | Family::PatchNts1
            )
    }
}

/// The Hertz material and geometry of `solver_cost` (those of `contact_bench`).
pub const HERTZ: Setup = Setup {
    young: 210e3,
    poisson: 0.3,
    radius: 10.0,
    a_target: 1.0,
    mesh_ratio: crate::study::hertz::MESH_RATIO,
};
/// The Hertz block over a.
pub const HERTZ_BLOCK: f64 = 16.0;
/// Elements along x of the incline families' coarsest level (`6 × 3`; level l: `6·2^l × 3·2^l`).
pub const INCLINE_NX0: usize = 6;

/// One mesh level of one family, with its Lagrange reference.
pub struct Level {
    /// The family.
    pub family: Family,
    /// Level index (0: coarsest).
    pub index: usize,
    /// Element size (Hertz: h/a at the contact; membrane: 1/(side+1); beam: L/n_el over L;
    /// incline: 1/n_x).
    pub h: f64,
    /// Free DOFs.
    pub n_dofs: usize,
    /// The length δ is relative to.
    pub scale: f64,
    /// The stiffness ε is relative to.
    pub k_scale: f64,
    /// `augmented`'s ε: the constraints' mean K_dd (as in `contact_bench`).
    pub aug_eps: f64,
    /// Lagrange's discretization error (module doc).
    pub err_discretization: f64,
    /// Whether it was extrapolated (the finest membrane and beam levels).
    pub err_discretization_extrapolated: bool,
    kind: Kind,
}

enum Kind {
    Hertz {
        case: Case,
        grid: Grid,
        load: f64,
        exact: Exact,
        lift: f64,
        p_lagrange: Vec<f64>,
    },
    Fixed {
        problem: Problem,
        u_lagrange: Vec<f64>,
        /// The restriction: for each DOF of the next coarser level, its DOF here.
        from_coarse: Vec<usize>,
    },
    Sphere {
        scene: SphereIndentation,
        /// The top nodes at their distance from the axis.
        nodes: Vec<ContactNode>,
        exact: Exact,
        p_lagrange: Vec<f64>,
    },
}

/// A rule's solve on a level.
pub struct Solved {
    /// The problem it solved (Hertz: at the lift that carries the load).
    pub problem: Problem,
    /// Its solution.
    pub sol: Solution,
    /// Its penalty error (module doc).
    pub err_penalty: f64,
    /// Linear solves (Hertz: force-control solves; else 1 per solve call).
    pub solves: usize,
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn rel_inf(u: &[f64], r: &[f64]) -> f64 {
    let d: Vec<f64> = u.iter().zip(r).map(|(a, b)| a - b).collect();
    inf_norm(&d) / inf_norm(r)
}

impl Level {
    /// Solves `method` on this level.
    pub fn solve(&self, method: Method) -> Result<Solved> {
        match &self.kind {
            Kind::Hertz {
                case,
                grid,
                load,
                exact,
                lift,
                p_lagrange,
            } => {
                let l = solve_at_load(
                    case.name(),
                    |w| HERTZ.scene(*case, grid, w),
                    method,
                    *load,
                    *lift,
                    method.strategy().force_tol,
                )?;
                let p = l.scene.pressures(&l.sol.u);
                let err = hertz::pressure_distance(&l.scene.contact, &p, p_lagrange, exact);
                Ok(Solved {
                    problem: l.scene.problem,
                    sol: l.sol,
                    err_penalty: err,
                    solves: l.solves,
                })
            }
            Kind::Sphere {
                scene,
                nodes,
                exact,
                p_lagrange,
            } => {
                let sol = strategy::solve(&scene.problem, method)?;
                let p = scene.pressures(&sol.u);
                Ok(Solved {
                    problem: scene.problem.clone(),
                    err_penalty: hertz::pressure_distance(nodes, &p, p_lagrange, exact),
                    sol,
                    solves: 1,
                })
            }
            Kind::Fixed {
                problem,
                u_lagrange,
                ..
            } => {
                let sol = strategy::solve(problem, method)?;
                Ok(Solved {
                    problem: problem.clone(),
                    err_penalty: rel_inf(&sol.u, u_lagrange),
                    sol,
                    solves: 1,
                })
            }
        }
    }
}

/// The membrane problem with `side` interior nodes per direction (module doc).
pub fn membrane_problem(side: usize) -> Result<Problem> {
    let h = 1.0 / (side as f64 + 1.0);
    let k = membrane::stiffness(side, 1.0)?;
    let q = vec![-10.0 * h * h; side * side];
    let mut constraints = Vec::with_capacity(side * side);
    for i in 0..side {
        for j in 0..side {
            let (x, y) = ((i + 1) as f64 * h, (j + 1) as f64 * h);
            constraints.push(Constraint::on_dof(
                membrane::dof(side, i, j),
                -0.35 - 0.7 * ((x - 0.5).powi(2) + (y - 0.5).powi(2)),
                ConstraintKind::Lower,
            ));
        }
    }
    Problem::new(k, q, constraints)
}

/// The beam problem with `n_el` elements (module doc).
pub fn beam_problem(n_el: usize) -> Result<Problem> {
    bed::problem(Bed {
        n_el,
        load: -0.2 / n_el as f64,
        amp: 0.5,
        waves: 3.0,
    })
    .map(Problem::in_preferred_storage)
}

/// The Hertz level `h_rel` of `case`: its mesh, load and Lagrange at the load.
fn hertz_level(family: Family, case: Case, index: usize, h_rel: f64) -> Result<Level> {
    let (load, exact) = HERTZ.exact(case);
    let grid = HERTZ.grid(case, h_rel, HERTZ_BLOCK)?;
    let guess = HERTZ.lift_guess(case, &grid);
    let lag = solve_at_load(
        case.name(),
        |w| HERTZ.scene(case, &grid, w),
        Method::lagrange(),
        load,
        guess,
        FORCE_TOL,
    )?;
    let p_lagrange = lag.scene.pressures(&lag.sol.u);
    let err = hertz::pressure_error(&lag.scene.contact, &p_lagrange, &exact);
    Ok(Level {
        family,
        index,
        h: h_rel,
        n_dofs: lag.scene.n_free,
        scale: HERTZ.a_target,
        k_scale: HERTZ.e_star() / HERTZ.a_target,
        aug_eps: lag.scene.problem.mean_constraint_stiffness(),
        err_discretization: err,
        err_discretization_extrapolated: false,
        kind: Kind::Hertz {
            case,
            grid,
            load,
            exact,
            lift: lag.scene.lift,
            p_lagrange,
        },
    })
}

/// A membrane or beam level: the problem, Lagrange on it, and the map from the coarser
/// level's DOFs to its own.
fn fixed_level(family: Family, index: usize, size: usize) -> Result<Level> {
    let (problem, h, scale, from_coarse) = match family {
        _ if family.incline_deg().is_some() => {
            let theta = family.incline_deg().unwrap_or(30.0);
            let (nx, ny) = (size, size / 2);
            let (cx, cy) = (nx / 2, ny / 2);
            let map = (0..2 * (cx + 1) * cy)
                .map(|d| {
                    let (node, c) = (d / 2, d % 2);
                    incline_block::free_dof(ny, 2 * (node / cy), 2 * (node % cy), c)
                })
                .collect();
            (
                incline_block::problem(theta, nx, ny)?,
                1.0 / nx as f64,
                incline_block::PRESS * incline_block::HEIGHT,
                map,
            )
        }
        Family::Membrane => {
            let side = size;
            let coarse = side.div_ceil(2) - 1;
            let map = (0..coarse * coarse)
                .map(|d| membrane::dof(side, 2 * (d / coarse) + 1, 2 * (d % coarse) + 1))
                .collect();
            (
                membrane_problem(side)?,
                1.0 / (side as f64 + 1.0),
                0.35,
                map,
            )
        }
        _ => {
            let n_el = size;
            // Node i ≥ 1 has DOFs 3(i−1) + c; coarse node i is fine node 2i.
            let map = (0..3 * (n_el / 2))
                .map(|d| 3 * (2 * (d / 3 + 1) - 1) + d % 3)
                .collect();
            (beam_problem(n_el)?, 1.0 / n_el as f64, 0.5, map)
        }
    };
    let lag = strategy::solve(&problem, Method::lagrange())?;
    if !lag.stats.converged {
        return Err(Error::Numerical(format!(
            "{} level {index}: Lagrange did not converge",
            family.name()
        )));
    }
    Ok(Level {
        family,
        index,
        h,
        n_dofs: problem.n(),
        scale,
        k_scale: problem.max_constraint_stiffness(),
        aug_eps: problem.mean_constraint_stiffness(),
        err_discretization: f64::NAN,
        err_discretization_extrapolated: false,
        kind: Kind::Fixed {
            problem,
            u_lagrange: lag.u,
            from_coarse,
        },
    })
}

/// The sphere's block over a, its fine zone over a and the growth beyond (module doc).
pub const SPHERE_BLOCK: (f64, f64, f64) = (8.0, 1.25, 2.0);

/// The 3-D mesh of `hertz-3d` at element size `h_rel`·a (module doc).
pub fn sphere_grid(h_rel: f64) -> Result<Grid3> {
    let a = HERTZ.a_target;
    let (block, fine, growth) = SPHERE_BLOCK;
    Grid3::graded(block * a, block * a, h_rel * a, fine * a, growth)
}

/// The `hertz-3d` scene on `grid` at base lift `lift`.
pub fn sphere_scene(grid: &Grid3, lift: f64) -> Result<SphereIndentation> {
    let mat = Material {
        young: HERTZ.young,
        poisson: HERTZ.poisson,
    };
    solid::sphere_indentation(grid, &mat, Base::Clamped, HERTZ.radius, lift)
}

/// What Lagrange gives on a `hertz-3d` mesh: its scene at the lift that carries Hertz's load
/// for a = 1 (module doc), its solution and its pressures against Hertz's.
pub struct SphereCheck {
    /// The scene at the lift.
    pub scene: SphereIndentation,
    /// Lagrange's u there.
    pub u: Vec<f64>,
    /// The load it carries.
    pub load: f64,
    /// Hertz for that load.
    pub exact: Exact,
    /// `p_err_rel` of its pressures ([`hertz::pressure_error`]).
    pub p_err_rel: f64,
    /// The pressure at the node on the axis over Hertz's p0.
    pub p0_ratio: f64,
    /// The contact radius read along the x axis ([`hertz::contact_width`]) over Hertz's a.
    pub a_ratio: f64,
    /// The top nodes at their distance r from the axis, with their areas.
    pub nodes: Vec<ContactNode>,
    /// Lagrange's pressures at them.
    pub p: Vec<f64>,
}

/// Lagrange on the `hertz-3d` mesh `grid` (module doc).
pub fn sphere_lagrange(grid: &Grid3) -> Result<SphereCheck> {
    let es = HERTZ.e_star();
    let (a, r) = (HERTZ.a_target, HERTZ.radius);
    let target = Geometry::Axisymmetric.hertz_load(a, r, es);
    let solve = |w: f64| -> Result<(SphereIndentation, Solution, f64)> {
        let scene = sphere_scene(grid, w)?;
        let sol = strategy::solve(&scene.problem, Method::lagrange())?;
        if !sol.stats.converged {
            return Err(Error::Numerical(format!(
                "hertz-3d: Lagrange did not converge at lift {w:e}"
            )));
        }
        let f = scene.total_force(&sol.u);
        Ok((scene, sol, f))
    };
    // Hertz: P ∝ w^{3/2}; one secant step in that law from the half-space's lift.
    let w0 = a * a / r;
    let (_, _, f0) = solve(w0)?;
    if f0.is_nan() || f0 <= 0.0 {
        return Err(Error::Numerical(format!(
            "hertz-3d: no contact force at lift {w0:e} ({f0:e})"
        )));
    }
    let w1 = w0 * (target / f0).powf(2.0 / 3.0);
    let (scene, sol, load) = solve(w1)?;
    let exact = Exact::hertz(Geometry::Axisymmetric, load, r, es);
    let nodes: Vec<ContactNode> = scene
        .contact
        .iter()
        .map(|n| ContactNode::new(n.r(), n.weight))
        .collect();
    let p = scene.pressures(&sol.u);
    let ny = grid.ys.len();
    // The x axis: the top nodes (i, 0), every ny-th.
    let (axis, p_axis): (Vec<ContactNode>, Vec<f64>) = (0..grid.xs.len())
        .map(|i| (nodes[i * ny], p[i * ny]))
        .unzip();
    Ok(SphereCheck {
        p_err_rel: hertz::pressure_error(&nodes, &p, &exact),
        p0_ratio: p[0] / exact.p0,
        a_ratio: hertz::contact_width(&axis, &p_axis, 1e-9 * exact.p0) / exact.a,
        load,
        exact,
        u: sol.u,
        scene,
        nodes,
        p,
    })
}

/// The `hertz-3d` level `h_rel`: its mesh, the lift that carries the load and Lagrange there.
fn sphere_level(index: usize, h_rel: f64) -> Result<Level> {
    let grid = sphere_grid(h_rel)?;
    let check = sphere_lagrange(&grid)?;
    let problem = &check.scene.problem;
    Ok(Level {
        family: Family::Hertz3d,
        index,
        h: h_rel,
        n_dofs: problem.n(),
        scale: HERTZ.a_target,
        k_scale: problem.max_constraint_stiffness(),
        aug_eps: problem.mean_constraint_stiffness(),
        err_discretization: check.p_err_rel,
        err_discretization_extrapolated: false,
        kind: Kind::Sphere {
            scene: check.scene,
            nodes: check.nodes,
            exact: check.exact,
            p_lagrange: check.p,
        },
    })
}

/// The coarsest sizes of the families' levels (each halving from level to level).
#[derive(Clone, Copy, Debug)]
pub struct Coarsest {
    /// Hertz h/a.
    pub hertz_h0: f64,
    /// Membrane side (interior nodes per direction).
    pub membrane_side0: usize,
    /// Beam elements.
    pub beam_el0: usize,
    /// `hertz-3d` h/a.
    pub sphere_h0: f64,
}

/// Every level of `family` (coarse to fine), with Lagrange and the discretization errors.
pub fn levels(family: Family, count: usize, c: Coarsest) -> Result<Vec<Level>> {
    let Coarsest {
        hertz_h0,
        membrane_side0,
        beam_el0,
        sphere_h0,
    } = c;
    // The levels are independent (each its own Lagrange solve): built side by side, finest
    // first (the longest), in level order.
    let mut out = (0..count)
        .rev()
        .collect::<Vec<usize>>()
        .into_par_iter()
        .map(|l| match (family, family.hertz_case()) {
            (_, Some(case)) => hertz_level(family, case, l, hertz_h0 / (1 << l) as f64),
            (Family::Membrane, _) => fixed_level(family, l, (membrane_side0 + 1) * (1 << l) - 1),
            (Family::Beam, _) => fixed_level(family, l, beam_el0 * (1 << l)),
            (Family::Hertz3d, _) => sphere_level(l, sphere_h0 / (1 << l) as f64),
            _ => fixed_level(family, l, INCLINE_NX0 * (1 << l)),
        })
        .collect::<Result<Vec<Level>>>()?;
    out.reverse();
    if family.hertz_case().is_none() && family != Family::Hertz3d {
        for l in 0..count.saturating_sub(1) {
            let (coarse, fine) = out.split_at_mut(l + 1);
            let (c, f) = (&mut coarse[l], &fine[0]);
            if let (
                Kind::Fixed { u_lagrange: uc, .. },
                Kind::Fixed {
                    u_lagrange: uf,
                    from_coarse,
                    ..
                },
            ) = (&c.kind, &f.kind)
            {
                let r: Vec<f64> = from_coarse.iter().map(|&d| uf[d]).collect();
                c.err_discretization = rel_inf(uc, &r);
            }
        }
        if count >= 3 {
            let (e1, e2) = (
                out[count - 3].err_discretization,
                out[count - 2].err_discretization,
            );
            out[count - 1].err_discretization = e2 * (e2 / e1);
        } else if count == 2 {
            out[1].err_discretization = out[0].err_discretization / 4.0;
        }
        if count >= 2 {
            out[count - 1].err_discretization_extrapolated = true;
        }
    }
    Ok(out)
}

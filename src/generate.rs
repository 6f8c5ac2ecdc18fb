//! Randomized contact configurations, seeded and reproducible.
//!
//! Every scene is a pure function of `(seed, family, index)`: its RNG is a ChaCha8 stream seeded
//! with a SplitMix64 hash of the three, so a scene does not depend on which thread or shard
//! builds it, nor on how many scenes precede it.
//!
//! Families:
//! * `beam` — cantilevers and clamped–clamped beams of 3…`max_elements` Euler–Bernoulli
//!   elements (Eq. 30) with random E, section, length and loads, pressed against rigid surfaces
//!   that limit some nodal transverse displacements (bilateral ties like the paper's example,
//!   and unilateral obstacles in the load path).
//! * `membrane` — a 2D membrane (5-point finite-difference grid, `T (4u_ij − Σ neighbours) =
//!   f h²`, clamped edges) under a uniform load pushed onto a rigid obstacle below it
//!   (`u ≥ ψ` at every node — the classic obstacle problem); sparse.
//! * `spectrum` — dense SPD `K = Q diag(λ) Qᵀ` with log-spaced eigenvalues spanning a
//!   prescribed spread (10²…10¹⁰), random loads and contact DOFs; a stress family.
//! * `hertz` — a block of Q4 elements (plane strain or axisymmetric, drawn at random; random
//!   E, ν, indenter radius R ∈ [5, 50]·a, mesh size h ∈ `elastic_h`·a, a = 1) under a rigid
//!   parabolic indenter ([`crate::model::elasticity`]) and a total load P drawn log-uniformly
//!   between the Hertz loads of contact half-widths 0.75a and 1.25a: unilateral constraints
//!   on the top nodes. The scene is displacement-controlled at the lift where the **Lagrange**
//!   solution carries P ([`force_control::solve_at_load`], mismatch ≤ 1e-10); the penalty
//!   rules see the same scene and carry loads of their own (the force-controlled benchmark of
//!   every rule against the analytic solution is `contact_bench`).
//! * `flat-punch` (formerly `patch`, still accepted) — an a × a block (plane strain or
//!   axisymmetric) on a frictionless base under a flat rigid punch over its whole top, at the
//!   lift where the Lagrange solution carries a uniform pressure p̄ ∈ [1e-4, 1e-2]·E*
//!   (log-uniform). One body in uniform compression, not the two-body contact patch test.
//!
//! * `two-body` — two stacked plane-strain blocks (`W = 1`, heights in [0.3, 1], random E
//!   and ν each) with non-matching interface meshes (2…8 elements across each, never equal),
//!   squeezed by a strain in [1e-4, 1e-2] (log-uniform), with `nts-1` or `mortar` interface
//!   rows drawn at random ([`crate::model::two_body`]): rows of up to ~7 terms, D not Boolean.
//!   Every rule runs on it (`optimal` with no certified floor: NaN).
//!
//! The metadata of `hertz` and `flat-punch` records the draws (`geometry`, `young`, `poisson`, `h_over_a`,
//! `radius`, `load`: the total force on the whole body, per unit thickness in plane strain,
//! `a_hertz`: Hertz's half-width for it) and the lift found (`lift`, `force_solves`).
//!
//! The default families ([`DEFAULT_FAMILIES`]) are the first three; `hertz` and `flat-punch`
//! are asked for by name (`--families hertz,flat-punch`). Their constraints are all unilateral, so every
//! rule runs on them, `barrier` included.

use crate::error::{Error, Result};
use crate::model::beam::{Frame, Section};
use crate::model::elasticity::{self, Base, Geometry, Grid, Material};
use crate::model::membrane as membrane_model;
use crate::strategy::{force_control, Method};
use crate::system::{Constraint, ConstraintKind, Problem, Stiffness};
use faer::Mat;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Scene families.
///
/// Read and written by name ([`Family::name`]; [`Family::from_name`] also reads `patch`), in
/// configurations and manifests alike.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Family {
    /// Euler–Bernoulli beams against rigid surfaces.
    Beam,
    /// Membrane obstacle problem (sparse).
    Membrane,
    /// SPD matrices with a prescribed eigenvalue spread.
    Spectrum,
    /// Elastic block on a rigid parabolic indenter (Hertz configuration).
    Hertz,
    /// Elastic block under a flat rigid punch (`flat-punch`; formerly `patch`).
    FlatPunch,
    /// Two stacked elastic blocks with non-matching interface meshes, node-to-segment or mortar
    /// rows (`two-body`: constraint rows that couple DOFs).
    TwoBody,
}

/// Family names accepted on the command line.
pub const FAMILY_NAMES: [&str; 6] = [
    "beam",
    "membrane",
    "spectrum",
    "hertz",
    "flat-punch",
    "two-body",
];

/// The families a sweep runs when none are named.
pub const DEFAULT_FAMILIES: [&str; 3] = ["beam", "membrane", "spectrum"];

/// The families named (names trimmed), each one of `valid`: an unknown name, or one outside
/// `valid`, is an error listing `valid`'s names followed by `extra` (what else the caller
/// accepts, e.g. `", or none"`).
pub fn parse_families<S: AsRef<str>>(
    names: &[S],
    valid: &[Family],
    extra: &str,
) -> Result<Vec<Family>> {
    names
        .iter()
        .map(|n| {
            let n = n.as_ref().trim();
            Family::from_name(n)
                .ok()
                .filter(|f| valid.contains(f))
                .ok_or_else(|| {
                    let names: Vec<&str> = valid.iter().map(|f| f.name()).collect();
                    Error::unknown("family", n, &names, extra)
                })
        })
        .collect()
}

/// Every family, in [`FAMILY_NAMES`] order.
pub const ALL_FAMILIES: [Family; 6] = [
    Family::Beam,
    Family::Membrane,
    Family::Spectrum,
    Family::Hertz,
    Family::FlatPunch,
    Family::TwoBody,
];

impl serde::Serialize for Family {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for Family {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let name = <String as serde::Deserialize>::deserialize(d)?;
        Family::from_name(&name).map_err(|e| serde::de::Error::custom(e.bare_message()))
    }
}

impl Family {
    /// Parses a family name.
    pub fn from_name(s: &str) -> Result<Self> {
        match s {
            "beam" => Ok(Family::Beam),
            "membrane" => Ok(Family::Membrane),
            "spectrum" => Ok(Family::Spectrum),
            "hertz" => Ok(Family::Hertz),
            // `patch`: the family's former name.
            "flat-punch" | "patch" => Ok(Family::FlatPunch),
            "two-body" => Ok(Family::TwoBody),
            _ => Err(Error::unknown("family", s, &FAMILY_NAMES, "")),
        }
    }

    /// The family's name.
    pub fn name(self) -> &'static str {
        match self {
            Family::Beam => "beam",
            Family::Membrane => "membrane",
            Family::Spectrum => "spectrum",
            Family::Hertz => "hertz",
            Family::FlatPunch => "flat-punch",
            Family::TwoBody => "two-body",
        }
    }
}

/// Size ranges of the generators.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GeneratorConfig {
    /// Beam elements: drawn log-uniformly in `[min, max]` (3 ≤ min ≤ max ≤ 500).
    pub beam_elements: (usize, usize),
    /// Membrane grid side (interior nodes per side) in `[min, max]` (≥ 10).
    pub membrane_side: (usize, usize),
    /// Spectrum family dimension in `[min, max]` (≥ 4).
    pub spectrum_n: (usize, usize),
    /// Spectrum family: log10 of the eigenvalue spread in `[min, max]`.
    pub spectrum_log10_spread: (f64, f64),
    /// `hertz` and `flat-punch`: element size at the contact over a, log-uniform in `[min, max]`
    /// (0.02 ≤ min ≤ max ≤ 0.5).
    pub elastic_h: (f64, f64),
}

impl Default for GeneratorConfig {
    fn default() -> Self {
        GeneratorConfig {
            beam_elements: (3, 60),
            membrane_side: (10, 16),
            spectrum_n: (20, 120),
            spectrum_log10_spread: (2.0, 10.0),
            elastic_h: (0.1, 0.25),
        }
    }
}

impl GeneratorConfig {
    /// Checks the ranges; errors repeat the valid range.
    pub fn validate(&self) -> Result<()> {
        self.check().map_err(|(_, e)| e)
    }

    /// [`GeneratorConfig::validate`], each error with its field (its key in a configuration
    /// file's `[generator]` table).
    pub fn check(&self) -> std::result::Result<(), (&'static str, Error)> {
        let bad = |key: &'static str, (a, b): (String, String), valid: &str| {
            Err((key, Error::out_of_range(key, format!("({a}, {b})"), valid)))
        };
        let ints = [
            ("beam_elements", self.beam_elements, (3, 500)),
            ("membrane_side", self.membrane_side, (10, 2000)),
            ("spectrum_n", self.spectrum_n, (4, 4000)),
        ];
        for (key, (a, b), (lo, hi)) in ints {
            if !(lo <= a && a <= b && b <= hi) {
                let valid = format!("{lo} ≤ min ≤ max ≤ {hi}");
                return bad(key, (a.to_string(), b.to_string()), &valid);
            }
        }
        let floats = [
            (
                "spectrum_log10_spread",
                self.spectrum_log10_spread,
                (0.0, 16.0),
            ),
            ("elastic_h", self.elastic_h, (0.02, 0.5)),
        ];
        for (key, (a, b), (lo, hi)) in floats {
            if !(a.is_finite() && b.is_finite() && lo <= a && a <= b && b <= hi) {
                let valid = format!("{lo} ≤ min ≤ max ≤ {hi}");
                return bad(key, (a.to_string(), b.to_string()), &valid);
            }
        }
        Ok(())
    }
}

/// A generated scene.
#[derive(Clone, Debug)]
pub struct GeneratedScene {
    /// `family-index` (e.g. `beam-0007`).
    pub name: String,
    /// Family.
    pub family: Family,
    /// The problem.
    pub problem: Problem,
    /// Provenance (generator parameters and seed).
    pub meta: serde_json::Value,
}

/// SplitMix64 — mixes (seed, family, index) into an independent stream seed.
pub fn scene_seed(seed: u64, family: Family, index: usize) -> u64 {
    let mut z = seed
        .wrapping_add(0x9E37_79B9_7F4A_7C15u64.wrapping_mul(1 + family as u64))
        .wrapping_add((index as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    (rng.random_range(lo.ln()..=hi.ln())).exp()
}

fn int_log_uniform(rng: &mut ChaCha8Rng, lo: usize, hi: usize) -> usize {
    if lo == hi {
        return lo;
    }
    (log_uniform(rng, lo as f64, hi as f64 + 0.999).floor() as usize).clamp(lo, hi)
}

/// Generates scene `index` of `family`.
pub fn generate(
    family: Family,
    index: usize,
    seed: u64,
    cfg: &GeneratorConfig,
) -> Result<GeneratedScene> {
    let s = scene_seed(seed, family, index);
    let name = format!("{}-{index:04}", family.name());
    let mut rng = ChaCha8Rng::seed_from_u64(s);
    let (problem, mut meta) = match family {
        Family::Beam => beam(&mut rng, cfg)?,
        Family::Membrane => membrane(&mut rng, cfg)?,
        Family::Spectrum => spectrum(&mut rng, cfg)?,
        Family::Hertz => elastic(&mut rng, cfg, false, &name)?,
        Family::FlatPunch => elastic(&mut rng, cfg, true, &name)?,
        Family::TwoBody => two_body(&mut rng)?,
    };
    meta["generator"] = serde_json::json!(family.name());
    meta["seed"] = serde_json::json!(seed);
    meta["index"] = serde_json::json!(index);
    meta["scene_seed"] = serde_json::json!(s);
    Ok(GeneratedScene {
        name,
        family,
        problem,
        meta,
    })
}

/// Picks a constraint on `dof` from the unconstrained displacement `u0d`, so that contact
/// actually happens: bilateral ties anywhere near the path, unilateral obstacles in the load path
/// (violated by u0), and some obstacles just out of reach.
fn constraint_from(rng: &mut ChaCha8Rng, dof: usize, u0d: f64) -> Constraint {
    let roll: f64 = rng.random();
    if roll < 0.3 {
        Constraint::on_dof(
            dof,
            u0d * rng.random_range(-0.5..0.9),
            ConstraintKind::Bilateral,
        )
    } else {
        // Obstacle on the side the structure moves to.
        let kind = if u0d >= 0.0 {
            ConstraintKind::Upper
        } else {
            ConstraintKind::Lower
        };
        let factor = if roll < 0.85 {
            rng.random_range(0.1..0.9)
        } else {
            rng.random_range(1.05..1.5)
        };
        Constraint::on_dof(dof, u0d * factor, kind)
    }
}

fn beam(rng: &mut ChaCha8Rng, cfg: &GeneratorConfig) -> Result<(Problem, serde_json::Value)> {
    let n_el = int_log_uniform(rng, cfg.beam_elements.0, cfg.beam_elements.1);
    let length = rng.random_range(10.0..100.0);
    let section = Section::rectangle(
        log_uniform(rng, 1e4, 3e5),
        rng.random_range(0.5..2.0),
        rng.random_range(0.5..2.0),
    );
    let clamped_both = rng.random_bool(0.3);
    let mut frame = Frame::cantilever(n_el, length, section)?;
    if clamped_both {
        let last = frame.nodes.len() - 1;
        frame.fixed[3 * last..3 * last + 3].fill(true);
    }
    let n_nodes = frame.nodes.len();
    let sparse = n_el > 150;
    let k = frame.assemble(sparse)?;
    let n = k.n();
    // Loads: a main transverse load at a random free node, small random nodal loads, axial.
    let mut q = vec![0.0; n];
    let p_main = log_uniform(rng, 0.5, 50.0) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let free_nodes: Vec<usize> = (1..n_nodes)
        .filter(|&i| frame.dof(i, 1).is_some())
        .collect();
    let main_node = free_nodes[rng.random_range(0..free_nodes.len())];
    q[frame.dof(main_node, 1).expect("free")] += p_main;
    for &i in &free_nodes {
        if rng.random_bool(0.3) {
            q[frame.dof(i, 1).expect("free")] += 0.2 * p_main * rng.random_range(-1.0..1.0);
        }
        if let Some(d) = frame.dof(i, 0) {
            if rng.random_bool(0.1) {
                q[d] += p_main * rng.random_range(-5.0..5.0);
            }
        }
    }
    let u0 = k.solve(&q)?;
    let m_max = free_nodes.len().clamp(1, 8);
    let m = rng.random_range(1..=m_max);
    let mut nodes = free_nodes.clone();
    // Partial Fisher–Yates for m distinct nodes.
    for i in 0..m {
        let j = rng.random_range(i..nodes.len());
        nodes.swap(i, j);
    }
    let mut cons: Vec<Constraint> = nodes[..m]
        .iter()
        .map(|&i| {
            let d = frame.dof(i, 1).expect("free");
            constraint_from(rng, d, u0[d])
        })
        .collect();
    cons.sort_by_key(|c| c.lead_dof());
    let meta = serde_json::json!({
        "elements": n_el, "length": length, "E": section.e, "A": section.a, "J": section.j,
        "supports": if clamped_both { "clamped-clamped" } else { "cantilever" },
        "sparse": sparse,
    });
    Ok((Problem::new(k, q, cons)?, meta))
}

fn membrane(rng: &mut ChaCha8Rng, cfg: &GeneratorConfig) -> Result<(Problem, serde_json::Value)> {
    let side = rng.random_range(cfg.membrane_side.0..=cfg.membrane_side.1);
    let n = side * side;
    let h = 1.0 / (side as f64 + 1.0);
    let tension = log_uniform(rng, 0.1, 10.0);
    let idx = |i: usize, j: usize| membrane_model::dof(side, i, j);
    let k = membrane_model::stiffness(side, tension)?;
    let f = -log_uniform(rng, 1.0, 100.0);
    let q = vec![f * h * h; n];
    let u0 = k.solve(&q)?;
    let sag = u0.iter().fold(0.0f64, |a, &v| a.min(v));
    // Obstacle: a tilted paraboloid cap below the membrane touching its lower part.
    let level = sag * rng.random_range(0.3..0.8);
    let (x0, y0) = (rng.random_range(0.3..0.7), rng.random_range(0.3..0.7));
    let curv = rng.random_range(0.0..2.0) * sag.abs();
    let tilt = (
        rng.random_range(-0.3..0.3) * sag.abs(),
        rng.random_range(-0.3..0.3) * sag.abs(),
    );
    let cons = (0..side)
        .flat_map(|i| (0..side).map(move |j| (i, j)))
        .map(|(i, j)| {
            let (x, y) = ((i + 1) as f64 * h, (j + 1) as f64 * h);
            let psi = level
                - curv * ((x - x0).powi(2) + (y - y0).powi(2))
                - tilt.0 * (x - 0.5)
                - tilt.1 * (y - 0.5);
            Constraint::on_dof(idx(i, j), psi, ConstraintKind::Lower)
        })
        .collect();
    let meta = serde_json::json!({
        "side": side, "h": h, "tension": tension, "load_density": f,
        "obstacle": {"level": level, "center": [x0, y0], "curvature": curv, "tilt": [tilt.0, tilt.1]},
    });
    Ok((Problem::new(k, q, cons)?, meta))
}

fn spectrum(rng: &mut ChaCha8Rng, cfg: &GeneratorConfig) -> Result<(Problem, serde_json::Value)> {
    let n = rng.random_range(cfg.spectrum_n.0..=cfg.spectrum_n.1);
    let spread = rng.random_range(cfg.spectrum_log10_spread.0..=cfg.spectrum_log10_spread.1);
    let a = Mat::from_fn(n, n, |_, _| rng.random_range(-1.0..1.0));
    let qr = a.qr();
    let qm = qr.compute_Q();
    let lambda: Vec<f64> = (0..n)
        .map(|i| 10f64.powf(spread * i as f64 / (n - 1) as f64))
        .collect();
    let ql = Mat::from_fn(n, n, |i, l| qm[(i, l)] * lambda[l]);
    let mut k = &ql * qm.transpose();
    // Exact symmetry (rounding in the product above is not symmetric).
    for i in 0..n {
        for j in 0..i {
            let v = 0.5 * (k[(i, j)] + k[(j, i)]);
            k[(i, j)] = v;
            k[(j, i)] = v;
        }
    }
    let k = Stiffness::Dense(k);
    let q: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
    let u0 = k.solve(&q)?;
    let m = rng.random_range(1..=(n / 4).clamp(1, 12));
    let mut dofs: Vec<usize> = (0..n).collect();
    for i in 0..m {
        let j = rng.random_range(i..n);
        dofs.swap(i, j);
    }
    let mut cons: Vec<Constraint> = dofs[..m]
        .iter()
        .map(|&d| constraint_from(rng, d, u0[d]))
        .collect();
    cons.sort_by_key(|c| c.lead_dof());
    let meta = serde_json::json!({"n": n, "log10_spread": spread});
    Ok((Problem::new(k, q, cons)?, meta))
}

/// A `hertz` (`punch = false`) or `flat-punch` scene (module doc), named `name` in errors.
fn elastic(
    rng: &mut ChaCha8Rng,
    cfg: &GeneratorConfig,
    punch: bool,
    name: &str,
) -> Result<(Problem, serde_json::Value)> {
    let geometry = if rng.random_bool(0.5) {
        Geometry::PlaneStrain
    } else {
        Geometry::Axisymmetric
    };
    let material = Material {
        young: log_uniform(rng, 1e3, 1e6),
        poisson: rng.random_range(0.0..0.45),
    };
    let e_star = material.contact_modulus();
    let h = log_uniform(rng, cfg.elastic_h.0, cfg.elastic_h.1);
    // The grid, its support, the load, and the half-space's response to it as the search's
    // first lift.
    let (grid, base, radius, load, guess, a_hertz) = if punch {
        let grid = Grid::graded(1.0, 1.0, h, 1.0, 1.0)?;
        // Mean pressure p̄ on the whole top: A = 2 (plane, per unit thickness) or π.
        let p_mean = log_uniform(rng, 1e-4, 1e-2) * e_star;
        let area = match geometry {
            Geometry::PlaneStrain => 2.0,
            Geometry::Axisymmetric => std::f64::consts::PI,
        };
        let guess = p_mean * grid.height() / e_star;
        (grid, Base::Sliding, None, p_mean * area, guess, None)
    } else {
        let r = log_uniform(rng, 5.0, 50.0);
        let grid = Grid::graded(8.0, 8.0, h, 1.5, 1.3)?;
        let (lo, hi) = (
            geometry.hertz_load(A_HERTZ.0, r, e_star),
            geometry.hertz_load(A_HERTZ.1, r, e_star),
        );
        let load = log_uniform(rng, lo, hi);
        let a = geometry.hertz_half_width(load, r, e_star);
        (grid, Base::Clamped, Some(r), load, a * a / r, Some(a))
    };
    let scene = |w: f64| {
        elasticity::indentation(&grid, geometry, &material, base, w, |x| match radius {
            Some(r) => x * x / (2.0 * r),
            None => 0.0,
        })
    };
    let loaded = force_control::solve_at_load(
        name,
        scene,
        Method::lagrange(),
        load,
        guess,
        force_control::FORCE_TOL,
    )?;
    let meta = serde_json::json!({
        "geometry": geometry,
        "young": material.young,
        "poisson": material.poisson,
        "h_over_a": h,
        "radius": radius,
        "load": load,
        "a_hertz": a_hertz,
        "lift": loaded.scene.lift,
        "force_solves": loaded.solves,
    });
    Ok((loaded.scene.problem, meta))
}

/// `hertz`: the load is drawn log-uniformly between the Hertz loads of these contact
/// half-widths (radii), in units of a; the mesh is fine (size h) up to 1.5.
const A_HERTZ: (f64, f64) = (0.75, 1.25);

/// A `two-body` scene (module doc): the draws in the metadata.
fn two_body(rng: &mut ChaCha8Rng) -> Result<(Problem, serde_json::Value)> {
    use crate::model::two_body::{patch, Discretization, TwoBlocks};
    let mut material = || Material {
        young: log_uniform(rng, 1e3, 1e6),
        poisson: rng.random_range(0.0..0.45),
    };
    let (lower, upper) = (material(), material());
    let nx_lower = rng.random_range(2..=8usize);
    let mut nx_upper = rng.random_range(2..=7usize);
    if nx_upper >= nx_lower {
        nx_upper += 1; // 2..=8 without nx_lower: the interface meshes never match
    }
    let blocks = TwoBlocks {
        width: 1.0,
        h_lower: rng.random_range(0.3..1.0),
        h_upper: rng.random_range(0.3..1.0),
        mesh_lower: (nx_lower, rng.random_range(1..=4usize)),
        mesh_upper: (nx_upper, rng.random_range(1..=4usize)),
        lower,
        upper,
    };
    let strain = log_uniform(rng, 1e-4, 1e-2);
    let squeeze = strain * (blocks.h_lower + blocks.h_upper);
    let disc = if rng.random_bool(0.5) {
        Discretization::Nts1
    } else {
        Discretization::Mortar
    };
    let scene = patch(&blocks, squeeze, disc)?;
    let exact_pressure = blocks.exact_pressure(squeeze);
    let meta = serde_json::json!({
        "discretization": disc.name(),
        "mesh_lower": blocks.mesh_lower,
        "mesh_upper": blocks.mesh_upper,
        "h_lower": blocks.h_lower,
        "h_upper": blocks.h_upper,
        "young": lower.young,
        "poisson": lower.poisson,
        "young2": upper.young,
        "poisson2": upper.poisson,
        "squeeze": squeeze,
        "exact_pressure": exact_pressure,
    });
    Ok((scene.problem, meta))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_family_reads_back_by_its_name_in_list_order() {
        let names: Vec<&str> = ALL_FAMILIES.iter().map(|f| f.name()).collect();
        assert_eq!(names, FAMILY_NAMES);
        for f in ALL_FAMILIES {
            assert_eq!(Family::from_name(f.name()).unwrap(), f);
            let json = serde_json::to_string(&f).unwrap();
            assert_eq!(json, format!("\"{}\"", f.name()));
            assert_eq!(serde_json::from_str::<Family>(&json).unwrap(), f);
        }
        let e = parse_families(&["beam", "shell"], &[Family::Beam], ", or none").unwrap_err();
        assert!(
            e.to_string().contains("'shell' (valid: beam, or none)"),
            "{e}"
        );
    }
}

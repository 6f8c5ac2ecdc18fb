//! Scenes that scale to 10⁶ DOFs for the run-time and engine-scale studies: a cantilever on a
//! Winkler foundation ([`beam_scene`]) and the 5-point membrane on a paraboloid obstacle
//! ([`membrane_scene`]), built directly from the model code with their displacement and
//! stiffness scales (δ and ε of those studies are relative to them).

use crate::error::Result;
use crate::model::beam::{Frame, Section};
use crate::system::{Constraint, ConstraintKind, Problem};

/// A scene of the run-time and engine-scale studies.
#[derive(Clone, Debug)]
pub struct PerfScene {
    /// `beam` or `membrane`.
    pub family: String,
    /// The requested size.
    pub size: usize,
    /// The problem.
    pub problem: Problem,
    /// Displacement scale max_c |u0\[d_c\]| (δ and tolerances are relative to it).
    pub scale: f64,
    /// max_c K\[d_c, d_c\] (ε is relative to it).
    pub k_scale: f64,
}

fn scales(p: &Problem, u0: &[f64]) -> (f64, f64) {
    let scale = p.displacement_scale(u0);
    let k_scale = p.max_constraint_stiffness();
    (scale, if k_scale > 0.0 { k_scale } else { 1.0 })
}

/// A cantilever of ⌈N/3⌉ unit-length Euler–Bernoulli elements (E = 2.1e5, 1×1 section) on a
/// Winkler foundation (transverse k_f = 1e-2·EI per node, axial 1e-3·EA), under the wavy load
/// `q_y = −(1 + 0.8 sin(2π x / 20))`, against a flat rigid surface `u_y ≥ 0.6 · min u0_y`
/// at up to `max_constraints` evenly spaced nodes (`lower` constraints).
pub fn beam_scene(size: usize, max_constraints: usize) -> Result<PerfScene> {
    let n_el = (size / 3).max(3);
    let section = Section::rectangle(2.1e5, 1.0, 1.0);
    let frame = Frame::cantilever(n_el, n_el as f64, section)?;
    let k = frame.assemble(true)?;
    let ei = section.e * section.j;
    let ea = section.e * section.a;
    // Node i ≥ 1 has DOFs 3(i−1) + {0: u_x, 1: u_y, 2: θ} (node 0 is clamped).
    let dof = |i: usize, c: usize| 3 * (i - 1) + c;
    let mut adds = Vec::with_capacity(2 * n_el);
    for i in 1..=n_el {
        adds.push((dof(i, 1), 1e-2 * ei));
        adds.push((dof(i, 0), 1e-3 * ea));
    }
    let k = k.with_diagonal_added(&adds);
    let mut q = vec![0.0; k.n()];
    for i in 1..=n_el {
        let x = i as f64;
        q[dof(i, 1)] = -(1.0 + 0.8 * (2.0 * std::f64::consts::PI * x / 20.0).sin());
    }
    let u0 = k.solve(&q)?;
    let lowest = (1..=n_el).map(|i| u0[dof(i, 1)]).fold(0.0f64, f64::min);
    let stride = n_el.div_ceil(max_constraints.max(1)).max(1);
    let constraints: Vec<Constraint> = (1..=n_el)
        .filter(|i| (i - 1) % stride == stride / 2)
        .map(|i| Constraint::on_dof(dof(i, 1), 0.6 * lowest, ConstraintKind::Lower))
        .collect();
    let problem = Problem::new(k, q, constraints)?;
    let (scale, k_scale) = scales(&problem, &u0);
    Ok(PerfScene {
        family: "beam".into(),
        size,
        problem,
        scale,
        k_scale,
    })
}

/// The 5-point membrane `4u_ij − Σ neighbours = f h²` ([`crate::model::membrane::stiffness`])
/// on a side×side interior grid
/// (side = round √N, clamped edges, f = −10), pressed onto the paraboloid obstacle
/// `u ≥ ψ = 0.5·min u0 − |min u0|·((x−½)² + (y−½)²)` sampled at the nodes of a sub-grid of
/// stride ⌈√(N / max_constraints)⌉ (`lower` constraints).
pub fn membrane_scene(size: usize, max_constraints: usize) -> Result<PerfScene> {
    let side = ((size as f64).sqrt().round() as usize).max(3);
    let n = side * side;
    let h = 1.0 / (side as f64 + 1.0);
    let idx = |i: usize, j: usize| crate::model::membrane::dof(side, i, j);
    let k = crate::model::membrane::stiffness(side, 1.0)?;
    let q = vec![-10.0 * h * h; n];
    let u0 = k.solve(&q)?;
    let sag = u0.iter().fold(0.0f64, |a, &v| a.min(v));
    let stride = ((n as f64 / max_constraints.max(1) as f64).sqrt().ceil() as usize).max(1);
    let mut constraints = Vec::new();
    for i in (stride / 2..side).step_by(stride) {
        for j in (stride / 2..side).step_by(stride) {
            let (x, y) = ((i + 1) as f64 * h, (j + 1) as f64 * h);
            let psi = 0.5 * sag - sag.abs() * ((x - 0.5).powi(2) + (y - 0.5).powi(2));
            constraints.push(Constraint::on_dof(idx(i, j), psi, ConstraintKind::Lower));
        }
    }
    let problem = Problem::new(k, q, constraints)?;
    let (scale, k_scale) = scales(&problem, &u0);
    Ok(PerfScene {
        family: "membrane".into(),
        size,
        problem,
        scale,
        k_scale,
    })
}

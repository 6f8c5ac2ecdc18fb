//! penalty-lab's smoothed-aggregation AMG (`linalg::amg`, scalar, B = ones) against PyAMG's
//! `smoothed_aggregation_solver` with its defaults: `tests/data/amg/reference.json`, made by
//! `scripts/amg_reference.py` on penalized membranes (side 63 and 127, penalty 1e2·K_dd and
//! 1e6·K_dd on a disc) that this test builds from the same formula. CG from x₀ = 0 preconditioned
//! by one V-cycle, counted to ‖u_k − u*‖∞ ≤ 1e-6‖u*‖∞ (u* a direct solve): within 1.5× of
//! PyAMG's count, and Jacobi's count within ±2 or 5 % of SciPy's (the systems are the
//! same). Nodal aggregation with the rigid-body modes (block size 2, block Gauss–Seidel) on the
//! inclined block of `model::incline_block` (θ = 30°, 48 × 24, two-term rows penalized by a
//! constant ε = 1, 1e4, 1e8): the same level sizes as PyAMG's BSR hierarchy and CG counts within
//! 1.5×. The same in 3-D with unknowns in slots: the `hertz-3d` block of `solver_cost`
//! (h/a = 1/4, one-DOF rows penalized by ε = 1, 1e3, 1e6 · max K_ii; block size 3, the
//! symmetry planes' empty slots identity rows), against PyAMG on the same padded matrix; and
//! in 2-D on rows that couple DOFs of one node (`hertz-normals`) or of nodes across two bodies
//! (`patch-two-body-nts-1`), nodal (block size 2, slots) and scalar.

use penalty_lab::linalg::amg::{Amg, AmgOptions};
use penalty_lab::linalg::krylov::{cg, Stop};
use penalty_lab::linalg::precond::Jacobi;
use penalty_lab::linalg::Factorization;
use penalty_lab::model::incline_block;
use penalty_lab::system::{Problem, Stiffness};
use serde::Deserialize;

#[derive(Deserialize)]
struct Reference {
    err_target: f64,
    cases: Vec<Case>,
    elastic: Vec<Elastic>,
    solid: Vec<Solid>,
    coupled: Vec<Coupled>,
}

#[derive(Deserialize)]
struct Coupled {
    case: String,
    h_over_a: f64,
    eps: f64,
    pcg_iters_amg_nodal_to_err: usize,
    converged: bool,
    levels: Vec<usize>,
    pcg_iters_amg_scalar_to_err: usize,
    scalar_converged: bool,
}

#[derive(Deserialize)]
struct Solid {
    h_over_a: f64,
    eps: f64,
    pcg_iters_amg_nodal_to_err: usize,
    converged: bool,
    levels: Vec<usize>,
}

#[derive(Deserialize)]
struct Elastic {
    theta_deg: f64,
    nx: usize,
    ny: usize,
    eps: f64,
    pcg_iters_amg_nodal_to_err: usize,
    converged: bool,
    levels: Vec<usize>,
}

#[derive(Deserialize)]
struct Case {
    side: usize,
    eps_rel: f64,
    pcg_iters_amg_scalar_to_err: usize,
    pcg_iters_jacobi_to_err: usize,
}

/// The membrane of `scripts/amg_reference.py`.
fn membrane(side: usize, eps_rel: f64) -> (Stiffness, Vec<f64>) {
    let h = 1.0 / (side as f64 + 1.0);
    let id = |i: usize, j: usize| i * side + j;
    let mut t = Vec::new();
    let mut b = vec![0.0; side * side];
    for i in 0..side {
        for j in 0..side {
            let (x, y) = ((i + 1) as f64 * h, (j + 1) as f64 * h);
            let r2 = (x - 0.5).powi(2) + (y - 0.5).powi(2);
            let eps = if r2 < 0.1 { eps_rel * 4.0 } else { 0.0 };
            t.push((id(i, j), id(i, j), 4.0 + eps));
            b[id(i, j)] = -10.0 * h * h + eps * (-0.35 - 0.7 * r2);
            for (di, dj) in [(1usize, 0usize), (0, 1)] {
                if i + di < side && j + dj < side {
                    t.push((id(i, j), id(i + di, j + dj), -1.0));
                    t.push((id(i + di, j + dj), id(i, j), -1.0));
                }
            }
        }
    }
    (Stiffness::from_triplets(side * side, &t).unwrap(), b)
}

/// A = K + ε Σ d dᵀ, b = q + ε Σ d û (the script's formula) of `p` at ε = `eps`, and u* of
/// it (refined in double-double where `refine`: cond(A) up to 1e14).
fn penalized(p: &Problem, eps: f64, refine: bool) -> (Stiffness, Vec<f64>, Vec<f64>) {
    let k = p.penalized_k(&vec![eps; p.m()]);
    let mut b = p.q.clone();
    for con in &p.constraints {
        for &(d, a) in &con.terms {
            b[d] += eps * a * con.limit;
        }
    }
    let f = Factorization::new(&k, true).unwrap();
    let mut u_star = f.solve(&b);
    if refine {
        let refined = penalty_lab::linalg::refine::refine(&k, &b, &f, &u_star);
        u_star = refined.x.iter().map(|v| v.to_f64()).collect();
    }
    (k, b, u_star)
}

/// CG preconditioned by `opts`' AMG on A to the error target: (its run, the level sizes).
fn amg_cg(
    k: &Stiffness,
    b: &[f64],
    u_star: &[f64],
    target: f64,
    opts: &AmgOptions,
) -> (penalty_lab::linalg::krylov::KrylovRun, Vec<usize>) {
    let a = k.to_sparse();
    let amg = Amg::new(a.as_ref(), opts).unwrap();
    let stop = Stop::ErrorOfU {
        reference: u_star,
        target,
    };
    let (_, run) = cg(a.as_ref(), &amg, b, stop, 10 * b.len());
    (run, amg.sizes.clone())
}

/// Our nodal AMG against PyAMG's on `p` at ε: the same levels, both converged, counts
/// within 1.5×; the line of the report.
fn check_nodal(p: &Problem, eps: f64, target: f64, theirs: (usize, bool, &[usize])) -> String {
    let (k, b, u_star) = penalized(p, eps, false);
    let nn = p.near_null.as_ref().unwrap();
    let (run, sizes) = amg_cg(&k, &b, &u_star, target, &AmgOptions::nodal(nn));
    let line = format!(
        "ε {eps:e}: nodal AMG {} (PyAMG {}), levels {sizes:?} (PyAMG {:?})",
        run.iterations, theirs.0, theirs.2
    );
    assert!(theirs.1 && run.converged, "{line}");
    assert_eq!(sizes, theirs.2, "{line}");
    let (o, t) = (run.iterations as f64, theirs.0 as f64);
    assert!(o <= 1.5 * t && t <= 1.5 * o, "{line}");
    line
}

#[test]
fn amg_iterations_are_within_1_5x_of_pyamg() {
    let dir = super::cond_reference::data_dir("amg");
    let text = std::fs::read_to_string(dir.join("reference.json")).unwrap();
    let reference: Reference = serde_json::from_str(&text).unwrap();
    assert_eq!(reference.cases.len(), 4);
    let mut report = Vec::new();
    for c in &reference.cases {
        let (k, b) = membrane(c.side, c.eps_rel);
        let u_star = Factorization::new(&k, true).unwrap().solve(&b);
        let a = k.to_sparse();
        let stop = Stop::ErrorOfU {
            reference: &u_star,
            target: reference.err_target,
        };
        let amg = Amg::new(a.as_ref(), &AmgOptions::default()).unwrap();
        let (_, run) = cg(a.as_ref(), &amg, &b, stop, 10 * b.len());
        let jac = Jacobi::new(a.as_ref()).unwrap();
        let (_, jrun) = cg(a.as_ref(), &jac, &b, stop, 10 * b.len());
        report.push(format!(
            "side {} ε {:e}: AMG {} (PyAMG {}), levels {:?}; Jacobi {} (SciPy {})",
            c.side,
            c.eps_rel,
            run.iterations,
            c.pcg_iters_amg_scalar_to_err,
            amg.sizes,
            jrun.iterations,
            c.pcg_iters_jacobi_to_err
        ));
        assert!(run.converged && jrun.converged, "{}", report.join("\n"));
        let (ours, theirs) = (run.iterations as f64, c.pcg_iters_amg_scalar_to_err as f64);
        assert!(
            ours <= 1.5 * theirs && theirs <= 1.5 * ours,
            "{}",
            report.join("\n")
        );
        let (j, s) = (jrun.iterations as f64, c.pcg_iters_jacobi_to_err as f64);
        assert!((j - s).abs() <= 2f64.max(0.05 * s), "{}", report.join("\n"));
    }
    eprintln!("{}", report.join("\n"));
}

#[test]
fn nodal_amg_matches_pyamg_on_two_term_rows() {
    let dir = super::cond_reference::data_dir("amg");
    let text = std::fs::read_to_string(dir.join("reference.json")).unwrap();
    let reference: Reference = serde_json::from_str(&text).unwrap();
    assert_eq!(reference.elastic.len(), 3);
    for c in &reference.elastic {
        let p = incline_block::problem(c.theta_deg, c.nx, c.ny).unwrap();
        let theirs = (c.pcg_iters_amg_nodal_to_err, c.converged, &c.levels[..]);
        eprintln!("{}", check_nodal(&p, c.eps, reference.err_target, theirs));
    }
}

#[test]
fn nodal_amg_in_slots_matches_pyamg_in_3d() {
    use penalty_lab::study::solver_cost::cases::{sphere_grid, sphere_scene, HERTZ};
    let dir = super::cond_reference::data_dir("amg");
    let text = std::fs::read_to_string(dir.join("reference.json")).unwrap();
    let reference: Reference = serde_json::from_str(&text).unwrap();
    assert_eq!(reference.solid.len(), 3);
    for c in &reference.solid {
        let grid = sphere_grid(c.h_over_a).unwrap();
        let lift = HERTZ.a_target * HERTZ.a_target / HERTZ.radius;
        let p = sphere_scene(&grid, lift).unwrap().problem;
        let theirs = (c.pcg_iters_amg_nodal_to_err, c.converged, &c.levels[..]);
        eprintln!("{}", check_nodal(&p, c.eps, reference.err_target, theirs));
    }
}

#[test]
fn nodal_and_scalar_amg_match_pyamg_on_coupled_contact_rows() {
    use penalty_lab::study::hertz::Case;
    use penalty_lab::study::solver_cost::cases::{HERTZ, HERTZ_BLOCK};
    let dir = super::cond_reference::data_dir("amg");
    let text = std::fs::read_to_string(dir.join("reference.json")).unwrap();
    let reference: Reference = serde_json::from_str(&text).unwrap();
    assert_eq!(reference.coupled.len(), 6);
    let mut report = Vec::new();
    for c in &reference.coupled {
        let case = Case::from_name(&c.case).unwrap();
        let grid = HERTZ.grid(case, c.h_over_a, HERTZ_BLOCK).unwrap();
        let p = HERTZ
            .scene(case, &grid, HERTZ.lift_guess(case, &grid))
            .unwrap()
            .problem;
        let (k, b, u_star) = penalized(&p, c.eps, true);
        let nn = p.near_null.as_ref().unwrap();
        let target = reference.err_target;
        let (run, sizes) = amg_cg(&k, &b, &u_star, target, &AmgOptions::nodal(nn));
        let (srun, _) = amg_cg(&k, &b, &u_star, target, &AmgOptions::default());
        report.push(format!(
            "{} ε {:e}: nodal {} (PyAMG {}), levels {:?} (PyAMG {:?}); scalar {} (PyAMG {})",
            c.case,
            c.eps,
            run.iterations,
            c.pcg_iters_amg_nodal_to_err,
            sizes,
            c.levels,
            srun.iterations,
            c.pcg_iters_amg_scalar_to_err
        ));
        let msg = report.join("\n");
        assert!(c.converged && run.converged, "{msg}");
        assert_eq!(sizes, c.levels, "{msg}");
        // Both reach the target or neither does (10 N iterations); where both do, the
        // counts agree.
        assert_eq!(c.scalar_converged, srun.converged, "{msg}");
        let mut pairs = vec![(run.iterations, c.pcg_iters_amg_nodal_to_err)];
        if c.scalar_converged {
            pairs.push((srun.iterations, c.pcg_iters_amg_scalar_to_err));
        }
        for (ours, theirs) in pairs {
            let (o, t) = (ours as f64, theirs as f64);
            assert!(o <= 1.5 * t && t <= 1.5 * o, "{msg}");
        }
    }
    eprintln!("{}", report.join("\n"));
}

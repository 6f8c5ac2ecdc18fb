//! Unit tests of the Krylov solvers (a child module: they reach its private items).
use super::*;
use crate::linalg::precond::Jacobi;
use crate::system::Stiffness;

fn laplacian(n: usize, extra: f64) -> Stiffness {
    let mut t = Vec::new();
    for i in 0..n {
        t.push((i, i, 2.0 + if i == n / 2 { extra } else { 0.0 }));
        if i + 1 < n {
            t.push((i, i + 1, -1.0));
            t.push((i + 1, i, -1.0));
        }
    }
    Stiffness::from_triplets(n, &t).unwrap()
}

fn residual(a: &Stiffness, x: &[f64], b: &[f64]) -> f64 {
    let ax = a.matvec(x);
    norm(&ax.iter().zip(b).map(|(p, q)| p - q).collect::<Vec<_>>()) / norm(b)
}

#[test]
fn cg_meets_its_test_and_sees_the_laplacian_spectrum() {
    // Eigenvalues of the 1-D Dirichlet Laplacian: 2 − 2cos(kπ/(n+1)), k = 1..n.
    let n = 50;
    let a = laplacian(n, 0.0);
    let s = a.to_sparse();
    let b: Vec<f64> = (0..n).map(|i| ((i * 7) % 5) as f64 - 2.0).collect();
    let pre = Jacobi::new(s.as_ref()).unwrap();
    let (x, run) = cg(s.as_ref(), &pre, &b, Stop::Residual(1e-10), 1000);
    assert!(run.converged);
    assert!(residual(&a, &x, &b) <= 1e-9, "{}", residual(&a, &x, &b));
    // In exact arithmetic CG ends by n steps; Jacobi is I/2 here.
    assert!(run.iterations <= n + 5, "{}", run.iterations);
    let h = std::f64::consts::PI / (n + 1) as f64;
    let (lo, hi) = ((2.0 - 2.0 * h.cos()) / 2.0, (2.0 + 2.0 * h.cos()) / 2.0);
    let (elo, ehi) = run.spectrum.unwrap();
    assert!((elo - lo).abs() <= 1e-6 * lo, "{elo} vs {lo}");
    assert!((ehi - hi).abs() <= 1e-9 * hi, "{ehi} vs {hi}");
}

#[test]
fn cg_stops_at_the_limit_unconverged_and_at_zero_rhs_at_once() {
    let a = laplacian(40, 1e8).to_sparse();
    let pre = Jacobi::new(a.as_ref()).unwrap();
    let b = vec![1.0; 40];
    let (_, run) = cg(a.as_ref(), &pre, &b, Stop::Residual(1e-14), 3);
    assert!(!run.converged);
    assert_eq!(run.iterations, 3);
    let (x, run) = cg(a.as_ref(), &pre, &[0.0; 40], Stop::Residual(1e-8), 10);
    assert!(run.converged && run.iterations == 0 && x.iter().all(|&v| v == 0.0));
}

/// `[K d; dᵀ 0]` with K the 20-node Laplacian and d = e_3, its block-diagonal
/// preconditioner and a right-hand side.
fn saddle() -> (Stiffness, Jacobi, Vec<f64>) {
    let n = 20;
    let mut t = Vec::new();
    laplacian(n, 0.0).for_each_entry(|i, j, v| t.push((i, j, v)));
    t.push((3, n, 1.0));
    t.push((n, 3, 1.0));
    let a = Stiffness::from_triplets(n + 1, &t).unwrap();
    let mut inv = vec![0.5; n + 1];
    inv[n] = 2.0; // (dᵀ diag(K)⁻¹ d)⁻¹
    let pre = Jacobi::from_inverse_diagonal(inv).unwrap();
    let b: Vec<f64> = (0..=n).map(|i| (i % 3) as f64 - 0.7).collect();
    (a, pre, b)
}

#[test]
fn minres_solves_a_saddle_point() {
    let (a, pre, b) = saddle();
    let s = a.to_sparse();
    let (x, run) = minres(s.as_ref(), &pre, &b, Stop::Residual(1e-12), 500);
    assert!(run.converged, "{run:?}");
    assert!(residual(&a, &x, &b) <= 1e-10, "{}", residual(&a, &x, &b));
}

#[test]
fn the_error_stop_counts_the_first_iterate_within_the_target() {
    // A stiff "penalty" on one DOF and a large right-hand side there: the residual test
    // stops early and far from u, the error test where u is right.
    let n = 60;
    let a = laplacian(n, 1e8);
    let s = a.to_sparse();
    let mut b: Vec<f64> = (0..n).map(|i| ((i * 3) % 7) as f64 - 3.0).collect();
    b[n / 2] += 1e8 * 0.25;
    let pre = Jacobi::new(s.as_ref()).unwrap();
    let (u_star, exact) = cg(s.as_ref(), &pre, &b, Stop::Residual(1e-15), 10 * n);
    assert!(exact.converged);
    let target = 1e-6;
    let stop = Stop::ErrorOfU {
        reference: &u_star,
        target,
    };
    let (x, run) = cg(s.as_ref(), &pre, &b, stop, 10 * n);
    assert!(run.converged && run.iterations > 0, "{run:?}");
    assert!(relative_error_of_u(&x, &u_star) <= target);
    // One iteration fewer does not meet it.
    let (y, before) = cg(s.as_ref(), &pre, &b, stop, run.iterations - 1);
    assert!(!before.converged);
    assert!(relative_error_of_u(&y, &u_star) > target);
    // The residual test at τ = 1e-8 stops earlier here, with u further off than 1e-6.
    let (z, loose) = cg(s.as_ref(), &pre, &b, Stop::Residual(1e-8), 10 * n);
    assert!(loose.iterations < run.iterations, "{loose:?} {run:?}");
    assert!(relative_error_of_u(&z, &u_star) > target);
}

/// `(x, run)` of each stop of one shared run, in stop order.
fn each(
    solver: EachSolver,
    a: SparseColMatRef<'_, usize, f64>,
    pre: &dyn Preconditioner,
    b: &[f64],
    stops: &[Stop<'_>],
    max_iters: usize,
) -> Vec<(Vec<f64>, KrylovRun)> {
    let mut out = vec![(Vec::new(), KrylovRun::DONE); stops.len()];
    solver(a, pre, b, stops, max_iters, &mut |i, x, run| {
        out[i] = (x.to_vec(), run)
    });
    out
}

#[test]
fn one_shared_run_reports_each_stop_as_its_own_run_would() {
    // CG on the stiff Laplacian: the residual test stops before the error test; with a
    // limit between the two, the error stop ends unconverged at the limit.
    let n = 60;
    let s = laplacian(n, 1e8).to_sparse();
    let mut b: Vec<f64> = (0..n).map(|i| ((i * 3) % 7) as f64 - 3.0).collect();
    b[n / 2] += 1e8 * 0.25;
    let pre = Jacobi::new(s.as_ref()).unwrap();
    let (u_star, _) = cg(s.as_ref(), &pre, &b, Stop::Residual(1e-15), 10 * n);
    let err = Stop::ErrorOfU {
        reference: &u_star,
        target: 1e-6,
    };
    let (tol, far) = (Stop::Residual(1e-8), Stop::Residual(1e-300));
    let loose = cg(s.as_ref(), &pre, &b, tol, 10 * n).1.iterations;
    for limit in [10 * n, loose + 1, loose] {
        let stops = [err, tol, far];
        let shared = each(cg_each, s.as_ref(), &pre, &b, &stops, limit);
        for (stop, (x, run)) in stops.iter().zip(&shared) {
            let (y, alone) = cg(s.as_ref(), &pre, &b, *stop, limit);
            assert_eq!(format!("{run:?}"), format!("{alone:?}"), "limit {limit}");
            assert_eq!(x, &y, "limit {limit}");
        }
        assert!(!shared[2].1.converged, "τ = 1e-300 is never met");
    }
    // MINRES on the saddle point, the same.
    let (a, pre, b) = saddle();
    let (s, m) = (a.to_sparse(), b.len() - 1);
    let (x, _) = minres(s.as_ref(), &pre, &b, Stop::Residual(1e-14), 500);
    let err = Stop::ErrorOfU {
        reference: &x[..m],
        target: 1e-4,
    };
    let stops = [Stop::Residual(1e-3), err, Stop::Residual(1e-300)];
    let shared = each(minres_each, s.as_ref(), &pre, &b, &stops, 500);
    for (stop, (x, run)) in stops.iter().zip(&shared) {
        let (y, alone) = minres(s.as_ref(), &pre, &b, *stop, 500);
        assert_eq!(format!("{run:?}"), format!("{alone:?}"));
        assert_eq!(x, &y);
    }
}

#[test]
fn minres_error_stop_on_the_displacement_block() {
    let (a, pre, b) = saddle();
    let (s, n) = (a.to_sparse(), b.len() - 1);
    let (x, _) = minres(s.as_ref(), &pre, &b, Stop::Residual(1e-14), 500);
    let u_star = &x[..n];
    let stop = Stop::ErrorOfU {
        reference: u_star,
        target: 1e-4,
    };
    let (y, run) = minres(s.as_ref(), &pre, &b, stop, 500);
    assert!(run.converged && run.iterations > 0);
    assert!(relative_error_of_u(&y, u_star) <= 1e-4);
    let (z, before) = minres(s.as_ref(), &pre, &b, stop, run.iterations - 1);
    assert!(!before.converged && relative_error_of_u(&z, u_star) > 1e-4);
}

#[test]
fn a_nan_iterate_never_meets_the_error_test() {
    let u = [1.0, 2.0, 3.0];
    assert!(relative_error_of_u(&[f64::NAN, 2.0, 3.0], &u).is_nan());
    assert!(relative_error_of_u(&[1.0, 2.0, f64::NAN], &u).is_nan());
    assert!(error_of_u(&[1.0, f64::NAN, 3.0], &u).is_nan());
    assert_eq!(relative_error_of_u(&[1.0, 2.0, 3.5], &u), 0.5 / 3.0);
    // u* = 0: only x = 0 is within any relative target.
    assert_eq!(relative_error_of_u(&[0.0, 0.0], &[0.0, 0.0]), 0.0);
    assert_eq!(
        relative_error_of_u(&[1e-300, 0.0], &[0.0, 0.0]),
        f64::INFINITY
    );
}

#[test]
fn tridiagonal_ends_of_a_known_matrix() {
    // tridiag(−1, 2, −1) of size 7: 2 − 2cos(kπ/8).
    let (lo, hi) = tridiagonal_ends(&[2.0; 7], &[-1.0; 6]);
    let h = std::f64::consts::PI / 8.0;
    assert!((lo - (2.0 - 2.0 * h.cos())).abs() <= 1e-14);
    assert!((hi - (2.0 + 2.0 * h.cos())).abs() <= 1e-14);
}

/// n/2 copies of the block [[a, b], [−b, a]]: two distinct eigenvalues a ± ib, so the
/// minimal polynomial has degree 2 and GMRES (unpreconditioned: Jacobi is a multiple of I
/// here) ends in 2 iterations whatever the restart; restarted every step it still
/// converges, more slowly; the error test sees the same iterates.
#[test]
fn gmres_ends_at_the_degree_of_the_minimal_polynomial() {
    let n = 40;
    let (a, bb) = (3.0, 1.5);
    let mut t = Vec::new();
    for k in (0..n).step_by(2) {
        t.extend([
            (k, k, a),
            (k, k + 1, bb),
            (k + 1, k, -bb),
            (k + 1, k + 1, a),
        ]);
    }
    let m = Stiffness::from_triplets(n, &t).unwrap();
    let s = m.to_sparse();
    let pre = Jacobi::new(s.as_ref()).unwrap();
    let b: Vec<f64> = (0..n).map(|i| ((i * 5) % 7) as f64 - 3.0).collect();
    let (x, run) = gmres(s.as_ref(), &pre, &b, 30, Stop::Residual(1e-12), 100);
    assert!(run.converged && run.iterations == 2, "{run:?}");
    assert!(residual(&m, &x, &b) <= 1e-13, "{}", residual(&m, &x, &b));
    let (x1, run1) = gmres(s.as_ref(), &pre, &b, 1, Stop::Residual(1e-12), 500);
    assert!(run1.converged && run1.iterations > 2, "{run1:?}");
    assert!(residual(&m, &x1, &b) <= 1e-11);
    let stop = Stop::ErrorOfU {
        reference: &x,
        target: 1e-10,
    };
    let (_, run2) = gmres(s.as_ref(), &pre, &b, 30, stop, 100);
    assert!(run2.converged && run2.iterations == 2, "{run2:?}");
    let (_, run3) = gmres(s.as_ref(), &pre, &b, 30, Stop::Residual(1e-12), 1);
    assert!(!run3.converged && run3.iterations == 1);
}

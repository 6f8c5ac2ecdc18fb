//! Independent check of the stress study's double-double reference (`study::stress::dd`, a
//! hand-written Dekker/QD arithmetic and LU) against faer's own extended-precision type
//! `faer::fx128` (the `qd` crate's double-double, used here with a written-out elimination).
//!
//! Both solve the exactly formed penalized system `(K + D E Dᵀ) u = q + D E û` with about
//! 106-bit arithmetic; on the paper's beam and the stress study's generated scenes with ε from
//! 1 to 1e16 their solutions, rounded to f64, agree to a few units of f64 rounding, where a
//! plain f64 solve misses by orders of magnitude more (checked, so the comparison can fail).

use faer::fx128;
use penalty_lab::generate::Family;
use penalty_lab::linalg::Factorization;
use penalty_lab::model::beam::paper;
use penalty_lab::study::stress::{stress_scenes, PenalizedSystem};

/// The exactly formed system solved in faer's double-double type by textbook Gaussian
/// elimination with partial pivoting (faer 0.24.4's own LU panics on `fx128` inside its SIMD
/// matrix product on the 28- and 40-unknown scenes used here, so the elimination is written out here: the
/// arithmetic, not the algorithm, is the independent part).
fn fx128_solution(sys: &PenalizedSystem) -> Vec<f64> {
    let p = sys.problem;
    let n = p.n();
    let k = p.k.to_dense();
    let mut a: Vec<Vec<fx128>> = (0..n)
        .map(|i| (0..n).map(|j| fx128::from(k[(i, j)])).collect())
        .collect();
    let mut b: Vec<fx128> = p.q.iter().map(|&v| fx128::from(v)).collect();
    for (c, con) in p.constraints.iter().enumerate() {
        let (e, d) = (sys.penalties[c], con.single_dof().unwrap());
        a[d][d] += fx128::from(e);
        b[d] += fx128::from(e) * fx128::from(sys.limits[c]);
    }
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&i, &j| a[i][col].0.abs().total_cmp(&a[j][col].0.abs()))
            .unwrap();
        a.swap(col, piv);
        b.swap(col, piv);
        let (top, rest) = a.split_at_mut(col + 1);
        let prow = &top[col];
        for (i, row) in rest.iter_mut().enumerate() {
            let f = row[col] / prow[col];
            for (r, p) in row[col..].iter_mut().zip(&prow[col..]) {
                *r -= f * *p;
            }
            let t = f * b[col];
            b[col + 1 + i] -= t;
        }
    }
    let mut x = vec![fx128::from(0.0); n];
    for i in (0..n).rev() {
        let mut s = b[i];
        for j in i + 1..n {
            s -= a[i][j] * x[j];
        }
        x[i] = s / a[i][i];
    }
    x.iter().map(|v| v.0 + v.1).collect()
}

fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let norm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    let d = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt();
    d / norm
}

#[test]
fn double_double_reference_agrees_with_faer_fx128() {
    let mut problems = vec![paper::problem()];
    let families = [Family::Spectrum, Family::Beam];
    for sc in stress_scenes(7, 2, &families).unwrap() {
        problems.push(sc.problem);
    }
    // Largest error of a plain f64 solve seen, to show the check discriminates.
    let mut worst_f64 = 0.0f64;
    for p in &problems {
        // Both carry ≈ 2⁻¹⁰⁴·cond₂ relative error before the final rounding to f64; the
        // rounding itself contributes ≤ ε_mach per entry: allow 4·√n·ε_mach.
        let tol = 4.0 * (p.n() as f64).sqrt() * f64::EPSILON;
        for k in 0..=16 {
            let eps = 10f64.powi(k);
            let sys = PenalizedSystem::new(p, &vec![eps; p.m()]).unwrap();
            let Ok(reference) = sys.reference() else {
                continue;
            };
            let theirs = fx128_solution(&sys);
            let d = rel_diff(&reference.u, &theirs);
            assert!(
                d <= tol,
                "N = {}, ε = {eps:e}: ‖Δu‖/‖u‖ = {d:e} > {tol:e}",
                p.n()
            );
            if let Ok(f) = Factorization::new(&sys.matrix(), false) {
                let e = rel_diff(&f.solve(&sys.rhs()), &theirs);
                if e.is_finite() {
                    worst_f64 = worst_f64.max(e / tol);
                }
            }
        }
    }
    assert!(
        worst_f64 > 1e3,
        "no point where f64 misses by 1e3× the tolerance ({worst_f64:e})"
    );
}

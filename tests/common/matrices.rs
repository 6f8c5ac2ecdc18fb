//! Matrices with a known structure or spectrum, generated scenes, and the pieces of a problem
//! compared bit for bit, shared by the tests that build them.

use penalty_lab::generate::{generate, Family, GeneratorConfig};
use penalty_lab::model::membrane;
use penalty_lab::system::{ConstraintKind, Problem, Stiffness};

/// The 1-D Laplacian tridiag(−1, 2, −1) of order `n` in sparse storage:
/// λ_k = 2 − 2 cos(kπ/(n+1)), det = n + 1.
pub fn laplacian_1d(n: usize) -> Stiffness {
    let mut t = Vec::new();
    for i in 0..n {
        t.push((i, i, 2.0));
        if i + 1 < n {
            t.push((i, i + 1, -1.0));
            t.push((i + 1, i, -1.0));
        }
    }
    Stiffness::from_triplets(n, &t).unwrap()
}

/// The 2-D Laplacian of a `side` × `side` membrane under `tension` (the membrane model's K).
pub fn laplacian_2d(side: usize, tension: f64) -> Stiffness {
    membrane::stiffness(side, tension).unwrap()
}

/// The generated membrane scenes `0..count` of the run seeded `seed`, their sides drawn from
/// `sides` (the sweep's generator).
pub fn membranes(sides: (usize, usize), count: usize, seed: u64) -> Vec<Problem> {
    let cfg = GeneratorConfig {
        membrane_side: sides,
        ..Default::default()
    };
    (0..count)
        .map(|i| generate(Family::Membrane, i, seed, &cfg).unwrap().problem)
        .collect()
}

/// The sparse matrix inside `a`; panics on dense storage.
pub fn sparse_of(a: &Stiffness) -> &faer::sparse::SparseColMat<usize, f64> {
    match a {
        Stiffness::Sparse(m) => m,
        Stiffness::Dense(_) => panic!("expected sparse storage"),
    }
}

/// The constraints of `p` as (DOF, limit bits, kind), for bit-exact comparisons.
pub fn constraint_bits(p: &Problem) -> Vec<(usize, u64, ConstraintKind)> {
    p.constraints
        .iter()
        .map(|c| (c.single_dof().unwrap(), c.limit.to_bits(), c.kind))
        .collect()
}

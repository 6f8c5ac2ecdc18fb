//! How symmetric a stored matrix is, and its symmetric part.
//!
//! The certified cond₂ routes factor one triangle (Cholesky) and multiply with both
//! (Lanczos, residuals): their proofs hold for the stored matrix only where every mirror pair
//! is equal bit for bit ([`Symmetry::Exact`]). A matrix unsymmetric by rounding — every pair
//! within `8·ε_mach·max|a|` ([`Symmetry::Near`]) — is certified through its symmetric part
//! `H = (A + Aᵀ)/2` with the bracket widened for the skew part `N = (A − Aᵀ)/2`
//! ([`Asymmetry::skew_norm_bound`] ≥ ‖N‖₂): for H ≻ 0 and unit x, `‖Ax‖ ≥ xᵀAx = xᵀHx`, so
//!
//! `λ_min(H) ≤ σ_min(A) ≤ (λ_min(H)² + ‖N‖₂²)^{1/2}` and `λ_max(H) ≤ σ_max(A) ≤ λ_max(H) + ‖N‖₂`
//!
//! (the upper end of σ_min from `‖A v‖² = λ² + ‖Nv‖²` for the eigenvector v of λ_min(H),
//! since `vᵀNv = 0`; the last by Weyl). Both estimates are second order in ‖N‖.

use super::Stiffness;
use serde::Serialize;

/// Where and how much a stored matrix is unsymmetric.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Asymmetry {
    /// The largest `|a_ij − a_ji|`.
    pub max_abs: f64,
    /// Its row i and column j (i > j).
    pub at: (usize, usize),
    /// The largest `|a_ij − a_ji| / max(|a_ij|, |a_ji|)` over the unsymmetric pairs.
    pub max_relative: f64,
    /// `max|a|`, the scale of the normwise test.
    pub max_entry: f64,
    /// A proven upper bound of `‖(A − Aᵀ)/2‖₂`: `min(‖N‖₁, ‖N‖_F)` (‖N‖₂ ≤ √(‖N‖₁‖N‖_∞) and
    /// ‖N‖₁ = ‖N‖_∞ for a skew N), rounded up.
    pub skew_norm_bound: f64,
}

impl Asymmetry {
    /// One line naming the asymmetry, for warnings.
    pub fn describe(&self) -> String {
        let (i, j) = self.at;
        format!(
            "max |a_ij − a_ji| = {:.3e} at ({i}, {j}) ({:.1e} of max|a| = {:.3e}; up to {:.1e} \
             of the pair's own size), ‖A − Aᵀ‖₂/2 ≤ {:.3e}",
            self.max_abs,
            self.max_abs / self.max_entry,
            self.max_entry,
            self.max_relative,
            self.skew_norm_bound
        )
    }
}

/// The symmetry class of a stored matrix ([`Stiffness::symmetry`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Symmetry {
    /// Every mirror pair equal bit for bit.
    Exact,
    /// Unsymmetric, every pair within `8·ε_mach·max|a|` (rounding-level asymmetry).
    Near(Asymmetry),
    /// Unsymmetric beyond that.
    Unsymmetric(Asymmetry),
}

impl Symmetry {
    /// The asymmetry, unless exact.
    pub fn asymmetry(&self) -> Option<Asymmetry> {
        match self {
            Symmetry::Exact => None,
            Symmetry::Near(a) | Symmetry::Unsymmetric(a) => Some(*a),
        }
    }
}

/// The relative rounding slack of a sum of `n` rounded nonnegative terms (γ_{n+2}, doubled).
fn slack(n: usize) -> f64 {
    1.0 + 2.0 * (n as f64 + 2.0) * f64::EPSILON
}

impl Stiffness {
    /// Calls `f(i, j, a_ij, a_ji)` once for every position (i, j) of the union of the
    /// patterns of A and Aᵀ (every position of a dense matrix).
    fn for_each_mirror(&self, mut f: impl FnMut(usize, usize, f64, f64)) {
        match self {
            Stiffness::Dense(m) => {
                let n = m.nrows();
                for j in 0..n {
                    for i in 0..n {
                        f(i, j, m[(i, j)], m[(j, i)]);
                    }
                }
            }
            Stiffness::Sparse(m) => {
                // Column j of A merged with column j of Aᵀ (row j of A), both sorted.
                let t = m
                    .as_ref()
                    .transpose()
                    .to_col_major()
                    .expect("the transpose of a stored matrix fits in memory");
                let (a, b) = (m.symbolic(), t.symbolic());
                let (av, bv) = (m.val(), t.val());
                for j in 0..m.ncols() {
                    let (ar, br) = (a.row_idx_of_col_raw(j), b.row_idx_of_col_raw(j));
                    let (avj, bvj) = (
                        &av[a.col_ptr()[j]..][..ar.len()],
                        &bv[b.col_ptr()[j]..][..br.len()],
                    );
                    let (mut p, mut q) = (0, 0);
                    while p < ar.len() || q < br.len() {
                        let ri = ar.get(p).copied().unwrap_or(usize::MAX);
                        let rt = br.get(q).copied().unwrap_or(usize::MAX);
                        let (i, x, y) = match ri.cmp(&rt) {
                            std::cmp::Ordering::Less => (ri, avj[p], 0.0),
                            std::cmp::Ordering::Greater => (rt, 0.0, bvj[q]),
                            std::cmp::Ordering::Equal => (ri, avj[p], bvj[q]),
                        };
                        f(i, j, x, y);
                        p += usize::from(ri <= rt);
                        q += usize::from(rt <= ri);
                    }
                }
            }
        }
    }

    /// The symmetry class of the stored matrix, with the size and place of its asymmetry
    /// (O(nnz); an exactly symmetric sparse matrix is recognized in one pass without a
    /// transpose).
    pub fn symmetry(&self) -> Symmetry {
        if let Stiffness::Sparse(m) = self {
            if super::exactly_symmetric(m) {
                return Symmetry::Exact;
            }
        }
        let n = self.n();
        let mut col = vec![0.0f64; n];
        let (mut fro, mut worst, mut at, mut rel, mut max_entry) =
            (0.0f64, 0.0f64, (0, 0), 0.0f64, 0.0f64);
        self.for_each_mirror(|i, j, x, y| {
            max_entry = max_entry.max(x.abs());
            if i > j && x != y {
                let d = (x - y).abs();
                col[i] += d;
                col[j] += d;
                fro += 2.0 * d * d;
                if d > worst {
                    (worst, at) = (d, (i, j));
                }
                rel = rel.max(d / x.abs().max(y.abs()));
            }
        });
        if worst == 0.0 && rel == 0.0 {
            return Symmetry::Exact;
        }
        let one = 0.5 * col.iter().fold(0.0f64, |a, &c| a.max(c)) * slack(n);
        let frob = 0.5 * fro.sqrt() * slack(n * n);
        let a = Asymmetry {
            max_abs: worst,
            at,
            max_relative: rel,
            max_entry,
            skew_norm_bound: one.min(frob),
        };
        if worst <= 8.0 * f64::EPSILON * max_entry {
            Symmetry::Near(a)
        } else {
            Symmetry::Unsymmetric(a)
        }
    }

    /// The symmetric part `H = fl((A + Aᵀ)/2)` in the same storage, exactly symmetric, and a
    /// proven upper bound of `‖H − (A + Aᵀ)/2‖₂` (its rounding: each entry is one rounded sum
    /// of the exact halves, whose error is found exactly by Knuth's TwoSum; plus the halving of
    /// subnormal entries).
    pub fn symmetric_part(&self) -> (Stiffness, f64) {
        let n = self.n();
        let mut col = vec![0.0f64; n];
        let half = |x: f64, y: f64| {
            let (a, b) = (0.5 * x, 0.5 * y);
            let s = a + b;
            let bb = s - a;
            let err = (a - (s - bb)) + (b - bb);
            (s, err.abs())
        };
        let h = match self {
            Stiffness::Dense(m) => {
                let mut out = faer::Mat::zeros(n, n);
                for j in 0..n {
                    for i in 0..n {
                        let (s, e) = half(m[(i, j)], m[(j, i)]);
                        out[(i, j)] = s;
                        col[j] += e;
                    }
                }
                Stiffness::Dense(out)
            }
            Stiffness::Sparse(_) => {
                let mut t = Vec::with_capacity(self.nnz() + self.nnz() / 8);
                self.for_each_mirror(|i, j, x, y| {
                    let (s, e) = half(x, y);
                    col[j] += e;
                    if s != 0.0 {
                        t.push((i, j, s));
                    }
                });
                Stiffness::from_triplets(n, &t).expect("positions of an n×n matrix")
            }
        };
        // Halving is exact above the subnormal range; below it loses at most 2^-1075 each.
        let sub = 2.0 * f64::from_bits(1) * n as f64;
        let delta = col.iter().fold(0.0f64, |a, &c| a.max(c)) * slack(n) + sub;
        (h, delta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dense(rows: &[&[f64]]) -> Stiffness {
        Stiffness::from_rows(&rows.iter().map(|r| r.to_vec()).collect::<Vec<_>>()).unwrap()
    }

    #[test]
    fn classes_and_bounds() {
        let exact = dense(&[&[2.0, -1.0], &[-1.0, 2.0]]);
        assert_eq!(exact.symmetry(), Symmetry::Exact);
        assert!(exact.is_symmetric());
        let near = dense(&[&[2.0, -1.0], &[-1.0 - 2.0 * f64::EPSILON, 2.0]]);
        let Symmetry::Near(a) = near.symmetry() else {
            panic!("near-symmetric")
        };
        assert!(!near.is_symmetric());
        assert_eq!(a.at, (1, 0));
        // ‖N‖₂ = |a_10 − a_01|/2 for a 2×2 skew part.
        assert!(a.skew_norm_bound >= f64::EPSILON && a.skew_norm_bound <= 1.01 * f64::EPSILON);
        let far = dense(&[&[2.0, -1.0], &[-0.5, 2.0]]);
        assert!(matches!(far.symmetry(), Symmetry::Unsymmetric(_)));
        // The same in sparse storage.
        let sp = |s: &Stiffness| Stiffness::Sparse(s.to_sparse());
        assert_eq!(sp(&exact).symmetry(), Symmetry::Exact);
        assert_eq!(sp(&near).symmetry(), near.symmetry());
        assert_eq!(sp(&far).symmetry(), far.symmetry());
        let (h, delta) = sp(&far).symmetric_part();
        assert!(h.is_symmetric());
        assert_eq!(h.get(1, 0), -0.75);
        assert!(delta < 1e-300);
    }
}

//! Preconditioned conjugate gradients with an earlier sparse Cholesky factor as the
//! preconditioner (faer's `conjugate_gradient`).

use super::sparse_llt::SparseLlt;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::{MatMut, Par};

/// The two operators of [`pcg`] for faer's `conjugate_gradient`: a sparse matrix (both
/// triangles stored; `A x`) and a sparse Cholesky factor used as preconditioner (`M⁻¹ x`, one
/// solve). Both are real symmetric, so `conj_apply = apply`.
enum Operator<'a> {
    Sparse(faer::sparse::SparseColMatRef<'a, usize, f64>),
    Factor(&'a SparseLlt),
}

impl std::fmt::Debug for Operator<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Operator::Sparse(a) => write!(f, "Sparse({}×{})", a.nrows(), a.ncols()),
            Operator::Factor(l) => write!(f, "Factor({})", l.symbolic.nrows()),
        }
    }
}

impl faer::matrix_free::LinOp<f64> for Operator<'_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> faer::dyn_stack::StackReq {
        faer::dyn_stack::StackReq::EMPTY
    }
    fn nrows(&self) -> usize {
        match self {
            Operator::Sparse(a) => a.nrows(),
            Operator::Factor(l) => l.symbolic.nrows(),
        }
    }
    fn ncols(&self) -> usize {
        self.nrows()
    }
    fn apply(
        &self,
        mut out: MatMut<'_, f64>,
        rhs: faer::MatRef<'_, f64>,
        par: Par,
        _: &mut MemStack,
    ) {
        match self {
            Operator::Sparse(a) => faer::sparse::linalg::matmul::sparse_dense_matmul(
                out,
                faer::Accum::Replace,
                *a,
                rhs,
                1.0,
                par,
            ),
            Operator::Factor(l) => {
                out.copy_from(rhs);
                l.solve_in_place(out);
            }
        }
    }
    fn conj_apply(
        &self,
        out: MatMut<'_, f64>,
        rhs: faer::MatRef<'_, f64>,
        par: Par,
        stack: &mut MemStack,
    ) {
        self.apply(out, rhs, par, stack);
    }
}

impl faer::matrix_free::Precond<f64> for Operator<'_> {}

/// Result of [`pcg`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PcgOutcome {
    /// `‖b − A x‖₂ ≤ tol·‖b‖₂` was reached.
    pub converged: bool,
    /// CG iterations done (each: one product with A, one solve with the preconditioner).
    pub iterations: usize,
}

/// Solves the sparse SPD system `A x = b` by preconditioned conjugate gradients (faer's
/// `conjugate_gradient`), with the Cholesky factor of a *nearby* matrix as preconditioner
/// (e.g. the factor of the previous active-set iteration: `M⁻¹A = I + low rank` when few
/// rows changed, so CG needs about as many iterations as rows changed). `x` holds the initial
/// guess on entry and the iterate on exit (meaningless if not converged). Stops when
/// `‖b − A x‖₂ ≤ tol·‖b‖₂` (a normwise backward error ≤ tol) or after `max_iters`.
pub fn pcg(
    a: faer::sparse::SparseColMatRef<'_, usize, f64>,
    precond: &SparseLlt,
    b: &[f64],
    x: &mut [f64],
    tol: f64,
    max_iters: usize,
) -> PcgOutcome {
    use faer::matrix_free::conjugate_gradient::{
        conjugate_gradient, conjugate_gradient_scratch, CgError, CgParams,
    };
    let n = b.len();
    let (op, pre) = (Operator::Sparse(a), Operator::Factor(precond));
    let params = CgParams {
        rel_tolerance: tol,
        max_iters,
        ..Default::default()
    };
    let par = Par::Seq;
    let mut mem = MemBuffer::new(conjugate_gradient_scratch(&pre, &op, 1, par));
    let out = MatMut::from_column_major_slice_mut(x, n, 1);
    let rhs = faer::MatRef::from_column_major_slice(b, n, 1);
    match conjugate_gradient(
        out,
        &pre,
        &op,
        rhs,
        params,
        |_| {},
        par,
        MemStack::new(&mut mem),
    ) {
        Ok(info) => PcgOutcome {
            converged: true,
            iterations: info.iter_count,
        },
        Err(CgError::NoConvergence { .. }) => PcgOutcome {
            converged: false,
            iterations: max_iters,
        },
        Err(_) => PcgOutcome {
            converged: false,
            iterations: 0,
        },
    }
}

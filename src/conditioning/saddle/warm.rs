//! Warm starts of the saddle-point route's Lanczos runs ([`super`]), from K's Ritz vectors.

use super::coupling::Blocks;
use crate::conditioning::sparse::RitzStarts;

/// The warm starts of a saddle point's Lanczos runs, from K's Ritz vectors (N + m entries).
pub(super) struct SaddleStarts {
    /// The run on A (λ_max): K's top vector, padded with zeros on the multipliers.
    top: Vec<f64>,
    /// The run on A⁻¹ (λ⁺_min): K's bottom vector, padded.
    bottom: Vec<f64>,
    /// The run on −A⁻¹ (λ⁻_max, the negative eigenvalue closest to 0): `[0; Dᵀv_top]`. For
    /// small |λ| a negative eigenpair has `x ≈ −K⁻¹Dy` and `DᵀK⁻¹D y ≈ −λy`, so y is near the
    /// bottom of `S = DᵀK⁻¹D`, where Dy excites K's stiff modes: K's top vector seen through
    /// Dᵀ. A start only (the folder's lagrange rows: 10–40 steps → 6–26).
    negative: Vec<f64>,
}

impl SaddleStarts {
    /// The starts from K's Ritz vectors `k` for the saddle point of `blocks` (N DOFs, m
    /// constraints); None unless both vectors have N entries.
    pub(super) fn of(k: &RitzStarts, blocks: &Blocks<'_>) -> Option<Self> {
        let (n, m) = (blocks.in_b.len(), blocks.m);
        if k.top.len() != n || k.bottom.len() != n {
            return None;
        }
        let pad = |v: &[f64]| v.iter().copied().chain((0..m).map(|_| 0.0)).collect();
        let multipliers = (0..m).map(|c| blocks.dt(&k.top, c));
        Some(SaddleStarts {
            top: pad(&k.top),
            bottom: pad(&k.bottom),
            negative: std::iter::repeat_n(0.0, n).chain(multipliers).collect(),
        })
    }
}

/// The warm start of a run (`top`: on ±A, else on ±A⁻¹; `sign`: of the operator): K's padded
/// top or bottom Ritz vector for the positive runs, `[0; Dᵀv_top]` for the run on −A⁻¹, none
/// for the run on −A.
pub(super) fn warm_start(starts: &Option<SaddleStarts>, sign: f64, top: bool) -> Option<&[f64]> {
    let s = starts.as_ref()?;
    match (sign > 0.0, top) {
        (true, true) => Some(&s.top),
        (true, false) => Some(&s.bottom),
        (false, false) => Some(&s.negative),
        (false, true) => None,
    }
}

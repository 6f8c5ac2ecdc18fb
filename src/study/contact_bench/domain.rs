//! The domain error of the Hertz cases. Hertz's solution is a half-space's;
//! the benchmark's block of [`BenchConfig::block_over_a`]·a with a clamped base is a finite
//! model of it, and on a fine mesh the block's bias is a sizeable part of Lagrange's error
//! against the analytic pressure. On every Hertz mesh Lagrange is also solved, at the same
//! load and with the same elements near the contact (the graded meshes share every node up to
//! where the larger block's elements keep growing), on blocks of [`DOMAIN_SIZES`]·a; the
//! largest is the **reference** block. Then, in the measure of [`analytic::pressure_error`]:
//! - `err_discretization` of every row = Lagrange's error on the reference block: the mesh's
//!   own error, the domain's removed to the reference's residue (the figure `domain` shows the
//!   distance to the reference falling ∝ 1/L; the reference's own is smaller by its ratio);
//! - `err_domain` of every row = `‖p_block − p_reference‖ / ‖p_exact‖` for the benchmark's
//!   block: what the finite block adds;
//! - the Lagrange row's `p_err_rel` = its error on the benchmark's block (both together).
//!
//! The flat punch is exact on its finite block: `err_domain` = 0 and no study. The study runs
//! on the rigid Hertz cases only (`Case::is_rigid_hertz`): `hertz-two-body` (a finite cap on
//! the block) and `hertz-normals` have `err_domain` = 0 and no study, so their
//! `err_discretization` is Lagrange's error on the benchmark's block, domain error included.

use super::{analytic, BenchConfig, MeshErrors, Prepared};
use crate::error::Result;
use crate::model::elasticity::ContactNode;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Block sizes over a of the domain study; the largest is the reference block.
pub const DOMAIN_SIZES: [f64; 4] = [16.0, 64.0, 256.0, 1024.0];

/// One Hertz mesh on one block size.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct DomainRow {
    /// Case.
    pub case: String,
    /// Element size at the contact.
    pub h: f64,
    /// Block size over a.
    pub block_over_a: f64,
    /// Free DOFs.
    pub n_dofs: usize,
    /// Lagrange's pressure error against the analytic pressure on this block.
    pub err_total: f64,
    /// `‖p − p_reference‖ / ‖p_exact‖`: this block's distance from the reference block.
    pub err_domain: f64,
}

/// The pressure distance of two blocks' Lagrange solutions on the same contact mesh: over the
/// top nodes they share (equal abscissae, from the axis outwards), plus each block's pressure
/// at the nodes the other lacks (taken as 0 there: beyond the contact zone both are).
pub fn block_distance(
    a: (&[ContactNode], &[f64]),
    b: (&[ContactNode], &[f64]),
    exact: &analytic::Exact,
) -> f64 {
    let shared = a.0.iter().zip(b.0).take_while(|(x, y)| x.x == y.x).count();
    let mut sum = 0.0;
    for c in 0..shared {
        sum += a.0[c].weight * (a.1[c] - b.1[c]).powi(2);
    }
    for (nodes, p) in [a, b] {
        for c in shared..nodes.len() {
            sum += nodes[c].weight * p[c].powi(2);
        }
    }
    let norm: f64 =
        a.0.iter()
            .map(|n| n.weight * exact.pressure(n.x).powi(2))
            .sum();
    (sum / norm).sqrt()
}

/// Solves the domain study of one Hertz mesh; `block` is the benchmark's own solve.
pub(crate) fn domain(cfg: &BenchConfig, block: &Prepared) -> Result<MeshErrors> {
    // Every block but the benchmark's own, solved in parallel.
    let solved: Vec<Option<Prepared>> = DOMAIN_SIZES
        .par_iter()
        .map(|&size| {
            (size != cfg.block_over_a)
                .then(|| Prepared::new_sized(cfg, block.case, block.h_rel, size))
                .transpose()
        })
        .collect::<Result<_>>()?;
    let blocks: Vec<&Prepared> = solved.iter().map(|s| s.as_ref().unwrap_or(block)).collect();
    let r = blocks[blocks.len() - 1];
    let (r_nodes, r_p) = (&r.scene().contact, &r.p_lagrange);
    let mut rows = Vec::new();
    for (&size, s) in DOMAIN_SIZES.iter().zip(&blocks) {
        let nodes = &s.scene().contact;
        rows.push(DomainRow {
            case: block.case.name().into(),
            h: block.h,
            block_over_a: size,
            n_dofs: s.scene().n_free,
            err_total: s.err_own,
            err_domain: block_distance((nodes, &s.p_lagrange), (r_nodes, r_p), &s.exact),
        });
    }
    Ok(MeshErrors {
        discretization: r.err_own,
        // The benchmark's block need not be one of the study's sizes (`--block-over-a`).
        domain: block_distance(
            (&block.scene().contact, &block.p_lagrange),
            (r_nodes, r_p),
            &block.exact,
        ),
        study: rows,
    })
}

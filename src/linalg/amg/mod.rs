//! Smoothed-aggregation algebraic multigrid (SA-AMG; Vaněk, Mandel & Brezina 1996) as a
//! preconditioner for CG on an SPD `A`, with the defaults of PyAMG's
//! `smoothed_aggregation_solver` (Olson & Schroder, PyAMG 5):
//!
//! 1. **Strength of connection** (symmetric): `i ~ j` iff `|a_ij| ≥ θ·√|a_ii a_jj|`, θ = 0 by
//!    default (every stored off-diagonal entry). Nodal (block size b): on the amalgamated
//!    matrix of node blocks, `|A_IJ|` the Frobenius norm of the b×b block.
//! 2. **Aggregation** (PyAMG's `standard_aggregation`): pass 1 makes an aggregate of every
//!    node whose strong neighbours are all free, with them; pass 2 joins each remaining node
//!    to a neighbouring aggregate; pass 3 makes aggregates of what is left.
//! 3. **Tentative prolongator** `T` from the near-null space `B` (N×k; scalar default: ones;
//!    nodal: e.g. the rigid-body modes, [`crate::system::NearNull`]), on the finest level
//!    first relaxed by 4 symmetric (block) Gauss–Seidel sweeps on `A x = 0`
//!    (PyAMG's `improve_candidates`):
//!    per aggregate, the thin QR of B's rows in it, `B_agg = Q R`; T holds the Q blocks, the
//!    coarse near-null space is the stack of the R's (so `T B_c = B`).
//! 4. **Smoothed prolongator** `P = (I − ω/ρ · D⁻¹A) T`, ω = 4/3, ρ ≈ ρ(D⁻¹A) from Lanczos
//!    on `D^{-1/2} A D^{-1/2}` restarted until the Ritz value has converged to 1 % (PyAMG's
//!    `approximate_spectral_radius`).
//! 5. **Galerkin** coarse operator `A_c = Pᵀ A P`, recursively until ≤ [`MAX_COARSE`]
//!    nodes (unknowns over the level's block size, as PyAMG counts them) or [`MAX_LEVELS`]
//!    levels; the coarsest is solved by its pseudo-inverse (PyAMG's `pinv`: eigenvalues below
//!    N·ε_mach·λ_max dropped; a coarsest level over [`MAX_DENSE_COARSE`] unknowns is factored by
//!    sparse Cholesky instead). Where stiff penalty rows make the coarsest matrix numerically
//!    singular, a Cholesky solve amplifies rounding and the V-cycle degrades (found on rows
//!    along curved normals at ε = 1e8·max K_ii: 9 123 CG iterations against PyAMG's 27).
//! 6. **V-cycle**: one symmetric Gauss–Seidel sweep (forward then backward) before and after
//!    the coarse correction, so that the cycle is a symmetric positive definite operator (CG
//!    needs one). Nodal (block size b on the finest level, k below): block Gauss–Seidel,
//!    `x_I = D_I⁻¹(b_I − Σ_{J≠I} A_IJ x_J)` with the inverted b×b diagonal blocks (PyAMG's
//!    `block_gauss_seidel` on a BSR matrix), each inverse symmetrized `(M + Mᵀ)/2` so the
//!    cycle stays symmetric where a block is ill-conditioned (a two-term penalty row
//!    `ε n nᵀ`; at ε ≈ 1e10·K_dd the cycle may still lose definiteness in floating point and
//!    CG break down, as PyAMG's does). The block smoother takes a two-term row's coupling
//!    into its diagonal block, which is why nodal AMG stays flat in ε where scalar AMG does
//!    not.
//!
//! **Why hand-written.** The Rust crates we measured do not meet PyAMG's iteration
//! counts: kryst 4.3's smoothed aggregation needed 4–11× PyAMG's CG iterations on the
//! membrane and elasticity systems of `scripts/amg_eval`, and its `InterpType::Multipass`
//! stalled in coarsening (out of memory under 8 GB, over 120 s, or a dense solve of the whole
//! matrix); no other crate on crates.io offers smoothed aggregation with a near-null space
//! (`scripts/amg_eval/README.md`). The sparse products are Gustavson's row-by-row
//! accumulation.

mod coarse;
mod slots;
mod smoother;

use super::krylov::Preconditioner;
use crate::error::{Error, Result};
use crate::system::Stiffness;
use coarse::Coarse;
use faer::sparse::SparseColMatRef;
use smoother::{gauss_seidel, improve_candidates, BlockDiag};

/// Coarsest size: a level with at most this many nodes (unknowns / block size) is solved
/// directly (PyAMG's `max_coarse`).
pub const MAX_COARSE: usize = 10;
/// The largest coarsest level solved by a dense pseudo-inverse (module doc, step 5).
pub const MAX_DENSE_COARSE: usize = 1000;
/// Most levels of the hierarchy (the last is solved directly whatever its size).
pub const MAX_LEVELS: usize = 12;
/// ω of the Jacobi prolongation smoother (PyAMG's default).
pub const OMEGA: f64 = 4.0 / 3.0;

/// Compressed sparse rows.
#[derive(Clone, Debug, PartialEq)]
struct Csr {
    n_rows: usize,
    n_cols: usize,
    ptr: Vec<usize>,
    col: Vec<usize>,
    val: Vec<f64>,
}

impl Csr {
    /// The rows of a symmetric matrix stored in CSC (column j = row j).
    fn of_symmetric(a: SparseColMatRef<'_, usize, f64>) -> Csr {
        let (cp, ri) = (a.symbolic().col_ptr(), a.symbolic().row_idx());
        let n = a.ncols();
        let mut ptr = Vec::with_capacity(n + 1);
        let (mut col, mut val) = (Vec::new(), Vec::new());
        ptr.push(0);
        for j in 0..n {
            col.extend_from_slice(&ri[cp[j]..cp[j + 1]]);
            val.extend_from_slice(&a.val()[cp[j]..cp[j + 1]]);
            ptr.push(col.len());
        }
        Csr {
            n_rows: n,
            n_cols: a.nrows(),
            ptr,
            col,
            val,
        }
    }

    fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let r = self.ptr[i]..self.ptr[i + 1];
        self.col[r.clone()]
            .iter()
            .copied()
            .zip(self.val[r].iter().copied())
    }

    /// `y = A x`.
    fn matvec(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate() {
            *yi = self.row(i).map(|(j, v)| v * x[j]).sum();
        }
    }

    fn diagonal(&self) -> Vec<f64> {
        (0..self.n_rows)
            .map(|i| self.row(i).find(|&(j, _)| j == i).map_or(0.0, |(_, v)| v))
            .collect()
    }

    fn transpose(&self) -> Csr {
        let mut count = vec![0usize; self.n_cols + 1];
        for &j in &self.col {
            count[j + 1] += 1;
        }
        for j in 0..self.n_cols {
            count[j + 1] += count[j];
        }
        let mut next = count.clone();
        let (mut col, mut val) = (vec![0; self.col.len()], vec![0.0; self.col.len()]);
        for i in 0..self.n_rows {
            for (j, v) in self.row(i) {
                col[next[j]] = i;
                val[next[j]] = v;
                next[j] += 1;
            }
        }
        Csr {
            n_rows: self.n_cols,
            n_cols: self.n_rows,
            ptr: count,
            col,
            val,
        }
    }

    /// `self · b` (Gustavson: each row accumulated in a dense work row, columns sorted).
    fn mul(&self, b: &Csr) -> Csr {
        let mut acc = vec![0.0; b.n_cols];
        let mut mark = vec![usize::MAX; b.n_cols];
        let mut ptr = Vec::with_capacity(self.n_rows + 1);
        let (mut col, mut val) = (Vec::new(), Vec::new());
        ptr.push(0);
        let mut cols = Vec::new();
        for i in 0..self.n_rows {
            cols.clear();
            for (k, a) in self.row(i) {
                for (j, v) in b.row(k) {
                    if mark[j] != i {
                        mark[j] = i;
                        acc[j] = 0.0;
                        cols.push(j);
                    }
                    acc[j] += a * v;
                }
            }
            cols.sort_unstable();
            for &j in &cols {
                col.push(j);
                val.push(acc[j]);
            }
            ptr.push(col.len());
        }
        Csr {
            n_rows: self.n_rows,
            n_cols: b.n_cols,
            ptr,
            col,
            val,
        }
    }

    fn to_stiffness(&self) -> Result<Stiffness> {
        let t: Vec<(usize, usize, f64)> = (0..self.n_rows)
            .flat_map(|i| self.row(i).map(move |(j, v)| (i, j, v)))
            .collect();
        Stiffness::from_triplets(self.n_rows, &t)
    }
}

/// How the hierarchy is built.
#[derive(Clone, Debug, PartialEq)]
pub struct AmgOptions {
    /// Unknowns per node (1: scalar aggregation).
    pub block_size: usize,
    /// The near-null space B, column-major N×k (`None`: k = 1, B = ones).
    pub near_null: Option<(Vec<f64>, usize)>,
    /// θ of the strength of connection.
    pub theta: f64,
    /// Unknowns in slots ([`crate::system::NearNull::with_slots`]): each unknown's slot and
    /// the number of slots (B's rows); the hierarchy is built on the slotted matrix (`slots`).
    pub slots: Option<(Vec<usize>, usize)>,
}

impl AmgOptions {
    /// Nodal aggregation on a problem's near-null space (its block size and B), θ default.
    pub fn nodal(nn: &crate::system::NearNull) -> AmgOptions {
        AmgOptions {
            block_size: nn.block_size,
            near_null: Some((nn.b.clone(), nn.k)),
            slots: nn.slots.clone().map(|s| (s, nn.padded_n())),
            ..AmgOptions::default()
        }
    }
}

impl Default for AmgOptions {
    fn default() -> Self {
        AmgOptions {
            block_size: 1,
            near_null: None,
            theta: 0.0,
            slots: None,
        }
    }
}

struct Level {
    a: Csr,
    /// The inverted diagonal blocks of A (the Gauss–Seidel smoother's).
    blocks: BlockDiag,
    /// Prolongator to this level from the next coarser, and its transpose.
    p: Csr,
    r: Csr,
}

/// An SA-AMG hierarchy (module doc), applied as one V-cycle from zero.
pub struct Amg {
    levels: Vec<Level>,
    coarse: Coarse,
    coarse_n: usize,
    /// Unknowns per level, finest first (the coarsest last; with slots, the finest counts
    /// the slots).
    pub sizes: Vec<usize>,
    /// Each unknown's slot and the number of slots, where the options had slots.
    slots: Option<(Vec<usize>, usize)>,
}

impl Amg {
    /// Builds the hierarchy of the SPD `a` (both triangles stored). Errors on a diagonal entry
    /// ≤ 0, a near-null space of the wrong size, a non-finite spectral estimate or a coarsest
    /// matrix that cannot be solved.
    pub fn new(a: SparseColMatRef<'_, usize, f64>, opts: &AmgOptions) -> Result<Amg> {
        let mut a = Csr::of_symmetric(a);
        if let Some((s, n_slots)) = &opts.slots {
            a = slots::padded(&a, s, *n_slots)?;
        }
        let n = a.n_rows;
        let bs = opts.block_size.max(1);
        if !n.is_multiple_of(bs) {
            return Err(Error::length_mismatch(
                format!("AMG: unknowns in blocks of {bs}"),
                n,
                n.div_ceil(bs) * bs,
            ));
        }
        let (mut b, mut k) = match &opts.near_null {
            Some((b, k)) => {
                if *k == 0 || b.len() != n * k {
                    return Err(Error::length_mismatch(
                        "AMG near-null space (N × k, column-major)",
                        b.len(),
                        n * (*k).max(1),
                    ));
                }
                (b.clone(), *k)
            }
            None => (vec![1.0; n], 1),
        };
        let mut levels = Vec::new();
        let mut sizes = vec![n];
        let mut block = bs;
        while a.n_rows > MAX_COARSE * block && levels.len() + 1 < MAX_LEVELS {
            let diag = a.diagonal();
            if let Some(i) = diag.iter().position(|&d| !(d > 0.0 && d.is_finite())) {
                return Err(Error::NotPositive {
                    name: format!("AMG: diagonal entry {i} of a level matrix"),
                    value: diag[i],
                });
            }
            let blocks = BlockDiag::new(&a, &diag, block)?;
            if levels.is_empty() {
                improve_candidates(&a, &blocks, &mut b, k);
            }
            let agg = aggregate(&a, block, opts.theta);
            let n_agg = agg.iter().copied().max().map_or(0, |m| m + 1);
            if n_agg == 0 || n_agg * k >= a.n_rows {
                break; // no coarsening: solve this level directly
            }
            let (t, bc) = tentative(&agg, n_agg, block, &b, k);
            let p = smooth(&a, &diag, &t)?;
            let r = p.transpose();
            let ac = r.mul(&a.mul(&p));
            sizes.push(ac.n_rows);
            let next = ac;
            levels.push(Level {
                a: std::mem::replace(&mut a, next),
                blocks,
                p,
                r,
            });
            b = bc;
            block = k;
            k = b.len() / a.n_rows;
        }
        let coarse = Coarse::new(&a)?;
        Ok(Amg {
            coarse_n: a.n_rows,
            levels,
            coarse,
            sizes,
            slots: opts.slots.clone(),
        })
    }

    /// One V-cycle on level `l` for `A_l x = b` from `x = 0`.
    fn cycle(&self, l: usize, b: &[f64], x: &mut [f64]) {
        if l == self.levels.len() {
            self.coarse.solve(b, x);
            return;
        }
        let lv = &self.levels[l];
        x.iter_mut().for_each(|v| *v = 0.0);
        gauss_seidel(&lv.a, &lv.blocks, b, x, true);
        gauss_seidel(&lv.a, &lv.blocks, b, x, false);
        let mut r = vec![0.0; b.len()];
        lv.a.matvec(x, &mut r);
        r.iter_mut().zip(b).for_each(|(r, b)| *r = b - *r);
        let mut rc = vec![0.0; lv.r.n_rows];
        lv.r.matvec(&r, &mut rc);
        let mut ec = vec![0.0; rc.len()];
        self.cycle(l + 1, &rc, &mut ec);
        let mut e = vec![0.0; b.len()];
        lv.p.matvec(&ec, &mut e);
        x.iter_mut().zip(&e).for_each(|(x, e)| *x += e);
        gauss_seidel(&lv.a, &lv.blocks, b, x, true);
        gauss_seidel(&lv.a, &lv.blocks, b, x, false);
    }

    /// Levels including the coarsest.
    pub fn levels(&self) -> usize {
        self.levels.len() + 1
    }

    /// Operator complexity: Σ nnz(A_l) / nnz(A_0) over the levels above the coarsest, plus the
    /// coarsest's size² (a dense bound on its factor).
    pub fn operator_complexity(&self) -> f64 {
        let nnz0 = self.levels.first().map_or(1, |l| l.a.col.len()) as f64;
        let sum: usize = self.levels.iter().map(|l| l.a.col.len()).sum();
        (sum as f64 + (self.coarse_n * self.coarse_n) as f64) / nnz0
    }
}

impl Preconditioner for Amg {
    fn apply(&self, r: &[f64], z: &mut [f64]) {
        match &self.slots {
            None => self.cycle(0, r, z),
            Some((s, n)) => {
                let rs = slots::scatter(r, s, *n);
                let mut zs = vec![0.0; *n];
                self.cycle(0, &rs, &mut zs);
                slots::gather(&zs, s, z);
            }
        }
    }
}

/// The aggregate of every node (module doc, step 2), nodes = blocks of `bs` unknowns.
fn aggregate(a: &Csr, bs: usize, theta: f64) -> Vec<usize> {
    let nodes = a.n_rows / bs;
    // The strength graph on nodes: |A_IJ| (Frobenius norm of the block) per neighbour.
    let mut strong: Vec<Vec<usize>> = vec![Vec::new(); nodes];
    let mut norm2: Vec<std::collections::HashMap<usize, f64>> = vec![Default::default(); nodes];
    for i in 0..a.n_rows {
        for (j, v) in a.row(i) {
            *norm2[i / bs].entry(j / bs).or_insert(0.0) += v * v;
        }
    }
    let dn: Vec<f64> = (0..nodes)
        .map(|i| norm2[i].get(&i).copied().unwrap_or(0.0).sqrt())
        .collect();
    for (i, row) in norm2.iter().enumerate() {
        let mut nb: Vec<usize> = row
            .iter()
            .filter(|&(&j, &v)| j != i && v.sqrt() >= theta * (dn[i] * dn[j]).sqrt() && v > 0.0)
            .map(|(&j, _)| j)
            .collect();
        nb.sort_unstable();
        strong[i] = nb;
    }
    const FREE: usize = usize::MAX;
    let mut agg = vec![FREE; nodes];
    let mut count = 0;
    // Pass 1: a free node whose strong neighbours are all free, with them.
    for i in 0..nodes {
        if agg[i] == FREE && strong[i].iter().all(|&j| agg[j] == FREE) {
            agg[i] = count;
            for &j in &strong[i] {
                agg[j] = count;
            }
            count += 1;
        }
    }
    // Pass 2: join a neighbouring aggregate of pass 1.
    let first = agg.clone();
    for i in 0..nodes {
        if agg[i] == FREE {
            if let Some(&j) = strong[i].iter().find(|&&j| first[j] != FREE) {
                agg[i] = first[j];
            }
        }
    }
    // Pass 3: new aggregates of what is left, with its free neighbours.
    for i in 0..nodes {
        if agg[i] == FREE {
            agg[i] = count;
            for &j in &strong[i] {
                if agg[j] == FREE {
                    agg[j] = count;
                }
            }
            count += 1;
        }
    }
    agg
}

/// The tentative prolongator and the coarse near-null space (module doc, step 3): unknown
/// `bs·node + c` of aggregate `g` has row `Q_g[(its place), :]` in columns `k·g .. k·g + k`.
fn tentative(agg: &[usize], n_agg: usize, bs: usize, b: &[f64], k: usize) -> (Csr, Vec<f64>) {
    let n = agg.len() * bs;
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); n_agg];
    for (node, &g) in agg.iter().enumerate() {
        members[g].extend((0..bs).map(|c| bs * node + c));
    }
    let nc = n_agg * k;
    let mut q_rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    let mut bc = vec![0.0; nc * k];
    for (g, rows) in members.iter().enumerate() {
        // Modified Gram–Schmidt, twice, on the columns of B restricted to the aggregate.
        let mut q: Vec<Vec<f64>> = (0..k)
            .map(|c| rows.iter().map(|&i| b[c * n + i]).collect())
            .collect();
        let mut r = vec![vec![0.0; k]; k];
        for c in 0..k {
            let scale = q[c].iter().map(|v| v * v).sum::<f64>().sqrt();
            for _ in 0..2 {
                for p in 0..c {
                    let d: f64 = q[p].iter().zip(&q[c]).map(|(x, y)| x * y).sum();
                    r[p][c] += d;
                    let qp = q[p].clone();
                    q[c].iter_mut().zip(&qp).for_each(|(y, x)| *y -= d * x);
                }
            }
            let nrm = q[c].iter().map(|v| v * v).sum::<f64>().sqrt();
            if nrm > 1e-10 * scale && nrm > 0.0 {
                r[c][c] = nrm;
                q[c].iter_mut().for_each(|v| *v /= nrm);
            } else {
                // Dependent on the previous columns here: a zero column of T.
                q[c].iter_mut().for_each(|v| *v = 0.0);
            }
        }
        for (place, &i) in rows.iter().enumerate() {
            for (c, qc) in q.iter().enumerate() {
                if qc[place] != 0.0 {
                    q_rows[i].push((k * g + c, qc[place]));
                }
            }
        }
        for (p, rp) in r.iter().enumerate() {
            for (c, &v) in rp.iter().enumerate() {
                bc[c * nc + k * g + p] = v;
            }
        }
    }
    let mut ptr = Vec::with_capacity(n + 1);
    let (mut col, mut val) = (Vec::new(), Vec::new());
    ptr.push(0);
    for row in q_rows {
        for (j, v) in row {
            col.push(j);
            val.push(v);
        }
        ptr.push(col.len());
    }
    (
        Csr {
            n_rows: n,
            n_cols: nc,
            ptr,
            col,
            val,
        },
        bc,
    )
}

/// `P = (I − ω/ρ · D⁻¹A) T` (module doc, step 4).
fn smooth(a: &Csr, diag: &[f64], t: &Csr) -> Result<Csr> {
    let rho = spectral_radius(a, diag)?;
    let at = a.mul(t);
    let w = OMEGA / rho;
    // P = T − w D⁻¹ (A T), merged row by row (both rows sorted by column).
    let mut ptr = Vec::with_capacity(t.n_rows + 1);
    let (mut col, mut val) = (Vec::new(), Vec::new());
    ptr.push(0);
    for (i, d) in diag.iter().enumerate() {
        let s = w / d;
        let (mut x, mut y) = (t.row(i).peekable(), at.row(i).peekable());
        loop {
            let next = match (x.peek(), y.peek()) {
                (Some(&(jx, vx)), Some(&(jy, vy))) => {
                    if jx == jy {
                        x.next();
                        y.next();
                        (jx, vx - s * vy)
                    } else if jx < jy {
                        x.next();
                        (jx, vx)
                    } else {
                        y.next();
                        (jy, -s * vy)
                    }
                }
                (Some(&(jx, vx)), None) => {
                    x.next();
                    (jx, vx)
                }
                (None, Some(&(jy, vy))) => {
                    y.next();
                    (jy, -s * vy)
                }
                (None, None) => break,
            };
            col.push(next.0);
            val.push(next.1);
        }
        ptr.push(col.len());
    }
    Ok(Csr {
        n_rows: t.n_rows,
        n_cols: t.n_cols,
        ptr,
        col,
        val,
    })
}

/// ρ(D⁻¹A) = λ_max(D^{-1/2} A D^{-1/2}) as PyAMG's `approximate_spectral_radius` takes it:
/// 15 Lanczos steps (full reorthogonalization) from a fixed start, restarted (at most 5 times)
/// from the largest Ritz vector until its residual `|β y_last|` is below 1 % of the Ritz
/// value. A single run from a smooth start can miss the large eigenvalues that stiff penalty
/// rows localize on a few nodes; ρ too small makes `P` amplify them (found on rows along
/// curved normals at ε = 1e8·max K_ii: 3 661 CG iterations against PyAMG's 27).
fn spectral_radius(a: &Csr, diag: &[f64]) -> Result<f64> {
    let n = a.n_rows;
    if n == 0 {
        return Ok(0.0);
    }
    let s: Vec<f64> = diag.iter().map(|d| 1.0 / d.sqrt()).collect();
    let steps = 15.min(n);
    let mut v: Vec<f64> = (0..n)
        .map(|i| 1.0 + ((i * 7919) % 13) as f64 / 13.0)
        .collect();
    let mut rho = 0.0;
    for _restart in 0..=5 {
        let nv = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        v.iter_mut().for_each(|x| *x /= nv);
        let mut basis: Vec<Vec<f64>> = Vec::with_capacity(steps);
        let (mut alpha, mut beta) = (Vec::new(), Vec::new());
        let (mut w, mut tmp) = (vec![0.0; n], vec![0.0; n]);
        let mut breakdown = false;
        for _ in 0..steps {
            let sv: Vec<f64> = v.iter().zip(&s).map(|(x, s)| x * s).collect();
            a.matvec(&sv, &mut tmp);
            w.iter_mut()
                .zip(&tmp)
                .zip(&s)
                .for_each(|((w, t), s)| *w = t * s);
            let al: f64 = w.iter().zip(&v).map(|(x, y)| x * y).sum();
            alpha.push(al);
            basis.push(v.clone());
            for q in &basis {
                let d: f64 = w.iter().zip(q).map(|(x, y)| x * y).sum();
                w.iter_mut().zip(q).for_each(|(x, y)| *x -= d * y);
            }
            let b = w.iter().map(|x| x * x).sum::<f64>().sqrt();
            if b.is_nan() || b <= 1e-12 * al.abs() {
                breakdown = true;
                break;
            }
            beta.push(b);
            v.iter_mut().zip(&w).for_each(|(v, w)| *v = w / b);
        }
        let k = alpha.len();
        let mut t = nalgebra::DMatrix::<f64>::zeros(k, k);
        for i in 0..k {
            t[(i, i)] = alpha[i];
            if i + 1 < k {
                t[(i, i + 1)] = beta[i];
                t[(i + 1, i)] = beta[i];
            }
        }
        let eig = t.symmetric_eigen();
        let top = (0..k)
            .max_by(|&i, &j| {
                eig.eigenvalues[i]
                    .abs()
                    .total_cmp(&eig.eigenvalues[j].abs())
            })
            .unwrap_or(0);
        rho = eig.eigenvalues[top].abs();
        if !rho.is_finite() {
            return Err(Error::Numerical(
                "AMG: the spectral radius estimate of D⁻¹A is not finite".into(),
            ));
        }
        let y = eig.eigenvectors.column(top);
        // The residual of the Ritz pair: β_k (after the last step) times y's last entry.
        let error = beta.get(k - 1).map_or(0.0, |b| b * y[k - 1]);
        if breakdown || error.abs() < 0.01 * rho {
            break;
        }
        v = vec![0.0; n];
        for (q, &c) in basis.iter().zip(y.iter()) {
            v.iter_mut().zip(q).for_each(|(v, q)| *v += c * q);
        }
    }
    Ok(rho)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::krylov::{cg, Stop};
    use crate::linalg::precond::Jacobi;

    /// The 5-point Laplacian on a side × side grid (Dirichlet).
    fn laplacian(side: usize) -> Stiffness {
        let id = |i: usize, j: usize| i * side + j;
        let mut t = Vec::new();
        for i in 0..side {
            for j in 0..side {
                t.push((id(i, j), id(i, j), 4.0));
                if i + 1 < side {
                    t.push((id(i, j), id(i + 1, j), -1.0));
                    t.push((id(i + 1, j), id(i, j), -1.0));
                }
                if j + 1 < side {
                    t.push((id(i, j), id(i, j + 1), -1.0));
                    t.push((id(i, j + 1), id(i, j), -1.0));
                }
            }
        }
        Stiffness::from_triplets(side * side, &t).unwrap()
    }

    #[test]
    fn sparse_products_match_dense() {
        let a = laplacian(4).to_sparse();
        let m = Csr::of_symmetric(a.as_ref());
        let mm = m.mul(&m.transpose());
        let dense = |c: &Csr| {
            let mut d = vec![vec![0.0; c.n_cols]; c.n_rows];
            for (i, row) in d.iter_mut().enumerate() {
                for (j, v) in c.row(i) {
                    row[j] += v;
                }
            }
            d
        };
        let (dm, dmm) = (dense(&m), dense(&mm));
        for i in 0..16 {
            for j in 0..16 {
                let e: f64 = (0..16).map(|k| dm[i][k] * dm[j][k]).sum();
                assert_eq!(dmm[i][j], e);
            }
        }
    }

    #[test]
    fn tentative_prolongator_reproduces_the_near_null_space() {
        let agg = vec![0, 0, 1, 1, 1, 2];
        let b: Vec<f64> = std::iter::repeat_n(1.0, 6)
            .chain((0..6).map(|i| i as f64))
            .collect();
        let (t, bc) = tentative(&agg, 3, 1, &b, 2);
        // T B_c = B.
        for c in 0..2 {
            let x: Vec<f64> = (0..6).map(|j| bc[c * 6 + j]).collect();
            let mut y = vec![0.0; 6];
            t.matvec(&x, &mut y);
            for i in 0..6 {
                assert!((y[i] - b[c * 6 + i]).abs() <= 1e-14 * 6.0, "{c} {i}: {y:?}");
            }
        }
        // Orthonormal columns (the one-node aggregate's second column is zero).
        let tt = t.transpose().mul(&t);
        for i in 0..6 {
            for (j, v) in tt.row(i) {
                let e = if i == j && i != 5 { 1.0 } else { 0.0 };
                assert!((v - e).abs() <= 1e-14, "{i} {j} {v}");
            }
        }
    }

    #[test]
    fn amg_cg_converges_in_few_iterations_independent_of_size() {
        let mut its = Vec::new();
        for side in [31, 63] {
            let a = laplacian(side).to_sparse();
            let amg = Amg::new(a.as_ref(), &AmgOptions::default()).unwrap();
            assert!(amg.levels() >= 2 && amg.operator_complexity() < 2.0);
            let b: Vec<f64> = (0..side * side)
                .map(|i| ((i * 37) % 11) as f64 - 5.0)
                .collect();
            let (_, run) = cg(a.as_ref(), &amg, &b, Stop::Residual(1e-8), 500);
            assert!(run.converged);
            let jac = Jacobi::new(a.as_ref()).unwrap();
            let (_, jrun) = cg(a.as_ref(), &jac, &b, Stop::Residual(1e-8), 5000);
            assert!(run.iterations * 4 < jrun.iterations, "{run:?} {jrun:?}");
            its.push(run.iterations);
        }
        // Near-optimal: the count grows by little as h halves (Jacobi's doubles).
        assert!(its[1] as f64 <= 1.5 * its[0] as f64, "{its:?}");
    }

    #[test]
    fn refuses_a_near_null_space_of_the_wrong_size() {
        let a = laplacian(20).to_sparse();
        let opts = AmgOptions {
            near_null: Some((vec![1.0; 7], 1)),
            ..AmgOptions::default()
        };
        assert!(Amg::new(a.as_ref(), &opts).is_err());
        let opts = AmgOptions {
            block_size: 3,
            ..AmgOptions::default()
        };
        assert!(Amg::new(a.as_ref(), &opts).is_err());
    }
}

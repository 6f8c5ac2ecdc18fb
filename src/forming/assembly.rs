//! Block-tridiagonal storage of the global matrix (3 DOFs per node, element e couples nodes e
//! and e+1), nodal rotations to local axes, and direct CSC output for the strategies.

use crate::system::Stiffness;
use faer::sparse::{SparseColMat, SymbolicSparseColMat};

/// A 3×3 block.
pub type Block = [[f64; 3]; 3];

/// `K` as diagonal blocks `d[i] = K[i, i]` and upper blocks `o[i] = K[i, i+1]`
/// (`K[i+1, i] = o[i]ᵀ`).
#[derive(Clone, Debug)]
pub struct BlockTri {
    /// Diagonal blocks (one per node).
    pub d: Vec<Block>,
    /// Upper off-diagonal blocks (one per element).
    pub o: Vec<Block>,
}

fn mul_t_a_b(t1: &Block, a: &Block, t2: &Block) -> Block {
    // t1ᵀ a t2
    let mut tmp = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            tmp[i][j] = (0..3).map(|k| a[i][k] * t2[k][j]).sum();
        }
    }
    let mut out = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            out[i][j] = (0..3).map(|k| t1[k][i] * tmp[k][j]).sum();
        }
    }
    out
}

impl BlockTri {
    /// Zero matrix for `nodes` nodes.
    pub fn zeros(nodes: usize) -> Self {
        BlockTri {
            d: vec![[[0.0; 3]; 3]; nodes],
            o: vec![[[0.0; 3]; 3]; nodes.saturating_sub(1)],
        }
    }

    /// Adds the 6×6 element matrix of element `e` (nodes e, e+1).
    pub fn add_element(&mut self, e: usize, ke: &[[f64; 6]; 6]) {
        for a in 0..3 {
            for b in 0..3 {
                self.d[e][a][b] += ke[a][b];
                self.d[e + 1][a][b] += ke[a + 3][b + 3];
                self.o[e][a][b] += ke[a][b + 3];
            }
        }
    }

    /// `y = K x` (x, y with 3 entries per node).
    pub fn matvec(&self, x: &[f64]) -> Vec<f64> {
        let nn = self.d.len();
        let mut y = vec![0.0; 3 * nn];
        for i in 0..nn {
            for a in 0..3 {
                let mut s = 0.0;
                for b in 0..3 {
                    s += self.d[i][a][b] * x[3 * i + b];
                    if i + 1 < nn {
                        s += self.o[i][a][b] * x[3 * (i + 1) + b];
                    }
                    if i > 0 {
                        s += self.o[i - 1][b][a] * x[3 * (i - 1) + b];
                    }
                }
                y[3 * i + a] = s;
            }
        }
        y
    }

    /// Change of basis `K ← Tᵀ K T` with block-diagonal T; `t[i] = None` means identity.
    pub fn rotate(&mut self, t: &[Option<Block>]) {
        const I: Block = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let get = |i: usize| t[i].unwrap_or(I);
        for i in 0..self.d.len() {
            if t[i].is_some() {
                self.d[i] = mul_t_a_b(&get(i), &self.d[i], &get(i));
            }
        }
        for i in 0..self.o.len() {
            if t[i].is_some() || t[i + 1].is_some() {
                self.o[i] = mul_t_a_b(&get(i), &self.o[i], &get(i + 1));
            }
        }
    }

    /// The matrix restricted to the free DOFs (`red[d]` = reduced index or `usize::MAX`), in
    /// compressed-column storage, exactly symmetric (diagonal blocks symmetrized).
    pub fn to_stiffness(&self, red: &[usize], nf: usize) -> crate::Result<Stiffness> {
        let nn = self.d.len();
        let mut col_ptr = Vec::with_capacity(nf + 1);
        let mut row_idx = Vec::with_capacity(nf * 9);
        let mut val = Vec::with_capacity(nf * 9);
        col_ptr.push(0usize);
        for i in 0..nn {
            for a in 0..3 {
                if red[3 * i + a] == usize::MAX {
                    continue;
                }
                let lo = i.saturating_sub(1);
                let hi = (i + 1).min(nn - 1);
                for k in lo..=hi {
                    for b in 0..3 {
                        let r = red[3 * k + b];
                        if r == usize::MAX {
                            continue;
                        }
                        // K[(k, b), (i, a)]
                        let v = if k == i {
                            0.5 * (self.d[i][b][a] + self.d[i][a][b])
                        } else if k + 1 == i {
                            self.o[k][b][a]
                        } else {
                            self.o[i][a][b]
                        };
                        row_idx.push(r);
                        val.push(v);
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        let sym = SymbolicSparseColMat::new_checked(nf, nf, col_ptr, None, row_idx);
        let m = SparseColMat::new(sym, val);
        Ok(Stiffness::Sparse(m))
    }
}

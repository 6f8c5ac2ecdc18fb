//! The near-null space B of K that a smoothed-aggregation AMG builds its coarse spaces from
//! (`linalg::amg`): for elasticity the rigid-body modes, `K B ≈ 0` away from the supports.
//!
//! In 2-D, with the DOFs of node i at `(x_i, y_i)` numbered `(u_x, u_y)`:
//! `B_i = [[1, 0, −y_i], [0, 1, x_i]]` (two translations and the rotation, PyAMG's
//! `gallery.elasticity` order); in 3-D, `B_i = [I₃ | −[x_i]×]` (three translations and the
//! rotations about x, y, z: columns `(0, −z, y)`, `(z, 0, −x)`, `(−y, x, 0)`). A scene gives
//! B itself (`"near_null_space": {"matrix_market": "B.mtx"}`, N×k, with `"block_size"`) or
//! the coordinates of its nodes (`"nodes": {"coordinates": [...], "dofs_per_node": d}`), from
//! which [`NearNull::rigid_body_modes`] builds it. Without either, the AMG is scalar with
//! B = ones.
//!
//! **Slots** ([`NearNull::with_slots`]; scenes: `near_null_space.slots`). Where supports fix some components of a
//! node but not all (a symmetry plane), the unknowns do not come in whole node blocks. B is
//! then given over *slots*, `block_size` per node, and each unknown names its slot; a slot
//! without an unknown is a prescribed component, which a nodal AMG fills with a decoupled
//! identity row (as codes that keep Dirichlet rows do) so that its node blocks stay whole.

use crate::error::{Error, Result};

/// B (N×k, column-major) and the number of DOFs per node the aggregation groups.
#[derive(Clone, Debug, PartialEq)]
pub struct NearNull {
    /// DOFs per node (consecutive DOFs `b·i … b·i + b − 1` belong to node i).
    pub block_size: usize,
    /// Columns k of B.
    pub k: usize,
    /// B, column-major: entry (r, c) at `b[c·N + r]` (N: slots, [`Self::padded_n`]).
    pub b: Vec<f64>,
    /// The slot of each unknown, increasing (module doc); `None`: unknown i is slot i.
    pub slots: Option<Vec<usize>>,
}

impl NearNull {
    /// Validates a given B: `k ≥ 1`, `b.len() = N·k`, finite entries, `N` a multiple of
    /// `block_size ≥ 1`, and no zero column.
    pub fn new(n: usize, block_size: usize, k: usize, b: Vec<f64>) -> Result<NearNull> {
        if block_size == 0 || !n.is_multiple_of(block_size) {
            return Err(Error::out_of_range(
                "near-null space: block_size (DOFs per node)",
                block_size,
                format!("≥ 1 and dividing N = {n}"),
            ));
        }
        if k == 0 || b.len() != n * k {
            return Err(Error::length_mismatch(
                format!("near-null space B (N × k with N = {n}, column-major)"),
                b.len(),
                n * k.max(1),
            ));
        }
        if let Some(i) = b.iter().position(|v| !v.is_finite()) {
            return Err(Error::not_finite(format!(
                "near-null space entry ({}, {})",
                i % n,
                i / n
            )));
        }
        if let Some(c) = (0..k).find(|&c| b[c * n..(c + 1) * n].iter().all(|&v| v == 0.0)) {
            return Err(Error::input(format!(
                "near-null space: column {c} of B is zero"
            )));
        }
        Ok(NearNull {
            block_size,
            k,
            b,
            slots: None,
        })
    }

    /// B over slots (module doc): unknown i fills slot `slots[i]`; the slots must increase
    /// and lie below [`Self::padded_n`]. The slots no unknown fills are prescribed components.
    pub fn with_slots(self, slots: Vec<usize>) -> Result<NearNull> {
        check_slots("near-null space", &slots, self.padded_n())?;
        Ok(NearNull {
            slots: Some(slots),
            ..self
        })
    }

    /// The rigid-body modes (module doc) of nodes at `coords` (each of length `dim` = 2 or 3),
    /// `dim` DOFs per node in the order x, y(, z).
    pub fn rigid_body_modes(coords: &[Vec<f64>], dim: usize) -> Result<NearNull> {
        if !(dim == 2 || dim == 3) {
            return Err(Error::out_of_range(
                "nodes: dofs_per_node for rigid-body modes",
                dim,
                "2 (plane) or 3 (solid)",
            ));
        }
        if let Some(i) = coords.iter().position(|c| c.len() != dim) {
            return Err(Error::length_mismatch(
                format!("nodes: coordinates of node {i}"),
                coords[i].len(),
                dim,
            ));
        }
        if let Some(i) = coords.iter().position(|c| c.iter().any(|v| !v.is_finite())) {
            return Err(Error::not_finite(format!("nodes: coordinates of node {i}")));
        }
        let n = coords.len() * dim;
        let k = if dim == 2 { 3 } else { 6 };
        let mut b = vec![0.0; n * k];
        let mut set = |row: usize, col: usize, v: f64| b[col * n + row] = v;
        for (i, x) in coords.iter().enumerate() {
            let r = dim * i;
            for d in 0..dim {
                set(r + d, d, 1.0);
            }
            if dim == 2 {
                set(r, 2, -x[1]);
                set(r + 1, 2, x[0]);
            } else {
                // Rotation about x: (0, −z, y); about y: (z, 0, −x); about z: (−y, x, 0).
                set(r + 1, 3, -x[2]);
                set(r + 2, 3, x[1]);
                set(r, 4, x[2]);
                set(r + 2, 4, -x[0]);
                set(r, 5, -x[1]);
                set(r + 1, 5, x[0]);
            }
        }
        NearNull::new(n, dim, k, b)
    }

    /// The rigid-body modes of every node that keeps a free DOF, over `dim` slots per such
    /// node: node `i` at `coords(i)`, its DOFs `dim·i + c`, free where `fixed[dim·i + c]` is
    /// None and numbered in that order (as an elimination of the prescribed DOFs numbers
    /// them). A prescribed component of a node that keeps another is an empty slot (module
    /// doc); a node with none free has no slots.
    pub fn rigid_body_modes_in_slots(
        dim: usize,
        coords: impl Fn(usize) -> Vec<f64>,
        fixed: &[Option<f64>],
    ) -> Result<NearNull> {
        let mut nodes = Vec::new();
        let mut slots = Vec::new();
        for node in 0..fixed.len() / dim.max(1) {
            let free: Vec<usize> = (0..dim)
                .filter(|&c| fixed[dim * node + c].is_none())
                .collect();
            if free.is_empty() {
                continue;
            }
            slots.extend(free.iter().map(|c| dim * nodes.len() + c));
            nodes.push(coords(node));
        }
        NearNull::rigid_body_modes(&nodes, dim)?.with_slots(slots)
    }

    /// The unknowns B is for (rows of B, or the number of slots filled).
    pub fn n(&self) -> usize {
        self.slots.as_ref().map_or(self.padded_n(), Vec::len)
    }

    /// Rows of B: one per slot (= [`Self::n`] without slots).
    pub fn padded_n(&self) -> usize {
        self.b.len() / self.k
    }
}

/// Checks that `slots` increase and lie below `n_slots` (errors name `what` and the unknown).
pub fn check_slots(what: &str, slots: &[usize], n_slots: usize) -> Result<()> {
    if let Some(i) =
        (0..slots.len()).find(|&i| slots[i] >= n_slots || (i > 0 && slots[i] <= slots[i - 1]))
    {
        return Err(Error::out_of_range(
            format!("{what}: slot of unknown {i}"),
            slots[i],
            format!("increasing and below the {n_slots} slots"),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_body_modes_are_the_kernel_of_a_free_bar() {
        // Two nodes of a 2-D bar along (1, 1): the axial stiffness k (e eᵀ ⊗ [1 −1; −1 1]).
        let coords = vec![vec![0.5, -1.0], vec![1.5, 0.0]];
        let nn = NearNull::rigid_body_modes(&coords, 2).unwrap();
        let e = [std::f64::consts::FRAC_1_SQRT_2; 2];
        let kmat = |i: usize, j: usize| {
            let s = if (i < 2) == (j < 2) { 1.0 } else { -1.0 };
            s * e[i % 2] * e[j % 2]
        };
        for c in 0..3 {
            let col = &nn.b[c * 4..(c + 1) * 4];
            for i in 0..4 {
                let r: f64 = (0..4).map(|j| kmat(i, j) * col[j]).sum();
                assert!(r.abs() < 4.0 * f64::EPSILON, "mode {c}, row {i}: {r}");
            }
        }
    }

    #[test]
    fn a_3d_rotation_mode_is_the_cross_product() {
        let coords = vec![vec![1.0, 2.0, 3.0]];
        let nn = NearNull::rigid_body_modes(&coords, 3).unwrap();
        // ω = e_z: u = ω × x = (−y, x, 0).
        assert_eq!(&nn.b[15..18], &[-2.0, 1.0, 0.0]);
        // ω = e_x: u = (0, −z, y).
        assert_eq!(&nn.b[9..12], &[0.0, -3.0, 2.0]);
    }

    #[test]
    fn bad_near_null_spaces_are_refused() {
        assert!(NearNull::new(4, 3, 1, vec![1.0; 4]).is_err());
        assert!(NearNull::new(4, 2, 2, vec![1.0; 7]).is_err());
        assert!(NearNull::new(2, 1, 1, vec![1.0, f64::NAN]).is_err());
        assert!(NearNull::new(2, 1, 2, vec![1.0, 1.0, 0.0, 0.0]).is_err());
        assert!(NearNull::rigid_body_modes(&[vec![0.0; 3]], 2).is_err());
        assert!(NearNull::rigid_body_modes(&[vec![0.0; 4]], 4).is_err());
    }
}

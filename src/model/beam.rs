//! 2D Euler–Bernoulli beam/frame elements (Eq. 30) and their assembly.
//!
//! Element DOFs `(u₁, w₁, θ₁, u₂, w₂, θ₂)` in local axes (u axial, w transverse, θ = dw/dx
//! counter-clockwise). The local stiffness (the paper's Eq. 30, with its layout misprint
//! corrected — see [`element_stiffness`]) is
//!
//! ```text
//! [ EA/l     0         0        −EA/l    0         0       ]
//! [ 0        12EJ/l³   6EJ/l²    0      −12EJ/l³   6EJ/l²  ]
//! [ 0        6EJ/l²    4EJ/l     0      −6EJ/l²    2EJ/l   ]
//! [ −EA/l    0         0         EA/l    0         0       ]
//! [ 0       −12EJ/l³  −6EJ/l²    0       12EJ/l³  −6EJ/l²  ]
//! [ 0        6EJ/l²    2EJ/l     0      −6EJ/l²    4EJ/l   ]
//! ```
//!
//! Frames rotate it by the element angle. Only [`Frame::assemble`] knows global DOF numbers:
//! node `i`'s DOF `k ∈ {0: u_x, 1: u_y, 2: θ}` maps to a global index unless it is fixed
//! (clamped supports remove rows/columns, i.e. essential BCs are eliminated).

use crate::error::{Error, Result};
use crate::system::{Constraint, ConstraintKind, Problem, Stiffness};

/// Section and material of a beam element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Section {
    /// Young modulus E (force/length²).
    pub e: f64,
    /// Cross-section area A (length²).
    pub a: f64,
    /// Second moment of area J (length⁴).
    pub j: f64,
}

impl Section {
    /// Rectangular b×h section: A = bh, J = bh³/12.
    pub fn rectangle(e: f64, b: f64, h: f64) -> Self {
        Section {
            e,
            a: b * h,
            j: b * h.powi(3) / 12.0,
        }
    }
}

/// Local element stiffness, Eq. 30 (6×6, DOFs u₁ w₁ θ₁ u₂ w₂ θ₂).
///
/// The printed Eq. 30 has a layout misprint: its 4th row reads `0 0 EA/l 0 0 0` and its 5th
/// row is all zeros; the symmetric matrix above (the standard frame element, which is what the
/// paper's assembled Eq. 31 actually contains) is used.
pub fn element_stiffness(s: Section, l: f64) -> [[f64; 6]; 6] {
    let ea = s.e * s.a / l;
    let k1 = 12.0 * s.e * s.j / l.powi(3);
    let k2 = 6.0 * s.e * s.j / l.powi(2);
    let k3 = 4.0 * s.e * s.j / l;
    let k4 = 2.0 * s.e * s.j / l;
    [
        [ea, 0.0, 0.0, -ea, 0.0, 0.0],
        [0.0, k1, k2, 0.0, -k1, k2],
        [0.0, k2, k3, 0.0, -k2, k4],
        [-ea, 0.0, 0.0, ea, 0.0, 0.0],
        [0.0, -k1, -k2, 0.0, k1, -k2],
        [0.0, k2, k4, 0.0, -k2, k3],
    ]
}

/// Element stiffness in global axes for an element from `p1` to `p2`: `Tᵀ k T`.
pub fn frame_element_stiffness(s: Section, p1: (f64, f64), p2: (f64, f64)) -> [[f64; 6]; 6] {
    let (dx, dy) = (p2.0 - p1.0, p2.1 - p1.1);
    let l = dx.hypot(dy);
    let (c, sn) = (dx / l, dy / l);
    let k = element_stiffness(s, l);
    // T maps global (ux, uy, θ) to local (u, w, θ) per node.
    let mut t = [[0.0; 6]; 6];
    for b in [0, 3] {
        t[b][b] = c;
        t[b][b + 1] = sn;
        t[b + 1][b] = -sn;
        t[b + 1][b + 1] = c;
        t[b + 2][b + 2] = 1.0;
    }
    let mut out = [[0.0; 6]; 6];
    for i in 0..6 {
        for j in 0..6 {
            let mut v = 0.0;
            for a in 0..6 {
                for b in 0..6 {
                    v += t[a][i] * k[a][b] * t[b][j];
                }
            }
            out[i][j] = v;
        }
    }
    out
}

/// A beam element between two nodes.
#[derive(Clone, Copy, Debug)]
pub struct Element {
    /// First node.
    pub n1: usize,
    /// Second node.
    pub n2: usize,
    /// Section.
    pub section: Section,
}

/// A 2D frame: nodes, elements, fixed DOFs.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Node coordinates (x, y).
    pub nodes: Vec<(f64, f64)>,
    /// Elements.
    pub elements: Vec<Element>,
    /// `fixed[3 i + k]`: node i's DOF k is clamped (eliminated).
    pub fixed: Vec<bool>,
}

impl Frame {
    /// A straight cantilever along +x with `n_el` equal elements of total length `length`,
    /// clamped (u, w, θ) at node 0.
    pub fn cantilever(n_el: usize, length: f64, section: Section) -> Result<Self> {
        if n_el == 0 {
            return Err(Error::out_of_range("cantilever elements", n_el, "≥ 1"));
        }
        Error::positive("cantilever length", length)?;
        let le = length / n_el as f64;
        let nodes = (0..=n_el).map(|i| (i as f64 * le, 0.0)).collect();
        let elements = (0..n_el)
            .map(|i| Element {
                n1: i,
                n2: i + 1,
                section,
            })
            .collect();
        let mut fixed = vec![false; 3 * (n_el + 1)];
        fixed[..3].fill(true);
        Ok(Frame {
            nodes,
            elements,
            fixed,
        })
    }

    /// Global DOF index of node `i`, local DOF `k` (0: u_x, 1: u_y, 2: θ), or `None` if fixed.
    pub fn dof(&self, node: usize, k: usize) -> Option<usize> {
        let idx = 3 * node + k;
        if self.fixed[idx] {
            None
        } else {
            Some(self.fixed[..idx].iter().filter(|&&f| !f).count())
        }
    }

    /// Number of free DOFs.
    pub fn n_dofs(&self) -> usize {
        self.fixed.iter().filter(|&&f| !f).count()
    }

    /// Assembles K (dense if `sparse` is false, else sparse CSC).
    pub fn assemble(&self, sparse: bool) -> Result<Stiffness> {
        let map: Vec<Option<usize>> = {
            let mut next = 0;
            self.fixed
                .iter()
                .map(|&f| {
                    if f {
                        None
                    } else {
                        next += 1;
                        Some(next - 1)
                    }
                })
                .collect()
        };
        let n = self.n_dofs();
        if n == 0 {
            return Err(Error::none_given(
                "frame: free DOFs",
                " (every DOF is fixed)",
            ));
        }
        let mut t = Vec::with_capacity(36 * self.elements.len());
        for el in &self.elements {
            let nodes = self.nodes.len();
            if let Some(missing) = [el.n1, el.n2].into_iter().find(|&i| i >= nodes) {
                return Err(Error::out_of_range(
                    format!("element ({}, {}): node", el.n1, el.n2),
                    missing,
                    format!("< {nodes} (the frame's nodes, 0-based)"),
                ));
            }
            if el.n1 == el.n2 {
                return Err(Error::duplicate(
                    format!("element ({}, {}): node", el.n1, el.n2),
                    el.n1,
                ));
            }
            let ke = frame_element_stiffness(el.section, self.nodes[el.n1], self.nodes[el.n2]);
            let g: Vec<Option<usize>> = (0..6)
                .map(|a| map[3 * if a < 3 { el.n1 } else { el.n2 } + a % 3])
                .collect();
            for a in 0..6 {
                for b in 0..6 {
                    if let (Some(i), Some(j)) = (g[a], g[b]) {
                        if ke[a][b] != 0.0 {
                            t.push((i, j, ke[a][b]));
                        }
                    }
                }
            }
        }
        if sparse {
            Stiffness::from_triplets(n, &t)
        } else {
            let mut rows = vec![vec![0.0; n]; n];
            for (i, j, v) in t {
                rows[i][j] += v;
            }
            Stiffness::from_rows(&rows)
        }
    }
}

/// The paper's beam (Fig. 2, Eq. 30–34): a 30 mm cantilever of 3 elements (l = 10 mm), square
/// 1×1 mm section (A = 1 mm², J = 1/12 mm⁴), clamped at node 1, loaded at node 4 by
/// q = (−50 axial, +1 transverse).
///
/// Units: Eq. 31 has EA/l = 210 and 12EJ/l³ = 2.1 with l = 10, A = 1, J = 1/12, i.e.
/// E = 2100 force-units/mm². With E = 210 GPa = 210 000 N/mm² that is a force unit of 100 N
/// (the text says "we skip units"); the loads 50 and 1 are in the same unit.
pub mod paper {
    use super::*;

    /// Young modulus in the example's units (see module docs).
    pub const E: f64 = 2100.0;
    /// Beam length (mm).
    pub const LENGTH: f64 = 30.0;
    /// Number of elements.
    pub const N_ELEMENTS: usize = 3;
    /// Load (Eq. 32).
    pub const LOAD: [f64; 9] = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -50.0, 1.0, 0.0];
    /// Constrained DOFs (Eq. 34, 0-based): node 3 transverse, node 4 axial and transverse.
    pub const DOFS: [usize; 3] = [4, 6, 7];
    /// Limits û (Eq. 34).
    pub const LIMITS: [f64; 3] = [3.0, -1.0, 30.0];

    /// The frame of Fig. 2.
    pub fn frame() -> Frame {
        Frame::cantilever(N_ELEMENTS, LENGTH, Section::rectangle(E, 1.0, 1.0))
            .expect("valid constants")
    }

    /// The contact problem of Eq. 31–34, all constraints bilateral (as the paper treats them).
    pub fn problem() -> Problem {
        problem_with_kind(ConstraintKind::Bilateral)
    }

    /// The same beam with all three constraints of the given kind.
    pub fn problem_with_kind(kind: ConstraintKind) -> Problem {
        let k = frame().assemble(false).expect("valid frame");
        let constraints = DOFS
            .iter()
            .zip(LIMITS)
            .map(|(&dof, limit)| Constraint::on_dof(dof, limit, kind))
            .collect();
        Problem::new(k, LOAD.to_vec(), constraints).expect("valid problem")
    }
}

/// A long cantilever resting on a wavy rigid bed: the scene family on which the plain
/// active-set loop of a classical penalty cycles (dense unilateral contact, ε near the beam's
/// own stiffness at the contact DOFs).
///
/// A steel-like cantilever (E = 2.1e5, 1×1 section) of length 100 with `n_el` elements,
/// clamped at x = 0, a transverse load `load` at every free node, and one `lower` constraint
/// per free node on its transverse DOF: `w(x) ≥ −amp · (1 + sin(waves·π·x/L)) · x/L`.
pub mod bed {
    use super::*;

    /// Parameters of the scene.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct Bed {
        /// Number of elements (N = 3·n_el DOFs, m = n_el constraints).
        pub n_el: usize,
        /// Transverse nodal load (negative: towards the bed).
        pub load: f64,
        /// Amplitude of the bed profile.
        pub amp: f64,
        /// Number of half-waves of the profile along the beam.
        pub waves: f64,
    }

    /// The contact problem (dense K).
    pub fn problem(b: Bed) -> Result<Problem> {
        let length = 100.0;
        let frame = Frame::cantilever(b.n_el, length, Section::rectangle(2.1e5, 1.0, 1.0))?;
        let k = frame.assemble(false)?;
        let mut q = vec![0.0; k.n()];
        let mut cons = Vec::with_capacity(b.n_el);
        for i in 1..=b.n_el {
            let d = frame.dof(i, 1).expect("only node 0 is clamped");
            q[d] = b.load;
            let x = frame.nodes[i].0 / length;
            let limit = -b.amp * (1.0 + (b.waves * std::f64::consts::PI * x).sin()) * x;
            cons.push(Constraint::on_dof(d, limit, ConstraintKind::Lower));
        }
        Problem::new(k, q, cons)
    }
}

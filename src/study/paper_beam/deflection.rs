//! The deflection curves (`deflection.csv`): nodal values and, between the nodes, the element
//! shape functions — Hermite cubics for w, linear for the axial displacement.

use super::PTS_PER_ELEMENT;
use crate::model::beam;
use serde::{Deserialize, Serialize};

/// A row of `deflection.csv`.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct DeflectionRow {
    /// `free`, `paper`, `condensed`, `lagrange`.
    pub solution: String,
    /// `node` (nodal values) or `curve` (interpolated).
    pub kind: String,
    /// Coordinate x (mm).
    pub x: f64,
    /// Axial displacement (linear between nodes).
    pub axial: f64,
    /// Transverse displacement w (Hermite cubic between nodes).
    pub w: f64,
    /// Rotation θ = dw/dx.
    pub theta: f64,
}

/// Nodal (axial, w, θ) of every node (clamped DOFs are 0).
fn nodal(frame: &beam::Frame, u: &[f64]) -> Vec<[f64; 3]> {
    (0..frame.nodes.len())
        .map(|i| {
            let g = |k| frame.dof(i, k).map_or(0.0, |d| u[d]);
            [g(0), g(1), g(2)]
        })
        .collect()
}

/// Nodal rows of solution `name` (displacements `u`) plus Hermite-cubic (w) / linear (axial)
/// curves between the nodes, [`PTS_PER_ELEMENT`] points per element.
pub fn deflection_rows(frame: &beam::Frame, name: &str, u: &[f64]) -> Vec<DeflectionRow> {
    let nv = nodal(frame, u);
    let mut rows: Vec<DeflectionRow> = frame
        .nodes
        .iter()
        .zip(&nv)
        .map(|(&(x, _), v)| DeflectionRow {
            solution: name.into(),
            kind: "node".into(),
            x,
            axial: v[0],
            w: v[1],
            theta: v[2],
        })
        .collect();
    for (e, el) in frame.elements.iter().enumerate() {
        let (x1, x2) = (frame.nodes[el.n1].0, frame.nodes[el.n2].0);
        let l = x2 - x1;
        let (a, b) = (nv[el.n1], nv[el.n2]);
        // The first point of every element but the first is the previous element's last.
        let start = usize::from(e > 0);
        for k in start..=PTS_PER_ELEMENT {
            let t = k as f64 / PTS_PER_ELEMENT as f64;
            let (t2, t3) = (t * t, t * t * t);
            let h = [
                1.0 - 3.0 * t2 + 2.0 * t3,
                t - 2.0 * t2 + t3,
                3.0 * t2 - 2.0 * t3,
                -t2 + t3,
            ];
            let dh = [
                -6.0 * t + 6.0 * t2,
                1.0 - 4.0 * t + 3.0 * t2,
                6.0 * t - 6.0 * t2,
                -2.0 * t + 3.0 * t2,
            ];
            let w = h[0] * a[1] + h[1] * l * a[2] + h[2] * b[1] + h[3] * l * b[2];
            let th = (dh[0] * a[1] + dh[1] * l * a[2] + dh[2] * b[1] + dh[3] * l * b[2]) / l;
            rows.push(DeflectionRow {
                solution: name.into(),
                kind: "curve".into(),
                x: x1 + t * l,
                axial: (1.0 - t) * a[0] + t * b[0],
                w,
                theta: th,
            });
        }
    }
    rows
}

//! VTK output: a solved contact scene as an XML unstructured grid (`.vtu`), which ParaView,
//! VisIt and meshio open.
//!
//! **Two sources.** `contact_bench --vtk DIR` writes the harness's single-body models
//! ([`indentation_fields`]: Q4 grid, below); `solve --vtk DIR` a user's scene that carries
//! `"nodes"` ([`scene_fields`]: its coordinates and cells, or one vertex per node; per node
//! `u`, `contact_force`, `gap` and `contact_node`).
//!
//! **What a model's file holds.** The body's nodes (2-D meshes at z = 0) and its cells (Q4
//! elements: VTK quads), and per node (point data):
//! - `u` — the displacement (3 components; z = 0 in 2-D), the prescribed values included;
//! - `contact_pressure` — p_c = the row's compressive force over its tributary length (area
//!   per radian, axisymmetric) at a contact node, 0 elsewhere; the same p as the benchmark's
//!   rows and profiles (`Indentation::pressures`);
//! - `gap` — the clearance to the obstacle at a contact node: `û_c − d_cᵀu` for an `upper`
//!   row, `d_cᵀu − û_c` for a `lower` one (negative: penetration; 0 for a bilateral row at
//!   its value), NaN elsewhere;
//! - `contact_node` — 1 at a contact node, 0 elsewhere.
//!
//! Units are the model's (the harness's cases: consistent units, lengths of a). The writer is
//! vtkio's (XML, inline base64 arrays); a file is written whole or not at all
//! ([`crate::provenance::write_atomic`]).

use crate::error::{Error, Result};
use crate::model::elasticity::{self, Base, Grid, Indentation};
use crate::scene::Nodes;
use crate::system::Problem;
use std::path::Path;
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

/// A field on the nodes: `components` values per node, node after node.
#[derive(Clone, Debug)]
pub struct Field {
    /// The array's name.
    pub name: String,
    /// Values per node (1 scalar, 3 vector).
    pub components: usize,
    /// `components × nodes` values.
    pub values: Vec<f64>,
}

impl Field {
    /// Fields from (name, components, values).
    fn set<const K: usize>(parts: [(&str, usize, Vec<f64>); K]) -> Vec<Field> {
        parts
            .into_iter()
            .map(|(name, components, values)| Field {
                name: name.into(),
                components,
                values,
            })
            .collect()
    }
}

/// Nodes (x, y, z) and cells (node lists in VTK's order); the cell type follows from the node
/// count and the dimension: 1 vertex, 2 line, 3 triangle, 4 quad (2-D) or tetrahedron (3-D),
/// 8 hexahedron.
#[derive(Clone, Debug)]
pub struct CellMesh {
    /// Node coordinates (z = 0 in 2-D).
    pub points: Vec<[f64; 3]>,
    /// Cells.
    pub cells: Vec<Vec<usize>>,
    /// 2 or 3.
    pub dim: usize,
}

impl CellMesh {
    /// The mesh of a scene's `"nodes"`: its cells, or one vertex per node without them.
    pub fn of_nodes(nodes: &Nodes) -> CellMesh {
        let points = nodes
            .coordinates
            .iter()
            .map(|c| [c[0], c[1], c.get(2).copied().unwrap_or(0.0)])
            .collect();
        let cells = if nodes.cells.is_empty() {
            (0..nodes.coordinates.len()).map(|k| vec![k]).collect()
        } else {
            nodes.cells.clone()
        };
        let dim = nodes.coordinates.first().map_or(2, Vec::len);
        CellMesh { points, cells, dim }
    }

    /// The Q4 mesh of `grid` (node (i, j) at (xs\[i\], ys\[j\]), index [`Grid::node`]).
    pub fn of_grid(grid: &Grid) -> CellMesh {
        let (nx, ny) = (grid.xs.len(), grid.ny());
        let points = (0..nx)
            .flat_map(|i| (0..ny).map(move |j| (i, j)))
            .map(|(i, j)| [grid.xs[i], grid.ys[j], 0.0])
            .collect();
        let mut cells = Vec::with_capacity(nx.saturating_sub(1) * ny.saturating_sub(1));
        for i in 0..nx.saturating_sub(1) {
            for j in 0..ny.saturating_sub(1) {
                cells.push(vec![
                    grid.node(i, j),
                    grid.node(i + 1, j),
                    grid.node(i + 1, j + 1),
                    grid.node(i, j + 1),
                ]);
            }
        }
        CellMesh {
            points,
            cells,
            dim: 2,
        }
    }

    fn cell_type(&self, len: usize) -> Result<CellType> {
        Ok(match (len, self.dim) {
            (1, _) => CellType::Vertex,
            (2, _) => CellType::Line,
            (3, _) => CellType::Triangle,
            (4, 2) => CellType::Quad,
            (4, _) => CellType::Tetra,
            (8, _) => CellType::Hexahedron,
            _ => {
                return Err(Error::unsupported(
                    format!("a VTK cell of {len} nodes"),
                    "1, 2, 3, 4 or 8 nodes",
                ))
            }
        })
    }
}

/// Creates `dir` if needed and refuses one that holds `.vtu` files already (a second run
/// into it would mix two runs' files).
pub fn check_empty_dir(dir: &Path) -> Result<()> {
    if dir.exists() {
        let entries = std::fs::read_dir(dir)
            .map_err(|e| Error::io(dir.display(), format!("cannot read the folder: {e}")))?;
        for e in entries.flatten() {
            if e.path().extension().is_some_and(|x| x == "vtu") {
                return Err(Error::io(
                    dir.display(),
                    "holds .vtu files of another run: choose an empty folder or remove them",
                ));
            }
        }
        return Ok(());
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| Error::io(dir.display(), format!("cannot create the folder: {e}")))
}

/// Writes `mesh` with the node fields `fields` to `path` (`.vtu`), atomically. Errors: a
/// field whose length is not `components × nodes`, a cell naming a node out of range, and
/// I/O (naming the file).
pub fn write_vtu(path: &Path, title: &str, mesh: &CellMesh, fields: Vec<Field>) -> Result<()> {
    let n = mesh.points.len();
    for f in &fields {
        if f.values.len() != f.components * n {
            return Err(Error::length_mismatch(
                format!("VTK field `{}`", f.name),
                f.values.len(),
                f.components * n,
            ));
        }
    }
    if let Some(bad) = mesh.cells.iter().flatten().find(|&&k| k >= n) {
        return Err(Error::out_of_range(
            "VTK cell node",
            bad,
            format!("< {n} nodes"),
        ));
    }
    let connectivity: Vec<u64> = mesh.cells.iter().flatten().map(|&k| k as u64).collect();
    let offsets = mesh
        .cells
        .iter()
        .scan(0u64, |end, c| {
            *end += c.len() as u64;
            Some(*end)
        })
        .collect();
    let types = mesh
        .cells
        .iter()
        .map(|c| mesh.cell_type(c.len()))
        .collect::<Result<Vec<_>>>()?;
    let point = fields
        .into_iter()
        .map(|f| {
            let elem = match f.components {
                3 => ElementType::Vectors,
                c => ElementType::Scalars {
                    num_comp: c as u32,
                    lookup_table: None,
                },
            };
            Attribute::DataArray(DataArray {
                name: f.name,
                elem,
                data: f.values.into(),
            })
        })
        .collect();
    let vtk = Vtk {
        version: Version::new(),
        title: title.to_string(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: mesh
                .points
                .iter()
                .flatten()
                .copied()
                .collect::<Vec<f64>>()
                .into(),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity,
                    offsets,
                },
                types,
            },
            data: Attributes {
                point,
                cell: Vec::new(),
            },
        }),
    };
    let mut bytes = Vec::new();
    vtk.write_xml(&mut bytes)
        .map_err(|e| Error::io(path.display(), format!("cannot encode VTK: {e}")))?;
    crate::provenance::write_atomic(path, &bytes)
}

/// The fields of a solved single-body indentation (module doc): `u` from the free unknowns
/// `u_free` and the prescribed values of `base` at the scene's lift; `contact_pressure`,
/// `gap` and `contact_node` at the top nodes the rows act on. `pressures` as
/// `Indentation::pressures` gives them, one per row. Errors where the scene's rows are not
/// one per top node, in order (two bodies, rows of other shapes).
pub fn indentation_fields(
    grid: &Grid,
    base: Base,
    scene: &Indentation,
    u_free: &[f64],
    pressures: &[f64],
) -> Result<Vec<Field>> {
    let nodes = grid.nodes();
    let fixed = elasticity::prescribed(grid, base, scene.lift);
    let free_count = fixed.iter().filter(|f| f.is_none()).count();
    if free_count != u_free.len() || scene.n_free != u_free.len() {
        return Err(Error::length_mismatch(
            "VTK output: free unknowns of the scene",
            u_free.len(),
            free_count,
        ));
    }
    // The free unknowns in DOF order (as `elasticity::eliminate` numbers them).
    let mut free = u_free.iter();
    let mut u = vec![0.0; 3 * nodes];
    for (d, f) in fixed.iter().enumerate() {
        u[3 * (d / 2) + d % 2] = f.or_else(|| free.next().copied()).unwrap_or(f64::NAN);
    }
    let m = scene.problem.m();
    let top = grid.ny() - 1;
    if m != grid.xs.len() || pressures.len() != m || scene.contact.len() != m {
        return Err(Error::unsupported(
            "VTK output of this scene",
            "one contact row per top node of a single body",
        ));
    }
    let (mut p, mut gap, mut flag) = (vec![0.0; nodes], vec![f64::NAN; nodes], vec![0.0; nodes]);
    for (c, node) in scene.contact.iter().enumerate() {
        if (node.x - grid.xs[c]).abs() > 1e-12 * grid.xs.last().copied().unwrap_or(1.0) {
            return Err(Error::unsupported(
                "VTK output of this scene",
                "contact rows in the order of the top nodes",
            ));
        }
        let k = grid.node(c, top);
        p[k] = pressures[c];
        gap[k] = clearance(&scene.problem, c, u_free);
        flag[k] = 1.0;
    }
    Ok(Field::set([
        ("u", 3, u),
        ("contact_pressure", 1, p),
        ("gap", 1, gap),
        ("contact_node", 1, flag),
    ]))
}

/// The clearance of row `c` at `u` (module doc's `gap`,
/// [`crate::system::ConstraintKind::clearance`]).
fn clearance(p: &Problem, c: usize, u: &[f64]) -> f64 {
    let con = &p.constraints[c];
    con.kind.clearance(con.gap(u))
}

/// The fields of a solved scene with `"nodes"`: `u` (the node's DOFs as its first components,
/// padded to 3), `contact_force` (the force the rows exert on the node, `−Σ_c r_c d_c` over
/// its DOFs, padded to 3; r the row forces with `K u = q − D r`), `gap` (the smallest
/// clearance of the rows acting on the node, NaN where none does) and `contact_node`.
pub fn scene_fields(p: &Problem, nodes: &Nodes, u: &[f64], forces: &[f64]) -> Result<Vec<Field>> {
    let (n, m, k) = (p.n(), p.m(), nodes.dofs_per_node);
    if u.len() != n || forces.len() != m {
        return Err(Error::length_mismatch(
            "VTK output: u and the row forces",
            u.len() + forces.len(),
            n + m,
        ));
    }
    if k > 3 {
        return Err(Error::unsupported(
            format!("VTK output of {k} DOFs per node"),
            "at most 3 (displacement components)",
        ));
    }
    let count = nodes.coordinates.len();
    let mut f = vec![0.0; n];
    let (mut gap, mut flag) = (vec![f64::NAN; count], vec![0.0; count]);
    for (c, r) in forces.iter().enumerate() {
        let g = clearance(p, c, u);
        for &(d, a) in &p.constraints[c].terms {
            f[d] -= r * a;
            let node = d / k;
            // NaN (no row yet) gives way to g.
            gap[node] = gap[node].min(g);
            flag[node] = 1.0;
        }
    }
    let pad = |v: &[f64]| -> Vec<f64> {
        (0..count)
            .flat_map(|i| (0..3).map(move |j| if j < k { v[i * k + j] } else { 0.0 }))
            .collect()
    };
    Ok(Field::set([
        ("u", 3, pad(u)),
        ("contact_force", 3, pad(&f)),
        ("gap", 1, gap),
        ("contact_node", 1, flag),
    ]))
}

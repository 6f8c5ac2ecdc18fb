//! `contact_bench --vtk DIR`: one `.vtu` per solved row of a single-body case
//! ([`crate::vtk`]).

use super::{BenchRow, Mesh};
use crate::error::Result;
use crate::model::elasticity::Indentation;

/// Writes one solved job of a single-body case as `.vtu` into `dir` ([`crate::vtk`]): the file
/// `<case>_h<h>_<method>[_<knob><value>].vtu`; nothing for the other cases.
pub(crate) fn write(
    dir: &std::path::Path,
    mesh: &Mesh,
    row: &BenchRow,
    scene: &Indentation,
    u: &[f64],
    p: &[f64],
) -> Result<()> {
    let Some(base) = mesh.case.vtk_base() else {
        return Ok(());
    };
    let knob = row
        .knob_value
        .map_or(String::new(), |v| format!("_{}{v:e}", row.knob));
    let name = format!("{}_h{}_{}{knob}.vtu", row.case, row.h, row.method);
    let fields = crate::vtk::indentation_fields(mesh.grid, base, scene, u, p)?;
    let title = format!("penalty-lab contact_bench {name}");
    crate::vtk::write_vtu(
        &dir.join(name),
        &title,
        &crate::vtk::CellMesh::of_grid(mesh.grid),
        fields,
    )
}

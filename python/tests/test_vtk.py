"""`contact_bench --vtk DIR` read back by meshio (an independent VTK reader): the Hertz
case's .vtu files open, and u and the contact pressure sit on the right nodes — the pressure
at every top node equals the run's own profile, the gap there is the indenter's clearance
x²/(2R) − u_y from the file's u, and the base nodes carry the lift."""

import json
import subprocess

import numpy as np
import pytest

meshio = pytest.importorskip("meshio")


def test_hertz_vtu_opens_in_meshio_with_u_and_pressure_on_the_right_nodes(tmp_path, cli_binary):
    exe = cli_binary("contact_bench")
    vtk = tmp_path / "vtk"
    out = subprocess.run(
        [exe, "--cases", "hertz-plane", "--meshes", "0.2", "--methods", "lagrange,condensed",
         "--deltas-rel", "1e-3", "--quiet", "--json", "--vtk", str(vtk),
         "--out", str(tmp_path / "run")],
        check=True, capture_output=True, text=True).stdout
    rec = json.loads(out)
    rows = rec["rows"]
    assert len(list(vtk.glob("*.vtu"))) == len(rows)
    for row in rows:
        rule = row["method"]
        pattern = f"hertz-plane_h{row['h']}_{rule}" + ("" if row["knob_value"] is None else "_*")
        (path,) = vtk.glob(pattern + ".vtu")
        mesh = meshio.read(path)
        pts, u = mesh.points, mesh.point_data["u"]
        p, gap = mesh.point_data["contact_pressure"], mesh.point_data["gap"]
        assert mesh.cells[0].type == "quad"
        prof = [q for q in rec["profiles"]
                if q["rule"] == rule and q.get("knob_rel") == row.get("knob_rel")]
        assert prof, row["method"]
        px, pp = np.array(prof[0]["x"]), np.array(prof[0]["p"])
        top = pts[:, 1] == pts[:, 1].max()
        xs = pts[top, 0]
        order = np.argsort(xs)
        np.testing.assert_array_equal(xs[order], px)
        np.testing.assert_array_equal(p[top][order], pp)
        clearance = pts[top, 0] ** 2 / (2 * row["radius"]) - u[top, 1]
        np.testing.assert_allclose(gap[top], clearance, rtol=0, atol=1e-12 * np.abs(u).max())
        assert np.all(p[~top] == 0) and np.all(np.isnan(gap[~top]))
        base = pts[:, 1] == 0
        np.testing.assert_array_equal(u[base, 1], row["lift"])
        np.testing.assert_array_equal(u[base, 0], 0.0)

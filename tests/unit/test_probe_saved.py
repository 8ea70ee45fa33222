"""`sphfem probe` on saved output: a linear field on a distorted, moving quad mesh and hex mesh is
interpolated exactly (bilinear / trilinear shape functions reproduce it), a cell field is its element's
value, SPH is the Shepard kernel interpolation (exact for a constant, and for a linear field at a point
of lattice symmetry), a point the mesh leaves reads NaN, and the CLI's table is the run's to remove."""
from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main
from sphfem_cli.output import GridStep, XdmfWriter
from sphfem_cli.output.folder import clear_earlier_run, write_manifest
from sphfem_cli.output.probe import ProbeError, probe


def _quads(nx=4, ny=3):
    x, y = np.meshgrid(np.linspace(0.0, 1.0, nx + 1), np.linspace(0.0, 0.6, ny + 1), indexing="ij")
    nodes = np.column_stack([x.ravel(), y.ravel()])
    nodes[:, 0] += 0.05 * np.sin(3.0 * nodes[:, 1])  # distorted, still convex
    nodes[:, 1] += 0.04 * np.cos(2.0 * nodes[:, 0])
    idx = np.arange(len(nodes)).reshape(nx + 1, ny + 1)
    conn = np.array([[idx[i, j], idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]] for i in range(nx) for j in range(ny)])
    return nodes, conn


def _hexes(n=2):
    g = np.linspace(0.0, 1.0, n + 1)
    x, y, z = np.meshgrid(g, g, g, indexing="ij")
    nodes = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    nodes += 0.03 * np.sin(4.0 * nodes[:, [1, 2, 0]])
    idx = np.arange(len(nodes)).reshape(n + 1, n + 1, n + 1)
    conn = []
    for i in range(n):
        for j in range(n):
            for k in range(n):
                conn.append([idx[i, j, k], idx[i + 1, j, k], idx[i + 1, j + 1, k], idx[i, j + 1, k],
                             idx[i, j, k + 1], idx[i + 1, j, k + 1], idx[i + 1, j + 1, k + 1], idx[i, j + 1, k + 1]])
    return nodes, np.array(conn)


def _linear(x, t):
    return 2.0 + 3.0 * x[:, 0] - 1.5 * x[:, 1] + 10.0 * t


def _write(run, t_values=(0.0, 1.0, 2.0)):
    nodes, conn = _quads()
    hx, hconn = _hexes()
    g = np.arange(-3, 4) * 0.1
    px, py = np.meshgrid(g, g, indexing="ij")
    particles = np.column_stack([px.ravel() + 5.0, py.ravel()])
    run.mkdir()
    (run / "deck.effective.yaml").write_text("sections: {fluid: {type: sph, kernel: cubic_spline}}\n")
    with XdmfWriter(run) as w:
        w.add_grid("plate", "Quadrilateral", conn, len(nodes))
        w.add_grid("block", "Hexahedron", hconn, len(hx))
        w.add_grid("water", "Polyvertex", None, len(particles))
        for t in t_values:
            moved = nodes + np.array([0.02 * t, 0.0])  # the plate slides in +x
            cells = np.arange(len(conn), dtype=float) + t
            stress = np.tile(np.arange(6.0), (len(conn), 1))
            hmoved = hx + np.array([0.0, 0.0, 0.1 * t])
            w.write_step(t, {
                "plate": GridStep(moved, {"temperature": _linear(moved, t), "velocity": np.column_stack(
                    [_linear(moved, t), -_linear(moved, t)])}, {"plastic_strain": cells, "stress": stress}),
                "block": GridStep(hmoved, {"temperature": 1.0 + hmoved @ np.array([1.0, 2.0, 3.0]) + t}),
                "water": GridStep(particles, {"pressure": 7.0 + particles[:, 0] - 5.0 + t,
                                              "mass": np.full(len(particles), 10.0),
                                              "density": np.full(len(particles), 1000.0),
                                              "smoothing_length": np.full(len(particles), 0.12)}),
            })
    return nodes, conn


def test_mesh_fields_at_a_point_over_time(tmp_path):
    run = tmp_path / "run"
    nodes, conn = _write(run)
    point = (0.37, 0.29)
    table = probe(run, point, "temperature", part="plate")
    assert table.columns == ["time", "temperature"]
    x = np.array([point])
    for t, v in table.rows:
        assert v == pytest.approx(_linear(x, t)[0], rel=1e-12)
    vel = probe(run, point, "velocity", part="plate")
    assert vel.columns == ["time", "velocity_x", "velocity_y", "velocity_z"]
    assert np.allclose(vel.rows[:, 1], -vel.rows[:, 2]) and np.all(vel.rows[:, 3] == 0.0)
    stress = probe(run, point, "stress")
    assert stress.columns[1:] == [f"stress_{c}" for c in ("xx", "yy", "zz", "xy", "yz", "zx")]
    assert np.allclose(stress.rows[:, 1:], np.arange(6.0))  # back in the code's order
    cells = probe(run, (0.01, 0.06), "plastic_strain")
    assert np.allclose(cells.rows[:, 1], [0.0, np.nan, np.nan], equal_nan=True)  # element 0, then the plate left
    block = probe(run, (0.4, 0.55, 0.3), "temperature", part="block")
    p = np.array([0.4, 0.55, 0.3])
    assert np.allclose(block.rows[:, 1], 1.0 + p @ [1.0, 2.0, 3.0] + block.rows[:, 0], rtol=1e-12)


def test_particles_by_kernel_interpolation(tmp_path):
    run = tmp_path / "run"
    _write(run)
    table = probe(run, (5.0, 0.0), "pressure")
    assert table.part == "water"
    assert np.allclose(table.rows[:, 1], 7.0 + table.rows[:, 0], rtol=1e-12)  # symmetric point: exact
    off = probe(run, (5.05, 0.05), "pressure")
    assert np.all(np.abs(off.rows[:, 1] - (7.05 + off.rows[:, 0])) < 0.01)
    with pytest.raises(ProbeError, match="lies in none of the parts"):
        probe(run, (9.0, 9.0), "pressure")
    with pytest.raises(ProbeError, match="no field 'vorticity'"):
        probe(run, (5.0, 0.0), "vorticity")


def test_cli_writes_a_table_the_run_owns(tmp_path):
    run = tmp_path / "run"
    _write(run)
    write_manifest(run, [], "0" * 64, ["plate", "block", "water"])
    result = CliRunner().invoke(main, ["probe", str(run), "--point", "5,0", "--quantity", "pressure"])
    assert result.exit_code == 0, result.output
    csv = run / "probes" / "probe_pressure.csv"
    assert csv.read_text().startswith("# sphfem probe: pressure at 5,0 in part water")
    rows = np.loadtxt(csv, delimiter=",", skiprows=2)
    assert rows.shape == (3, 2)
    result = CliRunner().invoke(main, ["probe", str(run), "--point", "5,0", "--quantity", "nothing"])
    assert result.exit_code == 2 and "no field 'nothing'" in result.output
    clear_earlier_run(run)
    assert not (run / "probes").exists()

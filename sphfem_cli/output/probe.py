"""``sphfem probe RUN --point X,Y[,Z] --quantity Q``: a saved run's field at a point, over time
(as DualSPHysics' MeasureTool does on its saved output), written as a history table.

At each saved step (results.h5, output.xdmf's layout), in the part that holds the point:

- a mesh part (FEM solid, ALE): the element whose shape holds the point at that step (the mesh
  moves), found by inverting its isoparametric map x(ξ) = Σ_a N_a(ξ) x_a by Newton's method
  (quad4 bilinear, hex8 trilinear, node order of docs/architecture.md); a point field is
  q = Σ_a N_a(ξ) q_a, a cell field the element's value;
- a particle part (SPH): the Shepard-normalised kernel interpolation
  q(x) = Σ_j V_j q_j W(|x − x_j|, h_j) / Σ_j V_j W(|x − x_j|, h_j), V_j = m_j / ρ_j, over the active
  particles (the deck's kernel; sph.reference.kernel_w), which needs mass, density and
  smoothing_length among the saved fields (saved by default). NaN where no particle reaches x.

With a sensor diameter (``--sensor-diameter``, ``--normal``) the value is the mean over the sensor's
face, disc or ball by the quadrature rule of model/sensors.py, as the run's pressure probes with a
``sensor`` take it; with ``--filter`` each column is followed by its low-passed copy
``<column>_filtered`` (output/filters.py), the raw column kept.

Values are NaN at steps where the point lies outside the part (it left the mesh, or no particle is
within 2h). Vectors give ``Q_x, Q_y[, Q_z]`` columns, symmetric tensors ``Q_xx … Q_zx`` in the code's
order (xx, yy, zz, xy, yz, zx), scalars ``Q``.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import h5py
import numpy as np

from ..model.sensors import sensor_mean, sensor_points
from .filters import low_pass
from .xdmf import TENSOR6_XDMF_ORDER

CODE_ORDER = np.argsort(TENSOR6_XDMF_ORDER)  # XDMF Tensor6 -> xx, yy, zz, xy, yz, zx
TENSOR = ("xx", "yy", "zz", "xy", "yz", "zx")
SIGNS = {4: [(-1, -1), (1, -1), (1, 1), (-1, 1)],
         8: [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]}


class ProbeError(ValueError):
    """A probe that cannot be taken (unknown part or quantity, a point outside every part)."""


@dataclass
class ProbeTable:
    part: str
    columns: list[str]
    rows: np.ndarray  # (steps, 1 + components): time, values

    def write(self, path: Path, header: str) -> Path:
        path.parent.mkdir(parents=True, exist_ok=True)
        with path.open("w", encoding="utf-8") as f:
            f.write(f"# sphfem probe: {header}\n")
            f.write(",".join(self.columns) + "\n")
            np.savetxt(f, self.rows, delimiter=",", fmt="%.10e")
        return path


def shape_functions(xi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """N_a(ξ) (n,) and dN_a/dξ (n, dim) of the bilinear quad (dim 2) or trilinear hex (dim 3)."""
    dim = len(xi)
    signs = np.array(SIGNS[2 ** dim], dtype=float)
    terms = 1.0 + signs * xi  # (n, dim)
    n = np.prod(terms, axis=1) / 2 ** dim
    dn = np.empty_like(signs)
    for d in range(dim):
        others = np.prod(np.delete(terms, d, axis=1), axis=1)
        dn[:, d] = signs[:, d] * others / 2 ** dim
    return n, dn


def parametric(corners: np.ndarray, x: np.ndarray, iterations: int = 25) -> np.ndarray | None:
    """ξ with Σ N_a(ξ) x_a = x for one element's corners (n, dim), or None if Newton does not converge."""
    xi = np.zeros(corners.shape[1])
    for _ in range(iterations):
        n, dn = shape_functions(xi)
        r = n @ corners - x
        jac = corners.T @ dn  # dx/dξ
        try:
            step = np.linalg.solve(jac, r)
        except np.linalg.LinAlgError:
            return None
        xi -= step
        if np.max(np.abs(step)) < 1e-12:
            return xi
        if np.max(np.abs(xi)) > 10.0:
            return None
    return xi


def _locate(coordinates: np.ndarray, connectivity: np.ndarray, x: np.ndarray) -> tuple[int, np.ndarray] | None:
    """(element, ξ) of the element holding x (within 1e-9 of its parametric cube), or None."""
    corners = coordinates[connectivity]  # (E, n, dim)
    lo, hi = corners.min(axis=1), corners.max(axis=1)
    span = np.max(hi - lo)
    near = np.nonzero(np.all((x >= lo - 1e-9 * span) & (x <= hi + 1e-9 * span), axis=1))[0]
    for e in near:
        xi = parametric(corners[e], x)
        if xi is not None and np.max(np.abs(xi)) <= 1.0 + 1e-9:
            return int(e), np.clip(xi, -1.0, 1.0)
    return None


def _components(name: str, stored: np.ndarray) -> tuple[list[str], np.ndarray]:
    """Column names and values in the code's order of a stored field (rows: points or cells)."""
    if stored.ndim == 1:
        return [name], stored[:, None]
    if stored.shape[1] == 6:
        return [f"{name}_{c}" for c in TENSOR], stored[:, CODE_ORDER]
    return [f"{name}_{a}" for a in "xyz"[: stored.shape[1]]], stored


def _kernel(run: Path) -> str:
    import yaml

    eff = run / "deck.effective.yaml"
    data = yaml.safe_load(eff.read_text()) if eff.exists() else {}
    for section in (data.get("sections") or {}).values():
        if isinstance(section, dict) and section.get("type") == "sph":
            return section.get("kernel", "cubic_spline")
    return "cubic_spline"


def _fields(step: h5py.Group) -> dict[str, tuple[str, h5py.Dataset]]:
    out = {}
    for center in ("point", "cell"):
        if center in step:
            out.update({name: (center, ds) for name, ds in step[center].items()})
    return out


def probe(run: Path, point: Sequence[float], quantity: str, part: str | None = None, sensor: float = 0.0,
          normal: Sequence[float] | None = None, filtering: dict | None = None) -> ProbeTable:
    """The history of ``quantity`` at ``point`` in a saved run (see the module docstring); with a
    ``sensor`` diameter the mean over the sensor (:func:`_sensor_value`), with ``filtering``
    (output.filters.low_pass settings) a ``<column>_filtered`` column after each raw one."""
    table = _probe(run, point, quantity, part, sensor, normal)
    if filtering is None:
        return table
    raw = table.rows[:, 1:]
    columns, rows = ["time"], [table.rows[:, 0]]
    for j, name in enumerate(table.columns[1:]):
        try:
            filtered = low_pass(table.rows[:, 0], raw[:, j], **filtering)
        except ValueError as err:
            raise ProbeError(f"cannot filter {name}: {err}") from None
        columns += [name, f"{name}_filtered"]
        rows += [raw[:, j], filtered]
    return ProbeTable(table.part, columns, np.column_stack(rows))


def _probe(run: Path, point: Sequence[float], quantity: str, part: str | None, sensor: float,
           normal: Sequence[float] | None) -> ProbeTable:
    run = Path(run)
    h5_path = run / "results.h5"
    if not h5_path.exists():
        raise ProbeError(f"{run}: no results.h5 (not a run folder)")
    with h5py.File(h5_path, "r", locking=False) as f:
        times = f["times"][()]
        grids = [g for g in f if g not in ("times", "histories")]
        if part is not None and part not in grids:
            raise ProbeError(f"no part '{part}' in {h5_path}; parts: {', '.join(grids)}")
        steps = [f"step_{i:06d}" for i in range(len(times))]
        candidates = [part] if part else grids
        having = [g for g in candidates if steps and steps[0] in f[g] and quantity in _fields(f[g][steps[0]])]
        if not having:
            known = sorted({q for g in candidates if steps and steps[0] in f[g] for q in _fields(f[g][steps[0]])})
            raise ProbeError(f"no field '{quantity}' saved in {'part ' + part if part else 'any part'}; "
                             f"saved: {', '.join(known)}")
        first = steps[0]
        dim3 = np.asarray(point, dtype=float)
        x = np.zeros(3)
        x[: len(dim3)] = dim3
        kernel = _kernel(run)
        if sensor > 0.0 and normal is not None and len(normal) != len(dim3):
            raise ProbeError(f"the normal has {len(normal)} components, the point {len(dim3)}")
        samples = _samples(dim3, sensor, normal)
        chosen = next((g for g in having if _value(f[g], first, quantity, x, kernel) is not None), None)
        if chosen is None:
            raise ProbeError(f"the point {tuple(point)} lies in none of the parts with '{quantity}' "
                             f"({', '.join(having)}) at t = {times[0]:g}")
        columns, rows = None, []
        for t, s in zip(times, steps):
            if s not in f[chosen]:
                continue
            value = (_value(f[chosen], s, quantity, x, kernel) if samples is None
                     else _sensor_value(f[chosen], s, quantity, samples, kernel))
            if value is None:
                names, _ = _components(quantity, _fields(f[chosen][first])[quantity][1][:1])
                value = (names, np.full(len(names), np.nan))
            columns = columns or value[0]
            rows.append([t, *value[1]])
    return ProbeTable(chosen, ["time", *columns], np.array(rows))


def _samples(point: np.ndarray, diameter: float, normal) -> tuple[np.ndarray, np.ndarray] | None:
    """The sensor's sample points padded to 3 components and their weights (model.sensors), or None."""
    if diameter <= 0.0:
        return None
    pts, weights = sensor_points(point, diameter, normal)
    padded = np.zeros((len(pts), 3))
    padded[:, : pts.shape[1]] = pts
    return padded, weights


def _sensor_value(grid: h5py.Group, step: str, quantity: str, samples, kernel: str):
    """The weighted mean over the sensor's sample points (model.sensors). A point outside the part
    reads 0 for a pressure (the dry part of a transducer's face, as the run's probes do); for other
    quantities it is left out and the weights of the others renormalised. None if no point is inside."""
    points, weights = samples
    values, names, inside = [], None, []
    for x in points:
        v = _value(grid, step, quantity, x, kernel)
        inside.append(v is not None)
        if v is not None:
            names = v[0]
            values.append(v[1])
        else:
            values.append(None)
    if names is None:
        return None
    width = len(names)
    stack = np.array([v if v is not None else np.full(width, np.nan) for v in values])
    if quantity.startswith("pressure"):
        return names, sensor_mean_rows(stack, weights)
    w = weights * np.array(inside)
    return names, (w @ np.nan_to_num(stack)) / w.sum()


def sensor_mean_rows(values: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Column-wise :func:`model.sensors.sensor_mean` of (points, components) values."""
    return np.array([sensor_mean(values[:, j], weights) for j in range(values.shape[1])])


def _value(grid: h5py.Group, step: str, quantity: str, x: np.ndarray, kernel: str):
    """(column names, values) of ``quantity`` at ``x`` in one grid at one step, or None outside it."""
    group = grid[step]
    fields = _fields(group)
    center, ds = fields[quantity]
    xyz = group["coordinates"][()]
    if grid.attrs["topology"] == "Polyvertex":
        return _particles(group, fields, ds[()], xyz, x, quantity, kernel)
    conn = grid["connectivity"][()]
    dim = 3 if conn.shape[1] == 8 else 2
    hit = _locate(xyz[:, :dim], conn, x[:dim])
    if hit is None:
        return None
    e, xi = hit
    values = ds[()]
    names, comp = _components(quantity, values)
    if center == "cell":
        return names, comp[e]
    n, _ = shape_functions(xi)
    return names, n @ comp[conn[e]]


def _particles(group, fields, values, xyz, x, quantity, kernel):
    from ..sph.reference import kernel_w
    from ..sph.system import KERNELS

    need = [q for q in ("mass", "density", "smoothing_length") if q not in fields]
    if need:
        raise ProbeError(f"the run saved no {', '.join(need)} for its particles: add them to output.fields")
    m, rho, h = (fields[q][1][()] for q in ("mass", "density", "smoothing_length"))
    active = fields["active"][1][()] > 0 if "active" in fields else np.ones(len(m), bool)
    dim = 2 if np.all(xyz[:, 2] == 0.0) and x[2] == 0.0 else 3
    r = np.linalg.norm(xyz[:, :dim] - x[:dim], axis=1)
    near = active & (r < 2.0 * h)
    if not near.any():
        return None
    w = (m[near] / rho[near]) * kernel_w(KERNELS[kernel], dim, r[near], h[near])
    if w.sum() <= 0.0:
        return None
    names, comp = _components(quantity, values)
    return names, (w @ comp[near]) / w.sum()

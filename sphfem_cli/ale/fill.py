"""Initial state of an ALE fluid: material fractions of regions, and the extensive per-material
state (volume, mass, internal energy per element and material) from fractions, densities and
energies or pressures.

Numpy, and one small kernel for the sample points of large quad4 fills (model/ uses ``fill_fractions``
while it builds the ALE mesh; ``AleSystem`` the rest).
"""
from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from numba import njit

from ..materials import slots as ms


def fill_fractions(nodes: np.ndarray, conn: np.ndarray, inside_fn: Callable, samples: int = 3,
                   points: tuple | None = None, ring: bool = False) -> np.ndarray:
    """Fraction of each quad4 (hex8) inside a region, by samples^2 (samples^3) points per element.

    ``inside_fn(x, y)`` (``inside_fn(x, y, z)`` in 3D) takes coordinate arrays and returns a
    boolean array. Sample points are the bilinear (trilinear) images of the midpoints of a
    samples^dim grid on the reference square (cube), each weighted by the Jacobian there, so the
    result is the exact fraction for a region made of whole sub-cells of a parallelogram
    (parallelepiped) element. ``points``: ``quad_sample_points(nodes, conn, samples)`` of a quad4
    mesh, computed once for several regions of it. ``ring``: the quad4 is the meridian section of a
    ring (x = r, ``dimension: axisymmetric``) and the fraction is one of the ring's volume,
    dV = 2 pi r dA: each point's weight is J r (by area alone a charge two elements in radius on
    the axis was filled 4 % heavy).
    """
    if np.shape(conn)[1] == 8:
        return _fill_fractions_3d(np.asarray(nodes, dtype=float), np.asarray(conn), inside_fn, samples)
    nodes = np.ascontiguousarray(nodes, dtype=np.float64)
    conn = np.ascontiguousarray(conn, dtype=np.int64)
    out = np.empty(len(conn))
    # by chunks of elements: the samples^2 points of a chunk stay small and reused (those of a 960^2
    # mesh at once were 200 MB of fresh memory, most of the set-up's time); every element's
    # fraction is the same either way
    for lo in range(0, len(conn), FILL_CHUNK):
        hi = min(lo + FILL_CHUNK, len(conn))
        if points is None:
            px, py, jac, jac_sum = quad_sample_points(nodes, conn[lo:hi], samples,
                                                      kernel=len(conn) > SAMPLES_KERNEL_ABOVE)
        else:
            px, py, jac, jac_sum = (a[lo:hi] for a in points)
        inside = np.asarray(inside_fn(px, py), dtype=bool)
        if ring:
            weight = jac * px
            out[lo:hi] = (weight * inside).sum(axis=1) / weight.sum(axis=1)
        else:
            out[lo:hi] = (jac * inside).sum(axis=1) / jac_sum
    return out


FILL_CHUNK = 1 << 14
"""Elements per chunk of ``fill_fractions`` (quad4): 16384 x 9 points, 1.2 MB per coordinate array."""


SAMPLES_KERNEL_ABOVE = 1 << 18
"""Meshes of more quad4 than this sample their points with the kernel ``_quad_samples`` (compiled once into numba's
cache), smaller ones in numpy (nothing to compile or load): the same bits. At 960^2 one fill's points cost 0.16-0.17 s
of user time in numpy against the kernel's 0.09-0.10 s (3 interleaved rounds in one process, load 7-8, 7 December
2026; the numpy passes by sample rows, 0.59-0.63 s before), about 75 ns more per element; loading the cached kernel
costs about 20 ms, compiling it 0.4-0.5 s: numpy is the cheaper up to about 2.6e5 elements on a warm cache."""


def quad_sample_points(nodes: np.ndarray, conn: np.ndarray, samples: int = 3, kernel: bool = False) -> tuple:
    """The samples^2 points of each quad4 of ``fill_fractions`` and their Jacobian weights:
    (x (E, S), y (E, S), J (E, S), sum of J over the points (E,)).

    x(s) = sum_a N_a(s) x_a and J = x_xi y_eta - x_eta y_xi, each sum over the corners a in order; in numpy, or
    with ``kernel`` by ``_quad_samples`` (the same operations: the same bits, tests/unit/test_setup_numpy.py).
    """
    t = (np.arange(samples) + 0.5) / samples * 2.0 - 1.0
    xi, eta = np.meshgrid(t, t, indexing="ij")
    xi = xi.ravel()
    eta = eta.ravel()
    sn = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
    shape = 0.25 * (1 + np.outer(xi, sn[:, 0])) * (1 + np.outer(eta, sn[:, 1]))  # (S, 4)
    dxi = 0.25 * sn[:, 0][None, :] * (1 + np.outer(eta, sn[:, 1]))
    deta = 0.25 * sn[:, 1][None, :] * (1 + np.outer(xi, sn[:, 0]))
    if kernel:
        px = np.empty((len(conn), len(xi)))
        py = np.empty_like(px)
        jac = np.empty_like(px)
        _quad_samples(np.ascontiguousarray(nodes, dtype=np.float64), np.ascontiguousarray(conn, dtype=np.int64),
                      shape, dxi, deta, px, py, jac)
        return px, py, jac, jac.sum(axis=1)
    nodes = np.asarray(nodes, dtype=np.float64)
    conn = np.asarray(conn, dtype=np.int64)
    n_elem, n = len(conn), samples
    cx = [nodes[conn[:, a], 0] for a in range(4)]  # (E,) each, contiguous
    cy = [nodes[conn[:, a], 1] for a in range(4)]
    # by sample rows (S, E): each pass an outer product, a weight times a contiguous corner column
    tmp = np.empty((n * n, n_elem))
    px, py = (np.ascontiguousarray(_corner_sum(shape, c, tmp).T) for c in (cx, cy))
    # d/dxi at point s = (i, j) (xi_i, eta_j) depends on j alone, d/deta on i alone: each distinct value once
    tmp = tmp[:n]
    x_xi, y_xi = (_corner_sum(dxi[:n], c, tmp) for c in (cx, cy))  # (n, E) over j
    x_eta, y_eta = (_corner_sum(deta[::n], c, tmp) for c in (cx, cy))  # (n, E) over i
    jac = np.empty((n_elem, n * n))
    row = np.empty(n_elem)
    for i in range(n):
        for j in range(n):
            np.multiply(x_xi[j], y_eta[i], out=row)
            row -= np.multiply(x_eta[i], y_xi[j], out=tmp[0])
            jac[:, i * n + j] = row
    return px, py, jac, jac.sum(axis=1)


def _corner_sum(weights: np.ndarray, corner: list, tmp: np.ndarray) -> np.ndarray:
    """sum_a weights[s, a] c_a (S, E) for weights (S, 4) and corner columns c_a (E,), the corners a added in order
    (elementwise: the same bits on every machine, and the kernel's); tmp (S, E) is scratch."""
    out = np.multiply.outer(weights[:, 0], corner[0])
    for a in range(1, 4):
        out += np.multiply.outer(weights[:, a], corner[a], out=tmp)
    return out


@njit(cache=True)
def _quad_samples(nodes, conn, shape, dxi, deta, px, py, jac):
    """Sample points (px, py) and Jacobians jac (E, S) of quad4 elements: x(s) = sum_a N_a(s) x_a and
    J = x_xi y_eta - x_eta y_xi, each sum taken over the corners a in order."""
    for e in range(conn.shape[0]):
        for s in range(shape.shape[0]):
            x = shape[s, 0] * nodes[conn[e, 0], 0]
            y = shape[s, 0] * nodes[conn[e, 0], 1]
            x_xi = dxi[s, 0] * nodes[conn[e, 0], 0]
            y_xi = dxi[s, 0] * nodes[conn[e, 0], 1]
            x_eta = deta[s, 0] * nodes[conn[e, 0], 0]
            y_eta = deta[s, 0] * nodes[conn[e, 0], 1]
            for a in range(1, 4):
                xa = nodes[conn[e, a], 0]
                ya = nodes[conn[e, a], 1]
                x += shape[s, a] * xa
                y += shape[s, a] * ya
                x_xi += dxi[s, a] * xa
                y_xi += dxi[s, a] * ya
                x_eta += deta[s, a] * xa
                y_eta += deta[s, a] * ya
            px[e, s] = x
            py[e, s] = y
            jac[e, s] = x_xi * y_eta - x_eta * y_xi


def _fill_fractions_3d(nodes: np.ndarray, conn: np.ndarray, inside_fn: Callable, samples: int) -> np.ndarray:
    """fill_fractions on hex8 (VTK corner order): samples^3 Jacobian-weighted points per element."""
    t = (np.arange(samples) + 0.5) / samples * 2.0 - 1.0
    xi = np.stack([g.ravel() for g in np.meshgrid(t, t, t, indexing="ij")], axis=1)  # (S, 3)
    sn = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                   [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
    lin = 1.0 + xi[:, None, :] * sn[None, :, :]  # (S, 8, 3) factors (1 + xi_k s_k)
    shape = 0.125 * lin.prod(axis=2)  # (S, 8)
    dshape = np.empty((3,) + shape.shape)  # dN/dxi_k
    for k in range(3):
        others = [j for j in range(3) if j != k]
        dshape[k] = 0.125 * sn[None, :, k] * lin[:, :, others[0]] * lin[:, :, others[1]]
    n_s = len(xi)
    out = np.empty(len(conn))
    chunk = max(1, 200_000 // n_s)
    for lo in range(0, len(conn), chunk):
        x = nodes[conn[lo:lo + chunk]]  # (e, 8, 3)
        corners = [[np.ascontiguousarray(x[:, a, k])[:, None] for k in range(3)] for a in range(8)]  # (e, 1) each
        # the map's values and derivatives at the points, corner by corner in corner order (elementwise numpy: the
        # same bits on every machine, which a matrix product through BLAS does not promise)
        pts = [sum(shape[:, a] * corners[a][k] for a in range(8)) for k in range(3)]  # x_k at s, (e, S)
        a = [[sum(dshape[j, :, c] * corners[c][k] for c in range(8)) for j in range(3)] for k in range(3)]
        # det(d x_k / d xi_j) by cofactors along the first row
        det = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
               - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
               + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
        inside = np.asarray(inside_fn(pts[0], pts[1], pts[2]), dtype=bool)
        out[lo:lo + chunk] = (det * inside).sum(axis=1) / det.sum(axis=1)
    return out


def energy_from_pressure(row: np.ndarray, rho: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Specific internal energy e with p_eos(rho, e) = p (every EOS here is linear in e):
    e = (p - p0(rho)) / (dp/de)(rho) / rho0, with p0 and dp/de the EOS at (rho / rho0, e = 0)
    (``materials.kernels.eos_state``, by ``materials.tables.eos_state_set_up``); e = 0 where dp/de = 0.

    The EOS is evaluated once per distinct density (a fill has one or a few; a hydrostatic one
    one per layer), the rest element-wise in the same order of operations as a scalar loop.
    """
    from ..materials.tables import eos_state_set_up  # the deck schema's models: not at this module's import
    rho = np.asarray(rho, dtype=float)
    p = np.asarray(p, dtype=float)
    eos = int(row[ms.P_EOS_TYPE])
    q = np.ascontiguousarray(row[ms.EOS_OFFSET:])
    rho0 = q[ms.Q_RHO0]
    shape = np.broadcast(rho, p).shape
    flat = np.broadcast_to(rho, shape).ravel()
    if len(flat) and (flat == flat[0]).all():  # one density (a fill without layers): no sort
        values, inverse = flat[:1], None
    else:
        values, inverse = np.unique(flat, return_inverse=True)
    p0 = np.empty(len(values))
    dpde = np.empty(len(values))
    for i, value in enumerate(values):
        p0[i], _, dpde[i] = eos_state_set_up(eos, q, float(value) / rho0, 0.0)
    if inverse is None:  # the same operations on scalars: the same bits, no gathered copies of p0 and dp/de
        if dpde[0] == 0.0:
            return np.zeros(shape)
        out = np.broadcast_to(p, shape) - p0[0]
        out /= dpde[0]
        out /= rho0
        return out
    p0, dpde = p0[inverse], dpde[inverse]
    out = np.zeros(len(inverse))
    live = dpde != 0.0
    out[live] = (np.broadcast_to(p, shape).ravel()[live] - p0[live]) / dpde[live] / rho0
    return out.reshape(shape)


def per_element(value, n_elem: int, n_mat: int, name: str) -> np.ndarray:
    """value (N,) broadcast to (E, N), or value (E, N) itself: a read-only view, not a copy."""
    arr = np.asarray(value, dtype=float)
    if arr.shape in ((n_mat,), (n_elem, n_mat)):
        return np.broadcast_to(arr, (n_elem, n_mat))
    raise ValueError(f"{name} must have shape ({n_mat},) or ({n_elem}, {n_mat}), got {arr.shape}")


def material_tables(materials: Sequence) -> tuple[np.ndarray, np.ndarray, np.ndarray, list]:
    """EOS tables of the materials: (eos (N,), EOS constants q (N, NQ), reference density (N,), rows).

    A material is a parameter row of ``materials.tables.pack_material`` (or its ``(type id, row)``
    pair), or None for void (eos -1: no mass, no pressure). rows: the rows, None for void.
    """
    n_mat = len(materials)
    mat_eos = np.full(n_mat, -1, dtype=np.int64)
    mat_q = np.zeros((n_mat, ms.NPARAM - ms.EOS_OFFSET))
    mat_rho0 = np.zeros(n_mat)
    rows = []
    for m, row in enumerate(materials):
        if isinstance(row, tuple):
            _, row = row  # (type id, parameter row)
        rows.append(row)
        if row is None:
            continue
        row = np.asarray(row, dtype=float)
        mat_eos[m] = int(row[ms.P_EOS_TYPE])
        mat_q[m] = row[ms.EOS_OFFSET:]
        mat_rho0[m] = row[ms.P_RHO0]
    return mat_eos, mat_q, mat_rho0, rows


def material_state(rows: list, vol0: np.ndarray, fractions, density, energy=None, pressure=None) -> tuple:
    """Extensive start state (vol_m, mass_m, ener_m), each (E, N), of elements of volume vol0 (E,).

    fractions (E, N) are normalised to sum 1 per element; density, energy (specific, per mass)
    and pressure are (N,) or (E, N); the energy follows from the pressure by the EOS
    (``energy_from_pressure``) when only the pressure is given, else it is 0. Void materials
    (rows[m] None) get no mass.
    """
    n_elem, n_mat = len(vol0), len(rows)
    fr = np.asarray(fractions, dtype=float)
    if fr.shape != (n_elem, n_mat):
        raise ValueError(f"fractions must be ({n_elem}, {n_mat}), got {fr.shape}")
    # (E, N) arrays only for the three results: the inputs are read in place (broadcast views, not copies; fresh
    # memory is the set-up's cost), each result the same elementwise operations as before, so the same bits
    vol_m = fr / fr.sum(axis=1, keepdims=True)
    vol_m *= vol0[:, None]
    rho = per_element(density, n_elem, n_mat, "density")
    mass_m = rho * vol_m
    for m in range(n_mat):
        if rows[m] is None:  # void: no mass
            mass_m[:, m] = 0.0
    ener_m = np.zeros((n_elem, n_mat))
    if energy is not None:
        np.multiply(mass_m, per_element(energy, n_elem, n_mat, "energy"), out=ener_m)
    elif pressure is not None:
        pr = per_element(pressure, n_elem, n_mat, "pressure")
        for m in range(n_mat):
            if rows[m] is not None:
                e = energy_from_pressure(np.asarray(rows[m], float), np.maximum(rho[:, m], 1e-300), pr[:, m])
                np.multiply(mass_m[:, m], e, out=ener_m[:, m])
    return vol_m, mass_m, ener_m


def inflow_state(eos: int, q: np.ndarray, rho0: float, density: float | None = None, energy: float | None = None,
                 pressure: float | None = None) -> tuple[float, float, float]:
    """(density, specific energy, pressure) of an inflowing material (``AleSystem.set_inflow``).

    density defaults to rho0; the specific energy is ``energy``, or the one giving ``pressure``
    (p = p0(rho) + dp/de rho0 e, every EOS here linear in e), or the EOS's e0 per reference
    volume over rho0 (as a fill).
    """
    from ..materials.tables import eos_state_set_up
    rho = rho0 if density is None else float(density)
    q = np.ascontiguousarray(q)
    p0, _, dpde = eos_state_set_up(int(eos), q, rho / rho0, 0.0)
    if energy is None and pressure is None:
        e = float(q[ms.Q_E0]) / rho0  # the EOS's e0 (per reference volume), as an initial fill
    elif energy is None:
        e = 0.0 if dpde == 0.0 else (float(pressure) - p0) / dpde / rho0
    else:
        e = float(energy)
    return rho, e, p0 + dpde * rho0 * e

"""``AleSystem``: a multi-material ALE (Eulerian by default) fluid on a quad4 (2D) or hex8 (3D) mesh.

Usage::

    from sphfem_cli.model.mesh import box_mesh
    from sphfem_cli.ale import AleSystem, fill_fractions

    mesh = box_mesh([0, 0], [1, 0.01], divisions=[100, 1])
    nodes, conn = mesh.nodes, mesh.elements
    left = fill_fractions(nodes, conn, lambda x, y: x < 0.5)      # (E,) fraction inside
    fr = np.stack([left, 1 - left], axis=1)                          # (E, N) per material
    ale = AleSystem(nodes, conn, materials=[row_a, row_b], fractions=fr,
                    density=[1.0, 0.125], pressure=[1.0, 0.1])
    ale.set_slip(bottom_nodes, normal=(0, 1)); ale.set_slip(top_nodes, normal=(0, 1)) ...
    while ale.time < t_end:
        ale.step(min(ale.stable_dt(0.5), t_end - ale.time))
    ale.totals(); ale.density(); ale.pressure(); ale.velocity

Constructor arguments:

- ``nodes`` (N, 2), ``conn`` (E, 4) counter-clockwise quad4 (``model.mesh.box_mesh`` order), or
  ``nodes`` (N, 3), ``conn`` (E, 8) hex8 in VTK order (``box_mesh`` in 3D): the same method with
  three sweep directions (docs/theory/ale.md, "3D"); a 3D smoothed mesh takes smoothing "average"
  with fixed boundary nodes only; vectors below have 3 components there;
- ``materials``: one entry per material, a parameter row of ``materials.tables.pack_material``
  (or its ``(type id, row)`` pair), or ``None`` for void (no mass, no pressure);
- ``fractions`` (E, N) initial volume fractions (rows summing to 1; see ``fill_fractions``);
- ``density`` (N,) or (E, N) initial material densities; ``energy`` specific internal energies
  [energy/mass] or ``pressure`` (the energy then follows from the EOS), each (N,) or (E, N);
- ``velocity`` (2,) or (N, 2) initial nodal velocity;
- ``q1``, ``q2`` quadratic and linear bulk-viscosity coefficients, ``hourglass`` viscous
  hourglass coefficient; ``order`` 1 (donor cell) or 2 (van Leer MUSCL) advection;
  ``interface`` "slic" (sharp, directional) or "donor" material-volume fluxes; ``closure``
  "relax" (pressure relaxation) or "equal_strain" for mixed elements, with ``relax_alpha``
  (0..1, fraction of the pressure difference removed per step) and ``relax_beta`` (largest
  relative volume loss of one material per step); ``advect_every`` remap every N steps (the
  mesh moves with the material in between); ``mesh_motion`` "eulerian" (the remap returns the
  mesh to its start), "lagrangian" (no remap: the mesh moves with the material) or "smooth"
  (``smooth_iterations`` passes moving interior nodes by ``smooth_weight`` towards their target,
  ``smoothing`` "average" (mean of their neighbours) or "equipotential" (Winslow), then
  ``eulerian_pull`` back towards their start; ``smooth_boundary`` "fixed" (boundary nodes
  Eulerian) or "sliding" (along straight sides, corners fixed));
  ``ke_fix`` return the kinetic energy lost by the
  momentum remap to the internal energy (total energy conserved);
  ``pressure_cutoff`` lowest material pressure (cavitation, LS-DYNA's *MAT_NULL PC; default none);
  ``mass_floor`` nodes whose mass is at or below this fraction of their full mass (their
  elements' reference volumes filled at the largest reference density) are held at zero velocity,
  their momentum booked with the wall impulse (default 1e-10: the gas front expanding into
  void, tests/verification/test_ale_void.py, moves within 0.1 cell of 1e-12's; 1e-8 holds it back
  3 cells).

Boundaries (node index arrays): ``set_slip(nodes, normal)`` normal velocity zero,
``set_fixed(nodes)`` velocity zero, ``set_transmit(nodes)`` boundary faces whose two nodes are in
the set are open (outflow / zero-gradient inflow, with the inside pressure applied outside),
``set_inflow(nodes, material, velocity, density, energy | pressure)`` inflow of a material at a
given state (ghost donor, prescribed nodal velocity).
Nodes in two slip sets with different normals become fixed (3D: they slide along the two walls'
intersection; a third wall makes them fixed).

Body force and structure coupling: ``gravity`` (2,) acceleration on the nodal masses;
``f_couple`` (N, 2) coupling forces of the step (contact.coupling), with their work accumulated
in ``gravity_work`` and ``coupling_work``; ``step(dt, couple_dt)`` gives the coupling forces the
impulse weight couple_dt.

Methods: ``stable_dt(scale)``, ``step(dt)``, ``totals()`` (mass per material, momentum,
kinetic, internal and total energy, accumulated wall impulse), ``material_totals()`` (mass,
internal and kinetic energy per material); accessors ``fractions()``,
``density()`` (per material, 0 where absent), ``pressure()`` (per material and mixture),
``mixture_density()``, ``centroids()``, ``velocity`` (N, 2), ``node_mass``, ``time``.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence

import math

import numpy as np

from ..materials import kernels as mk
from ..materials import slots as ms
from ..materials.burn import burn_fraction, lighting_time, quad_size
from . import kernels as K

_INTERFACES = {"donor": K.IFACE_DONOR, "slic": K.IFACE_SLIC}
_CLOSURES = {"equal_strain": K.CLOSURE_EQUAL_STRAIN, "relax": K.CLOSURE_RELAX}


def fill_fractions(nodes: np.ndarray, conn: np.ndarray, inside_fn: Callable, samples: int = 3) -> np.ndarray:
    """Fraction of each quad4 (hex8) inside a region, by samples^2 (samples^3) points per element.

    ``inside_fn(x, y)`` (``inside_fn(x, y, z)`` in 3D) takes coordinate arrays and returns a
    boolean array. Sample points are the bilinear (trilinear) images of the midpoints of a
    samples^dim grid on the reference square (cube), each weighted by the Jacobian there, so the
    result is the exact fraction for a region made of whole sub-cells of a parallelogram
    (parallelepiped) element.
    """
    if np.shape(conn)[1] == 8:
        return _fill_fractions_3d(np.asarray(nodes, dtype=float), np.asarray(conn), inside_fn, samples)
    x = nodes[conn]  # (E, 4, 2)
    t = (np.arange(samples) + 0.5) / samples * 2.0 - 1.0
    xi, eta = np.meshgrid(t, t, indexing="ij")
    xi = xi.ravel()
    eta = eta.ravel()
    sn = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
    shape = 0.25 * (1 + np.outer(xi, sn[:, 0])) * (1 + np.outer(eta, sn[:, 1]))  # (S, 4)
    dxi = 0.25 * sn[:, 0][None, :] * (1 + np.outer(eta, sn[:, 1]))
    deta = 0.25 * sn[:, 1][None, :] * (1 + np.outer(xi, sn[:, 0]))
    px = np.einsum("sa,ea->es", shape, x[:, :, 0])
    py = np.einsum("sa,ea->es", shape, x[:, :, 1])
    jac = (np.einsum("sa,ea->es", dxi, x[:, :, 0]) * np.einsum("sa,ea->es", deta, x[:, :, 1])
           - np.einsum("sa,ea->es", deta, x[:, :, 0]) * np.einsum("sa,ea->es", dxi, x[:, :, 1]))
    inside = np.asarray(inside_fn(px, py), dtype=bool)
    return (jac * inside).sum(axis=1) / jac.sum(axis=1)


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
    out = np.empty(len(conn))
    chunk = max(1, 200_000 // max(1, xi.shape[0]))
    for lo in range(0, len(conn), chunk):
        x = nodes[conn[lo:lo + chunk]]  # (e, 8, 3)
        pts = np.einsum("sa,eak->esk", shape, x)
        jac = np.einsum("jsa,eak->esjk", dshape, x)  # d x_k / d xi_j
        det = np.linalg.det(jac)
        inside = np.asarray(inside_fn(pts[..., 0], pts[..., 1], pts[..., 2]), dtype=bool)
        out[lo:lo + chunk] = (det * inside).sum(axis=1) / det.sum(axis=1)
    return out


def energy_from_pressure(row: np.ndarray, rho: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Specific internal energy e with p_eos(rho, e) = p (every EOS here is linear in e)."""
    rho = np.asarray(rho, dtype=float)
    p = np.asarray(p, dtype=float)
    eos = int(row[mk.P_EOS_TYPE])
    q = np.ascontiguousarray(row[mk.EOS_OFFSET:])
    rho0 = q[ms.Q_RHO0]
    out = np.zeros(np.broadcast(rho, p).shape)
    for idx in np.ndindex(out.shape):
        r = float(np.broadcast_to(rho, out.shape)[idx]) / rho0
        p0, _, dpde = mk._eos_state(eos, q, r, 0.0)
        if dpde != 0.0:
            out[idx] = (float(np.broadcast_to(p, out.shape)[idx]) - p0) / dpde / rho0
    return out


def build_topology(conn: np.ndarray, n_nodes: int) -> dict:
    """Faces, element-face and node-element maps and dual node lines of a quad4 (or hex8) mesh.

    Besides the maps, per sweep direction d: ``side_a[d]``, ``side_b[d]`` the local faces it
    crosses, ``corner_edge[d]``, ``corner_dst[d]`` (npe,) the edge along d each corner lies on and
    whether it is that edge's far (side-b) end, ``faces_by_dir[d]`` the faces it sweeps.
    """
    conn = np.ascontiguousarray(conn, dtype=np.int64)
    if conn.shape[1] == 8:
        return _build_topology_3d(conn, n_nodes)
    n_elem = conn.shape[0]
    a = conn.ravel()
    b = np.roll(conn, -1, axis=1).ravel()
    key = np.minimum(a, b) * n_nodes + np.maximum(a, b)
    uniq, first, inv = np.unique(key, return_index=True, return_inverse=True)
    n_faces = uniq.size
    flat = np.arange(4 * n_elem)
    owner_flat = first
    face_nodes = np.stack([a[owner_flat], b[owner_flat]], axis=1)
    face_elem = -np.ones((n_faces, 2), dtype=np.int64)
    face_local = -np.ones((n_faces, 2), dtype=np.int64)
    face_elem[:, 0] = owner_flat // 4
    face_local[:, 0] = owner_flat % 4
    second = flat[flat != first[inv]]
    if np.bincount(inv, minlength=n_faces).max() > 2:
        raise ValueError("a face is shared by more than two elements")
    face_elem[inv[second], 1] = second // 4
    face_local[inv[second], 1] = second % 4
    elem_face = inv.reshape(n_elem, 4).astype(np.int64)
    elem_sign = np.where(flat == first[inv], 1.0, -1.0).reshape(n_elem, 4)
    elem_nbr = np.where(elem_sign > 0, face_elem[elem_face, 1], face_elem[elem_face, 0]).astype(np.int64)
    face_dir = np.where(face_local[:, 0] % 2 == 1, 0, 1)

    order = np.argsort(a, kind="stable")
    node_elem_idx = flat[order].astype(np.int64)
    node_elem_ptr = np.zeros(n_nodes + 1, dtype=np.int64)
    node_elem_ptr[1:] = np.cumsum(np.bincount(a, minlength=n_nodes))

    node_line = -np.ones((n_elem, 2, 2, 4), dtype=np.int64)
    e_all = np.arange(n_elem)
    for d in range(2):
        ka, kb = K._SIDE_A[d], K._SIDE_B[d]
        for h in range(2):
            src = conn[:, K._HALF_NODES[d, h, 0]]
            dst = conn[:, K._HALF_NODES[d, h, 1]]
            node_line[:, d, h, 1] = src
            node_line[:, d, h, 2] = dst
            for col, node, k in ((0, src, ka), (3, dst, kb)):
                nb = elem_nbr[:, k]
                ok = nb >= 0
                fa, fb = conn[e_all, k], conn[e_all, (k + 1) % 4]
                other = np.where(fa == node, fb, fa)
                cn = conn[nb[ok]]
                c = np.argmax(cn == node[ok, None], axis=1)
                r = np.arange(cn.shape[0])
                c1 = cn[r, (c + 1) % 4]
                c2 = cn[r, (c + 3) % 4]
                node_line[ok, d, h, col] = np.where(c1 == other[ok], c2, c1)
    return dict(
        face_nodes=face_nodes.astype(np.int64), face_elem=face_elem, face_local=face_local,
        face_dir=face_dir, elem_face=elem_face, elem_sign=elem_sign, elem_nbr=elem_nbr,
        node_elem_ptr=node_elem_ptr, node_elem_idx=node_elem_idx, node_line=node_line,
        faces_by_dir=[np.flatnonzero(face_dir == d).astype(np.int64) for d in range(2)],
        side_a=K._SIDE_A, side_b=K._SIDE_B, corner_edge=K._CORNER_HALF, corner_dst=K._CORNER_DST,
    )


def _build_topology_3d(conn: np.ndarray, n_nodes: int) -> dict:
    """build_topology for hex8 (VTK order; local faces, edges: kernels.HEX_FACE_NODES, HEX_EDGES).

    A face is keyed by its sorted four nodes; its first element (owner) gives face_nodes in the
    owner's outward order, face_local and the sweep direction face_local // 2. node_line[e, d, h]
    = (before src, src, dst, after dst) along edge h of direction d: "before src" is the node
    joined to src by the edge of the side-a neighbour that leaves the shared face (-1 without one).
    """
    n_elem = conn.shape[0]
    loc = K.HEX_FACE_NODES
    quads = conn[:, loc].reshape(6 * n_elem, 4)  # (6E, 4) in outward order
    key = np.sort(quads, axis=1)
    uniq, first, inv, counts = np.unique(key, axis=0, return_index=True, return_inverse=True, return_counts=True)
    inv = inv.ravel()
    if counts.max(initial=0) > 2:
        raise ValueError("a face is shared by more than two elements")
    n_faces = uniq.shape[0]
    flat = np.arange(6 * n_elem)
    face_nodes = quads[first]
    face_elem = -np.ones((n_faces, 2), dtype=np.int64)
    face_local = -np.ones((n_faces, 2), dtype=np.int64)
    face_elem[:, 0] = first // 6
    face_local[:, 0] = first % 6
    second = flat[flat != first[inv]]
    face_elem[inv[second], 1] = second // 6
    face_local[inv[second], 1] = second % 6
    elem_face = inv.reshape(n_elem, 6).astype(np.int64)
    elem_sign = np.where(flat == first[inv], 1.0, -1.0).reshape(n_elem, 6)
    elem_nbr = np.where(elem_sign > 0, face_elem[elem_face, 1], face_elem[elem_face, 0]).astype(np.int64)
    face_dir = face_local[:, 0] // 2

    a = conn.ravel()
    order = np.argsort(a, kind="stable")
    node_elem_idx = np.arange(8 * n_elem, dtype=np.int64)[order]
    node_elem_ptr = np.zeros(n_nodes + 1, dtype=np.int64)
    node_elem_ptr[1:] = np.cumsum(np.bincount(a, minlength=n_nodes))

    node_line = -np.ones((n_elem, 3, 4, 4), dtype=np.int64)
    e_all = np.arange(n_elem)
    for d in range(3):
        for h in range(4):
            src = conn[:, K.HEX_EDGES[d, h, 0]]
            dst = conn[:, K.HEX_EDGES[d, h, 1]]
            node_line[:, d, h, 1] = src
            node_line[:, d, h, 2] = dst
            for col, node, k in ((0, src, 2 * d), (3, dst, 2 * d + 1)):
                nb = elem_nbr[:, k]
                ok = nb >= 0
                shared = conn[e_all[ok][:, None], loc[k][None, :]]  # (M, 4) nodes of the shared face
                cn = conn[nb[ok]]
                c = np.argmax(cn == node[ok, None], axis=1)
                cand = cn[np.arange(cn.shape[0])[:, None], K.HEX_CORNER_NBR[c]]  # (M, 3)
                off = ~(cand[:, :, None] == shared[:, None, :]).any(axis=2)
                node_line[ok, d, h, col] = cand[np.arange(cand.shape[0]), np.argmax(off, axis=1)]
    corner_edge = np.zeros((3, 8), dtype=np.int64)
    corner_dst = np.zeros((3, 8), dtype=np.int64)
    for d in range(3):
        for h in range(4):
            corner_edge[d, K.HEX_EDGES[d, h]] = h
            corner_dst[d, K.HEX_EDGES[d, h, 1]] = 1
    return dict(
        face_nodes=face_nodes.astype(np.int64), face_elem=face_elem, face_local=face_local,
        face_dir=face_dir, elem_face=elem_face, elem_sign=elem_sign, elem_nbr=elem_nbr,
        node_elem_ptr=node_elem_ptr, node_elem_idx=node_elem_idx, node_line=node_line,
        faces_by_dir=[np.flatnonzero(face_dir == d).astype(np.int64) for d in range(3)],
        side_a=(0, 2, 4), side_b=(1, 3, 5), corner_edge=corner_edge, corner_dst=corner_dst,
    )


def _hex_edges(conn: np.ndarray) -> np.ndarray:
    """Unique edges (n, 2) of a hex8 mesh."""
    e = np.concatenate([conn[:, K.HEX_EDGES[d]].reshape(-1, 2) for d in range(3)])
    return np.unique(np.sort(e, axis=1), axis=0)


def _winslow_stencil(conn: np.ndarray, n_nodes: int, interior: np.ndarray) -> tuple:
    """Logical neighbours of the interior nodes that have exactly four elements.

    Returns (ids, nbr) with nbr (len(ids), 8) = east, north, west, south, north-east, north-west,
    south-west, south-east: the elements around a node are chained counter-clockwise (the next
    element's first edge neighbour is this one's last), its edge neighbours in that order are
    E, N, W, S and the diagonal corners between them NE, NW, SW, SE. Which direction is "east"
    does not matter: the Winslow point is the same for each of the four choices.
    """
    a = np.arange(4 * conn.shape[0])
    e, k = a // 4, a % 4
    node = conn[e, k]
    valence = np.bincount(node, minlength=n_nodes)
    ok = interior & (valence == 4)
    ids = np.flatnonzero(ok)
    if ids.size == 0:
        return ids, np.zeros((0, 8), dtype=np.int64)
    sel = ok[node]
    order = np.argsort(node[sel], kind="stable")
    es, ks = e[sel][order].reshape(-1, 4), k[sel][order].reshape(-1, 4)
    c1 = conn[es, (ks + 1) % 4]
    c2 = conn[es, (ks + 2) % 4]
    c3 = conn[es, (ks + 3) % 4]
    nxt = np.argmax(c1[:, None, :] == c3[:, :, None], axis=2)  # nxt[n, i]: element after element i
    r = np.arange(ids.size)
    o = [np.zeros(ids.size, dtype=np.int64)]
    for _ in range(3):
        o.append(nxt[r, o[-1]])
    edges = [c1[r, j] for j in o]
    diags = [c2[r, j] for j in o]
    return ids, np.stack(edges + diags, axis=1).astype(np.int64)


def _winslow_target(x: np.ndarray, fallback: np.ndarray, stencil: tuple) -> np.ndarray:
    """Jacobi point of the Winslow (equipotential) equations alpha x_xixi - 2 beta x_xieta + gamma x_etaeta = 0.

    alpha = |x_eta|^2, beta = x_xi . x_eta, gamma = |x_xi|^2 with central differences on the
    logical stencil (Winslow 1967; Benson 1992 sec. 3.3): x = [alpha (x_E + x_W) + gamma (x_N + x_S)
    - beta/2 (x_NE - x_NW + x_SW - x_SE)] / (2 (alpha + gamma)). Nodes outside the stencil keep
    ``fallback``.
    """
    ids, nb = stencil
    out = fallback.copy()
    if ids.size == 0:
        return out
    xe, xn, xw, xs, xne, xnw, xsw, xse = (x[nb[:, j]] for j in range(8))
    x_xi = 0.5 * (xe - xw)
    x_eta = 0.5 * (xn - xs)
    alpha = (x_eta ** 2).sum(axis=1)[:, None]
    gamma = (x_xi ** 2).sum(axis=1)[:, None]
    beta = (x_xi * x_eta).sum(axis=1)[:, None]
    out[ids] = (alpha * (xe + xw) + gamma * (xn + xs) - 0.5 * beta * (xne - xnw + xsw - xse)) / (2.0 * (alpha + gamma))
    return out


def _sliding_nodes(x0: np.ndarray, boundary_faces: np.ndarray, n_nodes: int) -> tuple:
    """Boundary nodes inside a straight side: (ids, first and second boundary neighbour, unit tangent).

    A node qualifies when it has exactly two boundary neighbours and the three points are
    collinear (cross product below 1e-9 of the squared edge lengths); corners do not.
    """
    a = np.concatenate([boundary_faces[:, 0], boundary_faces[:, 1]])
    b = np.concatenate([boundary_faces[:, 1], boundary_faces[:, 0]])
    order = np.argsort(a, kind="stable")
    a, b = a[order], b[order]
    count = np.bincount(a, minlength=n_nodes)
    two = np.flatnonzero(count == 2)
    start = np.searchsorted(a, two)
    nb0, nb1 = b[start], b[start + 1]
    d0 = x0[nb0] - x0[two]
    d1 = x0[nb1] - x0[two]
    cross = d0[:, 0] * d1[:, 1] - d0[:, 1] * d1[:, 0]
    straight = np.abs(cross) <= 1e-9 * (d0 ** 2).sum(axis=1) ** 0.5 * (d1 ** 2).sum(axis=1) ** 0.5
    ids = two[straight]
    t = x0[nb1[straight]] - x0[nb0[straight]]
    t /= np.linalg.norm(t, axis=1)[:, None]
    return ids.astype(np.int64), nb0[straight].astype(np.int64), nb1[straight].astype(np.int64), t


def _largest_face_area(nodes: np.ndarray, conn: np.ndarray) -> np.ndarray:
    """Largest face area of each hex8 (half the cross product of the face's diagonals)."""
    q = nodes[conn[:, K.HEX_FACE_NODES]]  # (E, 6, 4, 3)
    return 0.5 * np.linalg.norm(np.cross(q[:, :, 2] - q[:, :, 0], q[:, :, 3] - q[:, :, 1]), axis=2).max(axis=1)


def _straight_lines(x0: np.ndarray, edges: np.ndarray, axis: int) -> tuple:
    """The mesh lines along ``axis``: (ids, end_a, end_b, s) for the nodes inside a line.

    A line is a chain of edges more aligned with ``axis`` than across it (|d . e_axis| > |d|/sqrt 2
    at the start); its two end nodes are the chain's ends; s in (0, 1) is each inner node's
    parameter between them at the start (arc length from end_a over the chain's length). Raises
    ValueError where a node has more than two such edges (not a structured mesh along ``axis``).
    """
    d = x0[edges[:, 1]] - x0[edges[:, 0]]
    along = np.abs(d[:, axis]) > np.linalg.norm(d, axis=1) / math.sqrt(2.0)
    a, b = edges[along, 0], edges[along, 1]
    n = x0.shape[0]
    deg = np.bincount(np.concatenate([a, b]), minlength=n)
    if deg.max(initial=0) > 2:
        raise ValueError("straight_lines smoothing needs a structured mesh: a node has more than two edges along the line axis")
    nbr = -np.ones((n, 2), dtype=np.int64)
    for u, w in ((a, b), (b, a)):
        for i, j in zip(u.tolist(), w.tolist()):
            nbr[i, 0 if nbr[i, 0] < 0 else 1] = j
    ids, end_a, end_b, par = [], [], [], []
    for start in np.flatnonzero(deg == 1):
        chain, prev, cur = [start], -1, start
        while True:
            nxt = [j for j in nbr[cur] if j >= 0 and j != prev]
            if not nxt:
                break
            prev, cur = cur, nxt[0]
            chain.append(cur)
        if chain[0] > chain[-1]:  # each chain once, from its lower-numbered end
            continue
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(x0[chain], axis=0), axis=1))])
        for node, t in zip(chain[1:-1], arc[1:-1] / arc[-1]):
            ids.append(node)
            end_a.append(chain[0])
            end_b.append(chain[-1])
            par.append(t)
    return (np.array(ids, dtype=np.int64), np.array(end_a, dtype=np.int64), np.array(end_b, dtype=np.int64),
            np.array(par, dtype=np.float64))


def _per_elem(value, n_elem: int, n_mat: int, name: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.shape == (n_mat,):
        return np.broadcast_to(arr, (n_elem, n_mat)).copy()
    if arr.shape == (n_elem, n_mat):
        return arr.copy()
    raise ValueError(f"{name} must have shape ({n_mat},) or ({n_elem}, {n_mat}), got {arr.shape}")


class AleSystem:
    """Multi-material ALE fluid on a quad4 or hex8 mesh (see the module docstring)."""

    def __init__(self, nodes, conn, materials: Sequence, fractions, density, energy=None, pressure=None,
                 velocity=None, q1: float = 1.5, q2: float = 0.06, hourglass: float = 0.1, order: int = 2,
                 interface: str = "slic", closure: str = "relax", relax_alpha: float = 0.5,
                 relax_beta: float = 0.5, advect_every: int = 1, ke_fix: bool = True, phi_eps: float = 1e-9,
                 mesh_motion: str = "eulerian", smooth_weight: float = 0.5, eulerian_pull: float = 0.2,
                 pressure_cutoff: float | None = None, mass_floor: float = 1e-10, smoothing: str = "average",
                 smooth_iterations: int = 1, smooth_boundary: str = "fixed", line_axis: int = 1):
        self.x0 = np.ascontiguousarray(nodes, dtype=np.float64)
        if self.x0.ndim != 2 or self.x0.shape[1] not in (2, 3):
            raise ValueError("AleSystem nodes must be (N, 2) or (N, 3)")
        self.dim = dim = self.x0.shape[1]
        self.conn = np.ascontiguousarray(conn, dtype=np.int64)
        self.npe = npe = 4 if dim == 2 else 8
        if self.conn.ndim != 2 or self.conn.shape[1] != npe:
            raise ValueError(f"AleSystem needs {'quad4 (E, 4)' if dim == 2 else 'hex8 (E, 8)'} connectivity in {dim}D")
        n_nodes, n_elem = self.x0.shape[0], self.conn.shape[0]
        n_mat = len(materials)
        self.n_mat = n_mat
        self.mat_eos = np.full(n_mat, -1, dtype=np.int64)
        self.mat_q = np.zeros((n_mat, mk.NPARAM - mk.EOS_OFFSET))
        self.mat_rho0 = np.zeros(n_mat)
        rows = []
        for m, row in enumerate(materials):
            if isinstance(row, tuple):
                _, row = row  # (type id, parameter row)
            rows.append(row)
            if row is None:
                continue
            row = np.asarray(row, dtype=float)
            self.mat_eos[m] = int(row[mk.P_EOS_TYPE])
            self.mat_q[m] = row[mk.EOS_OFFSET:]
            self.mat_rho0[m] = row[mk.P_RHO0]
        if order not in (1, 2):
            raise ValueError("order must be 1 (donor cell) or 2 (van Leer)")
        self.order = order
        self.iface = _INTERFACES[interface]
        self.closure = _CLOSURES[closure]
        self.q1, self.q2, self.qhg = float(q1), float(q2), float(hourglass)
        self.relax_alpha, self.relax_beta = float(relax_alpha), float(relax_beta)
        self.advect_every = int(advect_every)
        self.ke_fix = bool(ke_fix)
        self.phi_eps = float(phi_eps)
        self.p_cut = -np.inf if pressure_cutoff is None else float(pressure_cutoff)

        self.topo = build_topology(self.conn, n_nodes)
        if mesh_motion not in ("eulerian", "lagrangian", "smooth"):
            raise ValueError("mesh_motion must be 'eulerian', 'lagrangian' or 'smooth'")
        if smoothing not in ("average", "equipotential", "straight_lines"):
            raise ValueError("smoothing must be 'average', 'equipotential' or 'straight_lines'")
        if smooth_boundary not in ("fixed", "sliding"):
            raise ValueError("smooth_boundary must be 'fixed' or 'sliding'")
        if dim == 3 and mesh_motion == "smooth" and (smoothing == "equipotential" or smooth_boundary != "fixed"):
            raise ValueError("3D smoothed meshes take smoothing 'average' or 'straight_lines' with fixed boundary nodes only")
        self.mesh_motion = mesh_motion
        self.smoothing = smoothing
        self.smooth_iterations = int(smooth_iterations)
        self.smooth_boundary = smooth_boundary
        self.smooth_weight = float(smooth_weight)
        self.eulerian_pull = float(eulerian_pull)
        fn = self.topo["face_nodes"]
        edges = fn if dim == 2 else _hex_edges(self.conn)
        self._nbr_a = np.concatenate([edges[:, 0], edges[:, 1]])
        self._nbr_b = np.concatenate([edges[:, 1], edges[:, 0]])
        self._degree = np.bincount(self._nbr_a, minlength=n_nodes).astype(float)
        self.line_axis = int(line_axis)
        if mesh_motion == "smooth" and smoothing == "straight_lines":
            if not 0 <= self.line_axis < dim:
                raise ValueError(f"line_axis {self.line_axis} is not an axis of a {dim}D mesh")
            self._lines = _straight_lines(self.x0, edges, self.line_axis)
        on_boundary = np.zeros(n_nodes, dtype=bool)
        bf = fn[self.topo["face_elem"][:, 1] < 0]
        on_boundary[bf.ravel()] = True
        self._interior = ~on_boundary
        if dim == 2:
            self._stencil = _winslow_stencil(self.conn, n_nodes, self._interior)
            self._slide = _sliding_nodes(self.x0, bf, n_nodes)
            x = self.x0[self.conn]
            self.vol0 = 0.5 * ((x[:, 2, 0] - x[:, 0, 0]) * (x[:, 3, 1] - x[:, 1, 1])
                               - (x[:, 2, 1] - x[:, 0, 1]) * (x[:, 3, 0] - x[:, 1, 0]))
        else:
            self._stencil = (np.zeros(0, dtype=np.int64), np.zeros((0, 8), dtype=np.int64))
            self._slide = (np.zeros(0, dtype=np.int64),) * 3 + (np.zeros((0, 3)),)
            self.vol0 = np.empty(n_elem)
            K.element_volumes_3d(self.x0, self.conn, self.vol0)
        if np.any(self.vol0 <= 0):
            raise ValueError("elements with non-positive " + ("area (node order must be counter-clockwise)" if dim == 2
                             else "volume (hex8 corners in VTK order: bottom face counter-clockwise seen from above)"))

        fr = np.asarray(fractions, dtype=float)
        if fr.shape != (n_elem, n_mat):
            raise ValueError(f"fractions must be ({n_elem}, {n_mat}), got {fr.shape}")
        fr = fr / fr.sum(axis=1, keepdims=True)
        rho = _per_elem(density, n_elem, n_mat, "density")
        for m in range(n_mat):
            if rows[m] is None:
                rho[:, m] = 0.0
        if energy is not None:
            e = _per_elem(energy, n_elem, n_mat, "energy")
        elif pressure is not None:
            pr = _per_elem(pressure, n_elem, n_mat, "pressure")
            e = np.zeros((n_elem, n_mat))
            for m in range(n_mat):
                if rows[m] is not None:
                    e[:, m] = energy_from_pressure(np.asarray(rows[m], float), np.maximum(rho[:, m], 1e-300), pr[:, m])
        else:
            e = np.zeros((n_elem, n_mat))
        self.vol_m = fr * self.vol0[:, None]
        self.mass_m = rho * self.vol_m
        self.ener_m = self.mass_m * e

        self.x = self.x0.copy()
        self.velocity = np.zeros((n_nodes, dim))
        if velocity is not None:
            self.velocity[:] = np.asarray(velocity, dtype=float)
        self.node_mass = np.zeros(n_nodes)
        # nodal mass floor: mass_floor times the node's share of its elements filled at the largest
        # reference density (velocity of a near-empty node is not computed from momentum / mass)
        rho_ref = float(self.mat_rho0.max()) if n_mat else 0.0
        full = np.zeros(n_nodes)
        np.add.at(full, self.conn.ravel(), np.repeat(rho_ref * self.vol0 / npe, npe))
        self.m_floor = float(mass_floor) * full
        K.nodal_mass(self.mass_m, self.topo["node_elem_ptr"], self.topo["node_elem_idx"], npe, self.node_mass)
        self.bc_type = np.zeros(n_nodes, dtype=np.int64)
        self.bc_normal = np.zeros((n_nodes, dim))
        self.face_open = np.zeros(len(self.topo["face_nodes"]), dtype=np.bool_)
        self.wall_impulse = np.zeros(dim)
        self.outflow = np.zeros(n_mat)  # net mass leaving through open faces (diagnostic; inflow counts negative)
        # inflow faces: index into the inflow states (-1: none); per state the material fractions,
        # densities, specific energies and pressure of the outside (ghost) donor
        self.face_inflow = -np.ones(len(self.topo["face_nodes"]), dtype=np.int64)
        self.inflow_states: list[tuple[np.ndarray, np.ndarray, np.ndarray, float]] = []
        self.time = 0.0
        self.n_steps = 0
        self._since_remap = 0

        self.f_elem = np.zeros((n_elem, npe, dim))
        self.pscale = np.ones((n_elem, n_mat))  # pressure factor per material (programmed burn)
        self.burn = None  # [(material, lighting time (E,), D, element size (E,))]: set_burn
        self.pres_m = np.zeros((n_elem, n_mat))
        self.bulk_m = np.zeros((n_elem, n_mat))
        self.q_elem = np.zeros(n_elem)
        self.dt_elem = np.zeros(n_elem)
        self.work_elem = np.zeros(n_elem)
        self._fresh = False
        nf = len(self.topo["face_nodes"])
        self._fvol = np.zeros((nf, n_mat))
        self._fmass = np.zeros((nf, n_mat))
        self._fener = np.zeros((nf, n_mat))
        n_edges = npe // 2  # element edges along one sweep direction
        self._gm = np.zeros((n_elem, n_edges))
        self._gp = np.zeros((n_elem, n_edges, dim))
        self._gk = np.zeros((n_elem, n_edges))
        self._bm = np.zeros((n_elem, n_edges, 2))
        self._bp = np.zeros((n_elem, n_edges, 2, dim))
        self._bk = np.zeros((n_elem, n_edges, 2))
        self._impulse = np.zeros((n_nodes, dim))
        self._f_ext = np.zeros((n_nodes, dim))
        # body acceleration on the nodal masses, and the forces of couplings to structures
        # (contact.coupling): set f_couple before each step; its impulse is couple_dt * f_couple
        self.gravity = np.zeros(dim)
        self.f_couple = np.zeros((n_nodes, dim))
        self.gravity_work = 0.0
        self.coupling_work = 0.0
        self.v_lag = self.velocity.copy()  # v^{n+1/2} of the Lagrangian phase, before the remap
        self.v_mid = np.zeros((n_nodes, dim))  # (v^{n-1/2} + v^{n+1/2}) / 2 of the last Lagrangian phase
        # the kernels that differ between quad4 and hex8
        if dim == 2:
            self._k_forces, self._k_nodal, self._k_energy = K.lagrange_forces, K.nodal_update, K.lagrange_energy
            self._k_faces, self._k_finish = K.face_fluxes, K.finish_remap_nodes
        else:
            self._k_forces, self._k_nodal, self._k_energy = K.lagrange_forces_3d, K.nodal_update_3d, K.lagrange_energy_3d
            self._k_faces, self._k_finish = K.face_fluxes_3d, K.finish_remap_nodes_3d

    def set_burn(self, materials, velocities, detonations) -> None:
        """Programmed burn (``materials.burn``) of the given materials (indices) with detonation
        velocities D: lighting times at the element centroids of the initial (Eulerian) mesh from
        ``detonations`` [(point, time), ...], element size area / longest edge."""
        centroids = self.x0[self.conn].mean(axis=1)
        delta = quad_size(self.x0, self.conn) if self.dim == 2 else self.vol0 / _largest_face_area(self.x0, self.conn)
        self.burn = [(int(m), lighting_time(centroids, detonations, float(d)), float(d), delta)
                     for m, d in zip(materials, velocities)] or None
        self._fresh = False

    # ---------------------------------------------------------------- boundaries
    def set_fixed(self, node_ids) -> None:
        ids = np.asarray(node_ids, dtype=np.int64)
        self.bc_type[ids] = K.BC_FIXED
        self.velocity[ids] = 0.0

    def set_slip(self, node_ids, normal) -> None:
        ids = np.asarray(node_ids, dtype=np.int64)
        n = np.asarray(normal, dtype=float)
        n = n / np.linalg.norm(n)
        for i in ids:
            if self.bc_type[i] == K.BC_FIXED:
                continue
            if self.bc_type[i] == K.BC_VELOCITY:  # inflow node on a wall: the wall takes the normal part
                self.bc_normal[i] -= (self.bc_normal[i] @ n) * n
                self.velocity[i] = self.bc_normal[i]
                continue
            if self.bc_type[i] == K.BC_SLIP and abs(abs(self.bc_normal[i] @ n) - 1.0) > 1e-12:
                if self.dim == 3:  # two walls: along their intersection
                    t = np.cross(self.bc_normal[i], n)
                    self.bc_type[i] = K.BC_LINE
                    self.bc_normal[i] = t / np.linalg.norm(t)
                else:
                    self.bc_type[i] = K.BC_FIXED
                continue
            if self.bc_type[i] == K.BC_LINE:
                if abs(self.bc_normal[i] @ n) > 1e-12:  # a third wall across the line: a corner
                    self.bc_type[i] = K.BC_FIXED
                continue
            self.bc_type[i] = K.BC_SLIP
            self.bc_normal[i] = n
        v = self.velocity
        self.velocity[:] = np.where((self.bc_type == K.BC_FIXED)[:, None], 0.0, v)
        slip = self.bc_type == K.BC_SLIP
        vn = (v[slip] * self.bc_normal[slip]).sum(axis=1)
        self.velocity[slip] = v[slip] - vn[:, None] * self.bc_normal[slip]
        line = self.bc_type == K.BC_LINE
        vt = (v[line] * self.bc_normal[line]).sum(axis=1)
        self.velocity[line] = vt[:, None] * self.bc_normal[line]

    def set_transmit(self, node_ids) -> None:
        mark = np.zeros(self.x0.shape[0], dtype=bool)
        mark[np.asarray(node_ids, dtype=np.int64)] = True
        fn = self.topo["face_nodes"]
        boundary = self.topo["face_elem"][:, 1] < 0
        self.face_open |= boundary & mark[fn].all(axis=1)

    def set_inflow(self, node_ids, material: int, velocity, density: float | None = None,
                   energy: float | None = None, pressure: float | None = None) -> None:
        """Inflow of ``material`` at a given state through the boundary faces whose two nodes are in the set.

        The outside of those faces is a ghost element full of the material at ``density`` (default
        its reference density) and specific internal energy ``energy`` (or the one giving
        ``pressure``; default the EOS's e0, as a fill), reset to that state every step: it is the donor of the remap
        through the face when the face sweeps volume inwards, and pushes on the face with its
        pressure. The nodes get the velocity ``velocity`` (BC_VELOCITY; on a slip wall only its
        tangential part, on a fixed node none). Where the face sweeps volume outwards it acts as a
        transmitting face (zero gradient). Mass entering is booked negative in ``totals()["outflow"]``.
        """
        m = int(material)
        if self.mat_eos[m] < 0:
            raise ValueError("the inflow material must not be void")
        rho0 = float(self.mat_rho0[m])
        rho = rho0 if density is None else float(density)
        q = np.ascontiguousarray(self.mat_q[m])
        p0, _, dpde = mk._eos_state(int(self.mat_eos[m]), q, rho / rho0, 0.0)
        if energy is None and pressure is None:
            e = float(q[ms.Q_E0]) / rho0  # the EOS's e0 (per reference volume), as an initial fill
        elif energy is None:
            e = 0.0 if dpde == 0.0 else (float(pressure) - p0) / dpde / rho0
        else:
            e = float(energy)
        p_in = p0 + dpde * rho0 * e
        frac = np.zeros(self.n_mat)
        frac[m] = 1.0
        rho_m = np.zeros(self.n_mat)
        rho_m[m] = rho
        e_m = np.zeros(self.n_mat)
        e_m[m] = e
        self.inflow_states.append((frac, rho_m, e_m, float(p_in)))
        k = len(self.inflow_states) - 1
        ids = np.asarray(node_ids, dtype=np.int64)
        mark = np.zeros(self.x0.shape[0], dtype=bool)
        mark[ids] = True
        fn = self.topo["face_nodes"]
        faces = (self.topo["face_elem"][:, 1] < 0) & mark[fn].all(axis=1)
        self.face_open |= faces
        self.face_inflow[faces] = k
        u = np.asarray(velocity, dtype=float)
        for i in ids:
            if self.bc_type[i] == K.BC_FIXED:
                continue
            w = u.copy()
            if self.bc_type[i] == K.BC_SLIP:
                w -= (w @ self.bc_normal[i]) * self.bc_normal[i]
            elif self.bc_type[i] == K.BC_LINE:
                w = (w @ self.bc_normal[i]) * self.bc_normal[i]
            self.bc_type[i] = K.BC_VELOCITY
            self.bc_normal[i] = w
            self.velocity[i] = w

    # ---------------------------------------------------------------- stepping
    def _forces(self) -> None:
        if self.burn is not None:
            for m, t_light, d, delta in self.burn:
                self.pscale[:, m] = burn_fraction(self.time, t_light, d, delta)
        self._k_forces(self.x, self.velocity, self.conn, self.vol_m, self.mass_m, self.ener_m,
                       self.mat_eos, self.mat_q, self.mat_rho0, self.q1, self.q2, self.qhg, self.phi_eps,
                       self.pscale, self.p_cut, self.f_elem, self.pres_m, self.bulk_m, self.q_elem, self.dt_elem)
        self._fresh = True

    def stable_dt(self, scale: float = 0.5) -> float:
        """scale times the smallest element step l / (Q + sqrt(Q^2 + (c + |v|)^2)) (eq. 2.9)."""
        if not self._fresh:
            self._forces()
        return float(scale * self.dt_elem.min())

    def _external_forces(self) -> np.ndarray:
        f = self._f_ext
        f[:] = 0.0
        if not self.face_open.any():
            return f
        fo = np.flatnonzero(self.face_open)
        n0, n1 = self.topo["face_nodes"][fo, :2].T
        e = self.topo["face_elem"][fo, 0]
        vt = self.vol_m[e].sum(axis=1)
        p = (self.vol_m[e] * self.pres_m[e]).sum(axis=1) / vt
        ghost = self.face_inflow[fo]
        if np.any(ghost >= 0):  # inflow faces: the ghost's own pressure
            p_in = np.array([st[3] for st in self.inflow_states])
            p = np.where(ghost >= 0, p_in[np.maximum(ghost, 0)], p)
        if self.dim == 3:
            # -p A / 4 per node, A = (x2 - x0) x (x3 - x1) / 2 the bilinear face's outward area vector
            fnodes = self.topo["face_nodes"][fo]
            q = self.x[fnodes]
            area = 0.5 * np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
            for a in range(4):
                for k in range(3):
                    np.add.at(f[:, k], fnodes[:, a], -0.25 * p * area[:, k])
            return f
        t = self.x[n1] - self.x[n0]
        # the outside, a copy of the inside, pushes inward with its pressure: -p n L / 2 per node
        fx = -0.5 * p * t[:, 1]
        fy = 0.5 * p * t[:, 0]
        np.add.at(f[:, 0], n0, fx)
        np.add.at(f[:, 0], n1, fx)
        np.add.at(f[:, 1], n0, fy)
        np.add.at(f[:, 1], n1, fy)
        return f

    def step(self, dt: float, couple_dt: float | None = None) -> None:
        """One Lagrangian step of length dt followed (every advect_every steps) by the remap.

        Gravity acts on the nodal masses; the coupling forces ``f_couple`` give the impulse
        ``couple_dt * f_couple`` (default dt), so that a structure stepping them with its own
        weight (the central difference's dt_avg) receives exactly the opposite impulse. Their work
        over the step, f . (v^{n-1/2} + v^{n+1/2}) / 2 times the impulse weight (the same average
        that makes lagrange_energy conserve kinetic plus internal energy), is added to
        ``gravity_work`` and ``coupling_work``.
        """
        if not self._fresh:
            self._forces()
        topo = self.topo
        v_old = self.velocity.copy()
        f_ext = self._external_forces()
        has_gravity = bool(np.any(self.gravity))
        if has_gravity:
            f_ext += self.node_mass[:, None] * self.gravity
        w_couple = dt if couple_dt is None else couple_dt
        has_couple = bool(np.any(self.f_couple))
        if has_couple:
            f_ext += self.f_couple * (w_couple / dt)
        self._k_nodal(self.f_elem, topo["node_elem_ptr"], topo["node_elem_idx"], f_ext,
                      self.node_mass, self.m_floor, self.velocity, self.bc_type, self.bc_normal, dt, self._impulse)
        self.v_lag[:] = self.velocity
        v_mid = self.v_mid
        np.add(v_old, self.velocity, out=v_mid)
        v_mid *= 0.5
        if has_gravity:
            self.gravity_work += dt * float(np.sum(self.node_mass * (v_mid @ self.gravity)))
        if has_couple:
            self.coupling_work += w_couple * float(np.sum(self.f_couple * v_mid))
        self.wall_impulse += self._impulse.sum(axis=0)
        self._k_energy(self.x, v_old, self.velocity, dt, self.conn, self.f_elem, self.vol_m, self.mass_m,
                       self.ener_m, self.pres_m, self.bulk_m, self.q_elem, self.closure, self.relax_alpha,
                       self.relax_beta, self.phi_eps, self.work_elem)
        x_lag = self.x + dt * self.velocity
        self._since_remap += 1
        if self.mesh_motion == "lagrangian":
            self.x = x_lag
        elif self._since_remap >= self.advect_every:
            x_new = self._mesh_target(x_lag)
            self._remap(x_lag, x_new)
            self.x = x_new
            self._since_remap = 0
        else:
            self.x = x_lag
        self.time += dt
        self.n_steps += 1
        self._fresh = False

    def _mesh_target(self, x_lag: np.ndarray) -> np.ndarray:
        """Where the remap puts the mesh: its start (Eulerian), or a smoothed Lagrangian mesh.

        "smooth": starting from x_lag, smooth_iterations Jacobi passes move each interior node a
        fraction smooth_weight towards its target: the mean of its edge neighbours (smoothing
        "average", Benson 1992 sec. 3) or the Winslow equipotential point (smoothing
        "equipotential", Winslow 1967; interior nodes with four elements, the others averaged).
        Boundary nodes: "fixed" back to their start; "sliding" (nodes inside a straight side) on
        that side's line, moved the same fraction towards the mean of their two boundary
        neighbours, corners fixed. Last, every moving node goes a fraction eulerian_pull back
        towards its start (which bounds the drift of a mesh in a steady stream).
        """
        if self.mesh_motion == "eulerian":
            return self.x0.copy()
        if self.smoothing == "straight_lines":
            return self._straight_line_target(x_lag)
        inner = self._interior
        w = self.smooth_weight
        x = x_lag.copy()
        ids, nb0, nb1, tang = self._slide
        sliding = self.smooth_boundary == "sliding" and ids.size > 0
        for _ in range(self.smooth_iterations):
            mean = np.zeros_like(x)
            np.add.at(mean, self._nbr_a, x[self._nbr_b])
            mean /= self._degree[:, None]
            target = mean
            if self.smoothing == "equipotential":
                target = _winslow_target(x, mean, self._stencil)
            x_prev = x.copy()
            x[inner] = x[inner] + w * (target[inner] - x[inner])
            x[~inner] = self.x0[~inner]
            if sliding:
                # on the side's line through x0, moved along it towards the boundary neighbours' mean
                s_pos = ((x_prev[ids] - self.x0[ids]) * tang).sum(axis=1)
                s_mean = ((0.5 * (x_prev[nb0] + x_prev[nb1]) - self.x0[ids]) * tang).sum(axis=1)
                x[ids] = self.x0[ids] + (s_pos + w * (s_mean - s_pos))[:, None] * tang
        moving = inner.copy()
        if sliding:
            moving[ids] = True
        x_new = self.x0.copy()
        x_new[moving] = x[moving] + self.eulerian_pull * (self.x0[moving] - x[moving])
        return x_new

    def _straight_line_target(self, x_lag: np.ndarray) -> np.ndarray:
        """Smoothing "straight_lines": nodes move uniformly along the straight mesh lines along
        ``line_axis`` (the paper's section 5; LS-DYNA *ALE_SMOOTHING keeps a node at its initial
        parametric place between two master nodes).

        Every node moves along its line only (along the axis; the other coordinates keep their
        start): a line's two end nodes by the axis component of their Lagrangian displacement,
        the nodes inside it to their initial parameter s between the ends,
        x = x_a + s (x_b - x_a). So the mesh follows the material along the lines (a free surface
        at a line's end, a column compressed along them) and stays as straight and as evenly
        spread as it started; across the lines it is Eulerian. Last, every node goes a fraction
        eulerian_pull back towards its start.
        """
        ax = self.line_axis
        x = self.x0.copy()
        x[:, ax] = x_lag[:, ax]
        ids, a, b, s = self._lines
        x[ids] = x[a] + s[:, None] * (x[b] - x[a])
        return x + self.eulerian_pull * (self.x0 - x)

    def _inflow_fluxes(self, faces: np.ndarray, x_lag: np.ndarray, x_new: np.ndarray) -> None:
        """Replace the fluxes of inflow faces sweeping volume inwards by the ghost donor's.

        The swept volume is the same signed quad area face_fluxes uses (owner orientation: positive
        into the inside element); the ghost gives material volume phi_m dV, mass rho_m phi_m dV and
        energy e_m rho_m phi_m dV. Outward sweeps keep face_fluxes' zero-gradient outflow.
        """
        if faces.size == 0:
            return
        if self.dim == 3:
            dv = np.empty(faces.size)
            K.swept_volumes_3d(faces, self.topo["face_nodes"], x_lag, x_new, dv)
        else:
            n0, n1 = self.topo["face_nodes"][faces].T
            l0, l1, w0, w1 = x_lag[n0], x_lag[n1], x_new[n0], x_new[n1]
            # quad (l0, w0, w1, l1): half the cross product of its diagonals (kernels.quad_area)
            dv = 0.5 * ((w1[:, 0] - l0[:, 0]) * (l1[:, 1] - w0[:, 1]) - (w1[:, 1] - l0[:, 1]) * (l1[:, 0] - w0[:, 0]))
        inward = dv > 0.0
        for k, (frac, rho_m, e_m, _) in enumerate(self.inflow_states):
            sel = faces[inward & (self.face_inflow[faces] == k)]
            vol = dv[inward & (self.face_inflow[faces] == k)][:, None] * frac[None, :]
            self._fvol[sel] = vol
            self._fmass[sel] = vol * rho_m
            self._fener[sel] = vol * rho_m * e_m

    def _sweep_order(self) -> tuple:
        """Directions of this step's remap sweeps: 2D (x, y) and (y, x) on alternate steps; 3D the six
        orders over six steps, (x, y, z) cycled by one every second step and reversed on odd steps
        (xyz, zyx, yzx, xzy, zxy, yxz), so each direction leads, and follows each other, equally often."""
        if self.dim == 2:
            return (0, 1) if self.n_steps % 2 == 0 else (1, 0)
        shift = (self.n_steps // 2) % 3
        order = tuple((shift + i) % 3 for i in range(3))
        return order[::-1] if self.n_steps % 2 else order

    def _remap(self, x_lag: np.ndarray, x_new: np.ndarray) -> None:
        topo = self.topo
        mnode = self.node_mass.copy()
        pnode = mnode[:, None] * self.velocity
        knode = 0.5 * mnode * (self.velocity ** 2).sum(axis=1)
        any_open = bool(self.face_open.any())
        for d in self._sweep_order():
            ka, kb = topo["side_a"][d], topo["side_b"][d]
            self._k_faces(topo["faces_by_dir"][d], topo["face_nodes"], topo["face_elem"], topo["face_local"],
                          topo["elem_nbr"], self.face_open, x_lag, x_new, self.vol_m, self.mass_m, self.ener_m,
                          self.order, self.iface, self.phi_eps, self._fvol, self._fmass, self._fener)
            if any_open:
                fo = np.flatnonzero(self.face_open & (topo["face_dir"] == d))
                self._inflow_fluxes(fo[self.face_inflow[fo] >= 0], x_lag, x_new)
                self.outflow -= self._fmass[fo].sum(axis=0)
            K.apply_face_fluxes(ka, kb, topo["elem_face"], topo["elem_sign"], self._fvol, self._fmass, self._fener,
                                self.vol_m, self.mass_m, self.ener_m)
            K.dual_fluxes(ka, kb, d, self.conn, topo["elem_face"], topo["elem_sign"], topo["elem_nbr"], self.face_open,
                          any_open, self._fmass, topo["node_line"], mnode, pnode, self.order,
                          self._gm, self._gp, self._gk, self._bm, self._bp, self._bk)
            K.apply_dual_fluxes(topo["corner_edge"][d], topo["corner_dst"][d], topo["node_elem_ptr"],
                                topo["node_elem_idx"], any_open, self._gm, self._gp, self._gk,
                                self._bm, self._bp, self._bk, mnode, pnode, knode)
        dissip = np.empty_like(mnode)
        self._k_finish(mnode, pnode, knode, self.m_floor, self.bc_type, self.bc_normal, self.velocity, self._impulse, dissip)
        self.wall_impulse += self._impulse.sum(axis=0)
        K.nodal_mass(self.mass_m, topo["node_elem_ptr"], topo["node_elem_idx"], self.npe, self.node_mass)
        K.finish_remap_elements(self.conn, self.mass_m, self.ener_m, self.node_mass, dissip, self.ke_fix)

    # ---------------------------------------------------------------- output
    def totals(self) -> dict:
        """Conserved totals: mass per material, momentum, kinetic/internal/total energy, wall impulse."""
        ke = 0.5 * float((self.node_mass * (self.velocity ** 2).sum(axis=1)).sum())
        ie = float(self.ener_m.sum())
        return dict(
            mass=self.mass_m.sum(axis=0),
            momentum=(self.node_mass[:, None] * self.velocity).sum(axis=0),
            kinetic=ke, internal=ie, total=ke + ie,
            wall_impulse=self.wall_impulse.copy(),
            outflow=self.outflow.copy(),
        )

    def material_totals(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(mass, internal energy, kinetic energy) per material, each (N,).

        Kinetic energy per material: each element corner carries M_em / n of material m at its
        node's velocity (n = 4 corners, 8 in 3D), KE_m = sum_e sum_a M_em |v_a|^2 / 2n; over the
        materials these sum to the nodal kinetic energy of totals() (m_I = sum_e M_e / n).
        """
        v2 = (self.velocity ** 2).sum(axis=1)
        corner = v2[self.conn].sum(axis=1)  # (E,) sum of |v|^2 over the element's corners
        kinetic = 0.5 / self.npe * (self.mass_m * corner[:, None]).sum(axis=0)
        return self.mass_m.sum(axis=0), self.ener_m.sum(axis=0), kinetic

    def fractions(self) -> np.ndarray:
        return self.vol_m / self.vol_m.sum(axis=1, keepdims=True)

    def density(self) -> np.ndarray:
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(self.vol_m > 0, self.mass_m / np.where(self.vol_m > 0, self.vol_m, 1.0), 0.0)

    def mixture_density(self) -> np.ndarray:
        return self.mass_m.sum(axis=1) / self.vol_m.sum(axis=1)

    def pressure(self, mixture: bool = False) -> np.ndarray:
        """Material pressures (E, N) from the EOS at the current state, or the mixture (E,) value."""
        self._forces()
        if mixture:
            return (self.fractions() * self.pres_m).sum(axis=1)
        return self.pres_m.copy()

    def centroids(self) -> np.ndarray:
        return self.x[self.conn].mean(axis=1)

    def element_velocity(self) -> np.ndarray:
        return self.velocity[self.conn].mean(axis=1)

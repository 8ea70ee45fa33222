"""``AleSystem``: a multi-material ALE (Eulerian by default) fluid on a quad4 mesh.

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

- ``nodes`` (N, 2), ``conn`` (E, 4) counter-clockwise quad4 (``model.mesh.box_mesh`` order);
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
  mesh to its start) or "smooth" (interior nodes relaxed by ``smooth_weight`` towards the mean of
  their neighbours, then ``eulerian_pull`` back towards their start; boundary nodes Eulerian);
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
the set are open (outflow / zero-gradient inflow, with the inside pressure applied outside).
Nodes in two slip sets with different normals become fixed.

Body force and structure coupling: ``gravity`` (2,) acceleration on the nodal masses;
``f_couple`` (N, 2) coupling forces of the step (contact.coupling), with their work accumulated
in ``gravity_work`` and ``coupling_work``; ``step(dt, couple_dt)`` gives the coupling forces the
impulse weight couple_dt.

Methods: ``stable_dt(scale)``, ``step(dt)``, ``totals()`` (mass per material, momentum,
kinetic, internal and total energy, accumulated wall impulse); accessors ``fractions()``,
``density()`` (per material, 0 where absent), ``pressure()`` (per material and mixture),
``mixture_density()``, ``centroids()``, ``velocity`` (N, 2), ``node_mass``, ``time``.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..materials import kernels as mk
from ..materials.burn import burn_fraction, lighting_time, quad_size
from . import kernels as K

_INTERFACES = {"donor": K.IFACE_DONOR, "slic": K.IFACE_SLIC}
_CLOSURES = {"equal_strain": K.CLOSURE_EQUAL_STRAIN, "relax": K.CLOSURE_RELAX}


def fill_fractions(nodes: np.ndarray, conn: np.ndarray, inside_fn: Callable, samples: int = 3) -> np.ndarray:
    """Fraction of each quad4 inside a region, by samples x samples points per element.

    ``inside_fn(x, y)`` takes coordinate arrays and returns a boolean array. Sample points are the
    bilinear images of the midpoints of a samples x samples grid on the reference square, each
    weighted by the Jacobian there, so the result is the exact fraction for a region made of
    whole sub-cells of a parallelogram element.
    """
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


def energy_from_pressure(row: np.ndarray, rho: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Specific internal energy e with p_eos(rho, e) = p (every EOS here is linear in e)."""
    rho = np.asarray(rho, dtype=float)
    p = np.asarray(p, dtype=float)
    eos = int(row[mk.P_EOS_TYPE])
    q = np.ascontiguousarray(row[mk.EOS_OFFSET:])
    rho0 = q[0]
    out = np.zeros(np.broadcast(rho, p).shape)
    for idx in np.ndindex(out.shape):
        r = float(np.broadcast_to(rho, out.shape)[idx]) / rho0
        p0, _, dpde = mk._eos_state(eos, q, r, 0.0)
        if dpde != 0.0:
            out[idx] = (float(np.broadcast_to(p, out.shape)[idx]) - p0) / dpde / rho0
    return out


def build_topology(conn: np.ndarray, n_nodes: int) -> dict:
    """Faces, element-face and node-element maps and dual node lines of a quad4 mesh."""
    conn = np.ascontiguousarray(conn, dtype=np.int64)
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
    )


def _per_elem(value, n_elem: int, n_mat: int, name: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.shape == (n_mat,):
        return np.broadcast_to(arr, (n_elem, n_mat)).copy()
    if arr.shape == (n_elem, n_mat):
        return arr.copy()
    raise ValueError(f"{name} must have shape ({n_mat},) or ({n_elem}, {n_mat}), got {arr.shape}")


class AleSystem:
    """Multi-material ALE fluid on a quad4 mesh (see the module docstring)."""

    def __init__(self, nodes, conn, materials: Sequence, fractions, density, energy=None, pressure=None,
                 velocity=None, q1: float = 1.5, q2: float = 0.06, hourglass: float = 0.1, order: int = 2,
                 interface: str = "slic", closure: str = "relax", relax_alpha: float = 0.5,
                 relax_beta: float = 0.5, advect_every: int = 1, ke_fix: bool = True, phi_eps: float = 1e-9,
                 mesh_motion: str = "eulerian", smooth_weight: float = 0.5, eulerian_pull: float = 0.2,
                 pressure_cutoff: float | None = None, mass_floor: float = 1e-10):
        self.x0 = np.ascontiguousarray(nodes, dtype=np.float64)
        if self.x0.ndim != 2 or self.x0.shape[1] != 2:
            raise ValueError("AleSystem is 2D: nodes must be (N, 2)")
        self.conn = np.ascontiguousarray(conn, dtype=np.int64)
        if self.conn.shape[1] != 4:
            raise ValueError("AleSystem needs quad4 connectivity (E, 4)")
        n_nodes, n_elem = self.x0.shape[0], self.conn.shape[0]
        n_mat = len(materials)
        self.n_mat = n_mat
        self.mat_eos = np.full(n_mat, -1, dtype=np.int64)
        self.mat_q = np.zeros((n_mat, mk.NPARAM - mk.EOS_OFFSET))
        self.mat_rho0 = np.zeros(n_mat)
        rows = []
        for m, row in enumerate(materials):
            if isinstance(row, tuple):
                row = row[1]
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
        if mesh_motion not in ("eulerian", "smooth"):
            raise ValueError("mesh_motion must be 'eulerian' or 'smooth'")
        self.mesh_motion = mesh_motion
        self.smooth_weight = float(smooth_weight)
        self.eulerian_pull = float(eulerian_pull)
        fn = self.topo["face_nodes"]
        self._nbr_a = np.concatenate([fn[:, 0], fn[:, 1]])
        self._nbr_b = np.concatenate([fn[:, 1], fn[:, 0]])
        self._degree = np.bincount(self._nbr_a, minlength=n_nodes).astype(float)
        on_boundary = np.zeros(n_nodes, dtype=bool)
        bf = fn[self.topo["face_elem"][:, 1] < 0]
        on_boundary[bf.ravel()] = True
        self._interior = ~on_boundary
        x = self.x0[self.conn]
        self.vol0 = 0.5 * ((x[:, 2, 0] - x[:, 0, 0]) * (x[:, 3, 1] - x[:, 1, 1])
                           - (x[:, 2, 1] - x[:, 0, 1]) * (x[:, 3, 0] - x[:, 1, 0]))
        if np.any(self.vol0 <= 0):
            raise ValueError("elements with non-positive area (node order must be counter-clockwise)")

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
        self.velocity = np.zeros((n_nodes, 2))
        if velocity is not None:
            self.velocity[:] = np.asarray(velocity, dtype=float)
        self.node_mass = np.zeros(n_nodes)
        # nodal mass floor: mass_floor times the node's share of its elements filled at the largest
        # reference density (velocity of a near-empty node is not computed from momentum / mass)
        rho_ref = float(self.mat_rho0.max()) if n_mat else 0.0
        full = np.zeros(n_nodes)
        np.add.at(full, self.conn.ravel(), np.repeat(0.25 * rho_ref * self.vol0, 4))
        self.m_floor = float(mass_floor) * full
        K.nodal_mass(self.mass_m, self.topo["node_elem_ptr"], self.topo["node_elem_idx"], self.node_mass)
        self.bc_type = np.zeros(n_nodes, dtype=np.int64)
        self.bc_normal = np.zeros((n_nodes, 2))
        self.face_open = np.zeros(len(self.topo["face_nodes"]), dtype=np.bool_)
        self.wall_impulse = np.zeros(2)
        self.outflow = np.zeros(n_mat)  # net mass leaving through open faces (diagnostic)
        self.time = 0.0
        self.n_steps = 0
        self._since_remap = 0

        self.f_elem = np.zeros((n_elem, 4, 2))
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
        self._gm = np.zeros((n_elem, 2))
        self._gp = np.zeros((n_elem, 2, 2))
        self._gk = np.zeros((n_elem, 2))
        self._bm = np.zeros((n_elem, 2, 2))
        self._bp = np.zeros((n_elem, 2, 2, 2))
        self._bk = np.zeros((n_elem, 2, 2))
        self._impulse = np.zeros((n_nodes, 2))
        self._f_ext = np.zeros((n_nodes, 2))
        # body acceleration on the nodal masses, and the forces of couplings to structures
        # (contact.coupling): set f_couple before each step; its impulse is couple_dt * f_couple
        self.gravity = np.zeros(2)
        self.f_couple = np.zeros((n_nodes, 2))
        self.gravity_work = 0.0
        self.coupling_work = 0.0
        self.v_lag = self.velocity.copy()  # v^{n+1/2} of the Lagrangian phase, before the remap
        self.v_mid = np.zeros((n_nodes, 2))  # (v^{n-1/2} + v^{n+1/2}) / 2 of the last Lagrangian phase

    def set_burn(self, materials, velocities, detonations) -> None:
        """Programmed burn (``materials.burn``) of the given materials (indices) with detonation
        velocities D: lighting times at the element centroids of the initial (Eulerian) mesh from
        ``detonations`` [(point, time), ...], element size area / longest edge."""
        centroids = self.x0[self.conn].mean(axis=1)
        delta = quad_size(self.x0, self.conn)
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
            if self.bc_type[i] == K.BC_SLIP and abs(abs(self.bc_normal[i] @ n) - 1.0) > 1e-12:
                self.bc_type[i] = K.BC_FIXED
                continue
            self.bc_type[i] = K.BC_SLIP
            self.bc_normal[i] = n
        v = self.velocity
        self.velocity[:] = np.where((self.bc_type == K.BC_FIXED)[:, None], 0.0, v)
        slip = self.bc_type == K.BC_SLIP
        vn = (v[slip] * self.bc_normal[slip]).sum(axis=1)
        self.velocity[slip] = v[slip] - vn[:, None] * self.bc_normal[slip]

    def set_transmit(self, node_ids) -> None:
        mark = np.zeros(self.x0.shape[0], dtype=bool)
        mark[np.asarray(node_ids, dtype=np.int64)] = True
        fn = self.topo["face_nodes"]
        boundary = self.topo["face_elem"][:, 1] < 0
        self.face_open |= boundary & mark[fn[:, 0]] & mark[fn[:, 1]]

    # ---------------------------------------------------------------- stepping
    def _forces(self) -> None:
        if self.burn is not None:
            for m, t_light, d, delta in self.burn:
                self.pscale[:, m] = burn_fraction(self.time, t_light, d, delta)
        K.lagrange_forces(self.x, self.velocity, self.conn, self.vol_m, self.mass_m, self.ener_m,
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
        n0, n1 = self.topo["face_nodes"][fo].T
        e = self.topo["face_elem"][fo, 0]
        vt = self.vol_m[e].sum(axis=1)
        p = (self.vol_m[e] * self.pres_m[e]).sum(axis=1) / vt
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
        K.nodal_update(self.f_elem, topo["node_elem_ptr"], topo["node_elem_idx"], f_ext,
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
        K.lagrange_energy(self.x, v_old, self.velocity, dt, self.conn, self.f_elem, self.vol_m, self.mass_m,
                          self.ener_m, self.pres_m, self.bulk_m, self.q_elem, self.closure, self.relax_alpha,
                          self.relax_beta, self.phi_eps, self.work_elem)
        x_lag = self.x + dt * self.velocity
        self._since_remap += 1
        if self._since_remap >= self.advect_every:
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

        "smooth": interior nodes move from x_lag a fraction smooth_weight towards the mean of
        their edge neighbours (simple averaging, Benson 1992 sec. 3), then a fraction
        eulerian_pull back towards their start (which bounds the drift of a mesh in a steady
        stream); boundary nodes go back to their start.
        """
        if self.mesh_motion == "eulerian":
            return self.x0.copy()
        mean = np.zeros_like(x_lag)
        np.add.at(mean, self._nbr_a, x_lag[self._nbr_b])
        mean /= self._degree[:, None]
        x_new = self.x0.copy()
        w = self.smooth_weight
        inner = self._interior
        smoothed = x_lag[inner] + w * (mean[inner] - x_lag[inner])
        x_new[inner] = smoothed + self.eulerian_pull * (self.x0[inner] - smoothed)
        return x_new

    def _remap(self, x_lag: np.ndarray, x_new: np.ndarray) -> None:
        topo = self.topo
        mnode = self.node_mass.copy()
        pnode = mnode[:, None] * self.velocity
        knode = 0.5 * mnode * (self.velocity ** 2).sum(axis=1)
        dirs = (0, 1) if self.n_steps % 2 == 0 else (1, 0)
        any_open = bool(self.face_open.any())
        for d in dirs:
            K.face_fluxes(topo["faces_by_dir"][d], topo["face_nodes"], topo["face_elem"], topo["face_local"],
                          topo["elem_nbr"], self.face_open, x_lag, x_new, self.vol_m, self.mass_m, self.ener_m,
                          self.order, self.iface, self.phi_eps, self._fvol, self._fmass, self._fener)
            if any_open:
                fo = np.flatnonzero(self.face_open & (topo["face_dir"] == d))
                self.outflow -= self._fmass[fo].sum(axis=0)
            K.apply_face_fluxes(d, topo["elem_face"], topo["elem_sign"], self._fvol, self._fmass, self._fener,
                                self.vol_m, self.mass_m, self.ener_m)
            K.dual_fluxes(d, self.conn, topo["elem_face"], topo["elem_sign"], topo["elem_nbr"], self.face_open,
                          any_open, self._fmass, topo["node_line"], mnode, pnode, self.order,
                          self._gm, self._gp, self._gk, self._bm, self._bp, self._bk)
            K.apply_dual_fluxes(d, topo["node_elem_ptr"], topo["node_elem_idx"], any_open, self._gm, self._gp, self._gk,
                                self._bm, self._bp, self._bk, mnode, pnode, knode)
        dissip = np.empty_like(mnode)
        K.finish_remap_nodes(mnode, pnode, knode, self.m_floor, self.bc_type, self.bc_normal, self.velocity, self._impulse, dissip)
        self.wall_impulse += self._impulse.sum(axis=0)
        K.nodal_mass(self.mass_m, topo["node_elem_ptr"], topo["node_elem_idx"], self.node_mass)
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

"""``AleBoundaries``: the ALE mesh's boundary conditions, a base of ``AleSystem`` (ale/system.py), which owns the state.

Velocity conditions on nodes (fixed, slip walls, their lines and corners in 3D), open faces (transmitting: the
outside a copy of the inside; non-reflecting: the outside pressure with the radiation impedance, Lysmer &
Kuhlemeyer 1969), inflow faces (a ghost donor state), and what the step takes from them: the outside pressure's
nodal forces (``_external_forces``) and the inflow faces' fluxes (``_inflow_fluxes``).
"""
from __future__ import annotations

import numpy as np

from . import kernels as K
from .fill import inflow_state


class AleBoundaries:
    """The boundary methods of ``AleSystem`` (its arrays: bc_type, bc_normal, velocity, face_open, topo, ...)."""

    def set_fixed(self, node_ids) -> None:
        ids = np.asarray(node_ids, dtype=np.int64)
        self.bc_type[ids] = K.BC_FIXED
        self.velocity[ids] = 0.0

    def set_slip(self, node_ids, normal) -> None:
        ids = np.asarray(node_ids, dtype=np.int64)
        n = np.asarray(normal, dtype=float)
        n = n / np.linalg.norm(n)
        free = self.bc_type[ids] == K.BC_FREE  # most nodes of a wall: they slip along it (vectorised)
        self.bc_type[ids[free]] = K.BC_SLIP
        self.bc_normal[ids[free]] = n
        for i in ids[~free]:  # nodes on an earlier wall or boundary, in order
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

    def set_non_reflecting(self, node_ids, source=None) -> None:
        """Open boundary faces (as ``set_transmit``) that let acoustic waves out.

        The outside pushes on the face with p_far + p', p_far the inside pressure when the side is set
        (the far field at rest), Z = sum_m phi_m sqrt(rho_m K_m) the inside element's acoustic impedance
        (rho c of each material, volume-weighted), c = Z / rho:

        - without ``source``: p' = Z u_n, u_n the face's outward normal velocity (mean of its nodes'). An
          outgoing plane wave carries p' = Z u_n, so the face's nodes feel no force from it: the viscous
          boundary of Lysmer & Kuhlemeyer (1969, J. Eng. Mech. Div. ASCE 95, 859-877), LS-DYNA
          *BOUNDARY_NON_REFLECTING (normal part; a fluid has no shear wave). At an incidence angle theta
          it reflects (cos theta - 1) / (cos theta + 1) of the pressure (-0.09 at 35 degrees).
        - with ``source`` (a point, the charge's centre): p' = Z u_r - k (c / r) I, u_r the velocity along
          the unit vector from the source to the face's centre, r that distance, I = int p' dt the face's
          pressure impulse, k = 1 in 3D and r-z (spherical waves) and 1/2 in plane 2D (cylindrical). For a
          spherical wave p' = f(t - r/c) / r this is exact at any incidence, near field and incompressible
          after-flow included (rho u_r = p' / c + I / r); in plane 2D it is the first-order condition of
          Bayliss & Turkel (1980, Comm. Pure Appl. Math. 33, 707-725), p_t + c p_r + c p / (2 r) = 0.

        The advection through the face is the transmitting one.
        """
        self.set_transmit(node_ids)
        mark = np.zeros(self.x0.shape[0], dtype=bool)
        mark[np.asarray(node_ids, dtype=np.int64)] = True
        fn = self.topo["face_nodes"]
        faces = np.flatnonzero((self.topo["face_elem"][:, 1] < 0) & mark[fn].all(axis=1))
        if self.face_far_pressure is None:
            nf = len(fn)
            self.face_far_pressure = np.full(nf, np.nan)
            self.face_source_distance = np.full(nf, np.inf)
            self.face_source = np.zeros((nf, self.dim))
            self.face_impulse = np.zeros(nf)
        self._state()
        e = self.topo["face_elem"][faces, 0]
        vt = self.vol_m[e].sum(axis=1)
        self.face_far_pressure[faces] = (self.vol_m[e] * self.pres_m[e]).sum(axis=1) / vt
        if source is not None:
            src = np.asarray(source, dtype=float)[: self.dim]
            centre = self.x0[fn[faces]].mean(axis=1)
            self.face_source[faces] = src
            self.face_source_distance[faces] = np.linalg.norm(centre - src, axis=1)

    def _face_normals(self, fo: np.ndarray) -> np.ndarray:
        """Unit outward normals (F, dim) of the boundary faces fo."""
        fnodes = self.topo["face_nodes"][fo]
        q = self.x[fnodes]
        if self.dim == 3:
            n = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
        else:  # (t_y, -t_x), t = x1 - x0: outward for the owner's counter-clockwise order (also r-z)
            t = q[:, 1] - q[:, 0]
            n = np.stack([t[:, 1], -t[:, 0]], axis=1)
        return n / np.linalg.norm(n, axis=1)[:, None]

    def _radiation_pressure(self, fo: np.ndarray, e: np.ndarray, vt: np.ndarray, dt: float) -> np.ndarray:
        """p_far + p' on the non-reflecting faces among fo (``set_non_reflecting``), their impulses advanced
        by p' dt; NaN on the other faces."""
        out = np.full(len(fo), np.nan)
        if self.face_far_pressure is None:
            return out
        p_far = self.face_far_pressure[fo]
        nr = np.flatnonzero(np.isfinite(p_far))
        if len(nr) == 0:
            return out
        f, el = fo[nr], e[nr]
        # Z = sum_m phi_m sqrt(rho_m K_m) = sum_m sqrt(M_m V_m K_m) / V
        z = np.sqrt(self.mass_m[el] * self.vol_m[el] * self.bulk_m[el]).sum(axis=1) / vt[nr]
        fnodes = self.topo["face_nodes"][f]
        u = self.velocity[fnodes].mean(axis=1)
        r = self.face_source_distance[f]
        direction = self._face_normals(f)
        spherical = np.isfinite(r)
        if spherical.any():
            d = self.x[fnodes[spherical]].mean(axis=1) - self.face_source[f[spherical]]
            direction[spherical] = d / np.linalg.norm(d, axis=1)[:, None]
        p = z * (u * direction).sum(axis=1)
        if spherical.any():
            k = 0.5 if self.dim == 2 and not self.axisymmetric else 1.0
            rho = self.mass_m[el].sum(axis=1) / vt[nr]
            c = np.divide(z, rho, out=np.zeros_like(z), where=rho > 0.0)
            p -= np.where(spherical, k * c / r * self.face_impulse[f], 0.0)
            self.face_impulse[f] += p * dt
        out[nr] = p_far[nr] + p
        return out

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
        rho, e, p_in = inflow_state(int(self.mat_eos[m]), self.mat_q[m], float(self.mat_rho0[m]), density, energy,
                                    pressure)
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
        if self.face_inflow is None:
            self.face_inflow = np.full(len(fn), -1, dtype=np.int64)
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

    def _external_forces(self, dt: float) -> np.ndarray:
        f = self._f_ext
        f[:] = 0.0
        if not self.face_open.any():
            return f
        fo = np.flatnonzero(self.face_open)
        n0, n1 = self.topo["face_nodes"][fo, :2].T
        e = self.topo["face_elem"][fo, 0]
        vt = self.vol_m[e].sum(axis=1)
        p = (self.vol_m[e] * self.pres_m[e]).sum(axis=1) / vt
        p_nr = self._radiation_pressure(fo, e, vt, dt)
        p = np.where(np.isnan(p_nr), p, p_nr)
        if self.face_inflow is not None:  # inflow faces: the ghost's own pressure
            ghost = self.face_inflow[fo]
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
        if self.axisymmetric:
            from .axisymmetric import face_pressure_forces
            return face_pressure_forces(self.x, n0, n1, p, f)
        t = self.x[n1] - self.x[n0]
        # the outside, a copy of the inside, pushes inward with its pressure: -p n L / 2 per node
        fx = -0.5 * p * t[:, 1]
        fy = 0.5 * p * t[:, 0]
        np.add.at(f[:, 0], n0, fx)
        np.add.at(f[:, 0], n1, fx)
        np.add.at(f[:, 1], n0, fy)
        np.add.at(f[:, 1], n1, fy)
        return f

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
            if self.axisymmetric:
                from .axisymmetric import quad_ring_volumes
                dv = quad_ring_volumes(l0, w0, w1, l1)
            else:
                # quad (l0, w0, w1, l1): half the cross product of its diagonals (kernels.quad_area)
                dv = 0.5 * ((w1[:, 0] - l0[:, 0]) * (l1[:, 1] - w0[:, 1]) - (w1[:, 1] - l0[:, 1]) * (l1[:, 0] - w0[:, 0]))
        inward = dv > 0.0
        for k, (frac, rho_m, e_m, _) in enumerate(self.inflow_states):
            sel = faces[inward & (self.face_inflow[faces] == k)]
            vol = dv[inward & (self.face_inflow[faces] == k)][:, None] * frac[None, :]
            self._fvol[sel] = vol
            self._fmass[sel] = vol * rho_m
            self._fener[sel] = vol * rho_m * e_m

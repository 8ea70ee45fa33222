"""``LagrangeInSolidCoupling``: an ALE fluid pushing on a Lagrangian structure by penalty (2D, r-z and 3D).

The deck's ``couplings: {type: lagrange_in_solid}`` (LS-DYNA *CONSTRAINED_LAGRANGE_IN_SOLID with
CTYPE 4, penalty coupling). Equations and references: docs/theory/coupling.md.

Each outer face (segment) of the structure carries ``nquad`` coupling points at the midpoints of
equal sub-segments; in 3D each quad face carries nquad x nquad, at the centres of equal cells of
its parameter square, each with its cell's area (coupling_kernels_3d.face_point). Each step, on the state n of both sides (kernels in coupling_kernels, coupling_kernels_3d):

1. every point is located in the ALE mesh (a bucket search, any quad4 mesh). A free point
   (penetration 0) couples only once it has entered fluid: its host is the element containing it
   if that element's coupling-fluid volume fraction is at least ``min_fraction`` and the point
   lies beyond the element's interface reconstructed parallel to the segment
   (``fluid_side_depth``), so no force acts before contact. A point in contact at the last pass keeps the element
   containing it if that holds at least ``min_fraction``, else the element just in front of the
   segment (a probe at half the smallest ALE element size along the outward normal), else, with
   ``leakage_control``, the element just behind it (fluid that has crossed the surface); none:
   the point is free and its penetration 0;
2. penetration d^n = max(0, d^{n-1} + dt^{n-1/2} (v_s - v_f) . n), with v_f the ALE velocity at
   the point from the host's shape functions and v_s the segment's, both at v^{n-1/2} (for the
   ALE, after the remap: the fluid's velocity on the fixed mesh). Tried and measured worse on the
   block-entry test: the Lagrangian-phase velocity before the remap (contact energy dipping to
   -5e-4 of the impact energy instead of -2e-4) and the step-mean velocities the work uses (-8e-3);
3. force f = k d (+ damping 2 zeta sqrt(k m1 m2 / (m1 + m2)) times the closing speed), no tension,
   with k = pfac K A^2 / V (2D per unit depth: A the point's share of the segment length, V the
   host's area; 3D: A the point's share of the face's area, V the host's volume; K = rho0 c0^2 of the coupling fluid in the host); +f n to the host's nodes by its
   shape functions, -f n to the segment's two nodes by theirs.

Axisymmetric (``dimension: axisymmetric``, x = r, y = the axis): the 2D segments and kernels, each
point standing for the ring it sweeps. A = 2 pi r_p l (the ring's area), V the host's ring volume,
the masses ring masses: every force is for the full 2 pi, as the FEM (fem.axisymmetric) and ALE
(ale.axisymmetric) r-z forces, and the penalty layer L_c = V / (pfac A) = n h / pfac as in the plane
(h the meridian element size). A point on the axis (r_p = 0) carries no force; axis nodes of either
side keep u_r = 0 through their own conditions, so no radial force acts there. The interface
reconstruction behind the host search (``fluid_side_depth``) uses the meridian quad with the ring
volume fraction: an O(h / r) shift of the level in a partly filled host near the axis.

The ALE side receives the forces through ``AleSystem.f_couple`` with the impulse weight dt_avg of
the structure's central difference, so the two impulses cancel exactly. The penetration state
(``depth``, ``host``, ``stiff``) is plain numpy arrays, which a checkpoint saves and restores by name
(output.snapshot).
"""
from __future__ import annotations

import numpy as np

from ..ale.kernels import RHO_VOID
from ..materials.tables import eos_sound_speed_set_up
from ..materials.slots import EOS_OFFSET, P_EOS_TYPE, P_RHO0, Q_E0
from ..model.build import VOID
from . import coupling_kernels as ck
from . import coupling_kernels_3d as ck3
from .surface import master_segments


class LagrangeInSolidCoupling:
    """One ``lagrange_in_solid`` coupling inside the explicit loop (solver.explicit's interface)."""

    def __init__(self, sim, spec):
        model = sim.model
        if model.dim not in (2, 3):
            raise ValueError("lagrange_in_solid coupling is 2D or 3D")
        self.dim = model.dim
        self.ring = bool(getattr(model, "axisymmetric", False))  # r-z: points stand for rings
        self.sim = sim
        self.spec = spec
        self.name = f"{spec.fluid}->{spec.structure}"
        self.segments, _ = master_segments(model, spec.structure)
        self.segments = np.ascontiguousarray(self.segments, dtype=np.int64)
        self.nquad = int(spec.nquad)
        ale = sim.ale.system
        mats = model.ale.materials
        wanted = spec.materials
        self.coupling_mats = np.array([
            j for j, m in enumerate(mats)
            if model.material_type[m] != VOID and (wanted is None or model.material_names[m] in wanted)
        ], dtype=np.int64)
        self.mat_bulk = np.zeros(len(mats))
        self.mat_rho0 = np.array([float(model.material_param[m, P_RHO0]) for m in mats])
        for j in self.coupling_mats:
            row = model.material_param[mats[j]]
            q = np.ascontiguousarray(row[EOS_OFFSET:])
            c0 = eos_sound_speed_set_up(int(row[P_EOS_TYPE]), q, 1.0, q[Q_E0])  # the kernel's bits, nothing to compile
            self.mat_bulk[j] = row[P_RHO0] * c0 * c0
        root = 1.0 / self.dim  # the element size h = V^(1/dim); r-z: h = (meridian area)^(1/2)
        self.meridian = _meridian_areas(ale.x, ale.conn) if self.ring else None
        measure = self.meridian if self.ring else ale.vol0
        size = measure.min() ** root
        self.probe = 0.5 * size
        self.cell = float(measure.mean() ** root)
        self.points_per_face = self.nquad ** (self.dim - 1)
        n_points = len(self.segments) * self.points_per_face
        self.depth = np.zeros(n_points)
        self.host = -np.ones(n_points, dtype=np.int64)
        self.stiff = np.zeros(n_points)
        self.f_solid = np.zeros((model.n_nodes, self.dim))
        self.n_coupled = 0
        self.f_fluid = np.zeros_like(ale.f_couple)
        self.v_solid_mid = np.zeros((model.n_nodes, self.dim))  # (v^{n-1/2} + v^{n+1/2}) / 2 of the last step
        self.work = 0.0
        self.penetration_limit = None
        self.pfac = self._auto_pfac(model.coordinates) if spec.pfac == "auto" else float(spec.pfac)

    def _auto_pfac(self, x: np.ndarray) -> float:
        """pfac = 2 n (3D: 2 n^2), n the coupling points per fluid-element face (median over the wetted
        faces of the geometry x): the penalty layer L_c = n h / pfac is then h / 2 there (``layer_in_h``).
        With no face near the fluid, n from the mean element size and the segments' mean point spacing."""
        layer, measure, _ = self._layers(x, 1.0)  # at pfac 1, L_c / h = n (3D: n^2)
        if layer.size:
            return 2.0 * typical_layer(layer, measure)
        seg = x[self.segments]
        span = np.linalg.norm(seg[:, -1] - seg[:, 0], axis=1).mean() / self.nquad
        return 2.0 * (self.cell / span) ** (self.dim - 1) if span > 0 else 1.0

    # ------------------------------------------------------------------ forces
    def _fluid_fields(self, ale):
        """(fraction of coupling fluid, its bulk modulus, element area) per ALE element.

        The bulk modulus is K = sum_m V_m K0_m min(1, rho_m / rho0_m) / sum_m V_m over the coupling
        materials: each material's reference modulus scaled by how much of its volume its mass fills
        at reference density. A host whose fluid has expanded to a trace of its reference density
        (cavitated water at 1e-5 rho0 filling an element, detonation products far expanded) is a
        correspondingly soft spring, so k / m of its nodes stays bounded (about 4 pfac c0^2 l^2 / A^2
        with the host's own mass on its nodes) instead of growing as 1 / rho.
        """
        vol = ale.vol_m.sum(axis=1)
        cm = self.coupling_mats
        vol_c = ale.vol_m[:, cm]
        # as in the ALE kernels, a material below RHO_VOID of its reference density is void (fog the
        # remap left without mass: 1e-15 rho0 of detonation products filled elements above the plate)
        vol_c = np.where(ale.mass_m[:, cm] > RHO_VOID * self.mat_rho0[cm] * vol_c, vol_c, 0.0)
        vc = vol_c.sum(axis=1)
        frac = vc / vol
        # V_m min(1, rho_m / rho0_m) = min(V_m, M_m / rho0_m)
        filled = np.minimum(vol_c, ale.mass_m[:, cm] / self.mat_rho0[cm])
        with np.errstate(invalid="ignore", divide="ignore"):
            bulk = np.where(vc > 0, (filled * self.mat_bulk[cm]).sum(axis=1) / np.where(vc > 0, vc, 1.0), 0.0)
        return np.ascontiguousarray(frac), np.ascontiguousarray(bulk), np.ascontiguousarray(vol)

    def _bins(self, ale):
        x = ale.x
        lo = x.min(axis=0) - self.cell
        hi = x.max(axis=0) + self.cell
        nb = np.maximum(np.ceil((hi - lo) / self.cell).astype(np.int64), 1)
        if self.dim == 3:
            start, items = ck3.build_bins_3d(x, ale.conn, lo, self.cell, int(nb[0]), int(nb[1]), int(nb[2]))
        else:
            start, items = ck.build_bins(x, ale.conn, lo, self.cell, int(nb[0]), int(nb[1]))
        return lo, nb, start, items

    def forces(self, st) -> None:
        """Add the coupling forces of state n to st.f_contact and the ALE's f_couple."""
        ale = self.sim.ale.system
        frac, bulk, area = self._fluid_fields(ale)
        origin, nb, start, items = self._bins(ale)
        self.f_solid[:] = 0.0
        f_ale = self.f_fluid
        f_ale[:] = 0.0
        if self.dim == 3:
            self.n_coupled = ck3.coupling_forces_3d(
                self.segments, st.x, st.v, self.sim.model.mass, self.nquad, ale.x, ale.velocity, ale.node_mass,
                ale.conn, start, items, origin, self.cell, nb, frac, bulk, area,
                float(self.spec.min_fraction), self.pfac, float(self.spec.damping), self.probe,
                bool(self.spec.leakage_control), float(st.dt_prev), self.depth, self.host, self.stiff,
                self.f_solid, f_ale,
            )
            st.f_contact += self.f_solid
            ale.f_couple += f_ale
            ale.pressed[self.host[(self.host >= 0) & (self.depth > 0.0)]] = True
            return
        self.n_coupled = ck.coupling_forces(
            self.segments, st.x, st.v, self.sim.model.mass, self.nquad, ale.x, ale.velocity, ale.node_mass,
            ale.conn, start, items, origin, self.cell, int(nb[0]), int(nb[1]), frac, bulk, area,
            float(self.spec.min_fraction), self.pfac, float(self.spec.damping), self.probe,
            bool(self.spec.leakage_control), float(st.dt_prev), self.ring, self.depth, self.host, self.stiff,
            self.f_solid, f_ale,
        )
        st.f_contact += self.f_solid
        ale.f_couple += f_ale
        # the hosts of the points pressing on the fluid: their void is this structure's volume (the ALE closure)
        ale.pressed[self.host[(self.host >= 0) & (self.depth > 0.0)]] = True

    def layer_in_h(self) -> tuple[np.ndarray, np.ndarray, bool]:
        """``_layers`` of the current geometry at the coupling's pfac."""
        return self._layers(self.sim.state.x, self.pfac)

    def _layers(self, x: np.ndarray, pfac: float) -> tuple[np.ndarray, np.ndarray, bool]:
        """(L_c / h, segment length, wetted) per segment of the geometry x: the penalty's extra fluid layer.

        A point's spring k = pfac K l^2 / V (l = segment length / nquad, V the host's area) is, per
        unit length of the face, k / l = pfac K l / V; a fluid layer of thickness L under bulk
        modulus K is K / L. So the coupling acts as an extra layer L_c = V / (pfac l) = n h / pfac
        in series with the fluid, with h = sqrt(V) and n = h / l the coupling points per fluid
        element face (docs/theory/coupling.md, "Stiffness"). Measured on the initial geometry: a
        segment's host is the ALE element whose centroid is nearest the point half an element in
        front of the segment's midpoint. The segments returned are those whose host holds at least
        min_fraction of coupling fluid (``wetted`` True), else, when none does (a structure that
        enters the fluid later), every segment within one element size of a centroid.

        3D: per quad face (area F), k = pfac K A^2 / V with A = F / nquad^2 is, per unit area,
        pfac K A / V, so L_c = V / (pfac A) = n^2 h / pfac with h = V^(1/3), n = h / sqrt(A); the
        second array is then the faces' areas.

        r-z: A = 2 pi r l at the segment's midpoint and V the host's ring volume, h = sqrt of the
        host's meridian area: L_c = V / (pfac A) = n h / pfac again (V = 2 pi r h^2 near the face).
        """
        from scipy.spatial import cKDTree

        ale = self.sim.ale.system
        if len(self.segments) == 0:
            return np.zeros(0), np.zeros(0), False
        frac, _, _ = self._fluid_fields(ale)
        centroid = ale.x[ale.conn].mean(axis=1)
        if self.dim == 3:
            f = self.segments
            # (x_c - x_a) x (x_d - x_b) = 4 x_r x x_s at the face's centre: outward, |.| / 2 its area
            # when plane (the face's area by its points' shares below)
            diag = np.cross(x[f[:, 2]] - x[f[:, 0]], x[f[:, 3]] - x[f[:, 1]])
            normal = diag / np.maximum(np.linalg.norm(diag, axis=1), 1e-300)[:, None]
            front = x[f].mean(axis=1) + self.probe * normal
            dist, e = cKDTree(centroid).query(front)
            vol = np.abs(ale.vol0[e])
            h = np.cbrt(vol)
            face_area = face_shares_set_up(x, f, self.nquad).reshape(len(f), -1).sum(axis=1)  # no kernel to load
            share = face_area / self.points_per_face
            near = (dist <= h) & (share > 0)
            wet = near & (frac[e] >= float(self.spec.min_fraction))
            keep = wet if wet.any() else near
            return vol[keep] / (pfac * share[keep] * h[keep]), face_area[keep], bool(wet.any())
        t = x[self.segments[:, 1]] - x[self.segments[:, 0]]
        length = np.linalg.norm(t, axis=1)
        normal = np.stack([t[:, 1], -t[:, 0]], axis=1) / np.maximum(length, 1e-300)[:, None]
        front = 0.5 * (x[self.segments[:, 0]] + x[self.segments[:, 1]]) + self.probe * normal
        dist, e = cKDTree(centroid).query(front)
        area = np.abs(ale.vol0[e])
        h = np.sqrt(area)
        ell = length / self.nquad
        if self.ring:  # ring area over ring volume; the element size from the meridian area
            h = np.sqrt(self.meridian[e])
            ell = ell * (2.0 * np.pi * 0.5 * (x[self.segments[:, 0], 0] + x[self.segments[:, 1], 0]))
        near = (dist <= h) & (ell > 0)
        wet = near & (frac[e] >= float(self.spec.min_fraction))
        keep = wet if wet.any() else near
        return area[keep] / (pfac * ell[keep] * h[keep]), length[keep], bool(wet.any())

    def _point_shares(self, x: np.ndarray) -> np.ndarray:
        """Each coupling point's share of its face: length / nquad in 2D, its cell's area in 3D,
        the area 2 pi r_p length / nquad of its ring in r-z."""
        if self.dim == 3:
            share = np.zeros(len(self.segments) * self.points_per_face)
            ck3.face_shares(x, self.segments, self.nquad, share)
            return share
        ell = np.linalg.norm(x[self.segments[:, 1]] - x[self.segments[:, 0]], axis=1) / self.nquad
        share = np.repeat(ell, self.nquad)
        if self.ring:
            r = -1.0 + (2.0 * np.arange(self.nquad) + 1.0) / self.nquad  # the kernel's point positions
            ra = x[self.segments[:, 0], 0][:, None]
            rb = x[self.segments[:, 1], 0][:, None]
            share *= 2.0 * np.pi * (0.5 * (1.0 - r) * ra + 0.5 * (1.0 + r) * rb).ravel()
        return share

    def stable_dt(self) -> float:
        """sqrt(2 m_i / S_i) (1 + zeta^2)^(1/2) - zeta) over the nodes the coupled points load.

        S_i = sum of shape weight x stiffness over the points loading node i (Gershgorin bound of
        the coupling stiffness, see stiffness_sums); m_i the ALE nodal mass, the structure's nodal
        mass, or for a rigid body its mass against the sum over its nodes. inf when nothing couples.
        """
        if not np.any(self.host >= 0):
            return np.inf
        ale = self.sim.ale.system
        model = self.sim.model
        # the stiffness each host would give now, against the nodal masses of now: the step's remap
        # has moved mass since the force pass, and the stored stiffness over the new masses is no
        # bound (a host emptied by the remap: k of before over 1e-17 kg of after)
        _, bulk, area = self._fluid_fields(ale)
        x = self.sim.state.x
        ell = self._point_shares(x)
        h = np.maximum(self.host, 0)
        stiff = np.where(self.host >= 0, self.pfac * bulk[h] * ell * ell / area[h], 0.0)
        sum_s = np.zeros(model.n_nodes)
        sum_a = np.zeros(ale.x.shape[0])
        sums = ck3.stiffness_sums_3d if self.dim == 3 else ck.stiffness_sums
        sums(self.segments, self.nquad, ale.conn, self.host, stiff, x, ale.x, sum_s, sum_a)
        ratios = [sum_a[sum_a > 0] / ale.node_mass[sum_a > 0]]
        mass_s = model.mass.copy()
        rigid = np.zeros(model.n_nodes, dtype=bool)
        for b in model.rigid_bodies:
            rigid[b.nodes] = True
            total = sum_s[b.nodes].sum()
            if total > 0:
                ratios.append(np.array([total / b.mass]))
        free = (~rigid) & (sum_s > 0)
        ratios.append(sum_s[free] / mass_s[free])
        lam = 2.0 * max(float(r.max()) if r.size else 0.0 for r in ratios)
        if not lam > 0:
            return np.inf
        zeta = float(self.spec.damping)
        return 2.0 / np.sqrt(lam) * (np.sqrt(1.0 + zeta * zeta) - zeta)

    def record_work(self, dt: float, dt_avg: float, v_old: np.ndarray, st) -> None:
        """Work of the step's forces: on the structure f . (v^{n-1/2} + v^{n+1/2}) / 2 dt_avg over all
        node components; on the ALE nodes f . v_mid dt_avg with the mean velocity of AleSystem.step's
        nodal update (before the remap), the average its energy update uses."""
        np.add(v_old, st.v, out=self.v_solid_mid)
        self.v_solid_mid *= 0.5
        solid = dt_avg * float(np.sum(self.f_solid * self.v_solid_mid))
        fluid = dt_avg * float(np.sum(self.f_fluid * self.sim.ale.system.v_mid)) if self.n_coupled else 0.0
        self.work += solid + fluid

    # ------------------------------------------------------------------ diagnostics
    def max_penetration(self) -> tuple[float, str]:
        """The deepest penetration of the last force pass and the point that has it."""
        if self.depth.size == 0:
            return 0.0, f"coupling {self.name}"
        i = int(np.argmax(self.depth))
        s, q = divmod(i, self.points_per_face)
        x = self.sim.state.x[self.segments[s]].mean(axis=0)
        if self.dim == 3:
            return float(self.depth[i]), (f"coupling point {q} of face {s} (near x = {x[0]:.4g}, y = {x[1]:.4g}, "
                                          f"z = {x[2]:.4g}) of coupling {self.name}")
        return float(self.depth[i]), (f"coupling point {q} of segment {s} (near x = {x[0]:.4g}, y = {x[1]:.4g}) "
                                      f"of coupling {self.name}")

    def coupled_points(self) -> int:
        """Points that pushed at the last force pass."""
        return self.n_coupled


def face_shares_set_up(xs: np.ndarray, faces: np.ndarray, nquad: int) -> np.ndarray:
    """``coupling_kernels_3d.face_shares`` in numpy: the area share of every coupling point of the quad faces (S, 4),
    point (qr, qs) of face s at (s nquad + qr) nquad + qs. The share of the cell of centre (r, s) = (-1 + (2 qr + 1)
    h, -1 + (2 qs + 1) h), h = 1 / nquad: sum over the 2 x 2 Gauss points (r +- h / sqrt 3, s +- h / sqrt 3) of
    |x_r x x_s| h^2, x_r = ((1 - s)(x_b - x_a) + (1 + s)(x_c - x_d)) / 4, x_s = ((1 - r)(x_d - x_a) + (1 + r)(x_c -
    x_b)) / 4 (``face_point``). The kernel's operations in its order, elementwise over the faces (scalars in Python
    floats, as the kernel's doubles): the same bits (tests/unit/test_setup_numpy.py), with nothing to compile."""
    import math

    gauss = 1.0 / math.sqrt(3.0)  # coupling_kernels_3d._GAUSS2
    corner = [[np.ascontiguousarray(xs[faces[:, j], k]) for k in range(3)] for j in range(4)]
    ba = [corner[1][k] - corner[0][k] for k in range(3)]
    cd = [corner[2][k] - corner[3][k] for k in range(3)]
    da = [corner[3][k] - corner[0][k] for k in range(3)]
    cb = [corner[2][k] - corner[1][k] for k in range(3)]
    h = 1.0 / nquad
    out = np.empty((len(faces), nquad, nquad))
    for qr in range(nquad):
        for qs in range(nquad):
            r = -1.0 + (2.0 * qr + 1.0) * h
            s = -1.0 + (2.0 * qs + 1.0) * h
            share = np.zeros(len(faces))
            for gi in range(2):
                for gj in range(2):
                    rg = r + (2 * gi - 1) * gauss * h
                    sg = s + (2 * gj - 1) * gauss * h
                    ar = [0.25 * ((1.0 - sg) * ba[k] + (1.0 + sg) * cd[k]) for k in range(3)]
                    as_ = [0.25 * ((1.0 - rg) * da[k] + (1.0 + rg) * cb[k]) for k in range(3)]
                    c0 = ar[1] * as_[2] - ar[2] * as_[1]
                    c1 = ar[2] * as_[0] - ar[0] * as_[2]
                    c2 = ar[0] * as_[1] - ar[1] * as_[0]
                    share += np.sqrt(c0 * c0 + c1 * c1 + c2 * c2) * h * h
            out[:, qr, qs] = share
    return out.ravel()


def _meridian_areas(x: np.ndarray, conn: np.ndarray) -> np.ndarray:
    """Shoelace area of every quad4 of the meridian plane (E,): the element size of an r-z mesh."""
    px = x[conn, 0]
    py = x[conn, 1]
    return 0.5 * np.abs((px * np.roll(py, -1, axis=1) - np.roll(px, -1, axis=1) * py).sum(axis=1))


def typical_layer(layer: np.ndarray, measure: np.ndarray) -> float:
    """The median of ``layer`` weighted by ``measure`` (the faces' lengths or areas): a thin plate's
    short edge faces (small l, large L_c / h) carry little of the load and would dominate a maximum."""
    order = np.argsort(layer)
    cum = np.cumsum(measure[order])
    return float(layer[order][np.searchsorted(cum, 0.5 * cum[-1])])

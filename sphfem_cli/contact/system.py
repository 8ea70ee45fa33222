"""Nodes-to-surface penalty contact inside the explicit loop (LS-DYNA *CONTACT_AUTOMATIC_NODES_TO_SURFACE).

Slaves are SPH particles (an SPH part) or nodes (a solid part or a node set); the master is the
outer surface of a solid or rigid part, or a segment set. The interface the loop uses is stated
in solver.explicit; the force law and the search in contact.kernels.
"""
from __future__ import annotations

import numpy as np

from ..deck.schema.interaction import NodesToSurface
from ..materials.slots import P_K
from . import kernels as K
from .surface import master_segments


class NodesToSurfaceContact:
    """One `contacts` entry of the deck."""

    def __init__(self, sim, spec: NodesToSurface):
        model = sim.model
        self.sim, self.spec, self.name = sim, spec, f"{spec.nodes}->{spec.surface}"
        self.dim = model.dim
        self.faces, owner = master_segments(model, spec.surface)
        self.master_nodes = np.unique(self.faces)
        x0 = model.coordinates
        by_part = any(p.name == spec.nodes for p in model.parts)  # else a node set
        self.particle_slaves = by_part and model.parts[model.part_index(spec.nodes)].kind == "sph"
        if self.particle_slaves:
            self.part_index = model.part_index(spec.nodes)
            ps = model.particles
            slave_mass = ps.mass[ps.part == self.part_index]
            self.slave_thickness = 0.5 * ps.spacing if spec.thickness is None else np.full(ps.n, spec.thickness)
        else:
            self.slave_nodes = model.target_nodes(spec.nodes if by_part else None, None if by_part else spec.nodes)
            slave_mass = model.mass[self.slave_nodes]
            edge = min(float(np.min(np.linalg.norm(x0[self.faces[:, (j + 1) % self.faces.shape[1]]] - x0[self.faces[:, j]], axis=1)))
                       for j in range(self.faces.shape[1]))
            thickness = 0.1 * edge if spec.thickness is None else spec.thickness
            self._slave_mask = np.zeros(model.n_nodes, dtype=bool)
            self._slave_mask[self.slave_nodes] = True
            self._slave_mask[self.master_nodes] = False  # a node is never its own master
            self.slave_thickness = np.full(model.n_nodes, thickness)
        self.slave_mass_min = float(slave_mass.min()) if len(slave_mass) else np.inf

        # Segment stiffness k = penalty_scale K A^2 / V (3D), K L^2 / A (2D); depth limit V / A.
        area = self._segment_areas(x0)
        volume = model.volume0[owner]
        bulk = model.material_param[model.element_material[owner], P_K]
        self.seg_k = spec.penalty_scale * bulk * area * area / volume
        self.seg_depth = volume / area
        self.axisymmetric = bool(getattr(model, "axisymmetric", False))
        if self.axisymmetric:
            # r-z: segments sweep rings. seg_k is the meridian stiffness s K L^2 / A (A the meridian area,
            # volume0 holds 2 pi r_c A), and a point's spring is that times its ring 2 pi r_i (see forces);
            # the depth limit is the meridian length A / L.
            area_m = model.volume0[owner] / (2.0 * np.pi * np.maximum(self._owner_radius(model, owner), 1e-300))
            self.seg_k = spec.penalty_scale * bulk * area * area / area_m
            self.seg_depth = area_m / area
            if not self.particle_slaves:
                self._r_tributary = self._tributary_radius(model)
        self.reach = float(self.slave_thickness.max()) if len(slave_mass) else 0.0
        self._k_soft = None  # set on the first step for the soft constraint
        self._master_inv = None  # set on the first step (see _master_compliance)
        self._node_inv = None  # see _node_inverse_mass
        self._seg_inv = None  # see _segment_compliance
        self._initial_gaps_taken = False  # node slaves: see _take_initial_gaps
        self.work = 0.0
        self._f_master = np.zeros((model.n_nodes, self.dim))
        self._seg_of = None
        self._passes = None  # see _passes_per_node

    @staticmethod
    def _owner_radius(model, owner: np.ndarray) -> np.ndarray:
        """r_c of the master faces' elements: volume0 = 2 pi r_c A (model.mesh.ring_volumes)."""
        conn = model.connectivity[owner]
        return model.coordinates[conn, 0].mean(axis=1)

    @staticmethod
    def _tributary_radius(model) -> np.ndarray:
        """r-bar_i = sum_e V0_e / (2 pi sum_e A_e) over a node's elements: the radius of the ring its lumped mass
        rho V0 / 4 stands for (fem.axisymmetric), r_i itself inside a uniform mesh, dr/2 on the axis."""
        conn = model.connectivity
        radius = NodesToSurfaceContact._owner_radius(model, np.arange(len(conn)))
        meridian = model.volume0 / (2.0 * np.pi * np.maximum(radius, 1e-300))
        v = np.zeros(model.n_nodes)
        a = np.zeros(model.n_nodes)
        np.add.at(v, conn, model.volume0[:, None])
        np.add.at(a, conn, meridian[:, None])
        return np.where(a > 0.0, v / (2.0 * np.pi * np.maximum(a, 1e-300)), 0.0)

    def _ring(self, xp: np.ndarray) -> np.ndarray:
        """Per point, the factor on the segment stiffness: 1 in 2D and 3D; in r-z (x = r) the ring 2 pi r a
        particle stands for, or for a node 2 pi max(r_i, r-bar_i) (``_tributary_radius``): a node on the axis
        stands for the ring of its mass, not for nothing (with 2 pi r it had no spring and sank through)."""
        if not self.axisymmetric:
            return np.ones(len(xp))
        if self.particle_slaves:
            return 2.0 * np.pi * xp[:, 0]
        return 2.0 * np.pi * np.maximum(xp[:, 0], self._r_tributary)

    def _segment_areas(self, x: np.ndarray) -> np.ndarray:
        f = self.faces
        if self.dim == 2:
            return np.linalg.norm(x[f[:, 1]] - x[f[:, 0]], axis=1)
        d1, d2 = x[f[:, 2]] - x[f[:, 0]], x[f[:, 3]] - x[f[:, 1]]
        return 0.5 * np.linalg.norm(np.cross(d1, d2), axis=1)

    # ------------------------------------------------------------------------- slave side

    def _slaves(self):
        """(x, v, m, slave mask, thickness) of the slave points at state n."""
        if self.particle_slaves:
            ps = self.sim.particles.system
            mask = ps.active & (self.sim.model.particles.part[ps.ids] == self.part_index)
            return ps.x, ps.v, ps.m, mask, self.slave_thickness[ps.ids]
        st = self.sim.state
        return st.x, st.v, self.sim.model.mass, self._slave_mask, self.slave_thickness

    # ----------------------------------------------------------------------------- loop

    def stable_dt(self) -> float:
        """2/omega (sqrt(1 + zeta^2) - zeta): the contact spring's step, over sqrt(passes) (``_passes_per_node``).

        Penalty: omega^2 = k_max (1 / m_slave_min + max 1 / m_master), the two-mass spring of a slave
        and a master node (``_master_compliance``); soft constraint: omega dt0 = sqrt(soft_scale).
        """
        if self.spec.stiffness == "soft_constraint":
            if self._k_soft is None:
                return np.inf
            omega = np.sqrt(self.spec.soft_scale) / self._dt0
        else:
            if not len(self.seg_k) or not np.isfinite(self.slave_mass_min):
                return np.inf
            if self.axisymmetric:  # k_i / m_i = seg_k 2 pi r_i / m_i: the ring and its mass both scale with r
                xp, _, mp, mask, _ = self._slaves()
                if not mask.any():
                    return np.inf
                per_ring = float(np.max(np.maximum(self._ring(xp)[mask], 0.0) / mp[mask]))
                omega = np.sqrt(float(self.seg_k.max()) * (per_ring + self._master_compliance()))
            else:
                omega = np.sqrt(float(self.seg_k.max()) * (1.0 / self.slave_mass_min + self._master_compliance()))
        zeta = self.spec.damping
        return 2.0 / omega * (np.sqrt(1.0 + zeta * zeta) - zeta) / np.sqrt(self._passes_per_node())

    def _passes_per_node(self) -> int:
        """1 + the other node-slave contacts whose faces hold this one's slave nodes: a node that is a slave
        here and a master node there carries both passes' springs in parallel, omega^2 = (k_a + k_b)(...).
        Two blocks with a contact each way and penalty_scale 1.0 (test_contact._two_blocks) blew up at
        timestep_scale 0.9 with the one-pass bound; stable at 0.6 (0.9 / sqrt 2 = 0.64). Once, on the first call."""
        if self._passes is None:
            self._passes = 1
            if not self.particle_slaves:
                for other in self.sim.interactions:
                    if other is not self and isinstance(other, NodesToSurfaceContact) and not other.particle_slaves \
                            and other.spec.stiffness == "penalty" and np.intersect1d(other.master_nodes, self.slave_nodes).size:
                        self._passes += 1
        return self._passes

    def _node_inverse_mass(self) -> np.ndarray:
        """1 / m of each master node (in master_nodes' order): the nodal mass; a rigid part's node moves with its
        body mass, and a node fixed in every direction does not move (1/m = 0). Once (masses and constraints are fixed)."""
        if self._node_inv is None:
            model = self.sim.model
            nodes = self.master_nodes
            inv = 1.0 / np.maximum(model.mass[nodes], 1e-300)
            for b in model.rigid_bodies:
                inv[np.isin(nodes, b.nodes)] = 1.0 / b.mass
            inv[~self.sim.constraints.free[nodes].any(axis=1)] = 0.0
            self._node_inv = inv
        return self._node_inv

    def _master_compliance(self) -> float:
        """Largest 1 / m over the master nodes (times the ring 2 pi r in r-z), for the two-body spring.

        A slave on a segment and the segment's node form a two-mass spring, omega^2 = k (1/m_s + 1/m_m)
        (node weight 1, the worst case), m_m from ``_node_inverse_mass``. In r-z the node's
        ring factor is taken at its radius plus the longest master edge, a bound on the radius of
        the slaves it meets.
        """
        if self._master_inv is None:
            inv = self._node_inverse_mass().copy()
            if self.axisymmetric:
                x0 = self.sim.model.coordinates
                edge = float(np.max(np.linalg.norm(x0[self.faces[:, 1]] - x0[self.faces[:, 0]], axis=1)))
                inv *= 2.0 * np.pi * (x0[self.master_nodes, 0] + edge)
            self._master_inv = float(inv.max()) if len(inv) else 0.0
        return self._master_inv

    def _segment_compliance(self) -> np.ndarray:
        """Per segment, the largest 1 / m_m over its nodes (``_node_inverse_mass``): the soft constraint's master side.

        The soft spring k = s m_p / dt0^2 sets omega dt0 = sqrt(s) against an immovable master. On a node of
        mass m_m the particle and node form a two-mass spring, omega^2 = k (1/m_p + 1/m_m), so the spring is
        taken from the reduced mass, k = s m_p / (dt0^2 (1 + m_p / m_m)) (``point_forces``), which keeps
        omega dt0 = sqrt(s) whatever the master's mesh (LS-DYNA's SOFT = 1 takes m* = min(m_slave, m_master
        nodes), LSTC FAQ contact.soft1; the reduced mass is within a factor 2 of that). With m_p alone a plate
        refined under the water (structure_in_water_sph, 4 x 60 and 8 x 120 elements: omega dt0 = 1.13 and 2.20)
        blew up. Both masses are whole rings in r-z, so no ring factor enters. Once (masses are fixed).
        """
        if self._seg_inv is None:
            inv = np.zeros(self.sim.model.n_nodes)
            inv[self.master_nodes] = self._node_inverse_mass()
            self._seg_inv = inv[self.faces].max(axis=1) if len(self.faces) else np.zeros(0)
        return self._seg_inv

    def _take_initial_gaps(self, mp: np.ndarray, mask: np.ndarray, point_k: np.ndarray) -> None:
        """Node slaves that start (at the model's initial coordinates) within the contact thickness of a master face keep their initial
        gap (at least 0) as their thickness (LS-DYNA's IGNORE = 1, initial penetrations tracked).

        Bodies meshed touching (a rod on a rod) put every interface slave at gap 0, 0.1 edge inside
        the default thickness: a spring preloaded by k 0.1 edge whose energy is in no initial
        balance; it threw the bodies apart (two touching 5 x 5 blocks: energy ratio 1.096, contact
        energy -69 J). SPH slaves keep the lattice's dx/2, their radius. The gaps are the force pass's
        (``point_forces``) at the initial coordinates, at rest; its outputs are overwritten after.
        """
        self._initial_gaps_taken = True
        x0 = self.sim.model.coordinates
        lo, cell, ncell = self._grid(x0)
        start, segs = K.bin_segments(x0, self.faces, self.reach, lo, cell, ncell)
        at_rest = np.zeros_like(x0)
        K.point_forces(x0, at_rest, mp, mask, self.slave_thickness, x0, at_rest, self.faces, self.seg_k, self.seg_depth,
                       point_k, self._segment_compliance(), self._ring(x0), start, segs, lo, cell, ncell,
                       self.spec.damping, self.spec.friction, self.sim._dt_first or 0.0, self._f_point, self._seg_of,
                       self._weights, self._gap)
        # a gap equal to the thickness to round-off is the zone's edge, no preload: left as it is
        caught = (self._seg_of >= 0) & (self._gap < self.slave_thickness * (1.0 - 1e-9))
        self.slave_thickness[caught] = np.maximum(self._gap[caught], 0.0)

    def forces(self, st) -> None:
        xp, vp, mp, mask, thickness = self._slaves()
        if self.spec.stiffness == "soft_constraint":
            if self._k_soft is None:
                self._dt0 = self.sim._dt_first
                self._k_soft = self.spec.soft_scale / self._dt0 ** 2
            point_k = self._k_soft * mp
        else:
            point_k = np.zeros(len(mp))
        n = len(mp)
        self._f_point = np.zeros((n, self.dim))
        self._seg_of = np.empty(n, dtype=np.int64)
        self._weights = np.zeros((n, self.faces.shape[1]))
        self._gap = np.empty(n)
        if len(self.faces) and mask.any():
            lo, cell, ncell = self._grid(st.x)
            start, segs = K.bin_segments(st.x, self.faces, self.reach, lo, cell, ncell)
            if not self.particle_slaves and not self._initial_gaps_taken:
                self._take_initial_gaps(mp, mask, point_k)
            K.point_forces(xp, vp, mp, mask, thickness, st.x, st.v, self.faces, self.seg_k, self.seg_depth, point_k,
                           self._segment_compliance(), self._ring(xp), start, segs, lo, cell, ncell, self.spec.damping,
                           self.spec.friction, max(st.dt_prev, self.sim._dt_first or 0.0), self._f_point, self._seg_of,
                           self._weights, self._gap)
        self._f_master[:] = 0.0
        K.scatter_reactions(self._f_point, self._seg_of, self._weights, self.faces, self._f_master)
        st.f_contact += self._f_master
        if self.particle_slaves:
            ps = self.sim.particles.system
            ps.f_ext += self._f_point
            self._v_start = ps.v_half.copy() if ps.nsteps else ps.v.copy()  # v^{n-1/2} (v^0 at the start)
        else:
            st.f_contact += self._f_point

    def _grid(self, x: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
        """A cell grid over the master surface grown by the reach; cells about one segment wide."""
        used = x[self.master_nodes]
        lo = used.min(axis=0) - 2.0 * self.reach
        hi = used.max(axis=0) + 2.0 * self.reach
        size = float(np.median(self._segment_areas(x))) ** (1.0 / (self.dim - 1))
        cell = max(size, 2.0 * self.reach, 1e-12 * float(np.max(hi - lo)))
        ncell = np.maximum(1, np.ceil((hi - lo) / cell)).astype(np.int64)
        while np.prod(ncell) > 4 * len(self.faces) + 64:  # a sparse surface in a large box: coarser cells
            cell *= 2.0
            ncell = np.maximum(1, np.ceil((hi - lo) / cell)).astype(np.int64)
        return lo, cell, ncell

    def record_work(self, dt: float, dt_avg: float, v_old: np.ndarray, st) -> None:
        """Work of this contact's forces over the step, as the loop's integrators count it."""
        w = float(np.sum(self._f_master * (v_old + st.v))) * 0.5 * dt_avg
        if self.particle_slaves:
            w += float(np.sum(self._f_point * (self._v_start + self.sim.particles.system.v_half))) * 0.5 * dt_avg
        else:
            w += float(np.sum(self._f_point * (v_old + st.v))) * 0.5 * dt_avg
        self.work += w

    # --------------------------------------------------------------------------- output

    def max_penetration(self) -> tuple[float, str]:
        """Deepest slave below the master surface (positive gap = outside) at the last force pass."""
        if self._seg_of is None or not len(self._seg_of):
            return 0.0, ""
        inside = np.where(self._seg_of >= 0, -self._gap, 0.0)
        i = int(np.argmax(inside))
        if self.particle_slaves:
            return float(inside[i]), f"particle {int(self.sim.particles.system.ids[i])} of contact {self.name}"
        return float(inside[i]), f"node {i} of contact {self.name}"

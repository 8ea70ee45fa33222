"""``AleSystem``: a multi-material ALE (Eulerian by default) fluid on a quad4 (2D) or hex8 (3D) mesh.

Usage::

    from sphfem_cli.model.mesh import box_mesh
    from sphfem_cli.ale import AleOptions, AleSystem, fill_fractions

    mesh = box_mesh([0, 0], [1, 0.01], divisions=[100, 1])
    nodes, conn = mesh.nodes, mesh.elements
    left = fill_fractions(nodes, conn, lambda x, y: x < 0.5)      # (E,) fraction inside
    fr = np.stack([left, 1 - left], axis=1)                          # (E, N) per material
    ale = AleSystem(nodes, conn, materials=[row_a, row_b], fractions=fr,
                    density=[1.0, 0.125], pressure=[1.0, 0.1], options=AleOptions(advection="van_leer"))
    ale.set_slip(bottom_nodes, normal=(0, 1)); ale.set_slip(top_nodes, normal=(0, 1)) ...
    while ale.time < t_end:
        ale.step(min(ale.stable_dt(0.5), t_end - ale.time))
    ale.totals(); ale.density(); ale.pressure(); ale.velocity

Constructor arguments:

- ``nodes`` (N, 2), ``conn`` (E, 4) counter-clockwise quad4 (``model.mesh.box_mesh`` order), or
  ``nodes`` (N, 3), ``conn`` (E, 8) hex8 in VTK order (``box_mesh`` in 3D): the same method with
  three sweep directions (docs/theory/ale.md, "3D"); vectors below have 3 components there;
- ``materials``: one entry per material, a parameter row of ``materials.tables.pack_material``
  (or its ``(type id, row)`` pair), or ``None`` for void (no mass, no pressure);
- ``fractions`` (E, N) initial volume fractions (rows summing to 1; see ``fill.fill_fractions``);
- ``density`` (N,) or (E, N) initial material densities; ``energy`` specific internal energies
  [energy/mass] or ``pressure`` (the energy then follows from the EOS), each (N,) or (E, N)
  (``fill.material_state``);
- ``velocity`` (dim,) or (N, dim) initial nodal velocity;
- ``options``: ``options.AleOptions`` (advection, interface, closure, viscosities, cut-off,
  mesh motion ``options.MeshMotion`` ...); default ``AleOptions()``.

Its parts: ``topology`` (faces, maps, dual node lines), ``motion`` (where the remap puts the
mesh), ``fill`` (the initial state), ``kernels`` (the numba phases); this class holds the state
and steps it.

Boundaries (node index arrays): ``set_slip(nodes, normal)`` normal velocity zero,
``set_fixed(nodes)`` velocity zero, ``set_transmit(nodes)`` boundary faces whose two nodes are in
the set are open (outflow / zero-gradient inflow, with the inside pressure applied outside),
``set_non_reflecting(nodes)`` open faces with an impedance (rho c) outside pressure that lets a plane
acoustic wave out,
``set_inflow(nodes, material, velocity, density, energy | pressure)`` inflow of a material at a
given state (ghost donor, prescribed nodal velocity).
Nodes in two slip sets with different normals become fixed (3D: they slide along the two walls'
intersection; a third wall makes them fixed).

Body force and structure coupling: ``gravity`` (dim,) acceleration on the nodal masses;
``f_couple`` (N, dim) coupling forces of the step (contact.coupling), with their work accumulated
in ``gravity_work`` and ``coupling_work``; ``step(dt, couple_dt)`` gives the coupling forces the
impulse weight couple_dt.

Methods: ``stable_dt(scale)``, ``step(dt)``, ``totals()`` (mass per material, momentum,
kinetic, internal and total energy, accumulated wall impulse), ``material_totals()`` (mass,
internal and kinetic energy per material); accessors ``fractions()``,
``density()`` (per material, 0 where absent), ``pressure()`` (per material and mixture),
``mixture_density()``, ``centroids()``, ``velocity`` (N, dim), ``node_mass``, ``time``.
"""
from __future__ import annotations

from collections.abc import Sequence
from functools import partial

import numpy as np

from ..materials.burn import burn_fraction, lighting_time, quad_size
from ..model.pages import set_up_pages
from . import kernels as K
from .at_rest import initial_element_pass
from .boundaries import AleBoundaries
from .fill import material_state, material_tables
from .motion import MeshMover
from .options import AleOptions
from .topology import build_topology, largest_face_area

_INTERFACES = {"donor": K.IFACE_DONOR, "slic": K.IFACE_SLIC}
_PI_3 = np.pi / 3.0  # ring_geometry.PI_3 (math.pi / 3.0)
_HEX_CHUNK = 1 << 14  # elements per chunk of hex8_volumes_set_up and quad_areas_set_up


def ring_volumes_set_up(x: np.ndarray, conn: np.ndarray) -> np.ndarray:
    """The exact ring volume (pi / 3) S of every quad4 of the meridian plane (x = r, y = z), (E,), with
    S = (r0 + r1)(r0 z1 - r1 z0) + (r1 + r2)(r1 z2 - r2 z1) + (r2 + r3)(r2 z3 - r3 z2) + (r3 + r0)(r3 z0 - r0 z3)
    (Green's theorem over the four edges; ``ale.axisymmetric`` module docstring): the operations of
    ``axisymmetric.ring_volumes`` (``ring_geometry.ring_volume``) elementwise in their order, so the same bits
    (tests/unit/test_setup_numpy.py), with no kernel to compile or load before the first step."""
    r = [np.ascontiguousarray(x[conn[:, a], 0]) for a in range(4)]
    z = [np.ascontiguousarray(x[conn[:, a], 1]) for a in range(4)]
    s = (r[0] + r[1]) * (r[0] * z[1] - r[1] * z[0])
    for i, j in ((1, 2), (2, 3), (3, 0)):
        s += (r[i] + r[j]) * (r[i] * z[j] - r[j] * z[i])
    return _PI_3 * s


def hex8_volumes_set_up(x: np.ndarray, conn: np.ndarray) -> np.ndarray:
    """The exact trilinear volume of every hex8, (E,), as ``energy.element_volumes_3d`` computes it: the corners
    relative to corner 0 (p_a = x_a - x_0) into ``fem.geometry.hex8_volume_origin`` (V = (1/12) sum s x_I (y_j z_k -
    y_k z_j) over the rows of ``fem.tables.HEX_DV``, written out). Its Python body (``py_func``) on arrays does the
    kernel's IEEE operations elementwise in the same order (no fused multiply-add in either), so the same bits
    (tests/unit/test_setup_numpy.py), with no kernel to compile or load before the first step; by chunks of
    elements, so that the 21 corner columns and the temporaries stay small."""
    from ..fem.geometry import hex8_volume_origin

    out = np.empty(len(conn))
    for lo in range(0, len(conn), _HEX_CHUNK):
        c = conn[lo:lo + _HEX_CHUNK]
        origin = [x[c[:, 0], k] for k in range(3)]
        corners = [x[c[:, a], k] - origin[k] for a in range(1, 8) for k in range(3)]
        out[lo:lo + _HEX_CHUNK] = hex8_volume_origin.py_func(*corners)
    return out


def node_sums_set_up(terms: np.ndarray, node_elem_ptr: np.ndarray, node_elem_idx: np.ndarray, npe: int) -> np.ndarray:
    """s_I = the sum over node I's element corners, in ``node_elem_idx``'s order (its elements ascending), of the terms
    terms[e, 0], terms[e, 1], ... of each corner's element e in turn, from 0: the sums of the kernel
    ``remap_nodes.nodal_mass`` (terms (1/npe) M_em) in their order, so the same bits (tests/unit/test_setup_numpy.py),
    with nothing to compile before the first step. By corner slots (every node's j-th corner at once, j up to the
    largest node degree), so that the temporaries are node-sized (the former np.bincount over the repeated
    (element, corner, material) terms took 118 MB of fresh memory at 960^2, two materials)."""
    start = node_elem_ptr[:-1]
    degree = np.diff(node_elem_ptr)
    out = np.zeros(len(start))
    for j in range(int(degree.max(initial=0))):
        nodes = np.flatnonzero(degree > j)
        elem = node_elem_idx[start[nodes] + j] // npe
        for m in range(terms.shape[1]):
            out[nodes] += terms[elem, m]
    return out


def quad_areas_set_up(x: np.ndarray, conn: np.ndarray) -> np.ndarray:
    """The area A = ((x2 - x0)(y3 - y1) - (y2 - y0)(x3 - x1)) / 2 of every quad4 (E,) (half the cross product of its
    diagonals), by chunks of elements on contiguous corner columns (fresh memory is the set-up's cost: the whole-mesh
    corner columns were 59 MB at 960^2); elementwise, so every chunk size gives the same bits."""
    xs, ys = np.ascontiguousarray(x[:, 0]), np.ascontiguousarray(x[:, 1])
    out = np.empty(len(conn))
    for lo in range(0, len(conn), _HEX_CHUNK):
        c = conn[lo:lo + _HEX_CHUNK]
        cx = [xs[c[:, a]] for a in range(4)]
        cy = [ys[c[:, a]] for a in range(4)]
        out[lo:lo + _HEX_CHUNK] = 0.5 * ((cx[2] - cx[0]) * (cy[3] - cy[1]) - (cy[2] - cy[0]) * (cx[3] - cx[1]))
    return out


_CLOSURES = {"equal_strain": K.CLOSURE_EQUAL_STRAIN, "relax": K.CLOSURE_RELAX}


class AleSystem(AleBoundaries):
    """Multi-material ALE fluid on a quad4 or hex8 mesh (see the module docstring)."""

    @set_up_pages()  # numpy's huge-page advice off for the arrays made here (model/pages.py)
    def __init__(self, nodes, conn, materials: Sequence, fractions, density, energy=None, pressure=None,
                 velocity=None, options: AleOptions | None = None, axisymmetric: bool = False):
        self.options = opt = AleOptions() if options is None else options
        self.x0 = np.ascontiguousarray(nodes, dtype=np.float64)
        if self.x0.ndim != 2 or self.x0.shape[1] not in (2, 3):
            raise ValueError("AleSystem nodes must be (N, 2) or (N, 3)")
        self.dim = dim = self.x0.shape[1]
        self.conn = np.ascontiguousarray(conn, dtype=np.int64)
        self.npe = npe = 4 if dim == 2 else 8
        if self.conn.ndim != 2 or self.conn.shape[1] != npe:
            raise ValueError(f"AleSystem needs {'quad4 (E, 4)' if dim == 2 else 'hex8 (E, 8)'} connectivity in {dim}D")
        n_nodes, n_elem = self.x0.shape[0], self.conn.shape[0]
        self.axisymmetric = axisymmetric = bool(axisymmetric)
        if axisymmetric:
            if dim != 2:
                raise ValueError("an axisymmetric AleSystem is a quad4 mesh of the meridian plane (x = r, y = the axis)")
            if np.any(self.x0[:, 0] < 0.0):
                raise ValueError("an axisymmetric AleSystem lies in x = r >= 0 (y is the axis)")
        self.n_mat = n_mat = len(materials)
        self.mat_eos, self.mat_q, self.mat_rho0, rows = material_tables(materials)
        # the options as the kernels take them
        self.order = opt.order
        self.iface = _INTERFACES[opt.interface]
        self.closure = _CLOSURES[opt.closure]
        self.pressure_cutoff = -np.inf if opt.pressure_cutoff is None else float(opt.pressure_cutoff)

        self.topo = build_topology(self.conn, n_nodes)
        self.mesh = MeshMover(opt.motion, self.x0, self.conn, self.topo)
        if axisymmetric:
            self.vol0 = ring_volumes_set_up(self.x0, self.conn)  # axisymmetric.ring_volumes' bits, in numpy
        elif dim == 2:
            self.vol0 = quad_areas_set_up(self.x0, self.conn)
        else:
            self.vol0 = hex8_volumes_set_up(self.x0, self.conn)  # energy.element_volumes_3d's bits, in numpy
        if np.any(self.vol0 <= 0):
            raise ValueError("elements with non-positive " + ("area (node order must be counter-clockwise)" if dim == 2
                             else "volume (hex8 corners in VTK order: bottom face counter-clockwise seen from above)"))
        self.vol_m, self.mass_m, self.ener_m = material_state(rows, self.vol0, fractions, density, energy, pressure)
        # specific energy added to the stored one where the EOS is evaluated: the second half of the last
        # Lagrangian step's own p dV work (energy.lagrange_energy; zero at the start)
        self.e_lag = np.zeros(self.ener_m.shape)

        self.x = self.x0.copy()
        self.velocity = np.zeros((n_nodes, dim))
        if velocity is not None:
            self.velocity[:] = np.asarray(velocity, dtype=float)
        self.node_mass = np.zeros(n_nodes)
        # nodal mass floor: mass_floor times the node's share of its elements filled at the largest
        # reference density (velocity of a near-empty node is not computed from momentum / mass)
        rho_ref = float(self.mat_rho0.max()) if n_mat else 0.0
        ptr, idx = self.topo["node_elem_ptr"], self.topo["node_elem_idx"]
        full = node_sums_set_up((rho_ref * self.vol0 / npe)[:, None], ptr, idx, npe)  # (np.add.at's bits)
        self.m_floor = float(opt.mass_floor) * full
        self.node_mass[:] = node_sums_set_up((1.0 / npe) * self.mass_m, ptr, idx, npe)  # K.nodal_mass's bits
        self.bc_type = np.zeros(n_nodes, dtype=np.int64)
        self.bc_normal = np.zeros((n_nodes, dim))
        self.face_open = np.zeros(len(self.topo["face_nodes"]), dtype=np.bool_)
        self.wall_impulse = np.zeros(dim)
        self.outflow = np.zeros(n_mat)  # net mass leaving through open faces (diagnostic; inflow counts negative)
        # per face, made by the first set_inflow (None until then): inflow faces' index into the inflow states
        # (-1: none); per state the material fractions, densities, specific energies and pressure of the outside
        # (ghost) donor
        self.face_inflow = None
        # per face, made by the first set_non_reflecting (None until then): the far-field pressure outside (the
        # inside pressure when the side was set; NaN elsewhere), with a source the face's distance to it (inf
        # without), the source and the face's pressure impulse int (p - p_far) dt (at 960^2 these five arrays,
        # filled eagerly, were 59 MB of fresh memory before the first step of a mesh that had no such face)
        self.face_far_pressure = self.face_source_distance = self.face_source = self.face_impulse = None
        self.inflow_states: list[tuple[np.ndarray, np.ndarray, np.ndarray, float]] = []
        self.time = 0.0
        self.n_steps = 0
        self._since_remap = 0
        self._allocate(n_nodes, n_elem)
        if axisymmetric:  # the axis: u_r = 0 on its nodes (they slide along it)
            self.set_slip(np.flatnonzero(self.x0[:, 0] == 0.0), (1.0, 0.0))

    def _allocate(self, n_nodes: int, n_elem: int) -> None:
        """Work arrays of the kernels, and the coupling interface (gravity, f_couple, v_mid)."""
        dim, npe, n_mat = self.dim, self.npe, self.n_mat
        self.f_elem = np.zeros((n_elem, npe, dim))
        self.pscale = np.ones((n_elem, n_mat))  # pressure factor per material (programmed burn)
        self.burn = None  # [(material, lighting time (E,), D, element size (E,))]: set_burn
        self.pres_m = np.zeros((n_elem, n_mat))
        self.bulk_m = np.zeros((n_elem, n_mat))
        self.q_elem = np.zeros(n_elem)
        self.dt_elem = np.zeros(n_elem)
        self.work_elem = np.zeros(n_elem)
        self._fresh = False  # f_elem, pres_m, bulk_m, q_elem, dt_elem are the force kernel's of the current state
        self._fresh_state = False  # pres_m, bulk_m, q_elem, dt_elem are (from the initial pass, ``_state``)
        nf = len(self.topo["face_nodes"])
        self._fvol = np.zeros((nf, n_mat))
        self._fmass = np.zeros((nf, n_mat))
        self._fener = np.zeros((nf, n_mat))
        self._flow = np.zeros(nf, dtype=np.bool_)  # the face swept volume this sweep (remap.face_fluxes)
        n_edges = npe // 2  # element edges along one sweep direction
        # dual-edge fluxes (mass, kinetic energy, momentum per row: dual.G_MASS, G_KIN, G_MOM) and the node velocities
        self._g = np.zeros((n_elem, n_edges, K.G_MOM + dim))
        self._b = np.zeros((n_elem, n_edges, 2, K.G_MOM + dim))
        self._moving = np.zeros(n_elem, dtype=np.bool_)  # mass crosses the element's dual faces (dual.dual_fluxes)
        self._unode = np.zeros((n_nodes, dim))
        self._impulse = np.zeros((n_nodes, dim))
        self._f_ext = np.zeros((n_nodes, dim))
        # the step's node-sized work arrays (no allocation per step)
        self._v_old = np.zeros((n_nodes, dim))
        self._mnode = np.zeros(n_nodes)
        self._pnode = np.zeros((n_nodes, dim))
        self._knode = np.zeros(n_nodes)
        self._dissip = np.zeros(n_nodes)
        self._x_lag = np.zeros((n_nodes, dim))
        self._vrange = np.zeros((n_elem, 2, dim))  # the elements' corner velocity ranges (remap_nodes.finish_nodes)
        self._ranged = np.zeros(n_elem, dtype=np.bool_)  # mass crossed the element in a sweep of this remap
        # body acceleration on the nodal masses, and the forces of couplings to structures
        # (contact.coupling): set f_couple before each step; its impulse is couple_dt * f_couple
        self.gravity = np.zeros(dim)
        self.f_couple = np.zeros((n_nodes, dim))
        # elements a structure presses on this step (a coupling point with positive penetration hosted there; set
        # with f_couple): the mixed-element closure takes their void for the structure's volume (lagrange_energy)
        self.pressed = np.zeros(n_elem, dtype=np.bool_)
        self.gravity_work = 0.0
        self.coupling_work = 0.0
        self.v_lag = np.zeros((n_nodes, dim))  # v^{n+1/2} of the Lagrangian phase, before the remap (each step's)
        self.v_mid = np.zeros((n_nodes, dim))  # (v^{n-1/2} + v^{n+1/2}) / 2 of the last Lagrangian phase
        # one compiled kernel per element kind (quad4, hex8) and, for the forces, per geometry (ale/kernels.py);
        # the plane and the r-z quad4 share the energy and face kernels (the ring flag), all three geometries face_fluxes
        ring = self.axisymmetric
        if ring:
            from .axisymmetric import lagrange_forces_rz  # the ring's own (ale/lagrange.py, above lagrange_forces)
            self._k_forces = lagrange_forces_rz
        elif dim == 2:
            self._k_forces = K.lagrange_forces
        if dim == 2:
            self._k_nodal, self._k_finish = K.nodal_update, K.finish_remap_nodes
            self._k_energy = partial(K.lagrange_energy, ring=ring)
        else:
            self._k_forces, self._k_nodal, self._k_energy = K.lagrange_forces_3d, K.nodal_update_3d, K.lagrange_energy_3d
            self._k_finish = K.finish_remap_nodes_3d
        self._k_faces = partial(K.face_fluxes, ring=ring)

    def set_burn(self, materials, velocities, detonations) -> None:
        """Programmed burn (``materials.burn``) of the given materials (indices) with detonation
        velocities D: lighting times at the element centroids of the initial (Eulerian) mesh from
        ``detonations`` [(point, time), ...], element size area / longest edge."""
        centroids = self.x0[self.conn].mean(axis=1)
        delta = quad_size(self.x0, self.conn) if self.dim == 2 else self.vol0 / largest_face_area(self.x0, self.conn)
        self.burn = [(int(m), lighting_time(centroids, detonations, float(d)), float(d), delta)
                     for m, d in zip(materials, velocities)] or None
        self._fresh = False
        self._fresh_state = False

    # ---------------------------------------------------------------- stepping
    def _burn_scale(self) -> None:
        """pscale of the burning materials at the current time (``materials.burn``)."""
        if self.burn is not None:
            for m, t_light, d, delta in self.burn:
                self.pscale[:, m] = burn_fraction(self.time, t_light, d, delta)

    def _forces(self) -> None:
        self._burn_scale()
        opt = self.options
        self._k_forces(self.x, self.velocity, self.conn, self.vol_m, self.mass_m, self.ener_m, self.e_lag,
                       self.mat_eos, self.mat_q, self.mat_rho0, opt.q1, opt.q2, opt.hourglass, opt.phi_eps,
                       self.pscale, self.pressure_cutoff, self.f_elem, self.pres_m, self.bulk_m, self.q_elem, self.dt_elem)
        self._fresh = True

    def _initial_pass(self) -> bool:
        """Before the first step: pres_m, bulk_m, q_elem and dt_elem of the state from ``at_rest`` (numpy, the
        force kernel's bits; ``sphfem check`` then compiles no force kernel). False, nothing written, after the
        first step or where the pass does not cover the state."""
        if self.n_steps:
            return False
        self._burn_scale()
        opt = self.options
        return initial_element_pass(self.x, self.velocity, self.conn, self.vol_m, self.mass_m, self.ener_m, self.e_lag,
                                    self.mat_eos, self.mat_q, self.mat_rho0, opt.q1, opt.q2, opt.phi_eps, self.pscale,
                                    self.pressure_cutoff, self.axisymmetric, self.pres_m, self.bulk_m, self.q_elem,
                                    self.dt_elem)

    def _state(self) -> None:
        """pres_m, bulk_m, q_elem and dt_elem of the current state, if they are not yet: the initial pass where it
        applies (f_elem is then left to the first step's force kernel), else the force kernel."""
        if self._fresh or self._fresh_state:
            return
        if self._initial_pass():
            self._fresh_state = True
        else:
            self._forces()

    def stable_dt(self, scale: float = 0.5) -> float:
        """scale times the smallest element step l / (Q + sqrt(Q^2 + (c + |v|)^2)) (eq. 2.9)."""
        self._state()
        return float(scale * self.dt_elem.min())

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
        v_old = self._v_old
        f_ext = self._external_forces(dt)
        has_gravity = bool(np.any(self.gravity))
        if has_gravity:
            f_ext += self.node_mass[:, None] * self.gravity
        w_couple = dt if couple_dt is None else couple_dt
        has_couple = bool(np.any(self.f_couple))
        if has_couple:
            f_ext += self.f_couple * (w_couple / dt)
        lagrangian = self.options.motion.mesh_motion == "lagrangian"
        remap = not lagrangian and self._since_remap + 1 >= self.options.advect_every
        # x_lag = x + v^{n+1/2} dt, written by the nodal update (with v_old, v_lag and v_mid): into the work
        # array when the remap consumes it this step, else fresh (it becomes self.x, which callers may hold)
        x_lag = self._x_lag if remap else np.empty_like(self.x)
        v_mid = self.v_mid
        self._k_nodal(self.f_elem, topo["node_elem_ptr"], topo["node_elem_idx"], f_ext,
                      self.node_mass, self.m_floor, self.velocity, self.bc_type, self.bc_normal, dt, self._impulse,
                      self.x, v_old, v_mid, self.v_lag, x_lag)
        if has_gravity:
            self.gravity_work += dt * float(np.sum(self.node_mass * (v_mid @ self.gravity)))
        if has_couple:
            self.coupling_work += w_couple * float(np.sum(self.f_couple * v_mid))
        K.add_column_sums(self._impulse, self.wall_impulse)  # wall_impulse += impulse.sum(axis=0), same bits
        self._k_energy(self.x, v_old, self.velocity, dt, self.conn, self.f_elem, self.vol_m, self.mass_m,
                       self.ener_m, self.e_lag, self.pres_m, self.bulk_m, self.q_elem, self.closure, self.options.relax_alpha,
                       self.options.relax_beta, self.options.phi_eps, self.pressed, self.work_elem)
        self._since_remap += 1
        if lagrangian:
            self.x = x_lag
        elif remap:
            x_new = self.mesh.target(x_lag)
            self._remap(x_lag, x_new)
            self.x = x_new
            self._since_remap = 0
        else:
            self.x = x_lag
        self.time += dt
        self.n_steps += 1
        self._fresh = False
        self._fresh_state = False

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
        mnode, pnode, knode = self._mnode, self._pnode, self._knode
        K.remap_nodal_state(self.node_mass, self.velocity, mnode, pnode, knode)
        any_open = bool(self.face_open.any())
        ranged = self._ranged
        ranged[:] = False
        for d in self._sweep_order():
            ka, kb = topo["side_a"][d], topo["side_b"][d]
            self._k_faces(topo["faces_by_dir"][d], topo["face_nodes"], topo["face_elem"], topo["face_local"],
                          topo["elem_nbr"], self.face_open, x_lag, x_new, self.vol_m, self.mass_m, self.ener_m,
                          self.order, self.iface, self.options.phi_eps, self._fvol, self._fmass, self._fener,
                          self._flow)
            if any_open:
                fo = topo["faces_by_dir"][d]
                fo = fo[self.face_open[fo]]  # the open faces of this direction, ascending
                if self.face_inflow is not None:
                    self._inflow_fluxes(fo[self.face_inflow[fo] >= 0], x_lag, x_new)
                self.outflow -= self._fmass[fo].sum(axis=0)
            K.apply_face_fluxes(ka, kb, topo["elem_face"], topo["elem_sign"], self._fvol, self._fmass, self._fener,
                                self._flow, self.vol_m, self.mass_m, self.ener_m)
            K.node_velocities(mnode, pnode, self.m_floor, self._unode)
            K.dual_fluxes(ka, kb, d, self.conn, topo["elem_face"], topo["elem_sign"], topo["elem_nbr"], self.face_open,
                          any_open, self._fmass, topo["node_line"], mnode, self._unode, self.order, self._g, self._b,
                          self._moving)
            K.apply_dual_fluxes(topo["corner_edge"][d], topo["corner_dst"][d], topo["node_elem_ptr"],
                                topo["node_elem_idx"], any_open, self._g, self._b, self._moving, mnode, pnode, knode)
            np.logical_or(ranged, self._moving, out=ranged)  # the velocity bound's element ranges: where mass crossed
        dissip = self._dissip
        # the velocity bound from per-element corner ranges (remap_nodes.finish_nodes) where mass crossed at least a
        # quarter of the elements: the ranges cost 2.5 ns per element, the corner scan they replace about 11 ns
        # per bounded node (240^2, 1 thread: finish 6.7 -> 9-11 ns per cell at rest, 25 -> 14 in a vortex)
        # hex8: where mass crossed at least 1/32 of the elements (a bounded node's scan reads 8 elements x 8 corners
        # x 3 components, the ranges cost about 10 ns per element)
        use_ranges = (4 if self.dim == 2 else 32) * int(np.count_nonzero(ranged)) >= len(ranged)
        self._k_finish(mnode, pnode, knode, self.m_floor, self.v_lag, self.conn, topo["node_elem_ptr"],
                       topo["node_elem_idx"], self.bc_type, self.bc_normal, self.velocity, self._impulse, dissip,
                       self._vrange, use_ranges)
        K.add_column_sums(self._impulse, self.wall_impulse)  # wall_impulse += impulse.sum(axis=0), same bits
        K.nodal_mass(self.mass_m, topo["node_elem_ptr"], topo["node_elem_idx"], self.npe, self.node_mass)
        K.finish_remap_elements(self.conn, self.mass_m, self.ener_m, self.node_mass, dissip, self.options.ke_fix)

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
        if not self._initial_pass():
            self._forces()
        if mixture:
            return (self.fractions() * self.pres_m).sum(axis=1)
        return self.pres_m.copy()

    def centroids(self) -> np.ndarray:
        return self.x[self.conn].mean(axis=1)

    def element_velocity(self) -> np.ndarray:
        return self.velocity[self.conn].mean(axis=1)

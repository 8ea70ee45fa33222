"""``SphBoundaryCoupling``: an SPH fluid on a structure through boundary particles the structure carries (2D).

The deck's ``couplings: {type: sph_boundary}``. Behind every outer face of the structure (segment
a -> b, outward normal n to the right of a -> b, contact/surface.py) lie ``layers`` rows of boundary
particles at depths d_l = (l + 1/2) dx, l = 0 .. layers - 1 (dx the fluid's spacing); along the outline a row
is sampled per face (``sampling: face``: n_s = round(L_0 / dx) particles at parameters s_k = (k + 1/2) / n_s, each
standing for ds = L_0 / n_s) or by arc length (``sampling: arc_length``: every ds ~ dx along each run of faces
between corners, ``arc_length_sampling``), each particle on one face at parameter s, of mass rho_0 ds dx.
Each step, at state n, every particle is placed from the face's nodes,

    x_w = (1 - s) x_a + s x_b - d n,      v_w = (1 - s) v_a + s v_b,      a_w = (1 - s) a_a + s a_b

(a_w from the nodes' velocities of the last two steps with ``wall_acceleration``, else 0; the rotation
of n is not in v_w), its
pressure is extrapolated from the fluid on its face's side (``sph.structure_walls.wall_state``,
Adami et al. 2012 with g - a_w; with ``extrapolation: mdbc`` its density is the fluid's extrapolated to first
order from a ghost node mirrored through the face, or through the convex vertex for the particles behind a
corner, ``wall_state_mdbc``), and the pair terms with that fluid are added to the particles'
rates (``wall_pairs``): the forces to ``f_ext``, the continuity and energy terms to ``drho`` and
``de``. With ``corner_particles: once`` a particle that coincides with particles of other faces (behind a convex
corner, where two faces' layers overlap) counts 1 / k for a fluid point that sees k of them
(``structure_walls``). The reaction on each boundary particle goes to its face's nodes with weights 1 - s and s,
so fluid + structure momentum is conserved to round-off.

Energy: the fluid's internal-energy gain from the wall pairs, q = sum_i m_i de_i (``wall_pairs``), is
no work of f_ext, so it is booked on the fluid's side (subtracted from ``SphSystem.wall_energy``,
which the fluid's work subtracts); the interaction's ``work`` is the work of its forces on the
particles and the nodes (as the loop's integrators weigh them) plus q, and the energy table books
-work as contact energy: the share of the pair work the boundary absorbs, as ``wall_energy`` does
for fixed dummy walls.
"""
from __future__ import annotations

import math

import numpy as np

from ..deck.schema.interaction import SphBoundary
from ..materials.kernels import EOS_OFFSET, P_EOS_TYPE, P_RHO0
from ..materials.slots import Q_E0
from ..sph import structure_walls as sw
from ..sph.eos import sound_speed
from ..sph.kernel_functions import kernel_w
from ..sph.slots import SI_KERNEL
from .surface import master_segments


# a vertex where the outline's tangent turns by more than this is a corner: arc_length sampling anchors its runs there
CORNER_TURN = math.radians(30.0)


def face_sampling(x0: np.ndarray, faces: np.ndarray, dx: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One row of boundary particles, face by face: n_s = max(1, round(L_0 / dx)) per face at s_k = (k + 1/2) / n_s,
    each standing for L_0 / n_s of the face. Returns (face, s, arc spacing) per particle."""
    length = np.linalg.norm(x0[faces[:, 1]] - x0[faces[:, 0]], axis=1)
    n_s = np.maximum(1, np.round(length / dx)).astype(np.int64)
    seg = np.repeat(np.arange(len(faces), dtype=np.int64), n_s)
    k = np.arange(len(seg)) - np.repeat(np.cumsum(n_s) - n_s, n_s)
    return seg, (k + 0.5) / n_s[seg], (length / n_s)[seg]


def outline_runs(x0: np.ndarray, faces: np.ndarray) -> list[list[int]]:
    """The faces (a -> b) as runs of consecutive faces between corners: each chain of connected faces (a face's b is
    the next face's a) is walked in order, a closed chain from one of its corners, and cut at every vertex where the
    tangent turns by more than CORNER_TURN (convex or concave) and at an open chain's ends. A closed chain without
    corners (a faceted circle) is one run."""
    t = x0[faces[:, 1]] - x0[faces[:, 0]]
    t = t / np.maximum(np.linalg.norm(t, axis=1), 1e-300)[:, None]
    nxt = {int(a): g for g, a in enumerate(faces[:, 0])}
    ends = {int(b) for b in faces[:, 1]}

    def corner(f: int, g: int) -> bool:  # between face f and the next face g
        return float(np.clip(t[f] @ t[g], -1.0, 1.0)) < math.cos(CORNER_TURN)

    seen = np.zeros(len(faces), dtype=bool)
    chains = []
    starts = [f for f in range(len(faces)) if int(faces[f, 0]) not in ends] + list(range(len(faces)))
    for f0 in starts:  # open chains from their first face, then the closed ones
        if seen[f0]:
            continue
        chain, f = [], f0
        while f is not None and not seen[f]:
            seen[f] = True
            chain.append(f)
            f = nxt.get(int(faces[f, 1]))
        if f == chain[0]:  # closed: start it after a corner if it has one
            cut = [i for i in range(len(chain)) if corner(chain[i - 1], chain[i])]
            if cut:
                chain = chain[cut[0]:] + chain[: cut[0]]
        chains.append(chain)
    runs = []
    for chain in chains:
        run = [chain[0]]
        for f, g in zip(chain[:-1], chain[1:]):
            if corner(f, g):
                runs.append(run)
                run = []
            run.append(g)
        runs.append(run)
    return runs


def arc_length_sampling(x0: np.ndarray, faces: np.ndarray, dx: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One row of boundary particles by arc length along the outline, refining with the fluid whatever the faces'
    lengths: each run of ``outline_runs`` (length L, from corner to corner) carries n = max(1, round(L / dx)) particles
    at arcs (k + 1/2) L / n from its first corner, each on the face that holds its arc at that face's parameter s, and
    standing for ds = L / n of the outline. Anchored at the corners, the rows of the two faces of a convex vertex meet
    there as two lattices of pitch ds along the faces and dx in depth: where ds = dx (a side a whole number of
    spacings) the square behind the vertex holds coincident pairs, which ``corner_particles: once`` counts once, as on
    a particle lattice. Returns (face, s, arc spacing) per particle."""
    length = np.linalg.norm(x0[faces[:, 1]] - x0[faces[:, 0]], axis=1)
    seg, s, ds = [], [], []
    for run in outline_runs(x0, faces):
        lengths = length[run]
        start = np.concatenate([[0.0], np.cumsum(lengths)])
        n = max(1, int(round(start[-1] / dx)))
        arc = (np.arange(n) + 0.5) * (start[-1] / n)
        k = np.clip(np.searchsorted(start, arc, side="right") - 1, 0, len(run) - 1)
        seg.append(np.asarray(run, dtype=np.int64)[k])
        s.append((arc - start[k]) / lengths[k])
        ds.append(np.full(n, start[-1] / n))
    if not seg:
        return np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0)
    seg, s, ds = np.concatenate(seg), np.concatenate(s), np.concatenate(ds)
    order = np.argsort(seg, kind="stable")  # by face, along each face
    return seg[order], s[order], ds[order]


class SphBoundaryCoupling:
    """One ``sph_boundary`` coupling inside the explicit loop (solver.explicit's interface)."""

    def __init__(self, sim, spec: SphBoundary):
        model = sim.model
        self.sim, self.spec, self.name = sim, spec, f"{spec.fluid}->{spec.structure}"
        if model.dim != 2 or getattr(model, "axisymmetric", False):
            raise ValueError("sph_boundary coupling is 2D plane only")
        self.dim = model.dim
        self.faces, _ = master_segments(model, spec.structure)
        ps = sim.particles.system
        self.part_index = model.part_index(spec.fluid)
        mine = model.particles.part == self.part_index
        self.spacing = dx = float(np.median(model.particles.spacing[mine]))
        self.material = int(np.bincount(model.particles.material[mine]).argmax())
        ratio = float(ps.options.smoothing_ratio)
        self.layers = spec.layers or int(math.ceil(2.0 * ratio - 1e-9))
        self.slip = spec.condition == "slip"
        x0 = np.asarray(model.coordinates, dtype=np.float64)
        rho0 = float(ps.params[self.material, P_RHO0])
        sample = arc_length_sampling if spec.sampling == "arc_length" else face_sampling
        row_seg, row_s, row_ds = sample(x0, self.faces, dx)
        seg, s, depth, mass = [], [], [], []
        for l in range(self.layers):
            seg.append(row_seg)
            s.append(row_s)
            depth.append(np.full(len(row_seg), (l + 0.5) * dx))
            mass.append(rho0 * row_ds * dx)
        order = np.argsort(np.concatenate(seg), kind="stable")  # face, then layer, then along the face
        seg, s, depth, mass = (np.concatenate(a)[order] for a in (seg, s, depth, mass))
        self.seg = np.asarray(seg, dtype=np.int64)
        self.s = np.asarray(s, dtype=np.float64)
        self.depth = np.asarray(depth, dtype=np.float64)
        self.ws = np.zeros((len(self.seg), sw.NW))
        self.ws[:, sw.W_M] = mass
        self.ws[:, sw.W_H] = ratio * dx
        self.ws[:, sw.W_RHO] = rho0
        self.f_wall = np.zeros((len(self.seg), 3))
        self.f_nodes = np.zeros((model.n_nodes, self.dim))
        self.f_fluid = np.zeros((ps.n, self.dim))
        self._v_prev = None
        self._dt_prev = 0.0
        self.work = 0.0
        self._power = 0.0
        self._v_start = None
        # mDBC's ghost nodes: through the face, or through the convex vertex the particle's coincident group shares
        # (``_corner_ghosts``, from the first placement)
        self.mdbc = spec.extrapolation == "mdbc"
        self.vertex = np.full(len(self.seg), -1, dtype=np.int64)
        self.place(x0, np.zeros_like(x0), np.zeros_like(x0))
        coincident = (self._coincident(self.particles())
                      if spec.corner_particles == "once" or self.mdbc else None)
        self.twins = (coincident if spec.corner_particles == "once"
                      else np.full((len(self.seg), 1), -1, dtype=np.int64))
        self.side2 = np.full(len(self.seg), -1, dtype=np.int64)
        self.mdbc_order = np.zeros(len(self.seg), dtype=np.int64)  # 1 first order, 0 Shepard, -1 no fluid seen
        self.mdbc_cond = np.zeros(len(self.seg))  # the scaled system's condition number
        if self.mdbc:
            self._corner_ghosts(coincident, x0)
            self.place(x0, np.zeros_like(x0), np.zeros_like(x0))

    def _corner_ghosts(self, twins: np.ndarray, x0: np.ndarray) -> None:
        """For every particle with coincident particles of other segments (the squares behind the convex corners,
        where two faces' layers overlap): the convex vertex of its face nearest to it at the start (``vertex``: its
        ghost is mirrored through that vertex), and a coincident particle of the other face at that vertex
        (``side2``: the ghost sees the fluid on that face's side too). A convex vertex joins segments f = a -> b and
        g = b -> c with t_f x t_g > 0 (a left turn: with the outward normals to the right of a -> b the boundary runs
        counter-clockwise)."""
        faces = self.faces
        t = x0[faces[:, 1]] - x0[faces[:, 0]]
        t = t / np.linalg.norm(t, axis=1)[:, None]
        normal = np.stack([t[:, 1], -t[:, 0]], axis=1)
        starts = {int(a): g for g, a in enumerate(faces[:, 0])}
        corners = {}  # vertex node -> the outward normals of its two segments
        for f, b in enumerate(faces[:, 1]):
            g = starts.get(int(b))
            if g is not None and t[f, 0] * t[g, 1] - t[f, 1] * t[g, 0] > 1e-6:
                corners[int(b)] = (normal[f], normal[g])
        if not corners:
            return
        nodes = np.fromiter(corners, dtype=np.int64)
        pos = self.particles()
        for w in range(len(self.seg)):
            row = [o for o in twins[w] if o >= 0]
            if not row:
                continue
            own = normal[self.seg[w]]
            mine = [v for v in nodes if max(float(n @ own) for n in corners[v]) > 0.99]  # corners of its face
            if not mine:
                continue
            v = int(mine[int(np.argmin(np.linalg.norm(x0[mine] - pos[w], axis=1)))])
            other = [n for n in corners[v] if float(n @ own) < 0.5]
            match = [o for o in row if float(normal[self.seg[o]] @ other[0]) > 0.99]
            if match:
                self.vertex[w], self.side2[w] = v, match[0]

    def _coincident(self, pos: np.ndarray) -> np.ndarray:
        """(Nw, K) int64: for every particle (at ``pos``, the start) the particles of other faces within dx / 4
        of it (the squares where two faces' layers overlap behind a convex corner), -1 padded; K >= 1."""
        from scipy.spatial import cKDTree
        near = cKDTree(pos).query_ball_point(pos, 0.25 * self.spacing) if len(pos) else []
        others = [[o for o in near[w] if self.seg[o] != self.seg[w]] for w in range(len(pos))]
        twins = np.full((len(pos), max([1, *map(len, others)])), -1, dtype=np.int64)
        for w, row in enumerate(others):
            twins[w, : len(row)] = sorted(row)
        return twins

    # ------------------------------------------------------------------ particles from nodes

    def place(self, x: np.ndarray, v: np.ndarray, a: np.ndarray) -> None:
        """Positions, velocities, accelerations, face points and normals of the particles from the nodes."""
        ia, ib = self.faces[self.seg, 0], self.faces[self.seg, 1]
        t = x[ib] - x[ia]
        length = np.linalg.norm(t, axis=1)
        normal = np.stack([t[:, 1], -t[:, 0]], axis=1) / np.maximum(length, 1e-300)[:, None]
        s = self.s[:, None]
        face = (1.0 - s) * x[ia] + s * x[ib]
        ws = self.ws
        ws[:, sw.W_FX:sw.W_FY + 1] = face
        ws[:, sw.W_NX:sw.W_NY + 1] = normal
        ws[:, sw.W_X:sw.W_Y + 1] = face - self.depth[:, None] * normal
        if self.mdbc:  # ghost nodes: x_f + d n through the face, 2 x_v - x_w through a vertex
            ghost = face + self.depth[:, None] * normal
            at = self.vertex >= 0
            ghost[at] = 2.0 * x[self.vertex[at]] - ws[at, sw.W_X:sw.W_Y + 1]
            ws[:, sw.W_GX:sw.W_GY + 1] = ghost
        ws[:, sw.W_VX:sw.W_VY + 1] = (1.0 - s) * v[ia] + s * v[ib]
        ws[:, sw.W_AX:sw.W_AY + 1] = (1.0 - s) * a[ia] + s * a[ib]

    def particles(self) -> np.ndarray:
        """(Nw, 2) positions of the boundary particles now."""
        return self.ws[:, sw.W_X:sw.W_Y + 1].copy()

    # ----------------------------------------------------------------------------- loop

    def face_stiffness(self) -> float:
        """k = K W1(0) [N/m per m of face, per unit depth]: the normal stiffness the boundary particles put on a face.

        Linearised about rest (the pressure's own geometric term p grad grad W dropped: p << K), for a face moved by
        delta along its normal against a fluid half-space at rest: the continuity term of ``wall_pairs`` changes a
        fluid point's density at distance z by sum_w m_w delta . grad W_iw = rho_0 W1(z) delta (the wall's layers a
        half-space of density rho_0 m_w / (dx^2) = rho_0 reaching past 2 h: ``layers`` >= 2 h / dx; W1(z) =
        int W(sqrt(z^2 + y^2)) dy, the kernel projected on the normal), its pressure by K rho W1 delta / rho_0 = K W1(z)
        delta (K = rho_0 c^2), and Adami's p_w, a Shepard mean of those, by no more than K W1(0) delta. The normal
        force on the face, sum_i sum_w m_i m_w (dp_i + dp_w) / rho_0^2 dW/dz, is per unit length then
        K delta int_0^inf W1(z)^2 dz + K delta W1(0) int_0^inf W1 dz <= K delta W1(0) (W1 <= W1(0), int_0^inf W1 = 1/2).
        W1(0) = 2 int_0^{2h} W(r) dr (15 / (7 pi h) for the 2D cubic spline), h = smoothing_ratio dx; c the largest of
        the reference sound speed and the boundary particles' of the last step."""
        ps = self.sim.particles.system
        if getattr(self, "_w1", None) is None:
            h = float(self.ws[0, sw.W_H]) if len(self.ws) else 1.0
            kernel = int(ps.settings_i[SI_KERNEL])
            r = (np.arange(400) + 0.5) * (2.0 * h / 400)  # midpoint rule on [0, 2h]
            self._w1 = 2.0 * sum(kernel_w(kernel, 2, float(ri), h) for ri in r) * (2.0 * h / 400)
            eos, q = int(ps.params[self.material, P_EOS_TYPE]), ps.params[self.material, EOS_OFFSET:]
            self._c_ref = float(sound_speed(eos, q, 1.0, q[Q_E0]))
        rho0 = float(ps.params[self.material, P_RHO0])
        c = max(self._c_ref, float(self.ws[:, sw.W_C].max()) if len(self.ws) else 0.0)
        return rho0 * c * c * self._w1

    def node_stiffness(self, x: np.ndarray) -> np.ndarray:
        """(n_nodes,) S_i = sum over the faces of node i of k L_f / 2 (L_f the face's length at x): the row sum of
        the coupling's stiffness on the node (a face's force k L_f (u_a + u_b) . n / 2 goes half to each node, its
        boundary particles at s and 1 - s symmetric)."""
        length = np.linalg.norm(x[self.faces[:, 1]] - x[self.faces[:, 0]], axis=1)
        share = 0.5 * self.face_stiffness() * length
        stiff = np.zeros(x.shape[0])
        np.add.at(stiff, self.faces[:, 0], share)
        np.add.at(stiff, self.faces[:, 1], share)
        return stiff

    def stable_dt(self) -> float:
        """min_i sqrt(2 m_i / S_i) over the face nodes (the loop multiplies it by timestep_scale).

        The Gershgorin bound of ``ElementCoupling.stable_dt`` (contact/coupling.py) with S_i of ``node_stiffness``:
        k = K W1(0) per unit face length, K = rho_0 c^2 the fluid's bulk modulus, W1(0) = 2 int_0^{2h} W dr ~ 1 / dx
        (so the step scales as sqrt(dx)); m_i the structure's nodal mass, or for a rigid body its mass against the
        sum over its nodes. The fluid particles' side of the pairs is the fluid's CFL (the SPH domain's step).
        inf when the coupling has no boundary particles."""
        if not len(self.ws):
            return np.inf
        model = self.sim.model
        stiff = self.node_stiffness(self.sim.state.x)
        rigid = np.zeros(model.n_nodes, dtype=bool)
        ratios = [np.zeros(0)]
        for b in model.rigid_bodies:
            rigid[b.nodes] = True
            total = stiff[b.nodes].sum()
            if total > 0:
                ratios.append(np.array([total / b.mass]))
        free = (~rigid) & (stiff > 0) & (model.mass > 0)
        ratios.append(stiff[free] / model.mass[free])
        top = max(float(r.max()) if r.size else 0.0 for r in ratios)
        return math.sqrt(2.0 / top) if top > 0 else np.inf

    def forces(self, st) -> None:
        """Place the particles at state n, extrapolate their pressures, add the pair terms to the fluid's
        rates (of state n, computed by the SPH domain's stable_dt) and the reactions to the nodes."""
        ps = self.sim.particles.system
        # wall acceleration from the nodes' last two velocities v^{n-1/2}, v^{n-3/2}
        if not self.spec.wall_acceleration or self._v_prev is None or self._dt_prev <= 0.0:
            acc = np.zeros_like(st.v)
        else:
            acc = (st.v - self._v_prev) / (0.5 * (self._dt_prev + st.dt_prev))
        self._dt_prev = st.dt_prev
        self._v_prev = st.v.copy()
        self.place(st.x, st.v, acc)
        pts = ps._sorted
        self.f_wall[:] = 0.0
        if self.f_fluid.shape[0] != ps.n:
            self.f_fluid = np.zeros((ps.n, self.dim))
        self.f_fluid[:] = 0.0
        self._power = 0.0
        if len(self.ws) and pts is not None:
            # the slots of this coupling's SPH part (another part has its own coupling)
            perm = pts["perm"]
            mine = np.zeros(pts["sx"].shape[1], dtype=np.bool_)
            real = np.flatnonzero(perm < ps.n)
            mine[real] = self.sim.model.particles.part[ps.ids[perm[real]]] == self.part_index
            args = (pts["sx"], pts["sd"], mine)
            if self.mdbc:
                sw.wall_state_mdbc(self.ws, self.side2, self.material, *args, pts["cell_start"], ps.settings_f,
                                   ps.settings_i, pts["grid_f"], pts["grid_i"], ps.params, self.mdbc_order,
                                   self.mdbc_cond)
            else:
                sw.wall_state(self.ws, self.material, *args, pts["cell_start"], ps.settings_f, ps.settings_i,
                              pts["grid_f"], pts["grid_i"], ps.params)
            self._power = sw.wall_pairs(self.ws, self.twins, self.slip, *args, pts["perm"], pts["cell_start"], ps.settings_f,
                                        ps.settings_i, pts["grid_f"], pts["grid_i"], self.f_fluid, ps.drho, ps.de,
                                        self.f_wall)
        ps.f_ext += self.f_fluid
        self.f_nodes[:] = 0.0
        fw = self.f_wall[:, : self.dim]
        np.add.at(self.f_nodes, self.faces[self.seg, 0], (1.0 - self.s)[:, None] * fw)
        np.add.at(self.f_nodes, self.faces[self.seg, 1], self.s[:, None] * fw)
        st.f_contact += self.f_nodes
        self._v_start = ps.v_half.copy() if ps.nsteps else ps.v.copy()  # v^{n-1/2} (v^0 at the start)

    def record_work(self, dt: float, dt_avg: float, v_old: np.ndarray, st) -> None:
        """Work of the forces on nodes and particles over the step, as the loop's integrators weigh them, plus
        the fluid's internal energy from the wall pairs (the kick's weight dt_avg)."""
        ps = self.sim.particles.system
        w = float(np.sum(self.f_nodes * (v_old + st.v))) * 0.5 * dt_avg
        w += float(np.sum(self.f_fluid * (self._v_start + ps.v_half))) * 0.5 * dt_avg
        heat = self._power * dt_avg
        self.work += w + heat
        # the fluid's internal energy from the wall pairs is no work of f_ext: book it on the fluid's side
        # as the dummy walls' share is booked (SphSystem.wall_energy, subtracted from the fluid's work)
        ps.wall_energy -= heat

    # --------------------------------------------------------------------------- output

    def coupled_points(self) -> int:
        """Boundary particles of the coupling."""
        return len(self.ws)

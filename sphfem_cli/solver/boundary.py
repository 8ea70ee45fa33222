"""Kinematic conditions, loads and rigid bodies: everything the loop applies at the nodes."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.build import Model, RigidBody


class Curves:
    """Named piecewise-linear time curves, constant beyond their ends; None means 1."""

    def __init__(self, model: Model):
        self._tables = {
            name: (np.array([p[0] for p in c.points]), c.scale * np.array([p[1] for p in c.points]))
            for name, c in model.options.curves.items()
        }

    def __call__(self, name: str | None, t: float) -> float:
        if name is None:
            return 1.0
        ts, fs = self._tables[name]
        return float(np.interp(t, ts, fs))


@dataclass
class _Prescribed:
    nodes: np.ndarray
    components: list[tuple[int, float]]
    curve: str | None


class Constraints:
    """Fixed, symmetry and prescribed-velocity conditions as a free mask and prescribed values."""

    def __init__(self, model: Model, curves: Curves):
        self.curves = curves
        self.free = np.ones((model.n_nodes, model.dim), dtype=np.bool_)
        self.v_prescribed = np.zeros((model.n_nodes, model.dim))
        self.prescribed: list[_Prescribed] = []
        self.rigid_prescribed: dict[int, list[tuple[int, float, str | None]]] = {}
        self.rigid_held: set[int] = set()  # rigid parts fixed in every direction or hold_rotation: no spin
        rigid_parts = {b.part: b for b in model.rigid_bodies}
        if model.axisymmetric:  # the axis (r = 0): u_r = 0 on its nodes, always (model.checks.radii puts them at 0)
            self.free[model.coordinates[:, 0] == 0.0, 0] = False
        for bc in model.options.solids.conditions:
            comps, curve = list(bc.components), bc.curve
            if bc.part is not None and model.part_index(bc.part) in rigid_parts:
                entry = self.rigid_prescribed.setdefault(model.part_index(bc.part), [])
                entry.extend((k, val, curve) for k, val in comps)
                if bc.holds_body:
                    self.rigid_held.add(model.part_index(bc.part))
                continue
            nodes = model.target_nodes(bc.part, bc.set)
            for k, _ in comps:
                self.free[nodes, k] = False
            if any(val != 0.0 for _, val in comps):
                self.prescribed.append(_Prescribed(nodes, comps, curve))

    def update(self, t: float) -> None:
        """Prescribed velocities at time t (the mid-step time of the update that uses them)."""
        for p in self.prescribed:
            scale = self.curves(p.curve, t)
            for k, val in p.components:
                self.v_prescribed[p.nodes, k] = val * scale


class Loads:
    """External nodal forces: gravity, follower pressure on segments, nodal forces."""

    def __init__(self, model: Model, curves: Curves):
        self.model = model
        self.curves = curves
        self.gravity = []
        solids = model.options.solids
        for load in solids.gravity:
            mask = np.zeros(model.n_nodes, dtype=bool)
            for name in load.parts or [p.name for p in model.parts]:
                mask[model.part_nodes(name)] = True
            weight = np.where(mask, model.mass, 0.0)[:, None] * np.array(load.acceleration)[None, :]
            self.gravity.append((weight, load.curve))
        self.pressures = [(model.segment_sets[l.set], l.value, l.curve) for l in solids.pressures]
        self.axisymmetric = model.axisymmetric
        self.nodal = [(model.node_sets[l.set], np.array(l.force), l.curve) for l in solids.nodal_forces]
        self.active = bool(self.gravity or self.pressures or self.nodal)

    def compute(self, t: float, x: np.ndarray, out: np.ndarray) -> None:
        out[:] = 0.0
        for weight, curve in self.gravity:
            out += self.curves(curve, t) * weight
        for nodes, force, curve in self.nodal:
            out[nodes] += self.curves(curve, t) * force
        for segs, value, curve in self.pressures:
            p = value * self.curves(curve, t)
            if p == 0.0:
                continue
            area_vectors = _segment_area_vectors(x, segs)
            if self.axisymmetric:
                _ring_pressure(x, segs, -p * area_vectors, out)
                continue
            share = -p * area_vectors / segs.shape[1]
            for a in range(segs.shape[1]):
                np.add.at(out, segs[:, a], share)


def _ring_pressure(x: np.ndarray, segs: np.ndarray, edge_force: np.ndarray, out: np.ndarray) -> None:
    """Nodal forces of a pressure on the ring an r-z edge (a, b) sweeps: the ring force -p n L 2 pi r_m,
    r_m = (r_a + r_b)/2 (the exact area of the frustum), half to each node (`edge_force` is -p (dy, -dx)).

    Equal halves, not the consistent 2 pi (2 r_a + r_b)/6 split: the one-point element
    (fem.axisymmetric) spreads its ring weight 2 pi r_c evenly over its nodes too, so that a uniform
    stress balances a uniform pressure node by node (the patch test; the consistent split leaves an
    error of about 20 % at the axis, measured on a hydrostatically loaded solid cylinder).
    """
    share = edge_force * (0.5 * np.pi * (x[segs[:, 0], 0] + x[segs[:, 1], 0]))[:, None]
    np.add.at(out, segs[:, 0], share)
    np.add.at(out, segs[:, 1], share)


def _segment_area_vectors(x: np.ndarray, segs: np.ndarray) -> np.ndarray:
    """Outward area vector of each segment: 2D edge (dy, -dx); 3D quad half the diagonals' cross product."""
    if segs.shape[1] == 2:
        d = x[segs[:, 1]] - x[segs[:, 0]]
        return np.stack([d[:, 1], -d[:, 0]], axis=1)
    d1 = x[segs[:, 2]] - x[segs[:, 0]]
    d2 = x[segs[:, 3]] - x[segs[:, 1]]
    return 0.5 * np.cross(d1, d2)


class RigidBodies:
    """Rigid parts integrated as bodies; their nodes follow exactly (no straight-line drift).

    2D: centre c, angle theta, velocity V, spin omega; 3D: rotation matrix R, spin vector omega
    with Euler's equations in the world frame, I_w = R I0 R^T. Axisymmetric (x = r): a body of
    revolution moves along the axis only (V = (0, V_z), no spin): the radial resultant of its rings'
    forces is zero by symmetry, its axial one is the sum of the nodes' whole-ring forces, and its
    mass the sum of its ring masses (the model's masses are for the full 2 pi).
    """

    def __init__(self, model: Model, constraints: Constraints, curves: Curves):
        self.bodies: list[RigidBody] = model.rigid_bodies
        self.dim = model.dim
        self.axial_only = bool(model.axisymmetric)
        self.curves = curves
        self.constraints = constraints
        self.x0 = model.coordinates
        self.mass = model.mass
        self.center = [b.center.copy() for b in self.bodies]
        self.rotation = [np.eye(self.dim) for _ in self.bodies]
        self.velocity = [np.zeros(self.dim) for _ in self.bodies]
        self.spin = [np.zeros(1 if self.dim == 2 else 3) for _ in self.bodies]
        for b in self.bodies:
            constraints.free[b.nodes] = False

    def set_initial_velocity(self, v: np.ndarray) -> None:
        """Body velocity = momentum of its nodes' initial velocities over its mass (no initial spin)."""
        for i, b in enumerate(self.bodies):
            self.velocity[i] = (self.mass[b.nodes, None] * v[b.nodes]).sum(axis=0) / b.mass
            if self.axial_only:
                self.velocity[i][0] = 0.0
            v[b.nodes] = self.velocity[i]

    def kick(self, force: np.ndarray, t_mid: float, dt_avg: float, x: np.ndarray) -> None:
        """Advance body velocities by the resultant of `force` on their nodes; set their nodes' velocities."""
        for i, b in enumerate(self.bodies):
            f = force[b.nodes]
            r = x[b.nodes] - self.center[i]
            self.velocity[i] = self.velocity[i] + dt_avg * f.sum(axis=0) / b.mass
            if self.axial_only:
                self.velocity[i][0] = 0.0
            elif self.dim == 2:
                torque = float((r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0]).sum())
                self.spin[i] = self.spin[i] + dt_avg * torque / float(b.inertia)
            else:
                torque = np.cross(r, f).sum(axis=0)
                iw = self.rotation[i] @ b.inertia @ self.rotation[i].T
                w = self.spin[i]
                self.spin[i] = w + dt_avg * np.linalg.solve(iw, torque - np.cross(w, iw @ w))
            for k, val, curve in self.constraints.rigid_prescribed.get(b.part, []):
                self.velocity[i][k] = val * self.curves(curve, t_mid)  # r-z: only y (deck check)
            if b.part in self.constraints.rigid_held:
                self.spin[i] = np.zeros_like(self.spin[i])
            self.constraints.v_prescribed[b.nodes] = self._node_velocity(i, r)

    def drift(self, dt: float, x: np.ndarray) -> None:
        """Move each body by dt and place its nodes exactly."""
        for i, b in enumerate(self.bodies):
            self.center[i] = self.center[i] + dt * self.velocity[i]
            if self.axial_only:  # a translation along the axis: the radii stay exactly as they are
                x[b.nodes] = self.x0[b.nodes] + (self.center[i] - b.center)
                continue
            if self.dim == 2:
                a = dt * float(self.spin[i][0])
                c, s = np.cos(a), np.sin(a)
                self.rotation[i] = np.array([[c, -s], [s, c]]) @ self.rotation[i]
            else:
                self.rotation[i] = _cayley(0.5 * dt * self.spin[i]) @ self.rotation[i]
            r0 = self.x0[b.nodes] - b.center
            x[b.nodes] = self.center[i] + r0 @ self.rotation[i].T

    def _node_velocity(self, i: int, r: np.ndarray) -> np.ndarray:
        if self.dim == 2:
            w = float(self.spin[i][0])
            return self.velocity[i] + w * np.stack([-r[:, 1], r[:, 0]], axis=1)
        return self.velocity[i] + np.cross(self.spin[i], r)


def _cayley(a: np.ndarray) -> np.ndarray:
    """(I - A)^-1 (I + A) for the skew matrix A of axial vector a: an exact rotation."""
    skew = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + 2.0 / (1.0 + a @ a) * (skew + skew @ skew)

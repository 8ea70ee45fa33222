"""The Lagrangian solids (solid parts' nodes and elements) as a domain of the explicit loop (solver.domain).

Step n -> n+1, with forces F^n known (paper eq. 2.7):
  1. rigid bodies and prescribed velocities fix v^{n+1/2} on constrained components;
  2. v^{n+1/2} = v^{n-1/2} + dt_avg F^n/m, x^{n+1} = x^n + dt v^{n+1/2} (fem.kernels);
  3. element kernels: stress^{n+1}, internal forces F_int^{n+1}, stable steps;
  4. loads F_ext^{n+1}; after the step, the solids' stable step timestep_scale * min element dt.
The solids' arrays and the loop's clock are one `State` (`Simulation.state`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fem.at_rest import at_rest_element_pass
from ..fem.slots import INVERTED
from ..materials.slots import EOS_OFFSET, H_EPS, NHIST, P_EOS_TYPE, P_RHO0, Q_E0
from .boundary import Constraints, Curves, Loads, RigidBodies
from .domain import Domain, Energies
from .guards import RunStopped

TOPOLOGY = {4: "Quadrilateral", 8: "Hexahedron"}


@dataclass
class State:
    """Everything of the solids that evolves, and the loop's clock. Arrays are (N, dim) for nodes,
    (E, ...) for elements.

    `dt` is the solids' stable step for the next step; `dt_prev` the step last taken.
    """

    time: float
    step: int
    dt: float
    x: np.ndarray
    v: np.ndarray
    f_int: np.ndarray
    f_ext: np.ndarray
    stress: np.ndarray
    hist: np.ndarray
    energy: np.ndarray
    hg_energy: np.ndarray
    hg_force: np.ndarray
    volume: np.ndarray
    q_visc: np.ndarray
    node_power: np.ndarray
    f_contact: np.ndarray
    dt_prev: float = 0.0
    external_work: float = 0.0
    initial_energy: float = 0.0


def von_mises(stress: np.ndarray) -> np.ndarray:
    """sqrt(3/2 s:s) of the deviator, stress (E, 6) in order xx, yy, zz, xy, yz, zx."""
    p = stress[:, :3].mean(axis=1)
    s = stress[:, :3] - p[:, None]
    shear = stress[:, 3:]
    return np.sqrt(1.5 * (np.sum(s * s, axis=1) + 2.0 * np.sum(shear * shear, axis=1)))


class SolidDomain(Domain):
    """The solid parts: constraints, loads, rigid bodies, element forces and erosion."""

    kind = "solid"
    label = "solid"

    def __init__(self, sim):
        self.sim = sim
        model = sim.model
        self.model = model
        self.control = sim.control
        self.curves = Curves(model)
        self.constraints = Constraints(model, self.curves)
        self.loads = Loads(model, self.curves)
        self.rigid = RigidBodies(model, self.constraints, self.curves)
        self.inv_mass = 1.0 / model.mass
        self._f_elem = np.zeros((model.n_elements, model.nodes_per_element, model.dim))
        self._dt_elem = np.zeros(model.n_elements)
        self.has_solids = model.n_nodes > 0
        self.parts = tuple(i for i, p in enumerate(model.parts) if p.kind == "solid")
        self._erode_inverted, self._erode_strain, self._erode_dt_ratio = self._erosion_tables()
        self._has_strain_erosion = bool(np.isfinite(self._erode_strain).any())
        self._has_dt_erosion = bool(self._erode_dt_ratio.any())
        self._erode_dt = np.zeros(model.n_elements)  # the step below which an element erodes (0: never); initial_state
        self.eroded: list[tuple[float, int, str, str]] = []  # (time, element, part, reason)

    # ------------------------------------------------------------------------------- set-up

    def initial_state(self) -> State:
        """State 0: initial velocities, the forces and stable step of the initial configuration."""
        m = self.model
        n, e, dim = m.n_nodes, m.n_elements, m.dim
        v = np.zeros((n, dim))
        for ic in m.options.solids.initial:
            v[m.target_nodes(ic.part, ic.set)] = np.array(ic.velocity)
        self.rigid.set_initial_velocity(v)
        n_modes = 1 if dim == 2 else 4
        has_eos = m.material_param[m.element_material, P_EOS_TYPE] >= 0
        e0 = np.where(has_eos, m.material_param[m.element_material, EOS_OFFSET + Q_E0], 0.0) * m.volume0
        st = State(
            time=0.0, step=0, dt=0.0, x=m.coordinates.copy(), v=v,
            f_int=np.zeros((n, dim)), f_ext=np.zeros((n, dim)),
            stress=np.zeros((e, 6)), hist=np.zeros((e, NHIST)), energy=e0,
            hg_energy=np.zeros(e), hg_force=np.zeros((e, n_modes, dim)),
            volume=m.volume0.copy(), q_visc=np.zeros(e), node_power=np.zeros(n),
            f_contact=np.zeros((n, dim)),
        )
        if self.has_solids:  # zero-length step
            self._element_pass(st, 0.0)
            self.loads.compute(0.0, st.x, st.f_ext)
            if self._has_dt_erosion:
                self._erode_dt = self._erosion_steps()
        st.dt = self._solid_dt(st)
        return st

    def _erosion_tables(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per element, from the parts' `erosion`: erode when inverted (bool), plastic-strain limit (inf: none),
        time-step fraction (0: none)."""
        m = self.model
        inverted = np.zeros(m.n_elements, dtype=bool)
        strain = np.full(m.n_elements, np.inf)
        dt_ratio = np.zeros(m.n_elements)
        for p in m.parts:
            spec = m.options.solids.erosion.get(p.name)
            if p.kind != "solid" or spec is None:
                continue
            inverted[p.elements] = spec.on_negative_volume
            if spec.max_plastic_strain is not None:
                strain[p.elements] = spec.max_plastic_strain
            if spec.min_time_step_ratio is not None:
                dt_ratio[p.elements] = spec.min_time_step_ratio
        return inverted, strain, dt_ratio

    def _erosion_steps(self) -> np.ndarray:
        """Per element the step below which it erodes: min_time_step_ratio times its part's smallest element step
        of the initial state (LS-DYNA's DTMIN is a fraction of the first step too); 0 where no ratio is given."""
        m = self.model
        raw = self._dt_elem if m.element_dt_factor is None else self._dt_elem / m.element_dt_factor  # as _check_elements sees it
        out = np.zeros(m.n_elements)
        for p in m.parts:
            ratio = self._erode_dt_ratio[p.elements]
            if p.kind == "solid" and ratio.size and ratio.max() > 0.0:
                out[p.elements] = ratio * float(raw[p.elements].min())
        return out

    # ---------------------------------------------------------------------------------- loop

    def stable_dt(self, scale: float) -> float:
        """The step computed after the last step (`after_step`); +inf without deformable elements."""
        return self.sim.state.dt

    def clear_coupling(self) -> None:
        self.sim.state.f_contact[:] = 0.0

    def advance(self, t: float, dt: float, dt_avg: float) -> None:
        if not self.has_solids:
            return
        st = self.sim.state
        self._solid_step(st, t, dt, dt_avg)
        self._element_pass(st, dt)
        if self.loads.active:
            self.loads.compute(st.time, st.x, st.f_ext)

    def after_step(self) -> None:
        st = self.sim.state
        st.dt = self._solid_dt(st)

    def _solid_step(self, st: State, t: float, dt: float, dt_avg: float) -> None:
        """Nodes and rigid bodies from n to n+1 with the forces of step n."""
        t_mid = t + 0.5 * dt
        self.constraints.update(t_mid)
        f_applied = st.f_ext + st.f_contact if self.sim.interactions else st.f_ext
        if self.rigid.bodies:
            self.rigid.kick(st.f_int + f_applied, t_mid, dt_avg, st.x)
        from ..fem import kernels as fem  # loaded at the first step (`sphfem check` takes none)

        fem.central_difference_update(
            st.x, st.v, st.f_int, f_applied, self.inv_mass, self.constraints.free,
            self.constraints.v_prescribed, dt_avg, dt, st.node_power,
        )
        st.external_work += float(np.sum(st.node_power))
        if self.model.axisymmetric:
            self._reflect_at_axis(st)
        if self.rigid.bodies:
            self.rigid.drift(dt, st.x)

    @staticmethod
    def _reflect_at_axis(st: State) -> None:
        """r-z: a node that crossed the axis (x = r < 0) is put back on its mirror image with its radial velocity
        reversed: a ring that closes on the axis meets itself there (the symmetric collision). Only a loose node
        can get there (one whose elements were all eroded; the axis nodes keep u_r = 0): before, such nodes
        reached r = -3 mm in the Lagrangian bird, where a ring has no meaning."""
        crossed = st.x[:, 0] < 0.0
        if crossed.any():
            st.x[crossed, 0] = -st.x[crossed, 0]
            st.v[crossed, 0] = -st.v[crossed, 0]

    def _element_pass(self, st: State, dt: float) -> None:
        """Element stresses, forces and stable steps of state n+1 (the zero step of the initial state in
        numpy where ``fem.at_rest`` covers it, so that `sphfem check` loads no kernel)."""
        m = self.model
        if at_rest_element_pass(
                st.x, st.v, m.connectivity, m.element_active, m.element_material, m.element_section,
                m.material_type, m.material_param, m.section_param, m.volume0, dt, st.stress, st.hg_force,
                self._f_elem, self._dt_elem, st.volume, st.q_visc, m.axisymmetric):
            st.f_int[:] = 0.0  # the gather of zero element forces
        else:
            from ..fem import kernels as fem

            if m.axisymmetric:  # a module of its own: plane-strain and 3D decks never compile it
                from ..fem.axisymmetric import axisymmetric_element_forces as element_forces
            else:
                element_forces = fem.solid_element_forces
            element_forces(
                st.x, st.v, m.connectivity, m.element_active, m.element_material, m.element_section,
                m.material_type, m.material_param, m.section_param, m.volume0, dt,
                st.stress, st.hist, st.energy, st.hg_energy, st.hg_force,
                self._f_elem, self._dt_elem, st.volume, st.q_visc,
            )
            fem.gather_nodal_forces(self._f_elem, m.node_elem_ptr, m.node_elem_idx, st.f_int)
        self._check_elements(st)
        if m.element_dt_factor is not None:  # elements free to dilate (thin parts): model.build.free_dilatation_factor
            self._dt_elem *= m.element_dt_factor

    def _solid_dt(self, st: State) -> float:
        """timestep_scale times the smallest element step; +inf without deformable elements."""
        if not np.any(self.model.element_active):
            return np.inf
        dt = self.control.timestep_scale * float(self._dt_elem.min())
        if np.isnan(dt):
            raise RunStopped(self._where_not_finite(st), "non_finite", {"domain": "solid"})
        return dt

    def limiter_description(self) -> str:
        e = int(np.argmin(self._dt_elem))
        return f"element {e} of part '{self.part_of(e)}'"

    # ---------------------------------------------------------------------------- energies

    def kinetic_energy(self, st: State) -> float:
        return 0.5 * float(np.sum(self.model.mass[:, None] * st.v * st.v))

    def energies(self) -> Energies:
        st = self.sim.state
        return Energies(self.kinetic_energy(st), float(np.sum(st.energy)), float(np.sum(st.hg_energy)),
                        st.external_work)

    def part_energies(self, part: int) -> tuple[float, float, float]:
        st, p = self.sim.state, self.model.parts[part]
        node_ke = 0.5 * self.model.mass[p.nodes] * np.sum(st.v[p.nodes] * st.v[p.nodes], axis=1)
        return node_ke.sum(), st.energy[p.elements].sum(), st.hg_energy[p.elements].sum()

    # -------------------------------------------------------------------------- guards, output

    def state_arrays(self) -> dict[str, np.ndarray]:
        if not self.has_solids:
            return {}
        st = self.sim.state
        return {"node coordinates": st.x, "node velocity": st.v, "internal force": st.f_int,
                "stress": st.stress, "material history": st.hist, "internal energy": st.energy,
                "hourglass energy": st.hg_energy}

    def grid(self, part: int) -> tuple[str, np.ndarray, int]:
        m, p = self.model, self.model.parts[part]
        return TOPOLOGY[m.nodes_per_element], m.connectivity[p.elements] - p.nodes.start, p.nodes.stop - p.nodes.start

    def field_data(self, wanted) -> dict[int, tuple[np.ndarray, dict, dict]]:
        m, st = self.model, self.sim.state
        accel = (st.f_int + st.f_ext) * self.inv_mass[:, None]
        vm = von_mises(st.stress)
        pressure = -st.stress[:, :3].mean(axis=1)
        density = m.material_param[m.element_material, P_RHO0] * m.volume0 / st.volume
        out = {}
        for i in self.parts:
            n, e = m.parts[i].nodes, m.parts[i].elements
            point = {"displacement": st.x[n] - m.coordinates[n], "velocity": st.v[n], "acceleration": accel[n]}
            cell = {"stress": st.stress[e], "von_mises": vm[e], "pressure": pressure[e],
                    "plastic_strain": st.hist[e, H_EPS], "density": density[e]}
            out[i] = (st.x[n], {k: val for k, val in point.items() if wanted(k)},
                      {k: val for k, val in cell.items() if wanted(k)})
        return out

    # ------------------------------------------------------------------------------ erosion

    def part_of(self, e: int) -> str:
        return self.model.parts[int(self.model.element_part[e])].name

    def _check_elements(self, st: State) -> None:
        """Erode what the parts' `erosion` allows; stop on any other inverted element."""
        m = self.model
        bad = np.flatnonzero(self._dt_elem == INVERTED)
        if len(bad) and not np.isfinite(st.volume[bad]).all():
            self.sim.check_finite()  # an element "inverted" by a non-finite state: that state is the fault
        if len(bad) and self._erode_inverted[bad].any():
            self._erode(st, bad[self._erode_inverted[bad]], "negative volume")
            bad = bad[~self._erode_inverted[bad]]
        if self._has_strain_erosion:
            over = np.flatnonzero(m.element_active & (st.hist[:, H_EPS] > self._erode_strain))
            if len(over):
                self._erode(st, over, "plastic strain")
        if self._has_dt_erosion:
            small = np.flatnonzero(m.element_active & (self._dt_elem > 0.0) & (self._dt_elem < self._erode_dt))
            if len(small):
                self._erode(st, small, "time step")
        if len(bad):
            e = int(bad[0])
            raise RunStopped(
                f"negative volume in element {e} of part '{self.part_of(e)}' at t = {st.time:.6e} "
                f"(step {st.step}, volume {st.volume[e]:.3e}, {len(bad)} element(s) inverted) "
                "(remedies: lower timestep_scale, refine the mesh, raise hourglass stiffness, "
                "or give the part erosion: {on_negative_volume: true})",
                "negative_volume", {"element": e, "part": self.part_of(e), "volume": float(st.volume[e]),
                                    "inverted elements": len(bad)},
            )

    def _erode(self, st: State, elements: np.ndarray, reason: str) -> None:
        """Deactivate `elements`: no more forces or stable step from them; their energies stay in the sums."""
        m = self.model
        m.element_active[elements] = False
        self._f_elem[elements] = 0.0
        self._dt_elem[elements] = np.inf
        from ..fem import kernels as fem

        fem.gather_nodal_forces(self._f_elem, m.node_elem_ptr, m.node_elem_idx, st.f_int)
        for e in elements:
            self.eroded.append((st.time, int(e), self.part_of(int(e)), reason))

    def erosion_summary(self) -> str:
        """'n element(s) eroded (part: count, ...)', or '' when none was."""
        if not self.eroded:
            return ""
        counts: dict[str, int] = {}
        for _, _, part, _ in self.eroded:
            counts[part] = counts.get(part, 0) + 1
        parts = ", ".join(f"{k}: {v}" for k, v in counts.items())
        return f"{len(self.eroded)} element(s) eroded ({parts})"

    def _where_not_finite(self, st: State) -> str:
        bad = np.flatnonzero(~np.isfinite(self._dt_elem))
        e = int(bad[0]) if len(bad) else -1
        where = f" in element {e} of part '{self.part_of(e)}'" if e >= 0 else ""
        return (f"non-finite state{where} at t = {st.time:.6e}, step {st.step} "
                "(remedies: lower timestep_scale, check material constants and units)")

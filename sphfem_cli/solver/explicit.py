"""The explicit central-difference time loop (paper eq. 2.7) and its per-step state.

Step n -> n+1, with forces F^n known:
  1. rigid bodies and prescribed velocities fix v^{n+1/2} on constrained components;
  2. v^{n+1/2} = v^{n-1/2} + dt_avg F^n/m, x^{n+1} = x^n + dt v^{n+1/2} (fem.kernels);
  3. element kernels: stress^{n+1}, internal forces F_int^{n+1}, stable steps;
  4. loads F_ext^{n+1}; energy accounting; next dt = timestep_scale * min element dt.
SPH particles (solver.particles) and the ALE mesh (solver.ale_domain), when the deck has them,
advance with the same dt, the smallest stable step of all.

Contacts and couplings (`interactions`, from the deck's `contacts` and `couplings`) act at the
start of each step, on the state n of every domain: each adds its forces to `State.f_contact`
(solid nodes) and to the fluid's external-force array (`ParticleSystem.f_ext`, the ALE coupling
forces), which the loop clears first. Each interaction object provides

    forces(st)                                   add the forces of state n
    stable_dt() -> float                         the largest step its stiffness allows (inf if none)
    record_work(dt, dt_avg, v_old, st)           after the step: the work its forces did on every side
    work: float                                  that work, summed; its contact energy is -work

An interaction may also provide

    max_penetration() -> (depth, where)          the deepest penetration at the last force pass [length]
                                                 and a description of where (e.g. "particle 12 of contact a->b")
    penetration_limit: float                     the depth beyond which the run should stop [length]

The penetration guard (checked after every step, see `check_guards`) compares
max_penetration() with `control.max_penetration` when the deck sets it, else with the interaction's
own `penetration_limit`; an interaction with neither is not checked.

Solid nodes see the forces through the same central difference as f_ext, particles through their
leapfrog kick; both give every force the weight dt_avg, so equal and opposite forces conserve the
total momentum exactly.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..fem import kernels as fem
from ..materials.slots import EOS_OFFSET, H_EPS, NHIST, P_EOS_TYPE, Q_E0
from ..model.build import Model
from .boundary import Constraints, Curves, Loads, RigidBodies
from .guards import ENERGY_GUARD_EVERY, RunStopped, energy_band_at, energy_out_of_band, first_non_finite


DT_COLLAPSE = 1e-3  # a step below this fraction of the first one means the model is collapsing


def _stable_or_nan(stable_dt: Callable[[], float], *state: np.ndarray) -> float:
    """`stable_dt()`, or NaN when it fails on a non-finite state (a compiled kernel dividing by a
    NaN-derived zero raises ZeroDivisionError); a failure on a finite state is a bug and propagates."""
    try:
        return stable_dt()
    except (ZeroDivisionError, FloatingPointError, OverflowError, ValueError):  # ValueError: a cell grid sized by NaN
        if all(np.isfinite(a).all() for a in state):
            raise
        return float("nan")


@dataclass
class State:
    """Everything of the solids that evolves. Arrays are (N, dim) for nodes, (E, ...) for elements.

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


@dataclass
class EnergyRow:
    """One row of the global energy table (LS-DYNA glstat)."""

    time: float
    kinetic: float
    internal: float
    hourglass: float
    contact: float
    external_work: float
    total: float
    ratio: float
    dt: float
    reference: float = 0.0  # initial energy + external work (not a glstat column: total / ratio)

    COLUMNS = ("time", "kinetic", "internal", "hourglass", "contact", "external_work", "total", "energy_ratio", "dt")

    def values(self) -> list[float]:
        return [self.time, self.kinetic, self.internal, self.hourglass, self.contact, self.external_work,
                self.total, self.ratio, self.dt]


class Simulation:
    """A model, its state and the machinery of one run."""

    def __init__(self, model: Model):
        self.model = model
        deck = model.deck
        self.control = deck.control
        self.curves = Curves(model)
        self.constraints = Constraints(model, self.curves)
        self.loads = Loads(model, self.curves)
        self.rigid = RigidBodies(model, self.constraints, self.curves)
        self.inv_mass = 1.0 / model.mass
        self._f_elem = np.zeros((model.n_elements, model.nodes_per_element, model.dim))
        self._dt_elem = np.zeros(model.n_elements)
        self.has_solids = model.n_nodes > 0
        self.particles = None
        if model.particles is not None:
            from .particles import Particles

            self.particles = Particles(model)
        self.ale = None
        if model.ale is not None:
            from .ale_domain import AleDomain

            self.ale = AleDomain(model)
        self.interactions = []
        if deck.contacts:
            from ..contact.system import NodesToSurfaceContact

            self.interactions += [NodesToSurfaceContact(self, spec) for spec in deck.contacts]
        if deck.couplings:
            from ..contact.coupling import LagrangeInSolidCoupling

            self.interactions += [LagrangeInSolidCoupling(self, spec) for spec in deck.couplings]
        self._dt_first: float | None = None
        self.limiter = "solid"  # what set the last step: solid, sph, ale, contact, dt_max or none
        self._energy_scale = 0.0  # the energy in play, largest so far (guards.energy_out_of_band)
        self._erode_inverted, self._erode_strain = self._erosion_tables()
        self._has_strain_erosion = bool(np.isfinite(self._erode_strain).any())
        self.eroded: list[tuple[float, int, str, str]] = []  # (time, element, part, reason)
        self.state = self._initial_state()

    # ------------------------------------------------------------------------------- set-up

    def _initial_state(self) -> State:
        m = self.model
        n, e, dim = m.n_nodes, m.n_elements, m.dim
        v = np.zeros((n, dim))
        for ic in m.deck.initial:
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
        # Stable step and forces of the initial configuration (zero-length step).
        if self.has_solids:
            self._element_pass(st, 0.0)
            self.loads.compute(0.0, st.x, st.f_ext)
        st.dt = self._solid_dt(st)
        st.initial_energy = self.kinetic_energy(st) + float(np.sum(st.energy))
        if self.particles is not None:
            ke, ie, _, _ = self.particles.energies()
            st.initial_energy += ke + ie
        if self.ale is not None:
            st.initial_energy += sum(self.ale.energies())
        return st

    def _erosion_tables(self) -> tuple[np.ndarray, np.ndarray]:
        """Per element: erode when inverted (bool), plastic-strain limit (inf: none), from the parts' `erosion`."""
        m = self.model
        inverted = np.zeros(m.n_elements, dtype=bool)
        strain = np.full(m.n_elements, np.inf)
        for p in m.parts:
            spec = getattr(m.deck.parts.get(p.name), "erosion", None)
            if p.kind != "solid" or spec is None:
                continue
            inverted[p.elements] = spec.on_negative_volume
            if spec.max_plastic_strain is not None:
                strain[p.elements] = spec.max_plastic_strain
        return inverted, strain

    # ---------------------------------------------------------------------------------- loop

    def _element_pass(self, st: State, dt: float) -> None:
        m = self.model
        fem.solid_element_forces(
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

    def _step_size(self, st: State) -> float:
        """The step this step takes: the smallest over solids and particles, bounded by dt_max."""
        dt, limiter = st.dt, "solid"
        if self.particles is not None:
            dt_sph = _stable_or_nan(lambda: self.particles.stable_dt(self.control.timestep_scale),
                                    self.particles.system.x, self.particles.system.v)
            if not dt_sph == dt_sph:  # NaN
                raise RunStopped(f"non-finite SPH state at t = {st.time:.6e}, step {st.step} "
                                 "(remedies: lower timestep_scale, check the equation of state and units)",
                                 "non_finite", {"domain": "sph"})
            if dt_sph < dt:
                dt, limiter = dt_sph, "sph"
            self._check_lost(st)
        if self.ale is not None:
            dt_ale = _stable_or_nan(self.ale.stable_dt, self.ale.system.x, self.ale.system.velocity)
            if not dt_ale == dt_ale:
                raise RunStopped(f"non-finite ALE state at t = {st.time:.6e}, step {st.step} "
                                 "(remedies: lower the section's courant, check the equations of state and units)",
                                 "non_finite", {"domain": "ale"})
            if dt_ale < dt:
                dt, limiter = dt_ale, "ale"
        for it in self.interactions:
            dt_it = self.control.timestep_scale * it.stable_dt()
            if dt_it < dt:
                dt, limiter = dt_it, "contact"
        if self.control.dt_max is not None and self.control.dt_max < dt:
            dt, limiter = self.control.dt_max, "dt_max"
        self.limiter = limiter
        if not np.isfinite(dt):
            self.limiter = "none"
            return self.control.end_time / 1000.0  # nothing deformable limits the step
        if not dt > 0.0:
            raise RunStopped(f"the stable time step of the {limiter} domain is {dt:g} at t = {st.time:.6e} "
                             "(remedies: check the material and equation-of-state constants and the units)",
                             "time_step", {"dt": dt, "domain": limiter})
        if self._dt_first is None:
            self._dt_first = dt
            self._check_step_count(st, dt, limiter)
        collapsed = dt < DT_COLLAPSE * self._dt_first
        if dt < self.control.dt_min or collapsed:
            where = self.limiter_description()
            floor = (f"1/{1 / DT_COLLAPSE:.0f} of the first step {self._dt_first:.3e}" if collapsed
                     else f"dt_min {self.control.dt_min:.3e}")
            raise RunStopped(
                f"time step {dt:.3e} fell below {floor} at t = {st.time:.6e}, "
                f"step {st.step}, controlled by {where} "
                "(remedies: refine less there, check for a collapsing element or a violent impact, lower dt_min)",
                "time_step", {"dt": dt, "first dt": self._dt_first, "dt_min": self.control.dt_min, "where": where},
            )
        return dt

    def stable_dt(self) -> float:
        """The step the next step would take (as `sphfem check` reports it)."""
        return self._step_size(self.state)

    def limiter_description(self) -> str:
        """What set the last step `_step_size` chose: the element, particle or setting, and its part."""
        m = self.model
        if self.limiter == "solid":
            e = int(np.argmin(self._dt_elem))
            return f"element {e} of part '{self._part_of(e)}'"
        if self.limiter == "sph":
            ps = self.particles.system
            with np.errstate(divide="ignore", invalid="ignore"):
                cfl = np.where(ps.active, ps.h / (ps.c + np.linalg.norm(ps.v, axis=1)), np.inf)
            i = int(ps.ids[int(np.argmin(cfl))])
            return f"SPH particle {i} of part '{m.parts[int(m.particles.part[i])].name}'"
        if self.limiter == "ale":
            e = int(np.argmin(self.ale.system.dt_elem))
            return f"element {e} of ALE part '{self.ale.name}'"
        if self.limiter == "contact":
            return "a contact's stiffness"
        return {"dt_max": "control.dt_max",
                "none": "nothing (no element, particle or contact limits it: end_time / 1000)"}.get(self.limiter,
                                                                                                     self.limiter)

    def step(self, stop: float | None = None) -> None:
        """Advance one step, shortened if needed to land exactly on time `stop` (default end_time)."""
        st = self.state
        stop = self.control.end_time if stop is None else stop
        dt = self._step_size(st)
        if stop > st.time:  # never past stop: a huge stable step (a material with E ~ 0) lands on it
            dt = min(dt, stop - st.time)
        dt_avg = 0.5 * dt if st.step == 0 else 0.5 * (st.dt_prev + dt)
        if self.interactions:
            self._interaction_forces(st)
            v_old = st.v.copy()
        if self.has_solids:
            self._solid_step(st, dt, dt_avg)
        st.time += dt
        st.step += 1
        st.dt_prev = dt
        if self.has_solids:
            self._element_pass(st, dt)
            if self.loads.active:
                self.loads.compute(st.time, st.x, st.f_ext)
        if self.particles is not None:
            self.particles.step(dt)
        if self.ale is not None:
            self.ale.step(dt, dt_avg)
        for it in self.interactions:
            it.record_work(dt, dt_avg, v_old, st)
        st.dt = self._solid_dt(st)
        self.check_guards()

    def _interaction_forces(self, st: State) -> None:
        """Contact and coupling forces of state n, into cleared arrays."""
        st.f_contact[:] = 0.0
        if self.particles is not None:
            self.particles.system.f_ext[:] = 0.0
        if self.ale is not None:
            self.ale.system.f_couple[:] = 0.0
        for it in self.interactions:
            it.forces(st)

    def _solid_step(self, st: State, dt: float, dt_avg: float) -> None:
        """Nodes and rigid bodies from n to n+1 with the forces of step n."""
        t_mid = st.time + 0.5 * dt
        self.constraints.update(t_mid)
        f_applied = st.f_ext + st.f_contact if self.interactions else st.f_ext
        if self.rigid.bodies:
            self.rigid.kick(st.f_int + f_applied, t_mid, dt_avg, st.x)
        fem.central_difference_update(
            st.x, st.v, st.f_int, f_applied, self.inv_mass, self.constraints.free,
            self.constraints.v_prescribed, dt_avg, dt, st.node_power,
        )
        st.external_work += float(np.sum(st.node_power))
        if self.rigid.bodies:
            self.rigid.drift(dt, st.x)

    def run(self, on_step: Callable[[State], None] | None = None, until: float | None = None,
            next_stop: Callable[[], float] | None = None) -> None:
        """Step until `until` (default end_time), landing on every time `next_stop()` names.

        `on_step` is called after every step.
        """
        end = self.control.end_time if until is None else until
        st = self.state
        while st.time < end * (1.0 - 1e-12):
            stop = end if next_stop is None else min(end, next_stop())
            self.step(stop)
            if on_step is not None:
                on_step(st)

    # ---------------------------------------------------------------------------- energies

    def kinetic_energy(self, st: State | None = None) -> float:
        st = st or self.state
        return 0.5 * float(np.sum(self.model.mass[:, None] * st.v * st.v))

    def energy_row(self) -> EnergyRow:
        with np.errstate(over="ignore", invalid="ignore"):  # an overflow shows as a non-finite energy
            return self._energy_row()

    def _energy_row(self) -> EnergyRow:
        st = self.state
        ke = self.kinetic_energy()
        ie = float(np.sum(st.energy))
        hg = float(np.sum(st.hg_energy))
        work = st.external_work
        lost = 0.0
        if self.particles is not None:
            ke_p, ie_p, work_p, lost = self.particles.energies()
            ke, ie, work = ke + ke_p, ie + ie_p, work + work_p
        if self.ale is not None:
            ke_a, ie_a = self.ale.energies()
            ke, ie = ke + ke_a, ie + ie_a
            work += self.ale.external_work()
        contact_work = sum(it.work for it in self.interactions)
        work -= contact_work  # the solids' and fluids' work sums include the contact forces
        total = ke + ie + hg - contact_work
        reference = st.initial_energy + work - lost
        if abs(reference) > 1e-300:
            ratio = total / reference
        else:
            ratio = 1.0 if np.isfinite(total) and np.isfinite(reference) else float("nan")
        return EnergyRow(st.time, ke, ie, hg, -contact_work, work, total, ratio, st.dt_prev, reference)

    def part_energies(self) -> np.ndarray:
        """(parts, 3): kinetic, internal, hourglass per part (LS-DYNA matsum)."""
        m, st = self.model, self.state
        node_ke = 0.5 * m.mass * np.sum(st.v * st.v, axis=1)
        out = np.zeros((len(m.parts), 3))
        for i, p in enumerate(m.parts):
            if p.kind == "sph":
                out[i, :2] = self.particles.part_sums(i)
                continue
            if p.kind == "ale":
                out[i, :2] = self.ale.energies()
                continue
            out[i, 0] = node_ke[p.nodes].sum()
            out[i, 1] = st.energy[p.elements].sum()
            out[i, 2] = st.hg_energy[p.elements].sum()
        return out

    # ------------------------------------------------------------------------------ guards

    def _part_of(self, e: int) -> str:
        return self.model.parts[int(self.model.element_part[e])].name

    def _check_elements(self, st: State) -> None:
        """Erode what the parts' `erosion` allows; stop on any other inverted element."""
        m = self.model
        bad = np.flatnonzero(self._dt_elem == fem.INVERTED)
        if len(bad) and not np.isfinite(st.volume[bad]).all():
            self._check_finite()  # an element "inverted" by a non-finite state: that state is the fault
        if len(bad) and self._erode_inverted[bad].any():
            self._erode(st, bad[self._erode_inverted[bad]], "negative volume")
            bad = bad[~self._erode_inverted[bad]]
        if self._has_strain_erosion:
            over = np.flatnonzero(m.element_active & (st.hist[:, H_EPS] > self._erode_strain))
            if len(over):
                self._erode(st, over, "plastic strain")
        if len(bad):
            e = int(bad[0])
            raise RunStopped(
                f"negative volume in element {e} of part '{self._part_of(e)}' at t = {st.time:.6e} "
                f"(step {st.step}, volume {st.volume[e]:.3e}, {len(bad)} element(s) inverted) "
                "(remedies: lower timestep_scale, refine the mesh, raise hourglass stiffness, "
                "or give the part erosion: {on_negative_volume: true})",
                "negative_volume", {"element": e, "part": self._part_of(e), "volume": float(st.volume[e]),
                                    "inverted elements": len(bad)},
            )

    def _erode(self, st: State, elements: np.ndarray, reason: str) -> None:
        """Deactivate `elements`: no more forces or stable step from them; their energies stay in the sums."""
        m = self.model
        m.element_active[elements] = False
        self._f_elem[elements] = 0.0
        self._dt_elem[elements] = np.inf
        fem.gather_nodal_forces(self._f_elem, m.node_elem_ptr, m.node_elem_idx, st.f_int)
        for e in elements:
            self.eroded.append((st.time, int(e), self._part_of(int(e)), reason))

    def erosion_summary(self) -> str:
        """'n element(s) eroded (part: count, ...)', or '' when none was."""
        if not self.eroded:
            return ""
        counts: dict[str, int] = {}
        for _, _, part, _ in self.eroded:
            counts[part] = counts.get(part, 0) + 1
        parts = ", ".join(f"{k}: {v}" for k, v in counts.items())
        return f"{len(self.eroded)} element(s) eroded ({parts})"

    def _check_lost(self, st: State) -> None:
        """Stop when more than control.max_lost_fraction of the SPH particles have left the domain."""
        limit = self.control.max_lost_fraction
        ps = self.particles.system
        if limit is None or ps.lost <= limit * ps.n:
            return
        raise RunStopped(
            f"{ps.lost} of {ps.n} SPH particles ({ps.lost / ps.n:.1%}) have left the domain by t = {st.time:.6e}, "
            f"step {st.step}, more than max_lost_fraction {limit:g} (remedies: enlarge the section's domain or add "
            "walls, lower timestep_scale if particles were ejected by a blow-up, raise max_lost_fraction)",
            "lost_particles", {"lost": ps.lost, "particles": ps.n, "fraction": ps.lost / ps.n, "limit": limit},
        )

    def check_guards(self) -> None:
        """The guards judged after every step: a finite state, control.max_steps, contact penetration,
        and every ENERGY_GUARD_EVERY steps (and at end_time) the energies and their balance.

        Finite state: every array of every domain that feeds the output (`state_arrays`), one
        vectorised pass. Energies: finite, and the energy ratio within control.energy_band as
        guards.energy_out_of_band judges it. Penetration: each interaction's max_penetration()
        against control.max_penetration, else its own penetration_limit. A fixed step cadence keeps
        every verdict independent of the output intervals; the energy table costs 15-70 us a call on
        small decks, as much as a step of the smallest ones (benchmarks/guard_overhead.py).
        """
        st = self.state
        self._check_finite()
        if st.step >= self.control.max_steps and st.time < self.control.end_time * (1.0 - 1e-12):
            raise RunStopped(
                f"{st.step} steps taken by t = {st.time:.6e}, control.max_steps {self.control.max_steps:g}, before "
                f"end_time {self.control.end_time:g} (remedies: check what shrinks the step, raise control.max_steps)",
                "time_step", {"steps": st.step, "max_steps": self.control.max_steps})
        self._check_penetration()
        if st.step % ENERGY_GUARD_EVERY == 0 or st.time >= self.control.end_time * (1.0 - 1e-12):
            self._check_energy()

    def _check_energy(self) -> None:
        st = self.state
        row = self.energy_row()
        reference = row.reference
        energies = (row.kinetic, row.internal, row.hourglass, row.contact, row.total, reference)
        if not np.isfinite(energies).all():
            raise RunStopped(
                f"non-finite energy at t = {st.time:.6e}, step {st.step} (kinetic {row.kinetic:.4e}, internal "
                f"{row.internal:.4e}, hourglass {row.hourglass:.4e}, contact {row.contact:.4e}, initial + external "
                f"work {reference:.4e}) (remedies: lower timestep_scale, check material constants and units)",
                "non_finite", {"array": "energy"})
        band = self.control.energy_band
        if band is not None:
            in_play = abs(row.kinetic) + abs(row.internal) + abs(row.hourglass) + abs(row.contact)
            self._energy_scale = max(self._energy_scale, in_play, abs(reference))
            low, high = energy_band_at(band, st.step)
            if energy_out_of_band(row.ratio, row.total, reference, self._energy_scale, band, st.step):
                raise RunStopped(
                    f"energy ratio {row.ratio:.4f} left the band [{low:.4g}, {high:.4g}] at t = {st.time:.6e}, "
                    f"step {st.step} (total {row.total:.4e}, initial + external work {reference:.4e}, an error of "
                    f"{(row.total - reference) / self._energy_scale:+.1%} of the energy in play {self._energy_scale:.4e}; "
                    f"kinetic {row.kinetic:.4e}, internal {row.internal:.4e}, hourglass {row.hourglass:.4e}, contact "
                    f"{row.contact:.4e}) (remedies: lower timestep_scale, raise hourglass stiffness if hourglass "
                    "energy grows, refine where the mesh distorts, check contact stiffness; widen or switch off "
                    "control.energy_band if the loss is physical)",
                    "energy_ratio", {"ratio": row.ratio, "band": list(band), "band at this step": [low, high],
                                     "total": row.total, "reference": reference, "energy in play": self._energy_scale,
                                     "kinetic": row.kinetic, "internal": row.internal, "hourglass": row.hourglass,
                                     "contact": row.contact},
                )

    def _check_penetration(self) -> None:
        st = self.state
        for it in self.interactions:
            if not hasattr(it, "max_penetration"):
                continue
            limit = self.control.max_penetration
            if limit is None:
                limit = getattr(it, "penetration_limit", None)
            if limit is None:
                continue
            depth, where = it.max_penetration()
            if depth > limit:
                raise RunStopped(
                    f"penetration {depth:.4e} beyond the limit {limit:.4e} at {where or 'a contact'}, t = {st.time:.6e}, "
                    f"step {st.step} (remedies: raise the contact's penalty_scale, lower timestep_scale, refine the "
                    "master surface, or lower the impact speed)",
                    "penetration", {"depth": depth, "limit": limit, "where": where},
                )

    def _check_finite(self) -> None:
        st = self.state
        bad = first_non_finite(self.state_arrays())
        if bad is not None:
            name, row = bad
            raise RunStopped(
                f"non-finite {name} (row {row}) at t = {st.time:.6e}, step {st.step} "
                "(remedies: lower timestep_scale, check material constants, loads, prescribed motion and units)",
                "non_finite", {"array": name, "row": row})

    def state_arrays(self) -> dict[str, np.ndarray]:
        """Every evolving array that feeds the output, by a name for messages (the finite-state guard)."""
        st = self.state
        arrays = {}
        if self.has_solids:
            arrays.update({"node coordinates": st.x, "node velocity": st.v, "internal force": st.f_int,
                           "stress": st.stress, "material history": st.hist, "internal energy": st.energy,
                           "hourglass energy": st.hg_energy})
        if self.particles is not None:
            arrays.update(self.particles.state_arrays())
        if self.ale is not None:
            arrays.update(self.ale.state_arrays())
        return arrays

    def _check_step_count(self, st: State, dt: float, limiter: str) -> None:
        """Stop at once when end_time / dt exceeds control.max_steps: such a run would not end."""
        with np.errstate(over="ignore"):
            steps = (self.control.end_time - st.time) / dt
        if steps > self.control.max_steps:
            about = f"about {steps:.3g}" if np.isfinite(steps) else "more than 1e308"
            raise RunStopped(
                f"the {limiter} domain's time step {dt:.3e} needs {about} steps to end_time "
                f"{self.control.end_time:g}, more than control.max_steps {self.control.max_steps:g} (remedies: check "
                "timestep_scale, dt_max, the material constants and the units; raise control.max_steps)",
                "time_step", {"dt": dt, "steps": steps, "max_steps": self.control.max_steps, "domain": limiter})

    def _where_not_finite(self, st: State) -> str:
        bad = np.flatnonzero(~np.isfinite(self._dt_elem))
        e = int(bad[0]) if len(bad) else -1
        where = f" in element {e} of part '{self._part_of(e)}'" if e >= 0 else ""
        return (f"non-finite state{where} at t = {st.time:.6e}, step {st.step} "
                "(remedies: lower timestep_scale, check material constants and units)")

"""The explicit central-difference time loop (paper eq. 2.7) over a list of domains.

The loop holds the domains of the model (solver.domain: the contract and its registration; the
solids, solver.solid_domain, always first; then SPH particles, solver.sph_domain, and the ALE mesh,
solver.ale_domain, when the deck has them) and advances them all with the same dt, the smallest
stable step of all. One step n -> n+1:

  1. dt = min over domains and interactions of their stable steps (bounded by control.dt_max);
  2. interactions add their forces of state n (after every domain cleared its coupling arrays);
  3. every domain advances n -> n+1 (the solids: paper eq. 2.7, see solver.solid_domain);
  4. interactions book their work; every domain finishes the step (after_step); the guards.

Contacts and couplings (`interactions`, from the deck's `contacts` and `couplings`) act at the
start of each step, on the state n of every domain: each adds its forces to `State.f_contact`
(solid nodes) and to the fluid's external-force array (`SphSystem.f_ext`, the ALE coupling
forces), which the domains clear first. Each interaction object provides

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

from ..model.build import Model
from .domain import Domain, build_domains
from .guards import ENERGY_GUARD_EVERY, RunStopped, energy_band_at, energy_injected, energy_out_of_band, first_non_finite
from .solid_domain import State

__all__ = ["DT_COLLAPSE", "EnergyRow", "RunStopped", "Simulation", "State"]

DT_COLLAPSE = 1e-3  # a step below this fraction of the first one means the model is collapsing


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
    """A model, its domains, its interactions and the loop of one run."""

    def __init__(self, model: Model):
        self.model = model
        self.control = model.options.control
        self.interactions = []  # built after the domains: contacts and couplings look them up
        self.domains: list[Domain] = build_domains(self)
        self.solids = self.domains[0]
        self.particles = self.domain("sph")
        self.ale = self.domain("ale")
        options = model.options
        if options.contacts:
            from ..contact.system import NodesToSurfaceContact

            self.interactions += [NodesToSurfaceContact(self, spec) for spec in options.contacts]
        if options.couplings:
            from ..contact.coupling import LagrangeInSolidCoupling

            for spec in options.couplings:
                if spec.type == "sph_boundary":
                    from ..contact.sph_boundary import SphBoundaryCoupling

                    self.interactions.append(SphBoundaryCoupling(self, spec))
                else:
                    self.interactions.append(LagrangeInSolidCoupling(self, spec))
        self._dt_first: float | None = None
        self.limiter = "solid"  # the kind of domain that set the last step, or contact, dt_max, none
        self._energy_scale = 0.0  # the energy in play, largest so far (guards.energy_out_of_band)
        self.state = self.solids.initial_state()
        initial = 0.0
        for d in self.domains:
            e = d.energies()
            initial += e.kinetic + e.internal
        self.state.initial_energy = initial

    def domain(self, kind: str) -> Domain | None:
        """The domain of that kind (solid, sph, ale, ...), None when the model has none."""
        return next((d for d in self.domains if d.kind == kind), None)

    # The solids' machinery, by the names the rest of the code and the tests use.
    has_solids = property(lambda self: self.solids.has_solids)
    constraints = property(lambda self: self.solids.constraints)
    loads = property(lambda self: self.solids.loads)
    rigid = property(lambda self: self.solids.rigid)
    curves = property(lambda self: self.solids.curves)
    inv_mass = property(lambda self: self.solids.inv_mass)
    eroded = property(lambda self: self.solids.eroded)

    def erosion_summary(self) -> str:
        """'n element(s) eroded (part: count, ...)', or '' when none was."""
        return self.solids.erosion_summary()

    # ---------------------------------------------------------------------------------- loop

    def _step_size(self, st: State) -> float:
        """The step this step takes: the smallest over domains and interactions, bounded by dt_max."""
        scale = self.control.timestep_scale
        dt, limiter = np.inf, self.domains[0].kind
        for d in self.domains:
            dt_d = d.stable_dt(scale)
            if not dt_d == dt_d:  # NaN
                raise RunStopped(f"non-finite {d.label} state at t = {st.time:.6e}, step {st.step} "
                                 f"(remedies: {d.non_finite_remedy})", "non_finite", {"domain": d.kind})
            if dt_d < dt:
                dt, limiter = dt_d, d.kind
            d.check_step(st)
        for it in self.interactions:
            dt_it = scale * it.stable_dt()
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
        d = self.domain(self.limiter)
        if d is not None:
            return d.limiter_description()
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
            for d in self.domains:
                d.clear_coupling()
            for it in self.interactions:
                it.forces(st)
            v_old = st.v.copy()
        t = st.time
        st.time += dt
        st.step += 1
        st.dt_prev = dt
        for d in self.domains:
            d.advance(t, dt, dt_avg)
        for it in self.interactions:
            it.record_work(dt, dt_avg, v_old, st)
        for d in self.domains:
            d.after_step()
        self.check_guards()

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
        """Kinetic energy of the solids' nodes."""
        return self.solids.kinetic_energy(st or self.state)

    def energy_row(self) -> EnergyRow:
        with np.errstate(over="ignore", invalid="ignore"):  # an overflow shows as a non-finite energy
            return self._energy_row()

    def _energy_row(self) -> EnergyRow:
        st = self.state
        ke = ie = hg = work = lost = 0.0
        for d in self.domains:  # in domain order: the sums' order is part of the result
            e = d.energies()
            ke, ie, hg, work, lost = ke + e.kinetic, ie + e.internal, hg + e.hourglass, work + e.work, lost + e.lost
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
        out = np.zeros((len(self.model.parts), 3))
        for d in self.domains:
            for i in d.parts:
                values = d.part_energies(i)
                out[i, :len(values)] = values
        return out

    # ------------------------------------------------------------------------------ guards

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
        self.check_finite()
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
            injected = energy_injected(row.contact, row.hourglass, self._energy_scale, band, st.step)
            if injected is not None:
                term, value = injected
                raise RunStopped(
                    f"{term} energy {value:.4e} is below -{1.0 - band[0]:.0%} of the energy in play "
                    f"{self._energy_scale:.4e} at t = {st.time:.6e}, step {st.step}: the {term} put energy into "
                    f"the model (kinetic {row.kinetic:.4e}, internal {row.internal:.4e}, hourglass {row.hourglass:.4e}, "
                    f"contact {row.contact:.4e}, energy ratio {row.ratio:.4f}) (remedies: lower timestep_scale, "
                    "raise the hourglass stiffness or use its stiffness form, erode crushed elements "
                    "(erosion.min_time_step_ratio), check contact stiffness and initial penetrations)",
                    "energy_injected", {"term": term, "value": value, "energy in play": self._energy_scale,
                                        "kinetic": row.kinetic, "internal": row.internal, "hourglass": row.hourglass,
                                        "contact": row.contact, "ratio": row.ratio},
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

    def check_finite(self) -> None:
        """Stop on the first non-finite value of any domain's state arrays."""
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
        arrays = {}
        for d in self.domains:
            arrays.update(d.state_arrays())
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

"""The domain contract: what a physics (solids, SPH particles, the ALE mesh, ...) gives the explicit loop.

This docstring is the doc of record for the contract. `Simulation` (solver.explicit) holds a list
of domains, built by the factories registered here in registration order, and calls them in that
order; the order fixes every sum over domains (energies, the stable step), so it never changes
for shipped physics: solid, sph, ale.

One step n -> n+1 (paper eq. 2.7; every domain advances with the same dt, the smallest of all):

    stable_dt(scale) -> float     the largest step the domain's state n allows [time]: inf when nothing
                                  of it limits, NaN on a non-finite state (the loop stops the run with
                                  `label` and `non_finite_remedy`). A domain may compute its rates of
                                  state n here (SPH does): it is called once per step, before advance.
                                  `scale` is control.timestep_scale (a domain with its own number, as
                                  ALE's section timestep_scale, uses that instead, and says so).
    check_step(state)             after stable_dt: the domain's own guards on state n (raise RunStopped).
    clear_coupling()              zero the force arrays that interactions (contacts, couplings) add to;
                                  called before the interactions' forces(state), only when there are some.
    advance(t, dt, dt_avg)        state n -> n+1; t is the time at n (state.time is already t + dt),
                                  dt_avg = (dt_prev + dt) / 2 the impulse weight of forces of state n.
    after_step()                  once every domain advanced and the interactions booked their work.
    limiter_description() -> str  what of the domain set the last step (when `kind` is the limiter).

Energies (histories/glstat.csv, matsum.csv and the energy guard):

    energies() -> Energies        kinetic, internal, hourglass, external work done on it so far
                                  (gravity, loads, walls, interactions' forces) and energy carried off
                                  (lost particles); the loop sums them over domains in order.
    part_energies(part) -> tuple  (kinetic, internal[, hourglass]) of one model part it owns.

State and output:

    parts: tuple[int, ...]        indices of the model parts it owns (one XDMF grid and matsum row each).
    state_arrays() -> dict        every evolving array that feeds the output, by a name for messages
                                  (the finite-state guard, one vectorised pass over all of them).
    grid(part) -> (topology, connectivity | None, n_points)   the XDMF grid of one of its parts.
    field_data(wanted) -> {part: (coordinates, point_data, cell_data)}   one field step of its parts;
                                  `wanted(name)` says whether a deck-selectable field is written.
    history_tables() -> [(name, columns)]   extra history tables (after glstat, matsum), columns after time.
    history_rows() -> [row, ...]  one row per table of history_tables(), after time.
    owns_probe(probe) -> bool, probe(probe) -> float   the output.probes it measures.

Registration: `register_domain(kind, factory, tables)`; `factory(sim)` returns the domain for the
model of `sim` or None when the model has none of it (and imports that physics only then, so a deck
without it compiles none of its kernels); `tables(model)` names the history tables its domain will
add, known before the domain is built (the output folder's manifest is written first). A domain's
objects keep plain attributes (the checkpoint restores them by name, output.snapshot). Settings come
from `model.options` (model/options.py).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np


@dataclass
class Energies:
    """One domain's share of the energy table [energy]."""

    kinetic: float = 0.0
    internal: float = 0.0
    hourglass: float = 0.0
    work: float = 0.0
    lost: float = 0.0


class Domain:
    """Base of the domain contract (module docstring); every method has a do-nothing default."""

    kind = "domain"  # the name of the step limiter it is (solid, sph, ale, ...)
    label = "domain"  # how messages name its state
    non_finite_remedy = "lower timestep_scale, check material constants and units"
    parts: tuple[int, ...] = ()

    def stable_dt(self, scale: float) -> float:
        return np.inf

    def check_step(self, state) -> None:
        return None

    def clear_coupling(self) -> None:
        return None

    def advance(self, t: float, dt: float, dt_avg: float) -> None:
        raise NotImplementedError

    def after_step(self) -> None:
        return None

    def limiter_description(self) -> str:
        return f"the {self.label} domain"

    def energies(self) -> Energies:
        return Energies()

    def part_energies(self, part: int) -> tuple[float, ...]:
        return ()

    def state_arrays(self) -> dict[str, np.ndarray]:
        return {}

    def grid(self, part: int) -> tuple[str, np.ndarray | None, int]:
        raise NotImplementedError

    def field_data(self, wanted: Callable[[str], bool]) -> dict[int, tuple[np.ndarray, dict, dict]]:
        return {}

    def history_tables(self) -> list[tuple[str, list[str]]]:
        return []

    def history_rows(self) -> list[list[float]]:
        return []

    def owns_probe(self, probe) -> bool:
        return False

    def probe(self, probe) -> float:
        raise NotImplementedError


def stable_or_nan(stable_dt: Callable[[], float], *state: np.ndarray) -> float:
    """`stable_dt()`, or NaN when it fails on a non-finite state (a compiled kernel dividing by a
    NaN-derived zero raises ZeroDivisionError); a failure on a finite state is a bug and propagates."""
    try:
        return stable_dt()
    except (ZeroDivisionError, FloatingPointError, OverflowError, ValueError):  # ValueError: a cell grid sized by NaN
        if all(np.isfinite(a).all() for a in state):
            raise
        return float("nan")


_FACTORIES: dict[str, tuple[Callable, Callable | None]] = {}


def register_domain(kind: str, factory: Callable, tables: Callable | None = None) -> None:
    """Add a domain kind: `factory(sim)` -> Domain | None, built after those registered before it;
    `tables(model)` -> the names of the history tables it adds (None: none)."""
    if kind in _FACTORIES:
        raise ValueError(f"domain kind {kind!r} is already registered")
    _FACTORIES[kind] = (factory, tables)


def unregister_domain(kind: str) -> None:
    """Remove a registered kind (tests that register a domain of their own)."""
    del _FACTORIES[kind]


def build_domains(sim) -> list[Domain]:
    """The domains of `sim`'s model, in registration order."""
    domains = []
    for factory, _ in list(_FACTORIES.values()):
        d = factory(sim)
        if d is not None:
            domains.append(d)
    return domains


def domain_tables(model) -> list[str]:
    """The history tables the domains of `model` will add, in domain order (without building them)."""
    return [name for _, tables in _FACTORIES.values() if tables is not None for name in tables(model)]


def _solids(sim):
    from .solid_domain import SolidDomain

    return SolidDomain(sim)


def _sph(sim):
    if sim.model.particles is None:
        return None
    from .sph_domain import SphDomain

    return SphDomain(sim.model, sim.model.options.sph, sim.control)


def _ale(sim):
    if sim.model.ale is None:
        return None
    from .ale_domain import AleDomain

    return AleDomain(sim.model, sim.model.options.ale)


register_domain("solid", _solids)
register_domain("sph", _sph)
register_domain("ale", _ale, lambda model: ["ale_materials"] if model.ale is not None else [])

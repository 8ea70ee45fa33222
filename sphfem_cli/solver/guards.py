"""The checks that stop a run (docs/stability.md): what they test and the exception they raise.

The guards are judged at a fixed step cadence (`Simulation.check_guards`: the state every step, the
energies every ENERGY_GUARD_EVERY steps), so no verdict depends on the output or history intervals.
"""
from __future__ import annotations

import numpy as np

ENERGY_GUARD_STEPS = 100  # before this step the band is widened by (ENERGY_GUARD_STEPS / step)^2 (start-up error)
ENERGY_GUARD_FIRST = 5  # the energy guard is judged from this step on (see energy_out_of_band)
ENERGY_GUARD_EVERY = 10  # the energies are judged every this many steps, and at end_time


class RunStopped(Exception):
    """A guard stopped the run; the message says where, when and what, and what to try.

    `guard` names the guard (non_finite, negative_volume, time_step, energy_ratio, energy_injected,
    lost_particles, penetration); `values` holds the figures the diagnostics file lists.
    """

    def __init__(self, message: str, guard: str = "", values: dict | None = None):
        super().__init__(message)
        self.guard = guard
        self.values = values or {}


def first_non_finite(arrays: dict[str, np.ndarray]) -> tuple[str, int] | None:
    """(name, first row) of the first array of `arrays` that holds a NaN or an infinity, else None.

    One vectorised pass over every array (`kernels.first_non_finite_array`); the row is looked for
    only once an array is found.
    """
    from .kernels import first_non_finite_array

    if not arrays:
        return None
    k = first_non_finite_array(tuple([a.ravel() for a in arrays.values()]))  # every state array is float64
    if k < 0:
        return None
    name = list(arrays)[k]
    a = arrays[name]
    rows = np.flatnonzero(~np.isfinite(a.reshape(len(a), -1)).all(axis=1))
    return name, int(rows[0])


def energy_band_at(band: tuple[float, float], step: int) -> tuple[float, float]:
    """The band on the energy ratio at `step`: `control.energy_band`, its half-widths widened by
    (ENERGY_GUARD_STEPS / step)^2 before step ENERGY_GUARD_STEPS.

    The widening covers the central difference's start-up error (kinetic energy at half steps against
    work at full steps), which decays about as 1/step^2: the energy ratio of the dam-break deck
    starting from rest was measured at 5.9 after 10 steps, 1.15 after 50 and 1.03 after 100.
    """
    widen = max(1.0, (ENERGY_GUARD_STEPS / max(step, 1)) ** 2)
    return 1.0 - (1.0 - band[0]) * widen, 1.0 + (band[1] - 1.0) * widen


def energy_out_of_band(ratio: float, total: float, reference: float, in_play: float,
                       band: tuple[float, float], step: int) -> bool:
    """Is the energy balance broken? Both must hold:

    - the energy ratio total / reference is outside the band of `energy_band_at` (reference = initial
      energy + external work; total = kinetic + internal + hourglass + contact energy);
    - the error total - reference is outside the band's own half-widths times the energy in play
      (the largest so far of |reference| and |kinetic| + |internal| + |hourglass| + |contact|).

    Where every energy is positive the energy in play is about the reference and the second test
    follows from the first. Where energies of opposite sign exchange (water released from rest:
    kinetic energy out of negative internal energy, a contact storing some), the reference can be
    hundreds of times smaller than the energies it balances, and a ratio out of the band is then no
    energy error: the elastic gate's ratio was -27 at step 6 for an error of 4 % of the energy in
    play. A blow-up fails both: its error is the growing energy itself.

    Nothing is judged before step ENERGY_GUARD_FIRST: the leapfrog kicks the SPH internal energy
    a half step behind the velocity, so after the first step the kinetic energy of a column
    released from rest stands alone (40 x 80 particles: error 100 % of the energy in play at step 1,
    14 % at step 2, 5 % at step 3, 1.2 % at step 5, 0.4 % at step 10).
    """
    if step < ENERGY_GUARD_FIRST:
        return False
    low, high = energy_band_at(band, step)
    if low <= ratio <= high:
        return False
    error = (total - reference) / in_play if in_play > 0.0 else 0.0
    return not band[0] - 1.0 <= error <= band[1] - 1.0


def energy_injected(contact: float, hourglass: float, in_play: float, band: tuple[float, float],
                    step: int) -> tuple[str, float] | None:
    """('contact' or 'hourglass', its energy) when that energy is below -(1 - band[0]) times the energy in
    play, else None.

    Both are what the model gave them: the contact energy is minus the work of the contact forces (the
    springs' energy plus the damping's loss), the hourglass energy the stiffness form's stored energy plus
    the viscous form's loss. Neither is negative in a sound run beyond the leapfrog's first-order error of a
    penalty spring (a rigid block into ALE water: -9.4e-4 of its kinetic energy). A large negative one is
    energy the contact or the hourglass control put in, and the balance stays closed (the injection is booked
    in that term), so `energy_out_of_band` cannot see it: the 1.25 mm Lagrangian bird of
    decks/bird_strike_axisymmetric_lagrangian.yaml reached a kinetic energy of 147 kJ from 7.9 kJ with
    contact -132 kJ and hourglass -53 kJ at an energy ratio of 1.12 and an error of 0.3 % of the energy in
    play, and ended "completed". With the default band the limit is 10 % of the energy in play.
    """
    if step < ENERGY_GUARD_FIRST:
        return None
    limit = -(1.0 - band[0]) * in_play
    for name, value in (("contact", contact), ("hourglass", hourglass)):
        if value < limit:
            return name, value
    return None

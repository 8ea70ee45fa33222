"""Are a deck's material constants those of a real material in the deck's units? (`sphfem check`)

A deck declares one consistent unit system and the kernels never convert, so a density typed in
kg/m^3 into an mm-t-s deck, or a modulus in MPa into an SI deck, runs without complaint and gives
a wrong answer. Converted to SI, every real solid, liquid and gas lies inside the ranges below;
a constant orders of magnitude outside them is almost surely typed in other units, and `check`
warns (it does not refuse: the constants may be meant, as in a scaled model).

Ranges (SI), each an order of magnitude or more beyond the real extremes:

=======================  ===============  ===============================================================
quantity                 plausible        real extremes
=======================  ===============  ===============================================================
density                  1e-3 .. 1e5      gases at 1 atm ~0.08 kg/m^3 (hydrogen), osmium 22 600 kg/m^3
Young's modulus          1e2 .. 1e13      soft gels ~1e3 Pa, diamond 1.2e12 Pa
Young's modulus,         >= 1e6           nothing as dense as 2000 kg/m^3 is softer than loose soil
density >= 2000                           (~1e7 Pa); the lightest stiff metal is lead, 1.4e10 Pa
sound speed              0.1 .. 1e5       gels ~1 m/s, diamond 18 000 m/s; SPH's artificial c0 >= ~10 m/s
=======================  ===============  ===============================================================

The sound speed is sqrt((K + 4 G / 3) / rho0) from the packed row (fluids: K = rho0 c0^2 of the
equation of state at rest, G = 0). Ashby, Materials Selection in Mechanical Design (2011), ch. 4,
for the modulus-density chart these ranges enclose.
"""
from __future__ import annotations

from dataclasses import dataclass

import math

from .slots import P_E, P_G, P_K, P_RHO0

LENGTH = {"m": 1.0, "mm": 1e-3, "cm": 1e-2}
MASS = {"kg": 1.0, "t": 1e3, "g": 1e-3}
TIME = {"s": 1.0, "ms": 1e-3, "us": 1e-6}

DENSITY_RANGE = (1e-3, 1e5)  # kg/m^3
MODULUS_RANGE = (1e2, 1e13)  # Pa
DENSE = 2000.0  # kg/m^3: from this density on, a modulus below DENSE_MODULUS_MIN is implausible
DENSE_MODULUS_MIN = 1e6  # Pa
SOUND_SPEED_RANGE = (0.1, 1e5)  # m/s


@dataclass
class MaterialFigures:
    """One material's constants in the deck's units and in SI, and what looks wrong with them."""

    name: str
    density: float
    modulus: float | None  # Young's modulus; None for a fluid
    sound_speed: float | None
    warnings: list[str]


def si_factors(length: str, mass: str, time: str) -> tuple[float, float, float]:
    """SI value of one deck unit of (density, pressure, velocity)."""
    ln, ms, tm = LENGTH[length], MASS[mass], TIME[time]
    return ms / ln**3, ms / (ln * tm * tm), ln / tm


def _outside(value: float, lo: float, hi: float) -> bool:
    return not lo <= value <= hi


def material_figures(name: str, row, fluid: bool, units) -> MaterialFigures:
    """Density, modulus and sound speed of one packed material row (`materials.tables`), with warnings.

    `units`: the deck's `Units`.
    """
    to_rho, to_pa, to_ms = si_factors(units.length, units.mass, units.time)
    _, pressure, density_unit = units.derived
    speed_unit = f"{units.length}/{units.time}"
    rho, e, g, k = float(row[P_RHO0]), float(row[P_E]), float(row[P_G]), float(row[P_K])
    c = math.sqrt((k + 4.0 * g / 3.0) / rho) if rho > 0.0 and k + 4.0 * g / 3.0 > 0.0 else None
    warnings = []
    advice = f"check the units: the deck is in {units.length}-{units.mass}-{units.time}"
    if _outside(rho * to_rho, *DENSITY_RANGE):
        warnings.append(f"density {rho:g} {density_unit} is {rho * to_rho:.3g} kg/m^3, outside any real solid, "
                        f"liquid or gas ({DENSITY_RANGE[0]:g} to {DENSITY_RANGE[1]:g} kg/m^3); {advice}")
    if not fluid:
        e_si = e * to_pa
        if _outside(e_si, *MODULUS_RANGE):
            warnings.append(f"Young's modulus {e:g} {pressure} is {e_si:.3g} Pa, outside any real solid "
                            f"({MODULUS_RANGE[0]:g} to {MODULUS_RANGE[1]:g} Pa); {advice}")
        elif rho * to_rho >= DENSE and e_si < DENSE_MODULUS_MIN:
            warnings.append(f"Young's modulus {e:g} {pressure} ({e_si:.3g} Pa) with density {rho * to_rho:.3g} kg/m^3: "
                            f"no real solid that dense is softer than {DENSE_MODULUS_MIN:g} Pa; {advice}")
    if c is not None and _outside(c * to_ms, *SOUND_SPEED_RANGE):
        warnings.append(f"sound speed {c:.3g} {speed_unit} is {c * to_ms:.3g} m/s, outside any real material "
                        f"({SOUND_SPEED_RANGE[0]:g} to {SOUND_SPEED_RANGE[1]:g} m/s); {advice}")
    return MaterialFigures(name, rho, None if fluid else e, c, warnings)

"""Units of history columns, from the deck's ``units:`` (the unit systems of deck/schema/control.py).

A column's physical dimension follows from its name (the names output/results.py writes):
lengths (displacement, coordinates, height, front), velocity, acceleration, stresses and
pressure, energies (glstat, matsum, ale_materials: kinetic, internal, hourglass, contact,
external_work, total), mass, force (contact_force), the step (dt) and the dimensionless ones
(energy_ratio, plastic_strain). In 2D (plane strain) forces, masses and energies are per unit
thickness (docs/deck-reference.md), so they carry a "/length".
"""
from __future__ import annotations

from ..deck.schema import UNIT_SYSTEMS

_LENGTH = ("displacement", "coordinates", "height", "front", "surface_height")
_ENERGY = ("kinetic", "internal", "hourglass", "contact", "external_work", "total")
_PRESSURE = ("stress", "von_mises", "pressure")
_NONE = ("energy_ratio", "plastic_strain")


def _family(column: str) -> str:
    """The dimension family of a column name (a table's column or a quantity's COLUMN part)."""
    name = column
    for axis in ("_x", "_y", "_z"):
        if name.endswith(axis):
            name = name[: -len(axis)]
    if name in _NONE:
        return "none"
    if name == "time" or name == "dt":
        return "time"
    if name == "contact_force":
        return "force"
    if name.startswith("stress_") or name in _PRESSURE:
        return "pressure"
    if name in _LENGTH:
        return "length"
    if name == "velocity":
        return "velocity"
    if name == "acceleration":
        return "acceleration"
    if name == "density":
        return "density"
    head = name.split("_", 1)[0]
    if name.startswith("mass_") or name.endswith("_mass"):
        return "mass"
    if name in _ENERGY or head in _ENERGY or any(name.endswith("_" + k) for k in _ENERGY):
        return "energy"
    return "unknown"


def unit_of(column: str, units: dict | None = None, dimension: int = 2) -> str:
    """The unit of a history column (or ``TABLE.COLUMN`` quantity) in the deck's system; "-" when dimensionless."""
    units = units or {}
    length, mass, time = units.get("length", "m"), units.get("mass", "kg"), units.get("time", "s")
    force, pressure, density = UNIT_SYSTEMS.get((length, mass, time), (f"{mass}*{length}/{time}^2",) * 3)
    per = f"/{length}" if dimension == 2 else ""
    family = _family(column.rpartition(".")[2])
    energy = "J" if (force, length) == ("N", "m") else f"{force}*{length}"
    return {
        "none": "-", "time": time, "force": force + per, "pressure": pressure, "length": length,
        "velocity": f"{length}/{time}", "acceleration": f"{length}/{time}^2", "density": density,
        "mass": mass + per, "energy": energy + per, "unknown": "unit not known",
    }[family]


def label(column: str, units: dict | None = None, dimension: int = 2) -> str:
    """``name [unit]`` for an axis."""
    return f"{column} [{unit_of(column, units, dimension)}]"

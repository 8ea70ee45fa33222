"""The reference data of the r-z scenes, read from tests/data (issue 15, B3g).

Each scene has ``tests/data/<name>.yaml`` (the values, one entry each: ``value``, ``unit``, ``source``, ``how``)
and ``tests/data/<name>.md`` (the sources cited exactly, how each value was obtained, the resolution study the
comparison rests on); a computed curve or table sits beside them as CSV. Tests and study scripts read the
values here instead of typing them again.

    value("bird_strike_axisymmetric", "hugoniot_pressure")     # float, SI
    entry("bird_strike_axisymmetric", "hugoniot_pressure")     # the whole entry (value, unit, source, how)
    table("underwater_explosion_free_field_1d")                 # a CSV as a numpy structured array

The 1D spherical reference of the free field (tests/verification/spherical_blast_reference.py) is regenerated
with ``python -m tests.reference_data spherical-blast-1d [DR ...]`` from the repository root (the levels of
tests/data/underwater_explosion_free_field.md by default; about 11 min of CPU on one core for all six).
"""
from __future__ import annotations

import csv
import sys
import time
from functools import lru_cache
from pathlib import Path

import numpy as np
import yaml

DATA = Path(__file__).resolve().parent / "data"
ROOT = DATA.parents[1]

BLAST_1D = "underwater_explosion_free_field_1d"
BLAST_1D_LEVELS = (2.0e-3, 1.0e-3, 5.0e-4, 2.5e-4, 1.25e-4, 6.25e-5)   # zone sizes dr, m
BLAST_1D_CHARGE_RADIUS = 0.02   # the free-field deck's fill ball, m
BLAST_1D_RADII = tuple(sorted({round(r, 4) for r in (0.06, 0.08, 0.10, 0.12, 0.14, 0.16, 0.18, 0.20)}
                              | {round(k * BLAST_1D_CHARGE_RADIUS, 4)
                                 for k in (5, 7.5, 10, 12.5, 15, 17.5, 20, 22.5, 25)}))


@lru_cache(maxsize=None)
def _load(name: str) -> dict:
    return yaml.safe_load((DATA / f"{name}.yaml").read_text())


def entry(name: str, key: str) -> dict:
    """The entry ``key`` of tests/data/<name>.yaml: value, unit, source, how."""
    values = _load(name)["values"]
    if key not in values:
        raise KeyError(f"tests/data/{name}.yaml has no value {key!r} (it has {sorted(values)})")
    return values[key]


def value(name: str, key: str):
    """The value of ``key`` in tests/data/<name>.yaml: a float, or a list of floats (PyYAML reads 1.5e6 without
    a '+' in its exponent as text, so every number is converted here)."""
    v = entry(name, key)["value"]
    return [float(x) for x in v] if isinstance(v, list) else float(v)


def table(name: str) -> np.ndarray:
    """tests/data/<name>.csv as a structured array (columns by the header's names)."""
    return np.genfromtxt(DATA / f"{name}.csv", delimiter=",", names=True)


def blast_1d_domain(dr: float, c_water: float = 1480.0) -> tuple[float, float]:
    """(t_end, r_max) of the stored 1D levels: spherical_blast_reference.blast's defaults for BLAST_1D_RADII (the
    sound's travel to the last radius plus 80 us; the rigid outer wall beyond the reflection's reach). A run with
    the same dr and r_max and an earlier t_end takes the same steps, so it reproduces the stored peaks of the
    radii it passes (tests/verification/test_spherical_blast_reference.py)."""
    r = max(BLAST_1D_RADII)
    t_end = r / c_water + 8.0e-5
    return t_end, r + 0.6 * c_water * max(t_end - r / (2.0 * c_water), 0.0) + 20 * dr


def spherical_blast_1d(levels=BLAST_1D_LEVELS, out: Path | None = None) -> Path:
    """Write tests/data/underwater_explosion_free_field_1d.csv: the 1D spherical reference's peak pressure, its
    time and the decay constant theta (peak to peak/e) at BLAST_1D_RADII, per zone size dr, for the charge and
    water of decks/underwater_explosion_free_field_axisymmetric_ale.yaml (spherical_blast_reference.blast with
    its defaults: programmed burn, C_Q 1.5, C_L 0.3, Courant 0.5, t_end = R_max / c + 80 us)."""
    sys.path.insert(0, str(ROOT))
    from tests.verification.spherical_blast_reference import blast, peaks, setup_from_deck

    out = out or DATA / f"{BLAST_1D}.csv"
    setup = setup_from_deck()
    radii = np.array(BLAST_1D_RADII)
    rows = []
    for dr in levels:
        cpu = time.process_time()
        t_end, r_max = blast_1d_domain(dr, setup.water.c)
        res = blast(setup, dr, radii, t_end=t_end, r_max=r_max)
        cpu = time.process_time() - cpu
        pk = peaks(res)
        e0, e1 = sum(res["energy_start"]), sum(res["energy_end"])
        print(f"dr {dr:g} m: {res['zones']} zones, {res['steps']} steps, CPU {cpu:.1f} s, "
              f"energy error {(e1 - e0) / e0:.1e}", flush=True)
        for k, r in enumerate(radii):
            rows.append([f"{dr:g}", f"{r:g}"] + [f"{pk[q][k]:.8e}" for q in ("peak", "t_peak", "theta")])
    with out.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["dr_m", "R_m", "peak_Pa", "t_peak_s", "theta_s"])
        w.writerows(rows)
    return out


if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] != "spherical-blast-1d":
        sys.exit("usage: python -m tests.reference_data spherical-blast-1d [DR ...]")
    levels = tuple(float(a) for a in sys.argv[2:]) or BLAST_1D_LEVELS
    print(spherical_blast_1d(levels))

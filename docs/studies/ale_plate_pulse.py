"""The ALE plate strip loaded by a decaying (exponential) pulse, against the 1D column reference fed
with the ALE's own free-field wave (docs/studies/underwater_explosion.md, "Issue 12: the ALE strip").

    python docs/studies/ale_plate_pulse.py OUT SIZE [SIZE ...] [--p0 PA] [--set KEY=JSON ...]

Built on tests/verification/ale_plate_strip.yaml (water, cut-off, plate, coupling as the UNDEX
deck) with the column lengthened to y = -0.2 m and the bottom inflow replaced by a slip wall. The
initial water holds a right-going pulse p(s) = P0 exp(-s / (c0 theta)) behind a front at
y = -0.03 m (s the distance behind it, theta 20 us), one slab per element row, each on water's
Hugoniot from rest (u from p = rho0 (c0 + s1 u) u, rho = rho0 U / (U - u), U = c0 + s1 u; the
energy follows from the EOS at p). Per size two runs: the strip (plate segments refined with the
water so that n = h / l = 1) and a free field (no plate, water up to a slip top at y = 0.15 m, whose
echo reaches y = 0 after 0.2 ms). The free field's pressure in the element row under y = 0 is the
incident history fed to ``plate_shock_reference.column_plate`` (30 mm, dx 0.05 mm, the same
cut-off), shifted by h / (2 c0) from the row's centre to the face. --set applies KEY=JSON to both
runs' decks (e.g. couplings.0.pfac=8.0, sections.fluid.closure="equal_strain"; a couplings key
only to the strip). Prints one JSON line per size: the free field's peak and impulse at the face,
the plate's velocity maximum, the reference's, their ratio, CPU seconds and the load average.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from sphfem_cli import api  # noqa: E402
from tests.verification.plate_shock_reference import (  # noqa: E402
    C_W, P_CAV, RHO_W, S1_W, column_plate, hugoniot_velocity)

THETA, Y_FRONT, Y_BOTTOM, Y_TOP_FREE = 2.0e-5, -0.03, -0.2, 0.15
WIDTH = 0.005
END_PLATE, END_FREE = 9.0e-5, 1.0e-4


def _assign(deck: dict, key: str, value) -> None:
    *path, last = key.split(".")
    node = deck
    for p in path:
        node = node[int(p)] if p.isdigit() else node[p]
    node[last] = value


def pulse_deck(h: float, p0: float, plate: bool, settings: dict) -> dict:
    """The strip deck (plate=True) or its free field, with the pulse as slab fills of size h."""
    deck = yaml.safe_load((ROOT / "tests" / "verification" / "ale_plate_strip.yaml").read_text())
    box = deck["parts"]["tank"]["geometry"]["box"]
    box.update(min=[0.0, Y_BOTTOM], element_size=h)
    top = 0.0 if plate else Y_TOP_FREE
    fills = [{"material": "water", "box": {"min": [0.0, Y_BOTTOM], "max": [WIDTH, top]}}]
    for k in range(int(round((Y_FRONT - Y_BOTTOM) / h))):
        y0, y1 = Y_FRONT - (k + 1) * h, Y_FRONT - k * h
        p = p0 * np.exp(-(Y_FRONT - 0.5 * (y0 + y1)) / (C_W * THETA))
        u = float(hugoniot_velocity(p))
        shock = C_W + S1_W * u
        fills.append({"material": "water", "box": {"min": [0.0, y0], "max": [WIDTH, y1]},
                      "density": RHO_W * shock / (shock - u), "pressure": float(p), "velocity": [0.0, u]})
    deck["parts"]["tank"]["fill"] = fills
    slip = {"type": "ale_boundary", "part": "tank", "sides": ["left", "right", "top", "bottom"], "condition": "slip"}
    deck["output"]["probes"] = [{"name": "face", "type": "pressure", "point": [0.5 * WIDTH, -1e-6]}]
    if plate:
        deck["parts"]["plate"]["geometry"]["box"]["divisions"] = [max(1, int(round(0.0025 / h))), 2]
        deck["boundaries"] = [b for b in deck["boundaries"] if b["type"] == "fixed"] + [slip]
        end = END_PLATE
    else:
        box["max"] = [WIDTH, Y_TOP_FREE]
        for key in ("sets", "couplings", "output.histories"):
            *path, last = key.split(".")
            (deck[path[0]] if path else deck).pop(last)
        deck["parts"].pop("plate")
        deck["sections"].pop("plate")
        deck["materials"].pop("steel")
        deck["boundaries"] = [slip]
        end = END_FREE
    deck["control"]["end_time"] = end
    deck["output"]["interval"] = end
    for key, value in settings.items():
        if plate or not key.startswith("couplings"):
            _assign(deck, key, value)
    return deck


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("sizes", type=float, nargs="+")
    ap.add_argument("--p0", type=float, default=1.0e8)
    ap.add_argument("--set", action="append", default=[], help="KEY=JSON for both decks")
    a = ap.parse_args()
    settings = {s.split("=", 1)[0]: json.loads(s.split("=", 1)[1]) for s in a.set}
    cut = settings.get("sections.fluid.pressure_cutoff", P_CAV)
    for h in a.sizes:
        t0 = time.process_time()
        runs = {}
        for kind in ("free", "plate"):
            folder = a.out / f"{kind}_{h:g}"
            api.run(pulse_deck(h, a.p0, kind == "plate", settings), folder, overwrite=True, threads=1)
            runs[kind] = api.read_histories(folder)
        face = runs["free"]["face"]
        t_in = face["time"] + 0.5 * h / C_W
        impulse = float(np.trapezoid(np.maximum(face["pressure"], 0.0), face["time"]))
        ref = column_plate(t_in, face["pressure"], END_PLATE, 5e-5, length=0.03, p_cav=cut)
        v = runs["plate"]["plate"]["velocity_y"]
        print(json.dumps({"size": h, "p0": a.p0, "settings": settings,
                          "free_peak_MPa": round(float(face["pressure"].max()) / 1e6, 2),
                          "free_impulse_Pa_s": round(impulse, 1), "exact_impulse_Pa_s": a.p0 * THETA,
                          "plate_vmax": round(float(v.max()), 3), "reference_vmax": round(float(ref["v"].max()), 3),
                          "ratio": round(float(v.max() / ref["v"].max()), 4),
                          "cpu_s": round(time.process_time() - t0, 1), "load": os.getloadavg()}), flush=True)


if __name__ == "__main__":
    main()

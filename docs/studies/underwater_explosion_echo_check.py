"""Echo check of the ALE underwater-explosion decks' transmitting sides (issue 18 A3, audit gap 4).

Runs a deck as shipped and a copy with more water (mesh and water fill enlarged by `extra` metres on
every transmitting side, element size unchanged; the plate part extended to the new sides with every
node beyond the original clamped ends fixed, a rigid wall around the plate), then prints the plate
centre's differences. docs/studies/fsi_convergence_audit.md gives the figures.

    PYTHONPATH=. NUMBA_NUM_THREADS=1 python docs/studies/underwater_explosion_echo_check.py plane 0.3 6.2e-4 /tmp/echo
    PYTHONPATH=. NUMBA_NUM_THREADS=1 python docs/studies/underwater_explosion_echo_check.py axi 0.5 8.6e-4 /tmp/echo
    PYTHONPATH=. NUMBA_NUM_THREADS=1 python docs/studies/underwater_explosion_echo_check.py axi 0.5 1e-3 /tmp/echo source

An optional fifth argument sets the open sides of both runs: transmit, plane (non_reflecting without a
source) or source (non_reflecting with the charge's centre as source); default: as the deck has them.
"""
import sys
from pathlib import Path

import numpy as np
import yaml

from sphfem_cli import api

DECKS = Path(__file__).resolve().parents[2] / "decks"
EPS = 1e-6


def deck(which, extra, end, sides=None):
    name = "underwater_explosion_ale.yaml" if which == "plane" else "underwater_explosion_axisymmetric_ale.yaml"
    d = yaml.safe_load((DECKS / name).read_text())
    if sides is not None:
        for bc in d["boundaries"]:
            if bc["type"] == "ale_boundary" and bc.get("condition") in ("transmit", "non_reflecting"):
                bc.pop("source", None)
                bc["condition"] = "transmit" if sides == "transmit" else "non_reflecting"
                if sides == "source":
                    bc["source"] = d["detonations"][0]["point"]
    d["control"]["end_time"] = end
    d["output"]["interval"] = 2.0e-4
    if extra == 0:
        return d
    h = 0.0025
    x0 = round(-extra, 6) if which == "plane" else 0.0     # r-z: the axis stays at r = 0
    x1 = round((0.30 if which == "plane" else 0.15) + extra, 6)
    y0 = round(-0.20 - extra, 6)
    d["parts"]["tank"]["geometry"]["box"].update(min=[x0, y0], max=[x1, 0.065])
    d["parts"]["tank"]["fill"][0]["box"] = {"min": [x0, y0], "max": [x1, 0.0]}
    d["parts"]["plate"]["geometry"]["box"] = {"min": [x0, 0.0], "max": [x1, 0.005],
                                              "divisions": [round((x1 - x0) / h), 4]}
    if which == "plane":
        d["sets"]["clamp_left"] = {"type": "node", "part": "plate", "box": {"min": [x0 - 0.1, -0.1], "max": [EPS, 0.1]}}
        d["sets"]["clamp_right"] = {"type": "node", "part": "plate", "box": {"min": [0.30 - EPS, -0.1], "max": [x1 + 0.1, 0.1]}}
    else:
        d["sets"]["rim"] = {"type": "node", "part": "plate", "box": {"min": [0.15 - EPS, -0.1], "max": [x1 + 0.1, 0.1]}}
    return d


def main():
    which, extra, end, out = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), Path(sys.argv[4])
    sides = sys.argv[5] if len(sys.argv) > 5 else None
    runs = {}
    for tag, e in (("ship", 0.0), ("big", extra)):
        r = api.run(deck(which, e, end, sides), out / f"{which}_{tag}_{sides or 'deck'}", overwrite=True, threads=1)
        print(tag, r.status, r.time, r.steps, flush=True)
        runs[tag] = r.histories()["centre"]
    a, b = runs["ship"], runs["big"]
    t = np.arange(0.0, min(a["time"][-1], b["time"][-1]), 1e-6)
    for k, sc, thr in (("displacement_y", 1e3, 0.002), ("velocity_y", 1.0, 1.0), ("von_mises", 1e-6, 15.0)):
        x, y = np.interp(t, a["time"], a[k]) * sc, np.interp(t, b["time"], b[k]) * sc
        d = np.abs(x - y)
        i, j = np.argmax(d), np.nonzero(d > thr)[0]
        print(f"{k}: first |d| > {thr} at {t[j[0]] * 1e6 if len(j) else None} us; largest {d[i]:.4g} at "
              f"{t[i] * 1e3:.3f} ms ({x[i]:.4g} / {y[i]:.4g}); peaks {x.max():.4g} / {y.max():.4g}")
        for tt in (1e-4, 2e-4, 3e-4, 4e-4, 5e-4, 6e-4, 8e-4):
            if tt <= t[-1]:
                n = np.searchsorted(t, tt)
                print(f"   {tt * 1e3:.1f} ms: {x[n]:.4g} / {y[n]:.4g}")


if __name__ == "__main__":
    main()

"""The shock-to-plate reference of docs/studies/underwater_explosion.md, fed with a solver's waves.

    python docs/studies/underwater_explosion_transfer.py NAME:FREE_RUN:PLATE_RUN [...]

FREE_RUN is a run of the deck without the plate (water up to the slip top, a pressure probe
``p100`` at the plate's wet face (0.15, 0.0)); PLATE_RUN a run of the shipped deck (history
``centre``, probe ``plate_pressure``). Prints, per case at 0.1 ms: Taylor's plane linear plate,
the 1D Gruneisen column (30 mm, dx 0.2 / 0.1 / 0.05 mm, observed order), the 2D cylindrical-wave
factor, the reference (column x factor), the solver's plate centre and their ratio; one JSON line
per case. Module: tests/verification/plate_shock_reference.py (equations and sources there).
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "verification"))
import plate_shock_reference as ref  # noqa: E402

T_CMP = 1.0e-4   # s: the free-field runs end here; the clamps' first signal reaches the centre ~0.15 ms


def _csv(path):
    return np.genfromtxt(path, delimiter=",", names=True)


def case(name, free_run, plate_run):
    t0 = time.process_time()
    a = _csv(Path(free_run) / "histories" / "p100.csv")
    t, p = a["time"], np.nan_to_num(a["pressure"])
    taylor = float(np.interp(T_CMP, t, ref.taylor_plate(t, p)))
    cols = [float(ref.column_plate(t, p, T_CMP, dx, length=0.03, t_out=np.array([T_CMP]))["v"][0])
            for dx in (2e-4, 1e-4, 5e-5)]
    order, column = ref.observed_order(*cols)
    s2 = ref.strip_plate_2d(t, p, T_CMP, dx=2e-3, dt=5e-7)
    s1 = ref.strip_plate_2d(t, p, T_CMP, dx=2e-3, dt=5e-7, plane=True)
    factor = float(s2["v_centre"][-1] / s1["v_centre"][-1])
    c = _csv(Path(plate_run) / "histories" / "centre.csv")
    solver = float(np.interp(T_CMP, c["time"], c["velocity_y"]))
    reference = column * factor
    return {"case": name, "incident_peak_MPa": round(float(p.max()) / 1e6, 1),
            "incident_impulse_Pa_s": round(float(np.trapezoid(np.clip(p, 0, None), t)), 0),
            "taylor": round(taylor, 2), "column": [round(v, 3) for v in cols], "column_order": round(order, 2),
            "column_extrapolated": round(column, 2), "factor_2d": round(factor, 4),
            "reference": round(reference, 2), "solver": round(solver, 2),
            "solver_over_reference": round(solver / reference, 4), "cpu_s": round(time.process_time() - t0, 1)}


if __name__ == "__main__":
    for arg in sys.argv[1:]:
        print(json.dumps(case(*arg.split(":"))), flush=True)

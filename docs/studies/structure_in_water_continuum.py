"""Convergence of the continuum reference of section 4.1 (tests/verification/wet_plate_continuum_reference.py).

Runs every case once (results cached in WORK/results.json), then prints the tables of
docs/studies/structure_in_water.md, "An independent continuum reference":

    PYTHONPATH=. python docs/studies/structure_in_water_continuum.py [WORK]

Cases (name: element, nx, ny, hf m, dt s, wet, end s); wet runs end at 2 ms (the code-to-code table's
window; the peaks lie at 1.2-1.4 ms), dry runs at 3 ms (the solvers' dry figures were 3 ms runs).
"""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "verification"))
sys.path.insert(0, str(ROOT))
import wet_plate_continuum_reference as cr  # noqa: E402
import wet_plate_reference as wpr  # noqa: E402

from sphfem_cli.study.metrics import three_grid  # noqa: E402

WET, DRY = 2e-3, 3e-3
CASES = {}
for n in (1, 2, 4):                                   # plate series, q9, water 2.5 mm
    CASES[f"q9_{2 * n}x{30 * n}_hf2.5"] = ("q9", 2 * n, 30 * n, 0.0025, 2e-6, True, WET)
for hf in (0.01, 0.005, 0.0025, 0.00125):             # fluid series, q9 4 x 60
    CASES[f"q9_4x60_hf{hf * 1e3:g}"] = ("q9", 4, 60, hf, 2e-6, True, WET)
for dt in (1e-6, 5e-7):                               # time step, q9 4 x 60, water 2.5 mm
    CASES[f"q9_4x60_hf2.5_dt{dt * 1e6:g}"] = ("q9", 4, 60, 0.0025, dt, True, WET)
CASES["q9_8x120_hf1.25_dt1"] = ("q9", 8, 120, 0.00125, 1e-6, True, WET)   # the finest of all three
for n in (1, 2, 4, 8):                                # dry, q9
    CASES[f"q9_{2 * n}x{30 * n}_dry"] = ("q9", 2 * n, 30 * n, 0.0, 2e-6, False, DRY)
for n in (1, 2, 4):                                   # dry and wet, the solvers' quad4
    CASES[f"q4r_{2 * n}x{30 * n}_dry"] = ("q4r", 2 * n, 30 * n, 0.0, 2e-6, False, DRY)
    CASES[f"q4r_{2 * n}x{30 * n}_hf2.5"] = ("q4r", 2 * n, 30 * n, 0.0025, 2e-6, True, WET)
for hf in (0.01, 0.005, 0.00125):                     # the solvers' plate, 4 x 60, fluid series
    CASES[f"q4r_4x60_hf{hf * 1e3:g}"] = ("q4r", 4, 60, hf, 2e-6, True, WET)


# first natural frequency (Hz) in the closed tank, the bottom held in x (wet_frequency): name -> args
FREQS = {f"q9_{2 * n}x{30 * n}_hf2.5": ("q9", 2 * n, 30 * n, 0.0025) for n in (1, 2, 4)}
FREQS.update({f"q9_4x60_hf{hf * 1e3:g}": ("q9", 4, 60, hf) for hf in (0.01, 0.005, 0.00125)})
FREQS.update({f"q4r_{2 * n}x{30 * n}_hf2.5": ("q4r", 2 * n, 30 * n, 0.0025) for n in (1, 2, 4)})
FREQS.update({f"q4r_4x60_hf{hf * 1e3:g}": ("q4r", 4, 60, hf) for hf in (0.005, 0.00125)})
FREQS.update({f"{el}_{2 * n}x{30 * n}_dry": (el, 2 * n, 30 * n, 0.0) for el in ("q9", "q4r") for n in (1, 2, 4)})


def frequency(name: str) -> float:
    el, nx, ny, hf = FREQS[name]
    with wpr.one_blas_thread():
        if hf == 0.0:
            return cr.wet_frequency(nx, ny, element=el, wet=False, guess=1600.0)
        return cr.wet_frequency(nx, ny, hf, element=el)


def run(name: str) -> dict:
    el, nx, ny, hf, dt, wet, end = CASES[name]
    t0 = time.process_time()
    with wpr.one_blas_thread():
        r = cr.driven_response(nx, ny, hf=hf if wet else 0.005, dt=dt, end=end, element=el, wet=wet)
    i = int(np.argmax(np.abs(r.w_mid)))
    out = {"peak_u_mm": abs(r.w_mid[i]) * 1e3, "t_peak_ms": r.t[i] * 1e3,
           "peak_v": float(np.abs(r.v_mid).max()),
           "gauges_MPa": [float(np.abs(r.gauges[g]).max()) / 1e6 for g in wpr.GAUGES],
           "p_range_MPa": (r.p_range / 1e6).tolist(),
           "corner_MPa": ({f"{t:g} ms": (r.corner[int(round(t * 1e-3 / dt))] / 1e6).tolist() for t in (0.5, 1.0)}
                          | {"run": [float(r.corner[:, 1].min() / 1e6), float(r.corner[:, 2].max() / 1e6)],
                             "corner node, run": [float(r.corner[:, 0].min() / 1e6),
                                                  float(r.corner[:, 0].max() / 1e6)]}) if wet else {},
           "energy_after_pulse_span": float(np.ptp(r.energy[r.t >= 6e-4]) / r.energy[-1]),
           "dofs": list(r.n_dofs), "cpu_s": time.process_time() - t0}
    print(name, json.dumps(out), flush=True)
    return out


def order_line(label: str, names: list[str], h: list[float], key, unit: str = "", table: dict | None = None) -> str:
    vals = [key((res if table is None else table)[n]) for n in names]
    cv = three_grid(h, vals)
    txt = " / ".join(f"{v:.4g}" for v in vals)
    if cv.diverging or not np.isfinite(cv.order):
        return f"| {label} | {txt} {unit} | no order (not monotone or diverging) |"
    if cv.order < 0.5:  # the changes do not shrink (e.g. a peak time sampled at the step): no extrapolation
        return f"| {label} | {txt} {unit} | no order (changes do not shrink: order {cv.order:.2f}) |"
    return (f"| {label} | {txt} {unit} | order {cv.order:.2f}, extrapolated {cv.extrapolated:.5g}, "
            f"GCI {100 * cv.gci_fine:.3f} % |")


if __name__ == "__main__":
    work = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/wetplate2d_study")
    work.mkdir(parents=True, exist_ok=True)
    store = work / "results.json"
    res = json.loads(store.read_text()) if store.exists() else {}
    for name in CASES:
        if name not in res:
            res[name] = run(name)
            store.write_text(json.dumps(res, indent=1))
    freqs = json.loads((work / "frequencies.json").read_text()) if (work / "frequencies.json").exists() else {}
    for name in FREQS:
        if name not in freqs:
            freqs[name] = frequency(name)
            (work / "frequencies.json").write_text(json.dumps(freqs, indent=1))
    print("\n| case | first frequency Hz |\n|---|---|")
    for name, f in freqs.items():
        print(f"| {name} | {f:.1f} |")
    for title, names in (("q9 plate 2x30 / 4x60 / 8x120, hf 2.5", [f"q9_{2 * n}x{30 * n}_hf2.5" for n in (1, 2, 4)]),
                         ("q9 4x60, hf 5 / 2.5 / 1.25", ["q9_4x60_hf5", "q9_4x60_hf2.5", "q9_4x60_hf1.25"]),
                         ("q4r plate 2x30 / 4x60 / 8x120, hf 2.5", [f"q4r_{2 * n}x{30 * n}_hf2.5" for n in (1, 2, 4)]),
                         ("q4r 4x60, hf 5 / 2.5 / 1.25", ["q4r_4x60_hf5", "q4r_4x60_hf2.5", "q4r_4x60_hf1.25"])):
        print(order_line("frequency Hz, " + title, names, [4, 2, 1], lambda f: f, table=freqs))
    keys = {"peak u mm": lambda r: r["peak_u_mm"], "t peak ms": lambda r: r["t_peak_ms"],
            "peak v m/s": lambda r: r["peak_v"], "gauge 0-25 MPa": lambda r: r["gauges_MPa"][0],
            "gauge 25-50 MPa": lambda r: r["gauges_MPa"][1]}
    series = {
        "plate q9 2x30 / 4x60 / 8x120, hf 2.5 mm": ([f"q9_{2 * n}x{30 * n}_hf2.5" for n in (1, 2, 4)], [4, 2, 1]),
        "fluid hf 10 / 5 / 2.5 mm, q9 4x60": ([f"q9_4x60_hf{h:g}" for h in (10, 5, 2.5)], [4, 2, 1]),
        "fluid hf 5 / 2.5 / 1.25 mm, q9 4x60": ([f"q9_4x60_hf{h:g}" for h in (5, 2.5, 1.25)], [4, 2, 1]),
        "dt 2 / 1 / 0.5 us, q9 4x60 hf 2.5": (["q9_4x60_hf2.5", "q9_4x60_hf2.5_dt1", "q9_4x60_hf2.5_dt0.5"],
                                              [4, 2, 1]),
        "quad4 plate 2x30 / 4x60 / 8x120, hf 2.5 mm": ([f"q4r_{2 * n}x{30 * n}_hf2.5" for n in (1, 2, 4)],
                                                       [4, 2, 1]),
        "quad4 4x60, hf 5 / 2.5 / 1.25 mm": (["q4r_4x60_hf5", "q4r_4x60_hf2.5", "q4r_4x60_hf1.25"], [4, 2, 1]),
    }
    for title, (names, h) in series.items():
        print(f"\n{title}\n| quantity | values | three-grid |\n|---|---|---|")
        for label, key in keys.items():
            print(order_line(label, names, h, key))
    print("\ndry (3 ms): q9 2x30 / 4x60 / 8x120 / 16x240")
    print(order_line("dry peak u mm, q9 4x60/8x120/16x240", [f"q9_{2 * n}x{30 * n}_dry" for n in (2, 4, 8)],
                     [4, 2, 1], keys["peak u mm"]))
    print(order_line("dry peak u mm, quad4", [f"q4r_{2 * n}x{30 * n}_dry" for n in (1, 2, 4)], [4, 2, 1],
                     keys["peak u mm"]))
    print("\n| case | peak u mm (t ms) | peak v m/s | gauges MPa | p range MPa | corner p MPa | E span | CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    for name, r in res.items():
        print(f"| {name} | {r['peak_u_mm']:.4f} ({r['t_peak_ms']:.3f}) | {r['peak_v']:.3f} | "
              f"{r['gauges_MPa'][0]:.2f} / {r['gauges_MPa'][1]:.2f} | "
              f"{r['p_range_MPa'][0]:.3f} / {r['p_range_MPa'][1]:.3f} | "
              f"{r['corner_MPa']} | {r['energy_after_pulse_span']:.1e} | {r['cpu_s']:.1f} |")

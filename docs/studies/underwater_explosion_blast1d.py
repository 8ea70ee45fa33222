"""Issue 15, the "Cole excess": the 1D spherical reference (tests/verification/spherical_blast_reference.py)
refined, against Cole's similitude and the r-z ALE, and the candidates for the excess one at a time.

    python docs/studies/underwater_explosion_blast1d.py --series 5e-4 2.5e-4 1.25e-4 6.25e-5
    python docs/studies/underwater_explosion_blast1d.py --viscosity 5e-4 2.5e-4 1.25e-4
    python docs/studies/underwater_explosion_blast1d.py --candidates 5e-4
    python docs/studies/underwater_explosion_blast1d.py --rz 0.005 0.0025      # the r-z deck, ~1 min CPU

--series: the 1D peak pressure and decay constant theta (peak to peak/e) at RADII per zone size dr (m), the
observed order and GCI of the three finest (Celik et al. 2008, sphfem_cli.study.metrics.three_grid), and
the finest against Cole's similitude (W = the sphere's 0.05462 kg). --viscosity: the extrapolated peaks
for C_L = 0.06 / 0.3 / 0.6. --candidates: at one dr, each candidate's peak over the deck's (the burn, the viscosity's linear coefficient, the water's Gruneisen constants).
--rz: the r-z deck at element size h, with the solver's linear viscosity Q2 = 0.06 (its default) and 0.3 (the
1D reference's), on the dense ray of docs/studies/underwater_explosion_axi_vs_3d.py
(peaks interpolated log-log to RADII_NEAR), beside the 1D at dr = h. Results go to --json (one file per
mode, merged into it when it exists) so the tables can be rebuilt without running again.
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from sphfem_cli.study.metrics import describe, three_grid  # noqa: E402
from tests.verification.spherical_blast_reference import (  # noqa: E402
    blast, cole_peak, cole_theta, peaks, setup_from_deck)

A = 0.02                                                     # charge radius, m (the deck's fill ball)
RADII_NEAR = (0.06, 0.08, 0.10, 0.12, 0.14, 0.16, 0.18, 0.20)  # the r-z study's table
RADII = tuple(sorted(set(RADII_NEAR) | {k * A for k in (5, 7.5, 10, 12.5, 15, 17.5, 20, 22.5, 25)}))
CANDIDATES = {
    "deck (programmed burn, C_L 0.3)": {},
    "instantaneous burn (F = 1 at t = 0)": {"burn": "instantaneous"},
    "linear viscosity C_L 0.06 (the solver's Q2)": {"cl": 0.06},
    "linear viscosity C_L 0.6": {"cl": 0.6},
    "water gamma0 0.11 (thermodynamic, 20 C)": {"water": {"gamma0": 0.11}},
    "water S1 2.11 (Rice-Walsh Us at up = 150 m/s)": {"water": {"s1": 2.11}},
    "charge energy E0 - 10 %": {"explosive": {"e0": 6.3e9}},
}


def run_1d(dr: float, radii=RADII, change: dict | None = None) -> dict:
    change = dict(change or {})
    setup = setup_from_deck()
    if "water" in change or "explosive" in change:
        setup = setup.replace(explosive=change.pop("explosive", None), water=change.pop("water", None))
    cpu = time.process_time()
    res = blast(setup, dr, np.array(radii), **change)
    cpu = time.process_time() - cpu
    pk = peaks(res)
    e0, e1 = sum(res["energy_start"]), sum(res["energy_end"])
    return {"dr": dr, "radii": list(radii), "peak": pk["peak"].tolist(), "t_peak": pk["t_peak"].tolist(),
            "theta": pk["theta"].tolist(), "cpu": cpu, "steps": res["steps"], "zones": res["zones"],
            "energy_error": (e1 - e0) / e0}


def series(levels: list[float]) -> dict:
    runs = [run_1d(dr) for dr in levels]
    w = setup_from_deck().charge_mass
    radii = np.array(RADII)
    print("| R (m) | R/a | " + " | ".join(f"{r['dr'] * 1e3:g} mm" for r in runs)
          + " | order, GCI (3 finest) | extrapolated | finest / Cole | theta finest (us) | Cole theta (us) |")
    print("|" + "---|" * (len(runs) + 7))
    for k, rad in enumerate(radii):
        vals = [r["peak"][k] for r in runs]
        conv = three_grid([r["dr"] for r in runs[-3:]], vals[-3:])
        ext = conv.extrapolated if np.isfinite(conv.extrapolated) else float("nan")
        print(f"| {rad:.2f} | {rad / A:.1f} | " + " | ".join(f"{v / 1e6:.1f}" for v in vals)
              + f" | {describe(conv)} | {ext / 1e6:.1f} | {vals[-1] / cole_peak(w, rad):.3f}"
              f" | {runs[-1]['theta'][k] * 1e6:.1f} | {cole_theta(w, rad) * 1e6:.1f} |")
    for r in runs:
        print(f"dr {r['dr'] * 1e3:g} mm: {r['zones']} zones, {r['steps']} steps, CPU {r['cpu']:.1f} s, "
              f"energy error {r['energy_error']:.1e}")
    return {"series": runs}


def viscosity(levels: list[float], radii=(0.06, 0.10, 0.20, 0.30)) -> dict:
    """The peaks' limit for three linear viscosity coefficients C_L (three levels each, to 0.25 ms)."""
    out = {}
    for cl in (0.06, 0.3, 0.6):
        runs = [run_1d(dr, radii, {"cl": cl, "t_end": 2.5e-4}) for dr in levels]
        out[f"{cl:g}"] = runs
        cells = []
        for k in range(len(radii)):
            conv = three_grid([r["dr"] for r in runs[-3:]], [r["peak"][k] for r in runs[-3:]])
            cells.append(f"{conv.extrapolated / 1e6:.1f} ({describe(conv)})")
        print(f"| {cl:g} | " + " | ".join(cells) + " |", flush=True)
    return {"viscosity": out}


def candidates(dr: float) -> dict:
    out = {}
    for name, change in CANDIDATES.items():
        out[name] = run_1d(dr, change=change)
    base = np.array(out[next(iter(CANDIDATES))]["peak"])
    sel = [k for k, r in enumerate(RADII) if round(r / A, 1) in (3.0, 5.0, 10.0, 15.0, 20.0, 25.0)]
    print(f"dr = {dr * 1e3:g} mm; peak / the deck's at R/a = " + ", ".join(f"{RADII[k] / A:g}" for k in sel))
    for name, r in out.items():
        print(f"| {name} | " + " | ".join(f"{r['peak'][k] / base[k]:.3f}" for k in sel) + f" | CPU {r['cpu']:.1f} s |")
    return {"candidates": {"dr": dr, "runs": out}}


def rz(levels: list[float], q2_values=(0.06, 0.3)) -> dict:
    spec = importlib.util.spec_from_file_location("axi_vs_3d", ROOT / "docs/studies/underwater_explosion_axi_vs_3d.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    out = {}
    radii = np.array(RADII_NEAR)
    for h in levels:
        one = run_1d(h, RADII_NEAR, {"t_end": 1.2e-4})
        for q2 in q2_values:
            run = mod.peaks(2, h, {"sections.fluid.bulk_viscosity.q2": q2})
            p_rz = mod.loglog(run, radii)
            out[f"{h:g} q2 {q2:g}"] = {"h": h, "q2": q2, "rz_peak": p_rz.tolist(), "rz_cpu": run["cpu"],
                                       "rz_charge": run["charge"], "one_d": one}
            print(f"h = {h * 1e3:g} mm, r-z Q2 = {q2:g} (CPU {run['cpu']:.1f} s, charge {run['charge']:.5f} kg): "
                  + ", ".join(f"{r:.2f} m r-z {a / 1e6:.1f} / 1D {b / 1e6:.1f}"
                              for r, a, b in zip(radii, p_rz, one["peak"])), flush=True)
    return {"rz": out}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--series", type=float, nargs="*", default=[])
    parser.add_argument("--candidates", type=float, default=None)
    parser.add_argument("--viscosity", type=float, nargs="*", default=[])
    parser.add_argument("--rz", type=float, nargs="*", default=[])
    parser.add_argument("--q2", type=float, nargs="*", default=[0.06, 0.3], help="r-z linear viscosities")
    parser.add_argument("--json", type=Path, default=Path("study_undex_blast1d.json"))
    args = parser.parse_args()
    data = json.loads(args.json.read_text()) if args.json.exists() else {}
    if args.series:
        data.update(series(args.series))
    if args.viscosity:
        data.update(viscosity(args.viscosity))
    if args.candidates:
        data.update(candidates(args.candidates))
    if args.rz:
        data.update(rz(args.rz, args.q2))
    args.json.write_text(json.dumps(data, indent=1))


if __name__ == "__main__":
    main()

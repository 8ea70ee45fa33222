"""Issue 15, scene 2: decks/bird_strike_axisymmetric_{sph,ale,lagrangian}.yaml refined, against Wilbeck's exact
results for a fluid cylinder on a rigid target, and against each other.

    python docs/studies/bird_strike.py                    # from the repository root; SPH dx 5 / 2.5 / 1.25 mm
    python docs/studies/bird_strike.py --method ale --sizes 0.005 0.0025 0.00125
    python docs/studies/bird_strike.py --method lagrangian --sizes 0.005 0.0025 0.00125   # the bird's element size
    python docs/studies/bird_strike.py --plot docs/studies/bird_strike_force.png   # the runs above, overlaid

Exact results (Wilbeck 1978, AFML-TR-77-134; the deck's header): the impulse equals the bird's momentum
m v; the Hugoniot pressure at the centre P_H = rho0 U_s v (U_s from the Tait Hugoniot, solved here);
the steady stagnation pressure 1/2 rho v^2 and force rho A v^2 (the jet's momentum flux).

Prints per spacing: impulse / (m v) over the run; the centre's peak over the first 50 us / P_H; the
centre's mean pressure and the target's mean force over the window WINDOW (ms) over their steady values;
the CPU seconds; then the observed order and GCI (Roache, safety 1.25) on the last three spacings.
"""
from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from sphfem_cli import api
from sphfem_cli.study.metrics import describe, three_grid
from sphfem_cli.api import read_histories

ROOT = Path(__file__).resolve().parents[2]
DECKS = {method: ROOT / f"decks/bird_strike_axisymmetric_{method}.yaml" for method in ("sph", "ale", "lagrangian")}
SEGMENT = 0.25 / 100  # the ALE deck's target segment, m
WORK = Path("study_bird_strike")
RHO, C0, GAMMA, SPEED, RADIUS, LENGTH = 1000.0, 1483.0, 7.0, 100.0, 0.05, 0.2  # the deck's
WINDOW = (1.0e-3, 1.8e-3)  # s: after the cavity on the axis has closed, before the rear arrives


def hugoniot_pressure() -> float:
    """P_H = rho0 U_s v with rho0 U_s = rho (U_s - v) and p(rho) = B ((rho/rho0)^gamma - 1), B = rho0 c0^2 / gamma."""
    b = RHO * C0 ** 2 / GAMMA

    def jump(us: float) -> float:
        return b * ((us / (us - SPEED)) ** GAMMA - 1.0) - RHO * us * SPEED

    return RHO * brentq(jump, C0, 3.0 * C0) * SPEED


def overrides(method: str, size: float) -> dict:
    """SPH: the particle spacing. Lagrangian: the bird's element size. ALE: the element size, with the coupling's rule of the deck kept,
    L_c = h / 2 (pfac = 2 n, n = h / (segment / nquad) coupling points per water element, nquad raised where
    the target's segment is longer than the element; docs/theory/coupling.md, "Stiffness")."""
    if method == "sph":
        return {"parts.bird.spacing": size}
    if method == "lagrangian":  # the bird's ring elements; the centre history stays at (2.5, 2.5) mm
        return {"parts.bird.geometry.box.divisions": [round(RADIUS / size), round(LENGTH / size)]}
    nquad = max(2, math.ceil(SEGMENT / size - 1e-9))
    return {"parts.air.geometry.box.element_size": size, "couplings.0.nquad": nquad,
            "couplings.0.pfac": 2.0 * size / (SEGMENT / nquad)}


def level(method: str, size: float) -> dict:
    cpu = time.process_time()
    result = api.run(DECKS[method], WORK / f"{method}_{size * 1e3:g}mm", overrides(method, size), threads=1,
                     overwrite=True)
    cpu = time.process_time() - cpu
    assert result.completed, result.message
    hist = result.histories()
    t, force = hist["target"]["time"], -hist["target"]["contact_force_y"]
    tc, pc = hist["centre"]["time"], np.nan_to_num(hist["centre"]["pressure"])
    area = math.pi * RADIUS ** 2
    mass = RHO * area * LENGTH
    win, winc = (t >= WINDOW[0]) & (t <= WINDOW[1]), (tc >= WINDOW[0]) & (tc <= WINDOW[1])
    out = {"impulse/mv": float(np.trapezoid(force, t)) / (mass * SPEED),
           "centre peak/P_H": float(pc[tc <= 5.0e-5].max()) / hugoniot_pressure(),
           "centre mean/(rho v^2/2)": float(pc[winc].mean()) / (0.5 * RHO * SPEED ** 2),
           "force mean/(rho A v^2)": float(force[win].mean()) / (RHO * area * SPEED ** 2),
           "cpu_s": cpu, "steps": result.steps}
    if method == "lagrangian":  # its "centre" is the material element that started there, gone by the window
        del out["centre mean/(rho v^2/2)"]
    return out


def plot(path: Path) -> None:
    """The target's force over rho A v^2 against time for every run under WORK: SPH solid, ALE dashed,
    Lagrangian dotted."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    steady = RHO * math.pi * RADIUS ** 2 * SPEED ** 2
    fig, (full, early) = plt.subplots(1, 2, figsize=(11, 4.2))
    for folder in sorted(WORK.iterdir(), key=lambda f: (f.name.split("_")[0], -float(f.name.split("_")[1][:-2]))):
        hist = read_histories(folder)["target"]
        t, force = hist["time"] * 1e3, -hist["contact_force_y"] / steady
        style = {"sph": "-", "ale": "--"}.get(folder.name.split("_")[0], ":")
        label = folder.name.replace("_", " ").replace("mm", " mm")
        for ax in (full, early):
            ax.plot(t, force, style, lw=1.0, label=label)
    full.axhline(1.0, color="k", lw=0.6, ls=":")
    full.set_ylim(0.0, 3.0)  # the impact spike (to ~20) is the right panel's
    early.set_xlim(0.0, 0.1)
    early.axhline(hugoniot_pressure() / (RHO * SPEED ** 2), color="k", lw=0.6, ls=":")  # P_H A / (rho A v^2)
    for ax, title in ((full, "whole run (spike clipped)"), (early, "first 0.1 ms")):
        ax.set_xlabel("time (ms)")
        ax.set_ylabel("target force / (rho A v^2) (-)")
        ax.set_title(f"Bird strike, r-z, 100 m/s: {title}")
        ax.grid(alpha=0.3)
    full.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--method", choices=sorted(DECKS), default="sph")
    parser.add_argument("--sizes", type=float, nargs="*", default=[0.005, 0.0025, 0.00125],
                        help="particle spacings (sph) or element sizes (ale, lagrangian), coarse to fine, ratio 2 (m)")
    parser.add_argument("--plot", type=Path, help="only plot the runs under WORK into this PNG")
    args = parser.parse_args()
    if args.plot:
        plot(args.plot)
        return
    WORK.mkdir(exist_ok=True)
    print(f"P_H {hugoniot_pressure() / 1e6:.1f} MPa, rho v^2/2 {0.5 * RHO * SPEED ** 2 / 1e6:.2f} MPa, "
          f"rho A v^2 {RHO * math.pi * RADIUS ** 2 * SPEED ** 2 / 1e3:.1f} kN, m v {RHO * math.pi * RADIUS ** 2 * LENGTH * SPEED:.1f} N s")
    runs = [level(args.method, size) for size in args.sizes]
    for size, run in zip(args.sizes, runs):
        print(f"{args.method} {size * 1e3:g} mm: " + ", ".join(f"{k} {v:.4g}" for k, v in run.items()))
    if len(runs) >= 3:
        for key in runs[0]:
            if key not in ("cpu_s", "steps"):
                conv = three_grid(args.sizes[-3:], [run[key] for run in runs[-3:]])
                print(f"{key}: {describe(conv)}")


if __name__ == "__main__":
    main()
